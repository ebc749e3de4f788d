//! `history`: roof drift (%) and maximum vertical drop (m) against time, from
//! `history.csv` (definitions in [`crate::output::history`]). Two panels on one time
//! axis; FE-stage points ([`style::FE_STAGE`]) and ruin-stage points
//! ([`style::PHYSICS_STAGE`]) are separate curves; a curve breaks where a value is
//! missing; Tc (`summary.json` `tc_s`) is a dashed vertical line with its value.
use super::style::{self, Swatch};
use super::Result;
use super::{font::FAMILY, run_label, tc_s, Figure, HistoryRow, RunFolder};
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// The history figure of a run.
pub struct HistoryFigure<'a> {
    run: &'a RunFolder,
}

impl<'a> HistoryFigure<'a> {
    /// The history figure of `run`.
    pub fn new(run: &'a RunFolder) -> Self {
        HistoryFigure { run }
    }
}

/// Runs of consecutive rows with a value and the same stage: (FE?, points (t, value)).
pub(crate) fn segments(
    rows: &[HistoryRow],
    value: impl Fn(&HistoryRow) -> Option<f64>,
) -> Vec<(bool, Vec<(f64, f64)>)> {
    let mut out: Vec<(bool, Vec<(f64, f64)>)> = Vec::new();
    let mut open = false;
    for r in rows {
        match value(r).filter(|v| v.is_finite()) {
            Some(v) => {
                match out.last_mut() {
                    Some((fe, pts)) if open && *fe == r.fe => pts.push((r.t_s, v)),
                    _ => out.push((r.fe, vec![(r.t_s, v)])),
                }
                open = true;
            }
            None => open = false,
        }
    }
    out
}

/// A value range holding `values` and 0, padded 5 % (a unit range when empty or flat).
pub(crate) fn value_range(values: impl IntoIterator<Item = f64>) -> (f64, f64) {
    let (mut lo, mut hi) = (0.0_f64, 0.0_f64);
    for v in values.into_iter().filter(|v| v.is_finite()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if hi - lo <= 0.0 {
        return (lo, lo + 1.0);
    }
    let p = 0.05 * (hi - lo);
    (if lo < 0.0 { lo - p } else { lo }, hi + p)
}

/// The time range of `rows` (and Tc), s.
pub(crate) fn time_range(rows: &[HistoryRow], tc: Option<f64>) -> (f64, f64) {
    let ts = rows.iter().map(|r| r.t_s).chain(tc);
    let (lo, hi) = ts.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), t| {
        (a.min(t), b.max(t))
    });
    if !(lo.is_finite() && hi.is_finite()) {
        (0.0, 1.0)
    } else if hi > lo {
        (lo, hi)
    } else {
        (lo, lo + 1.0)
    }
}

/// One curve of a time-history panel.
#[derive(Debug, Clone, PartialEq)]
pub struct Curve {
    /// Line colour.
    pub colour: RGBColor,
    /// Legend label.
    pub label: String,
    /// Points (t s, value).
    pub points: Vec<(f64, f64)>,
}

/// Width of the legend strip of the time-history figures, px.
pub(crate) const LEGEND_W: u32 = 210;

/// One time-history panel: the curves (colour, label, points) and Tc; `empty_note` is
/// written in the middle when there is no point at all.
pub(super) fn panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    t: (f64, f64),
    tc: Option<f64>,
    y_desc: &str,
    curves: &[Curve],
    empty_note: &str,
) -> Result<()>
where
    DB::ErrorType: 'static,
{
    let y = value_range(curves.iter().flat_map(|c| c.points.iter().map(|p| p.1)));
    let mut chart = ChartBuilder::on(area)
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(75)
        .build_cartesian_2d(t.0..t.1, y.0..y.1)?;
    let fx = style::tick_format(t.1 - t.0);
    let fy = style::tick_format(y.1 - y.0);
    chart
        .configure_mesh()
        .x_desc("t (s)")
        .y_desc(y_desc)
        .x_label_formatter(&fx)
        .y_label_formatter(&fy)
        .label_style((FAMILY, style::TICK_PX))
        .axis_desc_style((FAMILY, style::LABEL_PX))
        .light_line_style(style::GRID_LIGHT)
        .bold_line_style(style::GRID_BOLD)
        .draw()?;
    if let Some(tc) = tc {
        chart.draw_series(std::iter::once(DashedPathElement::new(
            vec![(tc, y.0), (tc, y.1)],
            6,
            4,
            style::TC_MARKER.stroke_width(2),
        )))?;
        chart.draw_series(std::iter::once(
            EmptyElement::at((tc, y.1))
                + Text::new(
                    format!("Tc = {tc:.3} s"),
                    (6, 4),
                    (FAMILY, style::LABEL_PX)
                        .into_font()
                        .color(&style::TC_MARKER),
                ),
        ))?;
    }
    for c in curves.iter().filter(|c| !c.points.is_empty()) {
        chart.draw_series(LineSeries::new(
            c.points.iter().copied(),
            c.colour.stroke_width(2),
        ))?;
    }
    if curves.iter().all(|c| c.points.is_empty()) {
        let (w, h) = area.dim_in_pixel();
        area.draw(&Text::new(
            empty_note.to_string(),
            (w as i32 / 2, h as i32 / 2),
            TextStyle::from((FAMILY, style::LABEL_PX).into_font())
                .pos(Pos::new(HPos::Center, VPos::Center)),
        ))?;
    }
    Ok(())
}

/// Legend entries of the non-empty `curves` (one per label, first colour) and Tc.
pub(super) fn legend_entries(
    heading: &str,
    curves: &[&[Curve]],
    tc: Option<f64>,
) -> Vec<(Swatch, String)> {
    let mut e = vec![(Swatch::Heading, heading.to_string())];
    for c in curves
        .iter()
        .flat_map(|c| c.iter())
        .filter(|c| !c.points.is_empty())
    {
        if !e.iter().any(|(_, l)| *l == c.label) {
            e.push((Swatch::Line(c.colour), c.label.clone()));
        }
    }
    if let Some(tc) = tc {
        e.push((Swatch::Dashed(style::TC_MARKER), format!("Tc = {tc:.3} s")));
    }
    e
}

/// Curves of one quantity: the FE and ruin-stage segments of `value`, coloured by stage.
fn stage_curves(rows: &[HistoryRow], value: impl Fn(&HistoryRow) -> Option<f64>) -> Vec<Curve> {
    segments(rows, value)
        .into_iter()
        .map(|(fe, points)| {
            let (colour, label) = if fe {
                (style::FE_STAGE, "FE stage")
            } else {
                (style::PHYSICS_STAGE, "ruin stage (Bullet)")
            };
            Curve {
                colour,
                label: label.to_string(),
                points,
            }
        })
        .collect()
}

impl Figure for HistoryFigure<'_> {
    fn name(&self) -> &'static str {
        "history"
    }

    fn size(&self) -> (u32, u32) {
        (1100, 850)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()>
    where
        DB::ErrorType: 'static,
    {
        root.fill(&style::BACKGROUND)?;
        let title = format!("Roof drift and maximum drop - {}", run_label(self.run));
        let root = root.titled(&title, (FAMILY, style::TITLE_PX))?;
        let (w, h) = root.dim_in_pixel();
        let (main, legend) = root.split_horizontally(w.saturating_sub(LEGEND_W));
        let (top, bottom) = main.split_vertically(h / 2);
        let rows = &self.run.history;
        let tc = tc_s(self.run);
        let t = time_range(rows, tc);
        let drift = stage_curves(rows, |r| r.roof_drift.map(|d| 100.0 * d));
        let drop = stage_curves(rows, |r| r.max_drop_m);
        panel(
            &top,
            t,
            tc,
            "roof drift (%)",
            &drift,
            "no roof drift in history.csv",
        )?;
        panel(
            &bottom,
            t,
            tc,
            "max vertical drop (m)",
            &drop,
            "no maximum drop in history.csv",
        )?;
        style::draw_legend(&legend, &legend_entries("Stage", &[&drift, &drop], tc))?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(t: f64, fe: bool, d: Option<f64>) -> HistoryRow {
        HistoryRow {
            t_s: t,
            fe,
            roof_drift: d,
            max_drop_m: None,
            counts: None,
            ground_m: [0.0; 3],
            energy: None,
        }
    }

    #[test]
    fn segments_break_at_stage_and_gaps() {
        let rows = vec![
            row(0.0, true, Some(0.0)),
            row(0.04, true, Some(0.01)),
            row(0.08, false, Some(0.02)),
            row(0.12, false, None),
            row(0.16, false, Some(0.03)),
            row(0.20, false, Some(f64::NAN)),
        ];
        let s = segments(&rows, |r| r.roof_drift);
        assert_eq!(s.len(), 3);
        assert_eq!(s[0], (true, vec![(0.0, 0.0), (0.04, 0.01)]));
        assert_eq!(s[1], (false, vec![(0.08, 0.02)]));
        assert_eq!(s[2], (false, vec![(0.16, 0.03)]));
    }

    #[test]
    fn ranges() {
        assert_eq!(value_range([]), (0.0, 1.0));
        let (lo, hi) = value_range([1.0, 3.0]);
        assert_eq!(lo, 0.0);
        assert!((hi - 3.15).abs() < 1e-12);
        let (lo, hi) = value_range([-2.0, 2.0]);
        assert!((lo + 2.2).abs() < 1e-12 && (hi - 2.2).abs() < 1e-12);
        assert_eq!(time_range(&[], Some(2.0)), (2.0, 3.0));
        assert_eq!(time_range(&[row(1.0, true, None)], Some(4.0)), (1.0, 4.0));
    }
}

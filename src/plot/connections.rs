//! `connections`: the numbers of intact, plastic and broken connections against time over
//! the ruin stage (the `history.csv` rows that carry counts), Tc marked as in
//! [`super::history`]. A run without a ruin stage gets the figure with a note instead.
use super::history::{legend_entries, panel, time_range, Curve, LEGEND_W};
use super::style;
use super::Result;
use super::{font::FAMILY, run_label, tc_s, Figure, RunFolder};
use plotters::coord::Shift;
use plotters::prelude::*;

/// The connection-count figure of a run.
pub struct ConnectionsFigure<'a> {
    run: &'a RunFolder,
}

impl<'a> ConnectionsFigure<'a> {
    /// The connection-count figure of `run`.
    pub fn new(run: &'a RunFolder) -> Self {
        ConnectionsFigure { run }
    }

    /// The curves (t s, count) of intact, plastic and broken connections.
    pub fn curves(&self) -> Vec<Curve> {
        let rows: Vec<(f64, (usize, usize, usize))> = self
            .run
            .history
            .iter()
            .filter_map(|r| r.counts.map(|c| (r.t_s, c)))
            .collect();
        let pick = |f: fn((usize, usize, usize)) -> usize| -> Vec<(f64, f64)> {
            rows.iter().map(|&(t, c)| (t, f(c) as f64)).collect()
        };
        let curve = |colour, label: &str, points| Curve {
            colour,
            label: label.to_string(),
            points,
        };
        vec![
            curve(style::INTACT, "intact", pick(|c| c.0)),
            curve(style::PLASTIC, "plastic", pick(|c| c.1)),
            curve(style::BROKEN, "broken", pick(|c| c.2)),
        ]
    }
}

impl Figure for ConnectionsFigure<'_> {
    fn name(&self) -> &'static str {
        "connections"
    }

    fn size(&self) -> (u32, u32) {
        (1100, 520)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()>
    where
        DB::ErrorType: 'static,
    {
        root.fill(&style::BACKGROUND)?;
        let curves = self.curves();
        let total = self
            .run
            .history
            .iter()
            .filter_map(|r| r.counts)
            .map(|c| c.0 + c.1 + c.2)
            .max()
            .unwrap_or(0);
        let title = format!("Connections ({total}) - {}", run_label(self.run));
        let root = root.titled(&title, (FAMILY, style::TITLE_PX))?;
        let (w, _) = root.dim_in_pixel();
        let (main, legend) = root.split_horizontally(w.saturating_sub(LEGEND_W));
        let tc = tc_s(self.run);
        let phys: Vec<_> = self
            .run
            .history
            .iter()
            .filter(|r| r.counts.is_some())
            .cloned()
            .collect();
        let t = time_range(&phys, tc);
        panel(
            &main,
            t,
            tc,
            "connections",
            &curves,
            "no ruin stage in this run: no connection counts",
        )?;
        style::draw_legend(&legend, &legend_entries("Connections", &[&curves], tc))?;
        Ok(())
    }
}

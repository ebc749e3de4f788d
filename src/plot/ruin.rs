//! The ruin figures: the final pose of every body projected on a view plane
//! ([`geometry::View`]): `ruin_plan`, `ruin_elevation_xz`, `ruin_elevation_yz`.
//!
//! Each active body is one filled polygon (its projection, [`geometry::project`]) in its
//! type colour shaded by story ([`style::body_fill`]), with a darker outline, drawn back
//! to front ([`geometry::draw_order`]); passive foundation blocks are outlines only; the
//! original outline of the undeformed active bodies is dashed; the elevations show the
//! final ground level. Axes are in metres with an equal aspect (one metre spans the same
//! pixels on both axes).
//!
//! **Panels.** The *near* window is the original outline widened on every side by its
//! larger side (3 × the footprint). When every body fits in a window twice that size,
//! the figure has one panel holding every body and the original outline, padded 3 %.
//! Otherwise (debris thrown far) it has two: *all bodies* (the whole extent, each active
//! body also marked by a 2 px dot in its colour so that small far debris stays visible,
//! the near window drawn as a grey frame) and *near the original footprint* (the near
//! window, only the bodies whose projection reaches into it). In the elevations the
//! equal-aspect widening extends the vertical range upwards only, so the ground stays at
//! the bottom.
use super::geometry::{self, Bounds, Stories, View};
use super::style::{self, Swatch};
use super::Result;
use super::{font::FAMILY, run_label, Figure, RunFolder};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;

/// Width of the legend panel, px.
pub(crate) const LEGEND_W: u32 = 230;

/// One ruin figure of a run.
pub struct RuinFigure<'a> {
    run: &'a RunFolder,
    view: View,
    stories: Stories,
}

impl<'a> RuinFigure<'a> {
    /// The ruin figure of `run` in `view`.
    pub fn new(run: &'a RunFolder, view: View) -> Self {
        RuinFigure {
            run,
            view,
            stories: Stories::from_bodies(&run.bodies),
        }
    }

    /// Indices of the active bodies in drawing order.
    pub fn active_order(&self) -> Vec<usize> {
        let ids: Vec<usize> = (0..self.run.bodies.len())
            .filter(|&i| !self.run.bodies[i].passive)
            .collect();
        geometry::draw_order(&self.run.final_poses, &ids, self.view)
    }

    /// Fill colour of body `i`.
    pub fn fill(&self, i: usize) -> RGBColor {
        let b = &self.run.bodies[i];
        style::body_fill(
            b.id.type_name(),
            self.stories.of(b.pose0.position[2]),
            self.stories.count(),
        )
    }

    /// Projection of body `i`'s final pose, m.
    pub fn projection(&self, i: usize) -> Vec<[f64; 2]> {
        let b = &self.run.bodies[i];
        geometry::project(&self.run.final_poses[i], b.half_extents, self.view)
    }

    /// The bounds of every final projection, the original outline and (elevations) the
    /// ground level, unpadded.
    pub fn extent(&self) -> Bounds {
        let mut pts: Vec<[f64; 2]> = (0..self.run.bodies.len())
            .flat_map(|i| self.projection(i))
            .collect();
        if let Some(o) = geometry::original_outline(&self.run.bodies, self.view) {
            pts.push([o.x[0], o.y[0]]);
            pts.push([o.x[1], o.y[1]]);
        }
        if self.view != View::Plan {
            if let Some(g) = geometry::final_ground_level(self.run) {
                let x = pts.first().map_or(0.0, |p| p[0]);
                pts.push([x, g]);
            }
        }
        Bounds::of(pts).unwrap_or(Bounds {
            x: [0.0, 1.0],
            y: [0.0, 1.0],
        })
    }

    /// The near window: the original outline widened by its larger side (≥ 0.5 m) on
    /// every side; in the elevations its bottom is a tenth of that side below the lower of
    /// the outline and the final ground (module docs).
    pub fn near_window(&self) -> Option<Bounds> {
        let o = geometry::original_outline(&self.run.bodies, self.view)?;
        let side = (o.x[1] - o.x[0]).max(o.y[1] - o.y[0]).max(0.5);
        let bottom = match (self.view, geometry::final_ground_level(self.run)) {
            (View::Plan, _) => o.y[0] - side,
            (_, g) => o.y[0].min(g.unwrap_or(o.y[0])) - 0.1 * side,
        };
        Some(Bounds {
            x: [o.x[0] - side, o.x[1] + side],
            y: [bottom, o.y[1] + side],
        })
    }

    /// The panels (module docs).
    pub fn panels(&self) -> Vec<Panel> {
        let all = self.extent();
        let near = self.near_window().filter(|w| {
            let grown = w.padded(0.5, 0.0); // twice the window: + half its side each way
            !(all.x[0] >= grown.x[0]
                && all.x[1] <= grown.x[1]
                && all.y[0] >= grown.y[0]
                && all.y[1] <= grown.y[1])
        });
        match near {
            None => vec![Panel {
                data: all.padded(0.03, 0.5),
                title: None,
                dots: false,
                frame: None,
            }],
            Some(w) => {
                let inside = (0..self.run.bodies.len())
                    .filter(|&i| !self.run.bodies[i].passive && self.reaches(i, &w))
                    .count();
                let active = self.run.bodies.iter().filter(|b| !b.passive).count();
                vec![
                    Panel {
                        data: all.padded(0.03, 0.5),
                        title: Some(format!(
                            "all bodies: extent {:.0} m x {:.0} m",
                            all.x[1] - all.x[0],
                            all.y[1] - all.y[0]
                        )),
                        dots: true,
                        frame: Some(w),
                    },
                    Panel {
                        data: w,
                        title: Some(format!(
                            "near the original footprint: {inside} of {active} bodies"
                        )),
                        dots: false,
                        frame: None,
                    },
                ]
            }
        }
    }

    /// Whether body `i`'s projection reaches into `w`.
    fn reaches(&self, i: usize, w: &Bounds) -> bool {
        Bounds::of(self.projection(i)).is_some_and(|b| {
            b.x[1] >= w.x[0] && b.x[0] <= w.x[1] && b.y[1] >= w.y[0] && b.y[0] <= w.y[1]
        })
    }

    /// The title drawn on `root`, then the panel areas (each with its own title) and the
    /// legend area.
    fn areas<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        panels: &[Panel],
    ) -> Result<Areas<DB>>
    where
        DB::ErrorType: 'static,
    {
        let root = root.titled(&self.title(), (FAMILY, style::TITLE_PX))?;
        let (w, _) = root.dim_in_pixel();
        let (main, legend) = root.split_horizontally(w.saturating_sub(LEGEND_W));
        let mut out = Vec::new();
        for (area, p) in main.split_evenly((1, panels.len())).into_iter().zip(panels) {
            out.push(match &p.title {
                Some(t) => area.titled(t, (FAMILY, style::LABEL_PX))?,
                None => area,
            });
        }
        Ok((out, legend))
    }

    /// The axis ranges of `panel` in `area`: its data bounds widened to an equal aspect
    /// for the plotting area left (measured on a chart of the same layout, which draws
    /// nothing).
    fn plot_bounds<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        panel: &Panel,
    ) -> Result<Bounds>
    where
        DB::ErrorType: 'static,
    {
        let data = panel.data;
        let (pw, ph) = chart_builder(area)
            .build_cartesian_2d(data.x[0]..data.x[1], data.y[0]..data.y[1])?
            .plotting_area()
            .dim_in_pixel();
        // plotters maps a range onto the first..last pixel: spans of w − 1, h − 1
        Ok(data.equal_aspect(
            pw.saturating_sub(1),
            ph.saturating_sub(1),
            self.view != View::Plan,
        ))
    }

    /// Where the metres land in the figure's pixels, per panel (the layout of
    /// [`Figure::draw`]).
    pub fn pixel_maps(&self) -> Result<Vec<PixelMap>> {
        super::font::ensure_registered()?;
        let panels = self.panels();
        let mut scratch = String::new();
        let root = SVGBackend::with_string(&mut scratch, self.size()).into_drawing_area();
        let (areas, _) = self.areas(&root, &panels)?;
        let mut out = Vec::new();
        for (area, panel) in areas.iter().zip(&panels) {
            let b = self.plot_bounds(area, panel)?;
            let chart = chart_builder(area).build_cartesian_2d(b.x[0]..b.x[1], b.y[0]..b.y[1])?;
            let (px, py) = chart.plotting_area().get_pixel_range();
            out.push(PixelMap {
                bounds: b,
                px: [px.start, px.end],
                py: [py.start, py.end],
            });
        }
        Ok(out)
    }

    /// Draws one panel.
    fn draw_panel<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        panel: &Panel,
    ) -> Result<()>
    where
        DB::ErrorType: 'static,
    {
        let b = self.plot_bounds(area, panel)?;
        let mut chart = view_chart(area, self.view, &b)?;

        let closed = |p: &[[f64; 2]]| -> Vec<(f64, f64)> {
            let mut v: Vec<(f64, f64)> = p.iter().map(|q| (q[0], q[1])).collect();
            if let Some(&f) = v.first() {
                v.push(f);
            }
            v
        };
        let shown = |i: usize| panel.dots || panel.frame.is_some() || self.reaches(i, &b);

        if self.view != View::Plan {
            if let Some(g) = geometry::final_ground_level(self.run) {
                chart.draw_series(std::iter::once(PathElement::new(
                    vec![(b.x[0], g), (b.x[1], g)],
                    style::GROUND.stroke_width(2),
                )))?;
            }
        }
        if let Some(w) = panel.frame {
            let r = [
                [w.x[0], w.y[0]],
                [w.x[1], w.y[0]],
                [w.x[1], w.y[1]],
                [w.x[0], w.y[1]],
            ];
            chart.draw_series(std::iter::once(PathElement::new(
                closed(&r),
                style::GRID_BOLD.stroke_width(1),
            )))?;
        }

        let passive: Vec<usize> = (0..self.run.bodies.len())
            .filter(|&i| self.run.bodies[i].passive && shown(i))
            .collect();
        for i in geometry::draw_order(&self.run.final_poses, &passive, self.view) {
            chart.draw_series(std::iter::once(PathElement::new(
                closed(&self.projection(i)),
                style::FOUNDATION_OUTLINE.stroke_width(1),
            )))?;
        }

        let order: Vec<usize> = self
            .active_order()
            .into_iter()
            .filter(|&i| shown(i))
            .collect();
        for &i in &order {
            let p = self.projection(i);
            let fill = self.fill(i);
            let pts: Vec<(f64, f64)> = p.iter().map(|q| (q[0], q[1])).collect();
            chart.draw_series(std::iter::once(Polygon::new(pts, fill.filled())))?;
            chart.draw_series(std::iter::once(PathElement::new(
                closed(&p),
                style::body_outline(fill).stroke_width(1),
            )))?;
        }
        if panel.dots {
            let (a, c) = self.view.axes();
            for &i in &order {
                let q = self.run.final_poses[i].position;
                chart.draw_series(std::iter::once(Circle::new(
                    (q[a], q[c]),
                    2,
                    self.fill(i).filled(),
                )))?;
            }
        }

        if let Some(o) = geometry::original_outline(&self.run.bodies, self.view) {
            let r = [
                [o.x[0], o.y[0]],
                [o.x[1], o.y[0]],
                [o.x[1], o.y[1]],
                [o.x[0], o.y[1]],
            ];
            chart.draw_series(std::iter::once(DashedPathElement::new(
                closed(&r),
                8,
                5,
                style::FOOTPRINT.stroke_width(2),
            )))?;
        }
        Ok(())
    }

    fn title(&self) -> String {
        let what = match self.view {
            View::Plan => "Ruins in plan (from above)",
            View::ElevationXz => "Ruins in elevation x-z (from -y)",
            View::ElevationYz => "Ruins in elevation y-z (from +x)",
        };
        format!("{what} - {}", run_label(self.run))
    }

    fn legend(&self) -> Vec<(Swatch, String)> {
        let bodies = &self.run.bodies;
        let mut e = vec![(Swatch::Heading, "Element type".to_string())];
        let types = style::legend_types(
            bodies
                .iter()
                .filter(|b| !b.passive)
                .map(|b| b.id.type_name()),
        );
        for t in types {
            let n = bodies
                .iter()
                .filter(|b| !b.passive && b.id.type_name() == t)
                .count();
            e.push((Swatch::Fill(style::type_colour(&t)), format!("{t} ({n})")));
        }
        let passive = bodies.iter().filter(|b| b.passive).count();
        if passive > 0 {
            e.push((
                Swatch::Outline(style::FOUNDATION_OUTLINE),
                format!("foundation ({passive}, fixed)"),
            ));
        }
        let n = self.stories.count();
        if n > 1 {
            e.push((Swatch::Heading, "Story (darker = lower)".to_string()));
            for s in (1..=n).rev() {
                let level = self.stories.levels.get(s - 1).copied().unwrap_or(f64::NAN);
                e.push((
                    Swatch::Fill(style::scaled(style::STORY_SWATCH, style::story_shade(s, n))),
                    format!("story {s} (floor {level:.2} m)"),
                ));
            }
        }
        e.push((Swatch::Heading, "Reference".to_string()));
        let outline = if self.view == View::Plan {
            "original footprint"
        } else {
            "original outline"
        };
        e.push((Swatch::Dashed(style::FOOTPRINT), outline.to_string()));
        if self.view != View::Plan {
            e.push((Swatch::Line(style::GROUND), "ground (final)".to_string()));
        }
        e
    }
}

/// The panel areas and the legend area of a ruin figure.
type Areas<DB> = (Vec<DrawingArea<DB, Shift>>, DrawingArea<DB, Shift>);

/// One panel of a ruin figure (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Panel {
    /// The bounds to show before the equal-aspect widening, m.
    pub data: Bounds,
    /// Panel title (two-panel figures).
    pub title: Option<String>,
    /// Mark every active body with a dot (the overview panel).
    pub dots: bool,
    /// A window to frame (the near window, in the overview panel).
    pub frame: Option<Bounds>,
}

/// The chart layout shared by drawing and [`RuinFigure::pixel_map`].
fn chart_builder<'a, 'b, DB: DrawingBackend>(
    main: &'a DrawingArea<DB, Shift>,
) -> ChartBuilder<'a, 'b, DB> {
    let mut cb = ChartBuilder::on(main);
    cb.margin(12).x_label_area_size(48).y_label_area_size(70);
    cb
}

/// The chart of a plan or elevation over `b` (m) on `main`: the axes named by `view`, ticks
/// formatted for the range, the grid drawn. The ruin figures and the void figures share it.
pub(super) fn view_chart<'a, DB: DrawingBackend>(
    main: &'a DrawingArea<DB, Shift>,
    view: View,
    b: &Bounds,
) -> Result<ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>>
where
    DB::ErrorType: 'static,
{
    let (xd, yd) = view.axis_names();
    let mut chart = chart_builder(main).build_cartesian_2d(b.x[0]..b.x[1], b.y[0]..b.y[1])?;
    let fx = style::tick_format(b.x[1] - b.x[0]);
    let fy = style::tick_format(b.y[1] - b.y[0]);
    chart
        .configure_mesh()
        .x_desc(xd)
        .y_desc(yd)
        .x_label_formatter(&fx)
        .y_label_formatter(&fy)
        .label_style((FAMILY, style::TICK_PX))
        .axis_desc_style((FAMILY, style::LABEL_PX))
        .light_line_style(style::GRID_LIGHT)
        .bold_line_style(style::GRID_BOLD)
        .draw()?;
    Ok(chart)
}

/// The axis transform of a ruin figure: the axis ranges (m) and the plotting area's pixel
/// ranges (x left to right, y top to bottom; the vertical axis points up).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PixelMap {
    /// Axis ranges, m.
    pub bounds: Bounds,
    /// Plotting-area pixel columns [start, end).
    pub px: [i32; 2],
    /// Plotting-area pixel rows [start, end).
    pub py: [i32; 2],
}

impl PixelMap {
    /// Pixel of the point `p` (m), before plotters' rounding: x runs from the first to
    /// the last pixel column of the plotting area, y from its last row (bottom) up to its
    /// first.
    pub fn to_px(&self, p: [f64; 2]) -> (f64, f64) {
        let b = &self.bounds;
        let fx = (p[0] - b.x[0]) / (b.x[1] - b.x[0]);
        let fy = (p[1] - b.y[0]) / (b.y[1] - b.y[0]);
        let (sx, sy) = self.spans();
        (
            f64::from(self.px[0]) + fx * sx,
            f64::from(self.py[1] - 1) - fy * sy,
        )
    }

    /// The point (m) at pixel `(x, y)` (the inverse of [`Self::to_px`]).
    pub fn to_m(&self, x: f64, y: f64) -> [f64; 2] {
        let b = &self.bounds;
        let (sx, sy) = self.spans();
        let fx = (x - f64::from(self.px[0])) / sx;
        let fy = (f64::from(self.py[1] - 1) - y) / sy;
        [
            b.x[0] + fx * (b.x[1] - b.x[0]),
            b.y[0] + fy * (b.y[1] - b.y[0]),
        ]
    }

    /// Pixel spans of the axes (last − first pixel).
    fn spans(&self) -> (f64, f64) {
        (
            f64::from(self.px[1] - 1 - self.px[0]),
            f64::from(self.py[1] - 1 - self.py[0]),
        )
    }
}

impl Figure for RuinFigure<'_> {
    fn name(&self) -> &'static str {
        match self.view {
            View::Plan => "ruin_plan",
            View::ElevationXz => "ruin_elevation_xz",
            View::ElevationYz => "ruin_elevation_yz",
        }
    }

    fn size(&self) -> (u32, u32) {
        let two = self.panels().len() > 1;
        match (self.view, two) {
            (View::Plan, false) => (1150, 900),
            (View::Plan, true) => (1700, 860),
            (_, false) => (1150, 750),
            (_, true) => (1700, 750),
        }
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()>
    where
        DB::ErrorType: 'static,
    {
        root.fill(&style::BACKGROUND)?;
        let panels = self.panels();
        let (areas, legend) = self.areas(root, &panels)?;
        for (area, panel) in areas.iter().zip(&panels) {
            self.draw_panel(area, panel)?;
        }
        style::draw_legend(&legend, &self.legend())?;
        Ok(())
    }
}

//! The ruin figures: the final pose of every body projected on a view plane
//! ([`geometry::View`]): `ruin_plan`, `ruin_elevation_xz`, `ruin_elevation_yz`.
//!
//! Each active body is one filled polygon (its projection, [`geometry::project`]) in its
//! type colour shaded by story ([`style::body_fill`]), with a darker outline, drawn back
//! to front ([`geometry::draw_order`]); passive foundation blocks are outlines only; the
//! original outline of the undeformed active bodies is dashed; the elevations show the
//! final ground level. The axis ranges hold every body and the original outline (so a
//! footprint stays visible however far debris flew), padded by 3 %, then widened to an
//! equal aspect (one metre spans the same pixels on both axes).
use super::geometry::{self, Bounds, Stories, View};
use super::style::{self, Swatch};
use super::{font::FAMILY, run_label, Figure, RunFolder};
use anyhow::Result;
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;

/// Width of the legend panel, px.
pub const LEGEND_W: u32 = 230;

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
            &b.type_name,
            self.stories.of(b.pose0.position[2]),
            self.stories.count(),
        )
    }

    /// Projection of body `i`'s final pose, m.
    pub fn projection(&self, i: usize) -> Vec<[f64; 2]> {
        let b = &self.run.bodies[i];
        geometry::project(&self.run.final_poses[i], b.half_extents, self.view)
    }

    /// The data bounds before the equal-aspect widening: every final projection, the
    /// original outline and (elevations) the ground level, padded 3 % (at least 0.5 m).
    pub fn data_bounds(&self) -> Bounds {
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
        Bounds::of(pts)
            .unwrap_or(Bounds {
                x: [0.0, 1.0],
                y: [0.0, 1.0],
            })
            .padded(0.03, 0.5)
    }

    /// The title drawn on `root`, then the plot and legend areas below it.
    fn areas<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
    ) -> Result<(DrawingArea<DB, Shift>, DrawingArea<DB, Shift>)>
    where
        DB::ErrorType: 'static,
    {
        let root = root.titled(&self.title(), (FAMILY, style::TITLE_PX))?;
        let (w, _) = root.dim_in_pixel();
        Ok(root.split_horizontally(w.saturating_sub(LEGEND_W)))
    }

    /// The axis ranges: [`Self::data_bounds`] widened to an equal aspect for the plotting
    /// area that `main` leaves (measured on a chart of the same layout, which draws
    /// nothing).
    fn plot_bounds<DB: DrawingBackend>(&self, main: &DrawingArea<DB, Shift>) -> Result<Bounds>
    where
        DB::ErrorType: 'static,
    {
        let data = self.data_bounds();
        let (pw, ph) = chart_builder(main)
            .build_cartesian_2d(data.x[0]..data.x[1], data.y[0]..data.y[1])?
            .plotting_area()
            .dim_in_pixel();
        // plotters maps a range onto the first..last pixel: spans of w − 1, h − 1
        Ok(data.equal_aspect(pw.saturating_sub(1), ph.saturating_sub(1)))
    }

    /// Where the metres land in the figure's pixels (the layout of [`Figure::draw`]).
    pub fn pixel_map(&self) -> Result<PixelMap> {
        super::font::ensure_registered()?;
        let mut scratch = String::new();
        let root = SVGBackend::with_string(&mut scratch, self.size()).into_drawing_area();
        let (main, _) = self.areas(&root)?;
        let b = self.plot_bounds(&main)?;
        let chart = chart_builder(&main).build_cartesian_2d(b.x[0]..b.x[1], b.y[0]..b.y[1])?;
        let (px, py) = chart.plotting_area().get_pixel_range();
        Ok(PixelMap {
            bounds: b,
            px: [px.start, px.end],
            py: [py.start, py.end],
        })
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
                .map(|b| b.type_name.as_str()),
        );
        for t in types {
            let n = bodies
                .iter()
                .filter(|b| !b.passive && b.type_name == t)
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
                    Swatch::Fill(style::scaled(
                        style::STORY_SWATCH,
                        style::story_shade(s, n),
                    )),
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

/// The chart layout shared by drawing and [`RuinFigure::pixel_map`].
fn chart_builder<'a, 'b, DB: DrawingBackend>(
    main: &'a DrawingArea<DB, Shift>,
) -> ChartBuilder<'a, 'b, DB> {
    let mut cb = ChartBuilder::on(main);
    cb.margin(12).x_label_area_size(48).y_label_area_size(70);
    cb
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
        match self.view {
            View::Plan => (1150, 900),
            _ => (1150, 750),
        }
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()>
    where
        DB::ErrorType: 'static,
    {
        root.fill(&style::BACKGROUND)?;
        let (main, legend) = self.areas(root)?;
        let b = self.plot_bounds(&main)?;
        let (xd, yd) = self.view.axis_names();
        let mut chart = chart_builder(&main).build_cartesian_2d(b.x[0]..b.x[1], b.y[0]..b.y[1])?;
        chart
            .configure_mesh()
            .x_desc(xd)
            .y_desc(yd)
            .label_style((FAMILY, style::TICK_PX))
            .axis_desc_style((FAMILY, style::LABEL_PX))
            .light_line_style(style::GRID_LIGHT)
            .bold_line_style(style::GRID_BOLD)
            .draw()?;

        let closed = |p: &[[f64; 2]]| -> Vec<(f64, f64)> {
            let mut v: Vec<(f64, f64)> = p.iter().map(|q| (q[0], q[1])).collect();
            if let Some(&f) = v.first() {
                v.push(f);
            }
            v
        };

        if self.view != View::Plan {
            if let Some(g) = geometry::final_ground_level(self.run) {
                chart.draw_series(std::iter::once(PathElement::new(
                    vec![(b.x[0], g), (b.x[1], g)],
                    style::GROUND.stroke_width(2),
                )))?;
            }
        }

        let passive: Vec<usize> = (0..self.run.bodies.len())
            .filter(|&i| self.run.bodies[i].passive)
            .collect();
        for i in geometry::draw_order(&self.run.final_poses, &passive, self.view) {
            chart.draw_series(std::iter::once(PathElement::new(
                closed(&self.projection(i)),
                style::FOUNDATION_OUTLINE.stroke_width(1),
            )))?;
        }

        for i in self.active_order() {
            let p = self.projection(i);
            let fill = self.fill(i);
            let pts: Vec<(f64, f64)> = p.iter().map(|q| (q[0], q[1])).collect();
            chart.draw_series(std::iter::once(Polygon::new(pts, fill.filled())))?;
            chart.draw_series(std::iter::once(PathElement::new(
                closed(&p),
                style::body_outline(fill).stroke_width(1),
            )))?;
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

        style::draw_legend(&legend, &self.legend())?;
        Ok(())
    }
}

//! `capacity`: the capacity curve of a pushover or cyclic analysis
//! ([`crate::fe::pushover`]): base shear over weight V/W against roof drift (%) (the
//! control node's displacement over its height above the base), one line through the
//! converged steps in order, the peak marked.
use super::font::FAMILY;
use super::history::value_range;
use super::{style, svg_string, Figure, Result};
use crate::fe::pushover::PushoverResult;
use plotters::coord::Shift;
use plotters::prelude::*;

/// The capacity-curve figure of a pushover result.
pub struct CapacityFigure {
    /// (roof drift %, V/W) per converged step.
    points: Vec<(f64, f64)>,
    /// The title.
    title: String,
}

impl CapacityFigure {
    /// The figure of `result` pushed along `direction` (0 = X, 1 = Y).
    pub fn new(result: &PushoverResult, direction: usize) -> Self {
        let points = result
            .curve
            .iter()
            .map(|p| {
                (
                    100.0 * p.control_displacement / result.control_height,
                    p.base_shear(direction) / result.weight,
                )
            })
            .collect();
        let title = format!(
            "Capacity curve - push along {}, control node {}",
            ["x", "y"][direction.min(1)],
            result.control_node
        );
        CapacityFigure { points, title }
    }
}

impl Figure for CapacityFigure {
    fn name(&self) -> &'static str {
        "capacity"
    }

    fn size(&self) -> (u32, u32) {
        (900, 600)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()>
    where
        DB::ErrorType: 'static,
    {
        root.fill(&style::BACKGROUND)?;
        let root = root.titled(&self.title, (FAMILY, style::TITLE_PX))?;
        let x = value_range(self.points.iter().map(|p| p.0));
        let y = value_range(self.points.iter().map(|p| p.1));
        let mut chart = ChartBuilder::on(&root)
            .margin(12)
            .x_label_area_size(45)
            .y_label_area_size(75)
            .build_cartesian_2d(x.0..x.1, y.0..y.1)?;
        let fx = style::tick_format(x.1 - x.0);
        let fy = style::tick_format(y.1 - y.0);
        chart
            .configure_mesh()
            .x_desc("roof drift (%)")
            .y_desc("base shear / weight V/W")
            .x_label_formatter(&fx)
            .y_label_formatter(&fy)
            .label_style((FAMILY, style::TICK_PX))
            .axis_desc_style((FAMILY, style::LABEL_PX))
            .light_line_style(style::GRID_LIGHT)
            .bold_line_style(style::GRID_BOLD)
            .draw()?;
        chart.draw_series(LineSeries::new(
            self.points.iter().copied(),
            style::FE_STAGE.stroke_width(2),
        ))?;
        if let Some(&peak) = self.points.iter().max_by(|a, b| a.1.total_cmp(&b.1)) {
            chart.draw_series(std::iter::once(
                EmptyElement::at(peak)
                    + Circle::new((0, 0), 5, style::PHYSICS_STAGE.filled())
                    + Text::new(
                        format!("peak V/W = {:.4} at {:.3} %", peak.1, peak.0),
                        (8, -20),
                        (FAMILY, style::LABEL_PX).into_font(),
                    ),
            ))?;
        }
        Ok(())
    }
}

/// The capacity curve of `result` as SVG text.
pub fn svg(result: &PushoverResult, direction: usize) -> Result<String> {
    svg_string(&CapacityFigure::new(result, direction))
}

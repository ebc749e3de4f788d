//! `energy`: the ruin stage's energy ledger against time, from `history.csv`'s energy
//! columns ([`crate::output::history`], [`crate::ruin::energy`]). Top panel, kJ: kinetic
//! (translational + rotational) T, potential V, mechanical E = T + V, the cumulative work
//! of the moving ground W_g and dissipated D (D includes Bullet's velocity damping), so
//! E + D − W_g is constant = E(start). Bottom panel: T alone, J, where the approach to
//! rest shows. Drawn only when the run folder has energy columns (ruin-stage frames);
//! the record's end (the start of the settle phase) is not marked, Tc is.
use super::history::{legend_entries, panel, time_range, Curve, LEGEND_W};
use super::style;
use super::Result;
use super::{font::FAMILY, run_label, tc_s, Figure, RunFolder};
use plotters::coord::Shift;
use plotters::prelude::*;

/// The energy figure of a run.
pub(crate) struct EnergyFigure<'a> {
    run: &'a RunFolder,
}

impl<'a> EnergyFigure<'a> {
    /// The energy figure of `run`.
    pub fn new(run: &'a RunFolder) -> Self {
        EnergyFigure { run }
    }

    /// Whether the run folder has any energy row.
    pub fn has_data(run: &RunFolder) -> bool {
        run.history.iter().any(|r| r.energy.is_some())
    }
}

fn curve(
    run: &RunFolder,
    colour: RGBColor,
    label: &str,
    f: impl Fn(&crate::output::history::EnergyRow) -> f64,
) -> Curve {
    Curve {
        colour,
        label: label.into(),
        points: run
            .history
            .iter()
            .filter_map(|r| r.energy.as_ref().map(|e| (r.t_s, f(e))))
            .collect(),
    }
}

impl Figure for EnergyFigure<'_> {
    fn name(&self) -> &'static str {
        "energy"
    }

    fn size(&self) -> (u32, u32) {
        (1100, 850)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()>
    where
        DB::ErrorType: 'static,
    {
        root.fill(&style::BACKGROUND)?;
        let title = format!("Energy ledger of the ruin stage - {}", run_label(self.run));
        let root = root.titled(&title, (FAMILY, style::TITLE_PX))?;
        let (w, h) = root.dim_in_pixel();
        let (main, legend) = root.split_horizontally(w.saturating_sub(LEGEND_W));
        let (top, bottom) = main.split_vertically(h / 2);
        let rows: Vec<_> = self
            .run
            .history
            .iter()
            .filter(|r| r.energy.is_some())
            .cloned()
            .collect();
        let tc = tc_s(self.run);
        let t = time_range(&rows, tc);
        let k = 1e-3;
        let main_curves = vec![
            curve(self.run, RGBColor(0, 90, 181), "kinetic T", |e| {
                k * (e.kinetic_j + e.rotational_j)
            }),
            curve(self.run, RGBColor(0, 140, 90), "potential V", |e| {
                k * e.potential_j
            }),
            curve(self.run, BLACK, "mechanical E = T + V", |e| {
                k * (e.kinetic_j + e.rotational_j + e.potential_j)
            }),
            curve(self.run, RGBColor(120, 85, 40), "ground work W_g", |e| {
                k * e.ground_work_j
            }),
            curve(self.run, RGBColor(220, 50, 32), "dissipated D", |e| {
                k * e.dissipated_j
            }),
        ];
        let kinetic = vec![curve(self.run, RGBColor(0, 90, 181), "kinetic T", |e| {
            e.kinetic_j + e.rotational_j
        })];
        panel(
            &top,
            t,
            tc,
            "energy (kJ)",
            &main_curves,
            "no energy in history.csv",
        )?;
        panel(
            &bottom,
            t,
            tc,
            "kinetic energy (J)",
            &kinetic,
            "no energy in history.csv",
        )?;
        style::draw_legend(&legend, &legend_entries("Energy", &[&main_curves], tc))?;
        Ok(())
    }
}

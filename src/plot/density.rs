//! `debris_density`: the debris-density map in plan of an ensemble folder
//! (`fem2rbd run --ensemble N`, [`crate::pipeline::ensemble`]). For every raster cell the
//! share of members in which the cell's centre lies inside the plan projection (convex
//! hull of the 8 corners, as in `summary.json`) of at least one active body at its final
//! pose: 1 = debris there in every member. Cell = 1/40 of the smaller side of the original
//! footprint; the original footprint is dashed; equal aspect.
use super::style::{self, Swatch};
use super::{font::FAMILY, Figure, RunFolder};
use super::{PlotError, Result};
use crate::plan_geometry::{bbox, corners, inside, projection};
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use std::collections::BTreeMap;
use std::path::Path;

/// The density map of an ensemble.
pub struct DensityFigure {
    /// Member count.
    pub members: usize,
    /// Cell side, m.
    pub cell_m: f64,
    /// (i, j) → share of members with debris in the cell.
    pub share: BTreeMap<(i64, i64), f64>,
    /// Original footprint (x range, y range), m.
    pub footprint: ([f64; 2], [f64; 2]),
    /// Title label.
    pub label: String,
}

/// A plan-view debris grid accumulated over runs of one model (an ensemble, or all runs
/// of one intensity of a study): square cells of side `cell_m`, cell (i, j) covering
/// [i·c, (i+1)·c) × [j·c, (j+1)·c) in world x, y (m). Per cell:
///
/// * `covered` — the number of runs in which the cell's centre lies inside the plan
///   projection (convex hull of the 8 corners, as in `summary.json`) of at least one
///   active body at its final pose;
/// * `centres` — the number of active bodies whose final centre lies in the cell, summed
///   over the runs. Σ `centres` = active bodies × runs; `centres` / (runs · c²) is the mean
///   number of bodies per m² (the density whose integral over the plan is the number of
///   bodies of one run).
#[derive(Debug, Clone, PartialEq)]
pub struct DensityGrid {
    /// Runs added.
    pub runs: usize,
    /// Active bodies of one run (the first run's).
    pub bodies: usize,
    /// Cell side, m: 1/40 of the smaller side of the original footprint.
    pub cell_m: f64,
    /// (i, j) → runs with debris over the cell's centre.
    pub covered: BTreeMap<(i64, i64), usize>,
    /// (i, j) → body final centres in the cell, over all runs.
    pub centres: BTreeMap<(i64, i64), usize>,
    /// Original footprint of the active bodies (x range, y range), m.
    pub footprint: ([f64; 2], [f64; 2]),
}

/// The cell holding `x` (m) for side `cell`.
pub fn cell_index(x: f64, cell: f64) -> i64 {
    (x / cell).floor() as i64
}

impl DensityGrid {
    /// An empty grid sized on `run`'s original footprint (its active bodies' undeformed
    /// boxes).
    pub fn for_run(run: &RunFolder) -> Self {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for b in run.bodies.iter().filter(|b| !b.passive) {
            for c in corners(&b.pose0, b.half_extents) {
                for k in 0..2 {
                    lo[k] = lo[k].min(c[k]);
                    hi[k] = hi[k].max(c[k]);
                }
            }
        }
        DensityGrid {
            runs: 0,
            bodies: run.bodies.iter().filter(|b| !b.passive).count(),
            cell_m: ((hi[0] - lo[0]).min(hi[1] - lo[1]).max(1e-3)) / 40.0,
            covered: BTreeMap::new(),
            centres: BTreeMap::new(),
            footprint: ([lo[0], hi[0]], [lo[1], hi[1]]),
        }
    }

    /// Adds one run's final poses.
    pub fn add(&mut self, run: &RunFolder) {
        let cell = self.cell_m;
        let mut cells = std::collections::BTreeSet::new();
        for (b, p) in run.bodies.iter().zip(&run.final_poses) {
            if b.passive {
                continue;
            }
            *self
                .centres
                .entry((
                    cell_index(p.position[0], cell),
                    cell_index(p.position[1], cell),
                ))
                .or_default() += 1;
            let poly = projection(p, b.half_extents);
            let (a, z) = bbox(&poly);
            for j in (a[1] / cell).floor() as i64..=(z[1] / cell).ceil() as i64 {
                for i in (a[0] / cell).floor() as i64..=(z[0] / cell).ceil() as i64 {
                    let (x, y) = ((i as f64 + 0.5) * cell, (j as f64 + 0.5) * cell);
                    if inside(&poly, x, y) {
                        cells.insert((i, j));
                    }
                }
            }
        }
        for c in cells {
            *self.covered.entry(c).or_default() += 1;
        }
        self.runs += 1;
    }

    /// The grid of run folders (sized on the first).
    pub fn of_runs(runs: &[RunFolder]) -> Result<Self> {
        let Some(first) = runs.first() else {
            return Err(PlotError::Input(
                "a density grid needs at least one run".to_string(),
            ));
        };
        let mut g = Self::for_run(first);
        for r in runs {
            g.add(r);
        }
        Ok(g)
    }

    /// Share of runs with debris over each cell (`covered` / runs).
    pub fn share(&self) -> BTreeMap<(i64, i64), f64> {
        self.covered
            .iter()
            .map(|(k, c)| (*k, *c as f64 / self.runs.max(1) as f64))
            .collect()
    }
}

impl DensityFigure {
    /// The figure of a grid, titled `label`.
    pub fn of_grid(g: &DensityGrid, label: String) -> Self {
        DensityFigure {
            members: g.runs,
            cell_m: g.cell_m,
            share: g.share(),
            footprint: g.footprint,
            label,
        }
    }

    /// Reads `dir/member-*/` (sorted) and computes the map.
    pub fn load(dir: &Path) -> Result<Self> {
        let mut members: Vec<_> = std::fs::read_dir(dir)
            .map_err(|e| PlotError::Input(format!("cannot read {}: {e}", dir.display())))?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| {
                p.is_dir()
                    && p.file_name()
                        .is_some_and(|n| n.to_string_lossy().starts_with("member-"))
            })
            .collect();
        members.sort();
        if members.is_empty() {
            return Err(PlotError::Input(format!(
                "{}: no member-NNN folders (not an ensemble folder)",
                dir.display()
            )));
        }
        let runs: Vec<RunFolder> = members
            .iter()
            .map(|p| RunFolder::load(p).map_err(|e| PlotError::Input(format!("{e:#}"))))
            .collect::<Result<_>>()?;
        let g = DensityGrid::of_runs(&runs)?;
        let label = format!("{} members, {}", g.runs, dir.display());
        Ok(Self::of_grid(&g, label))
    }
}

/// White → dark red for shares 0 → 1.
fn shade(s: f64) -> RGBColor {
    let s = s.clamp(0.0, 1.0);
    let lerp = |a: f64, b: f64| (a + (b - a) * s).round() as u8;
    RGBColor(lerp(255.0, 150.0), lerp(235.0, 0.0), lerp(220.0, 20.0))
}

impl Figure for DensityFigure {
    fn name(&self) -> &'static str {
        "debris_density"
    }

    fn size(&self) -> (u32, u32) {
        (1100, 900)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()>
    where
        DB::ErrorType: 'static,
    {
        root.fill(&style::BACKGROUND)?;
        let title = format!("Debris density in plan - {}", self.label);
        let root = root.titled(&title, (FAMILY, style::TITLE_PX))?;
        let (w, _) = root.dim_in_pixel();
        let (main, legend) = root.split_horizontally(w.saturating_sub(210));
        let c = self.cell_m;
        let (mut lo, mut hi) = (
            [self.footprint.0[0], self.footprint.1[0]],
            [self.footprint.0[1], self.footprint.1[1]],
        );
        for &(i, j) in self.share.keys() {
            lo[0] = lo[0].min(i as f64 * c);
            lo[1] = lo[1].min(j as f64 * c);
            hi[0] = hi[0].max((i + 1) as f64 * c);
            hi[1] = hi[1].max((j + 1) as f64 * c);
        }
        // Equal aspect: the plot area is about 890 × 790 px.
        let (sx, sy) = (hi[0] - lo[0], hi[1] - lo[1]);
        let scale = (sx / 830.0).max(sy / 730.0) * 1.05;
        let (cx, cy) = (0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]));
        let (hx, hy) = (415.0 * scale, 365.0 * scale);
        let mut chart = ChartBuilder::on(&main)
            .margin(12)
            .x_label_area_size(45)
            .y_label_area_size(60)
            .build_cartesian_2d(cx - hx..cx + hx, cy - hy..cy + hy)?;
        chart
            .configure_mesh()
            .x_desc("x (m)")
            .y_desc("y (m)")
            .label_style((FAMILY, style::TICK_PX))
            .axis_desc_style((FAMILY, style::LABEL_PX))
            .light_line_style(style::GRID_LIGHT)
            .bold_line_style(style::GRID_BOLD)
            .draw()?;
        chart.draw_series(self.share.iter().map(|(&(i, j), &s)| {
            Rectangle::new(
                [
                    (i as f64 * c, j as f64 * c),
                    ((i + 1) as f64 * c, (j + 1) as f64 * c),
                ],
                shade(s).filled(),
            )
        }))?;
        let (fx, fy) = self.footprint;
        chart.draw_series(std::iter::once(DashedPathElement::new(
            vec![
                (fx[0], fy[0]),
                (fx[1], fy[0]),
                (fx[1], fy[1]),
                (fx[0], fy[1]),
                (fx[0], fy[0]),
            ],
            6,
            4,
            style::FOOTPRINT.stroke_width(2),
        )))?;
        let mut entries = vec![(Swatch::Heading, "Share of runs".to_string())];
        for s in [0.2, 0.4, 0.6, 0.8, 1.0] {
            entries.push((Swatch::Fill(shade(s)), format!("{:.0} %", 100.0 * s)));
        }
        entries.push((
            Swatch::Dashed(style::FOOTPRINT),
            "original footprint".to_string(),
        ));
        entries.push((Swatch::Heading, format!("cell {:.3} m", c)));
        style::draw_legend(&legend, &entries)?;
        Ok(())
    }
}

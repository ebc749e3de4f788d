//! Figures of a collected study folder (`fem2rbd plot STUDY_DIR`), from `results/ida.csv`
//! and `results/study.json` alone ([`super::collect`]), one pair per (model, mode):
//!
//! * `ida_<model>_<mode>` — IDA curves: PGA (g, vertical, the usual IDA orientation)
//!   against peak roof drift (%, up to Tc), one line per record, collapsing runs drawn
//!   as crosses;
//! * `fragility_<model>_<mode>` — the fitted lognormal P(collapse) = Φ((ln x − ln θ)/β)
//!   with θ and β in the title, and the data: for an IDA the empirical distribution of the
//!   records' collapse capacities (fraction of all records, censored ones included in the
//!   count), for stripes the fraction of collapses per intensity.
//!
//! Text in the bundled DejaVu Sans; same folder, same bytes; the set written all or
//! nothing.
use super::error::{bail, At, Result, StudyError};
use crate::plot::font::FAMILY;
use crate::plot::style;
use crate::plot::{png_bytes, svg_string, Figure, ImageFormat};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Record colours (cycled).
const PALETTE: [RGBColor; 8] = [
    RGBColor(0, 90, 181),
    RGBColor(220, 50, 32),
    RGBColor(0, 140, 90),
    RGBColor(230, 140, 0),
    RGBColor(120, 60, 170),
    RGBColor(90, 90, 90),
    RGBColor(0, 170, 200),
    RGBColor(170, 110, 40),
];

/// One IDA point.
#[derive(Debug, Clone, PartialEq)]
struct Point {
    pga_g: f64,
    drift: Option<f64>,
    collapse: bool,
}

/// IDA curves of one (model, mode).
pub struct IdaFigure {
    name: &'static str,
    title: String,
    curves: Vec<(String, Vec<Point>)>,
}

/// Fragility of one (model, mode).
pub struct FragilityFigure {
    title: String,
    fit: Option<(f64, f64)>,
    /// Data points (x g, fraction), drawn as markers (stripes) or a step line (IDA).
    points: Vec<(f64, f64)>,
    ida: bool,
    x_max: f64,
}

fn mesh<DB: DrawingBackend, X, Y>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<X, Y>>,
    x: &str,
    y: &str,
) -> crate::plot::Result<()>
where
    DB::ErrorType: 'static,
    X: Ranged<ValueType = f64> + plotters::coord::ranged1d::ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + plotters::coord::ranged1d::ValueFormatter<f64>,
{
    chart
        .configure_mesh()
        .x_desc(x)
        .y_desc(y)
        .label_style((FAMILY, style::TICK_PX))
        .axis_desc_style((FAMILY, style::LABEL_PX))
        .light_line_style(style::GRID_LIGHT)
        .bold_line_style(style::GRID_BOLD)
        .draw()?;
    Ok(())
}

impl Figure for IdaFigure {
    fn name(&self) -> &'static str {
        self.name
    }
    fn size(&self) -> (u32, u32) {
        (900, 640)
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> crate::plot::Result<()>
    where
        DB::ErrorType: 'static,
    {
        root.fill(&style::BACKGROUND)?;
        let d_max = self
            .curves
            .iter()
            .flat_map(|c| c.1.iter().filter_map(|p| p.drift))
            .fold(0.0f64, f64::max)
            * 100.0;
        let g_max = self
            .curves
            .iter()
            .flat_map(|c| c.1.iter().map(|p| p.pga_g))
            .fold(0.0f64, f64::max);
        let (dx, gy) = (
            if d_max > 0.0 { d_max * 1.08 } else { 1.0 },
            if g_max > 0.0 { g_max * 1.08 } else { 1.0 },
        );
        let mut chart = ChartBuilder::on(root)
            .caption(&self.title, (FAMILY, style::TITLE_PX))
            .margin(16)
            .x_label_area_size(50)
            .y_label_area_size(70)
            .build_cartesian_2d(0.0..dx, 0.0..gy)?;
        mesh(&mut chart, "peak roof drift up to Tc (%)", "PGA (g)")?;
        for (k, (record, pts)) in self.curves.iter().enumerate() {
            let c = PALETTE[k % PALETTE.len()];
            let line: Vec<(f64, f64)> = pts
                .iter()
                .filter_map(|p| p.drift.map(|d| (d * 100.0, p.pga_g)))
                .collect();
            chart
                .draw_series(LineSeries::new(line.clone(), c.stroke_width(2)))?
                .label(record.clone())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(2))
                });
            chart.draw_series(pts.iter().filter_map(|p| {
                let d = p.drift? * 100.0;
                Some(if p.collapse {
                    Cross::new((d, p.pga_g), 6, c.stroke_width(2)).into_dyn()
                } else {
                    Circle::new((d, p.pga_g), 4, c.filled()).into_dyn()
                })
            }))?;
        }
        chart
            .configure_series_labels()
            .background_style(style::BACKGROUND.mix(0.9))
            .border_style(style::GRID_BOLD)
            .label_font((FAMILY, style::LABEL_PX))
            .position(SeriesLabelPosition::LowerRight)
            .draw()?;
        root.draw(&Text::new(
            "dot: no collapse, cross: collapse (Tc)",
            (90, 600),
            (FAMILY, style::TICK_PX),
        ))?;
        Ok(())
    }
}

impl Figure for FragilityFigure {
    fn name(&self) -> &'static str {
        "fragility"
    }
    fn size(&self) -> (u32, u32) {
        (900, 640)
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> crate::plot::Result<()>
    where
        DB::ErrorType: 'static,
    {
        root.fill(&style::BACKGROUND)?;
        let mut chart = ChartBuilder::on(root)
            .caption(&self.title, (FAMILY, style::TITLE_PX))
            .margin(16)
            .x_label_area_size(50)
            .y_label_area_size(70)
            .build_cartesian_2d(0.0..self.x_max, 0.0..1.0)?;
        mesh(&mut chart, "PGA (g)", "P(collapse)")?;
        let data_c = style::FE_STAGE;
        if self.ida {
            // Empirical CDF as steps.
            let mut steps = vec![(0.0, 0.0)];
            let mut last = 0.0;
            for &(x, f) in &self.points {
                steps.push((x, last));
                steps.push((x, f));
                last = f;
            }
            steps.push((self.x_max, last));
            chart
                .draw_series(LineSeries::new(steps, data_c.stroke_width(2)))?
                .label("records' collapse capacities (empirical)")
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], data_c.stroke_width(2))
                });
        } else {
            chart
                .draw_series(
                    self.points
                        .iter()
                        .map(|&(x, f)| Circle::new((x, f), 5, data_c.filled())),
                )?
                .label("fraction collapsed")
                .legend(move |(x, y)| Circle::new((x + 10, y), 5, data_c.filled()));
        }
        if let Some((theta, beta)) = self.fit {
            let fit_c = style::PHYSICS_STAGE;
            let n = 400;
            let pts: Vec<(f64, f64)> = (1..=n)
                .map(|i| {
                    let x = self.x_max * i as f64 / n as f64;
                    (x, super::fragility::phi((x / theta).ln() / beta))
                })
                .collect();
            chart
                .draw_series(LineSeries::new(pts, fit_c.stroke_width(3)))?
                .label(format!("lognormal MLE: θ = {theta:.3} g, β = {beta:.3}"))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], fit_c.stroke_width(3))
                });
        }
        chart
            .configure_series_labels()
            .background_style(style::BACKGROUND.mix(0.9))
            .border_style(style::GRID_BOLD)
            .label_font((FAMILY, style::LABEL_PX))
            .position(SeriesLabelPosition::LowerRight)
            .draw()?;
        Ok(())
    }
}

/// Renders `fig` as `out/<stem>.png` and / or `.svg` into `set` (written by
/// [`crate::plot::write_set`], all or nothing).
fn render<F: Figure>(
    fig: &F,
    stem: &str,
    out: &Path,
    format: ImageFormat,
    set: &mut Vec<(PathBuf, Vec<u8>)>,
) -> Result<()> {
    if matches!(format, ImageFormat::Png | ImageFormat::Both) {
        set.push((out.join(format!("{stem}.png")), png_bytes(fig)?));
    }
    if matches!(format, ImageFormat::Svg | ImageFormat::Both) {
        set.push((
            out.join(format!("{stem}.svg")),
            svg_string(fig)?.into_bytes(),
        ));
    }
    Ok(())
}

/// A collected study folder: it has `results/study.json`.
pub fn is_study_folder(dir: &Path) -> bool {
    dir.join("results").join("study.json").is_file()
}

/// One figure of a study: IDA curves, a fragility, or an intensity's debris density.
pub enum StudyFigure {
    /// IDA curves of one (model, mode).
    Ida(IdaFigure),
    /// The collapse fragility of one (model, mode).
    Fragility(FragilityFigure),
    /// The debris density of one (model, mode, intensity).
    Density(crate::plot::density::DensityFigure),
}

impl Figure for StudyFigure {
    fn name(&self) -> &'static str {
        match self {
            StudyFigure::Ida(f) => f.name(),
            StudyFigure::Fragility(f) => f.name(),
            StudyFigure::Density(f) => f.name(),
        }
    }
    fn size(&self) -> (u32, u32) {
        match self {
            StudyFigure::Ida(f) => f.size(),
            StudyFigure::Fragility(f) => f.size(),
            StudyFigure::Density(f) => f.size(),
        }
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> crate::plot::Result<()>
    where
        DB::ErrorType: 'static,
    {
        match self {
            StudyFigure::Ida(f) => f.draw(root),
            StudyFigure::Fragility(f) => f.draw(root),
            StudyFigure::Density(f) => f.draw(root),
        }
    }
}

/// Writes the figures of the collected study `dir` into `out` (created), all or nothing:
/// every figure is rendered before the first file is written ([`crate::plot::write_set`]).
pub fn write_all(dir: &Path, out: &Path, format: ImageFormat) -> Result<Vec<PathBuf>> {
    let figs = figures(dir)?;
    let mut set = Vec::new();
    for (stem, fig) in &figs {
        render(fig, stem, out, format, &mut set)?;
    }
    std::fs::create_dir_all(out).at(|| format!("cannot create {}", out.display()))?;
    Ok(crate::plot::write_set(set)?)
}

/// The figures of the collected study `dir` with their file stems, in writing order:
/// `ida_<model>_<mode>` per (model, mode) of `ida.csv`, `fragility_<model>_<mode>` per
/// fragility of `study.json`, `density_<model>_<mode>_<pga>g` per `results/density/*.json`.
pub fn figures(dir: &Path) -> Result<Vec<(String, StudyFigure)>> {
    let results = dir.join("results");
    let sj = super::plan::read_json(&results.join("study.json"))?;
    let ida_path = results.join("ida.csv");
    let text = crate::model::limits::read_regular_file(&ida_path)
        .at(|| format!("cannot read {}", ida_path.display()))?;
    // model, mode → record → points
    let mut curves: BTreeMap<(String, String), BTreeMap<String, Vec<Point>>> = BTreeMap::new();
    let mut lines = text.lines();
    if lines.next() != Some("model,mode,record,pga_g,peak_roof_drift,collapse") {
        bail!("{}:1: not an ida.csv header", ida_path.display());
    }
    for (i, l) in lines.enumerate() {
        let f: Vec<&str> = l.split(',').collect();
        let bad =
            || StudyError::Invalid(format!("{}:{}: bad row {l:?}", ida_path.display(), i + 2));
        if f.len() != 6 {
            return Err(bad());
        }
        let p = Point {
            pga_g: f[3].parse().map_err(|_| bad())?,
            drift: if f[4].is_empty() {
                None
            } else {
                Some(f[4].parse().map_err(|_| bad())?)
            },
            collapse: f[5] == "1",
        };
        curves
            .entry((f[0].to_string(), f[1].to_string()))
            .or_default()
            .entry(f[2].to_string())
            .or_default()
            .push(p);
    }
    let study = sj["study"].as_str().unwrap_or("study");
    let mut files = Vec::new();
    for ((model, mode), recs) in &curves {
        let fig = IdaFigure {
            name: "ida",
            title: format!("{study}: IDA, {model}, mode {mode}"),
            curves: recs.iter().map(|(k, v)| (k.clone(), v.clone())).collect(),
        };
        files.push((format!("ida_{model}_{mode}"), StudyFigure::Ida(fig)));
    }
    let empty = Vec::new();
    for fr in sj["fragility"].as_array().unwrap_or(&empty) {
        let model = fr["model"].as_str().unwrap_or("?");
        let mode = fr["mode"].as_str().unwrap_or("?");
        let ida = fr["method"].as_str().is_some_and(|m| m.starts_with("ida"));
        let fit = fr["fit"]["median_g"]
            .as_f64()
            .zip(fr["fit"]["beta"].as_f64());
        let data = fr["data"].as_array().unwrap_or(&empty);
        let mut points = Vec::new();
        let mut x_max: f64 = 0.0;
        if ida {
            let n = data.len() as f64;
            let mut caps: Vec<f64> = data
                .iter()
                .filter_map(|d| d["collapse_g"].as_f64())
                .collect();
            caps.sort_by(f64::total_cmp);
            for (k, x) in caps.iter().enumerate() {
                points.push((*x, (k + 1) as f64 / n));
            }
            x_max = data
                .iter()
                .filter_map(|d| d["collapse_g"].as_f64().or(d["censored_at_g"].as_f64()))
                .fold(0.0, f64::max);
        } else {
            for d in data {
                let (Some(x), Some(r), Some(z)) = (
                    d["pga_g"].as_f64(),
                    d["runs"].as_f64(),
                    d["collapses"].as_f64(),
                ) else {
                    continue;
                };
                points.push((x, z / r));
                x_max = x_max.max(x);
            }
        }
        if let Some((t, b)) = fit {
            x_max = x_max.max(t * (2.0 * b).exp());
        }
        let title = match fit {
            Some((t, b)) => format!(
                "{study}: collapse fragility, {model}, mode {mode} (θ = {t:.3} g, β = {b:.3})"
            ),
            None => format!(
                "{study}: collapse fragility, {model}, mode {mode} (no fit: {})",
                fr["fit_error"]
                    .as_str()
                    .unwrap_or("?")
                    .trim_start_matches("fragility: ")
            ),
        };
        let fig = FragilityFigure {
            title,
            fit,
            points,
            ida,
            x_max: if x_max > 0.0 { x_max * 1.05 } else { 1.0 },
        };
        files.push((
            format!("fragility_{model}_{mode}"),
            StudyFigure::Fragility(fig),
        ));
    }
    files.extend(density_figures(dir)?);
    Ok(files)
}

/// The debris-density figure of one `results/density/<stem>.json` ([`super::collect`]).
pub fn density_figure(path: &Path) -> Result<crate::plot::density::DensityFigure> {
    let j = super::plan::read_json(path)?;
    let bad =
        |what: &str| StudyError::Invalid(format!("{}: {what} missing or invalid", path.display()));
    let runs = j["runs"]
        .as_u64()
        .filter(|r| *r > 0)
        .ok_or_else(|| bad("runs"))?;
    let cell = j["cell_m"]
        .as_f64()
        .filter(|c| *c > 0.0)
        .ok_or_else(|| bad("cell_m"))?;
    let fp = |k: &str, i: usize| {
        j["footprint_m"][k][i]
            .as_f64()
            .ok_or_else(|| bad("footprint_m"))
    };
    let mut share = BTreeMap::new();
    for c in j["cells"].as_array().ok_or_else(|| bad("cells"))? {
        let (Some(i), Some(jj), Some(cov)) = (c[0].as_i64(), c[1].as_i64(), c[2].as_u64()) else {
            return Err(bad("cells"));
        };
        if cov > 0 {
            share.insert((i, jj), cov as f64 / runs as f64);
        }
    }
    Ok(crate::plot::density::DensityFigure {
        members: runs as usize,
        cell_m: cell,
        share,
        footprint: ([fp("x", 0)?, fp("x", 1)?], [fp("y", 0)?, fp("y", 1)?]),
        label: format!(
            "{}: {}, mode {}, PGA {:.3} g, {} runs",
            j["study"].as_str().unwrap_or("study"),
            j["model"].as_str().unwrap_or("?"),
            j["mode"].as_str().unwrap_or("?"),
            j["pga_g"].as_f64().unwrap_or(f64::NAN),
            runs
        ),
    })
}

/// `density_<model>_<mode>_<pga>g` for every `results/density/*.json`, in name order.
fn density_figures(dir: &Path) -> Result<Vec<(String, StudyFigure)>> {
    let ddir = dir.join("results").join("density");
    if !ddir.is_dir() {
        return Ok(Vec::new());
    }
    let mut jsons: Vec<PathBuf> = std::fs::read_dir(&ddir)
        .at(|| format!("cannot read {}", ddir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    jsons.sort();
    let mut files = Vec::new();
    for p in jsons {
        let fig = density_figure(&p)?;
        let stem = p
            .file_stem()
            .map(|s| s.to_string_lossy().replace("__", "_"))
            .unwrap_or_default();
        files.push((format!("density_{stem}"), StudyFigure::Density(fig)));
    }
    Ok(files)
}

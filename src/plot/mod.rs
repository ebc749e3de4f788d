//! Figures of a run folder (`fem2rbd plot`), PNG and SVG, drawn with plotters.
//!
//! Figures (file stems):
//!
//! * `ruin_plan` — the final pose of every body projected on the ground plane (convex hull
//!   of its 8 corners), filled by element type, darker for lower stories, drawn bottom to
//!   top; passive foundations outlined; the original footprint dashed; equal aspect;
//! * `ruin_elevation_xz`, `ruin_elevation_yz` — the same bodies on x–z (seen from −y) and
//!   y–z (seen from +x), back to front, with the final ground line;
//! * `history` — roof drift (%) and maximum vertical drop (m) against time, FE and ruin
//!   stage in different colours, Tc marked;
//! * `connections` — intact / plastic / broken connection counts against time over the
//!   ruin stage, Tc marked;
//! * `energy` — the ruin stage's energy ledger ([`energy`]), when `history.csv` has it;
//! * `debris_density` — for an ensemble folder (`ensemble.json`): the share of members
//!   with debris in each plan cell ([`density`]);
//! * `voids_plan`, `voids_section_xz`, `voids_section_yz` — the run's voids (`voids.csv`)
//!   by pattern and survivability with the rescuer's entry sides, when the run has them;
//!   `rescue_map` — an ensemble's chance of a survivable void per plan cell
//!   (`rescue_map.csv`), when it has one ([`voids`]).
//!
//! Definitions of the drawn quantities: [`geometry`] and [`crate::output::history`].
//! Text uses the bundled DejaVu Sans ([`font`]), never a system font. Same run folder,
//! same bytes: drawing orders are sorted, PNGs are encoded in memory with fixed settings
//! and every file is written atomically.
pub mod capacity;
pub mod connections;
pub mod density;
pub mod energy;
pub mod font;
pub mod geometry;
pub mod history;
pub mod ruin;
pub mod style;
pub mod voids;

pub use crate::output::run_folder::{BodyInfo, HistoryRow, RunFolder};

use crate::output::AtomicFile;
use crate::output::OutputError;

/// A figure that cannot be made: the run folder cannot be read, drawing or encoding
/// failed, or the file cannot be written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PlotError {
    /// The run or ensemble folder cannot be read (the message names the file and line).
    #[error("{0}")]
    Input(String),
    /// The bundled font could not be registered.
    #[error("the bundled font data/fonts/DejaVuSans.ttf could not be parsed")]
    Font,
    /// plotters failed while drawing a figure.
    #[error("drawing {figure}: {message}")]
    Draw {
        /// The figure (file stem), empty inside a figure's own code.
        figure: &'static str,
        /// plotters' message.
        message: String,
    },
    /// PNG encoding failed.
    #[error("PNG encoding: {0}")]
    Png(#[from] png::EncodingError),
    /// A figure file or the plot folder cannot be written.
    #[error("writing {}: {error}", path.display())]
    Write {
        /// The file or folder.
        path: PathBuf,
        /// What failed.
        error: OutputError,
    },
}

impl<E: std::error::Error + Send + Sync + 'static> From<DrawingAreaErrorKind<E>> for PlotError {
    fn from(e: DrawingAreaErrorKind<E>) -> Self {
        PlotError::Draw {
            figure: "",
            message: e.to_string(),
        }
    }
}

/// What drawing returns.
pub type Result<T> = std::result::Result<T, PlotError>;

/// The figure's name on a drawing error raised inside its code.
fn named(figure: &'static str) -> impl FnOnce(PlotError) -> PlotError {
    move |e| match e {
        PlotError::Draw { message, .. } => PlotError::Draw { figure, message },
        e => e,
    }
}
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::{Path, PathBuf};

/// Which files to write.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum ImageFormat {
    /// PNG only.
    Png,
    /// SVG only.
    Svg,
    /// PNG and SVG.
    Both,
}

impl ImageFormat {
    fn png(self) -> bool {
        matches!(self, ImageFormat::Png | ImageFormat::Both)
    }
    fn svg(self) -> bool {
        matches!(self, ImageFormat::Svg | ImageFormat::Both)
    }
}

/// A figure that can be drawn on any plotters backend.
pub trait Figure {
    /// File stem (`ruin_plan`, ...).
    fn name(&self) -> &'static str;
    /// Size in pixels (width, height); the SVG uses the same user units.
    fn size(&self) -> (u32, u32);
    /// Draws the whole figure on `root` (of [`Figure::size`]).
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()>
    where
        DB::ErrorType: 'static;
}

/// The figure as PNG bytes (8-bit RGB).
pub fn png_bytes<F: Figure>(fig: &F) -> Result<Vec<u8>> {
    font::ensure_registered()?;
    let (w, h) = fig.size();
    let mut rgb = vec![0u8; w as usize * h as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area();
        fig.draw(&root).map_err(named(fig.name()))?;
        root.present()?;
    }
    let mut out = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut out, w, h);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        let mut writer = enc.write_header()?;
        writer.write_image_data(&rgb)?;
        writer.finish()?;
    }
    Ok(out)
}

/// The figure as SVG text.
pub fn svg_string<F: Figure>(fig: &F) -> Result<String> {
    font::ensure_registered()?;
    let mut s = String::new();
    {
        let root = SVGBackend::with_string(&mut s, fig.size()).into_drawing_area();
        fig.draw(&root).map_err(named(fig.name()))?;
        root.present()?;
    }
    Ok(s)
}

/// Renders `fig` in `format` and adds its files (path, bytes) to `set`.
fn render<F: Figure>(
    fig: &F,
    out: &Path,
    format: ImageFormat,
    set: &mut Vec<(PathBuf, Vec<u8>)>,
) -> Result<()> {
    if format.png() {
        set.push((out.join(format!("{}.png", fig.name())), png_bytes(fig)?));
    }
    if format.svg() {
        set.push((
            out.join(format!("{}.svg", fig.name())),
            svg_string(fig)?.into_bytes(),
        ));
    }
    Ok(())
}

/// Writes a rendered figure set all or nothing: every file is written to its temporary
/// file ([`AtomicFile`]) before the first is renamed into place, so a failure while
/// writing (a full disk, a target that is a folder) leaves no new figure and no
/// temporary file.
pub(crate) fn write_set(set: Vec<(PathBuf, Vec<u8>)>) -> Result<Vec<PathBuf>> {
    use std::io::Write;
    let mut pending = Vec::with_capacity(set.len());
    for (p, bytes) in &set {
        let werr = |error| PlotError::Write {
            path: p.clone(),
            error,
        };
        let mut f = AtomicFile::create(p).map_err(werr)?;
        f.write_all(bytes)
            .and_then(|()| f.flush())
            .map_err(|e| werr(OutputError::io("cannot write", p)(e)))?;
        pending.push(f);
    }
    for (f, (p, _)) in pending.into_iter().zip(&set) {
        f.commit().map_err(|error| PlotError::Write {
            path: p.clone(),
            error,
        })?;
    }
    Ok(set.into_iter().map(|(p, _)| p).collect())
}

/// Writes the debris-density map of the ensemble folder `dir` and, when it has one, its
/// rescue map into `out` (created).
pub fn write_ensemble(dir: &Path, out: &Path, format: ImageFormat) -> Result<Vec<PathBuf>> {
    let fig = density::DensityFigure::load(dir)?;
    let mut set = Vec::new();
    render(&fig, out, format, &mut set)?;
    if let Some(map) = voids::RescueMapFigure::load(dir)? {
        render(&map, out, format, &mut set)?;
    }
    create_folder(out)?;
    write_set(set)
}

/// Creates the plot folder `out` once every figure is rendered (an input error leaves no
/// empty folder behind).
fn create_folder(out: &Path) -> Result<()> {
    std::fs::create_dir_all(out).map_err(|e| PlotError::Write {
        path: out.to_path_buf(),
        error: OutputError::io("cannot create the plot folder", out)(e),
    })
}

/// Writes every figure of `run` into `out` (created), all or nothing ([`write_set`]), and
/// returns the files written.
pub fn write_all(run: &RunFolder, out: &Path, format: ImageFormat) -> Result<Vec<PathBuf>> {
    let mut set = Vec::new();
    for view in [
        geometry::View::Plan,
        geometry::View::ElevationXz,
        geometry::View::ElevationYz,
    ] {
        render(&ruin::RuinFigure::new(run, view), out, format, &mut set)?;
    }
    render(&history::HistoryFigure::new(run), out, format, &mut set)?;
    render(
        &connections::ConnectionsFigure::new(run),
        out,
        format,
        &mut set,
    )?;
    if energy::EnergyFigure::has_data(run) {
        render(&energy::EnergyFigure::new(run), out, format, &mut set)?;
    }
    if let Some(vs) = voids::read_voids(&run.dir)? {
        for view in [
            geometry::View::Plan,
            geometry::View::ElevationXz,
            geometry::View::ElevationYz,
        ] {
            let fig = voids::VoidsFigure::new(Some(run), view, vs.clone());
            render(&fig, out, format, &mut set)?;
        }
    }
    create_folder(out)?;
    write_set(set)
}

/// The run's mode and collapse moment for titles, from `summary.json`:
/// `mode rigid, no Tc (rigid_only)` or `mode hybrid, Tc = 1.660 s (criterion)`.
pub(crate) fn run_label(run: &RunFolder) -> String {
    let mode = run.summary.mode.name();
    let reason = run.summary.tc_reason.name();
    match tc_s(run) {
        Some(tc) => format!("mode {mode}, Tc = {tc:.3} s ({reason})"),
        None => format!("mode {mode}, no Tc ({reason})"),
    }
}

/// Tc from `summary.json` (`tc_s`), s; None without collapse.
pub fn tc_s(run: &RunFolder) -> Option<f64> {
    run.summary.tc_s
}

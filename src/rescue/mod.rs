//! The rescue scenario of a ruin: where the voids are (covered free space a person could
//! survive in), how a rescuer or a search camera reaches them, and how high and wide the
//! rubble lies. It reads a run folder's `bodies.csv`, `ruins.csv` and `connections.csv`
//! (and the model scale from `summary.json`) and nothing else (docs/rescue.md).
//!
//! The steps, one file each:
//!
//! * [`input`]: the final boxes, their undeformed poses and the connections that still hold;
//! * [`grid`]: the regular grid over the ruin (cell size, extent, memory bound);
//! * [`occupancy`]: each cell's exact volume fraction covered by boxes (a convex clip);
//! * [`distance`]: the exact Euclidean distance transform (Felzenszwalb & Huttenlocher
//!   2012) of the solid cells, giving every free cell's clearance;
//! * [`boxes`]: a void's cells as a few disjoint boxes of whole cells;
//! * [`voids`]: free space under debris (covered) vs open air, split into chambers under
//!   one roof each, their measures and the throats between them;
//! * [`person`]: the body sizes that make a void survivable, and the rescuer's and the
//!   camera's sizes;
//! * [`pattern`]: the collapse pattern of each void from its roof bodies;
//! * [`access`]: routes from open air for a rescuer and a camera, else the least debris
//!   to breach;
//! * [`flood`]: the searches behind them, confined to the cells below each column's open
//!   air;
//! * [`route`]: the route of an access as a line (traced back along the search's steps,
//!   simplified to within a cell);
//! * [`rubble`]: height map, pile height, debris extent against the building height,
//!   porosity;
//! * [`stories`]: each story's volume loss (the free space under its ceiling, standing
//!   and in the ruin);
//! * [`report`]: `voids.csv`, `voids.json` and `rubble_height.csv`;
//! * [`volumes`]: the survivable voids of a `voids.json` as the volumes of `collapse.glb`;
//! * [`ensemble`]: over an ensemble's members, the plan map of the chance of a survivable
//!   void, the spread of the measures and the voids that recur in one place.
//!
//! Two threads: the standing building's occupancy (for the story losses) beside the
//! ruin's, then the rescuer's and the camera's searches beside the chambers, the story
//! losses and the breach search. Each reads its input only and writes its own result,
//! and everything else runs in a fixed order: the same run folder gives the same bytes.
pub mod access;
pub mod boxes;
pub mod distance;
pub mod ensemble;
pub mod flood;
pub mod grid;
pub mod input;
pub mod occupancy;
pub mod pattern;
pub mod person;
pub mod report;
pub mod route;
pub mod rubble;
pub mod stories;
pub mod voids;
pub mod volumes;

pub use input::{Connection, Ruin, RuinBox};
pub use person::Sizes;
pub use report::{analyse, Analysis};

/// Why a rescue analysis cannot run: a run folder file missing or inconsistent, a size
/// out of range, or a grid too large. Nothing is written when it fails.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RescueError {
    /// A run folder file could not be read or parsed (the file and line named).
    #[error(transparent)]
    RunFolder(#[from] crate::output::run_folder::RunFolderError),
    /// A file's content is inconsistent with the others (the file and line named).
    #[error("{file}:{line}: {message}")]
    Inconsistent {
        /// The file.
        file: String,
        /// The line (1-based).
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A size option is zero, negative or not finite.
    #[error("{option} = {value} m: {message}")]
    Size {
        /// The option (`--cell`, `--rescuer`, `--camera`, or the scale).
        option: &'static str,
        /// Its value.
        value: f64,
        /// The rule it breaks.
        message: String,
    },
    /// The grid would need more cells than [`grid::max_cells`] (more memory than the
    /// machine has, or than [`grid::MAX_BYTES`]).
    #[error(
        "--cell {cell_m} m (full scale; {model_cell_m} m at the model's scale) needs a grid of \
         {nx} x {ny} x {nz} = {cells} cells over the ruin ({extent}), more than the bound of \
         {max} cells (about {bytes_per_cell} bytes each, within the memory available now and at \
         most 16 GiB): give a larger --cell"
    )]
    GridTooLarge {
        /// The cell size asked for, full scale, m.
        cell_m: f64,
        /// The cell size at the model's scale, m.
        model_cell_m: f64,
        /// Cells along x.
        nx: u64,
        /// Cells along y.
        ny: u64,
        /// Cells along z.
        nz: u64,
        /// Their product.
        cells: u64,
        /// The extent in words.
        extent: String,
        /// The bound.
        max: u64,
        /// Memory per cell, bytes.
        bytes_per_cell: u64,
    },
    /// An output file could not be written.
    #[error(transparent)]
    Output(#[from] crate::output::OutputError),
}

/// What rescue analysis returns.
pub type Result<T> = std::result::Result<T, RescueError>;

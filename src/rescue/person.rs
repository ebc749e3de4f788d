//! The sizes a rescue analysis measures against, all given at full (prototype) scale in
//! metres and multiplied by the model's geometric scale before use (a 1/4-scale model's
//! ruin is measured with a quarter-size person and grid).
//!
//! * **Survivable** means that an adult fits, lying (1.8 × 0.5 × 0.3 m) or sitting
//!   (0.5 × 0.5 × 0.9 m), as an axis-aligned block in the void's free cells. No published
//!   minimum survivable void size exists; these are the usual reasoning of rescue courses
//!   (docs/rescue.md §1).
//! * The **rescuer** crawls through a passage as wide as `rescuer_m` (default 0.6 m: the
//!   shoulder width of an adult with protective clothing, the size of the openings breached
//!   for entry; an assumption stated in docs/rescue.md).
//! * The **search camera** needs `camera_m` (default 0.075 m: the head of a search camera
//!   on a pole or a fibre-optic scope is 0.04–0.1 m across).
//! * The **cell** of the grid is `cell_m` (default 0.1 m: a third of the lying
//!   clearance 0.3 m, so the smallest dimension that decides survivability is resolved to a
//!   third; the camera's 0.075 m is below it, and a free cell always lets a camera through).
use super::{RescueError, Result};

/// Default grid cell at full scale, m.
pub const DEFAULT_CELL_M: f64 = 0.1;
/// Default rescuer passage width at full scale, m.
pub const DEFAULT_RESCUER_M: f64 = 0.6;
/// Default search-camera diameter at full scale, m.
pub const DEFAULT_CAMERA_M: f64 = 0.075;
/// A lying adult, full scale: length × width × height, m.
pub const LYING_M: [f64; 3] = [1.8, 0.5, 0.3];
/// A sitting adult, full scale: length × width × height, m.
pub const SITTING_M: [f64; 3] = [0.5, 0.5, 0.9];
/// A cell is solid when boxes cover at least this fraction of its volume (the solid cells'
/// volume then converges to the boxes' volume as the cell shrinks: as much volume is
/// rounded up as down along a boundary).
pub const SOLID_FRACTION: f64 = 0.5;

/// The sizes of an analysis, full scale, m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sizes {
    /// Grid cell edge.
    pub cell_m: f64,
    /// Rescuer passage width.
    pub rescuer_m: f64,
    /// Search-camera diameter.
    pub camera_m: f64,
}

impl Default for Sizes {
    fn default() -> Self {
        Sizes {
            cell_m: DEFAULT_CELL_M,
            rescuer_m: DEFAULT_RESCUER_M,
            camera_m: DEFAULT_CAMERA_M,
        }
    }
}

/// The sizes at the model's scale, m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scaled {
    /// Grid cell edge.
    pub cell: f64,
    /// Rescuer passage width.
    pub rescuer: f64,
    /// Camera diameter.
    pub camera: f64,
    /// Lying adult (length, width, height).
    pub lying: [f64; 3],
    /// Sitting adult (length, width, height).
    pub sitting: [f64; 3],
}

impl Sizes {
    /// Checks the sizes (finite, > 0) and the scale, and scales them.
    pub fn scaled(&self, scale: f64) -> Result<Scaled> {
        for (option, value) in [
            ("--cell", self.cell_m),
            ("--rescuer", self.rescuer_m),
            ("--camera", self.camera_m),
            ("scale", scale),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(RescueError::Size {
                    option,
                    value,
                    message: "must be a finite number > 0".into(),
                });
            }
        }
        Ok(Scaled {
            cell: self.cell_m * scale,
            rescuer: self.rescuer_m * scale,
            camera: self.camera_m * scale,
            lying: LYING_M.map(|v| v * scale),
            sitting: SITTING_M.map(|v| v * scale),
        })
    }
}

/// The number of cells of edge `cell` that a length `len` needs (the smallest count whose
/// span is at least `len`; a relative 1e-9 forgives rounding).
pub fn cells_for(len: f64, cell: f64) -> usize {
    ((len / cell) * (1.0 - 1e-9)).ceil().max(1.0) as usize
}

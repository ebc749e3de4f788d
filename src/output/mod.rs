//! Everything the program writes. Files are written atomically: to a temporary name in
//! the same folder, flushed, then renamed, so a failed run never leaves a half file.
pub mod atomic;
pub mod csv_text;
pub mod error;
pub mod gltf;
pub mod history;
pub mod interrupt;
pub mod keyframes;
pub mod location;
pub mod palette;
pub mod ruins;
pub mod run_folder;
pub mod summary;
pub mod vtk;

pub use atomic::{write_all_atomic, write_atomic, AtomicFile};
pub use error::{AnimationError, OutputError};

//! Sparse linear algebra for the FE analyses, on `faer` (sequential, `Par::Seq`):
//! the global matrix pattern fixed once from the element connectivity
//! ([`SparsePattern`]), assembly as filling its values, and sparse solvers whose
//! symbolic analyses are computed once and reused ([`SparseSolver`] for the Newton
//! iterations, [`SparseLu`]).
pub mod pattern;
pub mod solver;

pub use pattern::{SparsePattern, StiffnessKind};
pub use solver::{Inertia, SolverError, SolverStats, SparseLu, SparseSolver};

//! Sparse linear algebra for the FE analyses, on `faer` (sequential, `Par::Seq`):
//! the global matrix pattern fixed once from the element connectivity
//! ([`SparsePattern`]), assembly as filling its values, and a sparse LU solver whose
//! symbolic analysis is computed once and reused ([`SparseLu`]).
pub mod pattern;
pub mod solver;

pub use pattern::{SparsePattern, StiffnessKind};
pub use solver::{SolverError, SparseLu};

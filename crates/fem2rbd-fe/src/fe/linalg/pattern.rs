//! Compressed-sparse-column pattern of the global (symmetric-structure) matrices,
//! computed once from the element connectivity, with per-element scatter maps so
//! that assembly only adds values.

use faer::sparse::{SparseColMatRef, SymbolicSparseColMat, SymbolicSparseColMatRef};

use crate::fe::domain::{Domain, NDF};
use crate::fe::element::{Prepare, MAX_ELEMENT_NODES};

/// Which element stiffness to assemble.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StiffnessKind {
    /// [`crate::fe::element::Element::tangent_stiffness`] of the trial state.
    Tangent,
    /// [`crate::fe::element::Element::initial_stiffness`].
    Initial,
}

const NONE: usize = usize::MAX;
/// Entries of the largest element matrix (`(6 · MAX_ELEMENT_NODES)²`).
const ELEMENT_MATRIX: usize = (NDF * MAX_ELEMENT_NODES) * (NDF * MAX_ELEMENT_NODES);

/// Pattern of the `neq × neq` global matrices (both triangles and the full diagonal
/// stored) and where each element entry lands in the value array.
#[derive(Debug, Clone)]
pub struct SparsePattern {
    symbolic: SymbolicSparseColMat<usize>,
    /// Per element with `m = 6 n` DOFs, `m²` value positions (row-major over the element
    /// matrix), `NONE` where a row or column is a fixed DOF.
    element_slots: Vec<Vec<usize>>,
    /// Per element, the equation numbers of its `6 n` DOFs (`None` for fixed DOFs).
    element_eqs: Vec<Vec<Option<usize>>>,
    /// Value position of each diagonal entry.
    diagonal_slots: Vec<usize>,
}

impl SparsePattern {
    /// Builds the pattern for a numbered domain (numbers it if needed).
    pub fn new(domain: &mut Domain) -> Self {
        if !domain.is_numbered() {
            domain.number_dofs();
        }
        let n = domain.num_equations();
        let mut cols: Vec<Vec<usize>> = (0..n).map(|i| vec![i]).collect();
        let eqs: Vec<Vec<Option<usize>>> = (0..domain.elements().len())
            .map(|e| domain.element_equations(e))
            .collect();
        for el in &eqs {
            for c in el.iter().flatten() {
                for r in el.iter().flatten() {
                    cols[*c].push(*r);
                }
            }
        }
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::new();
        col_ptr.push(0);
        for c in &mut cols {
            c.sort_unstable();
            c.dedup();
            row_idx.extend_from_slice(c);
            col_ptr.push(row_idx.len());
        }
        let slot = |r: usize, c: usize| -> usize {
            let rows = &row_idx[col_ptr[c]..col_ptr[c + 1]];
            col_ptr[c] + rows.binary_search(&r).expect("entry in pattern")
        };
        let element_slots = eqs
            .iter()
            .map(|el| {
                let m = el.len();
                let mut s = vec![NONE; m * m];
                for (i, r) in el.iter().enumerate() {
                    for (j, c) in el.iter().enumerate() {
                        if let (Some(r), Some(c)) = (r, c) {
                            s[m * i + j] = slot(*r, *c);
                        }
                    }
                }
                s
            })
            .collect();
        let diagonal_slots = (0..n).map(|i| slot(i, i)).collect();
        let symbolic = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
        Self {
            symbolic,
            element_slots,
            element_eqs: eqs,
            diagonal_slots,
        }
    }

    /// Matrix dimension (number of equations).
    pub fn dim(&self) -> usize {
        self.symbolic.nrows()
    }

    /// Number of stored entries (length of a value array).
    pub fn nnz(&self) -> usize {
        self.symbolic.row_idx().len()
    }

    /// A zeroed value array.
    pub fn zeros(&self) -> Vec<f64> {
        vec![0.0; self.nnz()]
    }

    /// The symbolic structure.
    pub fn symbolic(&self) -> SymbolicSparseColMatRef<'_, usize> {
        self.symbolic.as_ref()
    }

    /// A faer view of a value array on this pattern.
    pub fn as_mat<'a>(&'a self, values: &'a [f64]) -> SparseColMatRef<'a, usize, f64> {
        SparseColMatRef::new(self.symbolic.as_ref(), values)
    }

    /// `values[slots] += factor · k` for one element matrix `k` (`m × m`, column-major).
    fn scatter(slots: &[usize], k: &[f64], m: usize, factor: f64, values: &mut [f64]) {
        for j in 0..m {
            for i in 0..m {
                let s = slots[m * i + j];
                if s != NONE {
                    values[s] += factor * k[i + m * j];
                }
            }
        }
    }

    /// `values += factor · Σ_e K_e` (tangent or initial element stiffness), summed in
    /// element order. The tangents are formed first on the domain's threads
    /// ([`Domain::prepare_elements`]) and then copied into one buffer per element in turn
    /// (no allocation per element): the same bits for any thread count.
    pub fn add_stiffness(
        &self,
        domain: &Domain,
        kind: StiffnessKind,
        factor: f64,
        values: &mut [f64],
    ) {
        if kind == StiffnessKind::Tangent {
            domain.prepare_elements(Prepare::Tangent);
        }
        let mut k = [0.0; ELEMENT_MATRIX];
        for (el, slots) in domain.elements().iter().zip(&self.element_slots) {
            let m = NDF * el.nodes().len();
            match kind {
                StiffnessKind::Tangent => el.tangent_stiffness_into(&mut k[..m * m]),
                StiffnessKind::Initial => {
                    k[..m * m].copy_from_slice(el.initial_stiffness().as_slice())
                }
            }
            Self::scatter(slots, &k[..m * m], m, factor, values);
        }
    }

    /// `values += factor · Σ_e K0_e` over the elements whose damping stiffness is their
    /// (constant) initial stiffness ([`crate::fe::element::Element::damping_stiffness`]
    /// is `None`).
    pub fn add_constant_damping_stiffness(&self, domain: &Domain, factor: f64, values: &mut [f64]) {
        for (el, slots) in domain.elements().iter().zip(&self.element_slots) {
            if el.has_trial_damping_stiffness() {
                continue;
            }
            let k = el.initial_stiffness();
            Self::scatter(slots, k.as_slice(), k.nrows(), factor, values);
        }
    }

    /// `y += Σ_e D_e x_e` over the elements whose damping stiffness `D_e` follows the
    /// trial configuration (`damping_stiffness()` is `Some`), `x` and `y` in equations.
    /// The `D_e` are formed on the domain's threads ([`Domain::prepare_elements`]) and
    /// kept for the tangent of the same iteration; the products are formed and summed in
    /// element order (the same bits for any thread count).
    pub fn add_trial_damping_product(&self, domain: &Domain, x: &[f64], y: &mut [f64]) {
        domain.prepare_elements(Prepare::Damping);
        let mut k = [0.0; ELEMENT_MATRIX];
        let mut out = [0.0; NDF * MAX_ELEMENT_NODES];
        for (el, eqs) in domain.elements().iter().zip(&self.element_eqs) {
            let m = eqs.len();
            if !el.damping_stiffness_into(&mut k[..m * m]) {
                continue;
            }
            for (i, ri) in eqs.iter().enumerate() {
                if ri.is_none() {
                    out[i] = 0.0;
                    continue;
                }
                let mut acc = 0.0;
                for (j, cj) in eqs.iter().enumerate() {
                    if let Some(c) = cj {
                        acc += k[i + m * j] * x[*c];
                    }
                }
                out[i] = acc;
            }
            for (i, ri) in eqs.iter().enumerate() {
                if let Some(r) = ri {
                    y[*r] += out[i];
                }
            }
        }
    }

    /// `values += factor · Σ_e D_e` over the elements whose damping stiffness `D_e`
    /// follows the trial configuration (`damping_stiffness()` is `Some`), summed in
    /// element order (the `D_e` as kept by [`Self::add_trial_damping_product`], or formed
    /// on the domain's threads here).
    pub fn add_trial_damping_stiffness(&self, domain: &Domain, factor: f64, values: &mut [f64]) {
        domain.prepare_elements(Prepare::Damping);
        let mut k = [0.0; ELEMENT_MATRIX];
        for (el, slots) in domain.elements().iter().zip(&self.element_slots) {
            let m = NDF * el.nodes().len();
            if el.damping_stiffness_into(&mut k[..m * m]) {
                Self::scatter(slots, &k[..m * m], m, factor, values);
            }
        }
    }

    /// `values += factor · diag(d)`.
    pub fn add_diagonal(&self, d: &[f64], factor: f64, values: &mut [f64]) {
        for (s, x) in self.diagonal_slots.iter().zip(d) {
            values[*s] += factor * x;
        }
    }

    /// `y = A x` for a value array `a` on this pattern.
    pub fn mul_vec(&self, a: &[f64], x: &[f64], y: &mut [f64]) {
        y.iter_mut().for_each(|v| *v = 0.0);
        let cp = self.symbolic.col_ptr();
        let ri = self.symbolic.row_idx();
        for c in 0..self.dim() {
            let xc = x[c];
            for p in cp[c]..cp[c + 1] {
                y[ri[p]] += a[p] * xc;
            }
        }
    }

    /// Dense copy (row-major, `n × n`), for small problems and tests.
    pub fn to_dense(&self, a: &[f64]) -> nalgebra::DMatrix<f64> {
        let n = self.dim();
        let mut m = nalgebra::DMatrix::zeros(n, n);
        let cp = self.symbolic.col_ptr();
        let ri = self.symbolic.row_idx();
        for c in 0..n {
            for p in cp[c]..cp[c + 1] {
                m[(ri[p], c)] += a[p];
            }
        }
        m
    }
}

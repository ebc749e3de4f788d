//! Eigenvalue (modal) analysis: K φ = ω² M φ for the lowest modes, with a lumped
//! (diagonal) mass matrix in which some DOFs — typically rotations — are massless.
//!
//! Two solvers give the same modes:
//! - [`EigenMethod::DenseCondensed`]: static (Guyan) condensation of the massless DOFs,
//!   exact for lumped masses because no inertia acts on them:
//!   K̂ = K_aa − K_ab K_bb⁻¹ K_ba, then the symmetric standard problem
//!   (M_aa^{-1/2} K̂ M_aa^{-1/2}) z = ω² z, φ_a = M_aa^{-1/2} z, φ_b = −K_bb⁻¹ K_ba φ_a.
//!   Dense, O(n³): fine up to a few thousand DOFs (frame3: 258 DOFs).
//! - [`EigenMethod::SubspaceIteration`]: Bathe's subspace iteration (Bathe, *Finite
//!   Element Procedures*, §11.6) on the sparse K (one factorisation, reused), q = max(2p, p+8)
//!   vectors; the iterates X̄ = K⁻¹ M X satisfy the massless-DOF equations exactly, so
//!   no condensation is needed. Memory O(nnz(L) + n q); this is what scales to tens of
//!   thousands of DOFs. When q is not below the number of massed DOFs the problem is
//!   small and the dense solver is used instead. Slow when the wanted periods are
//!   close to the next ones (its convergence rate is λ_p/λ_{q+1}).
//! - [`EigenMethod::Lanczos`]: shift-invert block Lanczos ([`super::lanczos`]) with full
//!   reorthogonalisation and thick restarts, the default above 2000 equations. With the
//!   massed DOFs `a` and the massless `b`, and K_σ = K − σM (σ = 0: the initial
//!   stiffness of a supported structure is positive definite), the operator on the
//!   massed DOFs only is
//!   C = M_a^{1/2} [K_σ⁻¹]_aa M_a^{1/2}, symmetric, with eigenvalues θ = 1/(λ − σ) and
//!   eigenvectors z = M_a^{1/2} φ_a, because [K_σ⁻¹]_aa is the inverse of the statically
//!   condensed K̂ − σM_a (Ericsson & Ruhe, Math. Comp. 35 (1980) 1251, the spectral
//!   transformation; Nour-Omid, Parlett, Ericsson & Jensen, Math. Comp. 48 (1987) 663,
//!   for singular M). One factorisation of K_σ serves every step; the Euclidean inner product
//!   on z replaces the M-semi-inner product, and the massless DOFs never enter the
//!   basis. Mode shapes with their massless DOFs: φ = K_σ⁻¹ (M^{1/2} z) / θ, exact
//!   statics for them. Blocks of 4 vectors find eigenvalues of multiplicity up to 4
//!   (the X/Y pairs of symmetric plans); every returned pair is checked on the original
//!   problem, ‖Kφ − λMφ‖ ≤ 1e-6 ‖Kφ‖. Lanczos returns the eigenvalues nearest σ = 0:
//!   the lowest ones when K is positive definite (the initial stiffness); on an
//!   indefinite tangent it may miss strongly negative eigenvalues that the dense solver
//!   lists first.
//!
//! Both sparse solvers factor K_σ with [`SparseSolver`]: the symmetric LBLᵀ on AMD's order
//! with iterative refinement (the LU only where that does not reach LU accuracy). The LU
//! on COLAMD's order fills in far more: on a generated 20 × 20-bay, 10-story frame
//! (129 966 equations) it grew past 9 GB and minutes before the first Lanczos step.
//!
//! Mode shapes are mass-normalised (φᵀ M φ = 1, as OpenSees), signed so that the
//! largest-magnitude component is positive. Effective modal mass in direction d:
//! M*_d = (φᵀ M ι_d)², reported as a ratio of the total free mass in d.

use nalgebra::{DMatrix, DVector, SymmetricEigen};

use super::building_modes::{
    building_modes, is_building_mode, lateral_influence, lateral_ratios, Found,
    BUILDING_MODE_MASS_RATIO,
};
use super::lanczos::{block_lanczos, LanczosOptions};
use super::shift_invert::{massed_equations, ShiftInvert};
use super::AnalysisError;
use crate::fe::domain::{Domain, NDF};
use crate::fe::linalg::{SparsePattern, SparseSolver, StiffnessKind};

/// Which eigen solver.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum EigenMethod {
    /// Dense condensed when there are at most 2000 equations, else shift-invert block
    /// Lanczos.
    Auto,
    /// Dense Guyan-condensed solve.
    DenseCondensed,
    /// Sparse subspace iteration.
    SubspaceIteration {
        /// Tolerance on the relative residual ‖Kφ − ω²Mφ‖/‖Kφ‖ of each wanted mode
        /// (e.g. 1e-9; the eigenvalues are then accurate to about its square).
        tol: f64,
        /// Iteration limit.
        max_iter: usize,
    },
    /// Shift-invert block Lanczos (see the module docs).
    Lanczos {
        /// Tolerance on the relative Ritz residual ‖Cz − θz‖/|θ| of each wanted mode
        /// (e.g. 1e-10).
        tol: f64,
        /// Restart limit.
        max_restarts: usize,
    },
}

/// Which modes a modal analysis reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ModeSelection {
    /// The building's modes: the lowest modes with at least
    /// [`BUILDING_MODE_MASS_RATIO`] of the effective mass along X, Y or in torsion,
    /// exact eigenpairs with their index in the full spectrum
    /// ([`super::building_modes`]). The default of every analysis that needs modes.
    #[default]
    Building,
    /// The lowest modes, whatever they carry (local slab modes too).
    Lowest,
}

impl std::fmt::Display for ModeSelection {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            ModeSelection::Building => "building",
            ModeSelection::Lowest => "lowest",
        })
    }
}

/// The modes below the last reported one that are not reported.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SkippedModes {
    /// How many (Sturm sequence count, or every mode computed).
    pub count: usize,
    /// Upper bound on their summed effective mass ratio along X, Y and in torsion: the
    /// exact sum when every mode was computed (the dense solver), else the moment bound
    /// of [`super::building_modes`]. Under [`BUILDING_MODE_MASS_RATIO`] in every
    /// direction, none of them can be a building mode.
    pub mass_ratio_bound: [f64; 3],
}

/// Modal analysis settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModalSettings {
    /// Number of modes.
    pub modes: usize,
    /// Which modes (default: the building's).
    pub selection: ModeSelection,
    /// Initial stiffness (before gravity, like frame3's reference periods) or the
    /// tangent of the committed state.
    pub stiffness: StiffnessKind,
    /// Solver.
    pub method: EigenMethod,
}

impl Default for ModalSettings {
    fn default() -> Self {
        Self {
            modes: 3,
            selection: ModeSelection::default(),
            stiffness: StiffnessKind::Initial,
            method: EigenMethod::Auto,
        }
    }
}

/// Result of a modal analysis.
#[derive(Debug, Clone, PartialEq)]
pub struct ModalResult {
    /// ω² per mode (rad²/s²), ascending.
    pub omega_squared: Vec<f64>,
    /// Periods T = 2π/ω (s); infinite when ω² ≤ 0.
    pub periods: Vec<f64>,
    /// Mass-normalised mode shapes: per mode, per node `[ux, uy, uz, rx, ry, rz]`
    /// (fixed DOFs zero).
    pub shapes: Vec<Vec<[f64; NDF]>>,
    /// Participation factors Γ_d = φᵀ M ι_d per mode, d = X, Y, Z (kg^½).
    pub participation: Vec<[f64; 3]>,
    /// Effective modal mass ratio Γ_d² / Σ m_d per mode and direction.
    pub effective_mass_ratio: Vec<[f64; 3]>,
    /// Total free translational mass per direction (kg).
    pub total_mass: [f64; 3],
    /// Effective modal mass ratio in torsion, Γ_θ² / (r_θᵀ M r_θ), per mode: r_θ a unit
    /// rotation about the vertical axis through the plan mass centre.
    pub torsion_mass_ratio: Vec<f64>,
    /// Each mode's index in the full spectrum (1 = the longest period).
    pub index: Vec<usize>,
    /// Each pair's relative residual ‖Kφ − ω²Mφ‖ / ‖Kφ‖ on the problem solved.
    pub residual: Vec<f64>,
    /// Which modes these are.
    pub selection: ModeSelection,
    /// The modes below the last one that are not reported (none for the lowest).
    pub skipped: SkippedModes,
}

/// The most equations the dense solver takes: its n × n matrix is 8 n² bytes (10 000
/// equations: 0.8 GB).
pub const MAX_DENSE_EQUATIONS: usize = 10_000;

/// Runs the eigen analysis on the domain's committed state.
pub fn modal_analysis(
    domain: &mut Domain,
    settings: &ModalSettings,
) -> Result<ModalResult, AnalysisError> {
    let pattern = SparsePattern::new(domain);
    let n = pattern.dim();
    let m = domain.mass_diagonal();
    let massed = m.iter().filter(|&&x| x > 0.0).count();
    if settings.modes == 0 || settings.modes > massed {
        return Err(AnalysisError::Input(format!(
            "{} modes requested, the model has {massed} DOFs with mass: ask for 1 to {massed}",
            settings.modes
        )));
    }
    let mut k = pattern.zeros();
    pattern.add_stiffness(domain, settings.stiffness, 1.0, &mut k);
    let method = match settings.method {
        EigenMethod::Auto if n <= 2000 => EigenMethod::DenseCondensed,
        EigenMethod::Auto => EigenMethod::Lanczos {
            tol: 1e-10,
            max_restarts: 200,
        },
        other => other,
    };
    let dense_guard = || {
        // The dense solver holds n² reals: bounded before the allocation.
        if n > MAX_DENSE_EQUATIONS {
            return Err(AnalysisError::Input(format!(
                "modal analysis: {n} equations but only {massed} DOFs with mass, too \
                 few for the sparse solver with {} modes; the dense solver would need \
                 {:.1} GB (at most {MAX_DENSE_EQUATIONS} equations): give the model \
                 more mass or ask for fewer modes",
                settings.modes,
                (n as f64).powi(2) * 8e-9
            )));
        }
        Ok(())
    };
    if settings.selection == ModeSelection::Building {
        let influence = lateral_influence(domain);
        let found = match method {
            EigenMethod::Lanczos { .. }
                if lanczos_basis(settings.modes) + LANCZOS_BLOCK < massed =>
            {
                building_modes(&pattern, &k, &m, &influence, settings.modes)?
            }
            EigenMethod::SubspaceIteration { .. } => {
                return Err(AnalysisError::Input(
                    "the building's modes are found by the dense or the Lanczos solver, \
                     not by subspace iteration"
                        .into(),
                ))
            }
            _ => {
                dense_guard()?;
                dense_building_modes(&pattern.to_dense(&k), &m, &influence, settings.modes)?
            }
        };
        let residual = residuals(&pattern, &k, &m, &found.omega2, &found.phis);
        let mut result = package(domain, found.omega2, found.phis, &m);
        result.residual = residual;
        result.index = found.index;
        result.selection = ModeSelection::Building;
        result.skipped = found.skipped;
        return Ok(result);
    }
    // The subspace needs fewer vectors than massed DOFs; otherwise the problem is small.
    let q = (2 * settings.modes).max(settings.modes + 8);
    let (omega2, phis) = match method {
        EigenMethod::SubspaceIteration { tol, max_iter } if q < massed => {
            subspace_iteration(&pattern, &k, &m, settings.modes, tol, max_iter)?
        }
        EigenMethod::Lanczos { tol, max_restarts }
            if lanczos_basis(settings.modes) + LANCZOS_BLOCK < massed =>
        {
            shift_invert_lanczos(&pattern, &k, &m, settings.modes, tol, max_restarts)?
        }
        _ => {
            dense_guard()?;
            dense_condensed(&pattern.to_dense(&k), &m, settings.modes)?
        }
    };
    let residual = residuals(&pattern, &k, &m, &omega2, &phis);
    let mut result = package(domain, omega2, phis, &m);
    result.residual = residual;
    Ok(result)
}

/// ‖Kφ − λMφ‖ / ‖Kφ‖ of each pair.
fn residuals(
    pattern: &SparsePattern,
    k: &[f64],
    m: &[f64],
    omega2: &[f64],
    phis: &[DVector<f64>],
) -> Vec<f64> {
    omega2
        .iter()
        .zip(phis)
        .map(|(&l, phi)| relative_residual(pattern, k, m, l, phi))
        .collect()
}

fn package(
    domain: &Domain,
    omega2: Vec<f64>,
    mut phis: Vec<DVector<f64>>,
    m: &[f64],
) -> ModalResult {
    let iota: Vec<Vec<f64>> = (0..3).map(|d| domain.influence_vector(d)).collect();
    let lateral = lateral_influence(domain);
    let mut torsion = Vec::new();
    let total_mass: [f64; 3] =
        std::array::from_fn(|d| iota[d].iter().zip(m).map(|(i, m)| i * m).sum());
    let mut participation = Vec::new();
    let mut ratio = Vec::new();
    let mut shapes = Vec::new();
    for phi in &mut phis {
        let mn: f64 = phi.iter().zip(m).map(|(p, m)| p * p * m).sum();
        *phi /= mn.sqrt();
        let imax = phi.iamax();
        if phi[imax] < 0.0 {
            *phi = -phi.clone();
        }
        let g: [f64; 3] = std::array::from_fn(|d| {
            phi.iter()
                .zip(m)
                .zip(&iota[d])
                .map(|((p, m), i)| p * m * i)
                .sum()
        });
        participation.push(g);
        torsion.push(lateral_ratios(phi, m, &lateral)[2]);
        ratio.push(std::array::from_fn(|d| {
            if total_mass[d] > 0.0 {
                g[d] * g[d] / total_mass[d]
            } else {
                0.0
            }
        }));
        let shape = (0..domain.nodes().len())
            .map(|node| std::array::from_fn(|k| domain.equation(node, k).map_or(0.0, |e| phi[e])))
            .collect();
        shapes.push(shape);
    }
    let periods = omega2
        .iter()
        .map(|&w2| {
            if w2 > 0.0 {
                2.0 * std::f64::consts::PI / w2.sqrt()
            } else {
                f64::INFINITY
            }
        })
        .collect();
    ModalResult {
        index: (1..=omega2.len()).collect(),
        residual: Vec::new(),
        omega_squared: omega2,
        periods,
        shapes,
        participation,
        effective_mass_ratio: ratio,
        total_mass,
        torsion_mass_ratio: torsion,
        selection: ModeSelection::Lowest,
        skipped: SkippedModes::default(),
    }
}

/// Every mode of the dense Guyan-condensed problem (see module docs), ascending.
struct DenseSpectrum {
    /// Massed equations.
    a: Vec<usize>,
    /// Massless equations.
    b: Vec<usize>,
    /// T = K_bb⁻¹ K_ba.
    t: DMatrix<f64>,
    /// M_aa^{-1/2}.
    s: Vec<f64>,
    eig: SymmetricEigen<f64, nalgebra::Dyn>,
    /// Eigenvalue order, ascending.
    order: Vec<usize>,
}

impl DenseSpectrum {
    fn new(k: &DMatrix<f64>, m: &[f64]) -> Result<Self, AnalysisError> {
        let a: Vec<usize> = (0..m.len()).filter(|&i| m[i] > 0.0).collect();
        let b: Vec<usize> = (0..m.len()).filter(|&i| m[i] <= 0.0).collect();
        let sub = |rows: &[usize], cols: &[usize]| {
            DMatrix::from_fn(rows.len(), cols.len(), |i, j| k[(rows[i], cols[j])])
        };
        let kaa = sub(&a, &a);
        let kab = sub(&a, &b);
        // T = K_bb⁻¹ K_ba (massless DOFs follow the massed ones statically).
        let t = if b.is_empty() {
            DMatrix::zeros(0, a.len())
        } else {
            let kbb = sub(&b, &b);
            let lu = kbb.lu();
            lu.solve(&kab.transpose()).ok_or_else(|| {
                AnalysisError::Eigen("stiffness of the massless DOFs is singular".into())
            })?
        };
        let kc = &kaa - &kab * &t;
        let s: Vec<f64> = a.iter().map(|&i| 1.0 / m[i].sqrt()).collect();
        let mut h = DMatrix::from_fn(a.len(), a.len(), |i, j| kc[(i, j)] * s[i] * s[j]);
        h = (&h + h.transpose()) * 0.5;
        if h.iter().any(|x| !x.is_finite()) {
            return Err(AnalysisError::Eigen(
                "non-finite condensed stiffness".into(),
            ));
        }
        let eig = SymmetricEigen::new(h);
        let mut order: Vec<usize> = (0..a.len()).collect();
        order.sort_by(|&i, &j| eig.eigenvalues[i].total_cmp(&eig.eigenvalues[j]));
        Ok(Self {
            a,
            b,
            t,
            s,
            eig,
            order,
        })
    }

    /// Number of modes.
    fn len(&self) -> usize {
        self.order.len()
    }

    /// ω² of mode `i` (0-based, ascending).
    fn omega2(&self, i: usize) -> f64 {
        self.eig.eigenvalues[self.order[i]]
    }

    /// The massed part φ_a of mode `i` (M-normalised).
    fn massed_shape(&self, i: usize) -> DVector<f64> {
        let c = self.order[i];
        DVector::from_fn(self.a.len(), |r, _| {
            self.eig.eigenvectors[(r, c)] * self.s[r]
        })
    }

    /// Mode `i` on all equations.
    fn shape(&self, i: usize) -> DVector<f64> {
        let pa = self.massed_shape(i);
        let pb = -&self.t * &pa;
        let mut phi = DVector::zeros(self.a.len() + self.b.len());
        for (i, &ai) in self.a.iter().enumerate() {
            phi[ai] = pa[i];
        }
        for (i, &bi) in self.b.iter().enumerate() {
            phi[bi] = pb[i];
        }
        phi
    }
}

/// Dense Guyan-condensed generalized eigen solve: the `modes` lowest.
fn dense_condensed(
    k: &DMatrix<f64>,
    m: &[f64],
    modes: usize,
) -> Result<(Vec<f64>, Vec<DVector<f64>>), AnalysisError> {
    let spectrum = DenseSpectrum::new(k, m)?;
    let n = modes.min(spectrum.len());
    Ok((
        (0..n).map(|i| spectrum.omega2(i)).collect(),
        (0..n).map(|i| spectrum.shape(i)).collect(),
    ))
}

/// The building's modes (see [`ModeSelection::Building`]) from every mode of the dense
/// solver: exact indices, and the exact effective mass of the modes skipped.
fn dense_building_modes(
    k: &DMatrix<f64>,
    m: &[f64],
    influence: &[Vec<f64>; 3],
    modes: usize,
) -> Result<Found, AnalysisError> {
    let spectrum = DenseSpectrum::new(k, m)?;
    let mut chosen = Vec::new();
    // Per mode up to the last chosen: its ratios along X, Y and in torsion.
    let mut ratios_below = Vec::new();
    for i in 0..spectrum.len() {
        if chosen.len() == modes {
            break;
        }
        let pa = spectrum.massed_shape(i);
        let ratios: [f64; 3] = std::array::from_fn(|d| {
            let total: f64 = spectrum
                .a
                .iter()
                .map(|&e| influence[d][e].powi(2) * m[e])
                .sum();
            if total > 0.0 {
                let g: f64 = spectrum
                    .a
                    .iter()
                    .zip(pa.iter())
                    .map(|(&e, p)| p * m[e] * influence[d][e])
                    .sum();
                g * g / total
            } else {
                0.0
            }
        });
        if is_building_mode(&ratios) {
            chosen.push(i);
        }
        ratios_below.push(ratios);
    }
    let last = chosen.last().map_or(0, |&l| l);
    let skipped_modes: Vec<usize> = (0..last).filter(|i| !chosen.contains(i)).collect();
    let skipped: [f64; 3] =
        std::array::from_fn(|d| skipped_modes.iter().map(|&i| ratios_below[i][d]).sum());
    let skipped_count = skipped_modes.len();
    if chosen.is_empty() {
        return Err(AnalysisError::Eigen(format!(
            "no mode with at least {} % effective mass along X, Y or in torsion",
            BUILDING_MODE_MASS_RATIO * 100.0
        )));
    }
    Ok(Found {
        omega2: chosen.iter().map(|&i| spectrum.omega2(i)).collect(),
        phis: chosen.iter().map(|&i| spectrum.shape(i)).collect(),
        index: chosen.iter().map(|&i| i + 1).collect(),
        skipped: SkippedModes {
            count: skipped_count,
            mass_ratio_bound: skipped,
        },
    })
}

/// Solves the small projected problem K_r q = λ M_r q, eigenpairs ascending, q
/// M_r-orthonormal. M_r is reduced on its numerically non-null range (eigenvalues above
/// 1e-8 of the largest): vectors that have become dependent — the subspace holds
/// more vectors than the model has finite-frequency modes — are dropped, so the
/// returned basis may have fewer columns than M_r.
fn small_generalized(kr: &DMatrix<f64>, mr: &DMatrix<f64>) -> Option<(Vec<f64>, DMatrix<f64>)> {
    let mr = (mr + mr.transpose()) * 0.5;
    let me = SymmetricEigen::new(mr);
    let dmax = me.eigenvalues.max();
    if dmax.is_nan() || dmax <= 0.0 {
        return None;
    }
    let keep: Vec<usize> = (0..me.eigenvalues.len())
        .filter(|&i| me.eigenvalues[i] > 1e-8 * dmax)
        .collect();
    let q = kr.nrows();
    let b = DMatrix::from_fn(q, keep.len(), |r, c| {
        me.eigenvectors[(r, keep[c])] / me.eigenvalues[keep[c]].sqrt()
    });
    let mut h = b.transpose() * kr * &b;
    h = (&h + h.transpose()) * 0.5;
    let eig = SymmetricEigen::new(h);
    let mut idx: Vec<usize> = (0..eig.eigenvalues.len()).collect();
    idx.sort_by(|&i, &j| eig.eigenvalues[i].total_cmp(&eig.eigenvalues[j]));
    let lam = idx.iter().map(|&i| eig.eigenvalues[i]).collect();
    let z = DMatrix::from_fn(idx.len(), idx.len(), |r, c| eig.eigenvectors[(r, idx[c])]);
    Some((lam, b * z))
}

/// Bathe's subspace iteration with one sparse factorisation of K (see module docs).
fn subspace_iteration(
    pattern: &SparsePattern,
    k: &[f64],
    m: &[f64],
    modes: usize,
    tol: f64,
    max_iter: usize,
) -> Result<(Vec<f64>, Vec<DVector<f64>>), AnalysisError> {
    let n = m.len();
    let massed = m.iter().filter(|&&x| x > 0.0).count();
    let q = (2 * modes).max(modes + 8).min(massed - 1);
    let mut lu = SparseSolver::new(pattern)?;
    lu.factor(pattern, k)?;
    // Start vectors: diag(M), then deterministic pseudo-random values on the massed DOFs.
    let mut x = DMatrix::<f64>::zeros(n, q);
    let mut seed: u64 = 0x2545_f491_4f6c_dd1d;
    for c in 0..q {
        for r in 0..n {
            if m[r] > 0.0 {
                seed = seed
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let rnd = (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
                x[(r, c)] = if c == 0 { 1.0 } else { rnd };
            }
        }
    }
    let mut q = q;
    let mut col = vec![0.0; n];
    for _ in 0..max_iter {
        // Y = M X;  X̄ = K⁻¹ Y
        let y = DMatrix::from_fn(n, q, |r, c| m[r] * x[(r, c)]);
        let mut xb = DMatrix::<f64>::zeros(n, q);
        for c in 0..q {
            col.copy_from_slice(y.column(c).as_slice());
            lu.solve(pattern, &mut col)?;
            xb.column_mut(c).copy_from_slice(&col);
        }
        // Scale the columns to unit M-norm: without it, vectors dominated by very stiff
        // (or tiny-mass) modes make the projected mass matrix numerically singular.
        let mut y = y;
        for c in 0..q {
            let mn: f64 = (0..n).map(|r| m[r] * xb[(r, c)] * xb[(r, c)]).sum();
            if mn > 0.0 && mn.is_finite() {
                let s = 1.0 / mn.sqrt();
                xb.column_mut(c).scale_mut(s);
                y.column_mut(c).scale_mut(s);
            }
        }
        let kr = xb.transpose() * &y;
        let mxb = DMatrix::from_fn(n, q, |r, c| m[r] * xb[(r, c)]);
        let mr = xb.transpose() * &mxb;
        let (lam, qv) = small_generalized(&((&kr + kr.transpose()) * 0.5), &mr)
            .ok_or_else(|| AnalysisError::Eigen("subspace lost rank".into()))?;
        if lam.len() < modes {
            return Err(AnalysisError::Eigen("subspace lost rank".into()));
        }
        x = &xb * qv;
        q = x.ncols();
        // Converged when every wanted pair has a small residual ‖Kφ − λMφ‖ ≤ tol‖Kφ‖
        // (eigenvalues converge twice as fast as vectors, so test the vectors).
        let converged = (0..modes).all(|i| {
            let phi = x.column(i);
            pattern.mul_vec(k, phi.as_slice(), &mut col);
            let (mut r2, mut k2) = (0.0, 0.0);
            for r in 0..n {
                r2 += (col[r] - lam[i] * m[r] * phi[r]).powi(2);
                k2 += col[r] * col[r];
            }
            r2.sqrt() <= tol * k2.sqrt()
        });
        if converged {
            let phis = (0..modes).map(|i| x.column(i).into_owned()).collect();
            return Ok((lam[..modes].to_vec(), phis));
        }
    }
    Err(AnalysisError::Eigen(format!(
        "subspace iteration did not converge in {max_iter} iterations"
    )))
}

/// Block size of the Lanczos solver: eigenvalues up to this multiplicity are found.
const LANCZOS_BLOCK: usize = 4;

/// Expanded basis size of the Lanczos solver for `modes` wanted modes.
fn lanczos_basis(modes: usize) -> usize {
    (3 * modes).max(modes + 6 * LANCZOS_BLOCK).max(48)
}

/// Shift-invert block Lanczos on the massed DOFs (see the module docs), σ = 0.
fn shift_invert_lanczos(
    pattern: &SparsePattern,
    k: &[f64],
    m: &[f64],
    modes: usize,
    tol: f64,
    max_restarts: usize,
) -> Result<(Vec<f64>, Vec<DVector<f64>>), AnalysisError> {
    let massed = massed_equations(m);
    let mut op = ShiftInvert::new(pattern, k, m, &massed, 0.0)?.checked();
    lanczos_nearest(
        &mut op,
        k,
        m,
        modes,
        lanczos_basis(modes),
        tol,
        max_restarts,
    )
}

/// The `modes` eigenpairs nearest the shift of `op` by block Lanczos on its operator C,
/// ascending in λ; every pair is checked on the original problem,
/// ‖Kφ − λMφ‖ ≤ 1e-6 ‖Kφ‖.
pub(crate) fn lanczos_nearest(
    op: &mut ShiftInvert<'_>,
    k: &[f64],
    m: &[f64],
    modes: usize,
    basis: usize,
    tol: f64,
    max_restarts: usize,
) -> Result<(Vec<f64>, Vec<DVector<f64>>), AnalysisError> {
    let opts = LanczosOptions {
        block: LANCZOS_BLOCK,
        basis,
        tol,
        max_restarts,
    };
    let (theta, z) = block_lanczos(op.dim(), modes, |x, y| op.apply(x, y), &opts)
        .map_err(|e| AnalysisError::Eigen(e.to_string()))?;
    let sigma = op.sigma();
    let mut pairs = Vec::with_capacity(modes);
    for (c, &t) in theta.iter().enumerate() {
        pairs.push((sigma + 1.0 / t, op.shape(z.column(c).as_slice(), t)?));
    }
    pairs.sort_by(|x, y| x.0.total_cmp(&y.0));
    // Check every pair on the original problem.
    for (i, (lam, phi)) in pairs.iter().enumerate() {
        let r = relative_residual(op.pattern(), k, m, *lam, phi);
        if r > 1e-6 || !r.is_finite() {
            return Err(AnalysisError::Eigen(format!(
                "Lanczos mode {}: residual |K phi - lambda M phi| / |K phi| = {r:.2e}",
                i + 1,
            )));
        }
    }
    Ok(pairs.into_iter().unzip())
}

/// ‖Kφ − λMφ‖ / ‖Kφ‖ of a pair on the original problem.
pub(crate) fn relative_residual(
    pattern: &SparsePattern,
    k: &[f64],
    m: &[f64],
    lambda: f64,
    phi: &DVector<f64>,
) -> f64 {
    let mut kphi = vec![0.0; m.len()];
    pattern.mul_vec(k, phi.as_slice(), &mut kphi);
    let (mut r2, mut k2) = (0.0, 0.0);
    for r in 0..m.len() {
        r2 += (kphi[r] - lambda * m[r] * phi[r]).powi(2);
        k2 += kphi[r] * kphi[r];
    }
    (r2 / k2).sqrt()
}

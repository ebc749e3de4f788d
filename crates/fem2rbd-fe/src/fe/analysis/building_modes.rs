//! The building's modes: the lowest modes that carry at least
//! [`BUILDING_MODE_MASS_RATIO`] of the effective mass along X, Y or in torsion, each an
//! exact eigenpair, with its place in the whole spectrum.
//!
//! A model whose floors are lumped at slab nodes on flexible strips has hundreds of local
//! vertical slab modes below its first translation; the lowest N modes are then all
//! local. The building's modes are found without computing those:
//!
//! 1. **Load-dependent Ritz vectors** ([`super::ritz`]) started from the loads of a
//!    uniform base motion along X and Y and of a uniform rotation about the vertical
//!    axis through the plan mass centre (influence vectors r_x, r_y, r_θ). The space
//!    holds a mode in proportion to its participation, so the building's modes converge
//!    in it first (the method ETABS and SAP2000 use for mass participation; Wilson, Yuan
//!    & Dickens 1982). Ritz pairs are only approximations.
//! 2. **Exact eigenpairs.** The Ritz values λ̃ of the candidates (effective mass ratio
//!    ≥ half the threshold, Ritz residual ≤ 10⁻⁴ θ) become shifts, candidates within
//!    10⁻⁴ of each other one group: block inverse iteration with K − σM,
//!    σ = λ̃ (1 − 10⁻⁶) (the spectral transformation of [`super::shift_invert`], started
//!    from the group's Ritz vectors, Rayleigh–Ritz on the block at each step; Bathe,
//!    *Finite Element Procedures*, §11.2.3 with shifting) until every pair's residual is
//!    ≤ 10⁻¹⁰ θ, or else shift-invert block Lanczos for the pairs nearest σ. Every pair is
//!    checked on K φ = λ M φ. Only these exact pairs are reported, with their residual
//!    ‖Kφ − λMφ‖/‖Kφ‖; their effective masses decide which are the building's.
//! 3. **Numbering.** The Sturm sequence count of K − σM ([`super::shift_invert`]) just
//!    below each group of reported modes (the factorisation of step 2) and just above
//!    the last gives each mode's index in the full spectrum (1 = the longest period)
//!    and the number of modes skipped below the last one; where two counts differ by
//!    more than the modes between them, the count above the lower group says whether the
//!    others lie inside it (then each mode is counted on its own) or in the gap.
//! 4. **What the skipped modes carry.** A gap between reported modes (or below the
//!    first) that holds at most [`MAX_RESOLVED`] modes is solved exactly: shift-invert
//!    Lanczos at its middle (at σ = 0 below the first), checked against the Sturm count.
//!    For the modes of a larger gap, with z_d = M^{1/2} r_d, the shift-invert operator C
//!    at σ = 0 and u = 1/λ, the moments Σ_i Γ_{i,d}² u_iᵖ = z_dᵀ Cᵖ z_d (p = 0 … 8;
//!    p = 0 is the total mass) are known exactly. Subtracting the exact pairs found
//!    leaves R_p, the same sums over the modes not found. Those below the gap's upper
//!    end lie below U, the least shift (to 2 %, by bisection on Sturm counts) with as
//!    many eigenvalues below it. For any f(u) ≥ 0 with f ≥ 1 where u ≥ 1/U,
//!    Σ_{not found, λ < U} Γ² ≤ Σ_{not found} Γ² f(u) (a Chebyshev–Markov type
//!    inequality). The test functions f(u) = (u U)^q ((u − c)/(1/U − c))², q = 0 … 6,
//!    c ∈ [0, 1/U) (64 values) are such functions, their sums are
//!    (R_{q+2} − 2c R_{q+1} + c² R_q) U^q / (1/U − c)², and they weigh the higher modes
//!    not found (u ≪ 1/U) little. The least of them, plus the exact local pairs found,
//!    bounds the effective mass all skipped modes carry together along d: under the
//!    threshold in every direction, none of them can be a building mode.
//!
//! The Ritz space grows until the bound is under the threshold, or the building's modes
//! found have not changed while it doubled, or it is invariant (every mode with mass is
//! in it), or it reaches [`MAX_RITZ_VECTORS`]; the bound is reported either way.
//!
//! Every step is deterministic (fixed start vectors and orders): the same input gives
//! the same bits.

// `!(x <= y)` is used on purpose: NaN counts as a failure.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use nalgebra::{DMatrix, DVector, SymmetricEigen};

use super::modal::{lanczos_nearest, relative_residual, SkippedModes};
use super::ritz::KrylovSpace;
use super::shift_invert::{massed_equations, ShiftInvert};
use super::AnalysisError;
use crate::fe::domain::Domain;
use crate::fe::linalg::SparsePattern;

/// The least effective mass ratio along X, Y or in torsion that makes a mode the
/// building's: 1 %. Local slab modes carry well under 0.1 % each.
pub const BUILDING_MODE_MASS_RATIO: f64 = 0.01;

/// The most load-dependent Ritz vectors generated before the search stops.
pub const MAX_RITZ_VECTORS: usize = 300;

/// Relative Ritz residual ‖C y − θ y‖ / θ at which a candidate's λ̃ becomes a shift.
const RITZ_TOL: f64 = 1e-4;

/// Relative distance of the shifts below λ̃ (refinement and Sturm count) and above a
/// group's last eigenvalue (Sturm count).
const SHIFT_OFFSET: f64 = 1e-6;

/// Candidates (and reported modes) closer than this, relative, form one group.
const GROUP_GAP: f64 = 1e-4;

/// Ritz vectors added without a new converged candidate before the unconverged ones
/// become shifts too.
const STALL: usize = 60;

/// The most skipped modes in one gap that are found one by one (step 4).
const MAX_RESOLVED: usize = 24;

/// Block inverse iterations before the Lanczos fallback.
const MAX_INVERSE_ITERATIONS: usize = 30;

/// Highest power p of the moments z_dᵀ Cᵖ z_d of the bound (module docs).
const MOMENTS: usize = 8;

/// Centres c of the bound's test functions, evenly spaced in [0, u_Λ).
const BOUND_CENTRES: usize = 64;

/// Tolerance of the refinement (relative Ritz residual ‖C y − θ y‖ / |θ|).
const EXACT_TOL: f64 = 1e-10;

/// Influence vectors over the equations of the directions that decide a building mode:
/// a unit ground displacement along X and along Y, and a unit rotation (rad) about the
/// vertical axis through the plan mass centre (r = (−(y − y_c), x − x_c) on the
/// translations, 1 on the rotation about Z), the mass centre weighted by the X and Y
/// masses.
pub(crate) fn lateral_influence(domain: &Domain) -> [Vec<f64>; 3] {
    let x = domain.influence_vector(0);
    let y = domain.influence_vector(1);
    let n = x.len();
    let (mut sx, mut mx, mut sy, mut my) = (0.0, 0.0, 0.0, 0.0);
    for (i, node) in domain.nodes().iter().enumerate() {
        let mass = domain.mass(i);
        if domain.equation(i, 0).is_some() {
            sx += mass[0] * node.coords[0];
            mx += mass[0];
        }
        if domain.equation(i, 1).is_some() {
            sy += mass[1] * node.coords[1];
            my += mass[1];
        }
    }
    let xc = if mx > 0.0 { sx / mx } else { 0.0 };
    let yc = if my > 0.0 { sy / my } else { 0.0 };
    let mut t = vec![0.0; n];
    for (i, node) in domain.nodes().iter().enumerate() {
        if let Some(e) = domain.equation(i, 0) {
            t[e] = -(node.coords[1] - yc);
        }
        if let Some(e) = domain.equation(i, 1) {
            t[e] = node.coords[0] - xc;
        }
        if let Some(e) = domain.equation(i, 5) {
            t[e] = 1.0;
        }
    }
    [x, y, t]
}

/// Effective mass ratios Γ_d² / (r_dᵀ M r_d) of a mass-normalised shape along the
/// directions of [`lateral_influence`] (0 where the direction has no mass).
pub(crate) fn lateral_ratios(phi: &DVector<f64>, m: &[f64], r: &[Vec<f64>; 3]) -> [f64; 3] {
    std::array::from_fn(|d| {
        let total: f64 = r[d].iter().zip(m).map(|(r, m)| r * r * m).sum();
        if total > 0.0 {
            let g: f64 = phi
                .iter()
                .zip(m)
                .zip(&r[d])
                .map(|((p, m), r)| p * m * r)
                .sum();
            g * g / total
        } else {
            0.0
        }
    })
}

/// Whether ratios along X, Y and torsion make a building mode.
pub(crate) fn is_building_mode(ratios: &[f64; 3]) -> bool {
    ratios.iter().any(|&r| r >= BUILDING_MODE_MASS_RATIO)
}

/// The modes [`building_modes`] found: ω² ascending, mass-normalised shapes on all
/// equations, 1-based index in the full spectrum, and what the skipped modes carry.
#[derive(Debug, Clone)]
pub(crate) struct Found {
    pub omega2: Vec<f64>,
    pub phis: Vec<DVector<f64>>,
    pub index: Vec<usize>,
    pub skipped: SkippedModes,
}

/// An exact eigenpair found on the way, in z-coordinates too.
struct Exact {
    lambda: f64,
    phi: DVector<f64>,
    /// Participation factors Γ_d = zᵀ s_d (kg^½).
    gamma: [f64; 3],
    /// Effective mass ratios along X, Y, torsion.
    ratio: [f64; 3],
    /// Unit z = M_a^{1/2} φ_a.
    z: DVector<f64>,
}

/// The search's state: the exact pairs found, the Sturm counts made, and what the
/// bound needs.
struct Search<'a> {
    pattern: &'a SparsePattern,
    k: &'a [f64],
    m: &'a [f64],
    massed: &'a [usize],
    /// s_d = M_a^{1/2} r_{d,a}, per direction (all three; zero where no mass).
    loads: [DVector<f64>; 3],
    /// r_dᵀ M r_d = ‖s_d‖².
    totals: [f64; 3],
    /// z_dᵀ Cᵖ z_d for p = 1 … MOMENTS, per direction.
    moments: [[f64; MOMENTS]; 3],
    exact: Vec<Exact>,
    /// Sturm counts made: (σ, eigenvalues below σ).
    counts: Vec<(f64, usize)>,
    /// The factorisation of K − σM at the last shift (one symbolic analysis for all).
    shifted: Option<ShiftInvert<'a>>,
}

/// Orthonormal columns from `vectors` (twice Gram–Schmidt), dependent ones dropped.
fn orthonormal(vectors: &[DVector<f64>]) -> Vec<DVector<f64>> {
    let mut out: Vec<DVector<f64>> = Vec::with_capacity(vectors.len());
    for v in vectors {
        let n0 = v.norm();
        let mut v = v.clone();
        for _ in 0..2 {
            for q in &out {
                let c = q.dot(&v);
                v.axpy(-c, q, 1.0);
            }
        }
        let n = v.norm();
        if n > 1e-10 * n0 && n > 0.0 {
            out.push(v / n);
        }
    }
    out
}

impl<'a> Search<'a> {
    /// The operator at shift σ, refactoring the one held.
    fn at(&mut self, sigma: f64) -> Result<ShiftInvert<'a>, AnalysisError> {
        match self.shifted.take() {
            Some(mut op) => {
                op.shift(self.k, self.m, sigma)?;
                Ok(op)
            }
            None => ShiftInvert::new(self.pattern, self.k, self.m, self.massed, sigma),
        }
    }

    /// Adds an exact pair unless it repeats (or is not orthogonal to) one found before.
    fn insert(&mut self, lambda: f64, phi: DVector<f64>) {
        let mut z = DVector::from_iterator(
            self.massed.len(),
            self.massed.iter().map(|&e| self.m[e].sqrt() * phi[e]),
        );
        let norm = z.norm();
        if !(norm > 0.0) {
            return;
        }
        z /= norm;
        let phi = phi / norm;
        if self.exact.iter().any(|e| e.z.dot(&z).abs() > 1e-4) {
            return;
        }
        let gamma: [f64; 3] = std::array::from_fn(|d| z.dot(&self.loads[d]));
        let ratio = std::array::from_fn(|d| {
            if self.totals[d] > 0.0 {
                gamma[d] * gamma[d] / self.totals[d]
            } else {
                0.0
            }
        });
        self.exact.push(Exact {
            lambda,
            phi,
            gamma,
            ratio,
            z,
        });
    }

    /// The building's modes among the exact pairs: indices into `exact`, ascending λ, at
    /// most `modes`.
    fn building(&self, modes: usize) -> Vec<usize> {
        let mut idx: Vec<usize> = (0..self.exact.len())
            .filter(|&i| is_building_mode(&self.exact[i].ratio))
            .collect();
        idx.sort_by(|&a, &b| self.exact[a].lambda.total_cmp(&self.exact[b].lambda));
        idx.truncate(modes);
        idx
    }

    /// Upper bound, per direction, on the summed effective mass ratio of the modes below
    /// `last` (the last reported eigenvalue) that are not in `reported`: the exact pairs
    /// found there, plus, when `unfound_below` is given, the bound on the modes not found
    /// below it (module docs, step 4).
    fn skipped_bound(&self, reported: &[usize], last: f64, unfound_below: Option<f64>) -> [f64; 3] {
        std::array::from_fn(|d| {
            if self.totals[d] <= 0.0 {
                return 0.0;
            }
            let found: f64 = self
                .exact
                .iter()
                .enumerate()
                .filter(|(i, e)| e.lambda < last && !reported.contains(i))
                .map(|(_, e)| e.gamma[d] * e.gamma[d])
                .sum();
            let unfound = unfound_below.map_or(0.0, |l| self.unfound_bound(d, l));
            // A share of the mass is at most the whole.
            ((found + unfound) / self.totals[d]).min(1.0)
        })
    }

    /// Bound on Σ Γ_d² over the modes not found with λ < `lambda_max` (module docs,
    /// step 4), kg.
    fn unfound_bound(&self, d: usize, lambda_max: f64) -> f64 {
        let top = 1.0 / lambda_max;
        // Moments of the modes not found, Σ Γ² uᵖ (u = 1/λ), p = 0 … MOMENTS.
        let rest: Vec<f64> = (0..=MOMENTS)
            .map(|p| {
                let all = if p == 0 {
                    self.totals[d]
                } else {
                    self.moments[d][p - 1]
                };
                let found: f64 = self
                    .exact
                    .iter()
                    .map(|e| e.gamma[d] * e.gamma[d] / e.lambda.powi(p as i32))
                    .sum();
                all - found
            })
            .collect();
        let mut unfound = f64::INFINITY;
        for q in 0..=MOMENTS - 2 {
            for j in 0..BOUND_CENTRES {
                let c = top * j as f64 / BOUND_CENTRES as f64;
                let sum = rest[q + 2] - 2.0 * c * rest[q + 1] + c * c * rest[q];
                let scale = top.powi(q as i32) * (top - c) * (top - c);
                unfound = unfound.min(sum.max(0.0) / scale);
            }
        }
        unfound
    }

    /// The least shift U ≤ `upper` (to 2 %, by bisection on log σ) below which lie as
    /// many eigenvalues as below `upper`. `lowest` is the lowest Ritz value, an upper
    /// bound of the lowest eigenvalue (Cauchy interlacing), where the search starts.
    fn band_top(&mut self, upper: f64, lowest: Option<f64>) -> Result<f64, AnalysisError> {
        let want = self.count(upper)?;
        let mut hi = upper;
        let mut lo = lowest.map_or(0.5 * upper, |l| 0.99 * l.min(upper));
        while self.count(lo)? == want {
            hi = lo;
            lo *= 0.5;
        }
        while hi > 1.02 * lo {
            let mid = (lo * hi).sqrt();
            if self.count(mid)? == want {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        Ok(hi)
    }

    /// Finds the `count` eigenpairs strictly between `lower` and `upper` (the Sturm
    /// count's number there) by shift-invert Lanczos at σ (the nearest `count` + 2),
    /// when `count` ≤ [`MAX_RESOLVED`]. Whether all were found.
    fn resolve(
        &mut self,
        sigma: f64,
        count: usize,
        lower: f64,
        upper: f64,
    ) -> Result<bool, AnalysisError> {
        let inside = |s: &Self| {
            s.exact
                .iter()
                .filter(|e| {
                    e.lambda > lower * (1.0 + SHIFT_OFFSET)
                        && e.lambda < upper * (1.0 - SHIFT_OFFSET)
                })
                .count()
        };
        if inside(self) == count {
            return Ok(true);
        }
        if count > MAX_RESOLVED {
            return Ok(false);
        }
        let mut op = self.at(sigma)?;
        let nev = (count + 2).min(op.dim().saturating_sub(16)).max(1);
        let basis = (3 * nev).max(nev + 8).max(16);
        let found = lanczos_nearest(&mut op, self.k, self.m, nev, basis, EXACT_TOL, 200);
        self.shifted = Some(op);
        let (lams, phis) = found?;
        for (l, p) in lams.into_iter().zip(phis) {
            self.insert(l, p);
        }
        Ok(inside(self) == count)
    }

    /// The Sturm count at σ (cached).
    fn count(&mut self, sigma: f64) -> Result<usize, AnalysisError> {
        if let Some(&(_, c)) = self.counts.iter().find(|(s, _)| *s == sigma) {
            return Ok(c);
        }
        let op = self.at(sigma)?;
        let c = sturm(&op)?;
        self.shifted = Some(op);
        self.counts.push((sigma, c));
        Ok(c)
    }

    /// The Sturm count just below λ: a cached count at σ ∈ [λ (1 − 2·offset), λ), else
    /// a new one at λ (1 − offset). Returns (σ, count).
    fn count_below(&mut self, lambda: f64) -> Result<(f64, usize), AnalysisError> {
        if let Some(&found) = self
            .counts
            .iter()
            .find(|(s, _)| *s < lambda && *s >= lambda * (1.0 - 2.0 * SHIFT_OFFSET))
        {
            return Ok(found);
        }
        let sigma = lambda * (1.0 - SHIFT_OFFSET);
        Ok((sigma, self.count(sigma)?))
    }

    /// Exact pairs of a group of Ritz vectors `ys` (unit, z-coordinates) whose lowest
    /// Ritz value is λ̃ (module docs, step 2).
    fn refine(&mut self, lambda: f64, ys: &[DVector<f64>]) -> Result<(), AnalysisError> {
        let sigma = lambda * (1.0 - SHIFT_OFFSET);
        let mut op = self.at(sigma)?;
        self.counts.push((sigma, sturm(&op)?));
        let pairs = self.exact_pairs(&mut op, ys);
        self.shifted = Some(op);
        for (l, p) in pairs? {
            self.insert(l, p);
        }
        Ok(())
    }

    /// Exact pairs from the Ritz vectors `ys` with the operator `op` at its shift:
    /// inverse iteration, else Lanczos for the pairs nearest the shift.
    fn exact_pairs(
        &self,
        op: &mut ShiftInvert<'_>,
        ys: &[DVector<f64>],
    ) -> Result<Vec<(f64, DVector<f64>)>, AnalysisError> {
        let sigma = op.sigma();
        Ok(match inverse_iteration(op, ys)? {
            Some(pairs) => {
                let mut out = Vec::with_capacity(pairs.len());
                for (theta, z) in pairs {
                    let phi = op.shape(z.as_slice(), theta)?;
                    let lam = sigma + 1.0 / theta;
                    let r = relative_residual(self.pattern, self.k, self.m, lam, &phi);
                    if !(r <= 1e-6) {
                        return Err(AnalysisError::Eigen(format!(
                            "inverse iteration at {sigma:e} rad²/s²: residual |K phi - lambda M phi| / |K phi| = {r:.2e}"
                        )));
                    }
                    out.push((lam, phi));
                }
                out
            }
            None => {
                let nev = (ys.len() + 2).min(op.dim().saturating_sub(16)).max(1);
                let basis = (3 * nev).max(nev + 8).max(16);
                let (lams, phis) = lanczos_nearest(op, self.k, self.m, nev, basis, EXACT_TOL, 200)?;
                lams.into_iter().zip(phis).collect()
            }
        })
    }

    /// Whether a unit Ritz vector y of λ̃ lies (to 90 % of its norm²) in the span of
    /// the exact pairs within 5 % of λ̃.
    fn matched(&self, y: &DVector<f64>, lambda: f64) -> bool {
        let s: f64 = self
            .exact
            .iter()
            .filter(|e| (e.lambda - lambda).abs() <= 0.05 * lambda)
            .map(|e| e.z.dot(y).powi(2))
            .sum();
        s >= 0.9
    }
}

/// A Ritz value θ of the shift-invert operator and its unit vector z.
type RitzPair = (f64, DVector<f64>);

/// The Sturm count of a factorisation.
fn sturm(op: &ShiftInvert<'_>) -> Result<usize, AnalysisError> {
    op.count_below().ok_or_else(|| {
        AnalysisError::Eigen(format!(
            "no Sturm count of K - sigma M at sigma = {:e} rad²/s² (symmetric factors not \
             finite)",
            op.sigma()
        ))
    })
}

/// Block inverse iteration with the operator C_σ of `op` from the unit vectors `start`:
/// W = C_σ X, Rayleigh–Ritz H = Xᵀ W = S Θ Sᵀ, converged when every
/// ‖W s − θ X s‖ ≤ [`EXACT_TOL`] |θ|, else X = orth(W S). Returns (θ, unit z) per
/// pair, or `None` when not converged in [`MAX_INVERSE_ITERATIONS`].
fn inverse_iteration(
    op: &mut ShiftInvert<'_>,
    start: &[DVector<f64>],
) -> Result<Option<Vec<RitzPair>>, AnalysisError> {
    let mut x = orthonormal(start);
    let n = op.dim();
    for _ in 0..MAX_INVERSE_ITERATIONS {
        let g = x.len();
        if g == 0 {
            return Ok(None);
        }
        let mut w = Vec::with_capacity(g);
        for v in &x {
            let mut y = DVector::zeros(n);
            op.apply(v.as_slice(), y.as_mut_slice())?;
            w.push(y);
        }
        let h = DMatrix::from_fn(g, g, |i, j| 0.5 * (x[i].dot(&w[j]) + x[j].dot(&w[i])));
        let eig = SymmetricEigen::new(h);
        let mut order: Vec<usize> = (0..g).collect();
        order.sort_by(|&i, &j| {
            eig.eigenvalues[j]
                .abs()
                .total_cmp(&eig.eigenvalues[i].abs())
                .then(i.cmp(&j))
        });
        let mut pairs = Vec::with_capacity(g);
        let mut images = Vec::with_capacity(g);
        let mut converged = true;
        for &c in &order {
            let theta = eig.eigenvalues[c];
            let mut y = DVector::zeros(n);
            let mut cy = DVector::zeros(n);
            for i in 0..g {
                y.axpy(eig.eigenvectors[(i, c)], &x[i], 1.0);
                cy.axpy(eig.eigenvectors[(i, c)], &w[i], 1.0);
            }
            let mut r = cy.clone();
            r.axpy(-theta, &y, 1.0);
            if !(r.norm() <= EXACT_TOL * theta.abs()) {
                converged = false;
            }
            pairs.push((theta, y));
            images.push(cy);
        }
        if converged {
            return Ok(Some(pairs));
        }
        x = orthonormal(&images);
    }
    Ok(None)
}

/// The `modes` lowest building modes of K φ = λ M φ (module docs). `influence` is
/// [`lateral_influence`]. K must be positive definite (the initial stiffness of a
/// supported structure).
pub(crate) fn building_modes(
    pattern: &SparsePattern,
    k: &[f64],
    m: &[f64],
    influence: &[Vec<f64>; 3],
    modes: usize,
) -> Result<Found, AnalysisError> {
    let massed = massed_equations(m);
    let mut op0 = ShiftInvert::new(pattern, k, m, &massed, 0.0)?;
    if sturm(&op0)? != 0 {
        return Err(AnalysisError::Eigen(
            "the building's modes need a positive definite stiffness (the Sturm count of \
             K is not zero): list the lowest modes instead"
                .into(),
        ));
    }
    let loads: [DVector<f64>; 3] = std::array::from_fn(|d| {
        DVector::from_iterator(
            massed.len(),
            massed
                .iter()
                .zip(op0.sqrt_mass())
                .map(|(&e, s)| s * influence[d][e]),
        )
    });
    let totals: [f64; 3] = std::array::from_fn(|d| loads[d].norm_squared());
    if totals.iter().all(|&t| t <= 0.0) {
        return Err(AnalysisError::Input(
            "the model has no mass along X or Y: it has no building modes; list the \
             lowest modes instead"
                .into(),
        ));
    }
    // Moments z_dᵀ Cᵖ z_d from the powers v_j = Cʲ z_d, j ≤ MOMENTS/2.
    let mut moments = [[0.0; MOMENTS]; 3];
    let mut starts = Vec::new();
    for d in 0..3 {
        if totals[d] <= 0.0 {
            continue;
        }
        let mut powers = vec![loads[d].clone()];
        for j in 1..=MOMENTS / 2 {
            let mut v = DVector::zeros(massed.len());
            op0.apply(powers[j - 1].as_slice(), v.as_mut_slice())?;
            powers.push(v);
        }
        for p in 1..=MOMENTS {
            moments[d][p - 1] = powers[p / 2].dot(&powers[p.div_ceil(2)]);
        }
        starts.push(loads[d].clone());
    }
    let mut space = KrylovSpace::new(&starts, |x, y| op0.apply(x, y))?;
    let mut search = Search {
        pattern,
        k,
        m,
        massed: &massed,
        loads,
        totals,
        moments,
        exact: Vec::new(),
        counts: Vec::new(),
        shifted: None,
    };
    let cap = MAX_RITZ_VECTORS.min(massed.len());
    // The building's modes last found (their λ) and the space's size then.
    let mut last_set: Vec<f64> = Vec::new();
    let mut set_dim = 0;
    let mut last_result: Option<Found> = None;
    // The most leading converged candidates seen, the space's size then, and the shifts
    // of unconverged candidates refined.
    let (mut best_prefix, mut progress_dim) = (0, 0);
    let mut tried: Vec<f64> = Vec::new();
    loop {
        if !space.is_invariant() && space.dim() < cap {
            space.expand(|x, y| op0.apply(x, y))?;
        }
        let last = space.is_invariant() || space.dim() >= cap;
        let ritz = space.ritz();
        let proj: Vec<DVector<f64>> = search.loads.iter().map(|s| space.project(s)).collect();
        // Candidates by ascending λ̃ (θ descending): the Ritz pairs with at least half
        // the threshold along some direction, up to the `modes`-th with the threshold
        // itself, and whether each has converged.
        let mut wanted: Vec<(f64, DVector<f64>, bool)> = Vec::new();
        let mut strong = 0;
        for c in 0..ritz.theta.len() {
            let theta = ritz.theta[c];
            if !(theta > 0.0) {
                break;
            }
            let s = ritz.coordinates.column(c);
            let ratios: [f64; 3] = std::array::from_fn(|d| {
                if search.totals[d] > 0.0 {
                    s.dot(&proj[d]).powi(2) / search.totals[d]
                } else {
                    0.0
                }
            });
            if !ratios.iter().any(|&r| r >= 0.5 * BUILDING_MODE_MASS_RATIO) {
                continue;
            }
            let (y, res) = space.vector(s.as_slice(), theta);
            wanted.push((1.0 / theta, y, res <= RITZ_TOL * theta));
            if ratios
                .iter()
                .any(|&r| r >= BUILDING_MODE_MASS_RATIO * (1.0 - 1e-3))
            {
                strong += 1;
                if strong == modes {
                    break;
                }
            }
        }
        // The converged candidates up to the first that is not; all of them when the
        // space has grown by STALL vectors without a new converged one, or is done.
        let prefix = wanted.iter().take_while(|w| w.2).count();
        if prefix > best_prefix {
            best_prefix = prefix;
            progress_dim = space.dim();
        }
        let stalled = last || space.dim() >= progress_dim + STALL;
        let take = if stalled { wanted.len() } else { prefix };
        if stalled {
            progress_dim = space.dim();
        }
        // Exact pairs for the groups with a candidate not yet matched (an unconverged one
        // once per λ̃).
        let wanted = &wanted[..take];
        let mut i = 0;
        while i < wanted.len() {
            let mut j = i + 1;
            while j < wanted.len() && wanted[j].0 <= wanted[j - 1].0 * (1.0 + GROUP_GAP) {
                j += 1;
            }
            let group = &wanted[i..j];
            let open = group.iter().any(|(l, y, _)| !search.matched(y, *l));
            let fresh = group.iter().all(|w| w.2)
                || !tried
                    .iter()
                    .any(|&t: &f64| (t - group[0].0).abs() <= 1e-3 * t);
            if open && fresh {
                if !group.iter().all(|w| w.2) {
                    tried.push(group[0].0);
                }
                let ys: Vec<DVector<f64>> = group.iter().map(|w| w.1.clone()).collect();
                search.refine(group[0].0, &ys)?;
            }
            i = j;
        }
        let building = search.building(modes);
        let set: Vec<f64> = building.iter().map(|&i| search.exact[i].lambda).collect();
        if set != last_set {
            last_set = set;
            set_dim = space.dim();
            last_result = if building.is_empty() {
                None
            } else {
                // The lowest Ritz value (the largest θ), above the lowest eigenvalue.
                let lowest = ritz.theta.first().filter(|&&t| t > 0.0).map(|t| 1.0 / t);
                Some(number(&mut search, &building, lowest)?)
            };
        }
        let Some(result) = &last_result else {
            if last {
                return Err(AnalysisError::Eigen(format!(
                    "no mode with at least {} % effective mass along X, Y or in torsion \
                     among {} load-dependent Ritz vectors",
                    BUILDING_MODE_MASS_RATIO * 100.0,
                    space.dim()
                )));
            }
            continue;
        };
        let certain = result
            .skipped
            .mass_ratio_bound
            .iter()
            .all(|&b| b < BUILDING_MODE_MASS_RATIO);
        let complete = building.len() == modes;
        let stable = space.dim() >= 2 * set_dim;
        if last || (complete && (certain || stable)) {
            return Ok(last_result.expect("checked above"));
        }
    }
}

/// The reported modes with their Sturm-counted indices and what the skipped modes carry
/// (module docs, steps 3 and 4).
fn number(
    search: &mut Search<'_>,
    building: &[usize],
    lowest: Option<f64>,
) -> Result<Found, AnalysisError> {
    let lambdas: Vec<f64> = building.iter().map(|&i| search.exact[i].lambda).collect();
    // Groups of reported eigenvalues closer than GROUP_GAP: [start, end).
    let mut groups = Vec::new();
    let mut a = 0;
    while a < lambdas.len() {
        let mut b = a + 1;
        while b < lambdas.len() && lambdas[b] <= lambdas[b - 1] * (1.0 + GROUP_GAP) {
            b += 1;
        }
        groups.push((a, b));
        a = b;
    }
    let lows: Vec<(f64, usize)> = groups
        .iter()
        .map(|&(a, _)| search.count_below(lambdas[a]))
        .collect::<Result<_, _>>()?;
    let mut index = Vec::with_capacity(lambdas.len());
    // The upper end of the highest range whose skipped modes were not all found.
    let mut top: Option<f64> = None;
    // Below the first group: the lowest eigenvalues, found when they are few.
    let first = lows[0].1;
    if first > 0 && !search.resolve(0.0, first, 0.0, lambdas[0])? {
        top = Some(lows[0].0);
    }
    let mut below_last = 0;
    for (g, &(a, b)) in groups.iter().enumerate() {
        let (_, lo) = lows[g];
        let next = lows.get(g + 1).map(|x| x.1);
        let above = lambdas[b - 1] * (1.0 + SHIFT_OFFSET);
        let hi = if next == Some(lo + (b - a)) {
            lo + (b - a)
        } else {
            search.count(above)?
        };
        if hi < lo + (b - a) {
            return Err(AnalysisError::Eigen(format!(
                "Sturm count: {} eigenvalues from {:e} to {above:e} rad²/s², but {} modes \
                 found there",
                hi - lo,
                lows[g].0,
                b - a
            )));
        }
        if hi == lo + (b - a) {
            index.extend((0..b - a).map(|j| lo + 1 + j));
        } else {
            // Unreported eigenvalues inside the group: count below each mode.
            for &l in &lambdas[a..b] {
                index.push(search.count_below(l)?.1 + 1);
            }
            top = Some(above);
        }
        if let Some(n) = next {
            // The gap to the next group: its modes, found when they are few.
            let (l0, l1) = (lambdas[b - 1], lambdas[groups[g + 1].0]);
            if n > hi && !search.resolve(0.5 * (l0 + l1), n - hi, l0, l1)? {
                top = Some(lows[g + 1].0);
            }
        }
        below_last = hi;
    }
    let last = *lambdas.last().expect("one building mode");
    // The modes not found below `top` lie below U, the least shift (to 2 %) with as many
    // eigenvalues below it: the bound's test functions need f ≥ 1 only below U.
    let top = match top {
        Some(t) => Some(search.band_top(t, lowest)?),
        None => None,
    };
    let bound = search.skipped_bound(building, last, top);
    Ok(Found {
        omega2: lambdas,
        phis: building
            .iter()
            .map(|&i| search.exact[i].phi.clone())
            .collect(),
        index,
        skipped: SkippedModes {
            count: below_last - building.len(),
            mass_ratio_bound: bound,
        },
    })
}

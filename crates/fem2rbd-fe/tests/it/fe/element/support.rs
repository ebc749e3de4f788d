//! Shared helpers of the `fe_element_*` tests: small test materials and a dense static
//! Newton driver (the real analysis layer lives elsewhere; these tests must not depend
//! on it). Used by each test file of this folder as `use super::support;`.
#![allow(dead_code)]

use fem2rbd_fe::fe::element::beam::BeamColumn;
use fem2rbd_fe::fe::element::{EndDisplacements, Vec12};
use fem2rbd_fe::fe::material::{MaterialDamage, UniaxialMaterial};
use nalgebra::{DMatrix, DVector};

/// Linear elastic test material σ = E ε.
#[derive(Debug, Clone)]
pub struct LinearElastic {
    pub e: f64,
    strain: f64,
}

impl LinearElastic {
    pub fn new(e: f64) -> Self {
        Self { e, strain: 0.0 }
    }
}

impl UniaxialMaterial for LinearElastic {
    fn set_trial_strain(&mut self, strain: f64) {
        self.strain = strain;
    }
    fn strain(&self) -> f64 {
        self.strain
    }
    fn stress(&self) -> f64 {
        self.e * self.strain
    }
    fn tangent(&self) -> f64 {
        self.e
    }
    fn initial_tangent(&self) -> f64 {
        self.e
    }
    fn commit_state(&mut self) {}
    fn revert_to_last_commit(&mut self) {}
    fn revert_to_start(&mut self) {
        self.strain = 0.0;
    }
    fn boxed_clone(&self) -> Box<dyn UniaxialMaterial> {
        Box::new(self.clone())
    }
}

/// Elastic-perfectly-plastic test material (yield stress `fy`, return mapping on the
/// committed plastic strain). Reports `yielded` once it has yielded.
#[derive(Debug, Clone)]
pub struct ElasticPerfectlyPlastic {
    pub e: f64,
    pub fy: f64,
    eps: f64,
    sig: f64,
    tan: f64,
    ep: f64,
    ep_c: f64,
    eps_c: f64,
    sig_c: f64,
    tan_c: f64,
    yielded_c: bool,
}

impl ElasticPerfectlyPlastic {
    pub fn new(e: f64, fy: f64) -> Self {
        Self {
            e,
            fy,
            eps: 0.0,
            sig: 0.0,
            tan: e,
            ep: 0.0,
            ep_c: 0.0,
            eps_c: 0.0,
            sig_c: 0.0,
            tan_c: e,
            yielded_c: false,
        }
    }
}

impl UniaxialMaterial for ElasticPerfectlyPlastic {
    fn set_trial_strain(&mut self, strain: f64) {
        self.eps = strain;
        let trial = self.e * (strain - self.ep_c);
        if trial.abs() > self.fy {
            self.sig = self.fy * trial.signum();
            self.ep = strain - self.sig / self.e;
            self.tan = 0.0;
        } else {
            self.sig = trial;
            self.ep = self.ep_c;
            self.tan = self.e;
        }
    }
    fn strain(&self) -> f64 {
        self.eps
    }
    fn stress(&self) -> f64 {
        self.sig
    }
    fn tangent(&self) -> f64 {
        self.tan
    }
    fn initial_tangent(&self) -> f64 {
        self.e
    }
    fn commit_state(&mut self) {
        self.ep_c = self.ep;
        self.eps_c = self.eps;
        self.sig_c = self.sig;
        self.tan_c = self.tan;
        self.yielded_c |= self.tan == 0.0;
    }
    fn revert_to_last_commit(&mut self) {
        self.eps = self.eps_c;
        self.ep = self.ep_c;
        self.sig = self.sig_c;
        self.tan = self.tan_c;
    }
    fn revert_to_start(&mut self) {
        *self = Self::new(self.e, self.fy);
    }
    fn boxed_clone(&self) -> Box<dyn UniaxialMaterial> {
        Box::new(self.clone())
    }
    fn damage(&self) -> MaterialDamage {
        MaterialDamage {
            yielded: self.yielded_c,
            ruptured: false,
        }
    }
}

/// Bilinear material with linear kinematic hardening (hardening modulus ratio `b`):
/// 1D return mapping, H = bE/(1 − b) so the elastoplastic tangent is bE. For the
/// monotonic tests here it is the law of OpenSees `Steel01` without isotropic hardening.
#[derive(Debug, Clone)]
pub struct BilinearKinematic {
    pub e: f64,
    pub fy: f64,
    pub b: f64,
    eps: f64,
    sig: f64,
    tan: f64,
    ep: f64,
    alpha: f64,
    ep_c: f64,
    alpha_c: f64,
    eps_c: f64,
    sig_c: f64,
    tan_c: f64,
    yielded_c: bool,
}

impl BilinearKinematic {
    pub fn new(e: f64, fy: f64, b: f64) -> Self {
        Self {
            e,
            fy,
            b,
            eps: 0.0,
            sig: 0.0,
            tan: e,
            ep: 0.0,
            alpha: 0.0,
            ep_c: 0.0,
            alpha_c: 0.0,
            eps_c: 0.0,
            sig_c: 0.0,
            tan_c: e,
            yielded_c: false,
        }
    }
}

impl UniaxialMaterial for BilinearKinematic {
    fn set_trial_strain(&mut self, strain: f64) {
        self.eps = strain;
        let h = self.b * self.e / (1.0 - self.b);
        let trial = self.e * (strain - self.ep_c);
        let xi = trial - self.alpha_c;
        let f = xi.abs() - self.fy;
        if f > 0.0 {
            let dg = f / (self.e + h);
            self.ep = self.ep_c + dg * xi.signum();
            self.alpha = self.alpha_c + h * dg * xi.signum();
            self.sig = self.e * (strain - self.ep);
            self.tan = self.e * h / (self.e + h);
        } else {
            self.ep = self.ep_c;
            self.alpha = self.alpha_c;
            self.sig = trial;
            self.tan = self.e;
        }
    }
    fn strain(&self) -> f64 {
        self.eps
    }
    fn stress(&self) -> f64 {
        self.sig
    }
    fn tangent(&self) -> f64 {
        self.tan
    }
    fn initial_tangent(&self) -> f64 {
        self.e
    }
    fn commit_state(&mut self) {
        self.ep_c = self.ep;
        self.alpha_c = self.alpha;
        self.eps_c = self.eps;
        self.sig_c = self.sig;
        self.tan_c = self.tan;
        self.yielded_c |= self.tan < self.e;
    }
    fn revert_to_last_commit(&mut self) {
        self.eps = self.eps_c;
        self.ep = self.ep_c;
        self.alpha = self.alpha_c;
        self.sig = self.sig_c;
        self.tan = self.tan_c;
    }
    fn revert_to_start(&mut self) {
        *self = Self::new(self.e, self.fy, self.b);
    }
    fn boxed_clone(&self) -> Box<dyn UniaxialMaterial> {
        Box::new(self.clone())
    }
    fn damage(&self) -> MaterialDamage {
        MaterialDamage {
            yielded: self.yielded_c,
            ruptured: false,
        }
    }
}

/// Fibers of a b × h rectangle (local y across b, local z across h), `ny × nz` cells.
pub fn rectangle_fibers(
    b: f64,
    h: f64,
    ny: usize,
    nz: usize,
    mat: &dyn UniaxialMaterial,
) -> Vec<(f64, f64, f64, Box<dyn UniaxialMaterial>)> {
    let (dy, dz) = (b / ny as f64, h / nz as f64);
    let mut f = Vec::new();
    for i in 0..ny {
        for k in 0..nz {
            let y = -0.5 * b + (i as f64 + 0.5) * dy;
            let z = -0.5 * h + (k as f64 + 0.5) * dz;
            f.push((y, z, dy * dz, mat.boxed_clone()));
        }
    }
    f
}

/// A tiny static model: elements on nodes with 6 DOFs each, some DOFs fixed.
pub struct Model {
    pub n_nodes: usize,
    pub elements: Vec<Box<dyn BeamColumn>>,
    pub fixed: Vec<usize>,
    pub u: DVector<f64>,
}

impl Model {
    pub fn new(n_nodes: usize, elements: Vec<Box<dyn BeamColumn>>, fixed: Vec<usize>) -> Self {
        Self {
            n_nodes,
            elements,
            fixed,
            u: DVector::zeros(6 * n_nodes),
        }
    }

    fn gather(&self, u: &DVector<f64>, nodes: &[usize]) -> Vec12 {
        let mut v = Vec12::zeros();
        for (k, n) in nodes.iter().enumerate() {
            for d in 0..6 {
                v[6 * k + d] = u[6 * n + d];
            }
        }
        v
    }

    /// Sets every element's trial state from `u` and assembles (R, K).
    fn assemble(
        &mut self,
        u: &DVector<f64>,
        du: &DVector<f64>,
    ) -> Result<(DVector<f64>, DMatrix<f64>), String> {
        let n = 6 * self.n_nodes;
        let mut r = DVector::zeros(n);
        let mut k = DMatrix::zeros(n, n);
        for i in 0..self.elements.len() {
            let nodes: [usize; 2] = self.elements[i].nodes().try_into().unwrap();
            let (total, delta) = (self.gather(u, &nodes), self.gather(du, &nodes));
            let disp = EndDisplacements {
                total: total.as_slice(),
                delta: delta.as_slice(),
            };
            let e = &mut self.elements[i];
            e.set_trial(&disp).map_err(|e| e.to_string())?;
            let re = e.resisting_force();
            let ke = e.tangent_stiffness();
            let dof = |a: usize| 6 * nodes[a / 6] + a % 6;
            for a in 0..12 {
                r[dof(a)] += re[a];
                for b in 0..12 {
                    k[(dof(a), dof(b))] += ke[(a, b)];
                }
            }
        }
        Ok((r, k))
    }

    /// Applies `load` (full vector, N / N·m) in `steps` equal load increments with Newton
    /// iterations until ‖Δu‖₂ < 1e-12 (OpenSees `NormDispIncr 1e-12`, at most 100
    /// iterations); returns the Newton iterations per step.
    pub fn solve(&mut self, load: &DVector<f64>, steps: usize) -> Result<Vec<usize>, String> {
        let lambdas: Vec<f64> = (1..=steps).map(|s| s as f64 / steps as f64).collect();
        self.solve_path(load, &lambdas, |_| {})
    }

    /// Follows the load-factor path `lambdas` (total factor after each step, any sign),
    /// calling `after_step` with the converged displacements of each step.
    pub fn solve_path(
        &mut self,
        load: &DVector<f64>,
        lambdas: &[f64],
        mut after_step: impl FnMut(&DVector<f64>),
    ) -> Result<Vec<usize>, String> {
        let n = 6 * self.n_nodes;
        let free: Vec<usize> = (0..n).filter(|d| !self.fixed.contains(d)).collect();
        let mut iters = Vec::new();
        let mut u = self.u.clone();
        let mut du_last = DVector::zeros(n);
        for (s, &lambda) in lambdas.iter().enumerate() {
            let mut converged = false;
            for it in 0..100 {
                let (r, k) = self.assemble(&u, &du_last)?;
                let resid = lambda * load - r;
                let kf = DMatrix::from_fn(free.len(), free.len(), |i, j| k[(free[i], free[j])]);
                let rf = DVector::from_fn(free.len(), |i, _| resid[free[i]]);
                let duf = kf
                    .lu()
                    .solve(&rf)
                    .ok_or_else(|| "singular stiffness".to_string())?;
                let mut du = DVector::zeros(n);
                for (i, &d) in free.iter().enumerate() {
                    du[d] = duf[i];
                }
                u += &du;
                du_last = du.clone();
                // OpenSees `test NormDispIncr 1e-12`: 2-norm of the increment (m, rad).
                if du.norm() < 1e-12 {
                    // Final state determination at the converged displacements.
                    let zero = DVector::zeros(n);
                    self.assemble(&u, &zero)?;
                    iters.push(it + 1);
                    converged = true;
                    break;
                }
            }
            if !converged {
                return Err(format!("Newton did not converge in load step {s}"));
            }
            for e in &mut self.elements {
                e.commit_state();
            }
            after_step(&u);
        }
        self.u = u;
        Ok(iters)
    }

    /// Resisting force vector of the current state.
    pub fn resisting(&mut self) -> DVector<f64> {
        let u = self.u.clone();
        let zero = DVector::zeros(u.len());
        self.assemble(&u, &zero).expect("state determination").0
    }
}

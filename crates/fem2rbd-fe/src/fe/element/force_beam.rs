//! Force-based fiber beam-column (OpenSees `forceBeamColumn` 3D) with the element state
//! determination of Spacone, Filippou & Taucer (1996) / Neuenhofer & Filippou (1997):
//! section forces follow exactly from the basic forces by equilibrium, and compatibility
//! is enforced by internal element iterations.
//!
//! Equilibrium at ξ = x/L: `s(ξ) = b(ξ) q` with `N = q0`, `Mz = (ξ−1) q1 + ξ q2`,
//! `My = (ξ−1) q3 + ξ q4`, `T = q5`. Element flexibility `f = Σ bᵀ f_s b w L` over
//! Gauss-Lobatto points; residual deformations `v_r = Σ bᵀ (e_s + f_s (b q − s_r)) w L`.
//!
//! One state determination for a new trial `v` (own implementation of the algorithm of
//! OpenSees `ForceBeamColumn3d::update`):
//! 1. `Δv = v − v_prev`; `q ← q + k Δv`;
//! 2. at each section `Δe = f_s (b q − s_r)`, `e ← e + Δe`, section state from `e`;
//! 3. `f`, `v_r` as above; `k = f⁻¹`; `Δv = v − v_r`; `Δq = k Δv`; `q ← q + Δq`;
//!    converged when `|Δv · Δq| < tol` (an energy norm, N·m), else repeat 2–3.
//!
//! If it does not converge in `max_iter` iterations it retries with the initial section
//! flexibility (10 × `max_iter`), then with the initial flexibility only in the first
//! iteration; if all three fail, `Δv` is divided by `subdivide_factor` and applied in
//! parts, up to `max_subdivisions` times (OpenSees' defaults: 10 iterations, 1e-12, 4
//! subdivisions by a factor 10; the reference frame uses 50 / 1e-12).

use super::beam::{
    damage_of, section_states, transform_error, BeamColumn, FormCache, SectionState,
};
use super::quadrature::gauss_lobatto;
use super::{dmat, dvec, Element, ElementDamage, ElementError, EndDisplacements, Mat12, Prepare};
use crate::fe::section::{flexibility, Section};
use crate::fe::transform::{CrdTransf, DeformedFrame, Mat6};
use nalgebra::{DMatrix, DVector};
use nalgebra::{Matrix4, SMatrix, Vector4, Vector6};

type Mat4x6 = SMatrix<f64, 4, 6>;

/// Element iteration controls of the force-based element.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ForceBeamOptions {
    /// Maximum element iterations per attempt (OpenSees `-iter maxIter`).
    pub max_iter: usize,
    /// Tolerance on `|Δv · Δq|` (N·m) (OpenSees `-iter … tol`).
    pub tol: f64,
    /// Maximum number of subdivisions of Δv.
    pub max_subdivisions: usize,
    /// Factor by which Δv is divided on each subdivision (≥ 1).
    pub subdivide_factor: f64,
}

impl Default for ForceBeamOptions {
    /// OpenSees' defaults: 10 iterations, 1e-12, 4 subdivisions by 10.
    fn default() -> Self {
        Self {
            max_iter: 10,
            tol: 1e-12,
            max_subdivisions: 4,
            subdivide_factor: 10.0,
        }
    }
}

/// Converged element state (trial or committed).
#[derive(Debug, Clone)]
struct State {
    /// Basic deformations this state is compatible with.
    v: Vector6<f64>,
    /// Basic forces.
    q: Vector6<f64>,
    /// Basic stiffness `f⁻¹`.
    kv: Mat6,
    /// Section deformations, resultants and flexibilities.
    es: Vec<Vector4<f64>>,
    sr: Vec<Vector4<f64>>,
    fs: Vec<Matrix4<f64>>,
}

/// Force-based 3D beam-column.
#[derive(Debug)]
pub struct ForceBeam3d {
    tag: i64,
    nodes: [usize; 2],
    transf: Box<dyn CrdTransf>,
    sections: Vec<Box<dyn Section>>,
    xs: Vec<f64>,
    ws: Vec<f64>,
    /// `b(ξ)` at each point.
    b: Vec<Mat4x6>,
    /// Initial section flexibilities.
    fs0: Vec<Matrix4<f64>>,
    l: f64,
    opts: ForceBeamOptions,
    kv0: Mat6,
    trial: State,
    committed: State,
    /// Element iterations used by the last state determination (all attempts).
    last_iterations: usize,
    /// Tangent of the trial state, formed once per state.
    forms: FormCache,
}

/// `b(ξ)`: section forces from basic forces.
fn b_matrix(xi: f64) -> Mat4x6 {
    let mut b = Mat4x6::zeros();
    b[(0, 0)] = 1.0;
    b[(1, 1)] = xi - 1.0;
    b[(1, 2)] = xi;
    b[(2, 3)] = xi - 1.0;
    b[(2, 4)] = xi;
    b[(3, 5)] = 1.0;
    b
}

impl ForceBeam3d {
    /// New element with `n_ip ≥ 2` Gauss-Lobatto points, each with a copy of `section`.
    pub fn new(
        tag: i64,
        nodes: [usize; 2],
        section: &dyn Section,
        n_ip: usize,
        transf: Box<dyn CrdTransf>,
        opts: ForceBeamOptions,
    ) -> Result<Self, ElementError> {
        let err = |reason: String| ElementError {
            element: tag,
            reason,
        };
        if !(2..=20).contains(&n_ip) {
            return Err(err(format!(
                "number of integration points {n_ip} must be 2..=20"
            )));
        }
        if opts.max_iter == 0
            || opts.tol.is_nan()
            || opts.tol <= 0.0
            || opts.subdivide_factor.is_nan()
            || opts.subdivide_factor < 1.0
        {
            return Err(err(format!("invalid element iteration options {opts:?}")));
        }
        let (xs, ws) = gauss_lobatto(n_ip);
        let l = transf.initial_length();
        let b: Vec<Mat4x6> = xs.iter().map(|&x| b_matrix(x)).collect();
        let sections: Vec<Box<dyn Section>> = (0..n_ip).map(|_| section.boxed_clone()).collect();
        let fs0 = sections
            .iter()
            .map(|s| flexibility(&s.initial_tangent()))
            .collect::<Option<Vec<_>>>()
            .ok_or_else(|| err("section's initial tangent is singular".into()))?;
        let mut f = Mat6::zeros();
        for i in 0..n_ip {
            f += b[i].transpose() * fs0[i] * b[i] * (ws[i] * l);
        }
        let kv0 = f
            .try_inverse()
            .ok_or_else(|| err("initial element flexibility is singular".into()))?;
        let state = State {
            v: Vector6::zeros(),
            q: Vector6::zeros(),
            kv: kv0,
            es: vec![Vector4::zeros(); n_ip],
            sr: sections.iter().map(|s| s.resultant()).collect(),
            fs: fs0.clone(),
        };
        Ok(Self {
            tag,
            nodes,
            transf,
            sections,
            xs,
            ws,
            b,
            fs0,
            l,
            opts,
            kv0,
            committed: state.clone(),
            trial: state,
            last_iterations: 0,
            forms: FormCache::default(),
        })
    }

    /// `K = Tᵀ kv T + K_g` of the trial state (cached).
    fn tangent12(&self) -> &Mat12 {
        self.forms
            .tangent(|| self.transf.global_stiffness(&self.trial.kv, &self.trial.q))
    }

    /// Element iterations used by the last state determination.
    pub fn last_iterations(&self) -> usize {
        self.last_iterations
    }

    /// Brings the element from state `start` to compatibility with `start.v + dv`.
    /// Returns the new state, or `None` when the attempt does not converge.
    fn iterate(&mut self, start: &State, dv: &Vector6<f64>, mode: usize) -> Option<State> {
        let n = self.sections.len();
        let mut st = start.clone();
        let v_target = start.v + dv;
        st.q += st.kv * dv;
        let max_iter = if mode == 1 {
            10 * self.opts.max_iter
        } else {
            self.opts.max_iter
        };
        for j in 0..max_iter {
            self.last_iterations += 1;
            let mut f = Mat6::zeros();
            let mut vr = Vector6::zeros();
            for i in 0..n {
                let b = &self.b[i];
                let wl = self.ws[i] * self.l;
                let s = b * st.q;
                let ds = s - st.sr[i];
                let use_initial = mode == 1 || (mode == 2 && j == 0);
                let fsec = if use_initial { &self.fs0[i] } else { &st.fs[i] };
                st.es[i] += fsec * ds;
                let sec = &mut self.sections[i];
                sec.set_trial_deformation(&st.es[i]);
                st.sr[i] = sec.resultant();
                st.fs[i] = flexibility(&sec.tangent())?;
                let resid = st.fs[i] * (s - st.sr[i]);
                f += b.transpose() * st.fs[i] * b * wl;
                vr += b.transpose() * (st.es[i] + resid) * wl;
            }
            st.kv = f.try_inverse()?;
            let ddv = v_target - vr;
            let dq = st.kv * ddv;
            let dw = ddv.dot(&dq);
            st.q += dq;
            if !dw.is_finite() || st.q.iter().any(|x| !x.is_finite()) {
                return None;
            }
            if dw.abs() < self.opts.tol {
                st.v = v_target;
                return Some(st);
            }
        }
        None
    }

    /// Element state determination for the new basic deformations `v`.
    fn state_determination(&mut self, v: Vector6<f64>) -> Result<(), ElementError> {
        self.last_iterations = 0;
        let dv = v - self.trial.v;
        if dv.norm() <= f64::EPSILON {
            return Ok(());
        }
        let mut state = self.trial.clone();
        let mut to_do = dv;
        let mut step = dv;
        let mut n_sub = 1;
        while n_sub <= self.opts.max_subdivisions {
            let mut done = None;
            for mode in 0..3 {
                if let Some(s) = self.iterate(&state, &step, mode) {
                    done = Some(s);
                    break;
                }
            }
            match done {
                Some(s) => {
                    state = s;
                    to_do -= step;
                    if to_do.norm() <= f64::EPSILON * (1.0 + v.norm()) {
                        self.trial = state;
                        self.trial.v = v;
                        return Ok(());
                    }
                    step = to_do;
                    n_sub = 1;
                }
                None => {
                    step /= self.opts.subdivide_factor;
                    n_sub += 1;
                }
            }
        }
        // Leave the sections consistent with the last converged trial state.
        for (i, sec) in self.sections.iter_mut().enumerate() {
            sec.set_trial_deformation(&self.trial.es[i]);
        }
        Err(ElementError {
            element: self.tag,
            reason: format!(
                "force-based element did not reach compatible forces and deformations \
                 ({} iterations, {} subdivisions)",
                self.opts.max_iter, self.opts.max_subdivisions
            ),
        })
    }
}

impl Element for ForceBeam3d {
    fn tag(&self) -> i64 {
        self.tag
    }
    fn nodes(&self) -> &[usize] {
        &self.nodes
    }
    fn set_trial(&mut self, disp: &EndDisplacements<'_>) -> Result<(), ElementError> {
        self.forms.clear();
        self.transf
            .update(&disp.total12())
            .map_err(|e| transform_error(self.tag, e))?;
        let v = self.transf.basic_deformations();
        self.state_determination(v)
    }
    fn resisting_force(&self) -> DVector<f64> {
        dvec(&self.transf.global_resisting_force(&self.trial.q))
    }
    fn tangent_stiffness(&self) -> DMatrix<f64> {
        dmat(self.tangent12())
    }
    fn resisting_force_into(&self, out: &mut [f64]) {
        out.copy_from_slice(self.transf.global_resisting_force(&self.trial.q).as_slice());
    }
    fn tangent_stiffness_into(&self, out: &mut [f64]) {
        out.copy_from_slice(self.tangent12().as_slice());
    }
    fn has_trial_damping_stiffness(&self) -> bool {
        false
    }
    fn prepare(&self, what: Prepare) {
        if what == Prepare::Tangent {
            self.tangent12();
        }
    }
    fn initial_stiffness(&self) -> DMatrix<f64> {
        dmat(&self.transf.initial_global_stiffness(&self.kv0))
    }
    fn commit_state(&mut self) {
        self.transf.commit();
        for s in &mut self.sections {
            s.commit_state();
        }
        self.committed = self.trial.clone();
    }
    fn revert_to_last_commit(&mut self) {
        self.transf.revert();
        for s in &mut self.sections {
            s.revert_to_last_commit();
        }
        self.trial = self.committed.clone();
        self.forms.clear();
    }
    fn damage(&self) -> ElementDamage {
        damage_of(&self.sections)
    }
    fn sections(&self) -> Vec<(f64, &dyn Section)> {
        self.xs
            .iter()
            .zip(&self.sections)
            .map(|(&xi, s)| (xi, s.as_ref()))
            .collect()
    }
}

impl BeamColumn for ForceBeam3d {
    fn basic_forces(&self) -> Vector6<f64> {
        self.trial.q
    }
    fn basic_deformations(&self) -> Vector6<f64> {
        self.trial.v
    }
    fn section_states(&self) -> Vec<SectionState> {
        section_states(&self.sections, &self.xs, &self.ws)
    }
    fn deformed_frame(&self) -> DeformedFrame {
        self.transf.deformed_frame()
    }
    fn into_element(self: Box<Self>) -> Box<dyn Element> {
        self
    }
}

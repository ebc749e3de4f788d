//! Corotational (large-rotation) kinematics of the four-node shell: OpenSees 3.7.1
//! `ASDShellQ4 … -corotational` (`ASDShellQ4CorotationalTransformation`, after Felippa &
//! Haugen, "A unified formulation of small-strain corotational finite elements: I.
//! Theory", CMAME 194 (2005) 2285–2335), with the residual OpenSees forms and its
//! consistent tangent.
//!
//! **Frame.** The corotated frame of the current nodes xᵢ = Xᵢ + uᵢ (m): origin c at their
//! mean, e₃ ∥ d₁₃ × d₂₄ (the diagonals), e₁ first along the side 1 → 2 projected on the
//! plane, then turned about e₃ by the polar angle α of the in-plane deformation gradient at
//! the element centre, F = Σᵢ qᵢ ⊗ ∇₀Nᵢ(0, 0) (qᵢ: in-plane current coordinates, ∇₀Nᵢ the
//! bilinear shape-function gradients in the reference local frame),
//! α = atan2(F₂₁ − F₁₂, F₁₁ + F₂₂), so that F is symmetric (the stretch U of F = R U) in
//! the final frame. R (3 × 3, rows e₁ e₂ e₃) maps global to local components.
//!
//! **Local (deformational) displacements.** uₗ,ᵢ = R (xᵢ − c) − R₀ (Xᵢ − c₀) (m; R₀, c₀
//! of the undeformed element); θₗ,ᵢ = log(R Rₙ,ᵢ R₀ᵀ) (rotation vector, |θ| ≤ π), where the
//! nodal rotation Rₙ,ᵢ is compounded from the increments of the additive rotation DOFs
//! between two trials, Rₙ ← exp([Δθ]×) Rₙ (a spatial spin; OpenSees keeps it as a
//! quaternion). The small-displacement element ([`super::ShellKinematics`], reference
//! geometry, no warpage matrix) turns uₗ into the local force fₗ and tangent Kₗ.
//!
//! **Residual** (as OpenSees 3.7.1 forms it): r = Tᵀ Pₜᵀ fₗ, T = diag(R, …, R) (8 blocks),
//! Pₜ = I − (1/4) Σ (translation averaging) the translational projector. OpenSees' spin
//! projector S G is zero there (its source: "when attaching the local system using the
//! polar decomposition … the G matrix should be exactly 0"), and the rotational rows are
//! not multiplied by Hᵀ; we reproduce that residual exactly so that the equilibrium paths
//! agree.
//!
//! **Consistent tangent.** Varying the residual: δuₗ = H (Pₜ − S G) T δu (H: Felippa's
//! axial-vector Jacobian I − ½Ω + η Ω² per node, η = (1 − ½θ cot ½θ)/θ², eq. 101 of the
//! 2005 paper; S: the spin-lever matrix, −[pᵢ]× on translations and I on rotations, pᵢ the
//! current local node coordinates; G: the spin-fitter δωₗ = G T δu of this frame) and
//! δ(Rᵀ v) = −Rᵀ [v]× δωₗ, so
//! K = Tᵀ (Pₜᵀ Kₗ H (Pₜ − S G) − F̃ G) T with F̃ the stack of [f̃ᵢ]× of f̃ = Pₜᵀ fₗ.
//! OpenSees' own tangent keeps only Tᵀ Pₜᵀ Kₗ H Pₜ T (no geometric stiffness), which is why
//! it needs displacement control for the elastica; ours converges quadratically.
//!
//! The spin fitter of this frame (local components, 2A = |d₁₃ × d₂₄|): the normal gives
//! δω₁ = (x₄₂ δw₁ − x₃₁ δw₂ − x₄₂ δw₃ + x₃₁ δw₄)/2A and
//! δω₂ = (y₄₂ δw₁ − y₃₁ δw₂ − y₄₂ δw₃ + y₃₁ δw₄)/2A (xᵢⱼ = xᵢ − xⱼ, local); the polar
//! condition F₁₂ = F₂₁ held through the variation gives
//! δω₃ = [Σᵢ (δvᵢ gᵢ₁ − δuᵢ gᵢ₂) + δω₁ Σᵢ zᵢ gᵢ₁ + δω₂ Σᵢ zᵢ gᵢ₂] / (F₁₁ + F₂₂)
//! (gᵢ = ∇₀Nᵢ, zᵢ the warp of node i off the current mid-plane).

use nalgebra::{Matrix2, Matrix3, Rotation3, SMatrix, UnitQuaternion, Vector3};

use super::{LocalFrame, Mat24, ShellError, Vec24};

/// Spin (cross-product) matrix [v]×: [v]× w = v × w.
fn spin(v: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -v[2], v[1], v[2], 0.0, -v[0], -v[1], v[0], 0.0)
}

/// Rotation vector of a unit quaternion, |θ| ≤ π (OpenSees `ASDQuaternion::toRotationVector`:
/// the sign of the quaternion is chosen with w ≥ 0; θ = 2 asin|v| or 2 acos w, whichever is
/// better conditioned).
fn rotation_vector(q: &UnitQuaternion<f64>) -> Vector3<f64> {
    let q = q.quaternion();
    let (mut w, mut v) = (q.w, q.imag());
    if w < 0.0 {
        w = -w;
        v = -v;
    }
    let n = v.norm();
    if n == 0.0 {
        return Vector3::zeros();
    }
    let mult = if n < w {
        2.0 / n * n.asin()
    } else {
        2.0 / n * w.clamp(-1.0, 1.0).acos()
    };
    v * mult
}

/// Felippa & Haugen's axial-vector Jacobian H(θ) = I − ½Ω + η Ω² (Ω = [θ]×),
/// η = (1 − ½θ cot ½θ)/θ², with its series below θ = 0.05 (eq. 101).
fn axial_jacobian(theta: &Vector3<f64>) -> Matrix3<f64> {
    let mut a = theta.norm();
    if a >= 2.0 * std::f64::consts::PI {
        a %= 2.0 * std::f64::consts::PI;
    }
    let eta = if a < 0.05 {
        let a2 = a * a;
        1.0 / 12.0 + a2 / 720.0 + a2 * a2 / 30240.0 + a2 * a2 * a2 / 1_209_600.0
    } else {
        (1.0 - 0.5 * a / (0.5 * a).tan()) / (a * a)
    };
    let om = spin(theta);
    Matrix3::identity() - om * 0.5 + om * om * eta
}

/// Bilinear shape-function gradients at the element centre in the reference local frame
/// (∂Nᵢ/∂X, ∂Nᵢ/∂Y), from the reference in-plane coordinates `a`.
fn centre_gradients(a: &[[f64; 2]; 4]) -> Result<[[f64; 2]; 4], ShellError> {
    const DXI: [f64; 4] = [-0.25, 0.25, 0.25, -0.25];
    const DETA: [f64; 4] = [-0.25, -0.25, 0.25, 0.25];
    let mut j = Matrix2::<f64>::zeros();
    for i in 0..4 {
        j[(0, 0)] += DXI[i] * a[i][0];
        j[(0, 1)] += DETA[i] * a[i][0];
        j[(1, 0)] += DXI[i] * a[i][1];
        j[(1, 1)] += DETA[i] * a[i][1];
    }
    let ji = j
        .try_inverse()
        .ok_or_else(|| ShellError::Invalid("degenerate element".into()))?;
    Ok([0, 1, 2, 3].map(|i| {
        [
            DXI[i] * ji[(0, 0)] + DETA[i] * ji[(1, 0)],
            DXI[i] * ji[(0, 1)] + DETA[i] * ji[(1, 1)],
        ]
    }))
}

/// The corotated frame of a configuration.
#[derive(Debug, Clone)]
pub(crate) struct CorotFrame {
    /// Rows e₁, e₂, e₃ (global → local).
    pub r: Matrix3<f64>,
    /// Centre (m, global).
    pub c: Vector3<f64>,
    /// Local coordinates of the nodes (m).
    pub p: [Vector3<f64>; 4],
}

/// Corotational state of one element: the reference geometry and the nodal rotations.
#[derive(Debug, Clone)]
pub(crate) struct Corotational {
    /// Undeformed nodes (m, global).
    x0: [Vector3<f64>; 4],
    /// Reference frame R₀.
    r0: Matrix3<f64>,
    /// Reference local coordinates R₀ (Xᵢ − c₀) (m; c₀ the mean of the Xᵢ).
    p0: [Vector3<f64>; 4],
    /// ∇₀Nᵢ at the centre (1/m).
    grads: [[f64; 2]; 4],
    /// Nodal rotations (trial, committed) and the additive rotation DOFs last seen.
    qn: [UnitQuaternion<f64>; 4],
    rv: [Vector3<f64>; 4],
    qn_committed: [UnitQuaternion<f64>; 4],
    rv_committed: [Vector3<f64>; 4],
}

impl Corotational {
    /// The state of an undeformed element with nodes `coords` (m).
    pub fn new(coords: &[[f64; 3]; 4]) -> Result<Self, ShellError> {
        let x0 = coords.map(Vector3::from);
        let lf = LocalFrame::new(&x0)?;
        let a = [0, 1, 2, 3].map(|i| [lf.p[i][0], lf.p[i][1]]);
        let grads = centre_gradients(&a)?;
        let id = UnitQuaternion::identity();
        Ok(Self {
            x0,
            r0: lf.r,
            p0: lf.p,
            grads,
            qn: [id; 4],
            rv: [Vector3::zeros(); 4],
            qn_committed: [id; 4],
            rv_committed: [Vector3::zeros(); 4],
        })
    }

    /// Compounds the nodal rotations with the increments of the additive rotation DOFs
    /// since the last trial (`ug`: 24 global DOFs, totals).
    pub fn update_rotations(&mut self, ug: &Vec24) {
        for i in 0..4 {
            let rv = Vector3::new(ug[6 * i + 3], ug[6 * i + 4], ug[6 * i + 5]);
            let d = rv - self.rv[i];
            self.rv[i] = rv;
            self.qn[i] = UnitQuaternion::from_scaled_axis(d) * self.qn[i];
        }
    }

    /// Accepts the trial rotations.
    pub fn commit(&mut self) {
        self.qn_committed = self.qn;
        self.rv_committed = self.rv;
    }

    /// Returns to the committed rotations.
    pub fn revert(&mut self) {
        self.qn = self.qn_committed;
        self.rv = self.rv_committed;
    }

    /// The corotated frame of the displaced nodes (`ug`: 24 global DOFs).
    pub fn frame(&self, ug: &Vec24) -> Result<CorotFrame, ShellError> {
        let x = [0, 1, 2, 3]
            .map(|i| self.x0[i] + Vector3::new(ug[6 * i], ug[6 * i + 1], ug[6 * i + 2]));
        let base = LocalFrame::new(&x)?;
        // Deformation gradient at the centre between reference and base in-plane coordinates.
        let mut f = Matrix2::<f64>::zeros();
        for i in 0..4 {
            for a in 0..2 {
                for b in 0..2 {
                    f[(a, b)] += base.p[i][a] * self.grads[i][b];
                }
            }
        }
        let alpha = (f[(1, 0)] - f[(0, 1)]).atan2(f[(0, 0)] + f[(1, 1)]);
        let e1 = base.r.row(0).transpose();
        let e2 = base.r.row(1).transpose();
        let e3 = base.r.row(2).transpose();
        let e1 = (e1 * alpha.cos() + e2 * alpha.sin()).normalize();
        let e2 = e3.cross(&e1).normalize();
        let r = Matrix3::from_rows(&[e1.transpose(), e2.transpose(), e3.transpose()]);
        let c = (x[0] + x[1] + x[2] + x[3]) * 0.25;
        let p = [0, 1, 2, 3].map(|i| r * (x[i] - c));
        Ok(CorotFrame { r, c, p })
    }

    /// Local (deformational) displacements and rotations in the frame `fr`.
    pub fn local_displacements(&self, fr: &CorotFrame, ug: &Vec24) -> Vec24 {
        let q = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(fr.r));
        let q0 = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(self.r0));
        let mut ul = Vec24::zeros();
        for i in 0..4 {
            let x = self.x0[i] + Vector3::new(ug[6 * i], ug[6 * i + 1], ug[6 * i + 2]);
            let d = fr.r * (x - fr.c) - self.p0[i];
            let th = rotation_vector(&(q * self.qn[i] * q0.inverse()));
            for k in 0..3 {
                ul[6 * i + k] = d[k];
                ul[6 * i + 3 + k] = th[k];
            }
        }
        ul
    }

    /// The spin fitter G (3 × 24, local components): δωₗ = G δuₗ,trans of the frame `fr`
    /// (see the module docs).
    pub fn spin_fitter(&self, fr: &CorotFrame) -> SMatrix<f64, 3, 24> {
        let p = &fr.p;
        let (x31, y31) = (p[2][0] - p[0][0], p[2][1] - p[0][1]);
        let (x42, y42) = (p[3][0] - p[1][0], p[3][1] - p[1][1]);
        let m = 1.0 / (x31 * y42 - y31 * x42);
        let mut g = SMatrix::<f64, 3, 24>::zeros();
        for (node, s) in [(0, 1.0), (2, -1.0)] {
            g[(0, 6 * node + 2)] = s * x42 * m;
            g[(1, 6 * node + 2)] = s * y42 * m;
        }
        for (node, s) in [(1, -1.0), (3, 1.0)] {
            g[(0, 6 * node + 2)] = s * x31 * m;
            g[(1, 6 * node + 2)] = s * y31 * m;
        }
        let gr = &self.grads;
        let trace: f64 = (0..4)
            .map(|i| p[i][0] * gr[i][0] + p[i][1] * gr[i][1])
            .sum();
        let zx: f64 = (0..4).map(|i| p[i][2] * gr[i][0]).sum();
        let zy: f64 = (0..4).map(|i| p[i][2] * gr[i][1]).sum();
        for i in 0..4 {
            g[(2, 6 * i)] = -gr[i][1] / trace;
            g[(2, 6 * i + 1)] = gr[i][0] / trace;
        }
        for c in 0..24 {
            g[(2, c)] += (g[(0, c)] * zx + g[(1, c)] * zy) / trace;
        }
        g
    }

    /// Global residual and consistent tangent from the local force `fl` and tangent `kl`
    /// of the local displacements `ul` in the frame `fr` (see the module docs).
    pub fn to_global(&self, fr: &CorotFrame, ul: &Vec24, fl: &Vec24, kl: &Mat24) -> (Vec24, Mat24) {
        let mut t = Mat24::zeros();
        for blk in 0..8 {
            t.fixed_view_mut::<3, 3>(3 * blk, 3 * blk).copy_from(&fr.r);
        }
        // Translational projector Pₜ.
        let mut pt = Mat24::identity();
        for i in 0..4 {
            for j in 0..4 {
                for k in 0..3 {
                    pt[(6 * i + k, 6 * j + k)] -= 0.25;
                }
            }
        }
        let ft = pt.transpose() * fl;
        let g = self.spin_fitter(fr);
        // Spin lever S: −[pᵢ]× on translations, I on rotations.
        let mut s = SMatrix::<f64, 24, 3>::zeros();
        let mut fnm = SMatrix::<f64, 24, 3>::zeros();
        for i in 0..4 {
            s.fixed_view_mut::<3, 3>(6 * i, 0)
                .copy_from(&(-spin(&fr.p[i])));
            s.fixed_view_mut::<3, 3>(6 * i + 3, 0)
                .copy_from(&Matrix3::identity());
            for o in [0, 3] {
                let v = Vector3::new(ft[6 * i + o], ft[6 * i + o + 1], ft[6 * i + o + 2]);
                fnm.fixed_view_mut::<3, 3>(6 * i + o, 0)
                    .copy_from(&spin(&v));
            }
        }
        let mut h = Mat24::identity();
        for i in 0..4 {
            let th = Vector3::new(ul[6 * i + 3], ul[6 * i + 4], ul[6 * i + 5]);
            h.fixed_view_mut::<3, 3>(6 * i + 3, 6 * i + 3)
                .copy_from(&axial_jacobian(&th));
        }
        let p = pt - s * g;
        let kloc = pt.transpose() * kl * h * p - fnm * g;
        (t.transpose() * ft, t.transpose() * kloc * t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The analytic spin fitter against finite differences of the frame, on a warped,
    /// distorted element in a displaced and rotated configuration.
    #[test]
    fn spin_fitter_matches_finite_differences_of_the_frame() {
        let coords = [
            [0.1, -0.05, 0.02],
            [1.1, 0.1, -0.03],
            [1.0, 0.9, 0.04],
            [-0.1, 1.05, -0.01],
        ];
        let co = Corotational::new(&coords).unwrap();
        let mut ug = Vec24::zeros();
        let rot = UnitQuaternion::from_scaled_axis(Vector3::new(0.3, -0.7, 0.5));
        for i in 0..4 {
            let x = Vector3::from(coords[i]);
            let y = rot * x
                + Vector3::new(0.2, 0.1, -0.3)
                + Vector3::new(0.01 * i as f64, -0.02, 0.015 * (i % 2) as f64);
            for k in 0..3 {
                ug[6 * i + k] = y[k] - x[k];
            }
        }
        let fr = co.frame(&ug).unwrap();
        let g = co.spin_fitter(&fr);
        let h = 1e-6;
        let mut worst: f64 = 0.0;
        for node in 0..4 {
            for k in 0..3 {
                // A global perturbation along the local axis k of this node.
                let dir = fr.r.row(k).transpose();
                let mut up = ug;
                let mut um = ug;
                for c in 0..3 {
                    up[6 * node + c] += h * dir[c];
                    um[6 * node + c] -= h * dir[c];
                }
                let rp = co.frame(&up).unwrap().r;
                let rm = co.frame(&um).unwrap().r;
                // R' = exp(−[δω]×) R ⇒ [δω]× = −(R' Rᵀ − R'' Rᵀ)/2.
                let d = (rp - rm) * fr.r.transpose() / (-2.0 * h);
                let w = Vector3::new(d[(2, 1)], d[(0, 2)], d[(1, 0)]);
                for r in 0..3 {
                    worst = worst.max((w[r] - g[(r, 6 * node + k)]).abs());
                }
            }
        }
        assert!(worst < 1e-7, "spin fitter vs finite differences: {worst:e}");
    }
}

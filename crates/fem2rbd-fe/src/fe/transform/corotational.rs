//! 3D corotational transformation, after OpenSees `CorotCrdTransf3d` (Crisfield 1990;
//! de Souza 2000, "Force-based finite element for large displacement inelastic analysis
//! of frames", PhD thesis, UC Berkeley, ch. 4). Large displacements and rotations with
//! small strains in the basic system.
//!
//! Kinematics (one update):
//! 1. Nodal triads `R_I`, `R_J` (start equal to the undeformed local axes `R0`) are
//!    compounded with the rotation increments since the last update, spatially:
//!    `R ← exp(S(Δθ)) R` (OpenSees does this with quaternions).
//! 2. The mean rigid frame `R̄ = R(γ/2) R_I` with `γ` the tangent-scaled pseudo-vector of
//!    `R_J R_Iᵀ` (`γ = 2 q_v / q_w`) and `R(w) = I + (S(w) + S(w)²/2)/(1 + |w|²/4)`.
//! 3. The corotated frame `e`: `e1` along the deformed chord (length `Ln`),
//!    `e_k = r_k − (r_k·e1)/2 (e1 + r1)` for k = 2, 3, with `r_k` the columns of `R̄`.
//! 4. Natural deformations `ul` (7): end rotations relative to `e`,
//!    `ul0 = asin((r_I2·e3 − r_I3·e2)/2)` (twist at I), `ul1 = asin((r_I1·e2 − r_I2·e1)/2)`
//!    (about e3), `ul2 = asin((r_I1·e3 − r_I3·e1)/2)` (about −e2), same at J (`ul3..5`),
//!    and the elongation `ul6 = 2 (x_JI + d_JI/2)·d_JI / (Ln + L)`.
//! 5. Basic deformations `v = Tp ul = [ul6, ul1, ul4, −ul2, −ul5, ul3 − ul0]`.
//!
//! The variation `δul = T δu` (δu with rotational spins) is OpenSees' matrix `T` (7 × 12),
//! written out in [`CorotTransf::kinematics`]. Forces: `p = Tᵀ Tpᵀ q`. Tangent:
//! `K = Tᵀ Tpᵀ kb Tp T + K_g` with OpenSees' closed-form geometric part `K_g ≈ ∂(Tᵀ)/∂u · pl`
//! ([`CorotTransf::geometric_stiffness`]; a unit test compares it with central differences
//! of `T`: equal up to terms of the order of the element deformation, as in OpenSees).
//!
//! The `delta` field of the element contract is not needed: like OpenSees' `update()`
//! (the bug-fixed version), the increment is computed from the total rotations last seen.
//! Nodes are assumed to have zero displacement when the element is created.

use super::{local_axes, orthonormalize, skew, CrdTransf, DeformedFrame, Mat6, TransformError};
use crate::fe::element::{Mat12, Vec12};
use nalgebra::{Matrix3, Rotation3, SMatrix, SVector, UnitQuaternion, Vector3, Vector6};

type Vec7 = SVector<f64, 7>;
type Mat7x12 = SMatrix<f64, 7, 12>;
type Mat6x7 = SMatrix<f64, 6, 7>;
type Mat12x3 = SMatrix<f64, 12, 3>;

/// The corotational kinematics of one configuration.
#[derive(Debug, Clone, Copy)]
struct Kinematics {
    /// Deformed length (m).
    ln: f64,
    /// Corotated frame `[e1 e2 e3]` (columns).
    e: Matrix3<f64>,
    /// Natural deformations.
    ul: Vec7,
    /// `δul = T δu`.
    t: Mat7x12,
    /// Mean rigid frame `R̄`.
    rbar: Matrix3<f64>,
    /// `L(r2)`, `L(r3)` (12 × 3): variations of the corotated frame.
    lr2: Mat12x3,
    lr3: Mat12x3,
}

/// 3D corotational transformation (OpenSees `geomTransf Corotational`).
#[derive(Debug, Clone)]
pub(crate) struct CorotTransf {
    xi: Vector3<f64>,
    xj: Vector3<f64>,
    r0: Matrix3<f64>,
    l: f64,
    /// `Tp`: basic from natural deformations (6 × 7).
    tp: Mat6x7,
    /// `T` of the undeformed configuration (for the initial stiffness).
    t0: Mat7x12,
    /// Trial total displacements last seen.
    u: Vec12,
    /// Trial nodal triads.
    qi: UnitQuaternion<f64>,
    qj: UnitQuaternion<f64>,
    kin: Kinematics,
    /// Committed state.
    u_c: Vec12,
    qi_c: UnitQuaternion<f64>,
    qj_c: UnitQuaternion<f64>,
    kin_c: Kinematics,
}

impl CorotTransf {
    /// New transformation for an element from `xi` to `xj` (m) with the x-z plane vector `vecxz`.
    pub fn new(
        xi: Vector3<f64>,
        xj: Vector3<f64>,
        vecxz: Vector3<f64>,
    ) -> Result<Self, TransformError> {
        let (r0, l) = local_axes(&xi, &xj, &vecxz)?;
        let mut tp = Mat6x7::zeros();
        tp[(0, 6)] = 1.0;
        tp[(1, 1)] = 1.0;
        tp[(2, 4)] = 1.0;
        tp[(3, 2)] = -1.0;
        tp[(4, 5)] = -1.0;
        tp[(5, 0)] = -1.0;
        tp[(5, 3)] = 1.0;
        let q0 = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(r0));
        let mut s = Self {
            xi,
            xj,
            r0,
            l,
            tp,
            t0: Mat7x12::zeros(),
            u: Vec12::zeros(),
            qi: q0,
            qj: q0,
            kin: Kinematics {
                ln: l,
                e: r0,
                ul: Vec7::zeros(),
                t: Mat7x12::zeros(),
                rbar: r0,
                lr2: Mat12x3::zeros(),
                lr3: Mat12x3::zeros(),
            },
            u_c: Vec12::zeros(),
            qi_c: q0,
            qj_c: q0,
            kin_c: Kinematics {
                ln: l,
                e: r0,
                ul: Vec7::zeros(),
                t: Mat7x12::zeros(),
                rbar: r0,
                lr2: Mat12x3::zeros(),
                lr3: Mat12x3::zeros(),
            },
        };
        let d0 = Vector3::zeros();
        s.kin = s.kinematics(&r0, &r0, &d0)?;
        s.kin_c = s.kin;
        s.t0 = s.kin.t;
        Ok(s)
    }

    /// Kinematics for nodal triads `ri`, `rj` and relative translation `dji = u_j − u_i`.
    fn kinematics(
        &self,
        ri: &Matrix3<f64>,
        rj: &Matrix3<f64>,
        dji: &Vector3<f64>,
    ) -> Result<Kinematics, TransformError> {
        // Mean rotation R̄ = R(γ/2) R_I.
        let rel = rj * ri.transpose();
        let gq = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(rel));
        let gq = gq.quaternion();
        let gamma = 2.0 * gq.imag() / gq.w;
        let w = 0.5 * gamma;
        let sw = skew(&w);
        let rhalf = Matrix3::identity() + (sw + 0.5 * sw * sw) / (1.0 + 0.25 * w.norm_squared());
        let rbar = rhalf * ri;
        let (r1, r2, r3): (Vector3<f64>, Vector3<f64>, Vector3<f64>) = (
            rbar.column(0).into(),
            rbar.column(1).into(),
            rbar.column(2).into(),
        );
        // Corotated frame.
        let xji = self.xj - self.xi;
        let dx = xji + dji;
        let ln = dx.norm();
        if ln.is_nan() || ln <= 0.0 {
            return Err(TransformError::ZeroDeformedLength);
        }
        let e1 = dx / ln;
        let e1r1 = e1 + r1;
        let e2 = r2 - 0.5 * r2.dot(&e1) * e1r1;
        let e3 = r3 - 0.5 * r3.dot(&e1) * e1r1;
        let (ri1, ri2, ri3): (Vector3<f64>, Vector3<f64>, Vector3<f64>) = (
            ri.column(0).into(),
            ri.column(1).into(),
            ri.column(2).into(),
        );
        let (rj1, rj2, rj3): (Vector3<f64>, Vector3<f64>, Vector3<f64>) = (
            rj.column(0).into(),
            rj.column(1).into(),
            rj.column(2).into(),
        );
        let asin = |x: f64| x.clamp(-1.0, 1.0).asin();
        let mut ul = Vec7::zeros();
        ul[0] = asin(0.5 * (ri2.dot(&e3) - ri3.dot(&e2)));
        ul[1] = asin(0.5 * (ri1.dot(&e2) - ri2.dot(&e1)));
        ul[2] = asin(0.5 * (ri1.dot(&e3) - ri3.dot(&e1)));
        ul[3] = asin(0.5 * (rj2.dot(&e3) - rj3.dot(&e2)));
        ul[4] = asin(0.5 * (rj1.dot(&e2) - rj2.dot(&e1)));
        ul[5] = asin(0.5 * (rj1.dot(&e3) - rj3.dot(&e1)));
        ul[6] = 2.0 * (xji + 0.5 * dji).dot(dji) / (ln + self.l);

        // T = ∂ul/∂u (spins for the rotational DOFs), OpenSees CorotCrdTransf3d.
        let a = (Matrix3::identity() - e1 * e1.transpose()) / ln;
        // L(r) (12 × 3): variation of e_k through e1 and R̄.
        let lmat = |r: &Vector3<f64>| -> Mat12x3 {
            let re1 = r.dot(&e1);
            let l1 = a * (0.5 * re1) + 0.5 * a * r * e1r1.transpose();
            let sr = skew(r);
            let l2 = 0.5 * sr - 0.25 * re1 * skew(&r1) - 0.25 * sr * e1 * e1r1.transpose();
            let mut m = Mat12x3::zeros();
            m.fixed_view_mut::<3, 3>(0, 0).copy_from(&l1);
            m.fixed_view_mut::<3, 3>(3, 0).copy_from(&l2);
            m.fixed_view_mut::<3, 3>(6, 0).copy_from(&(-l1));
            m.fixed_view_mut::<3, 3>(9, 0).copy_from(&l2);
            m
        };
        let lr2 = lmat(&r2);
        let lr3 = lmat(&r3);
        let mut t = Mat7x12::zeros();
        // Row of one end: translational part ±A r, rotational part at the end's DOFs.
        let set_row = |t: &mut Mat7x12,
                       row: usize,
                       at: Option<Vector3<f64>>,
                       rot_off: usize,
                       se: Vector3<f64>,
                       lr: SVector<f64, 12>| {
            let mut v = lr;
            if let Some(at) = at {
                for k in 0..3 {
                    v[k] += at[k];
                    v[6 + k] -= at[k];
                }
            }
            for k in 0..3 {
                v[rot_off + k] += se[k];
            }
            t.set_row(row, &v.transpose());
        };
        for (end, (q1, q2, q3)) in [(ri1, ri2, ri3), (rj1, rj2, rj3)].into_iter().enumerate() {
            let off = if end == 0 { 3 } else { 9 };
            let (s1, s2, s3) = (skew(&q1), skew(&q2), skew(&q3));
            let row0 = 3 * end;
            set_row(
                &mut t,
                row0,
                None,
                off,
                -s3 * e2 + s2 * e3,
                lr3 * q2 - lr2 * q3,
            );
            set_row(
                &mut t,
                row0 + 1,
                Some(a * q2),
                off,
                -s2 * e1 + s1 * e2,
                lr2 * q1,
            );
            set_row(
                &mut t,
                row0 + 2,
                Some(a * q3),
                off,
                -s3 * e1 + s1 * e3,
                lr3 * q1,
            );
        }
        for j in 0..6 {
            let c = 2.0 * ul[j].cos();
            for i in 0..12 {
                t[(j, i)] /= c;
            }
        }
        for k in 0..3 {
            t[(6, k)] = -e1[k];
            t[(6, 6 + k)] = e1[k];
        }
        Ok(Kinematics {
            ln,
            e: Matrix3::from_columns(&[e1, e2, e3]),
            ul,
            t,
            rbar,
            lr2,
            lr3,
        })
    }

    fn triads(&self) -> (Matrix3<f64>, Matrix3<f64>) {
        (
            self.qi.to_rotation_matrix().into_inner(),
            self.qj.to_rotation_matrix().into_inner(),
        )
    }

    fn dji(u: &Vec12) -> Vector3<f64> {
        u.fixed_rows::<3>(6) - u.fixed_rows::<3>(0)
    }

    /// Analytic geometric stiffness `∂(Tᵀ pl)/∂u` of OpenSees `CorotCrdTransf3d`
    /// (de Souza 2000, eq. 4.x; the twist moment enters through `m3` at both ends, as
    /// in OpenSees), with `m_k = pl_k / (2 cos ul_k)`.
    fn geometric_stiffness(&self, pl: &Vec7) -> Mat12 {
        let k = &self.kin;
        let (ri, rj) = self.triads();
        let col = |m: &Matrix3<f64>, c: usize| -> Vector3<f64> { m.column(c).into() };
        let (e1, e2, e3) = (col(&k.e, 0), col(&k.e, 1), col(&k.e, 2));
        let (r1, r2, r3) = (col(&k.rbar, 0), col(&k.rbar, 1), col(&k.rbar, 2));
        let (ri1, ri2, ri3) = (col(&ri, 0), col(&ri, 1), col(&ri, 2));
        let (rj1, rj2, rj3) = (col(&rj, 0), col(&rj, 1), col(&rj, 2));
        let ln = k.ln;
        let a = (Matrix3::identity() - e1 * e1.transpose()) / ln;
        let mut m = [0.0; 6];
        for i in 0..6 {
            m[i] = pl[i] / (2.0 * k.ul[i].cos());
        }
        let (se1, se2, se3) = (skew(&e1), skew(&e2), skew(&e3));
        let (si1, si2, si3) = (skew(&ri1), skew(&ri2), skew(&ri3));
        let (sj1, sj2, sj3) = (skew(&rj1), skew(&rj2), skew(&rj3));
        let mut kg = Mat12::zeros();
        let add = |kg: &mut Mat12, r: usize, c: usize, b: &Matrix3<f64>, f: f64| {
            let mut v = kg.fixed_view_mut::<3, 3>(r, c);
            v += b * f;
        };
        // Axial force on the chord direction.
        for (r, c, f) in [(0, 0, 1.0), (0, 6, -1.0), (6, 0, -1.0), (6, 6, 1.0)] {
            add(&mut kg, r, c, &a, f * pl[6]);
        }
        // Coupling of the frame variation with the nodal spins.
        let kbar_i = -(k.lr2 * (si3 * m[3] + si1 * m[1])) + k.lr3 * (si2 * m[3] - si1 * m[2]);
        let kbar_j = k.lr2 * (sj3 * m[3] - sj1 * m[4]) - k.lr3 * (sj2 * m[3] + sj1 * m[5]);
        for (kbar, c) in [(kbar_i, 3usize), (kbar_j, 9usize)] {
            let mut v = kg.fixed_view_mut::<12, 3>(0, c);
            v += kbar;
            let mut h = kg.fixed_view_mut::<3, 12>(c, 0);
            h += kbar.transpose();
        }
        let ks_i = (se2 * si3 - se3 * si2) * m[3]
            + (se2 * si1 - se1 * si2) * m[1]
            + (se3 * si1 - se1 * si3) * m[2];
        add(&mut kg, 3, 3, &ks_i, 1.0);
        let ks_j = (-se2 * sj3 + se3 * sj2) * m[3]
            + (se2 * sj1 - se1 * sj2) * m[4]
            + (se3 * sj1 - se1 * sj3) * m[5];
        add(&mut kg, 9, 9, &ks_j, 1.0);
        // Variation of the chord direction.
        let v = (ri2 * m[1] + ri3 * m[2] + rj2 * m[4] + rj3 * m[5]) / ln;
        let ks = a * e1.dot(&v) + a * v * e1.transpose() + e1 * v.transpose() * a;
        for (r, c, f) in [(0, 0, 1.0), (0, 6, -1.0), (6, 0, -1.0), (6, 6, 1.0)] {
            add(&mut kg, r, c, &ks, f);
        }
        let ks_ti = -(a * si2) * m[1] - (a * si3) * m[2];
        let ks_tj = -(a * sj2) * m[4] - (a * sj3) * m[5];
        for (ks, c) in [(ks_ti, 3usize), (ks_tj, 9usize)] {
            add(&mut kg, 0, c, &ks, 1.0);
            add(&mut kg, 6, c, &ks, -1.0);
            let kt = ks.transpose();
            add(&mut kg, c, 0, &kt, 1.0);
            add(&mut kg, c, 6, &kt, -1.0);
        }
        kg += self.ks2(&r2, &(ri3 - rj3), &e1, &r1, &a, ln) * m[3];
        kg += self.ks2(&r3, &(rj2 - ri2), &e1, &r1, &a, ln) * m[3];
        kg += self.ks2(&r2, &ri1, &e1, &r1, &a, ln) * m[1];
        kg += self.ks2(&r3, &ri1, &e1, &r1, &a, ln) * m[2];
        kg += self.ks2(&r2, &rj1, &e1, &r1, &a, ln) * m[4];
        kg += self.ks2(&r3, &rj1, &e1, &r1, &a, ln) * m[5];
        // Variation of the 1/(2 cos ul) factors.
        for i in 0..6 {
            let f = pl[i] * k.ul[i].tan();
            let row = k.t.row(i);
            kg += row.transpose() * row * f;
        }
        kg
    }

    /// OpenSees' `getKs2Matrix(r_i, z)`: second variation of `z · e_k` terms.
    fn ks2(
        &self,
        ri: &Vector3<f64>,
        z: &Vector3<f64>,
        e1: &Vector3<f64>,
        r1: &Vector3<f64>,
        a: &Matrix3<f64>,
        ln: f64,
    ) -> Mat12 {
        let rite1 = ri.dot(e1);
        let zte1 = z.dot(e1);
        let ztr1 = z.dot(r1);
        let s = zte1 + ztr1;
        let u = -0.5 * a * z * ri.transpose() * a
            + a * z * e1.transpose() * (rite1 / (2.0 * ln))
            + a * ri * e1.transpose() * (s / (2.0 * ln));
        let ks = u + u.transpose() + a * (rite1 * (2.0 * zte1 + ztr1) / (2.0 * ln));
        let mut out = Mat12::zeros();
        let add = |o: &mut Mat12, r: usize, c: usize, b: &Matrix3<f64>, f: f64| {
            let mut v = o.fixed_view_mut::<3, 3>(r, c);
            v += b * f;
        };
        for (r, c, f) in [(0, 0, 1.0), (0, 6, -1.0), (6, 0, -1.0), (6, 6, 1.0)] {
            add(&mut out, r, c, &ks, f);
        }
        let (sri, sr1, sz, se1) = (skew(ri), skew(r1), skew(z), skew(e1));
        let ks = -0.25 * a * z * e1.transpose() * sri
            - 0.25 * a * ri * z.transpose() * sr1
            - 0.25 * s * a * sri;
        for (r, c, f) in [(0, 3, 1.0), (0, 9, 1.0), (6, 3, -1.0), (6, 9, -1.0)] {
            add(&mut out, r, c, &ks, f);
            add(&mut out, c, r, &ks.transpose(), f);
        }
        let ks = -0.125 * rite1 * sz * sr1
            + 0.125 * sr1 * z * e1.transpose() * sri
            + 0.125 * sri * e1 * z.transpose() * sr1
            - 0.125 * s * se1 * sri
            + 0.25 * sz * sri;
        for (r, c) in [(3, 3), (3, 9), (9, 3), (9, 9)] {
            add(&mut out, r, c, &ks, 1.0);
        }
        out
    }

    /// `∂(Tᵀ pl)/∂u` by central differences of `T` (spins for rotations); a check of
    /// [`Self::geometric_stiffness`].
    #[cfg(test)]
    fn geometric_stiffness_numeric(&self, pl: &Vec7) -> Mat12 {
        let (ri, rj) = self.triads();
        let d = Self::dji(&self.u);
        let mut kg = Mat12::zeros();
        for j in 0..12 {
            let (block, k) = (j / 3, j % 3);
            let h = if block % 2 == 0 { 1e-6 * self.l } else { 1e-6 };
            let mut cols = [Vec12::zeros(); 2];
            for (s, sign) in [1.0, -1.0].into_iter().enumerate() {
                let mut ri_p = ri;
                let mut rj_p = rj;
                let mut d_p = d;
                let mut unit = Vector3::zeros();
                unit[k] = sign * h;
                match block {
                    0 => d_p -= unit,
                    1 => ri_p = super::rotation_from_vector(&unit) * ri,
                    2 => d_p += unit,
                    _ => rj_p = super::rotation_from_vector(&unit) * rj,
                }
                // A failure here would need a zero-length perturbed chord; keep the
                // current T then (the derivative column is then zero).
                let t = match self.kinematics(&ri_p, &rj_p, &d_p) {
                    Ok(kin) => kin.t,
                    Err(_) => self.kin.t,
                };
                cols[s] = t.transpose() * pl;
            }
            kg.set_column(j, &((cols[0] - cols[1]) / (2.0 * h)));
        }
        kg
    }
}

impl CrdTransf for CorotTransf {
    fn update(&mut self, total: &Vec12) -> Result<(), TransformError> {
        if total.iter().any(|x| !x.is_finite()) {
            return Err(TransformError::NonFinite);
        }
        let dai: Vector3<f64> = total.fixed_rows::<3>(3) - self.u.fixed_rows::<3>(3);
        let daj: Vector3<f64> = total.fixed_rows::<3>(9) - self.u.fixed_rows::<3>(9);
        let qi = UnitQuaternion::from_scaled_axis(dai) * self.qi;
        let qj = UnitQuaternion::from_scaled_axis(daj) * self.qj;
        let ri = qi.to_rotation_matrix().into_inner();
        let rj = qj.to_rotation_matrix().into_inner();
        let kin = self.kinematics(&ri, &rj, &Self::dji(total))?;
        self.u = *total;
        self.qi = qi;
        self.qj = qj;
        self.kin = kin;
        Ok(())
    }
    fn initial_length(&self) -> f64 {
        self.l
    }
    fn basic_deformations(&self) -> Vector6<f64> {
        self.tp * self.kin.ul
    }
    fn global_resisting_force(&self, q: &Vector6<f64>) -> Vec12 {
        self.kin.t.transpose() * (self.tp.transpose() * q)
    }
    fn global_stiffness(&self, kb: &Mat6, q: &Vector6<f64>) -> Mat12 {
        let tb = self.tp * self.kin.t;
        let pl = self.tp.transpose() * q;
        tb.transpose() * kb * tb + self.geometric_stiffness(&pl)
    }
    fn initial_global_stiffness(&self, kb0: &Mat6) -> Mat12 {
        let tb = self.tp * self.t0;
        tb.transpose() * kb0 * tb
    }
    fn trial_initial_global_stiffness(&self, kb0: &Mat6) -> Option<Mat12> {
        let tb = self.tp * self.kin.t;
        Some(tb.transpose() * kb0 * tb)
    }
    fn has_trial_initial_global_stiffness(&self) -> bool {
        true
    }
    fn commit(&mut self) {
        self.u_c = self.u;
        self.qi_c = self.qi;
        self.qj_c = self.qj;
        self.kin_c = self.kin;
    }
    fn revert(&mut self) {
        self.u = self.u_c;
        self.qi = self.qi_c;
        self.qj = self.qj_c;
        self.kin = self.kin_c;
    }
    fn deformed_frame(&self) -> DeformedFrame {
        DeformedFrame {
            node_i: self.xi + self.u.fixed_rows::<3>(0),
            node_j: self.xj + self.u.fixed_rows::<3>(6),
            axes: orthonormalize(&self.kin.e),
        }
    }
    fn initial_axes(&self) -> Matrix3<f64> {
        self.r0
    }
    fn boxed_clone(&self) -> Box<dyn CrdTransf> {
        Box::new(self.clone())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Large common rotation of both ends plus relative deformation scaled by `f`.
    fn sample_scaled(f: f64) -> (CorotTransf, Vec12) {
        let mut t = CorotTransf::new(
            Vector3::new(0.1, -0.2, 0.3),
            Vector3::new(1.3, 0.4, 0.9),
            Vector3::new(0.0, 0.0, 1.0),
        )
        .unwrap();
        let u = Vec12::from_column_slice(&[
            0.01, -0.02, 0.03, 0.10, -0.05, 0.20, -0.04, 0.05, 0.02, -0.15, 0.12, 0.07,
        ]) * f;
        let common = Vector3::new(0.4, -0.3, 0.5);
        let mut u = u;
        for b in [3, 9] {
            let r: Vector3<f64> = u.fixed_rows::<3>(b) + common;
            u.fixed_rows_mut::<3>(b).copy_from(&r);
        }
        t.update(&u).unwrap();
        (t, u)
    }

    /// `T` is the derivative of `ul` for the translational DOFs; for the spins it is
    /// OpenSees' (Crisfield's) approximation, in which the mean frame R̄ follows the
    /// average of the two end spins, so its error grows linearly with the relative
    /// rotation of the ends (and vanishes with it).
    #[test]
    fn t_matrix_is_derivative_of_natural_deformations() {
        let mut errs = vec![];
        for f in [1.0, 0.1, 0.01] {
            let (t, _) = sample_scaled(f);
            let (trans, rot) = t_error(&t);
            println!("scale {f}: max |T - dul/du| translations {trans:e}, spins {rot:e}");
            assert!(trans < 1e-7, "translational columns of T: {trans:e}");
            errs.push(rot);
        }
        assert!(errs[2] < 5e-4 && errs[1] < 5e-3, "{errs:?}");
        assert!(
            (errs[1] / errs[2] - 10.0).abs() < 1.0,
            "first order: {errs:?}"
        );
    }

    /// Largest difference between `T` and the central-difference derivative of `ul`,
    /// over translational and over rotational columns.
    fn t_error(t: &CorotTransf) -> (f64, f64) {
        let mut err = [0.0f64; 2];
        let (ri, rj) = t.triads();
        let d = CorotTransf::dji(&t.u);
        let h = 1e-6;
        for j in 0..12 {
            let (block, k) = (j / 3, j % 3);
            let mut ul = [Vec7::zeros(); 2];
            for (s, sign) in [1.0, -1.0].into_iter().enumerate() {
                let mut unit = Vector3::zeros();
                unit[k] = sign * h;
                let (mut ri_p, mut rj_p, mut d_p) = (ri, rj, d);
                match block {
                    0 => d_p -= unit,
                    1 => ri_p = super::super::rotation_from_vector(&unit) * ri,
                    2 => d_p += unit,
                    _ => rj_p = super::super::rotation_from_vector(&unit) * rj,
                }
                ul[s] = t.kinematics(&ri_p, &rj_p, &d_p).unwrap().ul;
            }
            let fd = (ul[0] - ul[1]) / (2.0 * h);
            for r in 0..7 {
                let e = (fd[r] - t.kin.t[(r, j)]).abs();
                err[block % 2] = err[block % 2].max(e);
            }
        }
        (err[0], err[1])
    }

    /// The analytic geometric stiffness equals the derivative of `Tᵀ pl` up to terms of
    /// the order of the deformation (OpenSees' approximation).
    #[test]
    fn analytic_geometric_stiffness_matches_finite_differences() {
        for f in [1.0, 0.01] {
            let (t, _) = sample_scaled(f);
            let pl = Vec7::from_column_slice(&[-3.0, 5.0, -2.0, 3.0, 4.0, 1.5, 1000.0]);
            let ka = t.geometric_stiffness(&pl);
            let kn = t.geometric_stiffness_numeric(&pl);
            let err = (ka - kn).abs().max() / kn.abs().max();
            println!("scale {f}: max |Kg analytic − Kg numeric| / max |Kg| = {err:e}");
            // OpenSees' closed form treats the twist moments of both ends through m3,
            // so it is exact only to first order in the deformation.
            assert!(err < 1e-3 * f.max(0.02), "{err}");
        }
    }

    /// Rigid-body motion gives zero basic deformations.
    #[test]
    fn rigid_body_motion_is_strain_free() {
        let xi = Vector3::new(0.0, 0.0, 0.0);
        let xj = Vector3::new(2.0, 0.0, 0.0);
        let mut t = CorotTransf::new(xi, xj, Vector3::new(0.0, 0.0, 1.0)).unwrap();
        // Large rigid rotation about (1,1,1), applied in 10 increments, plus a translation.
        let axis = Vector3::new(1.0, 1.0, 1.0).normalize() * 1.3;
        let rot = rotation_from(axis);
        let c = Vector3::new(0.3, -0.1, 0.2);
        let ui = c;
        let uj = rot * (xj - xi) + xi + c - xj;
        for s in 1..=10 {
            let f = s as f64 / 10.0;
            let mut u = Vec12::zeros();
            u.fixed_rows_mut::<3>(0).copy_from(&(ui * f));
            u.fixed_rows_mut::<3>(6).copy_from(&(uj * f));
            u.fixed_rows_mut::<3>(3).copy_from(&(axis * f));
            u.fixed_rows_mut::<3>(9).copy_from(&(axis * f));
            t.update(&u).unwrap();
        }
        // Intermediate translations are not on the rigid path, but the final state is.
        let v = t.basic_deformations();
        assert!(v.norm() < 1e-12, "{v}");
    }

    fn rotation_from(v: Vector3<f64>) -> Matrix3<f64> {
        super::super::rotation_from_vector(&v)
    }
}

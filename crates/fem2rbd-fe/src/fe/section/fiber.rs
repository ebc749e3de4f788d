//! Fiber section (OpenSees `FiberSection3d` with an elastic torsion `-GJ`).
//!
//! Each fiber has local coordinates `(y, z)` (m), an area `A` (m²) and its own uniaxial
//! material. With section deformations `e = [ε0, κz, κy, ϑ]`:
//!
//! - fiber strain `ε = ε0 − y κz + z κy`, i.e. `ε = aᵀ e` with `a = [1, −y, z]`;
//! - resultants `[N, Mz, My] = Σ σ A a`, `T = GJ ϑ`;
//! - tangent `k = Σ E_t A a aᵀ` (3 × 3), `k_TT = GJ`.
//!
//! Like OpenSees 3.7 `FiberSection3d` (default; `-noCentroid` turns it off), the fiber
//! coordinates are measured from the section's area centroid
//! `(ȳ, z̄) = (Σ A y / Σ A, Σ A z / Σ A)` — geometric area, not modulus-weighted. For
//! doubly symmetric sections this changes nothing.

use super::{Section, SectionDamage};
use crate::fe::material::UniaxialMaterial;
use nalgebra::{Matrix3, Matrix4, Vector3, Vector4};

/// One fiber: position in local section axes, area, material state.
#[derive(Debug)]
pub struct Fiber {
    /// Local y coordinate (m).
    pub y: f64,
    /// Local z coordinate (m).
    pub z: f64,
    /// Area (m²).
    pub area: f64,
    /// The fiber's own material (state).
    pub material: Box<dyn UniaxialMaterial>,
}

impl Clone for Fiber {
    fn clone(&self) -> Self {
        Self {
            y: self.y,
            z: self.z,
            area: self.area,
            material: self.material.boxed_clone(),
        }
    }
}

/// Running fibre sums of a section: `s = Σ (σ A) a`, `k = Σ ((E_t A) a) aᵀ` with
/// `a = [1, −y, z]`, each product formed as nalgebra forms `(σ A) a` and `((E_t A) a) aᵀ`
/// (so the sums are the same bits as the matrix expressions they replace).
#[derive(Default)]
struct Accumulator {
    s: [f64; 3],
    k: [[f64; 3]; 3],
}

impl Accumulator {
    #[inline(always)]
    fn add(&mut self, f: &Fiber, sig: f64, et: f64) {
        let a = [1.0, -f.y, f.z];
        let sa = sig * f.area;
        let ca = et * f.area;
        for i in 0..3 {
            self.s[i] += a[i] * sa;
            let cai = a[i] * ca;
            for j in 0..3 {
                self.k[i][j] += cai * a[j];
            }
        }
    }
}

/// Errors in section data.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SectionError {
    /// No fibers given.
    #[error("fiber section has no fibers")]
    Empty,
    /// A fiber with a non-positive or non-finite area, or non-finite coordinates.
    #[error("fiber {index}: invalid (y, z, area) = ({y}, {z}, {area})")]
    BadFiber {
        /// Index of the fiber in the input list.
        index: usize,
        /// Its y (m).
        y: f64,
        /// Its z (m).
        z: f64,
        /// Its area (m²).
        area: f64,
    },
    /// Non-positive or non-finite torsional rigidity.
    #[error("torsional rigidity GJ = {0} must be positive and finite")]
    BadGj(f64),
}

/// Fiber section with elastic torsion.
#[derive(Debug, Clone)]
pub struct FiberSection {
    /// Fibers with coordinates relative to the centroid.
    fibers: Vec<Fiber>,
    /// Area centroid `(ȳ, z̄)` of the input coordinates (m), or zero with `-noCentroid`.
    centroid: (f64, f64),
    gj: f64,
    e: Vector4<f64>,
    e_c: Vector4<f64>,
    s: Vector4<f64>,
    k: Matrix4<f64>,
    k0: Matrix4<f64>,
}

impl FiberSection {
    /// A fiber section from `(y, z, area, material)` fibers and the torsional rigidity
    /// `gj` (N·m²), coordinates measured from the area centroid (OpenSees' default).
    /// Each fiber gets its own material; the materials must be in their virgin state.
    pub fn new(
        fibers: Vec<(f64, f64, f64, Box<dyn UniaxialMaterial>)>,
        gj: f64,
    ) -> Result<Self, SectionError> {
        Self::with_centroid_option(fibers, gj, true)
    }

    /// As [`new`](Self::new); `compute_centroid = false` is OpenSees' `-noCentroid`
    /// (coordinates taken as given).
    pub fn with_centroid_option(
        fibers: Vec<(f64, f64, f64, Box<dyn UniaxialMaterial>)>,
        gj: f64,
        compute_centroid: bool,
    ) -> Result<Self, SectionError> {
        if fibers.is_empty() {
            return Err(SectionError::Empty);
        }
        if !(gj > 0.0 && gj.is_finite()) {
            return Err(SectionError::BadGj(gj));
        }
        let mut out = Vec::with_capacity(fibers.len());
        for (index, (y, z, area, material)) in fibers.into_iter().enumerate() {
            if !(area > 0.0 && area.is_finite() && y.is_finite() && z.is_finite()) {
                return Err(SectionError::BadFiber { index, y, z, area });
            }
            out.push(Fiber {
                y,
                z,
                area,
                material,
            });
        }
        let mut centroid = (0.0, 0.0);
        if compute_centroid {
            let a: f64 = out.iter().map(|f| f.area).sum();
            centroid = (
                out.iter().map(|f| f.y * f.area).sum::<f64>() / a,
                out.iter().map(|f| f.z * f.area).sum::<f64>() / a,
            );
            for f in &mut out {
                f.y -= centroid.0;
                f.z -= centroid.1;
            }
        }
        let mut s = Self {
            fibers: out,
            centroid,
            gj,
            e: Vector4::zeros(),
            e_c: Vector4::zeros(),
            s: Vector4::zeros(),
            k: Matrix4::zeros(),
            k0: Matrix4::zeros(),
        };
        s.k0 = s.integrate_initial();
        s.set_trial_deformation(&Vector4::zeros());
        Ok(s)
    }

    /// Area centroid `(ȳ, z̄)` of the input fiber coordinates (m); zero with `-noCentroid`.
    pub fn centroid(&self) -> (f64, f64) {
        self.centroid
    }

    /// The fibers (read-only; coordinates relative to the centroid).
    pub fn fibers(&self) -> &[Fiber] {
        &self.fibers
    }

    /// Torsional rigidity GJ (N·m²).
    pub fn gj(&self) -> f64 {
        self.gj
    }

    fn integrate_initial(&self) -> Matrix4<f64> {
        let mut k3 = Matrix3::zeros();
        for f in &self.fibers {
            let a = Vector3::new(1.0, -f.y, f.z);
            k3 += (f.material.initial_tangent() * f.area) * a * a.transpose();
        }
        let mut k = Matrix4::zeros();
        k.fixed_view_mut::<3, 3>(0, 0).copy_from(&k3);
        k[(3, 3)] = self.gj;
        k
    }

    /// Resultants and tangent from the materials' current (trial) stresses and moduli.
    fn integrate(&mut self) {
        let mut acc = Accumulator::default();
        for f in &self.fibers {
            acc.add(f, f.material.stress(), f.material.tangent());
        }
        self.store(&acc);
    }

    /// `s` and `k` from the fibre sums and the elastic torsion.
    fn store(&mut self, acc: &Accumulator) {
        let (s3, k3) = (&acc.s, &acc.k);
        self.s = Vector4::new(s3[0], s3[1], s3[2], self.gj * self.e[3]);
        self.k = Matrix4::new(
            k3[0][0], k3[0][1], k3[0][2], 0.0, //
            k3[1][0], k3[1][1], k3[1][2], 0.0, //
            k3[2][0], k3[2][1], k3[2][2], 0.0, //
            0.0, 0.0, 0.0, self.gj,
        );
    }

    fn fiber_strain(e: &Vector4<f64>, f: &Fiber) -> f64 {
        e[0] - f.y * e[1] + f.z * e[2]
    }

    /// Trial strain of every fiber, in input order.
    pub fn fiber_strains(&self) -> Vec<f64> {
        self.fibers.iter().map(|f| f.material.strain()).collect()
    }

    /// Trial stress of every fiber (Pa), in input order.
    pub fn fiber_stresses(&self) -> Vec<f64> {
        self.fibers.iter().map(|f| f.material.stress()).collect()
    }
}

impl Section for FiberSection {
    fn set_trial_deformation(&mut self, e: &Vector4<f64>) {
        self.e = *e;
        // One pass: strain, material, sums (the sums in fibre order, as `integrate`).
        let mut acc = Accumulator::default();
        for f in &mut self.fibers {
            let eps = Self::fiber_strain(e, f);
            let (sig, et) = f.material.set_trial_strain_response(eps);
            acc.add(f, sig, et);
        }
        self.store(&acc);
    }
    fn deformation(&self) -> Vector4<f64> {
        self.e
    }
    fn resultant(&self) -> Vector4<f64> {
        self.s
    }
    fn tangent(&self) -> Matrix4<f64> {
        self.k
    }
    fn initial_tangent(&self) -> Matrix4<f64> {
        self.k0
    }
    fn commit_state(&mut self) {
        for f in &mut self.fibers {
            f.material.commit_state();
        }
        self.e_c = self.e;
    }
    fn revert_to_last_commit(&mut self) {
        for f in &mut self.fibers {
            f.material.revert_to_last_commit();
        }
        self.e = self.e_c;
        self.integrate();
    }
    fn revert_to_start(&mut self) {
        for f in &mut self.fibers {
            f.material.revert_to_start();
        }
        self.e_c = Vector4::zeros();
        self.set_trial_deformation(&Vector4::zeros());
    }
    fn damage(&self) -> SectionDamage {
        let mut d = SectionDamage {
            min_strain: f64::INFINITY,
            max_strain: f64::NEG_INFINITY,
            ..Default::default()
        };
        for f in &self.fibers {
            let m = f.material.damage();
            d.yielded |= m.yielded;
            d.ruptured |= m.ruptured;
            let eps = f.material.strain();
            d.min_strain = d.min_strain.min(eps);
            d.max_strain = d.max_strain.max(eps);
        }
        d
    }
    fn boxed_clone(&self) -> Box<dyn Section> {
        Box::new(self.clone())
    }
}

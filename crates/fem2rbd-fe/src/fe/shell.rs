//! Four-node layered shell: the linear (small-displacement) stiffness of OpenSees'
//! `ASDShellQ4` (Petracca & Camata; OpenSees 3.7.1 `SRC/element/shell/ASDShellQ4.cpp`) on
//! a `LayeredShell` section (Huang & Lu), reproduced term by term so that the element
//! matrix equals OpenSees' to round-off.
//!
//! **Status:** [`element::ShellElement`] is the element of the FE domain (gravity, modal,
//! pushover, transient), with the nonlinear layer laws of [`layers`], in small
//! displacements or with OpenSees' corotational kinematics (`-corotational`, large
//! rotations: `corotational.rs`, Felippa–Haugen EICR with a polar-decomposition frame);
//! [`asd_shell_q4_stiffness`] is its linear stiffness on its own.
//!
//! Formulation (all in the element's local frame, 2 × 2 Gauss points, 24 DOFs
//! `[u v w θx θy θz]` per node):
//! - local frame: origin at the centroid of the four nodes, e3 ∥ d13 × d24, e1 = the edge
//!   1 → 2 projected on the plane, e2 = e3 × e1; nodes off the plane (warped) enter by the
//!   warpage matrix W (rigid offsets by Z1);
//! - membrane: bilinear field with the AGQI enhancement (Chen, Cheng, Li, Sze: area-
//!   coordinate gradients for the nodal DOFs, 4 incompatible internal DOFs with their mean
//!   removed so the strict patch test passes, condensed statically:
//!   K = K_uu − K_uq K_qq⁻¹ K_qu); OpenSees' code uses the area-coordinate gradients for
//!   the bending curvatures as well, and so do we;
//! - plate: curvatures from the same gradients, transverse shear by MITC4 (Dvorkin &
//!   Bathe) with OpenSees' tying-point interpolation and distortion transformation;
//! - drilling: Hughes–Brezzi penalty k_d = 0.233 · D₃₃ (the initial in-plane shear
//!   stiffness of the section, N/m), on B_d = √s · B_d(ξ, η) + √(1 − s) · B_d(0, 0) with
//!   s = 0.01 (OpenSees' default `-drillingStab`);
//! - section orientation: the generalized strains are rotated into the section axes by the
//!   angle between the element's e1 and the user's local x (`-local`), D_el = R_s D R_sᵀ;
//! - OpenSees' sections return moments with the sign of ε = e − zκ; the element flips the
//!   θx/θy columns of the bending rows of Bᵀ (B1) to compensate: K = ∫ B1ᵀ D B dA.
//!
//! Layered section (OpenSees `LayeredShellFiberSection`): layer i at its mid-thickness
//! zᵢ (bottom face at −h/2) with weight tᵢ; for a 5 × 5 layer tangent d
//! ([σ11 σ22 σ12 σ23 σ31] on the same strains) the 8 × 8 section tangent on
//! [ε11 ε22 γ12 κ11 κ22 κ12 γ23 γ31] is Σ tᵢ [[d_mm, −z d_mm, d_ms], [z d_mm, −z² d_mm,
//! z d_ms], [d_sm, −z d_sm, d_ss]] (no shear correction factor).

use std::collections::BTreeMap;

pub(crate) mod corotational;
pub mod element;
pub mod layers;

use nalgebra::{Matrix2, Matrix3, SMatrix, SVector, Vector3};

use crate::model::{Material, ShellLayer};

/// 8 × 8 section tangent on `[ε11 ε22 γ12 κ11 κ22 κ12 γ23 γ31]`.
pub(crate) type Mat8 = SMatrix<f64, 8, 8>;
/// 5 × 5 layer (plate-fibre) tangent on `[ε11 ε22 γ12 γ23 γ31]`.
pub(crate) type Mat5 = SMatrix<f64, 5, 5>;
/// 24 × 24 element matrix, DOFs `[ux uy uz rx ry rz]` per node, nodes 1..4.
pub type Mat24 = SMatrix<f64, 24, 24>;
pub(crate) type Mat8x24 = SMatrix<f64, 8, 24>;
pub(crate) type Mat8x4 = SMatrix<f64, 8, 4>;
pub(crate) type Vec24 = SVector<f64, 24>;

/// Failure to build a shell's stiffness.
#[derive(Debug, Clone, thiserror::Error, PartialEq)]
pub enum ShellError {
    /// Degenerate geometry, bad local axis, unknown material, singular condensation.
    #[error("shell: {0}")]
    Invalid(String),
}

/// Initial (elastic) tangent of a plate fibre: plane stress with E, ν and transverse
/// shear G = E/(2(1+ν)) (OpenSees `PlateFiber` of `ElasticIsotropic`, and
/// `PlateFromPlaneStress` with G given so).
pub(crate) fn isotropic_plate_fiber(e: f64, nu: f64) -> Mat5 {
    let c = e / (1.0 - nu * nu);
    let g = e / (2.0 * (1.0 + nu));
    let mut d = Mat5::zeros();
    d[(0, 0)] = c;
    d[(1, 1)] = c;
    d[(0, 1)] = c * nu;
    d[(1, 0)] = c * nu;
    d[(2, 2)] = g;
    d[(3, 3)] = g;
    d[(4, 4)] = g;
    d
}

/// Tangent of a smeared bar layer along `angle` degrees from local x with uniaxial
/// tangent `et` (OpenSees `PlateRebarMaterial::getTangent`, including its exact 0° and
/// 90° cases): ε = c² ε11 + s² ε22 + c s γ12.
pub(crate) fn rebar_plate_fiber(et: f64, angle: f64) -> Mat5 {
    let mut d = Mat5::zeros();
    if angle == 0.0 {
        d[(0, 0)] = et;
    } else if angle == 90.0 {
        d[(1, 1)] = et;
    } else {
        let r = angle * 4.0 * 1f64.asin() / 360.0;
        let (c, s) = (r.cos(), r.sin());
        d[(0, 0)] = et * c * c * c * c;
        d[(0, 1)] = et * c * c * s * s;
        d[(0, 2)] = et * c * c * c * s;
        d[(1, 0)] = d[(0, 1)];
        d[(1, 1)] = et * s * s * s * s;
        d[(1, 2)] = et * c * s * s * s;
        d[(2, 0)] = d[(0, 2)];
        d[(2, 1)] = d[(1, 2)];
        d[(2, 2)] = d[(0, 1)];
    }
    d
}

/// Initial tangents of a model's layers, `(thickness, d)` bottom to top.
pub fn initial_layer_tangents(
    layers: &[ShellLayer],
    materials: &BTreeMap<u32, &Material>,
) -> Result<Vec<(f64, Mat5)>, ShellError> {
    layers
        .iter()
        .map(|l| {
            Ok(match l {
                ShellLayer::Elastic { thickness, e, nu }
                | ShellLayer::Concrete {
                    thickness, e, nu, ..
                } => (*thickness, isotropic_plate_fiber(*e, *nu)),
                ShellLayer::Rebar {
                    thickness,
                    material,
                    angle,
                } => {
                    let m = materials.get(material).ok_or_else(|| {
                        ShellError::Invalid(format!("unknown rebar material {material}"))
                    })?;
                    (*thickness, rebar_plate_fiber(m.initial_tangent(), *angle))
                }
            })
        })
        .collect()
}

/// Section tangent of a layered section from its layer tangents (see module docs).
pub fn layered_section_tangent(layers: &[(f64, Mat5)]) -> Mat8 {
    let h: f64 = layers.iter().map(|l| l.0).sum();
    let mut t = Mat8::zeros();
    let mut cur = 0.0;
    for (thk, dd) in layers {
        // OpenSees: sg = (2·(cumulative thickness to the mid-plane))/h − 1, z = h/2 · sg.
        cur += thk;
        let sg = cur / h - 1.0;
        cur += thk;
        let z = 0.5 * h * sg;
        let w = *thk;
        let d = dd * w;
        for i in 0..3 {
            for j in 0..3 {
                t[(i, j)] += d[(i, j)];
                t[(i, 3 + j)] += -z * d[(i, j)];
                t[(3 + i, j)] += z * d[(i, j)];
                t[(3 + i, 3 + j)] += -z * z * d[(i, j)];
            }
            for j in 0..2 {
                t[(i, 6 + j)] += d[(i, 3 + j)];
                t[(3 + i, 6 + j)] += z * d[(i, 3 + j)];
                t[(6 + j, i)] += d[(3 + j, i)];
                t[(6 + j, 3 + i)] += -z * d[(3 + j, i)];
            }
        }
        for i in 0..2 {
            for j in 0..2 {
                t[(6 + i, 6 + j)] += d[(3 + i, 3 + j)];
            }
        }
    }
    t
}

/// The element's local frame (OpenSees `ASDShellQ4LocalCoordinateSystem`).
struct LocalFrame {
    /// Rows e1, e2, e3.
    r: Matrix3<f64>,
    /// Local coordinates of the nodes.
    p: [Vector3<f64>; 4],
}

impl LocalFrame {
    fn new(g: &[Vector3<f64>; 4]) -> Result<Self, ShellError> {
        let center = (g[0] + g[1] + g[2] + g[3]) * 0.25;
        let e3 = (g[2] - g[0]).cross(&(g[3] - g[1]));
        let n3 = e3.norm();
        if !(n3 > 0.0 && n3.is_finite()) {
            return Err(ShellError::Invalid("zero area".into()));
        }
        let e3 = e3 / n3;
        let mut e1 = g[1] - g[0];
        e1 -= e3 * e1.dot(&e3);
        let e1 = e1.normalize();
        let e2 = e3.cross(&e1).normalize();
        let r = Matrix3::from_rows(&[e1.transpose(), e2.transpose(), e3.transpose()]);
        let p = [0, 1, 2, 3].map(|i| r * (g[i] - center));
        Ok(Self { r, p })
    }
    fn x(&self, i: usize) -> f64 {
        self.p[i][0]
    }
    fn y(&self, i: usize) -> f64 {
        self.p[i][1]
    }
}

const GLOC: f64 = 0.577350269189626;
const XI: [f64; 4] = [-GLOC, GLOC, GLOC, -GLOC];
const ETA: [f64; 4] = [-GLOC, -GLOC, GLOC, GLOC];

fn shape(xi: f64, eta: f64) -> [f64; 4] {
    [
        0.25 * (1.0 - xi) * (1.0 - eta),
        0.25 * (1.0 + xi) * (1.0 - eta),
        0.25 * (1.0 + xi) * (1.0 + eta),
        0.25 * (1.0 - xi) * (1.0 + eta),
    ]
}

/// dN/dξ, dN/dη per node.
fn shape_derivs(xi: f64, eta: f64) -> [[f64; 2]; 4] {
    [
        [-(1.0 - eta) * 0.25, -(1.0 - xi) * 0.25],
        [(1.0 - eta) * 0.25, -(1.0 + xi) * 0.25],
        [(1.0 + eta) * 0.25, (1.0 + xi) * 0.25],
        [-(1.0 + eta) * 0.25, (1.0 - xi) * 0.25],
    ]
}

/// Jacobian determinant at (ξ, η) (OpenSees `JacobianOperator`).
fn det_j(lf: &LocalFrame, dn: &[[f64; 2]; 4]) -> f64 {
    let mut j = Matrix2::<f64>::zeros();
    for (i, d) in dn.iter().enumerate() {
        j[(0, 0)] += d[0] * lf.x(i);
        j[(1, 0)] += d[0] * lf.y(i);
        j[(0, 1)] += d[1] * lf.x(i);
        j[(1, 1)] += d[1] * lf.y(i);
    }
    j[(0, 0)] * j[(1, 1)] - j[(1, 0)] * j[(0, 1)]
}

/// AGQI parameters (OpenSees `AGQIParams`).
struct Agqi {
    b: [f64; 4],
    c: [f64; 4],
    a: f64,
    g: [f64; 4],
}

impl Agqi {
    fn new(lf: &LocalFrame) -> Self {
        let (x, y) = ([0, 1, 2, 3].map(|i| lf.x(i)), [0, 1, 2, 3].map(|i| lf.y(i)));
        let mut b = [0.0; 4];
        let mut c = [0.0; 4];
        for i in 0..4 {
            let j = (i + 1) % 4;
            let k = (j + 1) % 4;
            b[i] = y[j] - y[k];
            c[i] = x[k] - x[j];
        }
        let a1 = 0.5
            * (x[1] * y[3] + x[0] * y[1] + x[3] * y[0] - x[1] * y[0] - x[3] * y[1] - x[0] * y[3]);
        let a2 = 0.5
            * (x[1] * y[2] + x[0] * y[1] + x[2] * y[0] - x[1] * y[0] - x[2] * y[1] - x[0] * y[2]);
        let a3 = 0.5
            * (x[2] * y[3] + x[1] * y[2] + x[3] * y[1] - x[2] * y[1] - x[3] * y[2] - x[1] * y[3]);
        let a = a1 + a3;
        let g0 = a1 / a;
        let g1 = a2 / a;
        Self {
            b,
            c,
            a,
            g: [g0, g1, 1.0 - g0, 1.0 - g1],
        }
    }

    /// Area coordinates of (ξ, η) (Eq. 7 of the AGQI paper, as OpenSees).
    fn area_coords(&self, xi: f64, eta: f64) -> [f64; 4] {
        let g = &self.g;
        [
            0.25 * (1.0 - xi) * (g[1] * (1.0 - eta) + g[2] * (1.0 + eta)),
            0.25 * (1.0 - eta) * (g[3] * (1.0 - xi) + g[2] * (1.0 + xi)),
            0.25 * (1.0 + xi) * (g[0] * (1.0 - eta) + g[3] * (1.0 + eta)),
            0.25 * (1.0 + eta) * (g[0] * (1.0 - xi) + g[1] * (1.0 + xi)),
        ]
    }

    /// Area-coordinate shape-function gradients ∂N/∂x, ∂N/∂y of the nodal DOFs.
    fn gradients(&self, xi: f64, eta: f64) -> [[f64; 2]; 4] {
        const NXI: [f64; 4] = [-1.0, 1.0, 1.0, -1.0];
        const NETA: [f64; 4] = [-1.0, -1.0, 1.0, 1.0];
        let l = self.area_coords(xi, eta);
        let g = &self.g;
        let mut out = [[0.0; 2]; 4];
        for i in 0..4 {
            let j = (i + 1) % 4;
            let k = (j + 1) % 4;
            let (mut sx, mut sy) = (0.0, 0.0);
            for ii in 0..4 {
                let jj = (ii + 1) % 4;
                let kk = (jj + 1) % 4;
                let mm = (kk + 1) % 4;
                let f = NXI[ii] * NETA[ii] * (3.0 * (l[jj] - l[mm]) + (g[jj] - g[kk]));
                sx += self.b[ii] * f;
                sy += self.c[ii] * f;
            }
            let den = 1.0 + g[0] * g[2] + g[1] * g[3];
            out[i][0] = (self.b[i] + self.b[j]) / self.a / 2.0
                + NXI[i] * NETA[i] * g[k] * sx / 2.0 / self.a / den;
            out[i][1] = (self.c[i] + self.c[j]) / self.a / 2.0
                + NXI[i] * NETA[i] * g[k] * sy / 2.0 / self.a / den;
        }
        out
    }

    /// Strain matrix of the 4 internal DOFs at (ξ, η), before the mean is removed.
    fn bq(&self, xi: f64, eta: f64) -> Mat8x4 {
        let l = self.area_coords(xi, eta);
        let mut bq = Mat8x4::zeros();
        for i in 0..2 {
            let j = (i + 1) % 4;
            let k = (j + 1) % 4;
            let nqx = (self.b[i] * l[k] + self.b[k] * l[i]) / self.a / 2.0;
            let nqy = (self.c[i] * l[k] + self.c[k] * l[i]) / self.a / 2.0;
            bq[(0, 2 * i)] += nqx;
            bq[(1, 2 * i + 1)] += nqy;
            bq[(2, 2 * i)] += nqy;
            bq[(2, 2 * i + 1)] += nqx;
        }
        bq
    }
}

/// MITC4 data (OpenSees `MITC4Params`).
struct Mitc4 {
    ax: f64,
    ay: f64,
    bx: f64,
    by: f64,
    cx: f64,
    cy: f64,
    transformation: Matrix2<f64>,
    shear_strains: SMatrix<f64, 4, 24>,
}

impl Mitc4 {
    fn new(lf: &LocalFrame) -> Self {
        let (x, y) = ([0, 1, 2, 3].map(|i| lf.x(i)), [0, 1, 2, 3].map(|i| lf.y(i)));
        let (x21, y21) = (x[1] - x[0], y[1] - y[0]);
        let (x34, y34) = (x[2] - x[3], y[2] - y[3]);
        let (x41, y41) = (x[3] - x[0], y[3] - y[0]);
        let (x32, y32) = (x[2] - x[1], y[2] - y[1]);
        let ax = -x[0] + x[1] + x[2] - x[3];
        let bx = x[0] - x[1] + x[2] - x[3];
        let cx = -x[0] - x[1] + x[2] + x[3];
        let ay = -y[0] + y[1] + y[2] - y[3];
        let by = y[0] - y[1] + y[2] - y[3];
        let cy = -y[0] - y[1] + y[2] + y[3];
        let alpha = (ay / ax).atan();
        let beta = std::f64::consts::FRAC_PI_2 - (cx / cy).atan();
        let transformation = Matrix2::new(beta.sin(), -alpha.sin(), -beta.cos(), alpha.cos());
        let mut s = SMatrix::<f64, 4, 24>::zeros();
        let mut set = |r: usize, c: usize, v: f64| s[(r, c)] = v;
        set(0, 2, -0.5);
        set(0, 3, -y41 * 0.25);
        set(0, 4, x41 * 0.25);
        set(0, 20, 0.5);
        set(0, 21, -y41 * 0.25);
        set(0, 22, x41 * 0.25);
        set(1, 2, -0.5);
        set(1, 3, -y21 * 0.25);
        set(1, 4, x21 * 0.25);
        set(1, 8, 0.5);
        set(1, 9, -y21 * 0.25);
        set(1, 10, x21 * 0.25);
        set(2, 8, -0.5);
        set(2, 9, -y32 * 0.25);
        set(2, 10, x32 * 0.25);
        set(2, 14, 0.5);
        set(2, 15, -y32 * 0.25);
        set(2, 16, x32 * 0.25);
        set(3, 14, 0.5);
        set(3, 15, -y34 * 0.25);
        set(3, 16, x34 * 0.25);
        set(3, 20, -0.5);
        set(3, 21, -y34 * 0.25);
        set(3, 22, x34 * 0.25);
        Self {
            ax,
            ay,
            bx,
            by,
            cx,
            cy,
            transformation,
            shear_strains: s,
        }
    }
}

/// Rotation of generalized stresses by `radians` (OpenSees
/// `getRotationMatrixForGeneralizedStresses`).
fn stress_rotation(radians: f64) -> Mat8 {
    let (c, s) = (radians.cos(), radians.sin());
    let mut t = Mat8::zeros();
    for o in [0, 3] {
        t[(o, o)] = c * c;
        t[(o, o + 1)] = s * s;
        t[(o, o + 2)] = -2.0 * s * c;
        t[(o + 1, o)] = s * s;
        t[(o + 1, o + 1)] = c * c;
        t[(o + 1, o + 2)] = 2.0 * s * c;
        t[(o + 2, o)] = s * c;
        t[(o + 2, o + 1)] = -s * c;
        t[(o + 2, o + 2)] = c * c - s * s;
    }
    t[(6, 6)] = c;
    t[(6, 7)] = s;
    t[(7, 6)] = -s;
    t[(7, 7)] = c;
    t
}

/// Drilling stabilisation s of OpenSees' default `ASDShellQ4` (`-drillingStab 0.01`).
pub(crate) const DRILLING_STAB: f64 = 0.01;

/// Element kinematics at one Gauss point (local axes): strain operators and area weight.
#[derive(Debug, Clone)]
pub(crate) struct GaussKinematics {
    /// Generalized strains `[ε11 ε22 γ12 κ11 κ22 κ12 γ23 γ31]` from the 24 local DOFs.
    pub b: Mat8x24,
    /// `b` with the θx/θy columns of the bending rows negated (OpenSees' sections return
    /// moments with the sign of ε = e − zκ): internal forces are ∫ b1ᵀ σ dA.
    pub b1: Mat8x24,
    /// Drilling strain operator (s-weighted point value plus centroid value).
    pub bd: Vec24,
    /// Enhanced (AGQI) strains of the 4 internal DOFs, element mean removed.
    pub bq: Mat8x4,
    /// Jacobian determinant × Gauss weight (m²).
    pub da: f64,
}

/// Precomputed kinematics of an `ASDShellQ4` element in its undeformed configuration:
/// the global → local transformation (with the warpage offsets), the rotation of the
/// generalized stresses into the section axes, and the four Gauss points.
#[derive(Debug, Clone)]
pub(crate) struct ShellKinematics {
    /// Local DOFs = `t` · global DOFs.
    pub t: Mat24,
    /// σ_element = `rs` σ_section, ε_section = `rsᵀ` ε_element (`None` when the section
    /// axes are the element's).
    pub rs: Option<Mat8>,
    /// The 2 × 2 Gauss points.
    pub gauss: [GaussKinematics; 4],
}

impl ShellKinematics {
    /// Kinematics of the quadrilateral `coords` (m, counter-clockwise) with the user's
    /// local x axis `local_x` (`-local`).
    pub fn new(coords: &[[f64; 3]; 4], local_x: [f64; 3]) -> Result<Self, ShellError> {
        let g = coords.map(Vector3::from);
        let lf = LocalFrame::new(&g)?;
        // Section angle: the user's x projected on the plane, signed about e3.
        let e1_local = lf.r.row(0).transpose();
        let e3 = lf.r.row(2).transpose();
        let ux = Vector3::from(local_x);
        let e2u = e3.cross(&ux);
        let n2 = e2u.norm();
        if !(n2 > 0.0 && n2.is_finite()) {
            return Err(ShellError::Invalid(
                "the local x axis is normal to the shell".into(),
            ));
        }
        let e1u = (e2u / n2).cross(&e3).normalize();
        let mut angle = e1u.dot(&e1_local).clamp(-1.0, 1.0).acos();
        if angle != 0.0 && e1u.dot(&lf.r.row(1).transpose()) < 0.0 {
            angle = -angle;
        }
        let rs = (angle != 0.0).then(|| stress_rotation(angle));
        let mitc = Mitc4::new(&lf);
        let agq = Agqi::new(&lf);
        // Mean of the internal strain matrix over the element (strict patch test).
        let mut bq_mean = Mat8x4::zeros();
        let mut atot = 0.0;
        for gp in 0..4 {
            let da = det_j(&lf, &shape_derivs(XI[gp], ETA[gp]));
            atot += da;
            bq_mean += agq.bq(XI[gp], ETA[gp]) * da;
        }
        bq_mean /= atot;
        let drilling_b = |xi: f64, eta: f64| {
            let n = shape(xi, eta);
            let dn = agq.gradients(xi, eta);
            let mut bd = Vec24::zeros();
            for i in 0..4 {
                bd[6 * i] = -0.5 * dn[i][1];
                bd[6 * i + 1] = 0.5 * dn[i][0];
                bd[6 * i + 5] = -n[i];
            }
            bd
        };
        let bd0 = drilling_b(0.0, 0.0);
        let (alpha, beta) = (DRILLING_STAB.sqrt(), (1.0 - DRILLING_STAB).sqrt());
        let gauss = [0, 1, 2, 3].map(|gp| {
            let (xi, eta) = (XI[gp], ETA[gp]);
            let da = det_j(&lf, &shape_derivs(xi, eta));
            let dn = agq.gradients(xi, eta);
            let mut b = Mat8x24::zeros();
            for (i, [dx, dy]) in dn.iter().copied().enumerate() {
                let c = 6 * i;
                // membrane
                b[(0, c)] = dx;
                b[(1, c + 1)] = dy;
                b[(2, c)] = dy;
                b[(2, c + 1)] = dx;
                // bending
                b[(3, c + 4)] = -dx;
                b[(4, c + 3)] = dy;
                b[(5, c + 3)] = dx;
                b[(5, c + 4)] = -dy;
            }
            // MITC4 transverse shear.
            let mut msf = SMatrix::<f64, 2, 4>::zeros();
            msf[(1, 0)] = 1.0 - xi;
            msf[(0, 1)] = 1.0 - eta;
            msf[(1, 2)] = 1.0 + xi;
            msf[(0, 3)] = 1.0 + eta;
            let mut bn = msf * mitc.shear_strains;
            let t1 = ((mitc.cx + xi * mitc.bx).powi(2) + (mitc.cy + xi * mitc.by).powi(2)).sqrt()
                / (8.0 * da);
            let t2 = ((mitc.ax + eta * mitc.bx).powi(2) + (mitc.ay + eta * mitc.by).powi(2)).sqrt()
                / (8.0 * da);
            for c in 0..24 {
                bn[(0, c)] *= t1;
                bn[(1, c)] *= t2;
            }
            let tbn = mitc.transformation * bn;
            for c in 0..24 {
                b[(6, c)] = tbn[(0, c)];
                b[(7, c)] = tbn[(1, c)];
            }
            let mut b1 = b;
            for r in 3..6 {
                for i in 0..4 {
                    b1[(r, 6 * i + 3)] *= -1.0;
                    b1[(r, 6 * i + 4)] *= -1.0;
                }
            }
            GaussKinematics {
                b,
                b1,
                bd: drilling_b(xi, eta) * alpha + bd0 * beta,
                bq: agq.bq(xi, eta) - bq_mean,
                da,
            }
        });
        // Global → local: T = W R (W only for warped elements).
        let mut t = Mat24::zeros();
        for blk in 0..8 {
            t.fixed_view_mut::<3, 3>(3 * blk, 3 * blk).copy_from(&lf.r);
        }
        let wf = lf.p[0][2];
        if wf.abs() > 0.0 {
            let mut w = Mat24::identity();
            w[(0, 4)] = -wf;
            w[(1, 3)] = wf;
            w[(6, 10)] = wf;
            w[(7, 9)] = -wf;
            w[(12, 16)] = -wf;
            w[(13, 15)] = wf;
            w[(18, 22)] = wf;
            w[(19, 21)] = -wf;
            t = w * t;
        }
        Ok(Self { t, rs, gauss })
    }

    /// A section tangent (section axes) in the element's axes: `rs d rsᵀ`.
    pub fn to_element(&self, d: &Mat8) -> Mat8 {
        match &self.rs {
            Some(rs) => rs * d * rs.transpose(),
            None => *d,
        }
    }
}

/// Drilling penalty of `ASDShellQ4`: k_d = 0.233 · D₃₃ of the section's initial tangent
/// (N/m), OpenSees' `-drillingStab` default elastic drilling.
pub fn drilling_stiffness(d0: &Mat8) -> f64 {
    0.233 * d0[(2, 2)]
}

/// Linear stiffness (24 × 24, global axes) of an `ASDShellQ4` element (EAS on, elastic
/// drilling, small displacements) with nodes `coords` (m, counter-clockwise), the user's
/// local x axis `local_x` (`-local`; rebar angles are measured from it) and the section
/// tangent `d` (see [`layered_section_tangent`]), the same at the four Gauss points.
pub fn asd_shell_q4_stiffness(
    coords: &[[f64; 3]; 4],
    local_x: [f64; 3],
    d: &Mat8,
) -> Result<Mat24, ShellError> {
    let kin = ShellKinematics::new(coords, local_x)?;
    let dl = kin.to_element(d);
    let k_drill = drilling_stiffness(d);
    let mut k = Mat24::zeros();
    let mut kqq = SMatrix::<f64, 4, 4>::zeros();
    let mut kqu = SMatrix::<f64, 4, 24>::zeros();
    let mut kuq = SMatrix::<f64, 24, 4>::zeros();
    for g in &kin.gauss {
        k += g.b1.transpose() * dl * g.b * g.da;
        k += g.bd * g.bd.transpose() * (k_drill * g.da);
        kqq += g.bq.transpose() * dl * g.bq * g.da;
        kqu += g.bq.transpose() * dl * g.b * g.da;
        kuq += g.b1.transpose() * dl * g.bq * g.da;
    }
    let kqq_inv = kqq
        .try_inverse()
        .ok_or_else(|| ShellError::Invalid("singular enhanced-strain stiffness".into()))?;
    k -= kuq * kqq_inv * kqu;
    Ok(kin.t.transpose() * k * kin.t)
}
/// The linear stiffness (global axes) and node tags of a model's shell element with a
/// `layered_shell` section: layer tangents from the section (rebar from its uniaxial
/// material's initial tangent), local x from the element (`local_x`, default the edge
/// node 1 → node 2, as the OpenSees export writes it).
pub fn model_shell_stiffness(
    model: &crate::model::Model,
    element: &crate::model::Element,
) -> Result<([u32; 4], Mat24), ShellError> {
    use crate::model::{ElementKind, SectionKind};
    let ElementKind::Shell {
        nodes,
        section,
        local_x,
        ..
    } = &element.kind
    else {
        return Err(ShellError::Invalid(format!(
            "element {} is not a shell",
            element.tag
        )));
    };
    let secs = model.section_map();
    let mats = model.material_map();
    let Some(SectionKind::LayeredShell { layers, .. }) = secs.get(section).map(|s| &s.kind) else {
        return Err(ShellError::Invalid(format!(
            "element {}: section {section} is not a layered_shell section",
            element.tag
        )));
    };
    let mut coords = [[0.0; 3]; 4];
    for (c, t) in coords.iter_mut().zip(nodes) {
        *c = model
            .nodes
            .iter()
            .find(|n| n.tag == *t)
            .map(|n| n.xyz())
            .ok_or_else(|| {
                ShellError::Invalid(format!("element {}: unknown node {t}", element.tag))
            })?;
    }
    let lx = local_x.unwrap_or([
        coords[1][0] - coords[0][0],
        coords[1][1] - coords[0][1],
        coords[1][2] - coords[0][2],
    ]);
    let d = layered_section_tangent(&initial_layer_tangents(layers, &mats)?);
    let k = asd_shell_q4_stiffness(&coords, lx, &d).map_err(|ShellError::Invalid(m)| {
        ShellError::Invalid(format!("element {}: {m}", element.tag))
    })?;
    Ok((*nodes, k))
}

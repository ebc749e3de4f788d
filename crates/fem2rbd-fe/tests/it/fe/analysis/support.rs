//! Test-only elements for the analysis tests: a linear-elastic 3D Euler-Bernoulli frame
//! element (linear transformation, OpenSees vecxz convention) and wrappers that fail.
#![allow(dead_code)]

use fem2rbd_fe::fe::domain::Domain;
use fem2rbd_fe::fe::element::{dmat, dvec, Element, ElementError, EndDisplacements, Mat12, Vec12};
use nalgebra::{DMatrix, DVector};
use nalgebra::{Matrix3, Vector3};

/// Section properties (SI).
#[derive(Debug, Clone, Copy)]
pub struct Props {
    pub e: f64,
    pub g: f64,
    pub a: f64,
    pub iy: f64,
    pub iz: f64,
    pub j: f64,
}

/// Linear elastic frame element: K_global = Tᵀ K_local T, local y = vecxz × x,
/// z = x × y.
#[derive(Debug, Clone)]
pub struct ElasticFrame {
    pub tag: i64,
    pub nodes: [usize; 2],
    pub k: Mat12,
    pub u: Vec12,
}

impl ElasticFrame {
    pub fn new(tag: i64, d: &Domain, i: usize, j: usize, vecxz: [f64; 3], p: Props) -> Self {
        let ci = Vector3::from(d.nodes()[i].coords);
        let cj = Vector3::from(d.nodes()[j].coords);
        let dx = cj - ci;
        let l = dx.norm();
        let x = dx / l;
        let y = Vector3::from(vecxz).cross(&x).normalize();
        let z = x.cross(&y);
        let r = Matrix3::from_rows(&[x.transpose(), y.transpose(), z.transpose()]);
        let mut t = Mat12::zeros();
        for b in 0..4 {
            t.fixed_view_mut::<3, 3>(3 * b, 3 * b).copy_from(&r);
        }
        let mut kl = Mat12::zeros();
        let ea = p.e * p.a / l;
        let gj = p.g * p.j / l;
        let (eiz, eiy) = (p.e * p.iz, p.e * p.iy);
        let l2 = l * l;
        let l3 = l2 * l;
        let mut set = |i: usize, j: usize, v: f64| {
            kl[(i, j)] = v;
            kl[(j, i)] = v;
        };
        set(0, 0, ea);
        set(6, 6, ea);
        set(0, 6, -ea);
        set(3, 3, gj);
        set(9, 9, gj);
        set(3, 9, -gj);
        // x-y plane: v, θz (EIz)
        set(1, 1, 12.0 * eiz / l3);
        set(1, 5, 6.0 * eiz / l2);
        set(1, 7, -12.0 * eiz / l3);
        set(1, 11, 6.0 * eiz / l2);
        set(5, 5, 4.0 * eiz / l);
        set(5, 7, -6.0 * eiz / l2);
        set(5, 11, 2.0 * eiz / l);
        set(7, 7, 12.0 * eiz / l3);
        set(7, 11, -6.0 * eiz / l2);
        set(11, 11, 4.0 * eiz / l);
        // x-z plane: w, θy (EIy)
        set(2, 2, 12.0 * eiy / l3);
        set(2, 4, -6.0 * eiy / l2);
        set(2, 8, -12.0 * eiy / l3);
        set(2, 10, -6.0 * eiy / l2);
        set(4, 4, 4.0 * eiy / l);
        set(4, 8, 6.0 * eiy / l2);
        set(4, 10, 2.0 * eiy / l);
        set(8, 8, 12.0 * eiy / l3);
        set(8, 10, 6.0 * eiy / l2);
        set(10, 10, 4.0 * eiy / l);
        let k = t.transpose() * kl * t;
        Self {
            tag,
            nodes: [i, j],
            k,
            u: Vec12::zeros(),
        }
    }
}

impl Element for ElasticFrame {
    fn tag(&self) -> i64 {
        self.tag
    }
    fn nodes(&self) -> &[usize] {
        &self.nodes
    }
    fn set_trial(&mut self, disp: &EndDisplacements<'_>) -> Result<(), ElementError> {
        self.u = Vec12::from_column_slice(disp.total);
        Ok(())
    }
    fn resisting_force(&self) -> DVector<f64> {
        dvec(&(self.k * self.u))
    }
    fn tangent_stiffness(&self) -> DMatrix<f64> {
        dmat(&self.k)
    }
    fn initial_stiffness(&self) -> DMatrix<f64> {
        dmat(&self.k)
    }
    fn commit_state(&mut self) {}
    fn revert_to_last_commit(&mut self) {}
}

/// How a [`Failing`] element misbehaves.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FailMode {
    /// `set_trial` returns an error once any |total displacement| exceeds the limit.
    ErrorBeyond(f64),
    /// The resisting force becomes NaN once any |total displacement| exceeds the limit.
    NanBeyond(f64),
    /// `tangent_stiffness` is NaN (Newton, Krylov-Newton and line search fail; the
    /// initial-stiffness modified Newton converges).
    NanTangent,
}

/// A linear element that fails on purpose.
#[derive(Debug, Clone)]
pub struct Failing {
    pub inner: ElasticFrame,
    pub mode: FailMode,
    committed: Vec12,
}

impl Failing {
    pub fn new(inner: ElasticFrame, mode: FailMode) -> Self {
        Self {
            inner,
            mode,
            committed: Vec12::zeros(),
        }
    }
}

impl Element for Failing {
    fn tag(&self) -> i64 {
        self.inner.tag
    }
    fn nodes(&self) -> &[usize] {
        &self.inner.nodes
    }
    fn set_trial(&mut self, disp: &EndDisplacements<'_>) -> Result<(), ElementError> {
        self.inner.u = Vec12::from_column_slice(disp.total);
        if let FailMode::ErrorBeyond(lim) = self.mode {
            if disp.total.iter().any(|x| x.abs() > lim) {
                return Err(ElementError {
                    element: self.inner.tag,
                    reason: "limit".into(),
                });
            }
        }
        Ok(())
    }
    fn resisting_force(&self) -> DVector<f64> {
        match self.mode {
            FailMode::NanBeyond(lim) if self.inner.u.amax() > lim => DVector::repeat(12, f64::NAN),
            _ => self.inner.resisting_force(),
        }
    }
    fn tangent_stiffness(&self) -> DMatrix<f64> {
        match self.mode {
            FailMode::NanTangent => DMatrix::repeat(12, 12, f64::NAN),
            _ => dmat(&self.inner.k),
        }
    }
    fn initial_stiffness(&self) -> DMatrix<f64> {
        dmat(&self.inner.k)
    }
    fn commit_state(&mut self) {
        self.committed = self.inner.u;
    }
    fn revert_to_last_commit(&mut self) {
        self.inner.u = self.committed;
    }
}

/// Square section b × b of modulus E (G = E/2.4): handy props.
pub fn square(e: f64, b: f64) -> Props {
    let i = b.powi(4) / 12.0;
    Props {
        e,
        g: e / 2.4,
        a: b * b,
        iy: i,
        iz: i,
        j: 0.1406 * b.powi(4),
    }
}

/// A cantilever along +X from the origin, `n` elements of total length `l`, base
/// fixed; returns the domain and the tip node index.
pub fn cantilever(l: f64, n: usize, p: Props, vecxz: [f64; 3]) -> (Domain, usize) {
    let mut d = Domain::new();
    for k in 0..=n {
        d.add_node(k as i64 + 1, [l * k as f64 / n as f64, 0.0, 0.0])
            .unwrap();
    }
    d.fix(0, [true; 6]).unwrap();
    for k in 0..n {
        let el = ElasticFrame::new(k as i64 + 1, &d, k, k + 1, vecxz, p);
        d.add_element(Box::new(el)).unwrap();
    }
    (d, n)
}

/// A 3D frame: `bays`×`bays` bays of span `s`, `stories` stories of height `h`,
/// columns (vecxz = X) and beams (vecxz = Z), base fixed, lumped translational floor
/// masses `m` per node (no rotational mass). Returns the domain.
pub fn grid_frame(
    bays: usize,
    stories: usize,
    s: f64,
    h: f64,
    col: Props,
    beam: Props,
    m: f64,
) -> Domain {
    let mut d = Domain::new();
    let nn = bays + 1;
    let id = |f: usize, i: usize, j: usize| f * nn * nn + i * nn + j;
    for f in 0..=stories {
        for i in 0..nn {
            for j in 0..nn {
                let n = d
                    .add_node(
                        (100 * f + 10 * i + j) as i64,
                        [s * i as f64, s * j as f64, h * f as f64],
                    )
                    .unwrap();
                if f == 0 {
                    d.fix(n, [true; 6]).unwrap();
                } else {
                    d.set_mass(n, [m, m, m, 0.0, 0.0, 0.0]).unwrap();
                }
            }
        }
    }
    let mut tag = 0;
    let mut add = |d: &mut Domain, a: usize, b: usize, v: [f64; 3], p: Props| {
        tag += 1;
        let el = ElasticFrame::new(tag, d, a, b, v, p);
        d.add_element(Box::new(el)).unwrap();
    };
    for f in 1..=stories {
        for i in 0..nn {
            for j in 0..nn {
                add(&mut d, id(f - 1, i, j), id(f, i, j), [1.0, 0.0, 0.0], col);
                if i + 1 < nn {
                    add(&mut d, id(f, i, j), id(f, i + 1, j), [0.0, 0.0, 1.0], beam);
                }
                if j + 1 < nn {
                    add(&mut d, id(f, i, j), id(f, i, j + 1), [0.0, 0.0, 1.0], beam);
                }
            }
        }
    }
    d
}

/// Nonlinear axial spring between two nodes along global X: N = k δ + k3 δ³,
/// δ = ux_j − ux_i (N); tangent k + 3 k3 δ², initial stiffness k. Only the ux DOFs.
#[derive(Debug, Clone)]
pub struct CubicSpring {
    pub tag: i64,
    pub nodes: [usize; 2],
    pub k: f64,
    pub k3: f64,
    pub delta: f64,
}

impl Element for CubicSpring {
    fn tag(&self) -> i64 {
        self.tag
    }
    fn nodes(&self) -> &[usize] {
        &self.nodes
    }
    fn set_trial(&mut self, disp: &EndDisplacements<'_>) -> Result<(), ElementError> {
        self.delta = disp.total[6] - disp.total[0];
        Ok(())
    }
    fn resisting_force(&self) -> DVector<f64> {
        let n = self.k * self.delta + self.k3 * self.delta.powi(3);
        let mut f = Vec12::zeros();
        f[0] = -n;
        f[6] = n;
        dvec(&f)
    }
    fn tangent_stiffness(&self) -> DMatrix<f64> {
        let kt = self.k + 3.0 * self.k3 * self.delta * self.delta;
        let mut m = Mat12::zeros();
        m[(0, 0)] = kt;
        m[(6, 6)] = kt;
        m[(0, 6)] = -kt;
        m[(6, 0)] = -kt;
        dmat(&m)
    }
    fn initial_stiffness(&self) -> DMatrix<f64> {
        let mut m = Mat12::zeros();
        m[(0, 0)] = self.k;
        m[(6, 6)] = self.k;
        m[(0, 6)] = -self.k;
        m[(6, 0)] = -self.k;
        dmat(&m)
    }
    fn commit_state(&mut self) {}
    fn revert_to_last_commit(&mut self) {}
}

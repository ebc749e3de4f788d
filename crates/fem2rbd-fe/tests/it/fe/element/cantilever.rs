//! Elastic cantilever closed forms for every element formulation and every geometric
//! transformation: tip load in both local planes (δ = P L³/(3EI), θ = P L²/(2EI)),
//! axial load (δ = P L/(EA)) and torque (φ = T L/(GJ)). The member is inclined in space,
//! so the local-axes conventions (y = vecxz × x, z = x × y) are exercised too.

use super::support;

use fem2rbd_fe::fe::element::beam::{BeamColumn, BeamColumnSpec, Formulation};
use fem2rbd_fe::fe::element::{ElasticProps, ForceBeamOptions};
use fem2rbd_fe::fe::section::fiber::FiberSection;
use fem2rbd_fe::fe::section::Section;
use fem2rbd_fe::fe::transform::{local_axes, TransformKind};
use nalgebra::{DVector, Matrix3, Vector3};
use support::{rectangle_fibers, LinearElastic, Model};

const E: f64 = 200e9;
const G: f64 = 80e9;
const B: f64 = 0.1; // along local y
const H: f64 = 0.2; // along local z
const NY: usize = 4;
const NZ: usize = 8;
const L: f64 = 2.5;

/// Section properties of the fiber rectangle (mid-point sums): A, Iz = Σ A y², Iy = Σ A z².
fn props() -> ElasticProps {
    let a = B * H;
    let iz = H * B.powi(3) / 12.0 * (1.0 - 1.0 / (NY * NY) as f64);
    let iy = B * H.powi(3) / 12.0 * (1.0 - 1.0 / (NZ * NZ) as f64);
    ElasticProps {
        e: E,
        g: G,
        a,
        iy,
        iz,
        j: 1.7e-4,
    }
}

fn section() -> Box<dyn Section> {
    let p = props();
    Box::new(
        FiberSection::new(
            rectangle_fibers(B, H, NY, NZ, &LinearElastic::new(E)),
            G * p.j,
        )
        .unwrap(),
    )
}

fn geometry() -> (Vector3<f64>, Vector3<f64>, Vector3<f64>) {
    let x0 = Vector3::new(0.3, -0.2, 0.1);
    let dir = Vector3::new(1.0, 2.0, 2.0) / 3.0;
    (x0, x0 + dir * L, Vector3::new(0.0, 0.0, 1.0))
}

/// A cantilever of `n_el` elements; returns the model and the local axes.
fn cantilever(kind: TransformKind, form: Formulation, n_el: usize) -> (Model, Matrix3<f64>) {
    let (xi, xj, vecxz) = geometry();
    let (axes, _) = local_axes(&xi, &xj, &vecxz).unwrap();
    let mut elements: Vec<Box<dyn BeamColumn>> = Vec::new();
    for k in 0..n_el {
        let a = xi + (xj - xi) * (k as f64 / n_el as f64);
        let b = xi + (xj - xi) * ((k + 1) as f64 / n_el as f64);
        let section = match form {
            Formulation::Elastic(_) => None,
            _ => Some(section()),
        };
        elements.push(
            BeamColumnSpec {
                tag: k as i64 + 1,
                nodes: [k, k + 1],
                xi: a,
                xj: b,
                transform: kind,
                vecxz,
                formulation: form,
                section,
            }
            .build()
            .unwrap(),
        );
    }
    (Model::new(n_el + 1, elements, (0..6).collect()), axes)
}

/// Tip displacement and rotation in local axes after applying a tip force `f` and
/// moment `m` given in local axes.
fn tip_response(
    kind: TransformKind,
    form: Formulation,
    n_el: usize,
    f: Vector3<f64>,
    m: Vector3<f64>,
) -> (Vector3<f64>, Vector3<f64>) {
    let (mut model, axes) = cantilever(kind, form, n_el);
    let mut load = DVector::zeros(6 * (n_el + 1));
    let fg = axes * f;
    let mg = axes * m;
    for d in 0..3 {
        load[6 * n_el + d] = fg[d];
        load[6 * n_el + 3 + d] = mg[d];
    }
    model.solve(&load, 1).unwrap();
    let u = Vector3::new(
        model.u[6 * n_el],
        model.u[6 * n_el + 1],
        model.u[6 * n_el + 2],
    );
    let r = Vector3::new(
        model.u[6 * n_el + 3],
        model.u[6 * n_el + 4],
        model.u[6 * n_el + 5],
    );
    (axes.transpose() * u, axes.transpose() * r)
}

fn formulations() -> Vec<(&'static str, Formulation, usize)> {
    vec![
        ("elastic", Formulation::Elastic(props()), 1),
        (
            "force-based (Lobatto 5)",
            Formulation::ForceBased {
                n_ip: 5,
                options: ForceBeamOptions {
                    max_iter: 50,
                    tol: 1e-12,
                    ..Default::default()
                },
            },
            1,
        ),
        (
            "force-based (Lobatto 3)",
            Formulation::ForceBased {
                n_ip: 3,
                options: ForceBeamOptions::default(),
            },
            1,
        ),
        (
            "disp-based (Legendre 5)",
            Formulation::DispBased { n_ip: 5 },
            1,
        ),
        (
            "disp-based (Legendre 2)",
            Formulation::DispBased { n_ip: 2 },
            1,
        ),
        ("elastic, 4 elements", Formulation::Elastic(props()), 4),
    ]
}

fn check(name: &str, what: &str, got: f64, want: f64, tol: f64) {
    let rel = (got / want - 1.0).abs();
    println!("{name:>28} {what:<14} got {got:+.9e}  closed form {want:+.9e}  rel err {rel:.2e}");
    assert!(
        rel < tol,
        "{name}: {what} = {got}, closed form {want}, rel err {rel:e}"
    );
}

/// Loads small enough that the corotational (second-order) change is below 1e-6.
#[test]
fn tip_load_in_both_planes_axial_and_torsion() {
    let p = props();
    let small = 1e-4; // δ/L
    let py = small * 3.0 * E * p.iz / L.powi(2);
    let pz = small * 3.0 * E * p.iy / L.powi(2);
    let n = 1e-4 * E * p.a;
    let t = 1e-4 * G * p.j / L;
    for kind in [
        TransformKind::Linear,
        TransformKind::PDelta,
        TransformKind::Corotational,
    ] {
        // Geometric nonlinearity is of order (δ/L)² for the corotational transformation.
        let tol = if kind == TransformKind::Corotational {
            1e-6
        } else {
            1e-10
        };
        for (name, form, n_el) in formulations() {
            let name = format!("{kind:?} {name}");
            // Tip load along local y: bending about local z (Iz).
            let (u, r) = tip_response(
                kind,
                form,
                n_el,
                Vector3::new(0.0, py, 0.0),
                Vector3::zeros(),
            );
            check(
                &name,
                "uy = PL³/3EIz",
                u.y,
                py * L.powi(3) / (3.0 * E * p.iz),
                tol,
            );
            check(
                &name,
                "θz = PL²/2EIz",
                r.z,
                py * L.powi(2) / (2.0 * E * p.iz),
                tol,
            );
            // Tip load along local z: bending about local y (Iy), θy = −PL²/(2EIy).
            let (u, r) = tip_response(
                kind,
                form,
                n_el,
                Vector3::new(0.0, 0.0, pz),
                Vector3::zeros(),
            );
            check(
                &name,
                "uz = PL³/3EIy",
                u.z,
                pz * L.powi(3) / (3.0 * E * p.iy),
                tol,
            );
            check(
                &name,
                "θy = −PL²/2EIy",
                r.y,
                -pz * L.powi(2) / (2.0 * E * p.iy),
                tol,
            );
            // Axial.
            let (u, _) = tip_response(
                kind,
                form,
                n_el,
                Vector3::new(n, 0.0, 0.0),
                Vector3::zeros(),
            );
            check(&name, "ux = PL/EA", u.x, n * L / (E * p.a), tol);
            // Torsion.
            let (_, r) = tip_response(
                kind,
                form,
                n_el,
                Vector3::zeros(),
                Vector3::new(t, 0.0, 0.0),
            );
            check(&name, "θx = TL/GJ", r.x, t * L / (G * p.j), tol);
        }
    }
}

/// P-Δ closed form: a cantilever under axial compression N and tip load P has
/// δ = P L³/(3EI) · 3 (tan(kL) − kL)/(kL)³ with k² = N/(EI). The P-Δ transformation
/// (chord only, one element) and the corotational one (10 elements) approach it.
#[test]
fn beam_column_amplification() {
    let p = props();
    let ncr = std::f64::consts::PI.powi(2) * E * p.iz / (4.0 * L * L);
    let n = 0.3 * ncr;
    let py = 1e-6 * 3.0 * E * p.iz / L.powi(2);
    let k = (n / (E * p.iz)).sqrt();
    let kl = k * L;
    let exact = py * L.powi(3) / (3.0 * E * p.iz) * 3.0 * (kl.tan() - kl) / kl.powi(3);
    for (kind, n_el, tol) in [
        (TransformKind::Corotational, 10, 2e-3),
        (TransformKind::PDelta, 10, 2e-2),
    ] {
        let (mut model, axes) = cantilever(kind, Formulation::Elastic(p), n_el);
        let mut load = DVector::zeros(6 * (n_el + 1));
        let fg = axes * Vector3::new(-n, py, 0.0);
        for d in 0..3 {
            load[6 * n_el + d] = fg[d];
        }
        model.solve(&load, 5).unwrap();
        let u = axes.transpose()
            * Vector3::new(
                model.u[6 * n_el],
                model.u[6 * n_el + 1],
                model.u[6 * n_el + 2],
            );
        check(
            &format!("{kind:?} {n_el} el."),
            "uy amplified",
            u.y,
            exact,
            tol,
        );
    }
}

//! Elastic-perfectly-plastic rectangular cantilever under a tip load between first yield
//! and the plastic moment, against the closed form of the moment-area integral
//! δ = ∫₀ᴸ κ(M(x)) (L − x) dx with M(x) = P (L − x) and, for a rectangle,
//! κ = M/EI (M ≤ My), κ = κy / √(3 − 2M/My) (My < M < Mp = 1.5 My)
//! (e.g. Gere & Timoshenko, Mechanics of Materials, inelastic bending of beams).
//!
//! The force-based element is nearly exact with one element (its error is the Lobatto
//! quadrature of a curvature field with a kink); the displacement-based element is
//! too stiff with one element and converges as the mesh is refined. Also checks the
//! damage flags and that the elastic region stays undamaged.

use super::support;

use fem2rbd_fe::fe::element::beam::{BeamColumn, BeamColumnSpec, Formulation};
use fem2rbd_fe::fe::element::ForceBeamOptions;
use fem2rbd_fe::fe::section::fiber::FiberSection;
use fem2rbd_fe::fe::transform::TransformKind;
use nalgebra::{DVector, Vector3};
use support::{rectangle_fibers, ElasticPerfectlyPlastic, Model};

const L: f64 = 1.5;
const E: f64 = 200e9;
const FY: f64 = 300e6;
const B: f64 = 0.05;
const H: f64 = 0.1;
const NZ: usize = 200;

fn cantilever(n_el: usize, form: Formulation) -> Model {
    let mat = ElasticPerfectlyPlastic::new(E, FY);
    let section = FiberSection::new(rectangle_fibers(B, H, 2, NZ, &mat), 1e6).unwrap();
    let mut elements: Vec<Box<dyn BeamColumn>> = Vec::new();
    let x = |k: usize| Vector3::new(L * k as f64 / n_el as f64, 0.0, 0.0);
    for k in 0..n_el {
        elements.push(
            BeamColumnSpec {
                tag: k as i64 + 1,
                nodes: [k, k + 1],
                xi: x(k),
                xj: x(k + 1),
                transform: TransformKind::Linear,
                vecxz: Vector3::new(0.0, 0.0, 1.0),
                formulation: form,
                section: Some(Box::new(section.clone())),
            }
            .build()
            .unwrap(),
        );
    }
    Model::new(n_el + 1, elements, (0..6).collect())
}

/// Tip deflection by the moment-area integral (composite Simpson, 20 000 intervals).
fn closed_form(p: f64) -> f64 {
    let i = B * H.powi(3) / 12.0;
    let my = FY * B * H * H / 6.0;
    let ky = my / (E * i);
    let kappa = |m: f64| {
        if m <= my {
            m / (E * i)
        } else {
            ky / (3.0 - 2.0 * m / my).sqrt()
        }
    };
    let n = 20_000;
    let h = L / n as f64;
    let f = |x: f64| kappa(p * (L - x)) * (L - x);
    let mut s = f(0.0) + f(L);
    for k in 1..n {
        s += f(k as f64 * h) * if k % 2 == 1 { 4.0 } else { 2.0 };
    }
    s * h / 3.0
}

fn tip_deflection(n_el: usize, form: Formulation, p: f64) -> (f64, Model) {
    let mut model = cantilever(n_el, form);
    let mut load = DVector::zeros(6 * (n_el + 1));
    load[6 * n_el + 2] = p; // +Z = local z: bending about local y
    model.solve(&load, 10).unwrap();
    (model.u[6 * n_el + 2], model)
}

#[test]
fn elastoplastic_cantilever_tip_deflection() {
    let my = FY * B * H * H / 6.0;
    let p = 1.3 * my / L;
    let exact = closed_form(p);
    println!("closed form tip deflection at P L = 1.3 My: {exact:.6e} m");
    let fb = |n_ip| Formulation::ForceBased {
        n_ip,
        options: ForceBeamOptions {
            max_iter: 50,
            tol: 1e-12,
            ..Default::default()
        },
    };
    let mut fb_err = vec![];
    for n_ip in [5, 10] {
        let (d, model) = tip_deflection(1, fb(n_ip), p);
        let err = d / exact - 1.0;
        println!("force-based, 1 element, Lobatto {n_ip}: {d:.6e}  rel err {err:+.3e}");
        fb_err.push(err.abs());
        let damage = model.elements[0].damage();
        assert!(damage.yielded && !damage.ruptured);
        let st = model.elements[0].section_states();
        assert!(st[0].damage.yielded, "fixed end yields");
        assert!(!st[n_ip - 1].damage.yielded, "tip section stays elastic");
    }
    assert!(fb_err[0] < 1e-3 && fb_err[1] < 1e-3, "{fb_err:?}");
    let mut db_err = vec![];
    for n_el in [1, 2, 4, 8, 16] {
        let (d, _) = tip_deflection(n_el, Formulation::DispBased { n_ip: 5 }, p);
        let err = d / exact - 1.0;
        println!("disp-based, {n_el:2} elements, Legendre 5: {d:.6e}  rel err {err:+.3e}");
        db_err.push(err);
    }
    assert!(db_err[0] < 0.0, "one disp-based element is too stiff");
    for w in db_err.windows(2) {
        assert!(
            w[1].abs() < w[0].abs(),
            "disp-based converges with the mesh: {db_err:?}"
        );
    }
    assert!(db_err[4].abs() < 5e-4, "{db_err:?}");
}

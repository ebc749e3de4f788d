//! Static analysis through the whole path (domain, RCM numbering, sparse assembly,
//! sparse LU, Newton load control) against closed forms.
use super::support as fe_analysis_support;

use fe_analysis_support::{cantilever, square};
use fem2rbd_fe::fe::analysis::static_analysis::{load_control, LoadControl};

/// Cantilever with tip loads: δ = P L³/(3 E I), θ = P L²/(2 E I), axial N L/(E A),
/// torsion T L/(G J).
#[test]
fn cantilever_tip_deflection_and_rotation() {
    let (e, b, l) = (25e9, 0.1, 2.0);
    let p = square(e, b);
    let (mut d, tip) = cantilever(l, 8, p, [0.0, 0.0, 1.0]);
    let (pz, py, px, tx) = (-1000.0, 700.0, 5e4, 300.0);
    d.add_nodal_load(tip, [px, py, pz, tx, 0.0, 0.0]).unwrap();
    let steps = load_control(
        &mut d,
        &LoadControl {
            steps: 4,
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(steps.len(), 4);
    assert!((d.load_factor() - 1.0).abs() < 1e-12);
    let u = d.displacement(tip);
    let ei = e * p.iy;
    let rel = |a: f64, b: f64| ((a - b) / b).abs();
    assert!(rel(u[2], pz * l.powi(3) / (3.0 * ei)) < 1e-9, "uz {}", u[2]);
    assert!(rel(u[1], py * l.powi(3) / (3.0 * ei)) < 1e-9, "uy {}", u[1]);
    assert!(rel(u[0], px * l / (e * p.a)) < 1e-9, "ux {}", u[0]);
    assert!(rel(u[3], tx * l / (p.g * p.j)) < 1e-9, "rx {}", u[3]);
    // θy = −P_z L²/(2EI) with the right-hand rule (downward load → positive θy).
    assert!(rel(u[4], -pz * l * l / (2.0 * ei)) < 1e-9, "ry {}", u[4]);
    assert!(rel(u[5], py * l * l / (2.0 * ei)) < 1e-9, "rz {}", u[5]);
    // Linear problem: Newton converges on the second iteration (‖Δu‖ ~ roundoff).
    assert!(steps.iter().all(|s| s.iterations <= 2), "{steps:?}");
}

/// Same cantilever modelled vertically (column, vecxz = X), with load_const: after
/// load_const the loads stay and λ, time reset.
#[test]
fn column_gravity_then_load_const() {
    let (e, b, h) = (30e9, 0.2, 3.0);
    let p = square(e, b);
    let mut d = fem2rbd_fe::fe::domain::Domain::new();
    for k in 0..=3 {
        d.add_node(k, [0.0, 0.0, h * k as f64 / 3.0]).unwrap();
    }
    d.fix(0, [true; 6]).unwrap();
    for k in 0..3 {
        let el = fe_analysis_support::ElasticFrame::new(k as i64, &d, k, k + 1, [1.0, 0.0, 0.0], p);
        d.add_element(Box::new(el)).unwrap();
    }
    d.add_nodal_load(3, [2000.0, 0.0, -1e5, 0.0, 0.0, 0.0])
        .unwrap();
    load_control(&mut d, &LoadControl::default()).unwrap();
    d.load_const();
    assert_eq!(d.load_factor(), 0.0);
    assert_eq!(d.time(), 0.0);
    let u = d.displacement(3);
    let ei = e * p.iy;
    assert!(((u[0] - 2000.0 * h.powi(3) / (3.0 * ei)) / u[0]).abs() < 1e-9);
    assert!(((u[2] + 1e5 * h / (e * p.a)) / u[2]).abs() < 1e-9);
    // Constant loads are still applied: a further load-control run with an empty
    // pattern leaves the state unchanged.
    load_control(
        &mut d,
        &LoadControl {
            steps: 1,
            ..Default::default()
        },
    )
    .unwrap();
    assert!((d.displacement(3)[0] - u[0]).abs() < 1e-14);
}

/// Bad input is an error naming the item, not a panic.
#[test]
fn domain_input_errors() {
    let mut d = fem2rbd_fe::fe::domain::Domain::new();
    d.add_node(1, [0.0; 3]).unwrap();
    assert!(d
        .add_node(1, [1.0, 0.0, 0.0])
        .unwrap_err()
        .to_string()
        .contains("node 1"));
    assert!(d.add_node(2, [f64::NAN, 0.0, 0.0]).is_err());
    assert!(d.set_mass(0, [-1.0, 0.0, 0.0, 0.0, 0.0, 0.0]).is_err());
    assert!(d.fix(7, [true; 6]).is_err());
}

/// A mechanism (a node held by nothing in Y: zero stiffness) gives a singular tangent:
/// a reported error naming the step, no panic, the domain unchanged.
#[test]
fn singular_tangent_is_an_error() {
    let p = square(25e9, 0.1);
    let (mut d, tip) = cantilever(1.0, 2, p, [0.0, 0.0, 1.0]);
    let free = d.add_node(99, [5.0, 5.0, 5.0]).unwrap();
    d.add_nodal_load(free, [0.0, 1.0, 0.0, 0.0, 0.0, 0.0])
        .unwrap();
    d.add_nodal_load(tip, [0.0, 0.0, -1.0, 0.0, 0.0, 0.0])
        .unwrap();
    let err = load_control(
        &mut d,
        &LoadControl {
            steps: 2,
            ..Default::default()
        },
    )
    .unwrap_err();
    let msg = err.to_string();
    assert!(msg.contains("step 1") && msg.contains("singular"), "{msg}");
    assert_eq!(d.displacement(tip), [0.0; 6]);
    assert_eq!(d.load_factor(), 0.0);
}

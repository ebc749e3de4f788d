//! Large-rotation closed forms for the corotational transformation (own small Newton
//! driver with a dense solve, see `fe_element_support.rs`):
//!
//! - a cantilever under an end moment M = 2π EI/L curls into a full circle and its tip
//!   returns to the base (with chords of equal length the polygon closes exactly);
//! - a cantilever under a transverse tip load P L²/EI = 1 (Mattiasson 1981, "Numerical
//!   results from large deflection beam and frame problems analysed by means of elliptic
//!   integrals", IJNME 17:145–153, table 1): tip displacements along the beam
//!   u/L = 0.05643 and across it v/L = 0.30172.

use super::support;

use fem2rbd_fe::fe::element::beam::{BeamColumn, BeamColumnSpec, Formulation};
use fem2rbd_fe::fe::element::{ElasticProps, ForceBeamOptions};
use fem2rbd_fe::fe::section::fiber::FiberSection;
use fem2rbd_fe::fe::transform::TransformKind;
use nalgebra::{DVector, Vector3};
use support::{rectangle_fibers, LinearElastic, Model};

const L: f64 = 2.0;
const E: f64 = 1e9;
const B: f64 = 0.05;
const H: f64 = 0.1;

fn props() -> ElasticProps {
    ElasticProps {
        e: E,
        g: E / 2.6,
        a: B * H,
        // Local y across B (bending about z uses Iz = H B³/12 (1 − 1/ny²)) for the
        // 8-fiber-wide section below.
        iz: H * B.powi(3) / 12.0 * (1.0 - 1.0 / 64.0),
        iy: B * H.powi(3) / 12.0 * (1.0 - 1.0 / 16.0),
        j: 1e-6,
    }
}

/// Cantilever along global X from the origin, local y = global Y, local z = global Z.
fn cantilever(n_el: usize, form: Formulation) -> Model {
    let p = props();
    let mut elements: Vec<Box<dyn BeamColumn>> = Vec::new();
    for k in 0..n_el {
        let x = |k: usize| Vector3::new(L * k as f64 / n_el as f64, 0.0, 0.0);
        let section = match form {
            Formulation::Elastic(_) => None,
            _ => Some(Box::new(
                FiberSection::new(
                    rectangle_fibers(B, H, 8, 4, &LinearElastic::new(E)),
                    p.g * p.j,
                )
                .unwrap(),
            ) as Box<dyn fem2rbd_fe::fe::section::Section>),
        };
        elements.push(
            BeamColumnSpec {
                tag: k as i64 + 1,
                nodes: [k, k + 1],
                xi: x(k),
                xj: x(k + 1),
                transform: TransformKind::Corotational,
                vecxz: Vector3::new(0.0, 0.0, 1.0),
                formulation: form,
                section,
            }
            .build()
            .unwrap(),
        );
    }
    Model::new(n_el + 1, elements, (0..6).collect())
}

fn forms() -> Vec<(&'static str, Formulation)> {
    vec![
        ("elastic", Formulation::Elastic(props())),
        (
            "force-based fiber",
            Formulation::ForceBased {
                n_ip: 5,
                options: ForceBeamOptions {
                    max_iter: 50,
                    tol: 1e-12,
                    ..Default::default()
                },
            },
        ),
        ("disp-based fiber", Formulation::DispBased { n_ip: 5 }),
    ]
}

#[test]
fn end_moment_curls_cantilever_into_a_circle() {
    let n_el = 16;
    let ei = E * props().iz;
    let m = 2.0 * std::f64::consts::PI * ei / L;
    for (name, form) in forms() {
        let mut model = cantilever(n_el, form);
        let mut load = DVector::zeros(6 * (n_el + 1));
        load[6 * n_el + 5] = m;
        let iters = model.solve(&load, 20).unwrap();
        let tip = 6 * n_el;
        let (ux, uy, rz) = (model.u[tip], model.u[tip + 1], model.u[tip + 5]);
        // Half-way node: the diameter of the circle L/π straight up.
        let mid = 6 * (n_el / 2);
        let (mx, my) = (L / 2.0 + model.u[mid], model.u[mid + 1]);
        println!(
            "{name:>18}: tip ux/L + 1 = {:+.3e} (→ 0), uy/L {:+.3e} (→ 0), rz {:.9} (2π = {:.9}); \
             mid-node at ({mx:.6}, {my:.6}) (circle: (0, {:.6})); Newton iterations/step max {}",
            ux / L + 1.0,
            uy / L,
            rz,
            2.0 * std::f64::consts::PI,
            L / std::f64::consts::PI,
            iters.iter().max().unwrap()
        );
        assert!((ux + L).abs() < 1e-8 * L, "{name}: tip ux = {ux}");
        assert!(uy.abs() < 1e-8 * L, "{name}: tip uy = {uy}");
        assert!(
            (rz - 2.0 * std::f64::consts::PI).abs() < 1e-8,
            "{name}: rz = {rz}"
        );
        // Mid node: on a regular 16-gon of side L/16 the opposite vertex is at the
        // circumscribed diameter (L/16)/sin(π/16).
        let d = (L / n_el as f64) / (std::f64::consts::PI / n_el as f64).sin();
        assert!(
            mx.abs() < 1e-8 && (my - d).abs() < 1e-8,
            "{name}: mid ({mx}, {my})"
        );
        assert!(
            *iters.iter().max().unwrap() <= 8,
            "{name}: Newton iterations {iters:?}"
        );
        // Deformed frame hand-off: the last element points back along −X... rotated by
        // 2π·(n−½)/n about z; its centroid lies on the polygon.
        let frame = model.elements[n_el - 1].deformed_frame();
        let angle = 2.0 * std::f64::consts::PI * (n_el as f64 - 0.5) / n_el as f64;
        let x_axis = Vector3::new(angle.cos(), angle.sin(), 0.0);
        assert!(
            (frame.axes.column(0) - x_axis).norm() < 1e-8,
            "{name}: {}",
            frame.axes
        );
        assert!((frame.axes.column(2) - Vector3::z()).norm() < 1e-8);
    }
}

#[test]
fn tip_load_elastica_matches_mattiasson() {
    let ei = E * props().iz;
    let p = ei / (L * L); // P L²/EI = 1
    for (name, form, n_el) in [
        ("elastic", forms()[0].1, 20),
        ("force-based fiber", forms()[1].1, 10),
        ("disp-based fiber", forms()[2].1, 10),
    ] {
        let mut model = cantilever(n_el, form);
        let mut load = DVector::zeros(6 * (n_el + 1));
        load[6 * n_el + 1] = p;
        let iters = model.solve(&load, 5).unwrap();
        let tip = 6 * n_el;
        let u = -model.u[tip] / L;
        let v = model.u[tip + 1] / L;
        println!(
            "{name:>18} ({n_el} el.): u/L = {u:.5} (Mattiasson 0.05643), v/L = {v:.5} (0.30172), \
             Newton iterations/step {iters:?}"
        );
        assert!((u - 0.05643).abs() < 2e-4, "{name}: u/L = {u}");
        assert!((v - 0.30172).abs() < 2e-4, "{name}: v/L = {v}");
    }
}

//! Trial/commit/revert protocol of the elements (the analysis layer's step fallbacks rely
//! on it), initial stiffness, damage reporting and the force-based element's clean
//! failure when no compatible state exists.

use super::support;

use fem2rbd_fe::fe::element::beam::{BeamColumn, BeamColumnSpec, Formulation};
use fem2rbd_fe::fe::element::{EndDisplacements, ForceBeamOptions, Vec12};
use fem2rbd_fe::fe::section::fiber::FiberSection;
use fem2rbd_fe::fe::transform::TransformKind;
use nalgebra::Vector3;
use support::{rectangle_fibers, ElasticPerfectlyPlastic};

const E: f64 = 200e9;
const FY: f64 = 250e6;

fn element(form: Formulation, kind: TransformKind) -> Box<dyn BeamColumn> {
    let section = FiberSection::new(
        rectangle_fibers(0.1, 0.2, 4, 20, &ElasticPerfectlyPlastic::new(E, FY)),
        1e6,
    )
    .unwrap();
    BeamColumnSpec {
        tag: 7,
        nodes: [0, 1],
        xi: Vector3::new(0.0, 0.0, 0.0),
        xj: Vector3::new(0.0, 0.0, 2.0),
        transform: kind,
        vecxz: Vector3::new(1.0, 0.0, 0.0),
        formulation: form,
        section: Some(Box::new(section)),
    }
    .build()
    .unwrap()
}

fn forms() -> Vec<Formulation> {
    vec![
        Formulation::ForceBased {
            n_ip: 5,
            options: ForceBeamOptions {
                max_iter: 50,
                tol: 1e-12,
                ..Default::default()
            },
        },
        Formulation::DispBased { n_ip: 5 },
    ]
}

/// Totals and increments of a two-node element, owned ([`EndDisplacements`] borrows).
struct Disp(Vec12, Vec12);

impl Disp {
    fn view(&self) -> EndDisplacements<'_> {
        EndDisplacements {
            total: self.0.as_slice(),
            delta: self.1.as_slice(),
        }
    }
}

fn disp(total: Vec12, prev: Vec12) -> Disp {
    Disp(total, total - prev)
}

#[test]
fn revert_restores_the_committed_state() {
    for kind in [TransformKind::Linear, TransformKind::Corotational] {
        for form in forms() {
            let mut el = element(form, kind);
            // Column top pushed sideways (global X) into the plastic range, and rotated.
            let mut u1 = Vec12::zeros();
            u1[6] = 0.02;
            u1[10] = 0.01;
            el.set_trial(&disp(u1, Vec12::zeros()).view()).unwrap();
            el.commit_state();
            let f1 = el.resisting_force();
            let k1 = el.tangent_stiffness();
            let d1 = el.damage();
            assert!(d1.yielded, "{kind:?} {form:?}: yielded at 1 % drift");
            // A trial further on, then revert.
            let mut u2 = u1;
            u2[6] = 0.05;
            u2[9] = 0.03;
            el.set_trial(&disp(u2, u1).view()).unwrap();
            assert!((el.resisting_force() - &f1).norm() > 1e-3 * f1.norm());
            el.revert_to_last_commit();
            let fr = el.resisting_force();
            assert!(
                (&fr - &f1).norm() <= 1e-9 * f1.norm(),
                "{kind:?} {form:?}: after revert {fr} vs {f1}"
            );
            assert!(
                (el.tangent_stiffness() - &k1).norm() <= 1e-9 * k1.norm(),
                "{kind:?} {form:?}: tangent after revert"
            );
            // Setting the committed displacements again gives the committed forces.
            el.set_trial(&disp(u1, u1).view()).unwrap();
            assert!((el.resisting_force() - &f1).norm() <= 1e-8 * f1.norm());
            // Unloading back to zero leaves a residual (plastic) force state for the
            // disp-based element's sections, but the initial stiffness is unchanged and
            // equals the tangent of a fresh element.
            let fresh = element(form, kind);
            assert!(
                (el.initial_stiffness() - &fresh.tangent_stiffness()).norm()
                    <= 1e-9 * fresh.tangent_stiffness().norm()
            );
            // The section states report the extreme fiber strains of the trial state.
            let st = el.section_states();
            assert_eq!(st.len(), 5);
            assert!(st[0].damage.max_strain > FY / E && st[0].damage.min_strain < -FY / E);
            // The hand-off frame follows the top node.
            let fr = el.deformed_frame();
            assert!((fr.node_j - Vector3::new(0.02, 0.0, 2.0)).norm() < 1e-12);
            assert!((fr.centroid() - Vector3::new(0.01, 0.0, 1.0)).norm() < 1e-12);
        }
    }
}

#[test]
fn force_based_element_reports_failure_beyond_capacity() {
    // An axial shortening far beyond the squash load: every fiber yields, the section
    // flexibility does not exist and the element cannot find compatible forces.
    let mut el = element(forms()[0], TransformKind::Linear);
    let mut u = Vec12::zeros();
    u[8] = -0.001; // top moves down 1 mm: ε = −5e-4, elastic
    el.set_trial(&disp(u, Vec12::zeros()).view()).unwrap();
    el.commit_state();
    let f = el.resisting_force();
    // Resisting force at the top node, global Z: N = −EA ε.
    assert!(
        (f[8] + E * 0.02 * 5e-4).abs() < 1e-6 * E * 0.02 * 5e-4,
        "{}",
        f[8]
    );
    let mut u2 = u;
    u2[8] = -0.02; // ε = −1e-2 ≫ εy: all fibers yield, no tangent
    let err = el.set_trial(&disp(u2, u).view()).unwrap_err();
    assert_eq!(err.element, 7);
    assert!(err.reason.contains("compatible"), "{}", err.reason);
    el.revert_to_last_commit();
    assert!((el.resisting_force() - &f).norm() < 1e-9 * f.norm());
}

#[test]
fn beam_column_converts_to_plain_element() {
    let el = element(forms()[1], TransformKind::PDelta);
    let k = el.initial_stiffness();
    let plain: Box<dyn fem2rbd_fe::fe::element::Element> = el.into_element();
    assert_eq!(plain.tag(), 7);
    assert_eq!(plain.nodes(), [0, 1]);
    assert_eq!(plain.initial_stiffness(), k);
}

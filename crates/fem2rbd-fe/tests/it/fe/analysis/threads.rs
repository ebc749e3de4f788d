//! Element state determination on several threads gives the same bits as on one: frame3's
//! displacement-based fibre model is driven far into the nonlinear range (cyclic sway of
//! the roof to ±4 % drift in 24 committed steps), and every element's resisting force,
//! tangent and damage must be identical with 1, 2 and 3 threads. A chain of failing
//! elements checks that the error reported is the first in element order, as a sequential
//! loop reports it, and that every element was still updated.
use super::support::{square, ElasticFrame, FailMode, Failing};
use fem2rbd_fe::fe::build::{build_domain, BuildOptions, Variant};
use fem2rbd_fe::fe::domain::Domain;
use fem2rbd_fe::model::Model;

fn frame3(threads: usize) -> Domain {
    let model = Model::load(crate::repo_root().join("data/frame3-standin/model.toml")).unwrap();
    let options = BuildOptions {
        variant: Variant::Disp,
        ..BuildOptions::default()
    };
    let mut d = build_domain(&model, &options).unwrap().domain;
    d.set_threads(threads);
    d
}

/// Trial displacements of step `s`: every free node sways in x and y in proportion to its
/// height (roof drift `amp`), with a little twist, cycling with growing amplitude.
fn sway(d: &Domain, s: usize) -> Vec<f64> {
    let h = d.nodes().iter().map(|n| n.coords[2]).fold(0.0, f64::max);
    let amp = 0.04 * h * (s as f64 / 24.0) * (s as f64 * 0.7).sin();
    let mut u = vec![0.0; d.num_equations()];
    for (i, n) in d.nodes().iter().enumerate() {
        let r = n.coords[2] / h;
        let twist = 0.05 * (n.coords[0] - n.coords[1]);
        for (dof, v) in [
            (0, amp * r * (1.0 + twist)),
            (1, -0.6 * amp * r),
            (2, -1e-4 * r),
        ] {
            if let Some(e) = d.equation(i, dof) {
                u[e] = v;
            }
        }
    }
    u
}

#[test]
fn frame3_state_determination_is_bit_identical_for_any_thread_count() {
    let mut domains: Vec<Domain> = [1, 2, 3].map(frame3).into();
    assert!(
        domains[0].elements().len() >= 32,
        "too few elements to split"
    );
    let mut nonlinear = false;
    for s in 1..=24 {
        for d in &mut domains {
            let u = sway(d, s);
            d.set_trial_eq(&u, None, None).unwrap();
            d.commit();
        }
        let reference = &domains[0];
        for d in &domains[1..] {
            for (a, b) in reference.elements().iter().zip(d.elements()) {
                let (fa, fb) = (a.resisting_force(), b.resisting_force());
                assert!(
                    fa.iter()
                        .zip(fb.iter())
                        .all(|(x, y)| x.to_bits() == y.to_bits()),
                    "step {s}, element {}: forces differ with {} threads",
                    a.tag(),
                    d.threads()
                );
                let (ka, kb) = (a.tangent_stiffness(), b.tangent_stiffness());
                assert!(ka
                    .iter()
                    .zip(kb.iter())
                    .all(|(x, y)| x.to_bits() == y.to_bits()));
                assert_eq!(a.damage(), b.damage());
            }
        }
        nonlinear |= reference.elements().iter().any(|e| e.damage().yielded);
    }
    assert!(
        nonlinear,
        "the sway never yielded a fibre: the test is not nonlinear"
    );
}

#[test]
fn the_first_error_in_element_order_is_reported_and_all_elements_updated() {
    for threads in [1, 2, 4] {
        let mut d = Domain::new();
        d.set_threads(threads);
        let n = 80;
        for i in 0..=n {
            d.add_node(i as i64, [i as f64, 0.0, 0.0]).unwrap();
        }
        d.fix(0, [true; 6]).unwrap();
        for i in 0..n {
            let frame = ElasticFrame::new(
                i as i64 + 1,
                &d,
                i,
                i + 1,
                [0.0, 0.0, 1.0],
                square(3e10, 0.3),
            );
            // Elements 41.. fail once any end displacement exceeds their limit; element 41's
            // limit is the smallest reached, but elements 60.. have a lower one.
            let mode = match i + 1 {
                41..=59 => FailMode::ErrorBeyond(0.5),
                60.. => FailMode::ErrorBeyond(0.1),
                _ => FailMode::ErrorBeyond(f64::INFINITY),
            };
            d.add_element(Box::new(Failing::new(frame, mode))).unwrap();
        }
        d.number_dofs();
        let u: Vec<f64> = (0..d.num_equations()).map(|_| 1.0).collect();
        let err = d.set_trial_eq(&u, None, None).unwrap_err();
        assert_eq!(err.element, 41, "{threads} threads");
        // Every element saw the trial state, including those after the first failure: their
        // forces were zero before (no displacement) and are not now.
        for e in d.elements() {
            assert!(
                e.resisting_force().amax() > 0.0,
                "element {} not updated",
                e.tag()
            );
        }
    }
}

/// Gravity, then 0.4 s of a 0.8 g sine pulse train in X and 0.6 g in Y on frame3's
/// displacement-based model: every recorded displacement, velocity and acceleration is
/// the same bits with 1, 2 and 3 threads (element forces and stiffnesses formed on the
/// threads, assembly and the sparse solver in a fixed order), and the run is nonlinear.
#[test]
fn frame3_transient_is_bit_identical_for_any_thread_count() {
    use fem2rbd_fe::fe::analysis::rayleigh::RayleighDamping;
    use fem2rbd_fe::fe::analysis::static_analysis::{load_control, LoadControl};
    use fem2rbd_fe::fe::analysis::transient::{run_transient, StepControl, TransientSettings};
    let run = |threads: usize| {
        let mut d = frame3(threads);
        load_control(&mut d, &LoadControl::default()).unwrap();
        d.load_const();
        let damping = RayleighDamping::default_for_period(0.316).unwrap();
        let g = 9.81;
        let ground = |t: f64| {
            let s = (2.0 * std::f64::consts::PI * t / 0.3).sin();
            [0.8 * g * s, 0.6 * g * s, 0.0]
        };
        let settings = TransientSettings {
            t_end: 0.4,
            ..Default::default()
        };
        let r = run_transient(&mut d, Some(damping), &ground, &settings, &mut |_, _| {
            StepControl::Continue
        })
        .unwrap();
        let yielded = d.elements().iter().any(|e| e.damage().yielded);
        (r, yielded)
    };
    let (reference, yielded) = run(1);
    assert_eq!(reference.steps, 80);
    assert!(yielded, "no fibre yielded: the run is not nonlinear");
    let bits = |h: &fem2rbd_fe::fe::analysis::transient::History| -> Vec<u64> {
        [&h.disp, &h.vel, &h.acc]
            .iter()
            .flat_map(|f| f.iter().flatten().flatten().map(|x| x.to_bits()))
            .collect()
    };
    let want = bits(&reference.history);
    for threads in [2, 3] {
        let (r, _) = run(threads);
        assert_eq!(r.steps, reference.steps, "{threads} threads");
        assert!(
            bits(&r.history) == want,
            "{threads} threads: histories differ from 1 thread"
        );
    }
}

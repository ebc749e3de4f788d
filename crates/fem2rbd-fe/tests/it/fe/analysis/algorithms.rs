//! The equilibrium algorithms on a nonlinear (hardening cubic) spring under a static
//! load, against the root of k δ + k3 δ³ = P.
use super::support as fe_analysis_support;

use fe_analysis_support::CubicSpring;
use fem2rbd_fe::fe::analysis::static_analysis::{load_control, LoadControl};
use fem2rbd_fe::fe::analysis::{Algorithm, AnalysisError, ConvergenceTest, IterationFailure};
use fem2rbd_fe::fe::domain::Domain;

const K: f64 = 1000.0;

/// Spring from a fixed node to a node free in X only, loaded by P; k3 chosen so that
/// the tangent at the solution is `ratio` × k.
fn spring(ratio: f64) -> (Domain, f64) {
    let delta = 0.1;
    let k3 = (ratio - 1.0) * K / (3.0 * delta * delta);
    let p = K * delta + k3 * delta.powi(3);
    let mut d = Domain::new();
    d.add_node(1, [0.0; 3]).unwrap();
    d.add_node(2, [1.0, 0.0, 0.0]).unwrap();
    d.fix(0, [true; 6]).unwrap();
    d.fix(1, [false, true, true, true, true, true]).unwrap();
    d.add_element(Box::new(CubicSpring {
        tag: 1,
        nodes: [0, 1],
        k: K,
        k3,
        delta: 0.0,
    }))
    .unwrap();
    d.add_nodal_load(1, [p, 0.0, 0.0, 0.0, 0.0, 0.0]).unwrap();
    (d, delta)
}

fn solve(ratio: f64, alg: Algorithm, max_iter: usize) -> Result<(f64, usize), AnalysisError> {
    let (mut d, _) = spring(ratio);
    let s = LoadControl {
        steps: 1,
        test: ConvergenceTest {
            tol: 1e-12,
            max_iter,
        },
        algorithms: vec![alg],
    };
    let steps = load_control(&mut d, &s)?;
    Ok((d.displacement(1)[0], steps[0].iterations))
}

#[test]
fn every_algorithm_finds_the_root() {
    // Tangent at the solution 1.3 k: modified Newton with k converges (rate 0.3).
    let algs = [
        Algorithm::Newton,
        Algorithm::ModifiedNewtonInitial,
        Algorithm::KrylovNewton { max_dim: 3 },
        Algorithm::NewtonLineSearch { ratio: 0.8 },
    ];
    let mut its = Vec::new();
    for alg in algs {
        let (u, it) = solve(1.3, alg, 100).unwrap();
        eprintln!("{alg:?}: δ = {u}, {it} iterations");
        assert!((u - 0.1).abs() < 1e-11, "{alg:?}: {u}");
        its.push(it);
    }
    // Newton is quadratic; Krylov accelerates modified Newton.
    assert!(its[0] < its[1] && its[2] < its[1], "{its:?}");
}

/// Tangent at the solution 2.5 k: modified Newton with the initial stiffness diverges
/// (|1 − 2.5| > 1); Krylov-Newton and Newton converge. The failure is an error naming
/// the step; the domain keeps the last converged state (zero).
#[test]
fn krylov_converges_where_modified_newton_diverges() {
    let err = solve(2.5, Algorithm::ModifiedNewtonInitial, 200).unwrap_err();
    match &err {
        AnalysisError::StaticStepFailed {
            step: 1, reason, ..
        } => {
            assert!(matches!(
                reason,
                IterationFailure::NotConverged { .. } | IterationFailure::NonFiniteResidual
            ));
        }
        other => panic!("{other:?}"),
    }
    let (u, it) = solve(2.5, Algorithm::KrylovNewton { max_dim: 3 }, 100).unwrap();
    eprintln!("Krylov: {it} iterations");
    assert!((u - 0.1).abs() < 1e-11, "{u}");
    let (u, _) = solve(2.5, Algorithm::Newton, 100).unwrap();
    assert!((u - 0.1).abs() < 1e-11, "{u}");
}

/// Fallback order in load control: a failing first algorithm is followed by the next;
/// the state is reverted in between.
#[test]
fn static_fallback_chain() {
    let (mut d, _) = spring(2.5);
    let s = LoadControl {
        steps: 2,
        test: ConvergenceTest {
            tol: 1e-12,
            max_iter: 100,
        },
        algorithms: vec![Algorithm::ModifiedNewtonInitial, Algorithm::Newton],
    };
    load_control(&mut d, &s).unwrap();
    assert!((d.displacement(1)[0] - 0.1).abs() < 1e-11);
}

/// Displacement control through the limit point of a softening spring
/// (k3 < 0: N peaks at δ = √(k/(3|k3|))): λ·P_ref = k δ + k3 δ³ at every step, on the
/// rising and the falling branch, where load control cannot go.
#[test]
fn displacement_control_passes_limit_point() {
    use fem2rbd_fe::fe::analysis::static_analysis::{displacement_control, DisplacementControl};
    let k3 = -K / (3.0 * 0.2f64.powi(2)); // peak at δ = 0.2
    let mut d = Domain::new();
    d.add_node(1, [0.0; 3]).unwrap();
    d.add_node(2, [1.0, 0.0, 0.0]).unwrap();
    d.fix(0, [true; 6]).unwrap();
    d.fix(1, [false, true, true, true, true, true]).unwrap();
    d.add_element(Box::new(CubicSpring {
        tag: 1,
        nodes: [0, 1],
        k: K,
        k3,
        delta: 0.0,
    }))
    .unwrap();
    d.add_nodal_load(1, [10.0, 0.0, 0.0, 0.0, 0.0, 0.0])
        .unwrap();
    let s = DisplacementControl {
        node: 1,
        dof: 0,
        increment: 0.01,
        steps: 30,
        test: ConvergenceTest {
            tol: 1e-12,
            max_iter: 50,
        },
        fallbacks: true,
    };
    let steps = displacement_control(&mut d, &s).unwrap();
    let mut peak: f64 = 0.0;
    for (i, st) in steps.iter().enumerate() {
        let delta = 0.01 * (i + 1) as f64;
        let n = K * delta + k3 * delta.powi(3);
        assert!(
            (st.load_factor * 10.0 - n).abs() < 1e-8,
            "step {i}: {} vs {n}",
            st.load_factor * 10.0
        );
        peak = peak.max(st.load_factor * 10.0);
    }
    assert!((d.displacement(1)[0] - 0.3).abs() < 1e-12);
    // Peak N = 2/3 k δ_peak, and the end is on the falling branch.
    assert!((peak - 2.0 / 3.0 * K * 0.2).abs() < 1e-9, "{peak}");
    assert!(steps.last().unwrap().load_factor * 10.0 < peak * 0.9);
    // A DOF that is fixed is an input error, not a panic.
    let bad = DisplacementControl { dof: 1, ..s };
    assert!(matches!(
        displacement_control(&mut d, &bad),
        Err(AnalysisError::Input(_))
    ));
}

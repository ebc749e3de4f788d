//! The direct (sparse LDLᵀ) solve of the joints' bilateral rows
//! (`World::set_joint_solve`, the shim's `DirectJointSolver`) against closed forms, and
//! its determinism across solver threads.
use fem2rbd::bullet::*;

const G: f64 = 9.81;
const H: f64 = 1.0 / 200.0;

use crate::support::locked_joint as locked;

/// A 1 kg box hangs 1 m below a static anchor and a 100 kg box 1 m below it, both links
/// locked Generic6Dof constraints (pivots at the lower box's centre), h = 1/200 s.
/// Returns (sag of the heavy box after 1 s [m], top link's impulse in the last substep
/// [N·s], the solve's counters).
fn heavy_chain(mode: JointSolve, iterations: u32, warmstart: f64) -> (f64, f64, JointSolveStats) {
    let mut s = WorldSettings::default();
    s.solver.num_iterations = iterations;
    let mut w = World::new(&s).unwrap();
    w.set_joint_solve(mode, 1e-8).unwrap();
    w.set_joint_warmstart(warmstart).unwrap();
    let (_, heavy, top) = crate::support::hanging_chain(&mut w, 0.0);
    w.step(H, 200).unwrap();
    let impulse = w.joint_feedback(top).unwrap().force_b[2] * H;
    (
        3.0 - w.pose(heavy).unwrap().position[2],
        impulse,
        w.joint_solve().unwrap(),
    )
}

/// Closed form: a chain held by locked rows does not sag, and in equilibrium the top link
/// carries both boxes, an impulse (m₁ + m₂)·g·h per substep. The direct solve reaches the
/// rows' fixed point in every substep, so after 1 s the sag is rounding (measured 2·10⁻⁹ m;
/// bound 1 µm). Projected Gauss–Seidel with 4 sweeps falls
/// short of the heavy box's weight and leaves a sag of centimetres (docs/ruin-numerics.md
/// §11). A warm start is replaced by the direct impulse, not added to it.
#[test]
fn direct_joint_solve_holds_a_heavy_chain() {
    let weight_impulse = 101.0 * G * H;
    let (sag, imp, st) = heavy_chain(JointSolve::Direct, 10, 0.0);
    let (sag4, imp4, st4) = heavy_chain(JointSolve::Direct, 4, 0.0);
    let (sag_w, imp_w, _) = heavy_chain(JointSolve::Direct, 10, 0.5);
    let (sag_pgs, imp_pgs, st_pgs) = heavy_chain(JointSolve::Pgs, 4, 0.0);
    println!(
        "sag after 1 s: direct {sag:.3e} m (4 sweeps {sag4:.3e}, warm 0.5 {sag_w:.3e}), \
         pgs 4 sweeps {sag_pgs:.3e} m; top impulse direct {imp:.6} / {imp4:.6} / {imp_w:.6}, \
         pgs {imp_pgs:.6}, (m1+m2) g h {weight_impulse:.6} N·s; {st:?}"
    );
    for (s, i) in [(sag, imp), (sag4, imp4), (sag_w, imp_w)] {
        assert!(s.abs() < 1e-6, "direct: sag {s} m");
        assert!(
            (i - weight_impulse).abs() < 1e-6 * weight_impulse,
            "direct: top impulse {i} vs (m1+m2) g h {weight_impulse}"
        );
    }
    assert!(sag_pgs > 1e-2, "pgs with 4 sweeps sags, got {sag_pgs}");
    assert_eq!(st.mode, JointSolve::Direct);
    assert!(st.solves > 0 && st.fallbacks == 0 && st.rows > 0, "{st:?}");
    assert!(st4.solves > 0 && st4.fallbacks == 0, "{st4:?}");
    assert_eq!((st_pgs.mode, st_pgs.solves), (JointSolve::Pgs, 0));
    let mut w = World::new(&WorldSettings::default()).unwrap();
    assert!(w.set_joint_solve(JointSolve::Direct, f64::NAN).is_err());
    assert!(w.set_joint_solve(JointSolve::Direct, 2.0).is_err());
}

/// Three boxes (2, 5, 20 kg) hang in a chain from a static anchor; each link's vertical
/// row is an implicit spring of stiffness kᵢ given through ERP/CFM
/// ([`fem2rbd::ruin::stage::member_row_erp_cfm`] with the row's effective inverse mass
/// Kᵢ = 1/m_above + 1/m_below, x = √(kᵢKᵢ)·h = 2), the other rows locked. At rest link i
/// stretches by the weight below it over kᵢ, so the lowest box sits Σᵢ (Σ_{j≥i} mⱼ)·g/kᵢ
/// below its start (the rows' fixed point: λᵢ·Cᵢ/Dᵢ = ERPᵢ·eᵢ/h, i.e. λᵢ/h = kᵢ·eᵢ).
/// The direct solve at Bullet's default 10 sweeps lands on it within 0.5 % (measured
/// 0.00 %); PGS alone at 10 sweeps is off by more than 1 % (measured 2.9 %).
#[test]
fn direct_joint_solve_stretches_a_cfm_chain_by_the_closed_form() {
    let masses = [2.0, 5.0, 20.0];
    let run = |mode: JointSolve| {
        let mut w = World::new(&WorldSettings::default()).unwrap();
        w.set_joint_solve(mode, 1e-8).unwrap();
        let anchor = w
            .add_box(&BoxDesc::fixed([0.1; 3], Pose::at([0.0, 0.0, 5.0])))
            .unwrap();
        let mut above: Option<(BodyHandle, f64)> = None;
        let mut expected = 0.0;
        let mut last = anchor;
        for (i, &m) in masses.iter().enumerate() {
            let z = 4.0 - i as f64;
            let b = w
                .add_box(&BoxDesc::dynamic([0.1; 3], m, Pose::at([0.0, 0.0, z])))
                .unwrap();
            let k_inv = 1.0 / m + above.map_or(0.0, |(_, ma)| 1.0 / ma);
            let k = 4.0 / (H * H * k_inv); // x = 2
            let (erp, cfm) = fem2rbd::ruin::stage::member_row_erp_cfm(k, k_inv, H, 1.0);
            let c = locked(
                &mut w,
                above.map_or(anchor, |(a, _)| a),
                b,
                [0.0, 0.0, -1.0],
                [0.0; 3],
            );
            w.set_constraint_param(c, ConstraintParam::StopErp, 2, erp)
                .unwrap();
            w.set_constraint_param(c, ConstraintParam::StopCfm, 2, cfm)
                .unwrap();
            let below: f64 = masses[i..].iter().sum();
            expected += below * G / k;
            above = Some((b, m));
            last = b;
        }
        w.step(H, 400).unwrap();
        let z0 = 4.0 - (masses.len() - 1) as f64;
        (
            z0 - w.pose(last).unwrap().position[2],
            expected,
            w.joint_solve().unwrap(),
        )
    };
    let (ext, expected, st) = run(JointSolve::Direct);
    let (ext_pgs, _, _) = run(JointSolve::Pgs);
    println!(
        "chain extension: direct {ext:.4e} m, pgs (10 sweeps) {ext_pgs:.4e} m, \
         closed form {expected:.4e} m; {st:?}"
    );
    assert!(
        (ext - expected).abs() < 0.005 * expected,
        "direct: extension {ext} vs Σ m g / k {expected}"
    );
    assert!(
        (ext_pgs - expected).abs() > 0.01 * expected,
        "pgs: extension {ext_pgs} vs Σ m g / k {expected}"
    );
    assert!(st.solves > 0 && st.fallbacks == 0, "{st:?}");
}

/// A portal frame (two columns and a beam, every joint locked, both feet on a static
/// ground: a closed loop, so A is singular without the regularisation), a separate hanging
/// chain and a box dropped onto the ground, with the direct solve: the same bits with 1 and
/// 2 solver threads, no fallback, and the frame's beam stays within 1 µm of its start
/// (measured 2·10⁻¹¹ m).
#[test]
fn direct_joint_solve_is_deterministic_across_threads() {
    let run = |threads: usize| {
        let mut w = World::new(&WorldSettings::default()).unwrap();
        w.set_solver_threads(threads).unwrap();
        w.set_joint_solve(JointSolve::Direct, 1e-8).unwrap();
        let ground = w
            .add_box(&BoxDesc::fixed([5.0, 5.0, 0.5], Pose::at([0.0, 0.0, -0.5])))
            .unwrap();
        let c1 = w
            .add_box(&BoxDesc::dynamic(
                [0.1, 0.1, 1.0],
                50.0,
                Pose::at([-1.0, 0.0, 1.0]),
            ))
            .unwrap();
        let c2 = w
            .add_box(&BoxDesc::dynamic(
                [0.1, 0.1, 1.0],
                50.0,
                Pose::at([1.0, 0.0, 1.0]),
            ))
            .unwrap();
        let beam = w
            .add_box(&BoxDesc::dynamic(
                [1.2, 0.1, 0.1],
                400.0,
                Pose::at([0.0, 0.0, 2.1]),
            ))
            .unwrap();
        locked(&mut w, ground, c1, [-1.0, 0.0, 0.5], [0.0, 0.0, -1.0]);
        locked(&mut w, ground, c2, [1.0, 0.0, 0.5], [0.0, 0.0, -1.0]);
        locked(&mut w, c1, beam, [0.0, 0.0, 1.0], [-1.0, 0.0, -0.1]);
        locked(&mut w, c2, beam, [0.0, 0.0, 1.0], [1.0, 0.0, -0.1]);
        crate::support::hanging_chain(&mut w, 3.0);
        w.add_box(&BoxDesc::dynamic(
            [0.2; 3],
            10.0,
            Pose::at([-3.0, 1.0, 1.0]),
        ))
        .unwrap();
        w.step(H, 200).unwrap();
        let sag = 2.1 - w.pose(beam).unwrap().position[2];
        (
            w.poses().unwrap(),
            w.velocities().unwrap(),
            sag,
            w.joint_solve().unwrap(),
        )
    };
    let (p1, v1, sag, st) = run(1);
    let (p2, v2, _, st2) = run(2);
    println!("portal beam sag {sag:.3e} m; {st:?}");
    assert!(st.solves > 0 && st.fallbacks == 0, "{st:?}");
    assert_eq!((st.rows, st.fallbacks), (st2.rows, st2.fallbacks));
    assert!(sag.abs() < 1e-6, "portal beam sag {sag}");
    for (x, y) in p1.iter().zip(&p2) {
        for k in 0..3 {
            assert_eq!(x.position[k].to_bits(), y.position[k].to_bits());
        }
        for k in 0..4 {
            assert_eq!(x.orientation[k].to_bits(), y.orientation[k].to_bits());
        }
    }
    for (x, y) in v1.iter().zip(&v2) {
        for k in 0..3 {
            assert_eq!(x.linear[k].to_bits(), y.linear[k].to_bits());
            assert_eq!(x.angular[k].to_bits(), y.angular[k].to_bits());
        }
    }
}

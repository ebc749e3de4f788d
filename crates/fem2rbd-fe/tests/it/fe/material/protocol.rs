//! The trial/commit/revert protocol and damage flags of every material built through
//! `fem2rbd_fe::fe::material::build` (OpenSees type and parameter names).

use std::collections::BTreeMap;

use fem2rbd_fe::fe::material::{build, UniaxialMaterial};

fn map(kv: &[(&str, f64)]) -> BTreeMap<String, f64> {
    kv.iter().map(|(k, v)| (k.to_string(), *v)).collect()
}

/// (name, type, parameters, reference strain) — frame3's materials and the other laws.
fn materials() -> Vec<(&'static str, &'static str, BTreeMap<String, f64>, f64)> {
    let steel = [("Fy", 457.7e6), ("E0", 2e11), ("b", 0.01)];
    let mut s02 = steel.to_vec();
    s02.extend([("R0", 18.0), ("cR1", 0.925), ("cR2", 0.15)]);
    let mut s02i = s02.clone();
    s02i.extend([("a1", 0.04), ("a2", 1.0), ("a3", 0.04), ("a4", 1.0)]);
    let c = [
        ("fpc", -22.5e6),
        ("epsc0", -0.0018),
        ("fpcu", -4.5e6),
        ("epscu", -0.004),
    ];
    let mut c2 = c.to_vec();
    c2.extend([("lambda", 0.1), ("ft", 1.5653e6), ("Ets", 7.8266e8)]);
    let ey = 457.7e6 / 2e11;
    vec![
        (
            "elastic",
            "Elastic",
            map(&[("E", 2e11), ("Eneg", 1e11)]),
            1e-3,
        ),
        ("steel01", "Steel01", map(&steel), ey),
        ("steel02", "Steel02", map(&s02), ey),
        ("steel02_iso", "Steel02", map(&s02i), ey),
        ("concrete01", "Concrete01", map(&c), 0.0018),
        ("concrete02", "Concrete02", map(&c2), 0.0018),
    ]
}

/// Deterministic pseudo-random numbers in [-0.5, 0.5).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    }
}

fn state(m: &dyn UniaxialMaterial) -> (f64, f64, f64) {
    (m.strain(), m.stress(), m.tangent())
}

/// Newton-like iterations (several trial strains before each commit), failed steps
/// (revert) and boxed clones must leave the path identical to a material that only sees
/// the converged strains.
#[test]
fn iterations_reverts_and_clones_do_not_change_the_path() {
    for (name, kind, params, refe) in materials() {
        let mut iterated = build(kind, &params).unwrap();
        let mut direct = build(kind, &params).unwrap();
        let mut rng = Lcg(7);
        let mut eps = 0.0;
        for step in 0..3000 {
            eps += 0.6 * refe * rng.next() - 0.001 * eps;
            // Trial iterates, including overshoots and the committed strain itself.
            for k in 0..3 {
                iterated.set_trial_strain(eps + 2.0 * refe * rng.next() * (3 - k) as f64);
            }
            iterated.set_trial_strain(iterated.strain());
            if step % 7 == 3 {
                // A failed step: revert must restore exactly the committed state.
                let before = {
                    let mut probe = iterated.boxed_clone();
                    probe.revert_to_last_commit();
                    state(probe.as_ref())
                };
                iterated.set_trial_strain(eps + 5.0 * refe);
                iterated.revert_to_last_commit();
                assert_eq!(state(iterated.as_ref()), before, "{name} step {step}");
            }
            iterated.set_trial_strain(eps);
            iterated.set_trial_strain(eps);
            direct.set_trial_strain(eps);
            assert_eq!(
                state(iterated.as_ref()),
                state(direct.as_ref()),
                "{name}: trial at step {step} depends on earlier uncommitted trials"
            );
            // A clone continues independently and identically.
            let mut clone = iterated.boxed_clone();
            iterated.commit_state();
            direct.commit_state();
            clone.commit_state();
            assert_eq!(state(clone.as_ref()), state(direct.as_ref()));
            assert_eq!(iterated.damage(), direct.damage());
        }
        // revert_to_start returns to the virgin material.
        iterated.revert_to_start();
        let fresh = build(kind, &params).unwrap();
        assert_eq!(state(iterated.as_ref()), state(fresh.as_ref()), "{name}");
        assert_eq!(iterated.damage(), fresh.damage());
        assert_eq!(iterated.tangent(), fresh.initial_tangent(), "{name}");
    }
}

fn drive(m: &mut dyn UniaxialMaterial, eps: f64) {
    m.set_trial_strain(eps);
    m.commit_state();
}

#[test]
fn steel_damage_flags() {
    for kind in ["Steel01", "Steel02"] {
        let p = map(&[
            ("Fy", 400e6),
            ("E0", 2e11),
            ("b", 0.01),
            ("eps_rupture", 0.05),
        ]);
        let mut m = build(kind, &p).unwrap();
        drive(m.as_mut(), -0.99 * 0.002);
        assert!(!m.damage().yielded, "{kind}");
        // A trial beyond yield that is not committed does not count.
        m.set_trial_strain(-0.003);
        assert!(!m.damage().yielded, "{kind}");
        drive(m.as_mut(), -0.0021);
        assert!(m.damage().yielded && !m.damage().ruptured, "{kind}");
        drive(m.as_mut(), 0.049);
        assert!(m.stress() > 400e6, "{kind}");
        m.set_trial_strain(0.0501);
        assert_eq!(
            m.stress(),
            0.0,
            "{kind}: trial past rupture carries no stress"
        );
        assert!(!m.damage().ruptured, "{kind}: not committed yet");
        m.commit_state();
        assert!(m.damage().ruptured, "{kind}");
        for eps in [0.02, -0.01, 0.06] {
            drive(m.as_mut(), eps);
            assert_eq!(
                (m.stress(), m.tangent()),
                (0.0, 0.0),
                "{kind} after rupture"
            );
        }
        // Without eps_rupture the bar never ruptures.
        let mut m = build(kind, &map(&[("Fy", 400e6), ("E0", 2e11), ("b", 0.01)])).unwrap();
        drive(m.as_mut(), 0.2);
        assert!(m.damage().yielded && !m.damage().ruptured && m.stress() > 400e6);
    }
}

#[test]
fn concrete_damage_flags() {
    let c = [
        ("fpc", -30e6),
        ("epsc0", -0.002),
        ("fpcu", -6e6),
        ("epscu", -0.006),
    ];
    for kind in ["Concrete01", "Concrete02"] {
        let mut m = build(kind, &map(&c)).unwrap();
        drive(m.as_mut(), 0.001);
        drive(m.as_mut(), -0.0019);
        assert!(!m.damage().yielded, "{kind}");
        drive(m.as_mut(), -0.002);
        assert!(m.damage().yielded && !m.damage().ruptured, "{kind}");
        drive(m.as_mut(), -0.0059);
        assert!(!m.damage().ruptured, "{kind}");
        drive(m.as_mut(), -0.0061);
        assert!(m.damage().ruptured, "{kind}");
        assert_eq!(m.stress(), -6e6, "{kind}: residual plateau");
        drive(m.as_mut(), 0.0);
        assert!(m.damage().ruptured, "{kind}: damage is permanent");
    }
}

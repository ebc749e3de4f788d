//! fem2rbd's uniaxial materials against openseespy on the same cyclic strain histories.
//!
//! `tests/opensees/materials_ref.py` drives each OpenSees material with `setStrain`
//! (setTrialStrain + commitState per step) and prints strain/stress/tangent as JSON; this
//! test builds the same material with [`fem2rbd_fe::fe::material::build`] from the same
//! OpenSees parameter names, drives it with the same commit-every-step pattern and
//! requires |Δσ| ≤ 1e-6·max(|σ_OpenSees|, σ_scale) and |ΔE_t| ≤ 1e-6·max(|E_OpenSees|,
//! E_scale) at every step, where σ_scale is |fpc| or Fy and E_scale the initial modulus.
//! Requires python3 with openseespy (3.7.1); fails with a clear message without it.

use std::collections::BTreeMap;
use std::path::Path;
use std::process::Command;

use fem2rbd_fe::fe::material::build;
use serde_json::Value;

const REL_TOL: f64 = 1e-6;

fn reference() -> Value {
    let script = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .join("tests/opensees/materials_ref.py");
    let out = Command::new("python3")
        .arg(&script)
        .output()
        .unwrap_or_else(|e| panic!("cannot run python3 {}: {e}", script.display()));
    assert!(
        out.status.success(),
        "{} failed ({}); this test needs python3 with openseespy 3.7.1 \
         (pip install openseespy==3.7.1, see scripts/setup.sh).\nstderr:\n{}",
        script.display(),
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("materials_ref.py printed invalid JSON")
}

fn floats(v: &Value, key: &str) -> Vec<f64> {
    v[key]
        .as_array()
        .unwrap_or_else(|| panic!("missing array '{key}'"))
        .iter()
        .map(|x| f64::from_bits(x.as_u64().expect("IEEE-754 bit pattern as u64")))
        .collect()
}

/// Worst difference found for one quantity: (|Δ| / allowed scale, |Δ|, history, step).
#[derive(Default)]
struct Worst {
    ratio: f64,
    abs: f64,
    at: String,
}

impl Worst {
    fn update(&mut self, ours: f64, theirs: f64, floor: f64, at: impl FnOnce() -> String) {
        let diff = (ours - theirs).abs();
        let ratio = if ours == theirs {
            0.0
        } else if diff.is_nan() {
            f64::INFINITY // a NaN on either side is a failure
        } else {
            diff / theirs.abs().max(floor)
        };
        if ratio > self.ratio || (ratio == 0.0 && self.at.is_empty()) {
            self.ratio = ratio;
            self.abs = diff;
            self.at = at();
        }
    }
}

#[test]
fn materials_match_opensees_on_cyclic_histories() {
    let doc = reference();
    println!("openseespy {}", doc["openseespy"]);
    let mut failures = Vec::new();
    let cases = doc["cases"].as_array().expect("cases");
    assert!(cases.len() >= 5, "too few reference cases");
    for case in cases {
        let name = case["name"].as_str().unwrap();
        let kind = case["type"].as_str().unwrap();
        let params: BTreeMap<String, f64> = case["params"]
            .as_object()
            .unwrap()
            .iter()
            .map(|(k, v)| (k.clone(), v.as_f64().unwrap()))
            .collect();
        let s_scale = case["stress_scale"].as_f64().unwrap();
        let t_scale = case["tangent_scale"].as_f64().unwrap();
        let mut mat = build(kind, &params).unwrap_or_else(|e| panic!("{name}: {e}"));
        let (mut ws, mut wt) = (Worst::default(), Worst::default());
        let mut points = 0usize;
        for hist in case["histories"].as_array().unwrap() {
            let hname = hist["name"].as_str().unwrap();
            let (eps, sig, tan) = (
                floats(hist, "strain_bits"),
                floats(hist, "stress_bits"),
                floats(hist, "tangent_bits"),
            );
            assert!(eps.len() > 50 && eps.len() == sig.len() && eps.len() == tan.len());
            mat.revert_to_start();
            for (i, &e) in eps.iter().enumerate() {
                mat.set_trial_strain(e);
                let (s, t) = (mat.stress(), mat.tangent());
                mat.commit_state();
                let at = || {
                    format!(
                        "{hname} step {i} strain {e:e}: ours {s:e}/{t:e}, OpenSees {:e}/{:e}",
                        sig[i], tan[i]
                    )
                };
                ws.update(s, sig[i], s_scale, at);
                wt.update(t, tan[i], t_scale, at);
                points += 1;
            }
        }
        println!(
            "{name:22} {kind:10} {points:6} steps  worst stress |Δ|/max(|σ|,{s_scale:.3e}) = {:.2e} \
             (|Δ| = {:.2e} Pa)  worst tangent ratio = {:.2e} (|Δ| = {:.2e} Pa)",
            ws.ratio, ws.abs, wt.ratio, wt.abs
        );
        if ws.ratio > REL_TOL {
            failures.push(format!(
                "{name}: stress ratio {:.3e} at {}",
                ws.ratio, ws.at
            ));
        }
        if wt.ratio > REL_TOL {
            failures.push(format!(
                "{name}: tangent ratio {:.3e} at {}",
                wt.ratio, wt.at
            ));
        }
    }
    assert!(
        failures.is_empty(),
        "disagreement with OpenSees:\n{}",
        failures.join("\n")
    );
}

//! Modal periods of a one-bay portal frame (elastic columns and beam) infilled with an
//! elastic layered wall panel (2 × 2 shells sharing the frame's nodes): fem2rbd's beam
//! stiffness (the FE domain built from the frame members) plus `fe::shell`'s wall
//! stiffness and the model's lumped masses, solved densely with the massless DOFs
//! condensed, against openseespy's `eigen` on the script written by
//! `fem2rbd export opensees` for the whole model. First three periods to 1e-6.
//! The same model through the FE domain with the shells as domain elements
//! (`build_domain` + `modal_analysis`, what `fem2rbd modal` runs) with the dense,
//! subspace-iteration and Lanczos eigen solvers, against the same OpenSees periods.
//! Needs python3 with openseespy 3.7.1.
use std::process::Command;

use fem2rbd_fe::export::{opensees_script, OpenSeesOptions};
use fem2rbd_fe::fe::analysis::modal::{modal_analysis, EigenMethod, ModalSettings, ModeSelection};
use fem2rbd_fe::fe::build::{build_domain, BuildOptions};
use fem2rbd_fe::fe::linalg::{SparsePattern, StiffnessKind};
use fem2rbd_fe::fe::shell::model_shell_stiffness;
use fem2rbd_fe::model::{ElementKind, Model};
use nalgebra::{DMatrix, SymmetricEigen};
use serde_json::Value;

const MODEL: &str = r#"name = "portal-with-wall"
transformation = [
  { tag = 1, type = "linear", vecxz = [1.0, 0.0, 0.0] },
  { tag = 2, type = "linear", vecxz = [0.0, 0.0, 1.0] },
]
material = [ { tag = 1, type = "Elastic", E = 200e9 } ]
section = [
  { tag = 1, type = "elastic", E = 30e9, G = 12.5e9, A = 0.16, Iy = 2.1333e-3, Iz = 2.1333e-3, J = 3.6e-3, mass_per_length = 400.0 },
  { tag = 10, type = "layered_shell", density = 2500.0, layers = [
      { type = "elastic", thickness = 0.05, E = 30e9, nu = 0.2 },
      { type = "rebar", thickness = 0.0005, material = 1, angle = 90.0 },
      { type = "rebar", thickness = 0.0005, material = 1, angle = 0.0 },
      { type = "elastic", thickness = 0.05, E = 30e9, nu = 0.2 },
      { type = "elastic", thickness = 0.05, E = 30e9, nu = 0.2 },
  ] },
]
node = [
  { tag = 1, x = 0.0, y = 0.0, z = 0.0 }, { tag = 2, x = 1.5, y = 0.0, z = 0.0 }, { tag = 3, x = 3.0, y = 0.0, z = 0.0 },
  { tag = 4, x = 0.0, y = 0.0, z = 1.5 }, { tag = 5, x = 1.5, y = 0.0, z = 1.5 }, { tag = 6, x = 3.0, y = 0.0, z = 1.5 },
  { tag = 7, x = 0.0, y = 0.0, z = 3.0 }, { tag = 8, x = 1.5, y = 0.0, z = 3.0 }, { tag = 9, x = 3.0, y = 0.0, z = 3.0 },
]
support = [
  { node = 1, dofs = [1, 1, 1, 1, 1, 1] }, { node = 2, dofs = [1, 1, 1, 1, 1, 1] }, { node = 3, dofs = [1, 1, 1, 1, 1, 1] },
]
element = [
  { tag = 1, type_name = "Column", group = 1, type = "elastic_beam_column", nodes = [1, 4], section = 1, transf = 1 },
  { tag = 2, type_name = "Column", group = 1, type = "elastic_beam_column", nodes = [4, 7], section = 1, transf = 1 },
  { tag = 3, type_name = "Column", group = 1, type = "elastic_beam_column", nodes = [3, 6], section = 1, transf = 1 },
  { tag = 4, type_name = "Column", group = 1, type = "elastic_beam_column", nodes = [6, 9], section = 1, transf = 1 },
  { tag = 5, type_name = "Beam", group = 1, type = "elastic_beam_column", nodes = [7, 8], section = 1, transf = 2 },
  { tag = 6, type_name = "Beam", group = 1, type = "elastic_beam_column", nodes = [8, 9], section = 1, transf = 2 },
  { tag = 11, type_name = "Wall", group = 1, type = "shell", nodes = [1, 2, 5, 4], section = 10 },
  { tag = 12, type_name = "Wall", group = 1, type = "shell", nodes = [2, 3, 6, 5], section = 10 },
  { tag = 13, type_name = "Wall", group = 1, type = "shell", nodes = [4, 5, 8, 7], section = 10 },
  { tag = 14, type_name = "Wall", group = 1, type = "shell", nodes = [5, 6, 9, 8], section = 10 },
]
mass = [ { node = 7, m = 8000.0 }, { node = 8, m = 8000.0 }, { node = 9, m = 8000.0 } ]
"#;

/// ω² of K φ = ω² M φ with diagonal M, massless DOFs condensed statically.
fn condensed_omega2(k: &DMatrix<f64>, m: &[f64]) -> Vec<f64> {
    let a: Vec<usize> = (0..m.len()).filter(|&i| m[i] > 0.0).collect();
    let b: Vec<usize> = (0..m.len()).filter(|&i| m[i] <= 0.0).collect();
    let sub = |r: &[usize], c: &[usize]| DMatrix::from_fn(r.len(), c.len(), |i, j| k[(r[i], c[j])]);
    let kab = sub(&a, &b);
    let t = sub(&b, &b).lu().solve(&kab.transpose()).unwrap();
    let kc = sub(&a, &a) - &kab * t;
    let h = DMatrix::from_fn(a.len(), a.len(), |i, j| {
        kc[(i, j)] / (m[a[i]] * m[a[j]]).sqrt()
    });
    let mut w: Vec<f64> = SymmetricEigen::new((&h + h.transpose()) * 0.5)
        .eigenvalues
        .iter()
        .copied()
        .collect();
    w.sort_by(f64::total_cmp);
    w
}

#[test]
fn portal_frame_with_wall_panel_periods_match_opensees() {
    let model = Model::parse(MODEL, "portal.toml", false).unwrap();
    // Frame members through the FE domain (shells removed), all nodes kept.
    let mut frame = model.clone();
    frame
        .elements
        .retain(|e| !matches!(e.kind, ElementKind::Shell { .. }));
    let mut built = build_domain(&frame, &BuildOptions::default()).unwrap();
    let pattern = SparsePattern::new(&mut built.domain);
    let mut kv = pattern.zeros();
    pattern.add_stiffness(&built.domain, StiffnessKind::Initial, 1.0, &mut kv);
    let mut k = pattern.to_dense(&kv);
    let eq = |tag: &u32, dof: usize| built.domain.equation(built.node_index[tag], dof);
    for e in model
        .elements
        .iter()
        .filter(|e| matches!(e.kind, ElementKind::Shell { .. }))
    {
        let (nodes, ke) = model_shell_stiffness(&model, e).unwrap();
        for (a, na) in nodes.iter().enumerate() {
            for (b, nb) in nodes.iter().enumerate() {
                for p in 0..6 {
                    for q in 0..6 {
                        if let (Some(r), Some(c)) = (eq(na, p), eq(nb, q)) {
                            k[(r, c)] += ke[(6 * a + p, 6 * b + q)];
                        }
                    }
                }
            }
        }
    }
    // Lumped masses of the whole model (nodal masses + member and wall self-weight).
    let mut m = vec![0.0; k.nrows()];
    for (tag, mm) in model.lumped_masses() {
        for (p, v) in mm.iter().enumerate() {
            if let Some(r) = eq(&tag, p) {
                m[r] = *v;
            }
        }
    }
    let w2 = condensed_omega2(&k, &m);
    let periods: Vec<f64> = w2[..3]
        .iter()
        .map(|w| 2.0 * std::f64::consts::PI / w.sqrt())
        .collect();

    let dir = tempfile::tempdir().unwrap();
    let script = dir.path().join("portal.py");
    std::fs::write(
        &script,
        opensees_script(&model, "portal.toml", &OpenSeesOptions::default()).unwrap(),
    )
    .unwrap();
    let v: Value =
        crate::openseespy_json(Command::new("python3").arg(&script).args(["eigen", "3"]));
    for (kk, t) in periods.iter().enumerate() {
        let t_os = v["modes"][kk]["T"].as_f64().unwrap();
        eprintln!(
            "mode {}: fem2rbd {t:.9} s, OpenSees {t_os:.9} s ({:+.2e})",
            kk + 1,
            (t - t_os) / t_os
        );
        assert!(((t - t_os) / t_os).abs() < 1e-6);
    }
    // The whole model, shells included, as an FE domain.
    for method in [
        EigenMethod::DenseCondensed,
        EigenMethod::SubspaceIteration {
            tol: 1e-10,
            max_iter: 300,
        },
        EigenMethod::Lanczos {
            tol: 1e-10,
            max_restarts: 200,
        },
    ] {
        let mut whole = build_domain(&model, &BuildOptions::default()).unwrap();
        let modal = modal_analysis(
            &mut whole.domain,
            &ModalSettings {
                selection: ModeSelection::Lowest,
                modes: 3,
                method,
                ..Default::default()
            },
        )
        .unwrap();
        for (kk, t) in modal.periods.iter().enumerate() {
            let t_os = v["modes"][kk]["T"].as_f64().unwrap();
            eprintln!(
                "domain {method:?} mode {}: {t:.9} s ({:+.2e})",
                kk + 1,
                (t - t_os) / t_os
            );
            assert!(
                ((t - t_os) / t_os).abs() < 1e-6,
                "{method:?} mode {}",
                kk + 1
            );
        }
    }
}

/// The Newmark transient (average acceleration, Newton) of the same frame-wall model,
/// shells as domain elements, under a step ground acceleration a_g = 1 m/s² along Y from
/// t = 0, against the exact linear response by modal superposition over all 18 massed
/// modes of the same domain: u(t) = Σ_j φ_j Γ_j (−a_g / ω_j²) (1 − cos ω_j t). Top-node
/// displacement over 0.5 s (two periods of mode 1) with Δt = 1e-4 s; the average-
/// acceleration rule's period error (ω Δt)² / 12 is below 3e-5 for mode 1.
#[test]
fn portal_frame_with_wall_newmark_matches_modal_superposition() {
    use fem2rbd_fe::fe::analysis::transient::{run_transient, StepControl, TransientSettings};
    let model = Model::parse(MODEL, "portal.toml", false).unwrap();
    let mut built = build_domain(&model, &BuildOptions::default()).unwrap();
    let modes = built
        .domain
        .mass_diagonal()
        .iter()
        .filter(|&&m| m > 0.0)
        .count();
    let modal = modal_analysis(
        &mut built.domain,
        &ModalSettings {
            selection: ModeSelection::Lowest,
            modes,
            method: EigenMethod::DenseCondensed,
            ..Default::default()
        },
    )
    .unwrap();
    let top = built.node_index[&8];
    let (ag, dir) = (1.0, 1);
    let exact = |t: f64| -> f64 {
        (0..modes)
            .map(|j| {
                let w2 = modal.omega_squared[j];
                modal.shapes[j][top][dir]
                    * modal.participation[j][dir]
                    * (-ag / w2)
                    * (1.0 - (w2.sqrt() * t).cos())
            })
            .sum()
    };
    let settings = TransientSettings {
        dt: 1e-4,
        t_end: 0.5,
        ..Default::default()
    };
    let ground = move |_t: f64| [0.0, ag, 0.0];
    let mut worst = 0.0f64;
    let mut peak = 0.0f64;
    let res = run_transient(&mut built.domain, None, &ground, &settings, &mut |_, d| {
        let (t, u) = (d.time(), d.displacement(top)[dir]);
        let e = exact(t);
        worst = worst.max((u - e).abs());
        peak = peak.max(e.abs());
        StepControl::Continue
    })
    .unwrap();
    assert_eq!(res.steps, 5000);
    eprintln!(
        "top uy: peak {peak:.6e} m, worst |Newmark − modal| {worst:.3e} m ({:.2e} of the peak)",
        worst / peak
    );
    assert!(peak > 1e-4, "the step load moves the top: {peak}");
    assert!(worst < 1e-3 * peak, "{worst} vs peak {peak}");
}

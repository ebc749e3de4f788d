//! The shift-invert block Lanczos eigen solver (`EigenMethod::Lanczos`, the default above
//! 2000 equations) against a closed form with repeated and closely spaced eigenvalues and
//! massless DOFs, against the dense condensed solver, and against OpenSees (ARPACK) on the
//! exported model of a full-scale frame. The 7-story 6 × 4-bay frame of the shell-wall
//! issue (6 594 DOF) is `#[ignore]`d: run it with
//! `cargo test --release -p fem2rbd-fe --test it fe::analysis::lanczos -- --ignored --nocapture`.
use fem2rbd_fe::fe::analysis::modal::{modal_analysis, EigenMethod, ModalSettings, ModeSelection};
use fem2rbd_fe::fe::build::{build_domain, BuildOptions, Variant};
use fem2rbd_fe::fe::domain::Domain;
use fem2rbd_fe::fe::element::{ElasticBeam3d, ElasticProps};
use fem2rbd_fe::fe::linalg::StiffnessKind;
use fem2rbd_fe::fe::transform::{new_transform, TransformKind};
use fem2rbd_fe::model::generate::{frame, FrameParams};
use fem2rbd_fe::model::{Formulation, Model};
use nalgebra::Vector3;
use std::process::Command;
use std::time::Instant;

const LANCZOS: EigenMethod = EigenMethod::Lanczos {
    tol: 1e-10,
    max_restarts: 200,
};

fn settings(modes: usize, method: EigenMethod) -> ModalSettings {
    ModalSettings {
        selection: ModeSelection::Lowest,
        modes,
        stiffness: StiffnessKind::Initial,
        method,
    }
}

/// A vertical column of `n` stories (height h) whose node rotations are fixed, so that
/// each story is a shear spring k_y = 12 E Iz / h³ in local y and k_z = 12 E Iy / h³ in
/// local z; masses m in X and Y at every floor, the vertical DOFs free and massless.
fn shear_chain(n: usize, h: f64, m: f64, props: ElasticProps) -> Domain {
    let mut d = Domain::new();
    for k in 0..=n {
        let i = d.add_node(k as i64, [0.0, 0.0, k as f64 * h]).unwrap();
        if k == 0 {
            d.fix(i, [true; 6]).unwrap();
        } else {
            d.fix(i, [false, false, false, true, true, true]).unwrap();
            d.set_mass(i, [m, m, 0.0, 0.0, 0.0, 0.0]).unwrap();
        }
    }
    for k in 0..n {
        let xi = Vector3::new(0.0, 0.0, k as f64 * h);
        let xj = Vector3::new(0.0, 0.0, (k + 1) as f64 * h);
        // vecxz = X: local y = X × z-axis... local x = Z, y = vecxz × x = X × Z = −Y,
        // z = x × y = X. So k_local_z (Iy) acts in global X, k_local_y (Iz) in Y.
        let t = new_transform(TransformKind::Linear, xi, xj, Vector3::new(1.0, 0.0, 0.0)).unwrap();
        let el = ElasticBeam3d::new(k as i64 + 1, [k, k + 1], props, t).unwrap();
        d.add_element(Box::new(el)).unwrap();
    }
    d
}

/// Fixed–free chain of n equal masses m and springs k:
/// ω_j² = (4k/m) sin²((2j − 1)π / (2(2n + 1))), j = 1…n.
fn chain_omega2(n: usize, k: f64, m: f64, j: usize) -> f64 {
    let s = ((2 * j - 1) as f64 * std::f64::consts::PI / (2.0 * (2 * n + 1) as f64)).sin();
    4.0 * k / m * s * s
}

/// 800 stories, 2 400 equations (so `Auto` takes Lanczos), 1 600 of them massed: every
/// eigenvalue is double (X and Y) when Iy = Iz, and a pair split by 1e-7 when Iy differs
/// from Iz by 1e-7. Both copies of each pair are found to 1e-9 relative.
#[test]
fn shear_chain_repeated_and_close_pairs_match_the_closed_form() {
    let (n, h, m) = (800, 3.0, 1.0e4);
    for split in [0.0, 1e-7] {
        let i0 = 0.3f64.powi(4) / 12.0;
        let props = ElasticProps {
            e: 30e9,
            g: 12.5e9,
            a: 0.09,
            iy: i0 * (1.0 + split),
            iz: i0,
            j: 0.0141 * 0.3f64.powi(4),
        };
        let mut d = shear_chain(n, h, m, props);
        let t0 = Instant::now();
        let r = modal_analysis(&mut d, &settings(8, EigenMethod::Auto)).unwrap();
        let elapsed = t0.elapsed();
        assert_eq!(d.num_equations(), 3 * n);
        let k_y = 12.0 * props.e * props.iz / h.powi(3);
        let k_x = 12.0 * props.e * props.iy / h.powi(3);
        for j in 1..=4 {
            let wy = chain_omega2(n, k_y, m, j);
            let wx = chain_omega2(n, k_x, m, j);
            let (lo, hi) = (wy.min(wx), wy.max(wx));
            let got = [r.omega_squared[2 * j - 2], r.omega_squared[2 * j - 1]];
            eprintln!(
                "split {split:e}: mode pair {j}: {:.12e} {:.12e} closed form {lo:.12e} {hi:.12e}",
                got[0], got[1]
            );
            assert!(((got[0] - lo) / lo).abs() < 1e-9, "{got:?} vs {lo}");
            assert!(((got[1] - hi) / hi).abs() < 1e-9, "{got:?} vs {hi}");
            if split > 0.0 {
                // The split itself is resolved: (hi − lo)/lo = 1e-7 to 1e-3 of it.
                let s = (got[1] - got[0]) / got[0];
                assert!((s - split).abs() < 1e-3 * split, "split {s:e}");
            }
        }
        // The pair's two shapes are orthogonal and together carry X and Y: effective
        // masses of a fixed-free chain mode j sum to its closed-form share in each.
        let sx: f64 = r.effective_mass_ratio[..2].iter().map(|q| q[0]).sum();
        let sy: f64 = r.effective_mass_ratio[..2].iter().map(|q| q[1]).sum();
        assert!((sx - sy).abs() < 1e-8 && sx > 0.8, "{sx} {sy}");
        eprintln!("split {split:e}: 8 modes of 2400 DOF in {elapsed:?}");
    }
}

/// Full-scale RC frame (C30 concrete, 0.7 m columns, 7.5 m bays), displacement-based
/// fibre elements, scale 1.
fn full_scale_frame(bays_x: usize, bays_y: usize, stories: usize) -> Model {
    frame(&FrameParams {
        name: format!("frame-{bays_x}x{bays_y}x{stories}"),
        spans_x: vec![7.5; bays_x],
        spans_y: vec![7.5; bays_y],
        story_heights: vec![3.6; stories],
        column: [0.7, 0.7],
        beam: [0.35, 0.7],
        slab_thickness: 0.15,
        cover: 0.03,
        bar_offset: 0.05,
        column_bar_diameter: 0.025,
        beam_bar_diameter: 0.025,
        ec: vec![30e9],
        fc: vec![30e6],
        added_mass: vec![0.0],
        scale: 1.0,
        formulation: Formulation::Disp,
        ..FrameParams::default()
    })
    .unwrap()
}

/// Periods (s) of the first `n` modes from the exported openseespy script.
fn opensees_periods(model: &Model, n: usize) -> Vec<f64> {
    let dir = std::env::temp_dir().join(format!("fem2rbd-lanczos-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("{}.py", model.name));
    let script =
        fem2rbd_fe::export::opensees_script(model, "generated", &Default::default()).unwrap();
    std::fs::write(&path, script).unwrap();
    let v = crate::openseespy_json(
        Command::new("python3")
            .arg(&path)
            .args(["eigen", &n.to_string()]),
    );
    std::fs::remove_dir_all(&dir).ok();
    v["modes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["T"].as_f64().unwrap())
        .collect()
}

/// A 3-story 5 × 3-bay full-scale frame (327 nodes, 1 818 equations): Lanczos equals the
/// dense condensed solver to 1e-10 and OpenSees' ARPACK (the export picks it above
/// 1 500 DOFs) on the exported model to 1e-6.
#[test]
fn mid_size_frame_matches_dense_and_opensees_arpack() {
    let model = full_scale_frame(5, 3, 3);
    let modes = 6;
    let run = |method| {
        let mut built = build_domain(&model, &BuildOptions::default()).unwrap();
        let t0 = Instant::now();
        let r = modal_analysis(&mut built.domain, &settings(modes, method)).unwrap();
        (r, t0.elapsed(), built.domain.num_equations())
    };
    let (lz, t_lz, neq) = run(LANCZOS);
    let (dense, t_dense, _) = run(EigenMethod::DenseCondensed);
    assert_eq!(neq, 1818);
    let t_os = Instant::now();
    let os = opensees_periods(&model, modes);
    let t_os = t_os.elapsed();
    for (k, &c) in os.iter().enumerate().take(modes) {
        let (a, b) = (lz.periods[k], dense.periods[k]);
        eprintln!(
            "mode {}: Lanczos {a:.9} s, dense {b:.9} s, OpenSees {c:.9} s ({:+.2e})",
            k + 1,
            (a - c) / c
        );
        assert!(
            ((a - b) / b).abs() < 1e-10,
            "mode {}: {a} vs dense {b}",
            k + 1
        );
        assert!(
            ((a - c) / c).abs() < 1e-6,
            "mode {}: {a} vs OpenSees {c}",
            k + 1
        );
    }
    eprintln!("Lanczos {t_lz:?}, dense {t_dense:?}, openseespy (build + ARPACK) {t_os:?}");
}

/// The frame of the shell-wall issue: 7 stories, 6 × 4 bays of 7.5 m, 0.7 m columns,
/// 1 099 nodes, 6 594 equations. Subspace iteration did not converge on it; OpenSees'
/// ARPACK on the exported model gives 0.7930621877 / 0.7731163557 / 0.7051586708 /
/// 0.2520460367 / 0.2465552033 / 0.2246614223 s (openseespy 3.7.1, 6 s).
#[test]
#[ignore = "full-scale 6 594-DOF frame, about 10 s in debug; run with --ignored"]
fn seven_story_frame_matches_opensees_arpack() {
    let model = full_scale_frame(6, 4, 7);
    assert_eq!(model.nodes.len(), 1099);
    let mut built = build_domain(
        &model,
        &BuildOptions {
            variant: Variant::AsModel,
            ..Default::default()
        },
    )
    .unwrap();
    let t0 = Instant::now();
    let r = modal_analysis(&mut built.domain, &settings(6, EigenMethod::Auto)).unwrap();
    let elapsed = t0.elapsed();
    assert_eq!(built.domain.num_equations(), 6384); // 6 594 DOFs, 35 base nodes fixed
    let reference = [
        0.7930621876835777,
        0.773116355743366,
        0.705158670794201,
        0.25204603668459985,
        0.2465552033160204,
        0.2246614223496958,
    ];
    for (k, t_ref) in reference.iter().enumerate() {
        let t = r.periods[k];
        eprintln!(
            "mode {}: T = {t:.10} s, OpenSees ARPACK {t_ref:.10} s ({:+.2e})",
            k + 1,
            (t - t_ref) / t_ref
        );
        assert!(((t - t_ref) / t_ref).abs() < 1e-6);
    }
    eprintln!("6 modes of 6594 DOF in {elapsed:?}");
}

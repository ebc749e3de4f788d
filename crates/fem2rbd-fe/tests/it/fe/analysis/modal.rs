//! Modal analysis against closed forms; both eigen solvers (dense condensed, sparse
//! subspace iteration) on each case.
use super::support as fe_analysis_support;

use fe_analysis_support::{cantilever, grid_frame, square};
use fem2rbd_fe::fe::analysis::modal::{modal_analysis, EigenMethod, ModalSettings, ModeSelection};
use fem2rbd_fe::fe::linalg::StiffnessKind;

const SUBSPACE: EigenMethod = EigenMethod::SubspaceIteration {
    tol: 1e-10,
    max_iter: 500,
};

fn settings(modes: usize, method: EigenMethod) -> ModalSettings {
    ModalSettings {
        selection: ModeSelection::Lowest,
        modes,
        stiffness: StiffnessKind::Initial,
        method,
    }
}

/// Cantilever (4 elements) with a lumped tip mass m in X, Y, Z and massless rotations
/// and intermediate nodes: ω² = 3EI/(mL³) twice (bending in y and z) and EA/(mL)
/// (axial).
#[test]
fn cantilever_tip_mass() {
    let (e, b, l, m) = (25e9, 0.1, 1.5, 500.0);
    let p = square(e, b);
    for method in [EigenMethod::DenseCondensed, SUBSPACE] {
        let (mut d, tip) = cantilever(l, 4, p, [0.0, 0.0, 1.0]);
        d.set_mass(tip, [m, m, m, 0.0, 0.0, 0.0]).unwrap();
        let r = modal_analysis(&mut d, &settings(3, method)).unwrap();
        let wb = 3.0 * e * p.iy / (m * l.powi(3));
        let wa = e * p.a / (m * l);
        let rel = |a: f64, b: f64| ((a - b) / b).abs();
        assert!(
            rel(r.omega_squared[0], wb) < 1e-9,
            "{method:?} {:?} vs {wb}",
            r.omega_squared
        );
        assert!(
            rel(r.omega_squared[1], wb) < 1e-9,
            "{method:?} {:?}",
            r.omega_squared
        );
        assert!(
            rel(r.omega_squared[2], wa) < 1e-9,
            "{method:?} {:?} vs {wa}",
            r.omega_squared
        );
        // Each mode carries the whole mass of its direction (two bending modes share Y/Z).
        let ry: f64 = r.effective_mass_ratio[..2].iter().map(|q| q[1]).sum();
        let rz: f64 = r.effective_mass_ratio[..2].iter().map(|q| q[2]).sum();
        assert!(
            (ry - 1.0).abs() < 1e-9 && (rz - 1.0).abs() < 1e-9,
            "{:?}",
            r.effective_mass_ratio
        );
        assert!((r.effective_mass_ratio[2][0] - 1.0).abs() < 1e-9);
        // Mode shape: the massless rotation follows statically, θ_tip = 3δ/(2L).
        let s = &r.shapes[0][tip];
        let (defl, rot) = if s[1].abs() > s[2].abs() {
            (s[1], s[5])
        } else {
            (s[2], -s[4])
        };
        assert!(rel(rot, 1.5 * defl / l) < 1e-9, "{s:?}");
        assert!(rel(r.periods[2], 2.0 * std::f64::consts::PI / wa.sqrt()) < 1e-9);
    }
}

/// Two-story shear building: one column per story with the floor rotations fixed, so
/// each story has lateral stiffness k = 12EI/h³; floor masses m1, m2 in X only.
/// det(K − ω² M) = 0 with K = [[k1+k2, −k2], [−k2, k2]].
#[test]
fn two_story_shear_frame() {
    let (h, m1, m2) = (3.0, 2000.0, 1500.0);
    let p1 = square(30e9, 0.3);
    let p2 = square(30e9, 0.25);
    for method in [EigenMethod::DenseCondensed, SUBSPACE] {
        let mut d = fem2rbd_fe::fe::domain::Domain::new();
        for f in 0..3 {
            d.add_node(f, [0.0, 0.0, h * f as f64]).unwrap();
        }
        d.fix(0, [true; 6]).unwrap();
        for f in 1..3 {
            d.fix(f, [false, false, false, true, true, true]).unwrap();
        }
        d.set_mass(1, [m1, 0.0, 0.0, 0.0, 0.0, 0.0]).unwrap();
        d.set_mass(2, [m2, 0.0, 0.0, 0.0, 0.0, 0.0]).unwrap();
        for (f, p) in [(0usize, p1), (1, p2)] {
            let el =
                fe_analysis_support::ElasticFrame::new(f as i64, &d, f, f + 1, [1.0, 0.0, 0.0], p);
            d.add_element(Box::new(el)).unwrap();
        }
        let r = modal_analysis(&mut d, &settings(2, method)).unwrap();
        let k1 = 12.0 * 30e9 * p1.iy / h.powi(3);
        let k2 = 12.0 * 30e9 * p2.iy / h.powi(3);
        // m1 m2 λ² − (m1 k2 + m2 (k1 + k2)) λ + k1 k2 = 0
        let (a, b, c) = (m1 * m2, -(m1 * k2 + m2 * (k1 + k2)), k1 * k2);
        let disc = (b * b - 4.0 * a * c).sqrt();
        let l1 = (-b - disc) / (2.0 * a);
        let l2 = (-b + disc) / (2.0 * a);
        assert!(
            ((r.omega_squared[0] - l1) / l1).abs() < 1e-9,
            "{method:?} {:?} vs {l1}",
            r.omega_squared
        );
        assert!(
            ((r.omega_squared[1] - l2) / l2).abs() < 1e-9,
            "{method:?} {:?} vs {l2}",
            r.omega_squared
        );
        let sum: f64 = r.effective_mass_ratio.iter().map(|q| q[0]).sum();
        assert!((sum - 1.0).abs() < 1e-9, "{:?}", r.effective_mass_ratio);
        assert!((r.total_mass[0] - (m1 + m2)).abs() < 1e-9);
        // Mode 1 shape ratio φ2/φ1 = (k1 + k2 − m1 λ1)/k2.
        let ratio = r.shapes[0][2][0] / r.shapes[0][1][0];
        let expect = (k1 + k2 - m1 * l1) / k2;
        assert!(
            ((ratio - expect) / expect).abs() < 1e-8,
            "{ratio} vs {expect}"
        );
    }
}

/// Massless rotational DOFs condensed exactly = the limit of a tiny rotational mass.
#[test]
fn massless_condensation_equals_tiny_rotational_mass_limit() {
    let (e, b, l, m) = (25e9, 0.1, 2.0, 300.0);
    let p = square(e, b);
    let periods = |rot: f64, method: EigenMethod| {
        let (mut d, tip) = cantilever(l, 4, p, [0.0, 0.0, 1.0]);
        for node in 1..=tip {
            d.set_mass(node, [m, m, m, rot, rot, rot]).unwrap();
        }
        modal_analysis(&mut d, &settings(6, method))
            .unwrap()
            .periods
    };
    let exact = periods(0.0, EigenMethod::DenseCondensed);
    let tiny = periods(1e-9 * m * l * l, EigenMethod::DenseCondensed);
    let tiny_sub = periods(1e-9 * m * l * l, SUBSPACE);
    let exact_sub = periods(0.0, SUBSPACE);
    for k in 0..6 {
        // The sparse solver works on K⁻¹M, well conditioned: tiny rotational mass → the
        // condensed periods (the true difference, rotary inertia, is 2e-9 to 3e-8 relative here).
        assert!(
            ((tiny_sub[k] - exact[k]) / exact[k]).abs() < 1e-7,
            "{tiny_sub:?} {exact:?}"
        );
        assert!(
            ((exact_sub[k] - exact[k]) / exact[k]).abs() < 1e-8,
            "{exact_sub:?} {exact:?}"
        );
        // The dense M^(-1/2) K M^(-1/2) form is ill-conditioned by the tiny masses (ratio
        // 1e9): it only gets ~1e-6 — why massless DOFs are condensed, not given a mass.
        assert!(
            ((exact[k] - tiny[k]) / exact[k]).abs() < 1e-5,
            "{exact:?} {tiny:?}"
        );
    }
    // And the tiny mass actually changes something measurable (the test can fail).
    let big = periods(1e-2 * m * l * l, EigenMethod::DenseCondensed);
    assert!(
        ((exact[0] - big[0]) / exact[0]).abs() > 1e-4,
        "{exact:?} {big:?}"
    );
}

/// A 2×2-bay, 3-story 3D frame (usual frame3 size, 297 equations): sparse subspace
/// iteration reproduces the dense condensed periods; X and Y fundamental periods equal
/// by symmetry; effective mass ratios sum below 1 and the first X mode dominates.
#[test]
fn frame_subspace_matches_dense() {
    let col = square(25e9, 0.1);
    let beam = fe_analysis_support::Props {
        e: 25e9,
        g: 25e9 / 2.4,
        a: 0.075 * 0.15,
        iy: 0.075 * 0.15f64.powi(3) / 12.0,
        iz: 0.15 * 0.075f64.powi(3) / 12.0,
        j: 1.5e-5,
    };
    let run = |method| {
        let mut d = grid_frame(2, 3, 1.5, 1.0, col, beam, 300.0);
        modal_analysis(&mut d, &settings(6, method)).unwrap()
    };
    let dense = run(EigenMethod::DenseCondensed);
    let sub = run(SUBSPACE);
    for k in 0..6 {
        assert!(
            ((dense.periods[k] - sub.periods[k]) / dense.periods[k]).abs() < 1e-8,
            "{:?} {:?}",
            dense.periods,
            sub.periods
        );
    }
    assert!(((dense.periods[0] - dense.periods[1]) / dense.periods[0]).abs() < 1e-8);
    let x_ratio: f64 = dense.effective_mass_ratio.iter().map(|q| q[0]).sum();
    assert!(
        x_ratio < 1.0 && x_ratio > 0.8,
        "{:?}",
        dense.effective_mass_ratio
    );
}

/// A 6×6-bay, 8-story frame (2 352 equations, above the dense limit): `Auto` takes the
/// sparse subspace iteration; every returned pair satisfies ‖Kφ − ω²Mφ‖ ≤ 1e-8‖Kφ‖,
/// the X and Y fundamental periods are equal by symmetry, and the pairs are
/// M-orthonormal.
#[test]
fn large_frame_auto_uses_sparse_solver() {
    use fem2rbd_fe::fe::linalg::SparsePattern;
    let col = square(25e9, 0.3);
    let beam = square(25e9, 0.25);
    let mut d = grid_frame(6, 8, 5.0, 3.0, col, beam, 5000.0);
    let r = modal_analysis(&mut d, &settings(6, EigenMethod::Auto)).unwrap();
    assert!(d.num_equations() > 2000);
    eprintln!("periods {:?}", r.periods);
    let pattern = SparsePattern::new(&mut d);
    let mut k = pattern.zeros();
    pattern.add_stiffness(&d, StiffnessKind::Initial, 1.0, &mut k);
    let m = d.mass_diagonal();
    let n = d.num_equations();
    let to_eq = |shape: &Vec<[f64; 6]>| {
        let mut v = vec![0.0; n];
        for (node, s) in shape.iter().enumerate() {
            for c in 0..6 {
                if let Some(e) = d.equation(node, c) {
                    v[e] = s[c];
                }
            }
        }
        v
    };
    let phis: Vec<Vec<f64>> = r.shapes.iter().map(to_eq).collect();
    for (i, phi) in phis.iter().enumerate() {
        let mut kphi = vec![0.0; n];
        pattern.mul_vec(&k, phi, &mut kphi);
        let res: f64 = (0..n)
            .map(|j| (kphi[j] - r.omega_squared[i] * m[j] * phi[j]).powi(2))
            .sum::<f64>()
            .sqrt();
        let norm: f64 = kphi.iter().map(|x| x * x).sum::<f64>().sqrt();
        assert!(res <= 1e-8 * norm, "mode {i}: residual {res:e} vs {norm:e}");
        for (j, psi) in phis.iter().enumerate() {
            let mij: f64 = (0..n).map(|q| phi[q] * m[q] * psi[q]).sum();
            let expect = if i == j { 1.0 } else { 0.0 };
            assert!((mij - expect).abs() < 1e-8, "φ{i}ᵀMφ{j} = {mij}");
        }
    }
    assert!(((r.periods[0] - r.periods[1]) / r.periods[0]).abs() < 1e-8);
}

//! Fiber section closed forms: elastic stiffness Σ E A a aᵀ, fully plastic moment of a
//! rectangle fy b h²/4, sign conventions ε = ε0 − y κz + z κy.

use super::support;

use fem2rbd_fe::fe::section::fiber::FiberSection;
use fem2rbd_fe::fe::section::{flexibility, Section};
use nalgebra::Vector4;
use support::{rectangle_fibers, ElasticPerfectlyPlastic, LinearElastic};

#[test]
fn elastic_fiber_section_stiffness_is_sum_of_e_a_y2() {
    let e = 30e9;
    let (b, h) = (0.2, 0.4);
    let fibers = rectangle_fibers(b, h, 10, 20, &LinearElastic::new(e));
    // Closed forms of the fiber sums for a mid-point rule: Σ A = bh, Σ A y² = h b³/12 (1 − 1/ny²).
    let ea = e * b * h;
    let eiz = e * h * b.powi(3) / 12.0 * (1.0 - 1.0 / 100.0);
    let eiy = e * b * h.powi(3) / 12.0 * (1.0 - 1.0 / 400.0);
    let gj = 1.234e6;
    let s = FiberSection::new(fibers, gj).unwrap();
    let k = s.initial_tangent();
    println!(
        "EA {:.6e} EIz {:.6e} EIy {:.6e}",
        k[(0, 0)],
        k[(1, 1)],
        k[(2, 2)]
    );
    assert!((k[(0, 0)] / ea - 1.0).abs() < 1e-12);
    assert!((k[(1, 1)] / eiz - 1.0).abs() < 1e-12);
    assert!((k[(2, 2)] / eiy - 1.0).abs() < 1e-12);
    assert!(k[(0, 1)].abs() < 1e-6 * ea && k[(1, 2)].abs() < 1e-6 * eiz);
    assert_eq!(k[(3, 3)], gj);
    // An eccentric fiber couples axial force and bending with the OpenSees signs
    // (with `-noCentroid`; by default a single fiber is its own centroid).
    let one = vec![(
        0.1,
        -0.05,
        2e-4,
        Box::new(LinearElastic::new(e)) as Box<dyn fem2rbd_fe::fe::material::UniaxialMaterial>,
    )];
    let mut s1 = FiberSection::with_centroid_option(one, gj, false).unwrap();
    let k1 = s1.initial_tangent();
    assert!((k1[(0, 1)] - (-0.1 * e * 2e-4)).abs() < 1e-3);
    assert!((k1[(0, 2)] - (-0.05 * e * 2e-4)).abs() < 1e-3);
    // ε = ε0 − y κz + z κy
    s1.set_trial_deformation(&Vector4::new(1e-4, 2e-3, 3e-3, 0.01));
    let eps = 1e-4 - 0.1 * 2e-3 + (-0.05) * 3e-3;
    let r = s1.resultant();
    assert!((r[0] - e * eps * 2e-4).abs() < 1e-6);
    assert!(
        (r[1] - (-0.1) * e * eps * 2e-4).abs() < 1e-6,
        "Mz = −Σ σ A y"
    );
    assert!(
        (r[2] - (-0.05) * e * eps * 2e-4).abs() < 1e-6,
        "My = Σ σ A z"
    );
    assert!((r[3] - gj * 0.01).abs() < 1e-9);
    let f = flexibility(&s.tangent()).unwrap();
    assert!((f * s.tangent() - nalgebra::Matrix4::identity()).norm() < 1e-9);
}

#[test]
fn fully_plastic_moment_of_rectangle_is_fy_b_h2_over_4() {
    let (e, fy) = (200e9, 400e6);
    let (b, h) = (0.1, 0.2);
    let mat = ElasticPerfectlyPlastic::new(e, fy);
    let mut s = FiberSection::new(rectangle_fibers(b, h, 1, 200, &mat), 1.0).unwrap();
    let mp = fy * b * h * h / 4.0;
    let my_el = fy * b * h * h / 6.0;
    // First yield: κy at the extreme fiber (z = h/2 − h/400 for the outer fiber centre).
    let ky = fy / e / (0.5 * h);
    // Just below first yield of the outer fiber centre the section is elastic:
    // M = E κ Σ A z² = E κ b h³/12 (1 − 1/nz²).
    let k1 = 0.999 * ky * (0.5 * h) / (0.5 * h - h / 400.0);
    s.set_trial_deformation(&Vector4::new(0.0, 0.0, k1, 0.0));
    let m1 = s.resultant()[2];
    let m1_exact = e * k1 * b * h.powi(3) / 12.0 * (1.0 - 1.0 / 40000.0);
    println!(
        "M just below first yield {m1:.6e} (closed form {m1_exact:.6e}; fy b h²/6 = {my_el:.6e})"
    );
    assert!((m1 / m1_exact - 1.0).abs() < 1e-12);
    // Far into the plastic range: κ = 1000 κy.
    s.set_trial_deformation(&Vector4::new(0.0, 0.0, 1000.0 * ky, 0.0));
    let m = s.resultant()[2];
    println!("My at 1000 κy {m:.6e}, Mp {mp:.6e}, ratio {:.8}", m / mp);
    assert!((m / mp - 1.0).abs() < 1e-5, "M = {m}, Mp = {mp}");
    assert!(s.resultant()[0].abs() < 1e-6 * fy * b * h, "no axial force");
    assert!(s.tangent()[(2, 2)].abs() < 1e-3 * s.initial_tangent()[(2, 2)]);
    // Damage and extreme strains.
    s.commit_state();
    let d = s.damage();
    assert!(d.yielded && !d.ruptured);
    let emax = 1000.0 * ky * (0.5 * h - h / 400.0);
    assert!((d.max_strain - emax).abs() < 1e-12 && (d.min_strain + emax).abs() < 1e-12);
    // Bending about z: Mz = −Σ σ A y, plastic in the other plane too.
    let mut sz = FiberSection::new(rectangle_fibers(h, b, 200, 1, &mat), 1.0).unwrap();
    sz.set_trial_deformation(&Vector4::new(0.0, 1000.0 * ky, 0.0, 0.0));
    let mz = sz.resultant()[1];
    assert!((mz / mp - 1.0).abs() < 1e-5, "Mz = {mz}");
}

#[test]
fn fiber_coordinates_are_measured_from_the_area_centroid() {
    // A T-like section: flange 0.4 × 0.1 at z = 0.25, web 0.1 × 0.4 at z = 0 (as given).
    let e = 30e9;
    let m = LinearElastic::new(e);
    let mut fibers = rectangle_fibers(0.4, 0.1, 8, 2, &m);
    for f in &mut fibers {
        f.1 += 0.25;
    }
    fibers.extend(rectangle_fibers(0.1, 0.4, 2, 8, &m));
    let s = FiberSection::new(fibers, 1.0).unwrap();
    let zbar = (0.04 * 0.25) / 0.08;
    assert!((s.centroid().1 - zbar).abs() < 1e-15 && s.centroid().0.abs() < 1e-15);
    let k = s.initial_tangent();
    // No axial-bending coupling about the centroid; EIy by the parallel-axis theorem
    // with the mid-point fiber sums.
    assert!(k[(0, 2)].abs() < 1e-6 * k[(0, 0)]);
    let iy = 0.4 * 0.1f64.powi(3) / 12.0 * (1.0 - 1.0 / 4.0)
        + 0.04 * (0.25 - zbar).powi(2)
        + 0.1 * 0.4f64.powi(3) / 12.0 * (1.0 - 1.0 / 64.0)
        + 0.04 * zbar * zbar;
    assert!(
        (k[(2, 2)] / (e * iy) - 1.0).abs() < 1e-12,
        "{} vs {}",
        k[(2, 2)],
        e * iy
    );
}

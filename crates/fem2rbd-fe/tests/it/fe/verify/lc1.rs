//! frame3 LC1 (El Centro 1940: X ← ELC180 at 0.10 g, Y ← ELC270 at 0.08 g, Z ← ELC-UP at
//! 0.06 g; Δt = 0.005 s) in the elastic, force-based and displacement-based variants,
//! through [`fem2rbd_fe::fe::run::run_ground_motion`], against OpenSees 3.7.1 on the same
//! model (`tests/fixtures/opensees-frame3/LC1_*_first12s.csv`, results.md §4).
//!
//! Measure: at the sample times 2.0, 3.0, 5.0 s of results.md the roof-centre (node 312)
//! ux and uy differ from OpenSees by less than 2 % of OpenSees's peak |ux| resp. |uy| of
//! the whole run (results.md: 7.363/5.280 mm elastic, 12.674/10.153 force, 10.313/9.355
//! disp); the same bound holds over the whole compared window, step by step; and the
//! peaks of ux and uy within the window agree within 2 % in value and 0.05 s in time.
//! The CI tests run the first 12.5 s, which hold the whole-record peaks (ux at 4.585 /
//! 5.150 / 5.110 s, uy at 4.685 / 11.870 / 11.580 s); the `#[ignore]`d
//! `*_whole_record` tests run all 53.45 s and check the whole-record peaks of
//! results.md: `cargo test --release -p fem2rbd-fe --test it fe::verify::lc1 -- --ignored`.
use super::support as fe_verify_support;

use fe_verify_support::*;
use fem2rbd_fe::fe::build::Variant;

struct Reference {
    name: &'static str,
    variant: Variant,
    peak_ux_mm: f64,
    peak_uy_mm: f64,
}

const ELASTIC: Reference = Reference {
    name: "elastic",
    variant: Variant::Elastic,
    peak_ux_mm: 7.363,
    peak_uy_mm: 5.280,
};
const FORCE: Reference = Reference {
    name: "force",
    variant: Variant::Force,
    peak_ux_mm: 12.674,
    peak_uy_mm: 10.153,
};
const DISP: Reference = Reference {
    name: "disp",
    variant: Variant::Disp,
    peak_ux_mm: 10.313,
    peak_uy_mm: 9.355,
};

/// (time, value) of the largest |value| in t ≤ t_max.
fn peak(t: &[f64], y: &[f64], t_max: f64) -> (f64, f64) {
    let mut best = (0.0f64, 0.0f64);
    for (&ti, &yi) in t.iter().zip(y) {
        if ti <= t_max + 1e-9 && yi.abs() > best.1.abs() {
            best = (ti, yi);
        }
    }
    best
}

fn check(r: &Reference, t_end: f64) {
    let (head, rows) = read_csv(&fixture(&format!("LC1_{}_first12s.csv", r.name)));
    assert_eq!(head[1], "roof_centre_ux");
    let t_ref: Vec<f64> = rows.iter().map(|v| v[0]).collect();
    let ux_ref: Vec<f64> = rows.iter().map(|v| v[1]).collect();
    let uy_ref: Vec<f64> = rows.iter().map(|v| v[2]).collect();

    let model = frame3();
    let gm = el_centro(LC1);
    let res = run(&model, &gm, r.variant, t_end, &[312], &mut |_| false);
    let h = &res.transient.history;
    let t: Vec<f64> = h.time.clone();
    let ux: Vec<f64> = h.disp.iter().map(|d| d[0][0]).collect();
    let uy: Vec<f64> = h.disp.iter().map(|d| d[0][1]).collect();
    assert!(
        (t.last().unwrap() - t_end).abs() < 1e-9,
        "ended at {:?}",
        t.last()
    );

    let (sx, sy) = (r.peak_ux_mm * 1e-3, r.peak_uy_mm * 1e-3);
    let tol = 0.02;
    for ts in [2.0, 3.0, 5.0] {
        if ts > t_end {
            continue;
        }
        let (a, b) = (at(&t, &ux, ts), at(&t_ref, &ux_ref, ts));
        let (c, d) = (at(&t, &uy, ts), at(&t_ref, &uy_ref, ts));
        eprintln!(
            "LC1 {} t = {ts} s: ux {:+.3} mm (OpenSees {:+.3}), diff {:.2} % of peak; uy {:+.3} mm (OpenSees {:+.3}), diff {:.2} % of peak",
            r.name, a * 1e3, b * 1e3, (a - b).abs() / sx * 100.0, c * 1e3, d * 1e3, (c - d).abs() / sy * 100.0
        );
        assert!((a - b).abs() < tol * sx, "{} ux at {ts} s", r.name);
        assert!((c - d).abs() < tol * sy, "{} uy at {ts} s", r.name);
    }
    // Whole window, at every reference step.
    let (mut ex, mut ey) = (0.0f64, 0.0f64);
    for (i, &ti) in t_ref.iter().enumerate() {
        if ti > t_end + 1e-9 {
            break;
        }
        ex = ex.max((at(&t, &ux, ti) - ux_ref[i]).abs());
        ey = ey.max((at(&t, &uy, ti) - uy_ref[i]).abs());
    }
    eprintln!(
        "LC1 {} 0–{:.2} s: max |Δux| = {:.3} % of peak, max |Δuy| = {:.3} % of peak",
        r.name,
        t_end.min(*t_ref.last().unwrap()),
        ex / sx * 100.0,
        ey / sy * 100.0
    );
    assert!(ex < tol * sx && ey < tol * sy, "{} history", r.name);
    // Peaks inside the window covered by the reference series.
    let window = t_end.min(*t_ref.last().unwrap());
    for (name, y, y_ref) in [("ux", &ux, &ux_ref), ("uy", &uy, &uy_ref)] {
        let (tp, p) = peak(&t, y, window);
        let (tq, q) = peak(&t_ref, y_ref, window);
        eprintln!(
            "LC1 {} peak {name} up to {window} s: {:+.3} mm at {tp:.3} s (OpenSees {:+.3} mm at {tq:.3} s), diff {:+.2} %",
            r.name, p * 1e3, q * 1e3, (p - q) / q * 100.0
        );
        assert!((p - q).abs() < tol * q.abs(), "{} peak {name}", r.name);
        assert!((tp - tq).abs() < 0.05, "{} peak {name} time", r.name);
    }
    if t_end >= 12.0 {
        // The whole-record peaks of results.md lie before 12 s.
        let (_, p) = peak(&t, &ux, t_end);
        let (_, q) = peak(&t, &uy, t_end);
        eprintln!(
            "LC1 {} peak |ux|, |uy| over 0–{t_end} s: {:.3} / {:.3} mm (results.md, whole record: {} / {} mm)",
            r.name,
            p.abs() * 1e3,
            q.abs() * 1e3,
            r.peak_ux_mm,
            r.peak_uy_mm
        );
        assert!(
            (p.abs() - sx).abs() < tol * sx,
            "{} whole-run peak ux {p}",
            r.name
        );
        assert!(
            (q.abs() - sy).abs() < tol * sy,
            "{} whole-run peak uy {q}",
            r.name
        );
    }
}

#[test]
fn lc1_elastic_first_12_5s() {
    check(&ELASTIC, 12.5);
}

#[test]
fn lc1_force_first_12_5s() {
    check(&FORCE, 12.5);
}

#[test]
fn lc1_disp_first_12_5s() {
    check(&DISP, 12.5);
}

#[test]
#[ignore = "whole record (53.45 s, 10690 steps) per variant; run with --release --ignored (docs/fe-verification.md)"]
fn lc1_elastic_whole_record() {
    check(&ELASTIC, 53.45);
}

#[test]
#[ignore = "whole record (53.45 s, 10690 steps) per variant; run with --release --ignored (docs/fe-verification.md)"]
fn lc1_force_whole_record() {
    check(&FORCE, 53.45);
}

#[test]
#[ignore = "whole record (53.45 s, 10690 steps) per variant; run with --release --ignored (docs/fe-verification.md)"]
fn lc1_disp_whole_record() {
    check(&DISP, 53.45);
}

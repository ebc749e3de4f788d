//! Hand-off continuity (docs/handoff.md): the Bullet building must be the
//! building the FE had.
//!
//! * Gravity alone (a ground record of zeros) on the undamaged frame3 with FE-derived
//!   connections: the largest sag and roof drift of the Bullet building stay within the
//!   issue's targets (sag ≤ 10 mm, drift ≤ 0.02 %), and the FE under the same record
//!   sags a few millimetres (the reference the Bullet building is held against).
//! * The 1/50-drift hand-off under LC5 with FE-derived connections: how many connections
//!   start broken (FE rule: load path lost) and that Bullet does not reach the 0.25 m drop
//!   before half-way between the hand-off and the FE's own Tc (4.66 s, docs/case1.md).
//! * Static lateral strength (a slow ground ramp; docs/handoff.md, "The static lateral
//!   strength"): the converged Bullet frame against the rigid-plastic mechanism of the
//!   FE's sections, the
//!   unconverged one far below it, and the FE's own pushovers against OpenSees.
//!
//! Each test is self-contained (its own helpers); figures from `history.csv` as written.
use fem2rbd::pipeline::{self, write, Scenario, Silent};
use std::path::{Path, PathBuf};

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

/// The FE's Tc of frame3 under LC5 (vertical drop 0.25 m), docs/case1.md (fem2rbd and
/// OpenSees agree to the step).
const FE_TC_S: f64 = 4.66;

fn write_file(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn zeros(dir: &Path, seconds: f64) -> PathBuf {
    let n = (seconds / 0.005).round() as usize;
    let text: String = (0..=n)
        .map(|i| format!("{:.3} 0.0\n", i as f64 * 0.005))
        .collect();
    write_file(dir, "zeros.txt", &text)
}

fn lc5(mode: &str, collapse: &str, physics: &str) -> String {
    let mut s = format!("model = \"{ROOT}/data/frame3/model.toml\"\nmode = \"{mode}\"\n\n");
    for (f, d, g) in [
        ("ELC180", "X", 0.93),
        ("ELC270", "Y", 1.19),
        ("ELC-UP", "Z", 0.57),
    ] {
        s += &format!(
            "[[ground_motion]]\nfile = \"{ROOT}/data/ground-motions/RSN6_IMPVALL.I_I-{f}.AT2\"\n\
             direction = \"{d}\"\npga_g = {g}\ntime_scale = 0.5\n\n"
        );
    }
    s + &format!("[fe]\ndt = 0.005\n\n[collapse]\n{collapse}\n\n[physics]\n{physics}\n")
}

/// The Bullet frame at the FE's own capacities (docs/handoff.md §2.6, §5.5):
/// FE-derived connections, elastic slab panels, hinges to bar rupture, no BCB correction.
/// BCB's contacts (docs/handoff.md, "At the defaults"): connected pieces never touch, and
/// connected column bases also rest on the ground. The tests that measure a setting
/// with these contacts name them, so they keep measuring it.
const BCB_CONTACTS: &str = "experimental.connected_pairs_touch = \"never\"\nexperimental.ground_under_connected_bases = true";

const FE_CAPACITIES: &str = "connections = \"fe\"\npanel_connections = \"elastic\"\n\
     hinge_end = \"rupture\"\nlinear_correction = 1.0\nbending_correction = 1.0";

/// An LC5 hybrid scenario in the "FE throughout" setting ([`FE_CAPACITIES`], the FE's
/// mass-proportional damping to the ground) with the joints on the column above
/// (docs/handoff.md §2.7) and [`BCB_CONTACTS`], run to
/// `until_s` s without the rest test; `extra`: more `[physics]` lines.
fn fe_throughout(collapse: &str, until_s: f64, extra: &str) -> String {
    lc5(
        "hybrid",
        collapse,
        &format!(
            "time_limit_s = {until_s}\nstop_at_rest = false\n{FE_CAPACITIES}\n\
             ground_damping = \"fe\"\njoints = \"column_above\"\n{BCB_CONTACTS}\n{extra}"
        ),
    )
}

/// Runs a scenario text (written to a temporary folder as `name`).
fn run_text(name: &str, text: &str) -> pipeline::RunRecord {
    let dir = tempfile::tempdir().unwrap();
    let p = write_file(dir.path(), name, text);
    pipeline::run(&Scenario::load(&p).unwrap(), &Silent).unwrap()
}

/// `history.csv` rows: (t, stage, roof_drift, max_drop_m, intact, plastic, broken).
type Row = (f64, String, f64, f64, Option<[usize; 3]>);

/// The text of output file `name` of a run.
fn output_text(rec: &pipeline::RunRecord, name: &str) -> String {
    let files = write::contents(rec, false).unwrap();
    files
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, b)| String::from_utf8(b.clone()).unwrap())
        .unwrap()
}

fn history(rec: &pipeline::RunRecord) -> Vec<Row> {
    let text = output_text(rec, "history.csv");
    text.lines()
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            let counts = (!f[4].is_empty()).then(|| {
                [
                    f[4].parse().unwrap(),
                    f[5].parse().unwrap(),
                    f[6].parse().unwrap(),
                ]
            });
            (
                f[0].parse().unwrap(),
                f[1].to_string(),
                f[2].parse().unwrap(),
                f[3].parse().unwrap(),
                counts,
            )
        })
        .collect()
}

fn gravity_only(mode: &str, physics: &str, fe: &str, seconds: f64) -> Vec<Row> {
    history(&gravity_record(mode, physics, fe, seconds))
}

/// The run record of [`gravity_only`].
fn gravity_record(mode: &str, physics: &str, fe: &str, seconds: f64) -> pipeline::RunRecord {
    let dir = tempfile::tempdir().unwrap();
    let z = zeros(dir.path(), seconds);
    let text = format!(
        "model = \"{ROOT}/data/frame3/model.toml\"\nmode = \"{mode}\"\n\n\
         [[ground_motion]]\nfile = \"{}\"\ndirection = \"X\"\n\n[fe]\ndt = 0.005\n{fe}\n\n\
         [physics]\n{physics}\n",
        z.display()
    );
    let p = write_file(dir.path(), "gravity.toml", &text);
    let sc = Scenario::load(&p).unwrap();
    pipeline::run(&sc, &Silent).unwrap()
}

/// Gravity alone on frame3, rigid-only with the `[physics]` lines, for `seconds`: the
/// largest sag (m) and roof drift (ratio), printed under `label`; every connection must
/// still be intact at the end.
fn gravity_peaks(label: &str, physics: &str, seconds: f64) -> (f64, f64) {
    let rows = gravity_only(
        "rigid",
        &format!("time_limit_s = {seconds}\nstop_at_rest = false\n{physics}"),
        "",
        seconds,
    );
    let sag = rows.iter().map(|r| r.3).fold(0.0, f64::max);
    let drift = rows.iter().map(|r| r.2.abs()).fold(0.0, f64::max);
    let last = rows.last().unwrap();
    eprintln!(
        "Bullet ({label}), gravity alone {seconds} s: sag {:.2} mm, drift {:.4} %, counts {:?}",
        sag * 1e3,
        drift * 100.0,
        last.4
    );
    let [_, plastic, broken] = last.4.unwrap();
    assert_eq!(
        (plastic, broken),
        (0, 0),
        "{label}: connections gave way under gravity"
    );
    (sag, drift)
}

/// The connections of a run whose `first_row_lost` is set, as "Type-Type" kinds (sorted
/// body types, e.g. "Slab-Slab").
fn rows_lost(rec: &pipeline::RunRecord) -> Vec<String> {
    let text = output_text(rec, "connections.csv");
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| head.iter().position(|h| *h == name).unwrap();
    let (a, b, lost) = (col("a"), col("b"), col("first_row_lost"));
    lines
        .map(|l| l.split(',').collect::<Vec<_>>())
        .filter(|f| !f[lost].is_empty())
        .map(|f| {
            let mut k = [
                f[a].split(':').next().unwrap(),
                f[b].split(':').next().unwrap(),
            ];
            k.sort_unstable();
            k.join("-")
        })
        .collect()
}

/// Target (c) of the hand-off benchmark: the undamaged Bullet building (FE-derived
/// connections) under gravity alone sags at most 10 mm and sways at most 0.02 % roof
/// drift; every connection stays intact. The sag of Bullet's locked rows is set by the solver, not by
/// the connection strengths (docs/handoff.md): ≈ g·h²/(ERP·c) with c the fraction of the
/// needed impulse 100 Gauss–Seidel iterations deliver. Measured 3 s runs: 56 mm peak /
/// 36 mm steady and 0.38 % drift at 200 substeps/s, 5.0 mm and 0.010 % at 800. The
/// test runs 1 s at 800 substeps/s (the peak sag comes at 0.08 s), with Bullet's ERP 0.2
/// per substep (`erp_steps_per_second = 0`; the default scales it to 0.05 at 800,
/// docs/ruin-numerics.md, "The error reduction per second", so the sag then falls only as h,
/// not h²). The FE under the same zero record is the reference: its gravity sag (a few mm) and
/// zero drift.
#[test]
fn gravity_alone_the_bullet_building_stands_like_the_fe() {
    let (sag, drift) = gravity_peaks(
        "fe connections, 800 substeps/s",
        "connections = \"fe\"\nsteps_per_second = 800\nexperimental.axial_rows = \"bcb\"\nexperimental.joint_warmstart = 0.0\n\
         experimental.erp_steps_per_second = 0",
        1.0,
    );
    assert!(sag <= 0.010, "sag {:.2} mm > 10 mm", sag * 1e3);
    assert!(drift <= 2e-4, "roof drift {:.4} % > 0.02 %", drift * 100.0);

    let fe = gravity_only("fe", "", "duration = 0.5", 0.5);
    let fe_sag = fe.iter().map(|r| r.3).fold(0.0, f64::max);
    let fe_drift = fe.iter().map(|r| r.2.abs()).fold(0.0, f64::max);
    eprintln!(
        "FE, gravity alone: sag {:.2} mm, drift {:.5} %",
        fe_sag * 1e3,
        fe_drift * 100.0
    );
    // The FE's static gravity state: millimetres, no sway.
    assert!(fe_sag > 1e-4 && fe_sag < 0.010, "FE sag {fe_sag}");
    assert!(fe_drift < 1e-5, "FE drift {fe_drift}");
}

/// The hybrid default holds the undamaged frame under gravity (docs/ruin-convergence.md §2):
/// the `fem2rbd` preset (FE-derived connections, two-way axial row, joint warm start 0.5,
/// pieces that touch once yielded, bases on their connections, 200 substeps/s × 400
/// iterations), 3 s of gravity alone: peak sag 5.21 mm (at 0.08 s) and sway 0.0056 %
/// (release). Bounds: sag ≤ 2 × the FE's static 3.06 mm = 6.13 mm, drift ≤ 0.02 %; with
/// BCB's 100 iterations the same connections sag 28.34 mm.
#[test]
fn gravity_alone_the_hybrid_default_sags_within_twice_the_fe() {
    let (sag, drift) = gravity_peaks("the fem2rbd preset", "preset = \"fem2rbd\"", 3.0);
    assert!(
        (0.004..=2.0 * 3.06e-3).contains(&sag),
        "sag {:.2} mm",
        sag * 1e3
    );
    assert!(drift <= 2e-4, "roof drift {:.4} % > 0.02 %", drift * 100.0);
}

/// Target (c) at BCB's default 200 substeps/s: the connections' locked rows given the
/// members' stiffness through their ERP/CFM (`joint_rows = "member"`, docs/ruin-numerics.md
/// §8.3) and 200 solver iterations. Measured 3 s runs (release): locked rows 61.8 mm peak
/// sag, 0.27 % drift; member rows 18.2 mm, 0.088 %; member rows with 200 iterations
/// 8.9 mm, 0.026 % (0.018 % at 3 s). Those figures had 72 slab–column angular rows with
/// CFM 1.35–1.65, where Bullet's sweeps diverge; stiffened to CFM 0.5
/// (`ruin::stage::MEMBER_ROW_MAX_CFM`) they are 8.30 mm, 0.0369 % (7.09 mm,
/// 0.0306 % at 3 s). The sag target (≤ 10 mm) is met this way; the drift target
/// (≤ 0.02 %) is not, so the drift is asserted at 0.04 %, a regression bound above the
/// measured 0.0369 %, not the target. 1 s (the peak sag comes at 0.08 s).
#[test]
fn gravity_alone_member_rows_at_200_substeps() {
    let (sag, drift) = gravity_peaks(
        "fe connections, member rows, 200 iterations",
        "connections = \"fe\"\nexperimental.joint_rows = \"member\"\nsolver_iterations = 200\n\
         experimental.axial_rows = \"bcb\"\nexperimental.joint_warmstart = 0.0",
        1.0,
    );
    assert!(sag <= 0.010, "sag {:.2} mm > 10 mm", sag * 1e3);
    assert!(drift <= 4e-4, "roof drift {:.4} % > 0.04 %", drift * 100.0);
}

/// Frame3 with FE-derived connections under gravity alone for 1 s at 200 substeps/s,
/// rigid-only, with the extra `[physics]` lines: (peak sag m, peak roof drift ratio,
/// connections plastic or broken at the end).
fn gravity_peaks_1s(extra: &str) -> (f64, f64, usize) {
    let (sag, drift, lost, _) = gravity_peaks_and_rows_1s(extra);
    (sag, drift, lost)
}

/// [`gravity_peaks_1s`] and the kinds of the connections that had a row at its threshold.
fn gravity_peaks_and_rows_1s(extra: &str) -> (f64, f64, usize, Vec<String>) {
    let rec = gravity_record(
        "rigid",
        &format!("time_limit_s = 1.0\nstop_at_rest = false\nconnections = \"fe\"\n{extra}"),
        "",
        1.0,
    );
    let rows = history(&rec);
    let sag = rows.iter().map(|r| r.3).fold(0.0, f64::max);
    let drift = rows.iter().map(|r| r.2.abs()).fold(0.0, f64::max);
    let [_, plastic, broken] = rows.last().unwrap().4.unwrap();
    (sag, drift, plastic + broken, rows_lost(&rec))
}

/// Target (c) on frame3 at BCB's 200 substeps/s and 100 iterations, 1 s (every peak comes
/// before 0.7 s), three ways on the same building:
///
/// * the FE-derived connections' rows (the two-way axial row and
///   `joint_warmstart = 0.5`, docs/handoff.md §4.1) with [`BCB_CONTACTS`], against BCB's
///   two one-way rows without warm start. Measured 3 s runs (release): 28.34 mm peak sag (0.12 s), 0.0197 % peak drift (0.64 s); BCB's rows
///   61.75 mm, 0.275 %. The drift target (≤ 0.02 %) is met; the sag target (≤ 10 mm) is
///   **not** (the joint rows' Gauss–Seidel residual, docs/handoff.md §4), so the sag is
///   asserted at the measured 30 mm bound and at less than half of BCB's rows;
/// * the hybrid defaults (the bases on their connections alone, connected pieces
///   touching once yielded; docs/handoff.md, "At the defaults"): the same sag, 28.34 mm, and
///   0.0283 % peak drift, so the drift target is **not** met at 100 iterations (it is with
///   400: `gravity_alone_the_hybrid_default_sags_within_twice_the_fe`). The
///   drift is asserted in 0.025–0.032 %, a regression band around the measured figure,
///   not the target;
/// * the same with `joint_solve = "direct"` (the joints' bilateral rows solved by a sparse
///   LDLᵀ factorisation at every substep, ε = 1e-3; docs/ruin-numerics.md, "A direct solve").
///   Measured 3 s runs (release): 3.33 mm peak sag, 0.0110 % peak drift, 28 J injected
///   (PGS: 1159 J). Both targets are met; the sag is also asserted at less than a fifth of
///   the PGS run's.
#[test]
fn gravity_alone_at_200_substeps_pgs_direct_and_bcb_rows() {
    let run = gravity_peaks_1s;
    let (sag, drift, lost) = run(BCB_CONTACTS);
    let (sag_new, drift_new, lost_new) = run("");
    let (sag_bcb, drift_bcb, _) = run(&format!(
        "experimental.axial_rows = \"bcb\"\nexperimental.joint_warmstart = 0.0\n{BCB_CONTACTS}"
    ));
    let (sag_d, drift_d, lost_d) = run("experimental.joint_solve = \"direct\"");
    eprintln!(
        "gravity alone 1 s, 200 substeps/s: defaults sag {:.2} mm, drift {:.4} %; \
         BCB rows {:.2} mm, {:.4} %; direct {:.2} mm, {:.4} %",
        sag * 1e3,
        drift * 100.0,
        sag_bcb * 1e3,
        drift_bcb * 100.0,
        sag_d * 1e3,
        drift_d * 100.0
    );
    eprintln!(
        "the defaults: sag {:.2} mm, drift {:.4} %",
        sag_new * 1e3,
        drift_new * 100.0
    );
    assert_eq!(lost, 0, "connections gave way under gravity");
    assert!(drift <= 2e-4, "roof drift {:.4} % > 0.02 %", drift * 100.0);
    assert_eq!(lost_new, 0, "the defaults: connections gave way");
    assert!((sag_new - sag).abs() < 1e-3, "{sag_new} against {sag}");
    assert!(
        (2.5e-4..=3.2e-4).contains(&drift_new),
        "the defaults: roof drift {:.4} %",
        drift_new * 100.0
    );
    assert!(sag <= 0.030, "sag {:.2} mm > 30 mm", sag * 1e3);
    assert!(
        sag < 0.5 * sag_bcb,
        "sag {sag} not below half of BCB's {sag_bcb}"
    );
    assert!(
        drift < 0.2 * drift_bcb,
        "drift {drift} vs BCB's {drift_bcb}"
    );
    assert_eq!(lost_d, 0, "direct: connections gave way under gravity");
    assert!(sag_d <= 0.010, "direct: sag {:.2} mm > 10 mm", sag_d * 1e3);
    assert!(
        drift_d <= 2e-4,
        "direct: roof drift {:.4} % > 0.02 %",
        drift_d * 100.0
    );
    assert!(sag_d < 0.2 * sag, "direct: sag {sag_d} vs PGS's {sag}");
}

/// Slab panels as the FE has them (`panel_connections = "elastic"`: the FE's slab is lumped
/// mass on elastic strips, so a panel never limits a connection; docs/handoff.md §2.6),
/// with the direct joint solve and hinges to rupture, against the panels' group strengths
/// (the default), gravity alone 1 s at 200 substeps/s. With the group strengths the slab
/// panels' bending rows reach their thresholds under their own weight (a quarter panel of
/// 738 kg needs ≈ 1.3 kN·m at each supported edge, its group gives 0.30 kN·m × 1.5;
/// measured 3 s PGS run: 44 slab-panel connections, no other); with elastic panels no
/// connection does, and target (c) holds (measured 3 s release run: 3.17 mm peak sag,
/// 0.0135 % peak drift; FE 3.06 mm).
#[test]
fn elastic_panels_carry_the_slab_under_gravity() {
    let (_, _, lost_g, rows_g) = gravity_peaks_and_rows_1s("experimental.joint_solve = \"direct\"");
    let (sag, drift, lost, rows) = gravity_peaks_and_rows_1s(
        "experimental.joint_solve = \"direct\"\npanel_connections = \"elastic\"\nhinge_end = \"rupture\"",
    );
    eprintln!(
        "gravity alone 1 s, direct: group panels {} connections at a threshold {rows_g:?}; \
         elastic panels {} ({rows:?}), sag {:.2} mm, drift {:.4} %",
        rows_g.len(),
        rows.len(),
        sag * 1e3,
        drift * 100.0
    );
    assert_eq!((lost_g, lost), (0, 0), "connections gave way under gravity");
    assert!(
        !rows_g.is_empty() && rows_g.iter().all(|k| k.contains("Slab")),
        "group panels: {rows_g:?}"
    );
    assert!(rows.is_empty(), "elastic panels: {rows:?}");
    assert!(sag <= 0.010, "sag {:.2} mm > 10 mm", sag * 1e3);
    assert!(drift <= 2e-4, "roof drift {:.4} % > 0.02 %", drift * 100.0);
}

/// Target (b) of the hand-off benchmark with the 1/50-drift hand-off (GB 50011), at the
/// default 200 substeps/s: Bullet does not reach the 0.25 m drop before half-way between the
/// hand-off and the FE's Tc, and no connection starts broken merely from cover spalling
/// or yield (main: 80 broken, 16 plastic, 0.25 m at 1.4 s).
#[test]
fn drift_1_50_handoff_does_not_collapse_early() {
    let tc_guess = 1.16;
    let half = tc_guess + 0.5 * (FE_TC_S - tc_guess);
    let text = lc5(
        "hybrid",
        "criterion = \"drift_1_50\"",
        &format!(
            "time_limit_s = {:.2}\nstop_at_rest = false\nconnections = \"fe\"",
            half + 0.04
        ),
    );
    let rec = run_text("d150.toml", &text);
    let tc = rec.tc_s.unwrap();
    assert!((tc - tc_guess).abs() < 0.011, "Tc {tc}");
    let rows = history(&rec);
    let phys: Vec<&Row> = rows.iter().filter(|r| r.1 == "ruin").collect();
    let start = phys[0].4.unwrap();
    let first_drop = phys.iter().find(|r| r.3 >= 0.25).map(|r| r.0);
    eprintln!(
        "1/50 hand-off at {tc:.3} s: start i/p/b {start:?}; drop 0.25 m at {first_drop:?} \
         (half-way {half:.2} s); max drop by then {:.3} m",
        phys.iter().map(|r| r.3).fold(0.0, f64::max)
    );
    assert_eq!(start[1], 0, "no connection starts plastic from yield alone");
    assert!(
        start[2] < 10,
        "{} connections start broken (main: 80 from cover spalling)",
        start[2]
    );
    let t = first_drop.unwrap_or(f64::INFINITY);
    assert!(
        t >= half,
        "Bullet dropped 0.25 m at {t:.2} s, before half-way {half:.2} s"
    );
}

/// With both FE-consistency options of docs/handoff.md §2.6 (elastic slab panels, hinges to
/// bar rupture) and the rows at exactly the FE's capacities (corrections 1 / 1), the Bullet
/// frame fails where the FE building does, in its story-1 columns: the first connections
/// to break are story-1 column joints, and no slab-panel connection ever reaches a
/// threshold. Measured (ensemble of 8, release, 1/50 hand-off at 1.16 s): 0.25 m drop at
/// 2.16–2.20 s — 2.5 s before the FE's own collapse (4.66 s), docs/handoff.md,
/// "The FE's failure modes". Run to 2.5 s.
#[test]
fn at_the_fe_capacities_the_frame_fails_in_its_story_1_columns() {
    let text = lc5(
        "hybrid",
        "criterion = \"drift_1_50\"",
        &format!("time_limit_s = 2.5\nstop_at_rest = false\n{FE_CAPACITIES}"),
    );
    let rec = run_text("fe_caps.toml", &text);
    let rows = history(&rec);
    let first_drop = rows
        .iter()
        .filter(|r| r.1 == "ruin")
        .find(|r| r.3 >= 0.25)
        .map(|r| r.0);
    let text = output_text(&rec, "connections.csv");
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| head.iter().position(|h| *h == name).unwrap();
    let (a, b, broken, lost) = (
        col("a"),
        col("b"),
        col("time_broken_s"),
        col("first_row_lost"),
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    let mut breaks: Vec<(f64, &str, &str)> = rows
        .iter()
        .filter(|f| !f[broken].is_empty())
        .map(|f| (f[broken].parse().unwrap(), f[a], f[b]))
        .collect();
    breaks.sort_by(|x, y| x.0.total_cmp(&y.0));
    eprintln!(
        "FE capacities, both options: 0.25 m drop at {first_drop:?}; first breaks {:?}",
        &breaks[..breaks.len().min(6)]
    );
    let t = first_drop.expect("the frame stood to 2.5 s");
    assert!((1.9..=2.45).contains(&t), "0.25 m drop at {t:.2} s");
    let story1 = |n: &str| n.starts_with("Column:1:") || n.starts_with("Foundation:");
    assert!(breaks.len() >= 4, "{breaks:?}");
    for (tb, x, y) in &breaks[..4] {
        assert!(story1(x) && story1(y), "{x}–{y} broke at {tb} s");
    }
    assert!(
        rows.iter()
            .filter(|f| f[a].starts_with("Slab:") || f[b].starts_with("Slab:"))
            .all(|f| f[lost].is_empty() && f[broken].is_empty()),
        "a slab-panel connection reached a threshold"
    );
}

/// The FE's own ruin mode (docs/handoff.md, "The FE's own collapse and ruin"): the FE alone,
/// run on past its Tc (4.66 s) until its bodies would first touch, folds its first story
/// sideways and carries the two stories above down whole — floor 1's slab reaches the ground at
/// 5.24 s with all three floors 0.99 m lower, 0.99 / 1.05 / 1.11 m off in plan, slab
/// overlaps 0.93 / 0.93 (the same at PGA × 0.90 … 1.10: 0.89–0.95). A model without
/// contact says nothing after that keyframe; this is the mode the ruin stage is measured
/// against.
#[test]
fn the_fe_alone_folds_its_first_story_and_carries_the_rest_down_whole() {
    let text = lc5("fe", "criterion = \"vertical_drop\"", "")
        .replace("dt = 0.005\n", "dt = 0.005\nduration = 5.3\n");
    let rec = run_text("fe_alone.toml", &text);
    let s = write::run_summary(&rec, false);
    let c = s.fe_first_contact.expect("no contact by 5.3 s");
    let floors: Vec<(f64, f64)> = c
        .ruins
        .floors
        .iter()
        .map(|f| (f.horizontal_offset_m, f.centroid_displacement_m[2]))
        .collect();
    let overlaps: Vec<f64> = c
        .ruins
        .slab_overlap
        .iter()
        .map(|o| o.overlap_ratio)
        .collect();
    eprintln!(
        "FE first contact at {} s ({}): floors (offset, dz) {floors:?}, overlaps {overlaps:?}",
        c.t_s, c.detail
    );
    assert!((5.16..=5.32).contains(&c.t_s), "{}", c.t_s);
    assert!(c.detail.starts_with("Slab:1:") && c.detail.ends_with("reaches the ground"));
    assert_eq!(floors.len(), 3);
    for (k, (off, dz)) in floors.iter().enumerate() {
        assert!((0.9..=1.2).contains(off), "floor {} offset {off}", k + 1);
        assert!((-1.02..=-0.94).contains(dz), "floor {} drop {dz}", k + 1);
    }
    for o in &overlaps {
        assert!((0.88..=0.97).contains(o), "overlap {o}");
    }
    // Before it lands: floor 1 70 % down at 5.08 s, the three floors 0.72 m down and
    // 0.04 m apart.
    let f = s.floors_down.expect("floor 1 never 70 % down");
    assert!(
        (5.0..=5.16).contains(&f.t_s) && f.stories_above_whole,
        "{f:?}"
    );
}

/// Before the ground the Bullet frame comes down as the FE's does (docs/handoff.md,
/// "Joints on the column above"): handed over at 4 % drift (1.53 s) with the FE's capacities
/// and damping (elastic panels, hinges to rupture, corrections 1 / 1, ground damping "fe") and the
/// joints on the column above, at BCB's 100 iterations, floor 1 is 70 % down at 5.25 s (FE 5.08 s; ensemble of 8:
/// 4.57–5.45 s) with the stories above whole — every floor's drop within 0.15 m of floor
/// 1's, the floors within 0.25 m of each other in plan (FE: 0.72 m each, 0.04 m apart; 8
/// of 8 ensemble members).
#[test]
fn after_a_4pct_handoff_the_first_story_folds_with_the_stories_above_whole() {
    let text = fe_throughout("criterion = \"drift_4pct\"", 5.6, "solver_iterations = 100");
    let rec = run_text("fe_mode.toml", &text);
    let down = write::run_summary(&rec, false).floors_down;
    eprintln!("4 % hand-off, FE throughout, joints above: floor 1 70 % down {down:?}");
    let f = down.expect("floor 1 did not come down by 5.6 s");
    assert!((4.5..=5.6).contains(&f.t_s), "at {} s", f.t_s);
    assert!(f.stories_above_whole, "{f:?}");
    for z in &f.floor_drops_m {
        assert!((z - f.floor_drops_m[0]).abs() <= 0.15, "{f:?}");
    }
    for o in &f.story_offsets_m {
        assert!(*o <= 0.25, "{f:?}");
    }
}

/// The floor-2 joints (story-2 column pieces to story-3 column pieces) that broke between
/// `from` and `to` s, of a vertical-drop hand-off run in the "FE throughout" setting with
/// the joints on the column above, to 5.3 s, at 200 substeps/s and `iterations`.
fn floor2_joints_broken(iterations: u32, from: f64, to: f64) -> Vec<String> {
    let text = fe_throughout(
        "criterion = \"vertical_drop\"",
        5.3,
        &format!("solver_iterations = {iterations}"),
    );
    let rec = run_text("landing.toml", &text);
    let ruin = rec.ruin.as_ref().expect("no ruin stage");
    let name = |i: usize| rec.bodies[i].id.to_string();
    ruin.connections
        .iter()
        .filter(|c| {
            let (a, b) = (name(c.a), name(c.b));
            let (a, b) = (a.as_str(), b.as_str());
            (a.starts_with("Column:2:") && b.starts_with("Column:3:"))
                || (a.starts_with("Column:3:") && b.starts_with("Column:2:"))
        })
        .filter(|c| c.broke_at_s.is_some_and(|t| (from..=to).contains(&t)))
        .map(|c| format!("{}–{}", name(c.a), name(c.b)))
        .collect()
}

/// Whether story 2 survives the first floor's landing is a question of the solver's
/// convergence (docs/ruin-numerics.md, "Landings"). After the vertical-drop hand-off floor 1 lands
/// at 5.0–5.06 s at 2.5 m/s; a story-2 column then meets the impulse of the 1.6 t it
/// carries, J·ω = 1.6 MN against its joint's 285 kN compression strength. With BCB's 100
/// iterations at 200 substeps/s the column passes too little of the landing on
/// (`ruin::landing`), and no floor-2 joint breaks; with 400 iterations the joints break
/// at the landing (measured: Column:2:20–Column:3:33 and Column:2:24–Column:3:37 at
/// 5.06 s, Column:2:32–Column:3:45 at 5.10 s), as at 400, 800 and 1600 substeps/s with
/// 100.
#[test]
fn the_first_floor_landing_breaks_story_2_once_the_solve_passes_it_on() {
    let bcb = floor2_joints_broken(100, 4.66, 5.3);
    let converged = floor2_joints_broken(400, 5.0, 5.15);
    eprintln!("floor-2 joints broken: 100 iterations {bcb:?}, 400 iterations {converged:?}");
    assert!(bcb.is_empty(), "100 iterations: {bcb:?}");
    assert!(converged.len() >= 2, "400 iterations: {converged:?}");
}

/// The fastest piece of a 3 % drift hand-off in the "FE throughout" setting (joints
/// above, 400 iterations, 800 substeps/s) to 2.9 s, with the monitor checked once per
/// 25 Hz frame (BCB) or after every substep, and Bullet's ERP 0.2 per substep
/// (`erp_steps_per_second` = 0) or per second (200, the default: 0.05 at 800): (speed
/// m/s, its body, time s, energy the solver injected J).
fn fastest_piece_3pct(monitor_every_substep: bool, erp_steps: f64) -> (f64, String, f64, f64) {
    let text = fe_throughout(
        "criterion = \"drift\"\nratio = 0.03",
        2.9,
        &format!(
            "solver_iterations = 400\nsteps_per_second = 800\nexperimental.erp_steps_per_second = {erp_steps}\n\
             experimental.monitor_every_substep = {monitor_every_substep}"
        ),
    );
    let rec = run_text("thrown.toml", &text);
    let l = &rec.ruin.as_ref().expect("no ruin stage").ledger;
    let (i, t) = l.max_speed_at.expect("no dynamic body");
    (
        l.max_speed_mps,
        rec.bodies[i].id.to_string(),
        t,
        l.injected_j,
    )
}

/// A connection whose shear row broke is left a slider by its other rows: in this run
/// `Column:3:34`–`Column:3:35` (shear w lost at 2.755 s) slides 0.6 m along the broken
/// axis and is pushed 0.35 m into itself against a beam's contact before the 25 Hz
/// monitor sees it past its tolerances (2.835 s). Its locked rows ask for ERP·e/h =
/// 0.2 · 0.35 m · 800/s = 56 m/s, and the 6.25 kg piece is thrown at 89.7 m/s with 12 kJ
/// in one substep (docs/ruin-numerics.md, "The monitor's frame"; Bullet's ERP per substep,
/// `erp_steps_per_second = 0`, as then). Checked after every substep, the
/// connection breaks when it passes its tolerances and the fastest piece is a column
/// piece pinched between a landing beam and the ground (12.2 m/s at 2.515 s, measured
/// with `fem2rbd run --trace-body`).
#[test]
fn a_slider_connection_throws_its_piece_unless_the_monitor_checks_every_substep() {
    let (v_frame, body_frame, t_frame, inj_frame) = fastest_piece_3pct(false, 0.0);
    let (v_sub, body_sub, t_sub, inj_sub) = fastest_piece_3pct(true, 0.0);
    eprintln!(
        "per frame: {v_frame:.1} m/s ({body_frame} at {t_frame:.4} s), {inj_frame:.0} J injected; \
         per substep: {v_sub:.1} m/s ({body_sub} at {t_sub:.4} s), {inj_sub:.0} J injected"
    );
    assert!(v_frame > 40.0, "per frame {v_frame} m/s");
    assert_eq!(body_frame, "Column:3:34");
    assert!((2.82..=2.84).contains(&t_frame), "at {t_frame} s");
    assert!(
        v_sub < 15.0,
        "per substep {v_sub} m/s ({body_sub} at {t_sub} s)"
    );
    assert!(
        inj_sub < 0.1 * inj_frame,
        "{inj_sub} J against {inj_frame} J"
    );
}

/// The same run with the 25 Hz monitor and the default ERP given per second
/// (docs/ruin-numerics.md, "The error reduction per second"): at 800 substeps/s Bullet's ERP
/// is 0.05, so the slider's bias ERP·e/h is a quarter of the above. Measured: fastest piece
/// 10.4 m/s (`Column:1:12` at 2.46 s), 77 J injected — against 89.7 m/s and 56.5 kJ with the ERP
/// per substep, and 12.2 m/s and 979 J with the monitor checked every substep.
#[test]
fn with_the_erp_per_second_the_slider_is_not_thrown() {
    let (v, body, t, inj) = fastest_piece_3pct(false, 200.0);
    eprintln!("ERP per second, per frame: {v:.1} m/s ({body} at {t:.4} s), {inj:.0} J injected");
    assert!(v < 15.0, "{v} m/s ({body} at {t} s)");
    assert!(inj < 500.0, "{inj} J injected");
}

/// A ground-acceleration ramp in X, m/s² (two-column record written to `dir`): a(t) rises
/// at `rate_g`·g per second to `peak_g`·g, then a linear pulse as long as the ramp brings
/// the ground's velocity and displacement back to zero at the record's end, so the ruin
/// stage's zero-end baseline (`motion::Baseline::ZeroEnd`) leaves the ramp as it is. In
/// the ground's frame a slow ramp is a static lateral load m·a(t) on every body: an
/// inertial (mass-proportional) pushover under load control.
fn ramp_record(dir: &Path, rate_g: f64, peak_g: f64) -> PathBuf {
    let (h, g) = (0.005, 9.80665);
    let t1 = peak_g / rate_g;
    let n = (2.0 * t1 / h).round() as usize + 1;
    let after = |i: usize| i as f64 * h > t1 + 1e-9;
    let ramp: Vec<f64> = (0..n)
        .map(|i| {
            if after(i) {
                0.0
            } else {
                rate_g * g * i as f64 * h
            }
        })
        .collect();
    let b0: Vec<f64> = (0..n).map(|i| if after(i) { 1.0 } else { 0.0 }).collect();
    let b1: Vec<f64> = (0..n)
        .map(|i| if after(i) { i as f64 * h - t1 } else { 0.0 })
        .collect();
    // The ruin stage's integration (average acceleration): end velocity and displacement.
    let end = |a: &[f64]| {
        let (mut v, mut d) = (0.0, 0.0);
        for w in a.windows(2) {
            d += h * v + 0.25 * h * h * (w[0] + w[1]);
            v += 0.5 * h * (w[0] + w[1]);
        }
        (v, d)
    };
    let ((v0, d0), (v1, d1), (v2, d2)) = (end(&ramp), end(&b0), end(&b1));
    let det = v1 * d2 - v2 * d1;
    let (c0, c1) = ((-v0 * d2 + v2 * d0) / det, (-v1 * d0 + v0 * d1) / det);
    let text: String = (0..n)
        .map(|i| {
            format!(
                "{:.3} {:.9}\n",
                i as f64 * h,
                ramp[i] + c0 * b0[i] + c1 * b1[i]
            )
        })
        .collect();
    write_file(dir, "ramp.txt", &text)
}

/// Roof-to-base drift in X per ruin-stage frame, (t, drift): the X displacement of the
/// roof centroid of `history.csv` (`output::history::roof`) less the mass-weighted X
/// displacement of the lowest active bodies (the column base pieces), over the height
/// between them. Measured from the base pieces rather than from the ground because a
/// body joined to the kinematic ground leads it by v_g·h (the ground is placed at its
/// end-of-substep pose for the solve, `ruin::ground`), which under a ramp reaches
/// centimetres.
fn roof_to_base_drift(rec: &pipeline::RunRecord) -> Vec<(f64, f64)> {
    use fem2rbd::output::history::{roof, BodyRow};
    let b = &rec.bodies;
    let rows: Vec<BodyRow> = b.iter().map(BodyRow::from).collect();
    let roof = roof(&rows).unwrap();
    let low = (0..b.len())
        .filter(|&i| !b[i].passive)
        .map(|i| b[i].pose0.position[2])
        .fold(f64::MAX, f64::min);
    let base: Vec<usize> = (0..b.len())
        .filter(|&i| !b[i].passive && b[i].pose0.position[2] <= low + 1e-6)
        .collect();
    let base_mass: f64 = base.iter().map(|&i| b[i].mass_kg).sum();
    let height = roof.centroid0_m[2] - low;
    let frames = &rec.ruin.as_ref().unwrap().frames;
    frames
        .iter()
        .map(|f| {
            let dx = |i: usize| f.poses[i].position[0] - b[i].pose0.position[0];
            let top: f64 = roof
                .ids
                .iter()
                .zip(&roof.weights)
                .map(|(&i, w)| w * dx(i))
                .sum();
            let bottom: f64 = base.iter().map(|&i| b[i].mass_kg * dx(i)).sum::<f64>() / base_mass;
            (f.time_s, (top - bottom) / height)
        })
        .collect()
}

/// The rigid-plastic first-story sway mechanism of frame3 from the FE's own section
/// capacities at the gravity axial load (`fe::capacity`, docs/handoff.md §2.1): under a
/// uniform ground acceleration a_g the story-1 shear is M_free·a_g, and the mechanism
/// (hinges at both ends of the four story-1 columns) carries
/// V = Σ (M_base + M_top) / h₁, so a_g/g = Σ (M_base + M_top) / (h₁·M_free·g).
/// The moments are about the columns' local axis along global Y (bending in X sway).
/// Returns a_g/g.
fn story1_mechanism_g() -> f64 {
    use fem2rbd::fe::build::BuildOptions;
    use fem2rbd::fe::capacity::{gravity_capacities, PushSettings};
    let model = fem2rbd::model::Model::load(format!("{ROOT}/data/frame3/model.toml")).unwrap();
    let (_, caps) =
        gravity_capacities(&model, &BuildOptions::default(), &PushSettings::default()).unwrap();
    let h1 = 1.0;
    let mut sum_m = 0.0;
    let mut hinges = 0;
    for m in caps.values() {
        if m.axes[0][2].abs() < 0.99 {
            continue; // not a column
        }
        // Bending in X sway is about global Y: the local axis (y or z) along Y.
        let k = if m.axes[2][1].abs() > m.axes[1][1].abs() {
            0
        } else {
            1
        };
        for (end, node) in m.ends.iter().zip(m.nodes) {
            let at_base = node[2].abs() < 1e-6;
            let at_top = (node[2] - h1).abs() < 1e-6 && m.nodes.iter().any(|n| n[2] < h1 - 1e-6);
            if at_base || at_top {
                sum_m += end.section.moment_nm[k];
                hinges += 1;
            }
        }
    }
    assert_eq!(hinges, 8, "four story-1 columns, two ends each");
    let fixity = model.fixity();
    let m_free: f64 = model
        .lumped_masses()
        .iter()
        .filter(|(tag, _)| !fixity.contains_key(tag))
        .map(|(_, m)| m[0])
        .sum();
    sum_m / (h1 * m_free * model.gravity.g)
}

/// The ground acceleration (g) at which the roof-to-base drift of a ramp run first
/// reaches 2 % (`rate_g` the ramp's rate, g/s): past the peak of its capacity curve the
/// frame runs away within a fraction of a second, so this is its lateral strength.
fn ramp_capacity_g(rec: &pipeline::RunRecord, rate_g: f64) -> Option<f64> {
    roof_to_base_drift(rec)
        .iter()
        .find(|(_, d)| d.abs() >= 0.02)
        .map(|(t, _)| t * rate_g)
}

/// A rigid-only frame3 run under the ramp (0.03 g/s) to `until_s` with FE-derived
/// connections in the "FE throughout" setting and `extra` `[physics]` lines.
fn bullet_pushover(until_s: f64, extra: &str) -> pipeline::RunRecord {
    let dir = tempfile::tempdir().unwrap();
    let r = ramp_record(dir.path(), 0.03, 0.36);
    let text = format!(
        "model = \"{ROOT}/data/frame3/model.toml\"\nmode = \"rigid\"\n\n\
         [[ground_motion]]\nfile = \"{}\"\ndirection = \"X\"\n\n[collapse]\n\
         criterion = \"vertical_drop\"\n\n[physics]\ntime_limit_s = {until_s}\n\
         stop_at_rest = false\n{FE_CAPACITIES}\nground_damping = \"fe\"\n\
         joints = \"column_above\"\n{extra}\n",
        r.display()
    );
    let p = write_file(dir.path(), "ramp.toml", &text);
    pipeline::run(&Scenario::load(&p).unwrap(), &Silent).unwrap()
}

/// Static lateral strength (docs/handoff.md, "The static lateral strength", with
/// [`BCB_CONTACTS`]: the bases also on the ground): under a slow ground ramp
/// (0.03 g/s) the Bullet frame at the FE's capacities, solved with 400 iterations, runs
/// away at the strength of the rigid-plastic story-1 mechanism of its sections (measured
/// 0.238 g against 0.254 g; the force-based FE under the same ramp 0.239 g); with BCB's 100
/// iterations the unconverged rows make it about 18 times softer than the FE (0.67 %
/// roof-to-base drift at 0.03 g; FE 0.037 %) and P–Δ brings it down at 0.09 g.
#[test]
fn under_a_slow_ramp_the_converged_bullet_frame_has_its_sections_strength() {
    let mech = story1_mechanism_g();
    let conv = ramp_capacity_g(
        &bullet_pushover(9.0, &format!("solver_iterations = 400\n{BCB_CONTACTS}")),
        0.03,
    );
    let bcb = bullet_pushover(4.0, BCB_CONTACTS);
    let at_003 = roof_to_base_drift(&bcb)
        .iter()
        .find(|(t, _)| (t - 1.0).abs() < 1e-9)
        .unwrap()
        .1;
    let weak = ramp_capacity_g(&bcb, 0.03);
    eprintln!(
        "story-1 mechanism {mech:.3} g; Bullet 400 iterations {conv:?} g; \
         100 iterations {weak:?} g, drift at 0.03 g {:.3} %",
        at_003 * 100.0
    );
    let conv = conv.expect("the 400-iteration frame must run away by 0.27 g");
    assert!(
        (conv / mech - 1.0).abs() < 0.1,
        "400 iterations: {conv:.3} g against the mechanism's {mech:.3} g"
    );
    let weak = weak.expect("the 100-iteration frame must run away by 0.12 g");
    assert!(
        weak < 0.5 * mech,
        "100 iterations: {weak:.3} g, not under half the mechanism's {mech:.3} g"
    );
    // The FE's initial stiffness gives 0.037 % at 0.03 g (docs/handoff.md).
    assert!(
        at_003.abs() > 5.0 * 0.00037,
        "100 iterations: drift {at_003} at 0.03 g"
    );
}

/// The same ramp on the connections alone, without BCB's ground contact under the
/// connected column bases (`ground_under_connected_bases = false`, docs/handoff.md,
/// "On the connections alone"). A yielded hinge re-locked at its present rotation loses the
/// rotation error through which the solver carries its moment: a saw-tooth that holds 58 % of the
/// capacity, and the frame runs away at 0.179 g, 30 % below the story mechanism. Re-locked
/// by the return mapping (`hinge_return_mapping`) the hinges hold their capacity and the
/// frame runs away at 0.227 g (11 % below the mechanism's 0.254 g; the force-based FE
/// 0.239 g).
#[test]
fn on_its_connections_alone_the_bullet_frame_keeps_its_hinges_with_the_return_mapping() {
    let mech = story1_mechanism_g();
    let alone = "solver_iterations = 400\nexperimental.ground_under_connected_bases = false\n\
                 experimental.connected_pairs_touch = \"never\"";
    let relock = ramp_capacity_g(&bullet_pushover(9.0, alone), 0.03);
    let mapped = ramp_capacity_g(
        &bullet_pushover(
            9.0,
            &format!("{alone}\nexperimental.hinge_return_mapping = true"),
        ),
        0.03,
    );
    eprintln!(
        "story-1 mechanism {mech:.3} g; re-locked at the present rotation {relock:?} g; \
         return mapping {mapped:?} g"
    );
    let relock = relock.expect("the frame re-locked at the present rotation must run away");
    let mapped = mapped.expect("the frame with the return mapping must run away by 0.27 g");
    assert!(
        relock < 0.8 * mech,
        "re-locked at the present rotation: {relock:.3} g, not below 0.8 × {mech:.3} g"
    );
    assert!(
        (mapped / mech - 1.0).abs() < 0.15 && mapped > relock + 0.03,
        "return mapping: {mapped:.3} g against the mechanism's {mech:.3} g (re-locked {relock:.3} g)"
    );
}

/// The FE's own static pushover of frame3 (uniform, mass-proportional load in +X, roof
/// displacement control): the displacement-based mesh of the model (4 elements per
/// column) is stronger than the mechanism of its sections, the force-based formulation of
/// the same sections is not. The disp element's axial strain is constant along it while
/// its neutral axis moves, so its integration points carry a spurious axial compression
/// (OpenSees on the exported model, base element at the peak: section N −55.6 kN against
/// the element's −35.7 kN) and a moment above the section's capacity at the real axial
/// load (Calabrese, Almeida & Pinho 2010, J. Earthquake Eng. 14(S1) 38–68). OpenSees:
/// peak V/W 0.274 (disp), 0.205 (force); the mechanism 0.254 g.
#[test]
fn the_fe_mesh_is_stronger_than_its_sections_and_the_force_formulation_is_not() {
    use fem2rbd::fe::analysis::static_analysis::displacement_increment;
    use fem2rbd::fe::analysis::ConvergenceTest;
    use fem2rbd::fe::build::{BuildOptions, Variant};
    use fem2rbd::fe::run::prepare;
    let mech = story1_mechanism_g();
    let model = fem2rbd::model::Model::load(format!("{ROOT}/data/frame3/model.toml")).unwrap();
    let peak = |variant: Variant| {
        let mut p = prepare(
            &model,
            &BuildOptions {
                variant,
                ..Default::default()
            },
            1,
        )
        .unwrap();
        let d = &mut p.built.domain;
        let fixity = model.fixity();
        for (tag, m) in model.lumped_masses() {
            if !fixity.contains_key(&tag) {
                d.add_nodal_load(p.built.node_index[&tag], [m[0], 0.0, 0.0, 0.0, 0.0, 0.0])
                    .unwrap();
            }
        }
        let roof = p.built.node_index[&312];
        let mut best: f64 = 0.0;
        // 1 mm steps to 1.5 % roof drift; a failed step is retried in 2, 4, 8 sub-steps,
        // and the pushover ends where that fails too (past the peak).
        let test = ConvergenceTest {
            tol: 1e-8,
            max_iter: 100,
        };
        for _ in 0..45 {
            if !displacement_increment(d, roof, 0, 0.001, test) {
                break;
            }
            best = best.max(d.load_factor() / model.gravity.g);
        }
        best
    };
    let disp = peak(Variant::AsModel);
    let force = peak(Variant::Force);
    eprintln!(
        "FE static pushover peak V/W: disp mesh {disp:.4}, force {force:.4}; mechanism {mech:.4}"
    );
    // openseespy 3.7.1 on `fem2rbd export opensees` of the same model, the same load and
    // control (docs/handoff.md, "The static lateral strength").
    for (name, ours, reference) in [("disp", disp, 0.2744), ("force", force, 0.2054)] {
        assert!(
            (ours / reference - 1.0).abs() < 0.03,
            "{name}: peak V/W {ours:.4} against OpenSees {reference}"
        );
    }
    assert!(
        force < mech && mech < disp,
        "the mechanism {mech:.3} must lie between force {force:.3} and disp {disp:.3}"
    );
    assert!(
        disp > 1.25 * force,
        "disp {disp:.3} against force {force:.3}"
    );
}

/// Gravity holds: the undamaged frame3 with the hybrid defaults' connections (FE-derived,
/// the two-way axial row, joint warm start 0.5, rigid-only on a ground record of zeros,
/// every body and connection as at t = 0) sags at most twice the FE's static gravity
/// deflection and sways at most 0.02 % roof drift, at the cheapest setting that meets both:
/// BCB's 200 substeps/s and 100 iterations with the joints' bilateral rows solved directly
/// (`joint_solve = "direct"`, docs/ruin-numerics.md §11.1). The FE's deflection is the
/// largest drop of its nodes under the same zero record (its static gravity state:
/// 3.06 mm). Measured 3 s runs (docs/ruin-convergence.md, "Gravity holds"): the default
/// 28.34 mm, 0.0283 %; 200 iterations 12.42 mm, 400 substeps/s 11.86 mm (both more than
/// twice the FE's); 400 iterations 5.21 mm, 0.0056 %; the direct solve 3.19 mm, 0.0043 %.
/// Every peak comes before 0.1 s, so the Bullet runs take 1 s; 200 iterations is run too,
/// to show that 40 000 sweeps per second do not meet the bound.
#[test]
fn gravity_holds_with_the_direct_joint_solve() {
    let fe = gravity_only("fe", "", "duration = 0.5", 0.5);
    let fe_sag = fe.iter().map(|r| r.3).fold(0.0, f64::max);
    let (sag, drift, lost) = gravity_peaks_1s("experimental.joint_solve = \"direct\"");
    let (sag_200, drift_200, lost_200) = gravity_peaks_1s("solver_iterations = 200");
    eprintln!(
        "gravity alone: FE {:.2} mm; direct {:.2} mm ({:.2} × FE), {:.4} %; \
         200 iterations {:.2} mm ({:.2} × FE), {:.4} %",
        fe_sag * 1e3,
        sag * 1e3,
        sag / fe_sag,
        drift * 100.0,
        sag_200 * 1e3,
        sag_200 / fe_sag,
        drift_200 * 100.0
    );
    assert!((2.5e-3..=3.5e-3).contains(&fe_sag), "FE sag {fe_sag}");
    assert_eq!(
        (lost, lost_200),
        (0, 0),
        "connections gave way under gravity"
    );
    assert!(
        sag <= 2.0 * fe_sag,
        "direct: sag {:.2} mm > 2 × the FE's {:.2} mm",
        sag * 1e3,
        fe_sag * 1e3
    );
    assert!(
        drift <= 2e-4,
        "direct: roof drift {:.4} % > 0.02 %",
        drift * 100.0
    );
    assert!(
        sag_200 > 2.0 * fe_sag,
        "200 iterations: sag {:.2} mm within 2 × the FE's: a cheaper setting meets the bound",
        sag_200 * 1e3
    );
}

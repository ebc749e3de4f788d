//! `fem2rbd modal` and `fem2rbd fe` on frame3: the printed periods and mode characters
//! (the building's modes by default, the lowest with `--lowest`), the written `nodes.csv` against OpenSees's LC1 elastic run at t = 2.0 s (results.md:
//! node 312 ux/uy = +0.457/−1.740 mm), the summary, and bad input refused with nothing
//! written.

use crate::support::{read_csv, root, stdout_of};
use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_fem2rbd"))
}

fn gm(dir: &str, file: &str, pga: f64) -> String {
    format!(
        "{dir}={},pga={pga}",
        root().join("data/ground-motions").join(file).display()
    )
}

/// `fem2rbd modal ARGS` on the frame3 stand-in: its table rows (split on white space) and
/// the whole text.
fn frame3_modal(args: &[&str]) -> (Vec<Vec<String>>, String) {
    let text = String::from_utf8(stdout_of(
        bin()
            .arg("modal")
            .args(args)
            .arg(root().join("data/frame3-standin/model.toml")),
    ))
    .unwrap();
    let rows = text
        .lines()
        .skip(1)
        .take_while(|l| !l.is_empty())
        .map(|l| l.split_whitespace().map(String::from).collect())
        .collect();
    (rows, text)
}

/// The modal table's rows are exactly `expect`: (mode index, period in s, character) —
/// columns mode, index, T, f, MX, MY, MZ, MRZ, character.
fn assert_rows(rows: &[Vec<String>], text: &str, expect: &[(&str, &str, &str)]) {
    assert_eq!(rows.len(), expect.len(), "{text}");
    for (r, &(i, t, c)) in rows.iter().zip(expect) {
        assert_eq!(
            (r[1].as_str(), r[2].as_str(), r[8].as_str()),
            (i, t, c),
            "{text}"
        );
    }
}

#[test]
fn modal_lowest_prints_frame3_periods_and_characters() {
    let (rows, text) = frame3_modal(&["--modes", "4", "--variant", "force", "--lowest"]);
    assert_rows(
        &rows,
        &text,
        &[
            ("1", "0.31600", "X"),
            ("2", "0.31599", "Y"),
            ("3", "0.18349", "vertical"),
            ("4", "0.18060", "torsion"),
        ],
    );
    // effective mass ratio of the X mode in X; of the torsion mode in torsion
    assert_eq!(rows[0][4], "0.873", "{text}");
    assert_eq!(rows[3][7], "0.877", "{text}");
    // below the table: the sums, the X and Y modes, and the note that 87 % is under 90 %
    let summary: Vec<&str> = text.lines().skip(6).collect();
    assert!(
        summary[0].starts_with("effective mass of the 4 modes: X 0.873, Y 0.873"),
        "{text}"
    );
    assert!(
        summary[1].starts_with("largest in X: mode 1, T = 0.31600 s"),
        "{text}"
    );
    assert!(summary[2].starts_with("under 90 % in X"), "{text}");
    assert!(
        summary[3].starts_with("largest in Y: mode 2, T = 0.31599 s"),
        "{text}"
    );
    assert_eq!(summary[5], "the 4 lowest modes", "{text}");
}

/// By default the building's modes, numbered as in the whole spectrum: OpenSees lists
/// frame3's modes as X, Y, vertical (3), torsion (4), vertical (5, 6), second X (7,
/// 0.1055 s; tests/fixtures/opensees-frame3/results.md §2), and the vertical slab modes
/// carry no lateral mass, so they are the ones skipped.
#[test]
fn modal_by_default_lists_frame3_building_modes_and_what_it_skips() {
    let (rows, text) = frame3_modal(&["--modes", "4", "--variant", "force"]);
    assert_rows(
        &rows,
        &text,
        &[
            ("1", "0.31600", "X"),
            ("2", "0.31599", "Y"),
            ("4", "0.18060", "torsion"),
            ("7", "0.10547", "X"),
        ],
    );
    assert!(
        text.contains("the building's modes: the 4 lowest with at least 1 % effective mass"),
        "{text}"
    );
    // Index 3 and 5–6 are skipped: vertical slab modes without lateral mass.
    let skipped = text.lines().find(|l| l.starts_with("skipped:")).unwrap();
    assert!(
        skipped.starts_with(
            "skipped: 3 modes, index 3 (0.18060 s < T < 0.31599 s), 5–6 (0.10547 s < T < \
             0.18060 s); together at most X 0.0000, Y 0.0000, torsion 0.0000"
        ),
        "{text}"
    );
    assert!(
        skipped.ends_with("(none of them can be a building mode)"),
        "{text}"
    );
}

/// A cantilever of length L = 3 m with m = 1000 kg at its tip and no other mass: its three
/// modes are the tip's translations with k = 3EI/L³ sideways and EA/L along the axis
/// (Euler–Bernoulli, exact for the elastic beam-column), T = 2π √(m/k); with every mode
/// computed the effective masses add up to the whole mass in X, Y and Z.
#[test]
fn modal_lists_a_cantilevers_closed_form_modes_and_their_whole_mass() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("cantilever.toml");
    let (e, a, iy, iz, l, m): (f64, f64, f64, f64, f64, f64) =
        (3.0e10, 0.09, 6.75e-4, 3.0e-4, 3.0, 1000.0);
    std::fs::write(
        &model,
        format!(
            "name = \"cantilever\"\n\
             [[section]]\ntag = 1\ntype = \"elastic\"\nE = {e:e}\nG = 1.25e10\nA = {a}\n\
             Iy = {iy:e}\nIz = {iz:e}\nJ = 1.14e-3\n\
             [[transformation]]\ntag = 1\ntype = \"linear\"\nvecxz = [1.0, 0.0, 0.0]\n\
             [[node]]\ntag = 1\nx = 0.0\ny = 0.0\nz = 0.0\n\
             [[node]]\ntag = 2\nx = 0.0\ny = 0.0\nz = {l:?}\n\
             [[support]]\nnode = 1\ndofs = [1, 1, 1, 1, 1, 1]\n\
             [[element]]\ntag = 1\ntype_name = \"Column\"\ngroup = 1\n\
             type = \"elastic_beam_column\"\nnodes = [1, 2]\nsection = 1\ntransf = 1\n\
             [[mass]]\nnode = 2\nm = {m:?}\n"
        ),
    )
    .unwrap();
    let modal = |extra: &[&str]| -> serde_json::Value {
        serde_json::from_slice(&stdout_of(
            bin()
                .args(["modal", "--modes", "3", "--json"])
                .args(extra)
                .arg(&model),
        ))
        .unwrap()
    };
    let v = modal(&["--lowest"]);
    assert_eq!(v["selection"], "lowest");
    let t = |k: f64| 2.0 * std::f64::consts::PI * (m / k).sqrt();
    // local z is global X (vecxz), so X bends about Iy and Y about Iz
    let (tx, ty, tz) = (
        t(3.0 * e * iy / l.powi(3)),
        t(3.0 * e * iz / l.powi(3)),
        t(e * a / l),
    );
    let modes = v["modes"].as_array().unwrap();
    for (mode, want) in modes.iter().zip([ty, tx, tz]) {
        let got = mode["period_s"].as_f64().unwrap();
        assert!((got - want).abs() < 1e-9 * want, "{got} vs {want}");
    }
    for d in 0..3 {
        let sum = v["effective_mass_ratio_sum"][d].as_f64().unwrap();
        assert!((sum - 1.0).abs() < 1e-12, "direction {d}: {sum}");
    }
    assert_eq!(v["largest_effective_mass_mode"]["X"], 2);
    assert_eq!(v["largest_effective_mass_mode"]["Y"], 1);
    // The building's modes: the two bending modes only (the axial mode carries no
    // lateral mass, and a node on the axis no torsional mass), nothing skipped below.
    let b = modal(&[]);
    assert_eq!(b["selection"], "building");
    let modes = b["modes"].as_array().unwrap();
    assert_eq!(modes.len(), 2);
    for (mode, (want, index)) in modes.iter().zip([(ty, 1), (tx, 2)]) {
        assert_eq!(mode["index"], index);
        let got = mode["period_s"].as_f64().unwrap();
        assert!((got - want).abs() < 1e-9 * want, "{got} vs {want}");
        assert!(mode["residual"].as_f64().unwrap() < 1e-9);
    }
    assert_eq!(b["skipped"]["count"], 0);
}

#[test]
fn modal_json_gives_the_table_at_full_precision() {
    let run = |json: bool| {
        let mut c = bin();
        c.args(["modal", "--modes", "4", "--variant", "force"])
            .arg(root().join("data/frame3-standin/model.toml"));
        if json {
            c.arg("--json");
        }
        String::from_utf8(stdout_of(&mut c)).unwrap()
    };
    let table = run(false);
    let v: serde_json::Value = serde_json::from_str(&run(true)).unwrap();
    let modes = v["modes"].as_array().unwrap();
    assert_eq!(modes.len(), 4);
    for (line, m) in table.lines().skip(1).zip(modes) {
        let cols: Vec<&str> = line.split_whitespace().collect();
        let t = m["period_s"].as_f64().unwrap();
        assert_eq!(m["index"].as_u64().unwrap().to_string(), cols[1], "{line}");
        assert_eq!(format!("{t:.5}"), cols[2], "{line}");
        assert_eq!(m["character"].as_str().unwrap(), cols[8]);
        let f = m["frequency_hz"].as_f64().unwrap();
        assert!((f * t - 1.0).abs() < 1e-15);
    }
    // Full precision: the period is not the 5-decimal value of the table.
    let t1 = modes[0]["period_s"].as_f64().unwrap();
    assert_ne!(t1, 0.316);
    assert!((t1 - 0.316).abs() < 5e-6);
}

#[test]
fn fe_lc1_elastic_two_seconds_matches_opensees() {
    let dir = tempfile::tempdir().unwrap();
    let out_dir = dir.path().join("run");
    let out = bin()
        .args(["--quiet", "fe"])
        .arg(root().join("data/frame3-standin/model.toml"))
        .args(["--gm", &gm("X", "RSN6_IMPVALL.I_I-ELC180.AT2", 0.10)])
        .args(["--gm", &gm("Y", "RSN6_IMPVALL.I_I-ELC270.AT2", 0.08)])
        .args(["--gm", &gm("Z", "RSN6_IMPVALL.I_I-ELC-UP.AT2", 0.06)])
        .args([
            "--variant",
            "elastic",
            "--duration",
            "2.0",
            "--every",
            "20",
            "--out",
        ])
        .arg(&out_dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        out.stderr.is_empty(),
        "--quiet prints nothing: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let (head, rows) = read_csv(&out_dir.join("nodes.csv"));
    assert_eq!(head.len(), 1 + 6 * 43);
    assert_eq!(rows.len(), 21, "t = 0, 0.1, ..., 2.0");
    let col = |name: &str| head.iter().position(|h| h == name).unwrap();
    let last = rows.last().unwrap();
    assert!((last[0] - 2.0).abs() < 1e-9);
    let (ux, uy) = (last[col("ux_312")] * 1e3, last[col("uy_312")] * 1e3);
    eprintln!("fe CLI LC1 elastic t = 2 s: node 312 ux/uy = {ux:+.4}/{uy:+.4} mm (OpenSees +0.457/-1.740)");
    // 2 % of the peak response (7.363 / 5.280 mm)
    assert!((ux - 0.457).abs() < 0.02 * 7.363, "ux {ux}");
    assert!((uy + 1.740).abs() < 0.02 * 5.280, "uy {uy}");
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out_dir.join("fe_summary.json")).unwrap())
            .unwrap();
    assert_eq!(s["stop"]["reason"], "completed");
    assert_eq!(s["steps"], 400);
    assert!((s["periods_s"][0].as_f64().unwrap() - 0.316).abs() < 1e-4);
    // The largest uz is the gravity sag of a slab centre (OpenSees: -8.5 mm elastic).
    let uz = s["peaks"]["uz"]["value"].as_f64().unwrap();
    assert!((uz + 0.0085).abs() < 0.001, "uz peak {uz}");
    // reactions.csv: the recorded steps after t = 0; frame3 has no shells, so the frames
    // carry the whole base shear; the vertical reaction is the weight (92.08 kN) give or
    // take the vertical inertia of a 0.06 g record.
    let (head, rows) = read_csv(&out_dir.join("reactions.csv"));
    assert_eq!(
        head,
        [
            "t",
            "rx_n",
            "ry_n",
            "rz_n",
            "mx_nm",
            "my_nm",
            "mz_nm",
            "vx_frame_n",
            "vx_wall_n",
            "vy_frame_n",
            "vy_wall_n"
        ]
    );
    assert_eq!(rows.len(), 20, "t = 0.1, ..., 2.0");
    assert!((rows[19][0] - 2.0).abs() < 1e-9);
    let w = 9386.75 * 9.80665;
    for r in &rows {
        assert!(
            (r[7] + r[1]).abs() <= 1e-9 * r[1].abs() + 1e-6,
            "vx_frame {} rx {}",
            r[7],
            r[1]
        );
        assert!(
            (r[9] + r[2]).abs() <= 1e-9 * r[2].abs() + 1e-6,
            "vy_frame {} ry {}",
            r[9],
            r[2]
        );
        assert_eq!((r[8], r[10]), (0.0, 0.0));
        assert!((r[3] - w).abs() < 0.15 * w, "rz {} against W {w}", r[3]);
    }
    // The elastic frame's base shear follows its roof displacement (the first mode carries
    // 87 % of the mass): V_x = −ΣR_x and ux_312 at the same steps correlate closely and
    // with a positive stiffness.
    let (nhead, nrows) = read_csv(&out_dir.join("nodes.csv"));
    let ux = nhead.iter().position(|h| h == "ux_312").unwrap();
    let pairs: Vec<(f64, f64)> = rows
        .iter()
        .zip(&nrows[1..])
        .map(|(r, n)| {
            assert!((r[0] - n[0]).abs() < 1e-9, "same times");
            (n[ux], -r[1])
        })
        .collect();
    let k = pairs.len() as f64;
    let (mu, mv) = pairs
        .iter()
        .fold((0.0, 0.0), |a, p| (a.0 + p.0 / k, a.1 + p.1 / k));
    let (mut suv, mut suu, mut svv) = (0.0, 0.0, 0.0);
    for (u, v) in &pairs {
        suv += (u - mu) * (v - mv);
        suu += (u - mu) * (u - mu);
        svv += (v - mv) * (v - mv);
    }
    let rho = suv / (suu * svv).sqrt();
    eprintln!(
        "fe LC1 elastic: Vx against ux_312: correlation {rho:.4}, slope {:.3e} N/m",
        suv / suu
    );
    assert!(
        rho > 0.9,
        "base shear and roof displacement correlate by {rho}"
    );
}

#[test]
fn fe_bad_input_is_refused_and_nothing_written() {
    let dir = tempfile::tempdir().unwrap();
    let out_dir = dir.path().join("run");
    let model = root().join("data/frame3-standin/model.toml");
    let cases: [(Vec<String>, &str); 4] = [
        (
            vec!["--gm".into(), "W=x.at2".into()],
            "unknown direction \"W\"",
        ),
        (
            vec!["--gm".into(), "X=missing.at2".into()],
            "missing.at2 does not exist",
        ),
        (
            vec![
                "--gm".into(),
                gm("X", "RSN6_IMPVALL.I_I-ELC180.AT2", 0.1) + "x",
            ],
            "is not a number",
        ),
        (vec!["--gm".into(), "X".into()], "expected DIR=PATH"),
    ];
    for (args, msg) in cases {
        let out = bin()
            .arg("fe")
            .arg(&model)
            .args(&args)
            .arg("--out")
            .arg(&out_dir)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success());
        assert!(err.contains(msg), "{args:?}: {err}");
        assert!(!out_dir.exists(), "{args:?} wrote output");
    }
    let out = bin()
        .arg("fe")
        .arg(dir.path().join("nomodel.toml"))
        .args([
            "--gm",
            &gm("X", "RSN6_IMPVALL.I_I-ELC180.AT2", 0.1),
            "--out",
        ])
        .arg(&out_dir)
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("nomodel.toml"));
    assert!(!out_dir.exists());
}

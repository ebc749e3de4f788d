//! Ground-motion readers: the shipped El Centro records, both AT2 header forms, two-column
//! and BCB CSV files, and bad files whose errors must name file:line.
use fem2rbd_fe::model::limits::InputFileError;
use fem2rbd_fe::motion::{read_record, Format, GroundMotion, MotionError, Record, G};
use std::path::{Path, PathBuf};

fn gm_dir() -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join("data/ground-motions")
}
fn fixture(name: &str) -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .join("tests/fixtures/motion")
        .join(name)
}
fn one(path: &Path, f: Format) -> Record {
    let mut v = read_record(path, f).unwrap();
    assert_eq!(v.len(), 1);
    v.pop().unwrap()
}
fn err(path: &Path, f: Format) -> String {
    format!("{:#}", read_record(path, f).unwrap_err())
}

/// NPTS, dt, PGA (g, signed peak in the file) and its time, from the shared README and
/// the files themselves (max |value|; all three peaks are negative).
const EL_CENTRO: [(&str, usize, f64, f64); 3] = [
    ("RSN6_IMPVALL.I_I-ELC180.AT2", 5372, -0.2807955, 2.18),
    ("RSN6_IMPVALL.I_I-ELC270.AT2", 5346, -0.210743, 11.51),
    ("RSN6_IMPVALL.I_I-ELC-UP.AT2", 5378, -0.1781367, 3.37),
];

#[test]
fn el_centro_components_match_the_readme() {
    for (file, npts, peak_g, t_peak) in EL_CENTRO {
        let r = one(&gm_dir().join(file), Format::Auto);
        assert_eq!(r.accel_mps2.len(), npts, "{file}");
        assert_eq!(r.dt_s, 0.01, "{file}");
        assert_eq!(r.t0_s, 0.0);
        let (pga, t) = r.pga();
        assert!((pga - peak_g.abs() * G).abs() < 1e-12, "{file}: {pga}");
        assert!((t - t_peak).abs() < 1e-9, "{file}: {t}");
        let i = (t_peak / 0.01).round() as usize;
        assert_eq!(r.accel_mps2[i], peak_g * G);
        assert_eq!(r.name, file.trim_end_matches(".AT2"));
        // README, rounded: 0.2808 / 0.2107 / 0.1781 g.
        assert!(((pga / G) * 1e4).round() / 1e4 - (peak_g.abs() * 1e4).round() / 1e4 == 0.0);
    }
    // First sample of 180: .9984852E-03 g.
    let r = one(&gm_dir().join(EL_CENTRO[0].0), Format::At2);
    assert_eq!(r.accel_mps2[0], 0.9984852e-3 * G);
    assert!((r.end_time_s() - 53.71).abs() < 1e-9);
}

#[test]
fn three_component_length_is_the_shortest() {
    let c: Vec<Record> = EL_CENTRO
        .iter()
        .map(|(f, ..)| one(&gm_dir().join(f), Format::Auto))
        .collect();
    let gm = GroundMotion::new(Some(c[0].clone()), Some(c[1].clone()), Some(c[2].clone()));
    assert!((gm.duration_s() - 53.45).abs() < 1e-9);
    // Zero after the end (53.45 s) even though X and Z run longer.
    assert_eq!(gm.accel_at(53.46), [0.0; 3]);
    assert_eq!(gm.accel_at(-0.01), [0.0; 3]);
    // Linear interpolation halfway between samples 218 and 219 of X.
    let a = gm.accel_at(2.185);
    let expect = 0.5 * (c[0].accel_mps2[218] + c[0].accel_mps2[219]);
    assert!((a[0] - expect).abs() < 1e-12);
}

#[test]
fn both_at2_header_forms_read_the_same() {
    let a = one(&fixture("form_a.at2"), Format::Auto);
    let b = one(&fixture("form_b.at2"), Format::Auto);
    let expect: Vec<f64> = [0.1, -0.25, 0.05, 0.0, 0.125, -0.03, 0.01]
        .iter()
        .map(|g| g * G)
        .collect();
    for r in [&a, &b] {
        assert_eq!(r.dt_s, 0.02);
        assert_eq!(r.accel_mps2.len(), 7);
        for (x, y) in r.accel_mps2.iter().zip(&expect) {
            assert!((x - y).abs() < 1e-15);
        }
    }
}

#[test]
fn scaling_gives_the_requested_pga_exactly() {
    let mut r = one(&gm_dir().join(EL_CENTRO[0].0), Format::Auto);
    r.scale_to_pga(0.93).unwrap();
    let (pga, t) = r.pga();
    assert_eq!(pga, 0.93 * G);
    assert!((t - 2.18).abs() < 1e-9);
    let mut gm = GroundMotion::new(
        Some(one(&gm_dir().join(EL_CENTRO[0].0), Format::Auto)),
        Some(one(&gm_dir().join(EL_CENTRO[1].0), Format::Auto)),
        Some(one(&gm_dir().join(EL_CENTRO[2].0), Format::Auto)),
    );
    gm.scale_to_pga([Some(0.93), Some(1.19), Some(0.57)])
        .unwrap();
    for (c, target) in gm.components.iter().zip([0.93, 1.19, 0.57]) {
        assert_eq!(c.as_ref().unwrap().pga().0, target * G);
    }
    let mut gm2 = GroundMotion::new(None, None, None);
    let e = gm2.scale_to_pga([Some(0.1), None, None]).unwrap_err();
    assert!(matches!(e, MotionError::NoComponent { axis: "X" }), "{e}");
    assert_eq!(e.to_string(), "no X component to scale");
}

#[test]
fn time_scale_halves_the_duration() {
    let r = one(&gm_dir().join(EL_CENTRO[1].0), Format::Auto);
    let mut gm = GroundMotion::new(Some(r.clone()), None, None);
    let d0 = gm.duration_s();
    gm.time_scale(0.5).unwrap();
    assert!((gm.duration_s() - 0.5 * d0).abs() < 1e-12);
    assert!((gm.duration_s() - 26.725).abs() < 1e-9);
    // Same peak, at half the time.
    let s = gm.components[0].as_ref().unwrap();
    assert_eq!(s.pga().0, r.pga().0);
    assert!((s.pga().1 - 11.51 / 2.0).abs() < 1e-9);
    assert_eq!(gm.accel_at(5.755)[0], r.accel_at(11.51));
    assert!(matches!(
        gm.time_scale(0.0),
        Err(MotionError::Record { .. })
    ));
}

#[test]
fn bcb_csv_and_two_column_files() {
    let c = read_record(&fixture("bcb_motion.csv"), Format::Auto).unwrap();
    assert_eq!(c.len(), 3);
    assert_eq!(c[0].name, "bcb_motion:x");
    assert!((c[0].dt_s - 0.04).abs() < 1e-12);
    assert_eq!(c[0].accel_mps2, vec![0.0, 1.5, 3.0, -1.0, 0.0]);
    assert_eq!(c[1].accel_mps2, vec![0.0, -2.0, -4.0, 2.0, 0.0]);
    assert_eq!(c[2].accel_mps2, vec![0.0, 0.25, 0.5, 0.0, 0.0]);

    let t = one(
        &fixture("two_column_g.txt"),
        Format::TwoColumn { in_g: true },
    );
    assert_eq!(t.accel_mps2, vec![0.0, 0.2 * G, -0.1 * G, 0.05 * G]);
    let m = one(&fixture("two_column_g.txt"), Format::Auto);
    assert_eq!(m.accel_mps2, vec![0.0, 0.2, -0.1, 0.05]);
    assert!((m.dt_s - 0.01).abs() < 1e-12);
}

#[test]
fn bad_files_name_file_and_line() {
    let f = fixture("bad_header.at2");
    assert_eq!(
        err(&f, Format::Auto),
        format!(
            "{}:4: bad AT2 header line `NPTS=   seven, DT=   .0200 SEC,`: expected \
             `NPTS= <n>, DT= <dt> SEC` or `<n> <dt> NPTS, DT`",
            f.display()
        )
    );
    let f = fixture("npts_mismatch.at2");
    assert_eq!(
        err(&f, Format::At2),
        format!("{}:6: 6 samples read but NPTS = 7 (line 4)", f.display())
    );
    let f = fixture("non_number.at2");
    assert_eq!(
        err(&f, Format::At2),
        format!("{}:6: `.1O00000E-01` is not a number", f.display())
    );
    let f = fixture("uneven.txt");
    assert_eq!(
        err(&f, Format::Auto),
        format!(
            "{}:3: time 0.025 is off the uniform step 0.01 s (expected 0.02)",
            f.display()
        )
    );
    let f = fixture("csv_bad_number.csv");
    assert_eq!(
        err(&f, Format::Auto),
        format!("{}:3: `x2` is not a number", f.display())
    );
    // A two-column file read as CSV: wrong column count, named at line 1.
    let f = fixture("two_column_g.txt");
    assert_eq!(
        err(&f, Format::Csv),
        format!(
            "{}:1: expected 4 columns (t, ax, ay, az), found 2",
            f.display()
        )
    );
    // An AT2 file without a header line at all.
    let f = fixture("bcb_motion.csv");
    assert_eq!(
        err(&f, Format::At2),
        format!(
            "{}:4: AT2 header line not found: expected `NPTS= <n>, DT= <dt> SEC` or \
             `<n> <dt> NPTS, DT` within the first 10 lines",
            f.display()
        )
    );
    let f = fixture("cm_units.at2");
    assert_eq!(
        err(&f, Format::Auto),
        format!(
            "{}:3: AT2 values must be in g, the header says \
             `ACCELERATION TIME SERIES IN UNITS OF CM/SEC/SEC`",
            f.display()
        )
    );
    // The kind of failure: a line of the file, with its number.
    let e = read_record(&fixture("non_number.at2"), Format::At2).unwrap_err();
    assert!(matches!(e, MotionError::Syntax { line: 6, .. }), "{e}");
    let missing = fixture("does_not_exist.at2");
    let e = read_record(&missing, Format::Auto).unwrap_err();
    assert!(
        matches!(&e, MotionError::File(InputFileError::Missing { path, .. }) if path == &missing),
        "{e}"
    );
    assert!(err(&missing, Format::Auto).contains("does_not_exist.at2"));
}

#[test]
fn ground_motion_from_files_and_csv() {
    let gm = GroundMotion::from_files(
        [
            Some(&gm_dir().join(EL_CENTRO[0].0)),
            None,
            Some(&gm_dir().join(EL_CENTRO[2].0)),
        ],
        Format::Auto,
    )
    .unwrap();
    assert!(gm.components[1].is_none());
    assert!((gm.duration_s() - 53.71).abs() < 1e-9);
    assert_eq!(gm.accel_at(2.18)[0], -0.2807955 * G);
    assert_eq!(gm.accel_at(2.18)[1], 0.0);
    let c = GroundMotion::from_csv(&fixture("bcb_motion.csv")).unwrap();
    assert!((c.duration_s() - 0.16).abs() < 1e-12);
    // Halfway between rows 2 and 3 (t = 0.10): (3.0 + −1.0)/2, (−4 + 2)/2, (0.5 + 0)/2.
    let a = c.accel_at(0.10);
    assert!(
        (a[0] - 1.0).abs() < 1e-12 && (a[1] + 1.0).abs() < 1e-12 && (a[2] - 0.25).abs() < 1e-12
    );
    let e = GroundMotion::from_files([Some(&fixture("bcb_motion.csv")), None, None], Format::Auto)
        .unwrap_err();
    assert!(matches!(e, MotionError::Content { .. }), "{e}");
    assert_eq!(
        e.to_string(),
        format!(
            "{}: holds 3 components; give it as a three-component CSV instead",
            fixture("bcb_motion.csv").display()
        )
    );
}

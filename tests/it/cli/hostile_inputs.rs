//! The standing hostile-input suite (docs/reliability.md).
//!
//! `every_bad_input_is_refused_cleanly`: a table of bad inputs for every subcommand and
//! file format, each run through the real binary. Every case asserts
//! * the exit code (1: refused input; 2: a command line clap rejects),
//! * that the message names the file and line, or the item at fault (substrings),
//! * no panic and no abort (no `panicked`, no signal),
//! * that the working folder (which holds every output location) holds nothing new
//!   afterwards: no output, no temporary file, no partial folder.
//!
//! The property tests run the parsers (model TOML and JSON, scenario, scene JSON, AT2,
//! run folder) on generated inputs: they must return `Ok` or `Err`, never panic. They
//! run `PROPTEST_CASES` cases each (default 64 here, a few seconds; set e.g.
//! `PROPTEST_CASES=5000` for a longer search).
use proptest::prelude::*;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_fem2rbd");

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Every path under `dir` (relative), recursively.
fn listing(dir: &Path) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            out.insert(p.strip_prefix(dir).unwrap().display().to_string());
            if p.is_dir() && !p.is_symlink() {
                stack.push(p);
            }
        }
    }
    out
}

/// A scenario in the work folder; `{X}` is replaced by the El Centro 180 record.
const SCENARIO: &str = r#"model = "model.toml"
mode = "rigid"
output = "out"
[[ground_motion]]
file = "elc180.at2"
direction = "X"
pga_g = 0.3
time_scale = 0.5
"#;

/// One case: a name, the files it writes into the work folder first, the arguments
/// (`{w}` = the work folder), the exit code and the substrings of stderr.
struct Case {
    name: &'static str,
    files: Vec<(&'static str, String)>,
    args: Vec<String>,
    code: i32,
    want: Vec<String>,
}

fn case(name: &'static str, args: &str, code: i32, want: &[&str]) -> Case {
    Case {
        name,
        files: Vec::new(),
        args: args.split(' ').map(str::to_string).collect(),
        code,
        want: want.iter().map(|s| s.to_string()).collect(),
    }
}

impl Case {
    fn with(mut self, file: &'static str, text: impl Into<String>) -> Case {
        self.files.push((file, text.into()));
        self
    }
}

/// The scenario with `from` replaced by `to` (or `to` appended when `from` is empty).
fn scenario(from: &str, to: &str) -> String {
    if from.is_empty() {
        format!("{SCENARIO}{to}\n")
    } else {
        assert!(SCENARIO.contains(from), "{from}");
        SCENARIO.replacen(from, to, 1)
    }
}

/// The frame3 model with `from` replaced by `to`.
fn model(from: &str, to: &str) -> String {
    let m = std::fs::read_to_string(root().join("data/frame3/model.toml")).unwrap();
    assert!(m.contains(from), "{from}");
    m.replacen(from, to, 1)
}

/// A model of `n` nodes on a line and nothing else (over the node bound when n > 200 000).
fn nodes_model(n: usize) -> String {
    let mut s = String::with_capacity(n * 40);
    for i in 1..=n {
        s.push_str(&format!(
            "[[node]]\ntag = {i}\nx = {}.0\ny = 0.0\nz = 0.0\n",
            i % 1000
        ));
    }
    s
}

/// The drop scene (`data/scenes/drop.json`) with `from` replaced by `to`.
fn drop_scene(from: &str, to: &str) -> String {
    let s = std::fs::read_to_string(root().join("data/scenes/drop.json")).unwrap();
    assert!(s.contains(from), "{from}");
    s.replacen(from, to, 1)
}

/// A study of the El Centro record on the scenario `s.toml` ([`SCENARIO`]); `PGA` is the
/// list of intensities (line 8).
const STUDY: &str = "base = \"s.toml\"\n[records]\ntime_scale = 0.5\n[[records.list]]\n\
                     name = \"e\"\nx = \"elc180.at2\"\n[intensity]\npga_g = [PGA]\n";

/// frame3 with `rigid_body = false` on every element (FE-only: no rigid body).
fn all_fe_only() -> String {
    let m = model("", "");
    let mut parts = m.split("[[element]]\n");
    let mut out = parts.next().unwrap().to_string();
    for p in parts {
        out.push_str("[[element]]\n");
        if !p.contains("rigid_body") {
            out.push_str("rigid_body = false\n");
        }
        out.push_str(p);
    }
    out
}

fn at2(npts: &str, dt: &str, values: &str) -> String {
    format!(
        "PEER NGA STRONG MOTION DATABASE RECORD\nTEST\nACCELERATION TIME SERIES IN UNITS OF G\n\
         NPTS=  {npts}, DT=   {dt} SEC\n{values}\n"
    )
}

fn cases() -> Vec<Case> {
    let run = "run {w}/s.toml --quiet";
    let fe = "fe {w}/model.toml --out {w}/feout --gm";
    let os = "export opensees {w}/model.toml -o {w}/m.py";
    let gen = "generate frame -o {w}/g.toml";
    vec![
        // ---- scenario (`run`): defects 1, 4, 7, 8
        case(
            "time_scale 1e300",
            run,
            1,
            &[
                "s.toml",
                "ground_motion[0].time_scale",
                "1e300",
                "[0.01, 100]",
            ],
        )
        .with("s.toml", scenario("time_scale = 0.5", "time_scale = 1e300")),
        case(
            "time_scale 1e6",
            run,
            1,
            &["s.toml", "ground_motion[0].time_scale"],
        )
        .with("s.toml", scenario("time_scale = 0.5", "time_scale = 1e6")),
        case("fe.dt 1e-300", run, 1, &["s.toml", "fe.dt", "1e-300 s"])
            .with("s.toml", scenario("", "[fe]\ndt = 1e-300")),
        case("fe.dt 1e-9", run, 1, &["s.toml", "fe.dt", "[1e-6, 0.1] s"])
            .with("s.toml", scenario("", "[fe]\ndt = 1e-9")),
        case("fe.dt 1e300", run, 1, &["s.toml", "fe.dt"])
            .with("s.toml", scenario("", "[fe]\ndt = 1e300")),
        case("fe.duration inf", run, 1, &["s.toml", "fe.duration"])
            .with("s.toml", scenario("", "[fe]\nduration = inf")),
        case(
            "restitution 5",
            run,
            1,
            &["s.toml", "physics.restitution = 5", "[0, 1]"],
        )
        .with("s.toml", scenario("", "[physics]\nrestitution = 5.0")),
        case(
            "linear_damping 5",
            run,
            1,
            &["s.toml", "physics.linear_damping"],
        )
        .with("s.toml", scenario("", "[physics]\nlinear_damping = 5.0")),
        case(
            "friction nan",
            run,
            1,
            &["s.toml", "physics.friction = NaN"],
        )
        .with("s.toml", scenario("", "[physics]\nfriction = nan")),
        case(
            "settle_s -0.5",
            run,
            1,
            &["s.toml", "physics.settle_s = -0.5 s"],
        )
        .with("s.toml", scenario("", "[physics]\nsettle_s = -0.5")),
        case(
            "joint_warmstart 1.5",
            run,
            1,
            &["s.toml", "physics.experimental.joint_warmstart = 1.5", "[0, 1]"],
        )
        .with("s.toml", scenario("", "[physics]\nexperimental.joint_warmstart = 1.5")),
        case(
            "joint_iterations 0",
            run,
            1,
            &["s.toml", "physics.experimental.joint_iterations = 0"],
        )
        .with("s.toml", scenario("", "[physics]\nexperimental.joint_iterations = 0")),
        case(
            "linear_correction 0",
            run,
            1,
            &["s.toml", "physics.linear_correction = 0"],
        )
        .with("s.toml", scenario("", "[physics]\nlinear_correction = 0.0")),
        case(
            "axial_rows sideways",
            run,
            1,
            &["s.toml:", "unknown variant `sideways`", "two_way"],
        )
        .with("s.toml", scenario("", "[physics]\nexperimental.axial_rows = \"sideways\"")),
        case(
            "axial_rows in [physics]",
            run,
            1,
            &["s.toml:", "physics.axial_rows", "[physics.experimental]"],
        )
        .with("s.toml", scenario("", "[physics]\naxial_rows = \"bcb\"")),
        case(
            "joint_warmstart in [physics]",
            run,
            1,
            &["s.toml:", "physics.joint_warmstart", "[physics.experimental]"],
        )
        .with("s.toml", scenario("", "[physics]\njoint_warmstart = 0.5")),
        case(
            "preset unknown",
            run,
            1,
            &["s.toml:", "unknown variant `paper`", "bcb", "fem2rbd"],
        )
        .with("s.toml", scenario("", "[physics]\npreset = \"paper\"")),
        case(
            "joint_solve cholesky",
            run,
            1,
            &["s.toml:", "unknown variant `cholesky`", "pgs", "direct"],
        )
        .with("s.toml", scenario("", "[physics]\nexperimental.joint_solve = \"cholesky\"")),
        case(
            "joint_solve_regularisation -1",
            run,
            1,
            &["s.toml", "physics.experimental.joint_solve_regularisation"],
        )
        .with(
            "s.toml",
            scenario("", "[physics]\nexperimental.joint_solve_regularisation = -1.0"),
        ),
        case(
            "panel_connections elastic with formula",
            run,
            1,
            &["s.toml", "physics.panel_connections", "connections = \"fe\""],
        )
        .with(
            "s.toml",
            scenario(
                "",
                "[physics]\nconnections = \"formula\"\npanel_connections = \"elastic\"",
            ),
        ),
        case(
            "ground_damping fe without the model's damping",
            run,
            1,
            &["s.toml", "physics.ground_damping", "[damping]", "model.toml"],
        )
        .with(
            "model.toml",
            model(
                "[damping]\nxi = 0.05\nperiods = [0.316, 0.10533333333333333]\n",
                "",
            ),
        )
        .with("s.toml", scenario("", "[physics]\nground_damping = \"fe\"")),
        case(
            "hinge_end crumble",
            run,
            1,
            &["s.toml:", "unknown variant `crumble`", "rupture", "spring"],
        )
        .with("s.toml", scenario("", "[physics]\nhinge_end = \"crumble\"")),
        case(
            "connected_pairs_touch sometimes",
            run,
            1,
            &["s.toml:", "unknown variant `sometimes`", "never", "once_broken", "once_yielded"],
        )
        .with(
            "s.toml",
            scenario("", "[physics]\nexperimental.connected_pairs_touch = \"sometimes\""),
        ),
        case(
            "rest speed sampled",
            run,
            1,
            &["s.toml:", "unknown variant `sampled`", "frame_mean", "instantaneous"],
        )
        .with(
            "s.toml",
            scenario("", "[physics.rest]\nspeed = \"sampled\""),
        ),
        case(
            "hinge_return_mapping without re-locked hinges",
            run,
            1,
            &["s.toml", "physics.experimental.hinge_return_mapping", "hinge_keeps_rotation = true"],
        )
        .with(
            "s.toml",
            scenario(
                "",
                "[physics]\nexperimental.hinge_return_mapping = true\nexperimental.hinge_keeps_rotation = false",
            ),
        ),
        case(
            "joints nodes",
            run,
            1,
            &["s.toml:", "unknown variant `nodes`", "faces", "column_above"],
        )
        .with("s.toml", scenario("", "[physics]\njoints = \"nodes\"")),
        case(
            "time_limit_s 1e9",
            run,
            1,
            &["s.toml", "physics.time_limit_s"],
        )
        .with("s.toml", scenario("", "[physics]\ntime_limit_s = 1e9")),
        case(
            "steps_per_second 1e9",
            run,
            1,
            &["s.toml", "physics.steps_per_second"],
        )
        .with("s.toml", scenario("", "[physics]\nsteps_per_second = 1e9")),
        case(
            "erp_steps_per_second negative",
            run,
            1,
            &["s.toml", "physics.experimental.erp_steps_per_second"],
        )
        .with(
            "s.toml",
            scenario("", "[physics]\nexperimental.erp_steps_per_second = -200"),
        ),
        case(
            "spring_cap_steps_per_second negative",
            run,
            1,
            &["s.toml", "physics.experimental.spring_cap_steps_per_second"],
        )
        .with(
            "s.toml",
            scenario("", "[physics]\nexperimental.spring_cap_steps_per_second = -1"),
        ),
        case(
            "rest.hold_s negative",
            run,
            1,
            &["s.toml", "physics.rest.hold_s = -1 s"],
        )
        .with("s.toml", scenario("", "[physics.rest]\nhold_s = -1.0")),
        case(
            "rest.energy_ratio 0",
            run,
            1,
            &["s.toml", "physics.rest.energy_ratio = 0"],
        )
        .with("s.toml", scenario("", "[physics.rest]\nenergy_ratio = 0.0")),
        case(
            "rest.max_speed_mps nan",
            run,
            1,
            &["s.toml", "physics.rest.max_speed_mps"],
        )
        .with(
            "s.toml",
            scenario("", "[physics.rest]\nmax_speed_mps = nan"),
        ),
        case(
            "pga_g 50",
            run,
            1,
            &["s.toml", "ground_motion[0].pga_g = 50 g", "(0, 5] g"],
        )
        .with("s.toml", scenario("pga_g = 0.3", "pga_g = 50.0")),
        case("output empty", run, 1, &["s.toml", "output", "empty"])
            .with("s.toml", scenario("output = \"out\"", "output = \"\"")),
        case(
            "output is a file",
            run,
            1,
            &["output folder", "a-file", "not a folder"],
        )
        .with(
            "s.toml",
            scenario("output = \"out\"", "output = \"{w}/a-file\""),
        )
        .with("a-file", "x"),
        case(
            "output under a file",
            run,
            1,
            &["output folder", "a-file", "is a file"],
        )
        .with(
            "s.toml",
            scenario("output = \"out\"", "output = \"{w}/a-file/run\""),
        )
        .with("a-file", "x"),
        case(
            "output is a foreign folder",
            run,
            1,
            &["mine", "did not write"],
        )
        .with(
            "s.toml",
            scenario("output = \"out\"", "output = \"{w}/mine\""),
        )
        .with("mine/thesis.tex", "x"),
        // ---- ensembles: bounded, not of the fe mode, not on 0 threads
        case(
            "ensemble of a million",
            "run {w}/s.toml --quiet --ensemble 1000000",
            1,
            &["--ensemble 1000000", "1 to 1000 members"],
        )
        .with("s.toml", SCENARIO),
        case(
            "ensemble of the fe mode",
            "run {w}/s.toml --quiet --mode fe --ensemble 2",
            1,
            &["--ensemble with the fe mode", "identical"],
        )
        .with("s.toml", SCENARIO),
        case(
            "ensemble on 0 threads",
            "run {w}/s.toml --quiet --ensemble 2 --threads 0",
            1,
            &["--threads 0"],
        )
        .with("s.toml", SCENARIO),
        // ---- unit slips and impossible buildings: refused before any work, naming the
        // item, the value, the range and the slip it looks like
        case(
            "E0 in GPa typed as Pa",
            run,
            1,
            &["model.toml", "material 7: E0 = 200 Pa", "did you mean 200 GPa", "--allow-unusual"],
        )
        .with("s.toml", SCENARIO)
        .with("model.toml", model("E0 = 200000000000.0", "E0 = 200.0")),
        case(
            "fpc in MPa typed as Pa",
            run,
            1,
            &["material 1: |fpc| = 22.5 Pa", "did you mean 22.5 MPa"],
        )
        .with("s.toml", SCENARIO)
        .with("model.toml", model("fpc = -22500000.0", "fpc = -22.5")),
        case(
            "a node in millimetres",
            run,
            1,
            &["node 21: x = 3000 m", "did you mean 3 m?", "element"],
        )
        .with("s.toml", SCENARIO)
        .with("model.toml", model("x = 1.5\ny = 0.0\nz = 0.0", "x = 3000.0\ny = 0.0\nz = 0.0")),
        case(
            "damping in percent",
            run,
            1,
            &["damping.xi = 5 ", "did you mean 0.05?"],
        )
        .with("s.toml", SCENARIO)
        .with("model.toml", model("xi = 0.05", "xi = 5.0")),
        case(
            "gravity in mm/s²",
            run,
            1,
            &["gravity.g = 9810 m/s²", "did you mean 9.81 m/s²?"],
        )
        .with("s.toml", SCENARIO)
        .with("model.toml", model("g = 9.81", "g = 9810.0")),
        case(
            "density a thousand times",
            run,
            1,
            &["material 1: density = 2.5e6 kg/m³", "did you mean 2500 kg/m³?"],
        )
        .with("s.toml", SCENARIO)
        .with("model.toml", model("density = 2500.0", "density = 2500000.0")),
        case(
            "scale 1e-9",
            run,
            1,
            &["scale = 1e-9 is outside the plausible model scale range [0.01, 10]"],
        )
        .with("s.toml", SCENARIO)
        .with("model.toml", model("scale = 0.25", "scale = 1e-9")),
        // ---- geometry roles (frame3: stories of 1 m, bays of 1.5 m, 0.1 m columns)
        case(
            "beam deeper than its story",
            run,
            1,
            &["element 49: beam depth h 1.2 m / story height 1 m = 1.2 is outside the plausible beam depth / story height range [0, 1]"],
        )
        .with("s.toml", SCENARIO)
        .with("model.toml", model("h = 0.15", "h = 1.2")),
        case(
            "slab thicker than its story",
            run,
            1,
            &["element 57: slab thickness 1.5 m / story height 1 m = 1.5 is outside the plausible slab thickness / story height range [0, 1]"],
        )
        .with("s.toml", SCENARIO)
        .with("model.toml", model("thickness = 0.03", "thickness = 1.5")),
        case(
            "column section larger than the bay",
            run,
            1,
            &["element 1: column size 2 m / bay 1.5 m = 1.333", "column size / bay range [0, 1]"],
        )
        .with("s.toml", SCENARIO)
        .with("model.toml", model("b = 0.1", "b = 2.0")),
        case(
            "2 m wall between 0.1 m columns",
            run,
            1,
            &["element 9001: wall thickness 2 m / column size 0.1 m = 20 is outside the plausible wall thickness / column size range [0, 4]"],
        )
        .with("s.toml", SCENARIO)
        .with(
            "model.toml",
            model(
                "[[element]]\ntag = 1\n",
                "[[element]]\ntag = 9001\ntype_name = \"Wall\"\ngroup = 1\ntype = \"panel\"\n\
                 nodes = [1, 21, 121, 101]\nthickness = 2.0\n\n[[element]]\ntag = 1\n",
            ),
        ),
        case(
            "node at z = 1e308 (allowed as unusual)",
            "--allow-unusual modal {w}/model.toml",
            1,
            &["its lumped mass inf kg is not finite: the self-weight of the elements at it overflows"],
        )
        .with(
            "model.toml",
            model("x = 0.0\ny = 0.0\nz = 0.0", "x = 0.0\ny = 0.0\nz = 1e308"),
        ),
        case(
            "steps_per_second 10",
            run,
            1,
            &[
                "s.toml: physics.steps_per_second = 10 substeps/s is not a whole multiple of the frame rate 25 frames/s",
                "a keyframe is written every 0.04 s of simulated time",
                "give a multiple of 25 substeps/s, e.g. 25",
            ],
        )
        .with("s.toml", scenario("", "[physics]\nsteps_per_second = 10")),
        case(
            "steps_per_second 110 refused before the estimate",
            "run {w}/s.toml --quiet --estimate",
            1,
            &["s.toml: physics.steps_per_second = 110 substeps/s", "e.g. 125"],
        )
        .with("s.toml", scenario("", "[physics]\nsteps_per_second = 110")),
        // ---- no hang, no abort
        case(
            "200 001 nodes",
            "modal {w}/big.toml",
            1,
            &["big.toml", "node count 200001 exceeds the limit of 200000"],
        )
        .with("big.toml", nodes_model(200_001)),
        case(
            "5000 unused nodes",
            "modal {w}/model.toml",
            1,
            &["5000 node(s) used by no structural element (node 900001, 900002, 900003, 900004, 900005, 900006, 900007, 900008, 900009, 900010, …)"],
        )
        .with("model.toml", {
            let mut m = model("", "");
            for i in 1..=5000 {
                m.push_str(&format!("\n[[node]]\ntag = {}\nx = 0.5\ny = 0.5\nz = 0.5\n", 900_000 + i));
            }
            m
        }),
        case(
            "1e30 kg on a node",
            run,
            1,
            &["mass on node 101: m = 1e30 kg"],
        )
        .with("s.toml", SCENARIO)
        .with("model.toml", model("m = 118.85525", "m = 1e30")),
        case(
            "anchor period 500 s",
            run,
            1,
            &["damping.periods[0] = 500 s"],
        )
        .with("s.toml", SCENARIO)
        .with("model.toml", model("periods = [0.316,", "periods = [500.0,")),
        case(
            "E0 slip in fe",
            "fe {w}/model.toml --out {w}/feout --gm X={w}/elc180.at2",
            1,
            &["model.toml", "did you mean 200 GPa"],
        )
        .with("model.toml", model("E0 = 200000000000.0", "E0 = 200.0")),
        case(
            "E0 slip in modal",
            "modal {w}/model.toml",
            1,
            &["did you mean 200 GPa"],
        )
        .with("model.toml", model("E0 = 200000000000.0", "E0 = 200.0")),
        case(
            "E0 slip in map",
            "map {w}/model.toml -o {w}/b.csv",
            1,
            &["did you mean 200 GPa"],
        )
        .with("model.toml", model("E0 = 200000000000.0", "E0 = 200.0")),
        case(
            "E0 slip in export opensees",
            "export opensees {w}/model.toml -o {w}/m.py",
            1,
            &["did you mean 200 GPa"],
        )
        .with("model.toml", model("E0 = 200000000000.0", "E0 = 200.0")),
        case(
            "record is /dev/zero",
            run,
            1,
            &[
                "s.toml",
                "ground_motion[0]",
                "/dev/zero",
                "not a regular file",
            ],
        )
        .with(
            "s.toml",
            scenario("file = \"elc180.at2\"", "file = \"/dev/zero\""),
        ),
        case(
            "model missing",
            run,
            1,
            &["s.toml", "model", "none.toml", "does not exist"],
        )
        .with(
            "s.toml",
            scenario("model = \"model.toml\"", "model = \"none.toml\""),
        ),
        case("scenario syntax", run, 1, &["s.toml:2:"])
            .with("s.toml", scenario("mode = \"rigid\"", "mode = = 1")),
        case(
            "scenario unknown key",
            run,
            1,
            &["s.toml:10:", "unknown field `restitutio`"],
        )
        .with("s.toml", scenario("", "[physics]\nrestitutio = 0.5")),
        case(
            "scenario is a folder",
            "run {w}/sdir --quiet",
            1,
            &["scenario file", "sdir", "not a regular file"],
        )
        .with("sdir/x", "x"),
        // ---- records (AT2), through `run` and `fe`
        case(
            "AT2 NPTS 1e18",
            run,
            1,
            &["rec.at2:4", "NPTS", "exceeds the limit"],
        )
        .with("s.toml", scenario("elc180.at2", "rec.at2"))
        .with("rec.at2", at2("1000000000000000000", ".01", "0.1 0.2")),
        case(
            "AT2 DT 1e10",
            run,
            1,
            &["rec.at2:4", "DT = 1e10 s", "(0, 1] s"],
        )
        .with("s.toml", scenario("elc180.at2", "rec.at2"))
        .with("rec.at2", at2("2", "1e10", "0.1 0.2")),
        case(
            "AT2 truncated",
            &format!("{fe} X={{w}}/rec.at2"),
            1,
            &["rec.at2:5", "2 samples read but NPTS = 5"],
        )
        .with("rec.at2", at2("5", ".01", "0.1 0.2")),
        case(
            "AT2 bad number",
            &format!("{fe} X={{w}}/rec.at2"),
            1,
            &["rec.at2:5", "`0.x` is not a number"],
        )
        .with("rec.at2", at2("2", ".01", "0.1 0.x")),
        case(
            "two-column uneven",
            &format!("{fe} X={{w}}/rec.txt"),
            1,
            &["rec.txt:2", "off the uniform step"],
        )
        .with("rec.txt", "0 0.1\n0.01 0.2\n0.05 0.3\n0.06 0.1\n"),
        // ---- `fe`: defects 1, 9, 11, 12
        case(
            "fe --dt 1e-300",
            &format!("{fe} X={{w}}/elc180.at2 --dt 1e-300"),
            1,
            &["--dt = 1e-300 s"],
        ),
        case(
            "fe --time-scale 1e20",
            &format!("{fe} X={{w}}/elc180.at2 --time-scale 1e20"),
            1,
            &["--time-scale = 1e20"],
        ),
        case(
            "fe --duration 1e12",
            &format!("{fe} X={{w}}/elc180.at2 --duration 1e12"),
            1,
            &["--duration = 1e12 s"],
        ),
        case(
            "fe pga 0",
            &format!("{fe} X={{w}}/elc180.at2,pga=0"),
            1,
            &["--gm", "pga = 0 g"],
        ),
        case(
            "fe gm /dev/zero",
            &format!("{fe} X=/dev/zero"),
            1,
            &["/dev/zero", "not a regular file"],
        ),
        case(
            "fe gm missing",
            &format!("{fe} X={{w}}/none.at2"),
            1,
            &["none.at2 does not exist"],
        ),
        case(
            "fe gm twice",
            &format!("{fe} X={{w}}/elc180.at2 --gm x={{w}}/elc180.at2"),
            1,
            &["direction X given twice"],
        ),
        case(
            "fe gm syntax",
            &format!("{fe} Q={{w}}/elc180.at2"),
            1,
            &["--gm \"Q=", "unknown direction"],
        ),
        case(
            "fe --out empty",
            "fe {w}/model.toml --out  --gm X={w}/elc180.at2",
            2,
            &["a value is required for '--out <OUT>'"],
        ),
        case(
            "fe --out a file",
            "fe {w}/model.toml --out {w}/a-file --gm X={w}/elc180.at2",
            1,
            &["--out", "a-file", "not a folder"],
        )
        .with("a-file", "x"),
        case(
            "fe load_steps 4e9",
            &format!("{fe} X={{w}}/elc180.at2"),
            1,
            &[
                "model.toml:",
                "load_steps 4000000000 exceeds the limit of 100000",
            ],
        )
        .with(
            "model.toml",
            model("load_steps = 10", "load_steps = 4000000000"),
        ),
        // ---- model files (`modal`, `map`): defects 2, 12
        case(
            "core_fibers 1e5",
            "modal {w}/model.toml",
            1,
            &["model.toml:", "section 1", "fibre count"],
        )
        .with(
            "model.toml",
            model("core_fibers = [8, 8]", "core_fibers = [100000, 100000]"),
        ),
        case(
            "model is /dev/zero",
            "modal /dev/zero",
            1,
            &["model file", "/dev/zero", "not a regular file"],
        ),
        case(
            "model unknown key",
            "modal {w}/model.toml",
            1,
            &["model.toml:1", "unknown field `nmae`"],
        )
        .with("model.toml", model("name = ", "nmae = ")),
        case(
            "model JSON misspelt top-level key",
            "modal {w}/mis.json",
            1,
            &["mis.json:", "top level: unknown field `supprt`"],
        )
        .with(
            "mis.json",
            "{\"name\": \"x\",\n \"node\": [{\"tag\": 1, \"x\": 0, \"y\": 0, \"z\": 0}],\n \"mass\": [{\"node\": 1, \"m\": 1.0}],\n \"supprt\": []}\n",
        ),
        case(
            "empty model",
            "modal {w}/empty.toml",
            1,
            &["model \"empty\" has no structural elements"],
        )
        .with("empty.toml", "name = \"empty\"\n"),
        case(
            "map -o a folder",
            "map {w}/model.toml -o {w}/adir",
            1,
            &["--output", "adir", "is a folder"],
        )
        .with("adir/keep", "x"),
        case(
            "map -o empty",
            "map {w}/model.toml -o ",
            2,
            &["a value is required for '--output <OUTPUT>'"],
        ),
        // ---- `export opensees`: defect 11
        case(
            "opensees --stop-uz nan",
            &format!("{os} --stop-uz nan"),
            1,
            &["--stop-uz = NaN m"],
        ),
        case(
            "opensees truncated AT2",
            &format!("{os} --gm X={{w}}/rec.at2,0.3"),
            1,
            &["rec.at2:5", "NPTS = 5"],
        )
        .with("rec.at2", at2("5", ".01", "0.1 0.2")),
        case(
            "opensees pga 0",
            &format!("{os} --gm X={{w}}/elc180.at2,0"),
            1,
            &["--gm", "pga = 0 g"],
        ),
        case(
            "opensees two-column record",
            &format!("{os} --gm X={{w}}/rec.txt"),
            1,
            &["rec.txt:4", "AT2 header"],
        )
        .with("rec.txt", "0 0.1\n0.01 0.2\n"),
        case(
            "opensees --dt 1e300",
            &format!("{os} --dt 1e300"),
            1,
            &["--dt = 1e300 s"],
        ),
        case(
            "opensees -o a folder",
            "export opensees {w}/model.toml -o {w}/adir",
            1,
            &["--output", "is a folder"],
        )
        .with("adir/keep", "x"),
        // ---- `generate frame`: defects 2, 7, 12
        case(
            "generate --column-elements 4294967295",
            &format!("{gen} --column-elements 4294967295"),
            1,
            &["column_elements: count 4294967295 exceeds the limit of 50"],
        ),
        case(
            "generate --beam-elements 1e8",
            &format!("{gen} --beam-elements 100000000"),
            1,
            &["beam_elements"],
        ),
        case(
            "generate --column-fibers 1e5",
            &format!("{gen} --column-fibers 100000x100000"),
            1,
            &["column_fibers (ny): count 100000"],
        ),
        case(
            "generate --stories -1",
            &format!("{gen} --stories=-1,1,1"),
            1,
            &["stories[1] = -1 m"],
        ),
        case(
            "generate --xi 1e9",
            &format!("{gen} --xi 1e9"),
            1,
            &["xi = 1e9", "[0, 1]"],
        ),
        case(
            "generate --es 1e308",
            &format!("{gen} --es 1e308"),
            1,
            &["es = 1e308 Pa"],
        ),
        case(
            "generate --slab-thickness 0",
            &format!("{gen} --slab-thickness 0"),
            1,
            &["slab_thickness = 0 m"],
        ),
        case(
            "generate --spans-x 1e300",
            &format!("{gen} --spans-x 1e300"),
            1,
            &["spans_x[1] = 1e300 m"],
        ),
        case(
            "generate 4 stories with the default per-story --ec",
            &format!("{gen} --stories 1,1,1,1"),
            1,
            &["--ec: its default 25e9,27e9,23e9 has 3 values for 4 stories (--stories): give one value for every story, or one per story"],
        ),
        case(
            "generate a column wider than the bay",
            &format!("{gen} --column 2x2"),
            1,
            &["column section 2 m × 2 m is not smaller than the bay spans_x[1] = 1.5 m: neighbouring columns would overlap"],
        ),
        case(
            "generate a beam narrower than its bars",
            &format!("{gen} --beam 0.02x0.15"),
            1,
            &["beam section 0.02 m wide leaves no room for its bars", "must be wider than 0.026 m"],
        ),
        case(
            "generate -o a folder",
            "generate frame -o {w}/adir",
            1,
            &["--output", "is a folder"],
        )
        .with("adir/keep", "x"),
        case(
            "generate --points abc",
            &format!("{gen} --points abc"),
            2,
            &["--points"],
        ),
        // ---- `scene`
        case(
            "scene syntax",
            "scene {w}/sc.json --out {w}/o.csv",
            1,
            &["sc.json", "line 1"],
        )
        .with("sc.json", "{ \"bodies\": [ }"),
        case(
            "scene duration 1e9 s",
            "scene {w}/sc.json --out {w}/o.csv",
            1,
            &["sc.json", "physics substeps 240000000000 exceeds the limit"],
        )
        .with(
            "sc.json",
            std::fs::read_to_string(root().join("data/scenes/drop.json"))
                .unwrap()
                .replace("\"duration\": 2.0", "\"duration\": 1e9"),
        ),
        case(
            "scene is /dev/zero",
            "scene /dev/zero --out {w}/o.csv",
            1,
            &["scene file", "not a regular file"],
        ),
        case(
            "scene --out a folder",
            "scene {w}/sc.json --out {w}/adir",
            1,
            &["--out", "is a folder"],
        )
        .with(
            "sc.json",
            std::fs::read_to_string(root().join("data/scenes/drop.json")).unwrap(),
        )
        .with("adir/keep", "x"),
        // ---- `scene` plausibility (refused unless --allow-unusual)
        case(
            "scene box 0.9 m into the ground",
            "scene {w}/sc.json --out {w}/o.csv",
            1,
            &[
                "sc.json",
                "body 0 \"ground\" (line 6) and body 1 \"box\" (line 8) start 0.9 m inside each other",
                "tolerance of 0.01 m",
                "--allow-unusual",
            ],
        )
        .with("sc.json", drop_scene("[0, 0, 1.5]", "[0, 0, -0.4]")),
        case(
            "scene boxes inside each other",
            "scene {w}/sc.json --out {w}/o.csv",
            1,
            &["body 1 \"box\" (line 8) and body 2 \"twin\" (line 10) start 0.75 m inside each other"],
        )
        .with(
            "sc.json",
            drop_scene(
                "\"friction\": 0.5 }",
                "\"friction\": 0.5 },\n    { \"name\": \"twin\", \"half_extents\": [0.5, 0.5, 0.5], \"mass\": 1,\n      \"position\": [0.25, 0, 1.5] }",
            ),
        ),
        case(
            "scene velocity 1e6 m/s",
            "scene {w}/sc.json --out {w}/o.csv",
            1,
            &["body 1 \"box\" (line 8): |linear_velocity| = 1e6 m/s is outside the plausible speed range [0 m/s, 1000 m/s]"],
        )
        .with(
            "sc.json",
            drop_scene("\"friction\": 0.5", "\"friction\": 0.5, \"linear_velocity\": [1e6, 0, 0]"),
        ),
        case(
            "scene velocity 1e300 m/s (its square overflows)",
            "scene {w}/sc.json --out {w}/o.csv",
            1,
            &["body 1 \"box\" (line 8): |linear_velocity| = 1e300 m/s is outside the plausible speed range [0 m/s, 1000 m/s]"],
        )
        .with(
            "sc.json",
            drop_scene("\"friction\": 0.5", "\"friction\": 0.5, \"linear_velocity\": [1e300, 0, 0]"),
        ),
        // ---- studies: the target PGA capped as everywhere else
        case(
            "study pga 100 g",
            "study plan {w}/st.toml",
            1,
            &["st.toml:8: intensity.pga_g", "100 g is outside the target PGA range (0, 5] g"],
        )
        .with("s.toml", SCENARIO)
        .with("st.toml", STUDY.replace("PGA", "0.5, 100.0")),
        case(
            "study ida max_g 6 g",
            "study plan {w}/st.toml",
            1,
            &["intensity.ida.max_g", "6 g is outside the target PGA range (0, 5] g"],
        )
        .with("s.toml", SCENARIO)
        .with(
            "st.toml",
            STUDY.replace(
                "pga_g = [PGA]",
                "[intensity.ida]\nstart_g = 1.0\nstep_g = 1.0\nmax_g = 6.0\ntolerance_g = 0.5",
            ),
        ),
        // ---- models that give the ruin stage nothing, or a key twice
        case(
            "map of an empty model",
            "map {w}/empty.toml -o {w}/b.csv",
            1,
            &["empty.toml", "no element becomes a rigid body (0 element(s)"],
        )
        .with("empty.toml", "name = \"empty\"\n"),
        case(
            "map when every element has rigid_body = false",
            "map {w}/model.toml -o {w}/b.csv",
            1,
            &["model.toml", "no element becomes a rigid body (96 element(s), 96 of them rigid_body = false"],
        )
        .with("model.toml", all_fe_only()),
        case(
            "a key given twice in an element",
            "modal {w}/model.toml",
            1,
            &["model.toml:", "duplicate key rigid_body: each key is given once per item"],
        )
        .with(
            "model.toml",
            model("rigid_body = false", "rigid_body = false\nrigid_body = false"),
        ),
        case(
            "scene restitution 2",
            "scene {w}/sc.json --out {w}/o.csv",
            1,
            &["body 1 \"box\" (line 8): restitution = 2 is outside the plausible restitution range [0, 1]"],
        )
        .with(
            "sc.json",
            drop_scene("\"friction\": 0.5", "\"friction\": 0.5, \"restitution\": 2"),
        ),
        case(
            "scene friction 1e9",
            "scene {w}/sc.json --out {w}/o.csv",
            1,
            &["body 1 \"box\" (line 8): friction = 1e9 is outside the plausible friction coefficient range [0, 10]"],
        )
        .with("sc.json", drop_scene("\"friction\": 0.5", "\"friction\": 1e9")),
        case(
            "scene ERP 5 and negative CFM",
            "scene {w}/sc.json --out {w}/o.csv",
            1,
            &[
                "2 implausible value(s)",
                "world.solver: erp = 5 is outside the plausible error-reduction parameter range [0, 1]",
                "world.solver: global_cfm = -0.1 is outside the plausible constraint-force mixing range [0, 1]",
            ],
        )
        .with(
            "sc.json",
            drop_scene(
                "\"preset\": \"pybullet\"",
                "\"preset\": \"pybullet\", \"solver\": { \"erp\": 5, \"global_cfm\": -0.1 }",
            ),
        ),
        case(
            "scene gravity 1e9",
            "scene {w}/sc.json --out {w}/o.csv",
            1,
            &["world: |gravity| = 1e9 m/s² is outside the plausible gravity range [0 m/s², 100 m/s²]"],
        )
        .with(
            "sc.json",
            drop_scene("\"preset\": \"pybullet\"", "\"preset\": \"pybullet\", \"gravity\": [0, 0, -1e9]"),
        ),
        case(
            "scene substep 1 s",
            "scene {w}/sc.json --out {w}/o.csv",
            1,
            &["substep = 1 s is outside the plausible substep range [0 s, 0.1 s]"],
        )
        .with(
            "sc.json",
            drop_scene("\"substeps_per_second\": 240", "\"substep\": 1"),
        ),
        // ---- run folders (`export gltf`, `export vtk`, `plot`)
        case(
            "gltf: no run folder",
            "export gltf {w}/norun",
            1,
            &["norun", "does not exist"],
        ),
        case(
            "vtk: no run folder",
            "export vtk {w}/norun",
            1,
            &["norun", "does not exist"],
        ),
        case("plot: no run folder", "plot {w}/norun", 1, &["norun"]),
        case(
            "gltf: bodies.csv header",
            "export gltf {w}/rf",
            1,
            &["rf/bodies.csv:1", "header"],
        )
        .with("rf/bodies.csv", "name,grp\n"),
    ]
}

fn setup(w: &Path) {
    std::fs::copy(root().join("data/frame3/model.toml"), w.join("model.toml")).unwrap();
    std::fs::copy(
        root().join("data/ground-motions/RSN6_IMPVALL.I_I-ELC180.AT2"),
        w.join("elc180.at2"),
    )
    .unwrap();
}

#[test]
fn every_bad_input_is_refused_cleanly() {
    let cases = cases();
    let mut failures = Vec::new();
    for c in &cases {
        let tmp = tempfile::tempdir().unwrap();
        let w = tmp.path();
        setup(w);
        let wd = w.display().to_string();
        for (name, text) in &c.files {
            let p = w.join(name);
            std::fs::create_dir_all(p.parent().unwrap()).unwrap();
            std::fs::write(&p, text.replace("{w}", &wd)).unwrap();
        }
        let before = listing(w);
        let args: Vec<String> = c.args.iter().map(|a| a.replace("{w}", &wd)).collect();
        let out = Command::new(BIN)
            .current_dir(w)
            .args(&args)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        let after = listing(w);
        let mut why = Vec::new();
        if out.status.code() != Some(c.code) {
            why.push(format!("exit {:?}, want {}", out.status.code(), c.code));
        }
        if err.contains("panicked") {
            why.push("panicked".into());
        }
        for s in &c.want {
            if !err.contains(&s.replace("{w}", &wd)) {
                why.push(format!("stderr lacks {s:?}"));
            }
        }
        if after != before {
            let new: Vec<_> = after.difference(&before).collect();
            let gone: Vec<_> = before.difference(&after).collect();
            why.push(format!("work folder changed: new {new:?}, gone {gone:?}"));
        }
        if !why.is_empty() {
            failures.push(format!(
                "{}: {} — stderr: {}",
                c.name,
                why.join("; "),
                err.trim()
            ));
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} cases failed:\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n")
    );
    eprintln!("{} hostile cases refused cleanly", cases.len());
}

/// `--allow-unusual` accepts a scene with a box 0.9 m into the ground and runs it; the
/// scene's descriptive `name` and `description` keys are accepted.
#[test]
fn allow_unusual_runs_an_overlapping_scene() {
    let tmp = tempfile::tempdir().unwrap();
    let w = tmp.path();
    let text = drop_scene("[0, 0, 1.5]", "[0, 0, -0.4]").replacen(
        "{",
        "{\n  \"name\": \"sunk box\", \"description\": \"a box 0.9 m into the ground\",",
        1,
    );
    std::fs::write(w.join("sc.json"), text).unwrap();
    let out = Command::new(BIN)
        .current_dir(w)
        .args(["--allow-unusual", "scene", "sc.json", "--out", "o.csv"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let csv = std::fs::read_to_string(w.join("o.csv")).unwrap();
    // Header and the two bodies' final rows.
    assert_eq!(csv.lines().count(), 3, "{csv}");
    assert!(csv.lines().nth(2).unwrap().starts_with("480,"), "{csv}");
}

/// A comma, quote or newline in a body's name or group no longer breaks the run folder:
/// the tables are written with RFC 4180 quoting and read back with the `csv` crate
/// (defect 3: "bodies.csv:2: 19 fields, expected 17").
#[test]
fn names_with_commas_quotes_and_newlines_round_trip_through_the_run_folder() {
    use fem2rbd::body::BodyId;
    use fem2rbd::bullet::Pose;
    use fem2rbd::output::history::{bodies_csv, BodyRow};
    use fem2rbd::output::keyframes::keyframes_csv;
    use fem2rbd::output::run_folder::{parse_bodies, parse_keyframes};
    // Type names and material groups with a comma, a quote, a newline.
    let ids = [
        BodyId::element("Col,umn".into(), "a,b", 2),
        BodyId::element("a \"b\"".into(), "\"", 4),
        BodyId::element("two\nlines".into(), "x\r\ny", 6),
    ];
    let names: Vec<String> = ids.iter().map(BodyId::name).collect();
    let names: Vec<&str> = names.iter().map(String::as_str).collect();
    let rows: Vec<BodyRow> = (0..3)
        .map(|i| BodyRow {
            id: &ids[i],
            passive: false,
            pose0: Pose::at([i as f64, 0.5, 1.25]),
            half_extents: [0.1, 0.2, 0.3],
            mass_kg: 12.5,
        })
        .collect();
    let text = bodies_csv(&rows);
    let back = parse_bodies(&text, "bodies.csv").unwrap();
    for (r, b) in rows.iter().zip(&back) {
        assert_eq!(&b.id, r.id);
        assert_eq!(b.id.group(), r.id.material());
        assert_eq!(b.pose0.position, r.pose0.position);
    }
    let poses: Vec<Pose> = rows.iter().map(|r| r.pose0).collect();
    let kf = keyframes_csv(&names, &[(0.0, poses.as_slice()), (0.04, poses.as_slice())]);
    let frames = parse_keyframes(&kf, "keyframes.csv", &back).unwrap();
    assert_eq!(frames.len(), 2);
    assert_eq!(frames[1].0, 0.04);
    assert_eq!(frames[1].1[2].position, [2.0, 0.5, 1.25]);
}

fn parse_model(text: &str, json: bool) {
    let _ = fem2rbd::model::Model::parse(text, "gen", json);
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(64),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// Model TOML: the shipped model with one line replaced by arbitrary text, and
    /// arbitrary text — parse and validation return, never panic.
    #[test]
    fn model_toml_never_panics(line in 0usize..700, junk in ".{0,40}", free in "\\PC{0,200}") {
        let m = std::fs::read_to_string(root().join("data/frame3/model.toml")).unwrap();
        let mut lines: Vec<&str> = m.lines().collect();
        let k = line % lines.len();
        lines[k] = &junk;
        parse_model(&lines.join("\n"), false);
        parse_model(&free, false);
    }

    /// Model JSON: numbers replaced by arbitrary floats (NaN, ±inf as huge literals,
    /// zeros, negatives) in a small valid model.
    #[test]
    fn model_json_never_panics(x in any::<f64>(), e in any::<f64>(), pts in any::<u32>(), fib in any::<u32>()) {
        let num = |v: f64| if v.is_finite() { format!("{v:e}") } else { "1e999".into() };
        let text = format!(r#"{{
 "name": "p", "gravity": {{"g": 9.81, "load_steps": {pts}}},
 "material": [{{"tag": 1, "name": "s", "kind": "elastic", "E": {}}}],
 "section": [{{"tag": 1, "name": "c", "kind": "rc_rect", "b": 0.1, "h": 0.1, "cover": 0.01,
   "core_material": 1, "cover_material": 1, "bar_material": 1, "core_fibers": [{fib}, 2],
   "bars": [], "GJ": 1.0}}],
 "transformation": [{{"tag": 1, "kind": "linear", "vecxz": [1, 0, 0]}}],
 "node": [{{"tag": 1, "x": 0, "y": 0, "z": 0}}, {{"tag": 2, "x": {}, "y": 0, "z": 1}}],
 "support": [{{"node": 1, "dofs": [1,1,1,1,1,1]}}],
 "element": [{{"tag": 1, "type_name": "Column", "group": "1", "kind": "beam_column",
   "nodes": [1, 2], "section": 1, "transf": 1, "points": {pts}}}]
}}"#, num(e), num(x));
        parse_model(&text, true);
    }

    /// Scenario: arbitrary values for every numeric key.
    #[test]
    fn scenario_never_panics(key in prop::sample::select(vec![
        "time_scale", "pga_g", "dt", "duration", "restitution", "friction", "settle_s",
        "time_limit_s", "steps_per_second", "hold_s", "energy_ratio", "threshold_m",
    ]), v in any::<f64>(), junk in "\\PC{0,80}") {
        let dir = tempfile::tempdir().unwrap();
        setup(dir.path());
        let lit = if v.is_nan() { "nan".to_string() } else if v.is_infinite() { if v > 0.0 { "inf".into() } else { "-inf".into() } } else { format!("{v:e}") };
        let text = match key {
            "time_scale" | "pga_g" => SCENARIO.replacen(&format!("{key} = "), &format!("{key} = {lit} #"), 1),
            "dt" | "duration" => format!("{SCENARIO}[fe]\n{key} = {lit}\n"),
            "threshold_m" => format!("{SCENARIO}[collapse]\n{key} = {lit}\n"),
            "hold_s" | "energy_ratio" => format!("{SCENARIO}[physics.rest]\n{key} = {lit}\n"),
            _ => format!("{SCENARIO}[physics]\n{key} = {lit}\n"),
        };
        let p = dir.path().join("s.toml");
        let _ = fem2rbd::pipeline::Scenario::parse(&text, &p);
        let _ = fem2rbd::pipeline::Scenario::parse(&format!("{SCENARIO}{junk}"), &p);
    }

    /// Scene JSON: arbitrary numbers in a valid scene, and arbitrary text.
    #[test]
    fn scene_never_panics(d in any::<f64>(), m in any::<f64>(), s in any::<u32>(), free in "\\PC{0,200}") {
        let num = |v: f64| if v.is_finite() { format!("{v:e}") } else { "1e999".into() };
        let text = format!(r#"{{"duration": {}, "substeps_per_second": {s},
 "bodies": [{{"name": "b", "half_extents": [0.5, 0.5, 0.5], "mass": {}, "position": [0, 0, 1]}}]}}"#,
            num(d), num(m));
        let _ = fem2rbd::scene::Scene::from_json(&text);
        let _ = fem2rbd::scene::Scene::from_json(&free);
    }

    /// AT2: arbitrary header values and samples.
    #[test]
    fn at2_never_panics(npts in any::<u64>(), dt in any::<f64>(), vals in prop::collection::vec(any::<f64>(), 0..20), junk in "\\PC{0,60}") {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("r.at2");
        let body: Vec<String> = vals.iter().map(|v| format!("{v:e}")).collect();
        std::fs::write(&p, at2(&npts.to_string(), &format!("{dt:e}"), &body.join(" "))).unwrap();
        let _ = fem2rbd::motion::read_record(&p, fem2rbd::motion::Format::At2);
        std::fs::write(&p, format!("a\nb\nc\n{junk}\n1 2\n")).unwrap();
        let _ = fem2rbd::motion::read_record(&p, fem2rbd::motion::Format::Auto);
    }

    /// Run folder: `bodies.csv` and `keyframes.csv` with one line replaced by junk
    /// (quotes, commas, newlines included).
    #[test]
    fn run_folder_never_panics(line in 1usize..4, junk in "[a-z0-9,\"\n\r. -]{0,60}") {
        use fem2rbd::output::history::{bodies_csv, BodyRow};
        use fem2rbd::output::run_folder::{parse_bodies, parse_keyframes};
        use fem2rbd::bullet::Pose;
        let ids: Vec<fem2rbd::body::BodyId> =
            (0..3).map(|i| fem2rbd::body::BodyId::element("Column".into(), "1", i)).collect();
        let rows: Vec<BodyRow> = (0..3).map(|i| BodyRow {
            id: &ids[i], passive: false, pose0: Pose::at([0.0, 0.0, i as f64]),
            half_extents: [0.1; 3], mass_kg: 1.0,
        }).collect();
        let text = bodies_csv(&rows);
        let mut lines: Vec<&str> = text.lines().collect();
        lines[line] = &junk;
        let bad = lines.join("\n");
        let _ = parse_bodies(&bad, "bodies.csv");
        if let Ok(b) = parse_bodies(&text, "bodies.csv") {
            let kf = format!("t,name,x,y,z,qw,qx,qy,qz\n{junk}\n");
            let _ = parse_keyframes(&kf, "keyframes.csv", &b);
        }
    }
}

/// `fe` removes an element whose state determination fails in a step no fallback saves
/// (the cantilever's force-based column, whose steel yields at 1 kPa without hardening,
/// in its first step), says so, lists it in `fe_summary.json` and goes on to the end with
/// the tip mass in free flight. `fe --out` replaces a folder it wrote as a whole (an
/// earlier run's history is gone) and leaves no temporary folder beside it.
#[test]
fn fe_removes_a_failed_element_and_replaces_its_folder() {
    let tmp = tempfile::tempdir().unwrap();
    let w = tmp.path();
    setup(w);
    let out_dir = w.join("feout");
    std::fs::create_dir(&out_dir).unwrap();
    // An earlier `fe` folder: the marker, a summary and a history.
    std::fs::write(out_dir.join(".fem2rbd"), "fe\n").unwrap();
    std::fs::write(out_dir.join("fe_summary.json"), "{}").unwrap();
    std::fs::write(out_dir.join("nodes.csv"), "old run").unwrap();
    let out = Command::new(BIN)
        .arg("fe")
        .arg(root().join("tests/fixtures/yielding-cantilever.toml"))
        // Its steel yields at 1 kPa on purpose.
        .arg("--allow-unusual")
        .arg("--gm")
        .arg(format!("X={}", w.join("elc180.at2").display()))
        .args(["--duration", "1", "--out"])
        .arg(&out_dir)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{err}");
    assert!(
        err.contains("fe: element 1 removed at t = 0.0034 s"),
        "{err}"
    );
    let mut names: Vec<String> = std::fs::read_dir(&out_dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        [".fem2rbd", "fe_summary.json", "nodes.csv", "reactions.csv"]
    );
    assert_ne!(
        std::fs::read_to_string(out_dir.join("nodes.csv")).unwrap(),
        "old run"
    );
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out_dir.join("fe_summary.json")).unwrap())
            .unwrap();
    assert_eq!(s["stop"]["reason"], "completed");
    assert_eq!(s["stop"]["time"], 1.0);
    let removed = s["removed_elements"].as_array().unwrap();
    assert_eq!(removed.len(), 1);
    assert_eq!(removed[0]["element"], 1);
    // In the first step (to 0.005 s), from the last of its converged sub-steps.
    assert_eq!(removed[0]["attempted"], 0.005);
    let t = removed[0]["time"].as_f64().unwrap();
    assert!(t > 0.0 && t < 0.005, "removed at {t} s");
    assert!(removed[0]["message"]
        .as_str()
        .unwrap()
        .contains("force-based element did not reach compatible forces"));
    let beside: Vec<String> = std::fs::read_dir(w)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.'))
        .collect();
    assert!(beside.is_empty(), "temporaries left: {beside:?}");
}

/// Defect 3 end to end: a model whose element type and group hold a comma runs (FE
/// mode, 0.1 s), its run folder reads back, and `export gltf` of the folder gives the
/// run's own `collapse.glb` byte for byte (a comma in a name must not break
/// `bodies.csv`: "cannot build collapse.glb from the run's own tables: bodies.csv:2: 19
/// fields, expected 17").
/// Then `export vtk` twice: the second replaces the frame folder as a whole.
#[test]
fn a_comma_in_a_name_survives_a_whole_run() {
    let tmp = tempfile::tempdir().unwrap();
    let w = tmp.path();
    setup(w);
    let m = std::fs::read_to_string(w.join("model.toml")).unwrap();
    let m = m
        .replacen("type_name = \"Column\"", "type_name = \"Col,umn\"", 1)
        .replacen("group = 1\n", "group = \"a,b\"\n", 1);
    std::fs::write(w.join("model.toml"), m).unwrap();
    std::fs::write(
        w.join("s.toml"),
        scenario("mode = \"rigid\"", "mode = \"fe\"") + "[fe]\nduration = 0.1\n",
    )
    .unwrap();
    let st = Command::new(BIN)
        .current_dir(w)
        .args(["run", "s.toml", "--quiet"])
        .output()
        .unwrap();
    assert!(
        st.status.success(),
        "{}",
        String::from_utf8_lossy(&st.stderr)
    );
    let bodies = std::fs::read_to_string(w.join("out/bodies.csv")).unwrap();
    assert!(bodies.contains("\"Col,umn:"), "{bodies}");
    let st = Command::new(BIN)
        .current_dir(w)
        .args(["export", "gltf", "out", "-o", "again.glb"])
        .output()
        .unwrap();
    assert!(
        st.status.success(),
        "{}",
        String::from_utf8_lossy(&st.stderr)
    );
    assert_eq!(
        std::fs::read(w.join("again.glb")).unwrap(),
        std::fs::read(w.join("out/collapse.glb")).unwrap()
    );
    // Defect 6 for `export vtk`: a second export replaces the frame folder as a whole
    // (a stale frame of a longer earlier run is gone) and leaves no temporary beside it.
    let vtk = |args: &[&str]| {
        let st = Command::new(BIN)
            .current_dir(w)
            .args(["export", "vtk", "out"])
            .args(args)
            .output()
            .unwrap();
        assert!(
            st.status.success(),
            "{}",
            String::from_utf8_lossy(&st.stderr)
        );
    };
    vtk(&[]);
    let frames = w.join("out/vtk/collapse");
    let n = std::fs::read_dir(&frames).unwrap().count();
    assert!(n >= 2, "{n} frames");
    std::fs::write(frames.join("step_999999.vtu"), "stale").unwrap();
    vtk(&[]);
    assert!(!frames.join("step_999999.vtu").exists());
    assert_eq!(std::fs::read_dir(&frames).unwrap().count(), n);
    let mut left: Vec<String> = std::fs::read_dir(w.join("out/vtk"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    left.sort();
    assert_eq!(left, ["collapse", "collapse.pvd"]);
}

/// A value outside its plausible range that the user means (`--allow-unusual`) runs,
/// and the run's summary lists it; without the option the same run is refused.
#[test]
fn allow_unusual_runs_and_the_summary_records_it() {
    let tmp = tempfile::tempdir().unwrap();
    let w = tmp.path();
    setup(w);
    std::fs::write(w.join("model.toml"), model("xi = 0.05", "xi = 0.35")).unwrap();
    std::fs::write(
        w.join("s.toml"),
        scenario("mode = \"rigid\"", "mode = \"fe\"") + "[fe]\nduration = 0.05\n",
    )
    .unwrap();
    let run = |extra: &[&str]| {
        Command::new(BIN)
            .current_dir(w)
            .args(["run", "s.toml", "--quiet"])
            .args(extra)
            .output()
            .unwrap()
    };
    let refused = run(&[]);
    let err = String::from_utf8_lossy(&refused.stderr);
    assert_eq!(refused.status.code(), Some(1), "{err}");
    assert!(err.contains("damping.xi = 0.35 is outside"), "{err}");
    assert!(!w.join("out").exists());
    let ok = run(&["--allow-unusual"]);
    assert!(
        ok.status.success(),
        "{}",
        String::from_utf8_lossy(&ok.stderr)
    );
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(w.join("out/summary.json")).unwrap())
            .unwrap();
    assert_eq!(
        s["unusual_values"],
        serde_json::json!([
            "damping.xi = 0.35 is outside the plausible damping ratio range [0, 0.3]"
        ])
    );
}

/// A pipe given where a file is read (a study file, a run folder's table) is refused at
/// once, naming it, instead of blocking forever: every reader takes regular files only.
#[test]
fn pipes_are_refused_at_once_everywhere() {
    let tmp = tempfile::tempdir().unwrap();
    let w = tmp.path();
    let fifo = |p: &Path| {
        let ok = Command::new("mkfifo").arg(p).status().unwrap().success();
        assert!(ok, "mkfifo {}", p.display());
    };
    fifo(&w.join("study.toml"));
    let run = w.join("run");
    std::fs::create_dir(&run).unwrap();
    fifo(&run.join("bodies.csv"));
    let cases: [&[&str]; 5] = [
        &["study", "plan", "study.toml"],
        &["export", "gltf", "run", "-o", "x.glb"],
        &["voids", "run"],
        &["report", "run", "-o", "x.html"],
        &["plot", "run", "--out", "figs"],
    ];
    for args in cases {
        // `timeout` ends a reader that blocks on the pipe (exit 124).
        let out = Command::new("timeout")
            .arg("20")
            .arg(BIN)
            .args(args)
            .current_dir(w)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
        assert!(err.contains("not a regular file"), "{args:?}: {err}");
        assert!(
            !w.join("x.glb").exists() && !w.join("x.html").exists() && !w.join("figs").exists()
        );
    }
}

/// A pipe in place of a file a reader can do without (a run folder's `voids.csv` and
/// `voids.json`) is refused at once, naming it: never waited on (`report` used to block
/// on `voids.csv`), never taken for a missing file (`plot`, `report` and `export gltf`
/// used to leave the voids out without a word).
#[test]
fn pipes_in_place_of_optional_run_files_are_refused_naming_them() {
    let tmp = tempfile::tempdir().unwrap();
    let w = tmp.path();
    setup(w);
    std::fs::write(
        w.join("s.toml"),
        scenario("output = \"out\"", "output = \"run\"") + "[physics]\ntime_limit_s = 0.4\n",
    )
    .unwrap();
    let out = Command::new(BIN)
        .args(["run", "s.toml", "--quiet"])
        .current_dir(w)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let run = w.join("run");
    let cases: [(&str, &[&str]); 4] = [
        ("voids.csv", &["plot", "run", "--out", "figs"]),
        ("voids.csv", &["report", "run", "-o", "x.html"]),
        ("voids.json", &["report", "run", "-o", "x.html"]),
        ("voids.json", &["export", "gltf", "run", "-o", "x.glb"]),
    ];
    for (file, args) in cases {
        let p = run.join(file);
        let kept = std::fs::read(&p).unwrap();
        std::fs::remove_file(&p).unwrap();
        assert!(Command::new("mkfifo").arg(&p).status().unwrap().success());
        // `timeout` ends a reader that blocks on the pipe (exit 124).
        let out = Command::new("timeout")
            .arg("20")
            .arg(BIN)
            .args(args)
            .current_dir(w)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{file} {args:?}: {err}");
        assert!(
            err.contains(&format!("{file}: not a regular file")),
            "{file} {args:?}: {err}"
        );
        assert!(
            !w.join("figs").exists() && !w.join("x.html").exists() && !w.join("x.glb").exists()
        );
        std::fs::remove_file(&p).unwrap();
        std::fs::write(&p, kept).unwrap();
    }
}

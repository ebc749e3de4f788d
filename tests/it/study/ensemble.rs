//! The ensemble axis of a study (`[ensemble] members = N`) and the per-intensity
//! debris-density grids of `study collect`: member ids, a perturbed member rerun gives the
//! same bytes, the ensemble statistics are those of the members' `summary.json`, and the
//! density grid is the count of the members' final body centres per cell (recomputed here
//! from their `ruins.csv`), integrating to bodies × runs; the rescue map of the intensity
//! agrees with the runs' `voids.csv` and `ensemble.csv` gives their void counts' spread.
use std::collections::BTreeMap;
use std::fs;
use std::path::Path;
use std::process::Command;

const EXE: &str = env!("CARGO_BIN_EXE_fem2rbd");

fn repo(p: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join(p)
        .display()
        .to_string()
}

fn fem2rbd(args: &[&str]) -> (bool, String, String) {
    let o = Command::new(EXE).args(args).output().unwrap();
    (
        o.status.success(),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

fn tree(root: &Path) -> Vec<(String, Vec<u8>)> {
    let mut v: Vec<(String, Vec<u8>)> = fs::read_dir(root)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.file_name().unwrap() != "status.json")
        .map(|p| {
            (
                p.file_name().unwrap().to_string_lossy().into_owned(),
                fs::read(&p).unwrap(),
            )
        })
        .collect();
    v.sort();
    v
}

/// Final (x, y) of every active body of a run folder, from `bodies.csv` (passive column)
/// and `ruins.csv` (x, y columns).
fn final_xy(dir: &Path) -> Vec<(f64, f64)> {
    let read = |name: &str| -> (Vec<String>, Vec<Vec<String>>) {
        let mut r = csv::Reader::from_path(dir.join(name)).unwrap();
        let h: Vec<String> = r.headers().unwrap().iter().map(str::to_owned).collect();
        let rows = r
            .records()
            .map(|x| x.unwrap().iter().map(str::to_owned).collect())
            .collect();
        (h, rows)
    };
    let (bh, bodies) = read("bodies.csv");
    let (rh, ruins) = read("ruins.csv");
    let col = |h: &[String], k: &str| h.iter().position(|c| c == k).unwrap();
    let (passive, x, y) = (col(&bh, "passive"), col(&rh, "x"), col(&rh, "y"));
    assert_eq!(bodies.len(), ruins.len());
    bodies
        .iter()
        .zip(&ruins)
        .filter(|(b, _)| b[passive] != "1" && b[passive] != "true")
        .map(|(_, r)| (r[x].parse().unwrap(), r[y].parse().unwrap()))
        .collect()
}

#[test]
fn ensemble_members_statistics_and_density_grid() {
    let t = tempfile::tempdir().unwrap();
    fs::write(
        t.path().join("base.toml"),
        format!(
            "model = \"{}\"\nmode = \"hybrid\"\n[[ground_motion]]\nfile = \"{}\"\ndirection = \"X\"\n[fe]\ndt = 0.01\nduration = 2.0\n[collapse]\ncriterion = \"drift_4pct\"\n[physics]\ntime_limit_s = 2.0\n",
            repo("data/frame3/model.toml"),
            repo("data/ground-motions/RSN6_IMPVALL.I_I-ELC180.AT2")
        ),
    )
    .unwrap();
    let study = t.path().join("study.toml");
    let text = format!(
        "base = \"base.toml\"\n[records]\ntime_scale = 0.5\n[[records.list]]\nname = \"elcentro\"\nx = \"{gm}/RSN6_IMPVALL.I_I-ELC180.AT2\"\ny = \"{gm}/RSN6_IMPVALL.I_I-ELC270.AT2\"\n[intensity]\npga_g = [1.5]\n[ensemble]\nmembers = 3\nseed = 7\n",
        gm = repo("data/ground-motions")
    );
    fs::write(&study, &text).unwrap();
    let (s, out) = (study.to_str().unwrap(), t.path().join("out"));
    let o = out.to_str().unwrap();

    // Bad ensemble values are refused before anything runs, naming file and line.
    let bad = t.path().join("bad.toml");
    for (bt, msg) in [
        (
            text.replace("members = 3", "members = 0"),
            "bad.toml:11: ensemble.members must be 1 to 1000, got 0",
        ),
        (
            format!("modes = [\"fe\"]\n{text}"),
            "bad.toml:12: ensemble.members: members perturb the ruin stage only",
        ),
    ] {
        fs::write(&bad, bt).unwrap();
        let (ok, _, err) = fem2rbd(&["study", "plan", bad.to_str().unwrap()]);
        assert!(!ok && err.contains(msg), "{err}");
    }

    let (ok, manifest, err) = fem2rbd(&["--quiet", "study", "plan", s, "--out", o]);
    assert!(ok, "{err}");
    assert_eq!(
        manifest,
        "id\tround\tmodel\trecord\tmode\tpga_g\tmember\n\
         base__elcentro__hybrid__1.500g__m000\t0\tbase\telcentro\thybrid\t1.500\t0\n\
         base__elcentro__hybrid__1.500g__m001\t0\tbase\telcentro\thybrid\t1.500\t1\n\
         base__elcentro__hybrid__1.500g__m002\t0\tbase\telcentro\thybrid\t1.500\t2\n"
    );
    let (ok, _, err) = fem2rbd(&["--quiet", "study", "run", s, "--out", o, "--jobs", "2"]);
    assert!(ok, "{err}");
    let ids: Vec<String> = (0..3)
        .map(|m| format!("base__elcentro__hybrid__1.500g__m{m:03}"))
        .collect();

    // A perturbed member run again elsewhere: the same bytes.
    let again = t.path().join("again");
    let (ok, _, err) = fem2rbd(&[
        "--quiet",
        "study",
        "run-one",
        s,
        &ids[1],
        "--out",
        again.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    assert_eq!(
        tree(&out.join("runs").join(&ids[1])),
        tree(&again.join("runs").join(&ids[1]))
    );

    // The members share the FE stage (same Tc) and differ in the ruin stage.
    let summaries: Vec<serde_json::Value> = ids
        .iter()
        .map(|id| {
            serde_json::from_str(
                &fs::read_to_string(out.join("runs").join(id).join("summary.json")).unwrap(),
            )
            .unwrap()
        })
        .collect();
    assert!(summaries.iter().all(|x| x["tc_s"] == summaries[0]["tc_s"]));
    assert!(summaries[0]["tc_s"].as_f64().is_some());
    let area: Vec<f64> = summaries
        .iter()
        .map(|x| x["ruins"]["debris_footprint_area_m2"].as_f64().unwrap())
        .collect();
    assert!(area[1] != area[0] || area[2] != area[0], "{area:?}");

    // ensemble.csv: the mean / sample std / min / max of the members' values.
    let ens = fs::read_to_string(out.join("results/ensemble.csv")).unwrap();
    let row = ens
        .lines()
        .find(|l| l.starts_with("base,elcentro,hybrid,1.500,ruins.debris_footprint_area_m2,"))
        .unwrap_or_else(|| panic!("{ens}"));
    let f: Vec<f64> = row.split(',').skip(5).map(|x| x.parse().unwrap()).collect();
    let mean = area.iter().sum::<f64>() / 3.0;
    let std = (area.iter().map(|a| (a - mean).powi(2)).sum::<f64>() / 2.0).sqrt();
    let (mn, mx) = (
        area.iter().copied().fold(f64::INFINITY, f64::min),
        area.iter().copied().fold(f64::NEG_INFINITY, f64::max),
    );
    assert_eq!(f[0], 3.0);
    for (got, want) in f[1..].iter().zip([mean, std, mn, mx]) {
        assert!((got - want).abs() < 1.5e-6, "{row}: {got} vs {want}");
    }
    let runs = fs::read_to_string(out.join("results/runs.csv")).unwrap();
    assert!(runs.starts_with("id,round,model,record,mode,pga_g,member,status,"));

    // The density grid of the intensity: the final body centres of the three members per
    // cell, recomputed here from their ruins.csv.
    let dj: serde_json::Value = serde_json::from_str(
        &fs::read_to_string(out.join("results/density/base__hybrid__1.500g.json")).unwrap(),
    )
    .unwrap();
    let cell = dj["cell_m"].as_f64().unwrap();
    // frame3's footprint is 1.60 m square (1.5 m bays + 0.1 m columns): 1.6 / 40.
    assert!((cell - 0.04).abs() < 1e-9, "{cell}");
    assert_eq!(dj["runs"], 3);
    let bodies = summaries[0]["bodies"].as_u64().unwrap();
    assert_eq!(dj["bodies_per_run"].as_u64().unwrap(), bodies);
    let mut want: BTreeMap<(i64, i64), u64> = BTreeMap::new();
    let mut n = 0;
    for id in &ids {
        for (x, y) in final_xy(&out.join("runs").join(id)) {
            *want
                .entry(((x / cell).floor() as i64, (y / cell).floor() as i64))
                .or_default() += 1;
            n += 1;
        }
    }
    assert_eq!(n, 3 * bodies);
    let csv = fs::read_to_string(out.join("results/density/base__hybrid__1.500g.csv")).unwrap();
    let mut got: BTreeMap<(i64, i64), u64> = BTreeMap::new();
    let mut integral = 0.0;
    for l in csv.lines().skip(1) {
        let f: Vec<&str> = l.split(',').collect();
        let c: u64 = f[6].parse().unwrap();
        if c > 0 {
            got.insert((f[0].parse().unwrap(), f[1].parse().unwrap()), c);
        }
        // bodies per m² per run, integrated over the cell areas: bodies of one run.
        integral += f[7].parse::<f64>().unwrap() * cell * cell;
        let share: f64 = f[5].parse().unwrap();
        let covered: f64 = f[4].parse().unwrap();
        assert!((share - covered / 3.0).abs() < 1e-6);
    }
    assert_eq!(got, want);
    assert!((integral - bodies as f64).abs() < 1e-3, "{integral}");

    // The rescue map of the intensity agrees with the three runs' voids.csv, and
    // ensemble.csv holds the statistics of their void counts (voids.json).
    let runs_dirs: Vec<_> = ids.iter().map(|id| out.join("runs").join(id)).collect();
    crate::rescue::ensemble::assert_map_agrees(
        &out.join("results/rescue/base__hybrid__1.500g.csv"),
        &runs_dirs,
    );
    let rj: serde_json::Value = serde_json::from_str(
        &fs::read_to_string(out.join("results/rescue/base__hybrid__1.500g.json")).unwrap(),
    )
    .unwrap();
    assert_eq!(rj["members_analysed"], 3);
    let counts: Vec<f64> = runs_dirs
        .iter()
        .map(|d| {
            let v: serde_json::Value =
                serde_json::from_str(&fs::read_to_string(d.join("voids.json")).unwrap()).unwrap();
            v["voids_count"].as_f64().unwrap()
        })
        .collect();
    let row = ens
        .lines()
        .find(|l| l.starts_with("base,elcentro,hybrid,1.500,rescue.voids_count,3,"))
        .unwrap_or_else(|| panic!("{ens}"));
    let f: Vec<f64> = row.split(',').skip(6).map(|x| x.parse().unwrap()).collect();
    assert!(
        (f[0] - counts.iter().sum::<f64>() / 3.0).abs() < 1e-6,
        "{row}"
    );
    assert_eq!(f[2], counts.iter().copied().fold(f64::INFINITY, f64::min));
    assert_eq!(
        f[3],
        counts.iter().copied().fold(f64::NEG_INFINITY, f64::max)
    );

    // `fem2rbd plot` draws the density map of the intensity.
    let (ok, stdout, err) = fem2rbd(&["plot", o, "--format", "png"]);
    assert!(ok, "{err}");
    assert!(
        stdout
            .lines()
            .any(|l| l.ends_with("density_base_hybrid_1.500g.png")),
        "{stdout}"
    );
}

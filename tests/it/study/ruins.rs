//! The shipped hybrid ruin study `data/studies/frame3-ruins.toml` run as shipped (only
//! `--out` differs): its per-intensity debris-density grids are recomputed here from the
//! members' own `bodies.csv` and `ruins.csv` with an independent plan projection (box
//! corners → convex hull → cell centres inside), the grids integrate to bodies × runs,
//! their covered cells stay inside each run's `extent_beyond_footprint_m` and cover each
//! run's `debris_footprint_area_m2`, a member rerun alone gives the same bytes, and
//! `fem2rbd plot` draws a density map per intensity next to the IDA and fragility figures.
use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

const EXE: &str = env!("CARGO_BIN_EXE_fem2rbd");

fn repo(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

fn fem2rbd(args: &[&str]) -> (bool, String, String) {
    let o = Command::new(EXE).args(args).output().unwrap();
    (
        o.status.success(),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// Every file under `root` (relative path, bytes).
fn tree(root: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    fn walk(root: &Path, d: &Path, out: &mut Vec<(PathBuf, Vec<u8>)>) {
        for e in fs::read_dir(d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                walk(root, &p, out);
            } else {
                out.push((
                    p.strip_prefix(root).unwrap().to_path_buf(),
                    fs::read(&p).unwrap(),
                ));
            }
        }
    }
    let mut v = Vec::new();
    walk(root, root, &mut v);
    v.sort();
    v
}

/// A CSV file as (header, rows).
fn read_csv(p: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let mut r = csv::Reader::from_path(p).unwrap();
    let h = r.headers().unwrap().iter().map(str::to_owned).collect();
    let rows = r
        .records()
        .map(|x| x.unwrap().iter().map(str::to_owned).collect())
        .collect();
    (h, rows)
}

/// One active body at its final pose: centre (x, y) and the plan convex hull of its 8
/// box corners (counter-clockwise).
struct FinalBody {
    centre: [f64; 2],
    hull: Vec<[f64; 2]>,
}

/// Andrew's monotone chain: the convex hull of `p`, counter-clockwise, no collinear
/// points.
fn convex_hull(mut p: Vec<[f64; 2]>) -> Vec<[f64; 2]> {
    p.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    p.dedup();
    if p.len() < 3 {
        return p;
    }
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| {
        (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    };
    let mut h: Vec<[f64; 2]> = Vec::new();
    for pass in 0..2 {
        let start = h.len();
        let pts: Vec<[f64; 2]> = if pass == 0 {
            p.clone()
        } else {
            p.iter().rev().copied().collect()
        };
        for q in pts {
            while h.len() >= start + 2 && cross(h[h.len() - 2], h[h.len() - 1], q) <= 0.0 {
                h.pop();
            }
            h.push(q);
        }
        h.pop();
    }
    h
}

fn inside(hull: &[[f64; 2]], x: f64, y: f64) -> bool {
    hull.len() >= 3
        && (0..hull.len()).all(|i| {
            let (a, b) = (hull[i], hull[(i + 1) % hull.len()]);
            (b[0] - a[0]) * (y - a[1]) - (b[1] - a[1]) * (x - a[0]) >= 0.0
        })
}

/// The active bodies of a run folder at their final poses: half extents from
/// `bodies.csv`, final centre and unit quaternion (w, x, y, z) from `ruins.csv`; a box
/// corner is c + R(q)·(±hx, ±hy, ±hz).
fn final_bodies(dir: &Path) -> Vec<FinalBody> {
    let (bh, bodies) = read_csv(&dir.join("bodies.csv"));
    let (rh, ruins) = read_csv(&dir.join("ruins.csv"));
    assert_eq!(bodies.len(), ruins.len(), "{}", dir.display());
    let col = |h: &[String], k: &str| h.iter().position(|c| c == k).unwrap();
    let f = |row: &[String], h: &[String], k: &str| -> f64 { row[col(h, k)].parse().unwrap() };
    let mut out = Vec::new();
    for (b, r) in bodies.iter().zip(&ruins) {
        assert_eq!(b[col(&bh, "name")], r[col(&rh, "name")]);
        let passive = &b[col(&bh, "passive")];
        if passive == "1" || passive == "true" {
            continue;
        }
        let half = [f(b, &bh, "hx"), f(b, &bh, "hy"), f(b, &bh, "hz")];
        let c = [f(r, &rh, "x"), f(r, &rh, "y"), f(r, &rh, "z")];
        let (w, x, y, z) = (
            f(r, &rh, "qw"),
            f(r, &rh, "qx"),
            f(r, &rh, "qy"),
            f(r, &rh, "qz"),
        );
        // Rotation matrix of the unit quaternion (rows 0 and 1: the plan components).
        let m = [
            [
                1.0 - 2.0 * (y * y + z * z),
                2.0 * (x * y - w * z),
                2.0 * (x * z + w * y),
            ],
            [
                2.0 * (x * y + w * z),
                1.0 - 2.0 * (x * x + z * z),
                2.0 * (y * z - w * x),
            ],
        ];
        let mut pts = Vec::new();
        for s in 0..8 {
            let l = [
                if s & 1 == 0 { -half[0] } else { half[0] },
                if s & 2 == 0 { -half[1] } else { half[1] },
                if s & 4 == 0 { -half[2] } else { half[2] },
            ];
            pts.push([
                c[0] + m[0][0] * l[0] + m[0][1] * l[1] + m[0][2] * l[2],
                c[1] + m[1][0] * l[0] + m[1][1] * l[1] + m[1][2] * l[2],
            ]);
        }
        out.push(FinalBody {
            centre: [c[0], c[1]],
            hull: convex_hull(pts),
        });
    }
    out
}

/// The cells (side `c`) whose centre lies under at least one body's plan hull.
fn covered_cells(bodies: &[FinalBody], c: f64) -> BTreeSet<(i64, i64)> {
    let mut cells = BTreeSet::new();
    for b in bodies {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for q in &b.hull {
            for k in 0..2 {
                lo[k] = lo[k].min(q[k]);
                hi[k] = hi[k].max(q[k]);
            }
        }
        for j in (lo[1] / c).floor() as i64 - 1..=(hi[1] / c).ceil() as i64 {
            for i in (lo[0] / c).floor() as i64 - 1..=(hi[0] / c).ceil() as i64 {
                if inside(&b.hull, (i as f64 + 0.5) * c, (j as f64 + 0.5) * c) {
                    cells.insert((i, j));
                }
            }
        }
    }
    cells
}

#[test]
fn shipped_ruin_study_density_maps_per_intensity() {
    let study = repo("data/studies/frame3-ruins.toml");
    let s = study.to_str().unwrap();
    let t = tempfile::tempdir().unwrap();
    let (a, b) = (t.path().join("jobs2"), t.path().join("jobs1"));

    let (ok, manifest, err) =
        fem2rbd(&["--quiet", "study", "plan", s, "--out", a.to_str().unwrap()]);
    assert!(ok, "{err}");
    let entries: Vec<Vec<String>> = manifest
        .lines()
        .skip(1)
        .map(|l| l.split('\t').map(str::to_owned).collect())
        .collect();
    // 2 records × 2 intensities × 2 members, hybrid.
    assert_eq!(entries.len(), 8, "{manifest}");
    assert!(entries.iter().all(|e| e[4] == "hybrid"));
    let pgas: BTreeSet<&str> = entries.iter().map(|e| e[5].as_str()).collect();
    assert_eq!(pgas.len(), 2, "{manifest}");

    let o = a.to_str().unwrap();
    let (ok, _, err) = fem2rbd(&["--quiet", "study", "run", s, "--out", o, "--jobs", "2"]);
    assert!(ok, "{err}");
    // A perturbed member of the top intensity run again alone in another folder (as a
    // `--jobs 1` study or a Slurm task runs it): every file but status.json the same
    // bytes; and a second collect rewrites the same results.
    let last = &entries.last().unwrap()[0];
    let (ok, _, err) = fem2rbd(&[
        "--quiet",
        "study",
        "run-one",
        s,
        last,
        "--out",
        b.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let strip = |v: Vec<(PathBuf, Vec<u8>)>| -> Vec<(PathBuf, Vec<u8>)> {
        v.into_iter()
            .filter(|(p, _)| p.file_name().unwrap() != "status.json")
            .collect()
    };
    assert_eq!(
        strip(tree(&a.join("runs").join(last))),
        strip(tree(&b.join("runs").join(last)))
    );
    let results = tree(&a.join("results"));
    let (ok, _, err) = fem2rbd(&["--quiet", "study", "collect", s, "--out", o]);
    assert!(ok, "{err}");
    assert_eq!(tree(&a.join("results")), results);

    let runs = a.join("runs");
    let summary = |id: &str| -> serde_json::Value {
        serde_json::from_str(&fs::read_to_string(runs.join(id).join("summary.json")).unwrap())
            .unwrap()
    };
    let mut collapses = 0;
    for pga in &pgas {
        let ids: Vec<&str> = entries
            .iter()
            .filter(|e| e[5] == *pga)
            .map(|e| e[0].as_str())
            .collect();
        let stem = format!("frame3__hybrid__{pga}g");
        let dj: serde_json::Value = serde_json::from_str(
            &fs::read_to_string(a.join(format!("results/density/{stem}.json"))).unwrap(),
        )
        .unwrap();
        assert_eq!(dj["runs"].as_u64().unwrap(), ids.len() as u64);
        let run_ids: Vec<&str> = dj["run_ids"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_str().unwrap())
            .collect();
        assert_eq!(run_ids, ids);
        let c = dj["cell_m"].as_f64().unwrap();
        // frame3's footprint is 1.60 m square (1.5 m bays + 0.1 m columns): 1.6 / 40.
        assert!((c - 0.04).abs() < 1e-9, "{c}");
        let fp = &dj["footprint_m"];
        let fpv = |k: &str, i: usize| fp[k][i].as_f64().unwrap();
        let bodies = dj["bodies_per_run"].as_u64().unwrap();

        // Recompute both counts of every cell from the run folders.
        let mut want_cov: BTreeMap<(i64, i64), u64> = BTreeMap::new();
        let mut want_cen: BTreeMap<(i64, i64), u64> = BTreeMap::new();
        // The farthest any run's debris reaches beyond each side (summary.json).
        let mut reach = [0.0f64; 4];
        for id in &ids {
            let sm = summary(id);
            assert_eq!(sm["bodies"].as_u64().unwrap(), bodies, "{id}");
            let fb = final_bodies(&runs.join(id));
            assert_eq!(fb.len() as u64, bodies, "{id}");
            for b in &fb {
                *want_cen
                    .entry((
                        (b.centre[0] / c).floor() as i64,
                        (b.centre[1] / c).floor() as i64,
                    ))
                    .or_default() += 1;
            }
            let cells = covered_cells(&fb, c);
            for k in &cells {
                *want_cov.entry(*k).or_default() += 1;
            }
            if sm["tc_s"].is_null() {
                continue;
            }
            collapses += 1;
            // A collapsed run's debris area (the union of the same plan hulls, exact) and
            // its cells' area agree to the rasterisation error of 0.04 m cells.
            let area = sm["ruins"]["debris_footprint_area_m2"].as_f64().unwrap();
            let raster = cells.len() as f64 * c * c;
            assert!(
                (raster - area).abs() < 0.05 * area,
                "{id}: {} cells = {raster:.4} m² vs debris_footprint_area_m2 {area}",
                cells.len()
            );
            let e = &sm["ruins"]["extent_beyond_footprint_m"];
            for (k, side) in ["x_minus", "x_plus", "y_minus", "y_plus"]
                .iter()
                .enumerate()
            {
                reach[k] = reach[k].max(e[side].as_f64().unwrap());
            }
        }
        let (mut got_cov, mut got_cen) = (BTreeMap::new(), BTreeMap::new());
        for cell in dj["cells"].as_array().unwrap() {
            let v: Vec<i64> = cell
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_i64().unwrap())
                .collect();
            assert!(v[2] > 0 || v[3] > 0, "{stem}: an empty cell listed: {v:?}");
            assert!(v[2] as usize <= ids.len());
            if v[2] > 0 {
                got_cov.insert((v[0], v[1]), v[2] as u64);
                // Covered only within the farthest reach of the runs' debris.
                let (x, y) = ((v[0] as f64 + 0.5) * c, (v[1] as f64 + 0.5) * c);
                assert!(
                    x >= fpv("x", 0) - reach[0] - 1e-5
                        && x <= fpv("x", 1) + reach[1] + 1e-5
                        && y >= fpv("y", 0) - reach[2] - 1e-5
                        && y <= fpv("y", 1) + reach[3] + 1e-5,
                    "{stem}: cell {v:?} beyond the debris extent {reach:?}"
                );
            }
            if v[3] > 0 {
                got_cen.insert((v[0], v[1]), v[3] as u64);
            }
        }
        assert_eq!(got_cen, want_cen, "{stem}: body centres per cell");
        assert_eq!(got_cov, want_cov, "{stem}: runs covering each cell");
        let total: u64 = got_cen.values().sum();
        assert_eq!(total, bodies * ids.len() as u64, "{stem}");

        // The CSV: the same cells, share = covered / runs, and bodies_per_m2 integrating
        // to the bodies of one run.
        let (h, rows) = read_csv(&a.join(format!("results/density/{stem}.csv")));
        assert_eq!(
            h,
            [
                "i",
                "j",
                "x_m",
                "y_m",
                "runs_covered",
                "share",
                "body_centres",
                "bodies_per_m2"
            ]
        );
        assert_eq!(rows.len(), dj["cells"].as_array().unwrap().len());
        let mut integral = 0.0;
        for r in &rows {
            let key = (r[0].parse::<i64>().unwrap(), r[1].parse::<i64>().unwrap());
            let cov: f64 = r[4].parse().unwrap();
            assert_eq!(cov as u64, got_cov.get(&key).copied().unwrap_or(0));
            let share: f64 = r[5].parse().unwrap();
            assert!((share - cov / ids.len() as f64).abs() < 1e-6);
            integral += r[7].parse::<f64>().unwrap() * c * c;
        }
        assert!(
            (integral - bodies as f64).abs() < 1e-3,
            "{stem}: {integral}"
        );
    }
    // The example is a ruin study: every run collapses, and at the top intensity the
    // frame breaks apart (broken connections in every run).
    assert_eq!(collapses, 8);
    // The stripe fragility counts each record at each intensity once (2 records × 2
    // intensities), not each of the 2 members: collapse is the FE stage's, which they share.
    let sj: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(a.join("results/study.json")).unwrap()).unwrap();
    let frag = &sj["fragility"][0];
    assert_eq!(frag["method"], "stripes_lognormal_mle_binomial");
    assert_eq!(
        (frag["collapses"].as_u64(), frag["non_collapses"].as_u64()),
        (Some(4), Some(0))
    );
    for stripe in frag["data"].as_array().unwrap() {
        assert_eq!(stripe["runs"], 2, "{stripe}");
    }
    let top = pgas.iter().next_back().unwrap();
    for e in entries.iter().filter(|e| e[5] == *top) {
        let broken = summary(&e[0])["connections"]["broken"].as_u64().unwrap();
        assert!(broken > 0, "{}: no connection broken", e[0]);
    }

    // `fem2rbd plot`: a density map per intensity, the IDA curves and the fragility.
    let (ok, stdout, err) = fem2rbd(&["plot", a.to_str().unwrap(), "--format", "png"]);
    assert!(ok, "{err}");
    let mut want: Vec<String> = pgas
        .iter()
        .map(|p| format!("density_frame3_hybrid_{p}g.png"))
        .collect();
    want.push("ida_frame3_hybrid.png".into());
    want.push("fragility_frame3_hybrid.png".into());
    for w in &want {
        let line = stdout
            .lines()
            .find(|l| l.ends_with(w.as_str()))
            .unwrap_or_else(|| panic!("{w} not drawn: {stdout}"));
        let png = fs::read(line.trim()).unwrap();
        assert!(
            png.starts_with(b"\x89PNG\r\n\x1a\n") && png.len() > 10_000,
            "{w}"
        );
    }
}

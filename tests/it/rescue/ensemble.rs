//! The rescue maps of an ensemble (`fem2rbd::rescue::ensemble`, `rescue_map.csv` and
//! `rescue.json`): hand-built member folders analysed by `fem2rbd voids` give known
//! probabilities, recurring places and distributions; every map cell agrees with a
//! brute-force reading of the members' `voids.csv`; a real frame3 ensemble writes maps
//! that agree with its members; a member with a broken file is refused, naming it, and
//! nothing is written.
use super::scene::*;
use fem2rbd::body::{BodyId, BodyType};
use fem2rbd::rescue::ensemble::{write_maps, FILES, MAP_CELL_M};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_fem2rbd");

fn voids(dir: &Path) {
    let out = Command::new(BIN)
        .arg("--quiet")
        .arg("voids")
        .arg(dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// One member folder: the boxes written as a run folder and analysed.
pub fn member(dir: &Path, boxes: &[SceneBox], c: &[(usize, usize, &str)]) {
    write_run(dir, boxes, c, 1.0);
    voids(dir);
}

/// The table moved by `d`, its boxes numbered from element `first + 1` and its
/// connections from box `first`.
pub fn table_at(d: [f64; 3], first: usize) -> (Vec<SceneBox>, Vec<(usize, usize, &'static str)>) {
    let (b, c) = table();
    let mut b = shifted(&b, d);
    for (k, x) in b.iter_mut().enumerate() {
        let t = if k == 0 {
            BodyType::Slab
        } else {
            BodyType::Column
        };
        x.id = BodyId::element(t, "1", (first + k + 1) as u32);
    }
    (
        b,
        c.into_iter()
            .map(|(a, b, s)| (a + first, b + first, s))
            .collect(),
    )
}

fn empty_site() -> Vec<SceneBox> {
    vec![
        ground_block(1, [0.0, 0.0], 0.5),
        ground_block(2, [3.0, 0.0], 0.5),
    ]
}

/// Rows of `rescue_map.csv`: (i, j, x, y, [p_void, p_survivable, p_rescuer, p_camera]).
pub type Row = (usize, usize, f64, f64, [f64; 4]);

/// The header of `rescue_map.csv`.
pub const HEADER: &str = "i,j,x,y,p_void,p_survivable,p_survivable_rescuer,p_survivable_camera,\
p_route_rescuer,p_route_camera,p_entry_rescuer,p_entry_camera";

pub fn map_rows(dir: &Path) -> Vec<Row> {
    read_map(&dir.join("rescue_map.csv"))
}

/// The rows of a rescue map file, with the shares of its columns from `first` on (4:
/// beneath, 8: the routes).
fn read_columns(file: &Path, first: usize) -> Vec<Row> {
    let text = std::fs::read_to_string(file).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some(HEADER));
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            assert_eq!(f.len(), 12, "{l}");
            let n = |k: usize| f[k].parse::<f64>().unwrap();
            (
                f[0].parse().unwrap(),
                f[1].parse().unwrap(),
                n(2),
                n(3),
                [n(first), n(first + 1), n(first + 2), n(first + 3)],
            )
        })
        .collect()
}

/// The rows of a rescue map file.
pub fn read_map(file: &Path) -> Vec<Row> {
    read_columns(file, 4)
}

/// The rows of a rescue map file with its route shares: [p_route_rescuer, p_route_camera,
/// p_entry_rescuer, p_entry_camera].
pub fn read_route_map(file: &Path) -> Vec<Row> {
    read_columns(file, 8)
}

/// The member folders `member-NNN` of an ensemble folder, in order.
pub fn member_dirs(dir: &Path) -> Vec<PathBuf> {
    let mut names: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            p.file_name()
                .unwrap()
                .to_string_lossy()
                .starts_with("member-")
        })
        .collect();
    names.sort();
    names
}

/// The members' voids: per void, the plan squares of its cells' columns (each cell of each
/// box of `voids.json`, one by one), its survivable, rescuer and camera flags from
/// `voids.csv` (read with the csv crate by column name) and the plan points of its
/// rescuer's and camera's routes (`voids.json` `path_m`; empty when not reached), per
/// analysed member.
type PlanVoid = (Vec<[f64; 4]>, [bool; 3], [Vec<[f64; 2]>; 2]);
fn member_voids(dirs: &[PathBuf]) -> Vec<Vec<PlanVoid>> {
    let mut out = Vec::new();
    for d in dirs {
        let js: Value =
            serde_json::from_str(&std::fs::read_to_string(d.join("voids.json")).unwrap()).unwrap();
        if js.get("error").is_some() {
            continue;
        }
        let mut r = csv::Reader::from_path(d.join("voids.csv")).unwrap();
        let h = r.headers().unwrap().clone();
        let col = |name: &str| h.iter().position(|x| x == name).unwrap();
        let mut vs = Vec::new();
        for (n, rec) in r.records().enumerate() {
            let rec = rec.unwrap();
            let b = |name: &str| &rec[col(name)] == "1";
            let g = &js["grid"];
            let o = |k: usize| g["origin_m"][k].as_f64().unwrap();
            let cell = g["cell_m"].as_f64().unwrap();
            let mut squares = Vec::new();
            for bx in js["voids"][n]["boxes"].as_array().unwrap() {
                let k = |d: usize| bx[d].as_u64().unwrap();
                for i in k(0)..k(3) {
                    for j in k(1)..k(4) {
                        let (x0, y0) = (o(0) + i as f64 * cell, o(1) + j as f64 * cell);
                        squares.push([x0, x0 + cell, y0, y0 + cell]);
                    }
                }
            }
            assert!(!squares.is_empty());
            let flags = [b("survivable"), b("rescuer_access"), b("camera_access")];
            let path = |kind: &str, reached: bool| -> Vec<[f64; 2]> {
                let v = &js["voids"][n][kind];
                assert_eq!(
                    v["reached"], reached,
                    "{kind}: voids.json against voids.csv"
                );
                v["path_m"]
                    .as_array()
                    .map(|a| {
                        a.iter()
                            .map(|p| [p[0].as_f64().unwrap(), p[1].as_f64().unwrap()])
                            .collect()
                    })
                    .unwrap_or_default()
            };
            let routes = [path("rescuer", flags[1]), path("camera", flags[2])];
            vs.push((squares, flags, routes));
        }
        out.push(vs);
    }
    out
}

/// Whether the closed segment `a`–`b` and the closed square `[x0, x1, y0, y1]` meet, by
/// separating axes: their bounding boxes overlap, and the square's corners are not all
/// strictly on one side of the segment's line.
fn separated_not(a: [f64; 2], b: [f64; 2], sq: [f64; 4]) -> bool {
    let boxes = a[0].min(b[0]) <= sq[1]
        && sq[0] <= a[0].max(b[0])
        && a[1].min(b[1]) <= sq[3]
        && sq[2] <= a[1].max(b[1]);
    let side = |x: f64, y: f64| (b[0] - a[0]) * (y - a[1]) - (b[1] - a[1]) * (x - a[0]);
    let s = [
        side(sq[0], sq[2]),
        side(sq[1], sq[2]),
        side(sq[0], sq[3]),
        side(sq[1], sq[3]),
    ];
    boxes && !(s.iter().all(|v| *v > 0.0) || s.iter().all(|v| *v < 0.0))
}

/// Writing the maps of `dir` again gives the same bytes in every file.
pub fn assert_maps_written_again_are_the_same(dir: &Path) {
    let read = || -> Vec<Vec<u8>> {
        FILES
            .iter()
            .map(|f| std::fs::read(dir.join(f)).unwrap())
            .collect()
    };
    let a = read();
    write_maps(dir).unwrap();
    assert_eq!(a, read());
}

/// Every map cell's probabilities counted again, member by member, from the members'
/// `voids.csv` and `voids.json`: a void lies beneath a cell whose centre is in the plan
/// square of one of its cells; a route to a survivable void passes over a cell when one
/// of its segments meets the cell's closed square (its edges half a map cell from the
/// row's centre), and leaves open air there when its first point lies in that square.
pub fn assert_map_agrees_with_members(dir: &Path) {
    assert_map_agrees(&dir.join("rescue_map.csv"), &member_dirs(dir));
}

/// The map `file` against the run folders `members` (see
/// [`assert_map_agrees_with_members`]).
pub fn assert_map_agrees(file: &Path, members: &[PathBuf]) {
    let members = member_voids(members);
    assert!(!members.is_empty());
    let rows = read_map(file);
    let cell = rescue_json_cell(file);
    for ((i, j, x, y, p), (.., q)) in rows.iter().zip(read_route_map(file)) {
        let sq = [
            x - cell / 2.0,
            x + cell / 2.0,
            y - cell / 2.0,
            y + cell / 2.0,
        ];
        let mut routed = [0usize; 4];
        for vs in &members {
            let mut on = [false; 4];
            for (_, f, routes) in vs.iter().filter(|v| v.1[0]) {
                for (k, path) in routes.iter().enumerate() {
                    assert_eq!(path.len() >= 2, f[k + 1], "a route where reached");
                    on[k] |= path.windows(2).any(|s| separated_not(s[0], s[1], sq));
                    on[k + 2] |= path.first().is_some_and(|p| separated_not(*p, *p, sq));
                }
            }
            for k in 0..4 {
                routed[k] += usize::from(on[k]);
            }
        }
        for k in 0..4 {
            let want = routed[k] as f64 / members.len() as f64;
            assert!(
                (q[k] - want).abs() < 1e-6,
                "cell ({i}, {j}) at ({x}, {y}), route column {k}: {} vs {want}",
                q[k]
            );
        }
        let mut count = [0usize; 4];
        for vs in &members {
            let under: Vec<&[bool; 3]> = vs
                .iter()
                .filter(|(sq, ..)| {
                    sq.iter()
                        .any(|b| b[0] <= *x && *x <= b[1] && b[2] <= *y && *y <= b[3])
                })
                .map(|(_, f, _)| f)
                .collect();
            count[0] += usize::from(!under.is_empty());
            count[1] += usize::from(under.iter().any(|f| f[0]));
            count[2] += usize::from(under.iter().any(|f| f[0] && f[1]));
            count[3] += usize::from(under.iter().any(|f| f[0] && f[2]));
        }
        for k in 0..4 {
            let want = count[k] as f64 / members.len() as f64;
            assert!(
                (p[k] - want).abs() < 1e-6,
                "cell ({i}, {j}) at ({x}, {y}), column {k}: {} vs {want}",
                p[k]
            );
        }
    }
}

/// The map's cell edge, m, from the `rescue.json` beside the map `file` (a study's
/// `<stem>.json` beside its `<stem>.csv`).
fn rescue_json_cell(file: &Path) -> f64 {
    let name = file.file_name().unwrap().to_string_lossy();
    let js = if name == "rescue_map.csv" {
        file.with_file_name("rescue.json")
    } else {
        file.with_extension("json")
    };
    let js: Value = serde_json::from_str(&std::fs::read_to_string(&js).unwrap()).unwrap();
    js["map"]["cell_m"].as_f64().unwrap()
}

/// The row whose cell holds (x, y).
pub fn at(rows: &[Row], x: f64, y: f64, h: f64) -> [f64; 4] {
    let r = rows
        .iter()
        .find(|r| (r.2 - x).abs() <= h / 2.0 && (r.3 - y).abs() <= h / 2.0)
        .unwrap_or_else(|| panic!("no cell at ({x}, {y})"));
    r.4
}

/// Writes the five member folders of [`hand_built_members_give_known_probabilities_and_places`].
pub fn hand_built_ensemble(dir: &Path) {
    let (t, c) = table_at([0.0; 3], 0);
    member(&dir.join("member-000"), &t, &c);
    let (t1, c1) = table_at([0.5, 0.0, 0.0], 0);
    member(&dir.join("member-001"), &t1, &c1);
    member(&dir.join("member-002"), &empty_site(), &[]);
    let (mut two, mut c2) = table_at([0.0; 3], 0);
    let (far, cf) = table_at([6.0, 0.0, 0.0], two.len());
    two.extend(far);
    c2.extend(cf);
    member(&dir.join("member-003"), &two, &c2);
    let failed = dir.join("member-004");
    std::fs::create_dir_all(&failed).unwrap();
    std::fs::write(
        failed.join("voids.json"),
        "{\"error\": \"grid over the bound\"}\n",
    )
    .unwrap();
}

/// Members: 0 a table (3.0 × 2.0 m slab, one survivable void the rescuer reaches), 1 the
/// table 0.5 m along x, 2 an empty site (no voids, no grid), 3 the table and a second one
/// 6 m along x, 4 a member whose analysis failed (`voids.json` holds an error). Four are
/// analysed: under the table's middle 3 of 4 have a survivable void (0.75), under the far
/// table 1 of 4 (0.25); the table recurs in 3 members, the far table in 1.
#[test]
fn hand_built_members_give_known_probabilities_and_places() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    hand_built_ensemble(dir);
    let written = write_maps(dir).unwrap();
    assert_eq!(written, FILES.map(|f| dir.join(f)).to_vec());
    let rows = map_rows(dir);
    let h = MAP_CELL_M;
    let xs: Vec<f64> = rows.iter().map(|r| r.2).collect();
    let ys: Vec<f64> = rows.iter().map(|r| r.3).collect();
    let js: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("rescue.json")).unwrap()).unwrap();
    let n = js["map"]["cells"].as_array().unwrap();
    assert_eq!(
        rows.len() as u64,
        n[0].as_u64().unwrap() * n[1].as_u64().unwrap()
    );
    // Cells of 0.5 m from the stated origin, j-major.
    let o = &js["map"]["origin_m"];
    let nx = n[0].as_u64().unwrap() as usize;
    for (k, (i, j, x, y, _)) in rows.iter().enumerate() {
        assert_eq!((*i, *j), (k % nx, k / nx));
        assert!((x - o[0].as_f64().unwrap() - (*i as f64 + 0.5) * h).abs() < 2e-6);
        assert!((y - o[1].as_f64().unwrap() - (*j as f64 + 0.5) * h).abs() < 2e-6);
    }
    // The union covers both tables (x −1.5 … 7.5) and the margins.
    assert!(xs.iter().copied().fold(f64::INFINITY, f64::min) < -1.5);
    assert!(xs.iter().copied().fold(f64::NEG_INFINITY, f64::max) > 7.5);
    assert!(ys.iter().copied().fold(f64::INFINITY, f64::min) < -1.0);

    assert_eq!(at(&rows, 0.0, 0.0, h), [0.75, 0.75, 0.75, 0.75]);
    assert_eq!(at(&rows, 6.0, 0.0, h), [0.25, 0.25, 0.25, 0.25]);
    assert_eq!(at(&rows, 3.25, 0.0, h), [0.0; 4]);
    // x in [−1.5, −1.0): members 0 and 3 (0.5); in (1.5, 2.0]: member 1 (0.25); each
    // half-metre strip holds one column of cell centres.
    let mut seen: Vec<f64> = rows.iter().map(|r| r.4[1]).collect();
    seen.sort_by(f64::total_cmp);
    seen.dedup();
    assert_eq!(seen, [0.0, 0.25, 0.5, 0.75]);
    assert!(rows
        .iter()
        .all(|r| r.4[0] == r.4[1] && r.4[1] == r.4[2] && r.4[2] == r.4[3]));
    assert_map_agrees_with_members(dir);

    assert_eq!(js["members"], 5);
    assert_eq!(js["members_analysed"], 4);
    assert_eq!(js["not_analysed"][0]["member"], "member-004");
    assert_eq!(js["map"]["cell_m"], 0.5);
    let d = &js["distributions"];
    // Void counts 1, 1, 0, 2: sorted 0, 1, 1, 2 → quartiles (type 7) 0.75, 1, 1.25.
    assert_eq!(
        d["voids_count"],
        serde_json::json!({"min": 0.0, "p25": 0.75, "median": 1.0, "p75": 1.25, "mean": 1.0, "max": 2.0})
    );
    // Each table's void is 11.28 m³: 0, 11.28, 11.28, 22.56.
    let v = &d["survivable_volume_m3"];
    for (k, want) in [
        ("min", 0.0),
        ("p25", 8.46),
        ("median", 11.28),
        ("p75", 14.1),
        ("mean", 11.28),
        ("max", 22.56),
    ] {
        assert!((v[k].as_f64().unwrap() - want).abs() < 1e-6, "{k}: {v}");
    }
    // The pile is the slab's top, 2.2 m; the empty site has none.
    assert_eq!(d["max_height_m"]["min"], 0.0);
    assert!((d["max_height_m"]["max"].as_f64().unwrap() - 2.2).abs() < 1e-6);
    assert!((d["max_height_m"]["median"].as_f64().unwrap() - 2.2).abs() < 1e-6);

    let places = js["places"].as_array().unwrap();
    assert_eq!(places.len(), 2, "{places:?}");
    assert_eq!(places[0]["members"], 3);
    assert_eq!(places[0]["recurs"], true);
    assert_eq!(places[0]["probability"], 0.75);
    assert_eq!(
        places[0]["member_folders"],
        serde_json::json!(["member-000", "member-001", "member-003"])
    );
    assert_eq!(places[0]["patterns"], serde_json::json!({"pancake": 3}));
    assert!((places[0]["volume_m3"]["mean"].as_f64().unwrap() - 11.28).abs() < 1e-6);
    // Mean centroid: the tables at x = 0, 0.5, 0.
    assert!((places[0]["mean_centroid_m"][0].as_f64().unwrap() - 0.5 / 3.0).abs() < 1e-3);
    assert_eq!(places[0]["rescuer_reaches"], 3);
    assert_eq!(places[1]["members"], 1);
    assert_eq!(places[1]["recurs"], false);
    assert_eq!(
        places[1]["member_folders"],
        serde_json::json!(["member-003"])
    );

    // The same folder gives the same bytes.
    assert_maps_written_again_are_the_same(dir);
}

/// A member whose `voids.csv` lacks a column or holds a bad value, or that lacks
/// `voids.json`, is refused naming the file (and line); nothing is written.
#[test]
fn a_broken_member_is_refused_naming_its_file() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let (t, c) = table_at([0.0; 3], 0);
    member(&dir.join("member-000"), &t, &c);
    member(&dir.join("member-001"), &t, &c);
    let csv = dir.join("member-001/voids.csv");
    let good = std::fs::read_to_string(&csv).unwrap();

    std::fs::write(&csv, good.replacen("survivable", "survives", 1)).unwrap();
    let e = write_maps(dir).unwrap_err().to_string();
    assert!(
        e.contains("member-001/voids.csv:1") && e.contains("`survivable`"),
        "{e}"
    );

    let mut lines: Vec<String> = good.lines().map(String::from).collect();
    let h: Vec<&str> = lines[0].split(',').collect();
    let k = h.iter().position(|x| *x == "volume_m3").unwrap();
    let mut f: Vec<String> = lines[1].split(',').map(String::from).collect();
    f[k] = "lots".into();
    lines[1] = f.join(",");
    std::fs::write(&csv, lines.join("\n") + "\n").unwrap();
    let e = write_maps(dir).unwrap_err().to_string();
    assert!(
        e.contains("member-001/voids.csv:2") && e.contains("`volume_m3`"),
        "{e}"
    );

    std::fs::write(&csv, good).unwrap();
    std::fs::remove_file(dir.join("member-000/voids.json")).unwrap();
    let e = write_maps(dir).unwrap_err().to_string();
    assert!(e.contains("member-000/voids.json"), "{e}");
    for f in FILES {
        assert!(!dir.join(f).exists(), "{f} written");
    }
}

/// `fem2rbd run --ensemble 3` on frame3 LC5 (rigid mode cut at 1 s): the ensemble folder
/// holds the maps, every cell agrees with the members' `voids.csv`, and the distributions
/// of the void and survivable counts are the members' own (`voids.json`).
#[test]
fn a_frame3_ensemble_writes_maps_that_agree_with_its_members() {
    let tmp = tempfile::tempdir().unwrap();
    let text = crate::support::frame3_lc5("rigid", "", "", "time_limit_s = 1.0");
    let sc = tmp.path().join("ens.toml");
    std::fs::write(&sc, text).unwrap();
    let dir = tmp.path().join("ens");
    let out = Command::new(BIN)
        .arg("--quiet")
        .arg("run")
        .arg(&sc)
        .arg("--out")
        .arg(&dir)
        .args(["--ensemble", "3", "--threads", "2"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_map_agrees_with_members(&dir);
    let js: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("rescue.json")).unwrap()).unwrap();
    assert_eq!(js["members_analysed"], 3);
    assert_eq!(js["scale"], 0.25);
    assert_eq!(js["map"]["cell_m"], MAP_CELL_M * 0.25);
    let mut counts = Vec::new();
    let mut surv = Vec::new();
    for m in 0..3 {
        let v: Value = serde_json::from_str(
            &std::fs::read_to_string(dir.join(format!("member-{m:03}/voids.json"))).unwrap(),
        )
        .unwrap();
        counts.push(v["voids_count"].as_f64().unwrap());
        surv.push(v["survivable_count"].as_f64().unwrap());
    }
    eprintln!("void counts {counts:?}, survivable {surv:?}");
    let d = &js["distributions"];
    let fold = |v: &[f64], f: fn(f64, f64) -> f64, s: f64| v.iter().copied().fold(s, f);
    assert_eq!(
        d["voids_count"]["min"],
        fold(&counts, f64::min, f64::INFINITY)
    );
    assert_eq!(
        d["voids_count"]["max"],
        fold(&counts, f64::max, f64::NEG_INFINITY)
    );
    assert_eq!(
        d["survivable_count"]["max"],
        fold(&surv, f64::max, f64::NEG_INFINITY)
    );
    let n_places: u64 = js["places"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["members"].as_u64().unwrap())
        .sum();
    assert_eq!(n_places as f64, surv.iter().sum::<f64>());
}

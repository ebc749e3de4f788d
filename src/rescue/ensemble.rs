//! The rescue analysis over an ensemble: how likely a survivable void is beneath each plan
//! cell, how the members' void and pile measures spread, and which voids recur in the same
//! place (docs/rescue.md §6). It reads only the members' own rescue files — `voids.csv`
//! (columns by their header names), `voids.json` (rubble, grid, scale, each void's
//! boxes) — so it
//! follows whatever the per-ruin analysis finds.
//!
//! * **Plan map.** A 2-D grid of square cells of edge [`MAP_CELL_M`] × the model's scale
//!   over the union of the members' analysis grids in plan (origin at the union's lower
//!   corner). A void lies **beneath** a map cell when the cell's centre is inside the
//!   plan of the void's own cells: one of the plan rectangles of its boxes (`voids.json`
//!   `boxes`, [`super::boxes`]; bounds included), so an L-shaped void does not claim the
//!   corner of its bounding box that it does not cover. Per cell and member: whether a void, a survivable void, a survivable void
//!   the rescuer reaches, one the camera reaches lies beneath; the probability is the count
//!   of members with it over the analysed members.
//! * **Routes on the map.** Per cell and member, also: whether the rescuer's route to some
//!   survivable void it reaches **passes over** the cell — the route's plan polyline
//!   (`voids.json` `rescuer.path_m`, [`super::route`], its points' x and y), segment by
//!   segment, meets the cell's closed square ([`segment_meets_square`], bounds included:
//!   a segment along a cell edge passes over both cells, one through a corner over all
//!   four) — and whether such a route **leaves open air** in the cell (its first point
//!   lies in the cell's closed square); the same for the camera's routes. A part of a route
//!   outside the map's grid passes over no cell.
//! * **Distributions** over the analysed members of the void count, the survivable void
//!   count, the survivable voids' total volume, the count of survivable voids the rescuer
//!   reaches, and the pile's max and mean height (`voids.json` `rubble`; 0 without
//!   debris): min, quartiles (linear interpolation between order statistics, Hyndman & Fan
//!   1996 type 7), mean, max.
//! * **Voids by place.** The survivable voids of all members, members in order and each
//!   member's voids in `voids.csv` order (largest first), are matched to places: a void
//!   joins the place, holding no void of its own member yet, whose first void's bounding
//!   box overlaps its own the most by intersection over union (3-D), when that is at least
//!   [`MATCH_IOU`]; otherwise it opens a place. A place recurs when it holds voids of two
//!   or more members.
//!
//! A member whose `voids.json` holds an `error` (its grid was over the bound) is not
//! analysed: it is named in `rescue.json` and left out of every denominator.
use super::volumes::route_points;
use super::{RescueError, Result};
use crate::output::run_folder::RunFolderError;
use serde_json::{json, Map, Value};
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Map cell edge at full scale, m: about a lying adult's width (0.5 m), the smallest plan
/// size a trainer places a casualty at; five analysis cells at the default 0.1 m.
pub const MAP_CELL_M: f64 = 0.5;

/// Least intersection over union of two voids' bounding boxes for them to be one place:
/// one half, so a void matches at most one of two disjoint places and a box shifted by a
/// third of its length along one axis still matches (IoU = (2/3)/(4/3) = 0.5).
pub const MATCH_IOU: f64 = 0.5;

/// The files written into an ensemble folder.
pub const FILES: [&str; 2] = ["rescue_map.csv", "rescue.json"];

/// One void of a member, as its `voids.csv` row gives it.
#[derive(Debug, Clone, PartialEq)]
pub struct MemberVoid {
    /// Volume, m³.
    pub volume_m3: f64,
    /// A lying or sitting adult fits.
    pub survivable: bool,
    /// The rescuer reaches it.
    pub rescuer: bool,
    /// The camera reaches it.
    pub camera: bool,
    /// The collapse pattern's name.
    pub pattern: String,
    /// Centroid, m.
    pub centroid_m: [f64; 3],
    /// Bounding box (min, max), m.
    pub bounds_m: [[f64; 3]; 2],
    /// Its plan footprint: the plan rectangles ([min x, min y], [max x, max y], m) of its
    /// cells' boxes (`voids.json` `boxes`, [`super::boxes`]), without repeats; their
    /// union is the plan of its columns. Empty until [`read_member`] reads them.
    pub footprint_m: Vec<[[f64; 2]; 2]>,
    /// The rescuer's route in plan (x, y of `voids.json` `rescuer.path_m`, from where it
    /// leaves open air to the void), m; empty when the rescuer does not reach the void, or
    /// until [`read_member`] reads it.
    pub rescuer_path_m: Vec<[f64; 2]>,
    /// The camera's route in plan (`camera.path_m`), as `rescuer_path_m`.
    pub camera_path_m: Vec<[f64; 2]>,
}

/// One member's rescue analysis.
#[derive(Debug, Clone, PartialEq)]
pub struct MemberRescue {
    /// The voids, in `voids.csv` order.
    pub voids: Vec<MemberVoid>,
    /// The plan extent of its grid ([min x, min y], [max x, max y]), m (`None`: no grid,
    /// no debris).
    pub extent_m: Option<[[f64; 2]; 2]>,
    /// Pile height, max and mean, m (0 without debris).
    pub max_height_m: f64,
    /// See `max_height_m`.
    pub mean_height_m: f64,
    /// The model's scale.
    pub scale: f64,
}

/// A member folder: its name and its analysis, or why there is none.
#[derive(Debug, Clone, PartialEq)]
pub struct Member {
    /// Folder name (`member-003`).
    pub name: String,
    /// The analysis, or the error its `voids.json` records.
    pub rescue: std::result::Result<MemberRescue, String>,
}

fn inconsistent(file: &Path, line: usize, message: String) -> RescueError {
    RescueError::Inconsistent {
        file: file.display().to_string(),
        line,
        message,
    }
}

fn read(path: &Path) -> Result<String> {
    crate::model::limits::read_regular_file(path).map_err(|error| {
        RunFolderError::Read {
            path: path.to_path_buf(),
            error,
        }
        .into()
    })
}

/// The voids of a `voids.csv` text (`file` for errors), by column name.
pub fn parse_voids_csv(text: &str, file: &Path) -> Result<Vec<MemberVoid>> {
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(true)
        .from_reader(text.as_bytes());
    let header = reader
        .headers()
        .map_err(|e| inconsistent(file, 1, format!("not a CSV header: {e}")))?
        .clone();
    const NEEDED: [&str; 13] = [
        "volume_m3",
        "survivable",
        "rescuer_access",
        "camera_access",
        "pattern",
        "centroid_x",
        "centroid_y",
        "centroid_z",
        "min_x",
        "min_y",
        "min_z",
        "max_x",
        "max_y",
    ];
    let col = |name: &str| -> Result<usize> {
        header
            .iter()
            .position(|h| h == name)
            .ok_or_else(|| inconsistent(file, 1, format!("no column `{name}`")))
    };
    for name in NEEDED {
        col(name)?;
    }
    let max_z = col("max_z")?;
    let mut out = Vec::new();
    for rec in reader.records() {
        let rec = rec.map_err(|e| {
            let line = e.position().map_or(0, |p| p.line() as usize);
            inconsistent(file, line, format!("not a CSV row: {e}"))
        })?;
        let line = rec.position().map_or(0, |p| p.line() as usize);
        let text = |name: &str| -> Result<&str> { Ok(rec.get(col(name)?).unwrap_or("")) };
        let num = |name: &str| -> Result<f64> {
            let t = text(name)?;
            t.parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| inconsistent(file, line, format!("`{name}` = {t:?}: not a number")))
        };
        let flag = |name: &str| -> Result<bool> {
            match text(name)? {
                "1" => Ok(true),
                "0" => Ok(false),
                t => Err(inconsistent(
                    file,
                    line,
                    format!("`{name}` = {t:?}: not 1 or 0"),
                )),
            }
        };
        let mz = rec.get(max_z).unwrap_or("");
        let max_z = mz
            .parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| inconsistent(file, line, format!("`max_z` = {mz:?}: not a number")))?;
        let bounds_m = [
            [num("min_x")?, num("min_y")?, num("min_z")?],
            [num("max_x")?, num("max_y")?, max_z],
        ];
        if (0..3).any(|k| bounds_m[0][k] > bounds_m[1][k]) {
            return Err(inconsistent(
                file,
                line,
                "a bounding box minimum above its maximum".into(),
            ));
        }
        out.push(MemberVoid {
            volume_m3: num("volume_m3")?,
            survivable: flag("survivable")?,
            rescuer: flag("rescuer_access")?,
            camera: flag("camera_access")?,
            pattern: text("pattern")?.to_string(),
            centroid_m: [num("centroid_x")?, num("centroid_y")?, num("centroid_z")?],
            bounds_m,
            footprint_m: Vec::new(),
            rescuer_path_m: Vec::new(),
            camera_path_m: Vec::new(),
        });
    }
    Ok(out)
}

/// Reads one member's rescue files from its folder `dir`.
pub fn read_member(dir: &Path) -> Result<std::result::Result<MemberRescue, String>> {
    let jt = read(&dir.join("voids.json"))?;
    member_with(dir, &jt, &|| read(&dir.join("voids.csv")))
}

/// One member's rescue from the texts of its `voids.json` and `voids.csv` (as they are, or
/// are about to be, in its folder `dir`, which the messages name).
pub fn member_from_texts(
    dir: &Path,
    voids_json: &str,
    voids_csv: &str,
) -> Result<std::result::Result<MemberRescue, String>> {
    member_with(dir, voids_json, &|| Ok(voids_csv.to_string()))
}

fn member_with(
    dir: &Path,
    jt: &str,
    csv_text: &dyn Fn() -> Result<String>,
) -> Result<std::result::Result<MemberRescue, String>> {
    let jf = dir.join("voids.json");
    let js: Value = serde_json::from_str(jt)
        .map_err(|e| inconsistent(&jf, e.line(), format!("not JSON: {e}")))?;
    if let Some(e) = js.get("error") {
        return Ok(Err(e.as_str().unwrap_or("").to_string()));
    }
    let number = |v: Option<&Value>, what: &str| -> Result<f64> {
        v.and_then(Value::as_f64)
            .filter(|x| x.is_finite())
            .ok_or_else(|| inconsistent(&jf, 1, format!("`{what}`: not a number")))
    };
    let scale = number(js.get("scale"), "scale")?;
    if scale <= 0.0 {
        return Err(inconsistent(
            &jf,
            1,
            format!("`scale` = {scale}: not positive"),
        ));
    }
    // The grid's plan corner and cell, and its plan extent.
    let (plan, extent_m) = match js.get("grid") {
        None | Some(Value::Null) => (None, None),
        Some(g) => {
            let o = |k: usize| number(g.get("origin_m").and_then(|o| o.get(k)), "grid.origin_m");
            let n = |k: usize| number(g.get("cells").and_then(|o| o.get(k)), "grid.cells");
            let h = number(g.get("cell_m"), "grid.cell_m")?;
            let (ox, oy) = (o(0)?, o(1)?);
            (
                Some(([ox, oy], h)),
                Some([[ox, oy], [ox + n(0)? * h, oy + n(1)? * h]]),
            )
        }
    };
    let (max_height_m, mean_height_m) = match js.get("rubble") {
        None | Some(Value::Null) => (0.0, 0.0),
        Some(r) => (
            number(r.get("max_height_m"), "rubble.max_height_m")?,
            number(r.get("mean_height_m"), "rubble.mean_height_m")?,
        ),
    };
    let cf = dir.join("voids.csv");
    let mut voids = parse_voids_csv(&csv_text()?, &cf)?;
    let listed = js
        .get("voids")
        .and_then(Value::as_array)
        .map_or(&[][..], Vec::as_slice);
    if listed.len() != voids.len() {
        return Err(inconsistent(
            &jf,
            1,
            format!(
                "lists {} voids, {} has {}: the two are of different analyses",
                listed.len(),
                cf.display(),
                voids.len()
            ),
        ));
    }
    for (n, (v, j)) in voids.iter_mut().zip(listed).enumerate() {
        let Some((o, h)) = plan else {
            return Err(inconsistent(&jf, 1, "voids without a grid".into()));
        };
        let boxes = j.get("boxes").and_then(Value::as_array).ok_or_else(|| {
            inconsistent(
                &jf,
                1,
                format!(
                    "void {} has no `boxes` (its cells; the file is of an older analysis: \
                     `fem2rbd voids {}` writes it again)",
                    n + 1,
                    dir.display()
                ),
            )
        })?;
        let mut rects: Vec<[[u64; 2]; 2]> = Vec::with_capacity(boxes.len());
        for b in boxes {
            let k: Vec<u64> = b
                .as_array()
                .map(|a| a.iter().filter_map(Value::as_u64).collect())
                .unwrap_or_default();
            if k.len() != 6 || (0..3).any(|d| k[d] >= k[d + 3]) {
                return Err(inconsistent(
                    &jf,
                    1,
                    format!("void {}: box {b} is not 6 cell indices of a box", n + 1),
                ));
            }
            rects.push([[k[0], k[1]], [k[3], k[4]]]);
        }
        rects.sort_unstable();
        rects.dedup();
        v.footprint_m = rects
            .iter()
            .map(|r| r.map(|c| [o[0] + c[0] as f64 * h, o[1] + c[1] as f64 * h]))
            .collect();
        v.rescuer_path_m = plan_route(j, "rescuer", v.rescuer, n + 1, dir, &jf)?;
        v.camera_path_m = plan_route(j, "camera", v.camera, n + 1, dir, &jf)?;
    }
    Ok(Ok(MemberRescue {
        voids,
        extent_m,
        max_height_m,
        mean_height_m,
        scale,
    }))
}

/// The plan route (x, y of `path_m`) of `kind` (`rescuer`, `camera`) to void `number`,
/// the `voids.json` entry `void` of the member folder `dir` (the file `jf`), when
/// `voids.csv` says `kind` reaches it (`reached`); empty otherwise. A reached void
/// without its route (an older analysis) is refused naming the file.
fn plan_route(
    void: &Value,
    kind: &str,
    reached: bool,
    number: usize,
    dir: &Path,
    jf: &Path,
) -> Result<Vec<[f64; 2]>> {
    if !reached {
        return Ok(Vec::new());
    }
    let points = route_points(void, kind, number as u64)
        .map_err(|message| inconsistent(jf, 1, message))?
        .ok_or_else(|| {
            inconsistent(
                jf,
                1,
                format!(
                    "void {number} has no `{kind}.path_m` (its route; the file is of an older \
                     analysis: `fem2rbd voids {}` writes it again)",
                    dir.display()
                ),
            )
        })?;
    Ok(points.into_iter().map(|[x, y, _]| [x, y]).collect())
}

/// The member folders `member-NNN` of the ensemble folder `dir`, in member order, read.
pub fn read_members(dir: &Path) -> Result<Vec<Member>> {
    member_dirs(dir)?
        .into_iter()
        .map(|(name, path)| {
            Ok(Member {
                rescue: read_member(&path)?,
                name,
            })
        })
        .collect()
}

/// The member folders `member-NNN` of the ensemble folder `dir` (name, path), in member
/// order.
pub fn member_dirs(dir: &Path) -> Result<Vec<(String, PathBuf)>> {
    let entries = std::fs::read_dir(dir).map_err(|error| RunFolderError::Read {
        path: dir.to_path_buf(),
        error,
    })?;
    let mut found: Vec<(usize, String)> = Vec::new();
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        if let Some(k) = name
            .strip_prefix("member-")
            .and_then(|k| k.parse::<usize>().ok())
        {
            if e.path().is_dir() {
                found.push((k, name));
            }
        }
    }
    found.sort();
    Ok(found
        .into_iter()
        .map(|(_, name)| {
            let p = dir.join(&name);
            (name, p)
        })
        .collect())
}

/// Min, quartiles (type 7), mean and max of `v` (empty: all 0).
pub fn distribution(v: &[f64]) -> [f64; 6] {
    if v.is_empty() {
        return [0.0; 6];
    }
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    let q = |p: f64| {
        let h = p * (s.len() - 1) as f64;
        let (lo, hi) = (h.floor() as usize, h.ceil() as usize);
        s[lo] + (h - lo as f64) * (s[hi] - s[lo])
    };
    let mean = s.iter().sum::<f64>() / s.len() as f64;
    [s[0], q(0.25), q(0.5), q(0.75), mean, s[s.len() - 1]]
}

/// Intersection over union of two boxes (0 when either has no volume and they differ).
pub fn iou(a: &[[f64; 3]; 2], b: &[[f64; 3]; 2]) -> f64 {
    let vol =
        |lo: [f64; 3], hi: [f64; 3]| (0..3).map(|k| (hi[k] - lo[k]).max(0.0)).product::<f64>();
    let lo = [0, 1, 2].map(|k| a[0][k].max(b[0][k]));
    let hi = [0, 1, 2].map(|k| a[1][k].min(b[1][k]));
    let inter = vol(lo, hi);
    let union = vol(a[0], a[1]) + vol(b[0], b[1]) - inter;
    if union > 0.0 {
        inter / union
    } else if a == b {
        1.0
    } else {
        0.0
    }
}

/// A place where survivable voids of several members lie.
#[derive(Debug, Clone, PartialEq)]
pub struct Place {
    /// The bounding box of its first void, m.
    pub seed_bounds_m: [[f64; 3]; 2],
    /// (member index, the member's void) per member holding it, in member order.
    pub voids: Vec<(usize, MemberVoid)>,
}

/// The survivable voids of `members` matched to places (module docs), in order of first
/// appearance.
pub fn places(members: &[Member]) -> Vec<Place> {
    let mut out: Vec<Place> = Vec::new();
    for (m, member) in members.iter().enumerate() {
        let Ok(r) = &member.rescue else { continue };
        for v in r.voids.iter().filter(|v| v.survivable) {
            let best = out
                .iter()
                .enumerate()
                .filter(|(_, p)| p.voids.last().is_none_or(|(k, _)| *k != m))
                .map(|(i, p)| (i, iou(&p.seed_bounds_m, &v.bounds_m)))
                .filter(|(_, o)| *o >= MATCH_IOU)
                .fold(None::<(usize, f64)>, |b, (i, o)| match b {
                    Some((_, bo)) if bo >= o => b,
                    _ => Some((i, o)),
                });
            match best {
                Some((i, _)) => out[i].voids.push((m, v.clone())),
                None => out.push(Place {
                    seed_bounds_m: v.bounds_m,
                    voids: vec![(m, v.clone())],
                }),
            }
        }
    }
    out
}

/// The plan map's grid: lower corner, cell edge, counts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlanGrid {
    /// Lower corner, m.
    pub origin_m: [f64; 2],
    /// Cell edge, m.
    pub cell_m: f64,
    /// Cells along x and y.
    pub n: [usize; 2],
}

impl PlanGrid {
    /// The centre of cell (i, j), m.
    pub fn centre(&self, i: usize, j: usize) -> [f64; 2] {
        [
            self.origin_m[0] + (i as f64 + 0.5) * self.cell_m,
            self.origin_m[1] + (j as f64 + 0.5) * self.cell_m,
        ]
    }

    /// The closed square of cell (i, j): ([min x, min y], [max x, max y]), m.
    pub fn square(&self, i: usize, j: usize) -> [[f64; 2]; 2] {
        let lo = |k: usize, c: usize| self.origin_m[k] + c as f64 * self.cell_m;
        [[lo(0, i), lo(1, j)], [lo(0, i + 1), lo(1, j + 1)]]
    }

    /// The cells (row-major index `j · n[0] + i`, ascending) whose closed squares the
    /// segment `a`–`b` (m; `a == b`: a point) meets ([`segment_meets_square`]). Only the
    /// cells whose squares meet the segment's bounding box are tried.
    pub fn cells_met(&self, a: [f64; 2], b: [f64; 2]) -> Vec<usize> {
        // Cell c's square [o + c·h, o + (c+1)·h] meets [lo, hi] when
        // (lo − o)/h − 1 ≤ c ≤ (hi − o)/h; one cell of slack each way against rounding,
        // the exact test decides.
        let range = |k: usize| {
            let lo = a[k].min(b[k]);
            let hi = a[k].max(b[k]);
            let c0 = ((lo - self.origin_m[k]) / self.cell_m).floor() - 2.0;
            let c1 = ((hi - self.origin_m[k]) / self.cell_m).floor() + 1.0;
            let top = self.n[k] as f64 - 1.0;
            (c0.max(0.0), c1.min(top))
        };
        let ((i0, i1), (j0, j1)) = (range(0), range(1));
        let mut out = Vec::new();
        if i0 > i1 || j0 > j1 {
            return out;
        }
        for j in j0 as usize..=j1 as usize {
            for i in i0 as usize..=i1 as usize {
                if segment_meets_square(a, b, self.square(i, j)) {
                    out.push(j * self.n[0] + i);
                }
            }
        }
        out
    }
}

/// Whether the closed segment `a`–`b` meets the closed square `sq` ([min x, min y],
/// [max x, max y]), m: some `p(t) = a + t (b − a)`, `0 ≤ t ≤ 1`, has
/// `min ≤ p ≤ max` along x and y (bounds included). Clipped slab by slab
/// (Liang & Barsky 1984, "A new concept and method for line clipping", ACM Trans.
/// Graphics 3(1) 1–22): along an axis the segment moves along, the slab keeps
/// `t` between `(min − a)/d` and `(max − a)/d`; along one it does not move, `a` must lie
/// in the slab; the segment meets the square when the kept ranges of `t` overlap.
pub fn segment_meets_square(a: [f64; 2], b: [f64; 2], sq: [[f64; 2]; 2]) -> bool {
    let (mut t0, mut t1) = (0.0_f64, 1.0_f64);
    for k in 0..2 {
        let d = b[k] - a[k];
        if d == 0.0 {
            if a[k] < sq[0][k] || a[k] > sq[1][k] {
                return false;
            }
        } else {
            let (u, v) = ((sq[0][k] - a[k]) / d, (sq[1][k] - a[k]) / d);
            t0 = t0.max(u.min(v));
            t1 = t1.min(u.max(v));
            if t0 > t1 {
                return false;
            }
        }
    }
    true
}

/// Member counts per map cell, row-major (j, then i).
#[derive(Debug, Clone, PartialEq)]
pub struct CellCounts {
    /// Members with a void beneath.
    pub void: Vec<usize>,
    /// Members with a survivable void beneath.
    pub survivable: Vec<usize>,
    /// Members with a survivable void the rescuer reaches beneath.
    pub rescuer: Vec<usize>,
    /// Members with a survivable void the camera reaches beneath.
    pub camera: Vec<usize>,
    /// Members in which the rescuer's route to a survivable void passes over the cell.
    pub rescuer_route: Vec<usize>,
    /// Members in which the camera's route to a survivable void passes over the cell.
    pub camera_route: Vec<usize>,
    /// Members in which the rescuer's route to a survivable void leaves open air in the
    /// cell.
    pub rescuer_entry: Vec<usize>,
    /// Members in which the camera's route to a survivable void leaves open air in the
    /// cell.
    pub camera_entry: Vec<usize>,
}

/// The ensemble's rescue maps and statistics.
#[derive(Debug, Clone, PartialEq)]
pub struct Maps {
    /// The members, in order.
    pub members: Vec<Member>,
    /// The model's scale (1 when no member is analysed).
    pub scale: f64,
    /// The plan grid (`None`: no analysed member has a grid).
    pub grid: Option<PlanGrid>,
    /// Counts per cell.
    pub counts: CellCounts,
    /// The places of survivable voids.
    pub places: Vec<Place>,
}

/// The maps of `members` (all analysed members must share one scale; `file` names the
/// ensemble folder in that error).
pub fn maps(members: Vec<Member>, folder: &Path) -> Result<Maps> {
    let analysed: Vec<&MemberRescue> = members
        .iter()
        .filter_map(|m| m.rescue.as_ref().ok())
        .collect();
    let scale = analysed.first().map_or(1.0, |r| r.scale);
    if let Some((m, r)) = members
        .iter()
        .filter_map(|m| m.rescue.as_ref().ok().map(|r| (m, r)))
        .find(|(_, r)| r.scale != scale)
    {
        return Err(inconsistent(
            &folder.join(&m.name).join("voids.json"),
            1,
            format!("scale {} differs from the first member's {scale}", r.scale),
        ));
    }
    let extents: Vec<[[f64; 2]; 2]> = analysed.iter().filter_map(|r| r.extent_m).collect();
    let grid = (!extents.is_empty()).then(|| {
        let lo = [0, 1].map(|k| {
            extents
                .iter()
                .map(|e| e[0][k])
                .fold(f64::INFINITY, f64::min)
        });
        let hi = [0, 1].map(|k| {
            extents
                .iter()
                .map(|e| e[1][k])
                .fold(f64::NEG_INFINITY, f64::max)
        });
        let h = MAP_CELL_M * scale;
        // A span that is a whole number of cells to rounding needs no extra cell.
        let n = [0, 1].map(|k| (((hi[k] - lo[k]) / h - 1e-9).ceil() as usize).max(1));
        PlanGrid {
            origin_m: lo,
            cell_m: h,
            n,
        }
    });
    let cells = grid.map_or(0, |g| g.n[0] * g.n[1]);
    let mut counts = CellCounts {
        void: vec![0; cells],
        survivable: vec![0; cells],
        rescuer: vec![0; cells],
        camera: vec![0; cells],
        rescuer_route: vec![0; cells],
        camera_route: vec![0; cells],
        rescuer_entry: vec![0; cells],
        camera_entry: vec![0; cells],
    };
    if let Some(g) = grid {
        for r in &analysed {
            let mut under = [
                vec![false; cells],
                vec![false; cells],
                vec![false; cells],
                vec![false; cells],
            ];
            for v in &r.voids {
                let kinds = [
                    true,
                    v.survivable,
                    v.survivable && v.rescuer,
                    v.survivable && v.camera,
                ];
                for rect in &v.footprint_m {
                    // The cells whose centres lie in the rectangle:
                    // x_c = x0 + (i + ½) h ∈ [min, max].
                    let range = |k: usize| {
                        let a = ((rect[0][k] - g.origin_m[k]) / g.cell_m - 0.5)
                            .ceil()
                            .max(0.0) as usize;
                        let b = ((rect[1][k] - g.origin_m[k]) / g.cell_m - 0.5).floor();
                        (
                            a,
                            if b < 0.0 {
                                None
                            } else {
                                Some((b as usize).min(g.n[k] - 1))
                            },
                        )
                    };
                    let ((i0, i1), (j0, j1)) = (range(0), range(1));
                    let (Some(i1), Some(j1)) = (i1, j1) else {
                        continue;
                    };
                    for j in j0..=j1 {
                        for i in i0..=i1 {
                            for (u, on) in under.iter_mut().zip(kinds) {
                                u[j * g.n[0] + i] |= on;
                            }
                        }
                    }
                }
            }
            // The routes: [rescuer over, camera over, rescuer entry, camera entry].
            let mut routed = [
                vec![false; cells],
                vec![false; cells],
                vec![false; cells],
                vec![false; cells],
            ];
            for v in r.voids.iter().filter(|v| v.survivable) {
                for (k, path) in [&v.rescuer_path_m, &v.camera_path_m]
                    .into_iter()
                    .enumerate()
                {
                    for s in path.windows(2) {
                        for c in g.cells_met(s[0], s[1]) {
                            routed[k][c] = true;
                        }
                    }
                    if let Some(&p) = path.first() {
                        for c in g.cells_met(p, p) {
                            routed[k + 2][c] = true;
                        }
                    }
                }
            }
            for (c, u) in [
                &mut counts.void,
                &mut counts.survivable,
                &mut counts.rescuer,
                &mut counts.camera,
                &mut counts.rescuer_route,
                &mut counts.camera_route,
                &mut counts.rescuer_entry,
                &mut counts.camera_entry,
            ]
            .into_iter()
            .zip(under.iter().chain(&routed))
            {
                for (c, u) in c.iter_mut().zip(u) {
                    *c += usize::from(*u);
                }
            }
        }
    }
    let places = places(&members);
    Ok(Maps {
        members,
        scale,
        grid,
        counts,
        places,
    })
}

/// Rounded to 6 decimals (−0 as 0).
fn r6(x: f64) -> f64 {
    (x * 1e6).round() / 1e6 + 0.0
}

/// `rescue_map.csv` header.
pub const MAP_HEADER: &str =
    "i,j,x,y,p_void,p_survivable,p_survivable_rescuer,p_survivable_camera,\
p_route_rescuer,p_route_camera,p_entry_rescuer,p_entry_camera";

impl Maps {
    /// The analysed members' analyses.
    fn analysed(&self) -> Vec<&MemberRescue> {
        self.members
            .iter()
            .filter_map(|m| m.rescue.as_ref().ok())
            .collect()
    }

    /// The probability of `count` members among the analysed ones (0 without any).
    fn p(&self, count: usize) -> f64 {
        let n = self.analysed().len();
        if n == 0 {
            0.0
        } else {
            count as f64 / n as f64
        }
    }

    /// The `rescue_map.csv` text: one row per plan cell, j then i (columns in
    /// docs/rescue.md §6).
    pub fn map_csv(&self) -> String {
        let mut s = String::from(MAP_HEADER);
        s.push('\n');
        let n = self.analysed().len().max(1) as f64;
        if let Some(g) = self.grid {
            for j in 0..g.n[1] {
                for i in 0..g.n[0] {
                    let k = j * g.n[0] + i;
                    let c = g.centre(i, j);
                    let p = |x: usize| r6(x as f64 / n);
                    let _ = writeln!(
                        s,
                        "{i},{j},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6}",
                        r6(c[0]),
                        r6(c[1]),
                        p(self.counts.void[k]),
                        p(self.counts.survivable[k]),
                        p(self.counts.rescuer[k]),
                        p(self.counts.camera[k]),
                        p(self.counts.rescuer_route[k]),
                        p(self.counts.camera_route[k]),
                        p(self.counts.rescuer_entry[k]),
                        p(self.counts.camera_entry[k]),
                    );
                }
            }
        }
        s
    }

    /// The `rescue.json` value.
    pub fn json(&self) -> Value {
        let analysed = self.analysed();
        let dist = |f: &dyn Fn(&MemberRescue) -> f64| {
            let v: Vec<f64> = analysed.iter().map(|r| f(r)).collect();
            let d = distribution(&v);
            json!({"min": r6(d[0]), "p25": r6(d[1]), "median": r6(d[2]), "p75": r6(d[3]),
                   "mean": r6(d[4]), "max": r6(d[5])})
        };
        fn surv(r: &MemberRescue) -> impl Iterator<Item = &MemberVoid> {
            r.voids.iter().filter(|v| v.survivable)
        }
        let places: Vec<Value> = {
            let mut order: Vec<usize> = (0..self.places.len()).collect();
            order.sort_by_key(|&i| std::cmp::Reverse(self.places[i].voids.len()));
            order
                .into_iter()
                .map(|i| {
                    let p = &self.places[i];
                    let k = p.voids.len() as f64;
                    let mut patterns = Map::new();
                    let mut counted: BTreeMap<&str, usize> = BTreeMap::new();
                    for (_, v) in &p.voids {
                        *counted.entry(v.pattern.as_str()).or_default() += 1;
                    }
                    for (name, c) in counted {
                        patterns.insert(name.to_string(), json!(c));
                    }
                    let vols: Vec<f64> = p.voids.iter().map(|(_, v)| v.volume_m3).collect();
                    let mean_c = [0, 1, 2].map(|a| r6(p.voids.iter().map(|(_, v)| v.centroid_m[a]).sum::<f64>() / k));
                    json!({
                        "members": p.voids.len(),
                        "probability": r6(self.p(p.voids.len())),
                        "recurs": p.voids.len() >= 2,
                        "member_folders": p.voids.iter().map(|(m, _)| self.members[*m].name.clone()).collect::<Vec<_>>(),
                        "volume_m3": {"mean": r6(vols.iter().sum::<f64>() / k),
                                      "min": r6(vols.iter().copied().fold(f64::INFINITY, f64::min)),
                                      "max": r6(vols.iter().copied().fold(f64::NEG_INFINITY, f64::max))},
                        "mean_centroid_m": mean_c,
                        "first_bounds_m": [p.seed_bounds_m[0].map(r6), p.seed_bounds_m[1].map(r6)],
                        "patterns": Value::Object(patterns),
                        "rescuer_reaches": p.voids.iter().filter(|(_, v)| v.rescuer).count(),
                        "camera_reaches": p.voids.iter().filter(|(_, v)| v.camera).count(),
                    })
                })
                .collect()
        };
        json!({
            "members": self.members.len(),
            "members_analysed": analysed.len(),
            "not_analysed": self.members.iter().filter_map(|m| m.rescue.as_ref().err().map(|e| json!({"member": m.name, "error": e}))).collect::<Vec<_>>(),
            "scale": self.scale,
            "map": {
                "file": FILES[0],
                "cell_full_scale_m": MAP_CELL_M,
                "cell_m": self.grid.map(|g| r6(g.cell_m)),
                "origin_m": self.grid.map(|g| g.origin_m.map(r6)),
                "cells": self.grid.map(|g| g.n),
                "beneath": "the cell's centre lies in the plan of the void's cells (its boxes' plan rectangles, bounds included)",
                "route_over": "a segment of the plan polyline of the route (path_m) to a survivable void meets the cell's closed square",
                "entry": "the route's first point (where it leaves open air) lies in the cell's closed square",
            },
            "distributions": {
                "voids_count": dist(&|r| r.voids.len() as f64),
                "survivable_count": dist(&|r| surv(r).count() as f64),
                "survivable_volume_m3": dist(&|r| surv(r).map(|v| v.volume_m3).sum()),
                "rescuer_reachable_survivable": dist(&|r| surv(r).filter(|v| v.rescuer).count() as f64),
                "max_height_m": dist(&|r| r.max_height_m),
                "mean_height_m": dist(&|r| r.mean_height_m),
            },
            "match": {"by": "3-D bounding boxes of survivable voids, intersection over union against a place's first void", "iou_at_least": MATCH_IOU},
            "places": places,
        })
    }

    /// The two files (name, bytes), in [`FILES`] order.
    pub fn files(&self) -> Vec<(&'static str, Vec<u8>)> {
        let js = serde_json::to_string_pretty(&self.json()).expect("a JSON value") + "\n";
        vec![
            (FILES[0], self.map_csv().into_bytes()),
            (FILES[1], js.into_bytes()),
        ]
    }
}

/// Reads the members of the ensemble folder `dir` and writes `rescue_map.csv` and
/// `rescue.json` into it, each atomically, after both are built; returns their paths.
pub fn write_maps(dir: &Path) -> Result<Vec<PathBuf>> {
    let maps = maps(read_members(dir)?, dir)?;
    let mut out = Vec::new();
    for (name, bytes) in maps.files() {
        let p = dir.join(name);
        crate::output::write_atomic(&p, &bytes)?;
        out.push(p);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quartiles_interpolate_between_order_statistics() {
        // Type 7 of 1, 2, 4, 10: h = 0.75 → 1.75; h = 1.5 → 3; h = 2.25 → 5.5.
        assert_eq!(
            distribution(&[10.0, 1.0, 4.0, 2.0]),
            [1.0, 1.75, 3.0, 5.5, 4.25, 10.0]
        );
        assert_eq!(distribution(&[3.0]), [3.0; 6]);
    }

    #[test]
    fn overlap_of_boxes_shifted_by_a_third_is_one_half() {
        let a = [[0.0, 0.0, 0.0], [3.0, 1.0, 1.0]];
        let b = [[1.0, 0.0, 0.0], [4.0, 1.0, 1.0]];
        assert!((iou(&a, &b) - 0.5).abs() < 1e-12);
        assert_eq!(iou(&a, &a), 1.0);
        assert_eq!(iou(&a, &[[5.0, 0.0, 0.0], [6.0, 1.0, 1.0]]), 0.0);
    }

    /// A 4 × 3 grid of unit cells from (0, 0).
    fn grid() -> PlanGrid {
        PlanGrid {
            origin_m: [0.0, 0.0],
            cell_m: 1.0,
            n: [4, 3],
        }
    }

    #[test]
    fn a_segment_meets_a_square_with_its_bounds() {
        let sq = [[0.0, 0.0], [1.0, 1.0]];
        // Across, inside, along an edge, through a corner, a point on the edge.
        assert!(segment_meets_square([-1.0, 0.5], [2.0, 0.5], sq));
        assert!(segment_meets_square([0.2, 0.2], [0.3, 0.4], sq));
        assert!(segment_meets_square([-1.0, 1.0], [3.0, 1.0], sq));
        assert!(segment_meets_square([2.0, -1.0], [0.0, 1.0], sq));
        assert!(segment_meets_square([1.0, 0.5], [1.0, 0.5], sq));
        // Past the corner by 0.1 (the line x + y = 2.1), short of the square, beside it.
        assert!(!segment_meets_square([2.1, 0.0], [0.0, 2.1], sq));
        assert!(!segment_meets_square([-2.0, 0.5], [-0.1, 0.5], sq));
        assert!(!segment_meets_square([1.5, -1.0], [1.5, 2.0], sq));
    }

    #[test]
    fn the_cells_a_segment_passes_over() {
        let g = grid();
        // Along y = 0.5 from x = 0.5 to 2.5: cells (0..=2, 0).
        assert_eq!(g.cells_met([0.5, 0.5], [2.5, 0.5]), [0, 1, 2]);
        // Along the edge y = 1 from x = 0.5 to 1.5: both rows, columns 0 and 1.
        assert_eq!(g.cells_met([0.5, 1.0], [1.5, 1.0]), [0, 1, 4, 5]);
        // The diagonal (0.5, 0.5)–(2.5, 2.5) passes through the corners (1, 1) and (2, 2):
        // the cells on the diagonal and the four beside the corners it touches.
        assert_eq!(g.cells_met([0.5, 0.5], [2.5, 2.5]), [0, 1, 4, 5, 6, 9, 10]);
        // A point on a corner: the four cells round it; inside a cell: that cell.
        assert_eq!(g.cells_met([2.0, 1.0], [2.0, 1.0]), [1, 2, 5, 6]);
        assert_eq!(g.cells_met([3.5, 2.5], [3.5, 2.5]), [11]);
        // Outside the grid: none; entering it: the cells inside only.
        assert!(g.cells_met([-3.0, -1.0], [-1.0, -0.5]).is_empty());
        assert_eq!(g.cells_met([-5.0, 2.5], [0.5, 2.5]), [8]);
    }
}

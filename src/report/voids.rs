//! The voids of the final ruin in the report (`RUN_DIR/voids.json` and `voids.csv` of
//! `fem2rbd voids` or `run`, docs/rescue.md): the data the page draws them from, the
//! voids table and the rescue rows of the key figures.
//!
//! Each void is drawn as its exact cells: the disjoint boxes of whole cells of
//! `voids.json` (`boxes`, [`crate::rescue::boxes`]), one translucent instanced mesh per
//! void (an instance per box) in its pattern's colour (the colours of the void figures,
//! [`crate::output::palette::pattern_srgb`]), opaque to [`VOID_OPACITY`] when survivable and
//! to [`OTHER_OPACITY`] when not. A survivable void the rescuer reaches has its route drawn
//! as a black line (`voids.json` `rescuer.path_m`, [`crate::rescue::route`]) and a post
//! standing where the route leaves open air (as in the figures; without a route in
//! `voids.json`, on the middle of the side of its bounding box the route enters through);
//! a survivable void only the camera reaches has the camera's route as a grey line; a
//! survivable void the rescuer reaches only through debris has a cube on the first debris
//! cell to breach.
//!
//! A run folder without `voids.json` (no ruin stage, or written before the analysis
//! existed) or whose `voids.json` records an error gets a page that says so. When
//! `voids.json` exists, `voids.csv` must too, with one row per void.
use super::data::hex;
use super::html::escape;
use super::{inconsistent, ReportError, Result};
use crate::output::palette::pattern_srgb;
use serde::Deserialize;
use serde_json::{json, Value};
use std::fmt::Write as _;
use std::path::Path;

/// Fill opacity of a survivable void (that of the void figures).
pub const VOID_OPACITY: f64 = crate::plot::voids::VOID_OPACITY;

/// Fill opacity of a void no adult fits in.
pub const OTHER_OPACITY: f64 = 0.12;

/// The access of a void in `voids.json`.
#[derive(Debug, Clone, Deserialize)]
pub struct Reach {
    /// Reached.
    pub reached: bool,
    /// Crawl length under debris, m.
    #[serde(default)]
    pub route_m: Option<f64>,
    /// Entry side.
    #[serde(default)]
    pub entry: Option<String>,
    /// The route as a line, m (`None`: not reached, or a `voids.json` without routes).
    #[serde(default)]
    pub path_m: Option<Vec<[f64; 3]>>,
}

/// The breach of a void in `voids.json`.
#[derive(Debug, Clone, Deserialize)]
pub struct Breach {
    /// Least debris thickness, m.
    pub thickness_m: f64,
    /// The first cell to cut, m.
    pub at_m: Option<[f64; 3]>,
    /// Its side.
    pub side: String,
}

/// One void of `voids.json`, the fields the report shows.
#[derive(Debug, Clone, Deserialize)]
pub struct ReportVoid {
    /// Number, 1 = largest.
    pub void: usize,
    /// Volume, m³.
    pub volume_m3: f64,
    /// Clear height, m.
    pub clear_height_m: f64,
    /// Inscribed radius, m.
    pub inscribed_radius_m: f64,
    /// A lying adult fits.
    pub lying_fits: bool,
    /// A sitting adult fits.
    pub sitting_fits: bool,
    /// Survivable.
    pub survivable: bool,
    /// Pattern name.
    pub pattern: String,
    /// Roof bodies, most cells first.
    pub roof_bodies: Vec<String>,
    /// Bounding box, m.
    pub bounds_m: [[f64; 3]; 2],
    /// Rescuer access.
    pub rescuer: Reach,
    /// Camera access.
    pub camera: Reach,
    /// The least breach.
    pub breach: Breach,
    /// Its cells as boxes `[i0, j0, k0, i1, j1, k1]`.
    pub boxes: Vec<[usize; 6]>,
}

/// The grid of `voids.json`.
#[derive(Debug, Clone, Deserialize)]
pub struct VoidGrid {
    /// Corner of cell (0, 0, 0), m.
    pub origin_m: [f64; 3],
    /// Cell edge, m.
    pub cell_m: f64,
    /// Cells along x, y, z.
    pub cells: [usize; 3],
}

/// The analysed `voids.json`, the parts the report uses.
#[derive(Debug, Clone, Deserialize)]
pub struct Analysed {
    /// The grid (`None`: no debris).
    pub grid: Option<VoidGrid>,
    /// Voids.
    pub voids_count: usize,
    /// Survivable voids.
    pub survivable_count: usize,
    /// Their volume, m³.
    pub survivable_volume_m3: f64,
    /// Survivable voids the rescuer reaches.
    pub rescuer_reachable_survivable: usize,
    /// Survivable voids the camera reaches.
    pub camera_reachable_survivable: usize,
    /// The rubble measures (`None` without debris).
    pub rubble: Option<Value>,
    /// The voids, largest first.
    pub voids: Vec<ReportVoid>,
}

/// The rescue analysis of a run folder as the report finds it.
#[derive(Debug, Clone)]
pub enum RunVoids {
    /// No `voids.json`.
    Missing,
    /// `voids.json` records why the analysis did not run.
    Failed(String),
    /// The analysis.
    Analysed(Box<Analysed>),
}

/// Reads `dir/voids.json` (and checks `dir/voids.csv` against it).
pub fn load(dir: &Path) -> Result<RunVoids> {
    let path = dir.join("voids.json");
    let read = crate::model::limits::read_optional_regular_file(&path);
    let Some(text) = read.map_err(|error| ReportError::Read {
        path: path.clone(),
        error,
    })?
    else {
        return Ok(RunVoids::Missing);
    };
    let value: Value =
        serde_json::from_str(&text).map_err(|e| inconsistent(&path, format!("not JSON: {e}")))?;
    if let Some(e) = value.get("error") {
        return Ok(RunVoids::Failed(e.as_str().unwrap_or_default().to_string()));
    }
    let a: Analysed = serde_json::from_value(value)
        .map_err(|e| inconsistent(&path, format!("not a rescue analysis: {e}")))?;
    if a.voids.len() != a.voids_count {
        return Err(inconsistent(
            &path,
            format!(
                "voids_count = {} but {} voids listed",
                a.voids_count,
                a.voids.len()
            ),
        ));
    }
    for (n, v) in a.voids.iter().enumerate() {
        let Some(g) = &a.grid else {
            return Err(inconsistent(&path, "voids without a grid"));
        };
        if v.void != n + 1 {
            return Err(inconsistent(
                &path,
                format!("void {} listed as number {}", n + 1, v.void),
            ));
        }
        if v.boxes.is_empty() {
            return Err(inconsistent(
                &path,
                format!(
                    "void {} has no boxes (cells); `fem2rbd voids RUN_DIR` writes them",
                    v.void
                ),
            ));
        }
        for b in &v.boxes {
            if (0..3).any(|d| b[d] >= b[d + 3] || b[d + 3] > g.cells[d]) {
                return Err(inconsistent(
                    &path,
                    format!(
                        "void {}: box {b:?} is empty or outside the grid {:?}",
                        v.void, g.cells
                    ),
                ));
            }
        }
    }
    let csv = dir.join("voids.csv");
    let rows = crate::model::limits::read_regular_file(&csv)
        .map_err(|error| ReportError::Read {
            path: csv.clone(),
            error,
        })?
        .lines()
        .skip(1)
        .filter(|l| !l.is_empty())
        .count();
    if rows != a.voids_count {
        return Err(inconsistent(
            &csv,
            format!(
                "{rows} rows but voids.json lists {} voids: the two are of different analyses (`fem2rbd voids RUN_DIR` writes both)",
                a.voids_count
            ),
        ));
    }
    Ok(RunVoids::Analysed(Box::new(a)))
}

/// The point of `v`'s rescuer marker, when the rescuer reaches it: where its route leaves
/// open air (the route's first point), or without a route the middle of the side of its
/// bounding box the route enters through (`x-`: the −x side, …, `top`: the top).
pub fn entry_point(v: &ReportVoid) -> Option<[f64; 3]> {
    let e = v.rescuer.entry.as_deref().filter(|_| v.rescuer.reached)?;
    if let Some(p) = v.rescuer.path_m.as_ref().and_then(|p| p.first()) {
        return Some(*p);
    }
    Some(crate::plot::voids::entry_side_point(v.bounds_m, e))
}

/// The route line the page draws for `v` (flat x, y, z triples), with whose it is: the
/// rescuer's to a survivable void it reaches, else the camera's to a survivable void the
/// camera reaches; `None` otherwise or without a route in `voids.json`.
pub fn route_line(v: &ReportVoid) -> Option<(&'static str, Vec<f64>)> {
    if !v.survivable {
        return None;
    }
    let (who, reach) = if v.rescuer.reached {
        ("rescuer", &v.rescuer)
    } else if v.camera.reached {
        ("camera", &v.camera)
    } else {
        return None;
    };
    let p = reach.path_m.as_ref()?;
    Some((who, p.iter().flatten().copied().collect()))
}

fn pattern_hex(p: &str) -> String {
    hex(pattern_srgb(p))
}

/// The page data of the voids (`voids` of the page data; `null` without an analysis):
/// the grid, per void its number, pattern, colour, opacity, survivable, boxes (flat, 6
/// per box), the rescuer's entry marker and the breach marker (survivable voids only);
/// the legend of the patterns present.
pub fn page_data(voids: &RunVoids) -> Value {
    let RunVoids::Analysed(a) = voids else {
        return Value::Null;
    };
    let Some(g) = &a.grid else {
        return Value::Null;
    };
    let mut patterns: Vec<&str> = crate::plot::voids::PATTERNS
        .iter()
        .copied()
        .filter(|p| a.voids.iter().any(|v| v.pattern == *p))
        .collect();
    for v in &a.voids {
        if !patterns.contains(&v.pattern.as_str()) {
            patterns.push(&v.pattern);
        }
    }
    json!({
        "origin": g.origin_m,
        "cell": g.cell_m,
        "opacity": {"survivable": VOID_OPACITY, "other": OTHER_OPACITY},
        "patterns": patterns.iter().map(|p| json!({"name": p, "colour": pattern_hex(p)})).collect::<Vec<_>>(),
        "list": a.voids.iter().map(|v| json!({
            "void": v.void,
            "pattern": v.pattern,
            "colour": pattern_hex(&v.pattern),
            "survivable": v.survivable,
            "boxes": v.boxes.iter().flatten().collect::<Vec<_>>(),
            "entry": if v.survivable { entry_point(v) } else { None },
            "route": route_line(v).map(|(who, points)| json!({"who": who, "points": points})),
            "breach": if v.survivable && !v.rescuer.reached && v.breach.thickness_m > 0.0 {
                v.breach.at_m
            } else {
                None
            },
        })).collect::<Vec<_>>(),
    })
}

fn access_text(r: &Reach) -> String {
    match (r.reached, r.route_m, r.entry.as_deref()) {
        (true, Some(m), Some(e)) => format!("from {e}, {m:.3} m"),
        (true, _, _) => "yes".into(),
        (false, _, _) => "no".into(),
    }
}

/// The voids section's HTML: the table (`<table id="void-table">`, row `id="void-N"`,
/// `data-void="N"`), or a sentence saying why there is none.
pub fn section(voids: &RunVoids) -> String {
    let a = match voids {
        RunVoids::Missing => {
            return r#"<p class="note" id="voids-none">No rescue analysis: the run folder has no <code>voids.json</code> (it is written by <code>fem2rbd run</code> when a ruin stage ran, and by <code>fem2rbd voids RUN_DIR</code>).</p>"#.to_string();
        }
        RunVoids::Failed(e) => {
            return format!(
                r#"<p class="note" id="voids-none">No voids: the rescue analysis did not run ({}).</p>"#,
                escape(e)
            );
        }
        RunVoids::Analysed(a) => a,
    };
    if a.voids.is_empty() {
        return r#"<p class="note" id="voids-none">The rescue analysis found no void: no free space under debris (<code>voids.json</code>).</p>"#.to_string();
    }
    let mut s = format!(
        r#"<p class="note">{} voids (free space under one roof each), {} survivable (a lying or sitting adult fits), from <code>voids.json</code> and <code>voids.csv</code>. Each is drawn at the final ruin as its cells (boxes of whole {:.3} m cells), in its pattern's colour, fainter when no adult fits; the rescuer's route to a survivable void is a black line from a black post where it leaves open air (the camera's, where only the camera gets in, a grey line), a red cube marks the first debris to breach where neither reaches one. Click a row or a void to pick it.</p>
<details open><summary>voids, largest first</summary>
<table id="void-table"><thead><tr><th>void</th><th>pattern</th><th>volume (m³)</th><th>clear height (m)</th><th>inscribed radius (m)</th><th>survivable</th><th>rescuer</th><th>camera</th><th>breach (m)</th><th>roof</th></tr></thead><tbody>"#,
        a.voids_count,
        a.survivable_count,
        a.grid.as_ref().map_or(0.0, |g| g.cell_m),
    );
    for v in &a.voids {
        let fits = match (v.lying_fits, v.sitting_fits) {
            (true, true) => "yes (lying, sitting)",
            (true, false) => "yes (lying)",
            (false, true) => "yes (sitting)",
            (false, false) => "no",
        };
        let _ = write!(
            s,
            r#"<tr id="void-{n}" data-void="{n}"><td>{n}</td><td><span class="swatch" style="background:{c}"></span>{p}</td><td>{:.4}</td><td>{:.3}</td><td>{:.3}</td><td>{fits}</td><td>{}</td><td>{}</td><td>{:.3}</td><td>{}</td></tr>"#,
            v.volume_m3,
            v.clear_height_m,
            v.inscribed_radius_m,
            escape(&access_text(&v.rescuer)),
            escape(&access_text(&v.camera)),
            v.breach.thickness_m,
            escape(v.roof_bodies.first().map_or("", |r| r.as_str())),
            n = v.void,
            c = pattern_hex(&v.pattern),
            p = escape(&v.pattern),
        );
    }
    s.push_str("</tbody></table></details>");
    s
}

/// The rescue rows of the key figures: (key, label, text, value).
pub fn figure_rows(voids: &RunVoids) -> Vec<(String, String, String, Option<f64>)> {
    let mut r = Vec::new();
    let a = match voids {
        RunVoids::Missing => return r,
        RunVoids::Failed(e) => {
            r.push((
                "rescue.voids_count".into(),
                "Voids".into(),
                format!("not analysed: {e}"),
                None,
            ));
            return r;
        }
        RunVoids::Analysed(a) => a,
    };
    r.push((
        "rescue.voids_count".into(),
        "Voids".into(),
        format!(
            "{} voids, {} survivable ({:.4} m³ together); the rescuer reaches {} and the camera {} of the survivable ones",
            a.voids_count,
            a.survivable_count,
            a.survivable_volume_m3,
            a.rescuer_reachable_survivable,
            a.camera_reachable_survivable
        ),
        Some(a.voids_count as f64),
    ));
    r.push((
        "rescue.survivable_count".into(),
        "Survivable voids".into(),
        a.survivable_count.to_string(),
        Some(a.survivable_count as f64),
    ));
    r.push((
        "rescue.survivable_volume_m3".into(),
        "Survivable void volume".into(),
        format!("{:.4} m³", a.survivable_volume_m3),
        Some(a.survivable_volume_m3),
    ));
    if let Some(rb) = &a.rubble {
        let num = |k: &str| rb.get(k).and_then(Value::as_f64);
        if let (Some(max), Some(mean)) = (num("max_height_m"), num("mean_height_m")) {
            r.push((
                "rescue.pile_max_height_m".into(),
                "Rubble pile height".into(),
                format!("max {max:.3} m, mean {mean:.3} m over the debris"),
                Some(max),
            ));
        }
        let side = |k: &str, w: &str| {
            rb.get(k)
                .and_then(|e| e.get(w))
                .and_then(Value::as_f64)
                .unwrap_or(f64::NAN)
        };
        if let Some(h) = num("building_height_m") {
            let sides = ["x_minus", "x_plus", "y_minus", "y_plus"];
            let worst = sides
                .iter()
                .map(|w| side("extent_over_height", w))
                .fold(f64::NEG_INFINITY, f64::max);
            r.push((
                "rescue.extent_over_height".into(),
                "Debris extent / building height".into(),
                format!(
                    "{} (building height {h:.3} m; planning rule {:.2})",
                    sides
                        .iter()
                        .zip(["x−", "x+", "y−", "y+"])
                        .map(|(w, l)| format!(
                            "{l} {:.3} m = {:.2}",
                            side("extent_m", w),
                            side("extent_over_height", w)
                        ))
                        .collect::<Vec<_>>()
                        .join(", "),
                    num("planning_reach_over_height").unwrap_or(f64::NAN)
                ),
                Some(worst),
            ));
        }
    }
    r
}

//! The rescue map of an ensemble in its report (`rescue_map.csv` and `rescue.json` of
//! [`crate::rescue::ensemble`], docs/rescue.md §6): per plan cell, the share of the
//! analysed members with a survivable void beneath it (and with one the rescuer, or the
//! camera, reaches; with any void; in which the rescuer's route to a survivable void
//! passes over the cell, and leaves open air in it), each drawn as a plan grid of coloured cells with
//! a legend (white → dark blue, the colours of the `rescue_map` figure,
//! [`crate::plot::voids::share_colour`]); the distributions over the members (min,
//! quartiles, mean, max of the void count, the survivable count and volume, the
//! survivable voids the rescuer reaches and the pile height); and the places where
//! survivable voids recur, with their frequency.
//!
//! Each map is inline SVG: one `<rect>` per cell whose share is above 0, with its share
//! in `data-p` and a tooltip; the cells with a share of 0 are left white.
use super::html::escape;
use super::{inconsistent, ReportError, Result};
use crate::plot::voids::share_colour;
use serde_json::Value;
use std::fmt::Write as _;
use std::path::Path;

/// The map columns drawn, with their captions.
pub const MAPS: [(&str, &str); 6] = [
    (
        "p_survivable",
        "a survivable void beneath (a lying or sitting adult fits)",
    ),
    (
        "p_survivable_rescuer",
        "a survivable void beneath that the rescuer reaches",
    ),
    (
        "p_survivable_camera",
        "a survivable void beneath that the search camera reaches",
    ),
    ("p_void", "any void beneath"),
    (
        "p_route_rescuer",
        "the rescuer's route to a survivable void passing over the cell",
    ),
    (
        "p_entry_rescuer",
        "the rescuer's route to a survivable void leaving open air in the cell",
    ),
];

/// The distributions shown, with their labels and units.
const DISTRIBUTIONS: [(&str, &str); 6] = [
    ("voids_count", "voids"),
    ("survivable_count", "survivable voids"),
    ("survivable_volume_m3", "survivable volume (m³)"),
    (
        "rescuer_reachable_survivable",
        "survivable voids the rescuer reaches",
    ),
    ("max_height_m", "pile height, max (m)"),
    ("mean_height_m", "pile height, mean (m)"),
];

/// Plan cells: (x, y, the shares of [`MAPS`] in order).
struct Cell {
    x: f64,
    y: f64,
    p: [f64; MAPS.len()],
}

fn read(path: &Path) -> Result<String> {
    crate::model::limits::read_regular_file(path).map_err(|error| ReportError::Read {
        path: path.to_path_buf(),
        error,
    })
}

fn load_map(path: &Path) -> Result<Vec<Cell>> {
    let text = read(path)?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines
        .next()
        .ok_or_else(|| inconsistent(path, "is empty"))?
        .split(',')
        .collect();
    let col = |name: &str| {
        header
            .iter()
            .position(|h| *h == name)
            .ok_or_else(|| inconsistent(path, format!("has no column `{name}`")))
    };
    let (cx, cy) = (col("x")?, col("y")?);
    let cp = MAPS
        .iter()
        .map(|(name, _)| col(name))
        .collect::<Result<Vec<usize>>>()?;
    let mut cells = Vec::new();
    for (n, line) in lines.enumerate() {
        let f: Vec<&str> = line.split(',').collect();
        let num = |c: usize| -> Result<f64> {
            f.get(c)
                .and_then(|s| s.parse::<f64>().ok())
                .filter(|v| v.is_finite())
                .ok_or_else(|| {
                    inconsistent(
                        format!("{}:{}", path.display(), n + 2),
                        format!("`{}` is not a number", header[c]),
                    )
                })
        };
        let mut p = [0.0; MAPS.len()];
        for (p, &c) in p.iter_mut().zip(&cp) {
            *p = num(c)?;
        }
        cells.push(Cell {
            x: num(cx)?,
            y: num(cy)?,
            p,
        });
    }
    Ok(cells)
}

/// One map as SVG: the plan grid (`cell` m, over `lo`…`hi`, the cells' centres' range
/// widened by half a cell), y up.
fn map_svg(cells: &[Cell], k: usize, cell: f64, lo: [f64; 2], hi: [f64; 2]) -> String {
    let (nx, ny) = (
        ((hi[0] - lo[0]) / cell).round().max(1.0),
        ((hi[1] - lo[1]) / cell).round().max(1.0),
    );
    let px = (300.0 / nx.max(ny)).clamp(2.0, 14.0);
    let (w, h) = (nx * px, ny * px);
    let mut s = format!(
        r##"<svg class="rescue-map" data-column="{col}" xmlns="http://www.w3.org/2000/svg" width="{w:.0}" height="{h:.0}" viewBox="0 0 {w:.0} {h:.0}" role="img" aria-label="{col}"><rect x="0" y="0" width="{w:.0}" height="{h:.0}" fill="#ffffff" stroke="#888888"/>"##,
        col = MAPS[k].0,
    );
    for c in cells.iter().filter(|c| c.p[k] > 0.0) {
        let x = (c.x - 0.5 * cell - lo[0]) / cell * px;
        let y = (hi[1] - (c.y + 0.5 * cell)) / cell * px;
        let colour = share_colour(c.p[k]);
        let _ = write!(
            s,
            r#"<rect x="{x:.2}" y="{y:.2}" width="{px:.2}" height="{px:.2}" fill="rgb({},{},{})" data-p="{}"><title>x {:.3} m, y {:.3} m: {:.0} %</title></rect>"#,
            colour.0,
            colour.1,
            colour.2,
            c.p[k],
            c.x,
            c.y,
            100.0 * c.p[k]
        );
    }
    s.push_str("</svg>");
    s
}

fn legend() -> String {
    let mut s = String::from(r#"<p class="note" id="rescue-map-legend">share of the members: "#);
    for p in [0.0, 0.25, 0.5, 0.75, 1.0] {
        let c = share_colour(p);
        let _ = write!(
            s,
            r#"<span class="swatch" style="background:rgb({},{},{})"></span>{:.0} % "#,
            c.0,
            c.1,
            c.2,
            100.0 * p
        );
    }
    s.push_str("(white: none)</p>");
    s
}

fn num(v: &Value) -> String {
    match v.as_f64() {
        Some(x) if x == x.round() && x.abs() < 1e9 => format!("{x}"),
        Some(x) => format!("{x:.4}"),
        None => "–".into(),
    }
}

/// The rescue section of the ensemble page (`<section id="rescue">`'s content), or a
/// sentence saying why there is none.
pub fn section(dir: &Path) -> Result<String> {
    let (mp, jp) = (dir.join("rescue_map.csv"), dir.join("rescue.json"));
    if !mp.exists() || !jp.exists() {
        return Ok(r#"<p class="note" id="rescue-none">No rescue map: the ensemble folder has no <code>rescue_map.csv</code> and <code>rescue.json</code> (<code>fem2rbd run --ensemble N</code> or <code>fem2rbd voids ENSEMBLE_DIR</code> writes them when its members have a ruin stage).</p>"#.to_string());
    }
    section_of(&mp, &jp, "")
}

/// The rescue maps, distributions and places of the map `mp` and its `rescue.json` `jp`
/// (an ensemble's, or a study intensity's `results/rescue/<stem>.csv` and `.json`); the
/// element ids end in `suffix`, so that one page can hold several.
pub fn section_of(mp: &Path, jp: &Path, suffix: &str) -> Result<String> {
    let (mp, jp) = (mp.to_path_buf(), jp.to_path_buf());
    let js: Value = serde_json::from_str(&read(&jp)?)
        .map_err(|e| inconsistent(&jp, format!("not JSON: {e}")))?;
    let cells = load_map(&mp)?;
    let analysed = js["members_analysed"].as_u64().unwrap_or(0);
    let members = js["members"].as_u64().unwrap_or(0);
    let mut s = format!(
        r#"<p class="note">From <code>rescue_map.csv</code> and <code>rescue.json</code>: {analysed} of {members} members analysed (each member's <code>voids.json</code>; {rule}).</p>"#,
        rule = escape(js["map"]["beneath"].as_str().unwrap_or("")),
    );
    for e in js["not_analysed"].as_array().into_iter().flatten() {
        let _ = write!(
            s,
            r#"<p class="note">Not analysed: {} ({}).</p>"#,
            escape(e["member"].as_str().unwrap_or("")),
            escape(e["error"].as_str().unwrap_or(""))
        );
    }
    match (js["map"]["cell_m"].as_f64(), cells.is_empty()) {
        (Some(cell), false) => {
            let lo = [0, 1].map(|a| {
                cells
                    .iter()
                    .map(|c| if a == 0 { c.x } else { c.y })
                    .fold(f64::INFINITY, f64::min)
                    - 0.5 * cell
            });
            let hi = [0, 1].map(|a| {
                cells
                    .iter()
                    .map(|c| if a == 0 { c.x } else { c.y })
                    .fold(f64::NEG_INFINITY, f64::max)
                    + 0.5 * cell
            });
            let _ = write!(s, r#"<div id="rescue-maps{suffix}" class="rescue-maps">"#);
            for (k, (col, caption)) in MAPS.iter().enumerate() {
                let _ = write!(
                    s,
                    r#"<figure data-map="{col}">{}<figcaption>Share of the members with {caption} (<code>{col}</code>).</figcaption></figure>"#,
                    map_svg(&cells, k, cell, lo, hi)
                );
            }
            let _ = write!(
                s,
                r#"</div>{}<p class="note">Plan cells of {cell:.3} m over x {:.3} … {:.3} m, y {:.3} … {:.3} m (y up).</p>"#,
                legend(),
                lo[0],
                hi[0],
                lo[1],
                hi[1]
            );
        }
        _ => s.push_str(
            r#"<p class="note">The map is empty: no member has debris above the ground.</p>"#,
        ),
    }
    let _ = write!(
        s,
        r#"<h3>Over the members</h3><table id="rescue-distributions{suffix}" class="rescue-distributions">"#
    );
    s.push_str(r#"<thead><tr><th>measure</th><th>min</th><th>p25</th><th>median</th><th>p75</th><th>mean</th><th>max</th></tr></thead><tbody>"#);
    for (key, label) in DISTRIBUTIONS {
        let d = &js["distributions"][key];
        let _ = write!(
            s,
            r#"<tr data-key="{key}" data-median="{}"><th>{}</th>"#,
            d["median"],
            escape(label)
        );
        for q in ["min", "p25", "median", "p75", "mean", "max"] {
            let _ = write!(s, "<td>{}</td>", num(&d[q]));
        }
        s.push_str("</tr>");
    }
    s.push_str("</tbody></table>");
    let places = js["places"].as_array().cloned().unwrap_or_default();
    let _ = write!(
        s,
        r#"<h3>Where survivable voids recur</h3><p class="note">{} places (survivable voids of the members matched by their 3-D bounding boxes, intersection over union at least {}), most members first.</p><table id="rescue-places{suffix}" class="rescue-places"><thead><tr><th>place</th><th>members</th><th>frequency</th><th>volume mean (min … max) m³</th><th>centroid (m)</th><th>patterns</th><th>rescuer reaches</th><th>camera reaches</th></tr></thead><tbody>"#,
        places.len(),
        js["match"]["iou_at_least"]
    );
    for (n, p) in places.iter().enumerate() {
        let c = &p["mean_centroid_m"];
        let patterns = p["patterns"]
            .as_object()
            .map(|o| {
                o.iter()
                    .map(|(k, v)| format!("{k} × {v}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            })
            .unwrap_or_default();
        let _ = write!(
            s,
            r#"<tr data-place="{}" data-probability="{}"><td>{}</td><td>{}</td><td>{:.0} %</td><td>{} ({} … {})</td><td>{}, {}, {}</td><td>{}</td><td>{}</td><td>{}</td></tr>"#,
            n + 1,
            p["probability"],
            n + 1,
            escape(
                &p["member_folders"]
                    .as_array()
                    .map(|a| a
                        .iter()
                        .filter_map(Value::as_str)
                        .collect::<Vec<_>>()
                        .join(", "))
                    .unwrap_or_default()
            ),
            100.0 * p["probability"].as_f64().unwrap_or(0.0),
            num(&p["volume_m3"]["mean"]),
            num(&p["volume_m3"]["min"]),
            num(&p["volume_m3"]["max"]),
            num(&c[0]),
            num(&c[1]),
            num(&c[2]),
            escape(&patterns),
            p["rescuer_reaches"],
            p["camera_reaches"],
        );
    }
    s.push_str("</tbody></table>");
    Ok(s)
}

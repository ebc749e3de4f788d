//! The report of an ensemble folder (`fem2rbd run --ensemble N`: `ensemble.json` and
//! `member-NNN/` run folders): the members' final ruins overlaid in one 3-D view (each
//! member its own colour; members shown or hidden one by one), a table of the members'
//! key figures, and the debris-density map of `fem2rbd plot` (the share of members with
//! debris over each plan cell, [`crate::plot::density`]), inlined as SVG, and the rescue
//! map with the spread of the members' voids ([`super::rescue_map`]).
//!
//! Every member is read through [`RunFolder::load`]; all members must have the bodies of
//! the first (the same names in the same order), or the differing member's `bodies.csv`
//! is named. Final poses are those of `ruins.csv`, as float32 in base64 (one pose per
//! body and member; the run report's timeline is quantised, [`super::quantise`]).
use super::html::{escape, script_json};
use super::script::{ENSEMBLE_JS, PAGE_CSS, THREE_BUNDLE, THREE_LICENSE};
use super::{inconsistent, ReportError, Result};
use crate::output::run_folder::RunFolder;
use crate::plot::density::{DensityFigure, DensityGrid};
use serde_json::json;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Colours of members 0, 1, … (cycled), sRGB hex: well-separated hues.
const MEMBER_COLOURS: [&str; 10] = [
    "#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf",
    "#bcbd22", "#7f7f7f",
];

/// Whether `dir` is an ensemble folder (it holds `ensemble.json`).
pub fn is_ensemble(dir: &Path) -> bool {
    dir.join("ensemble.json").is_file()
}

/// The member folders of the ensemble folder `dir`, in name order.
fn member_dirs(dir: &Path) -> Result<Vec<PathBuf>> {
    let read_err = |error| ReportError::Read {
        path: dir.to_path_buf(),
        error,
    };
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).map_err(read_err)? {
        let p = e.map_err(read_err)?.path();
        if p.is_dir()
            && p.file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with("member-"))
        {
            out.push(p);
        }
    }
    out.sort();
    if out.is_empty() {
        return Err(inconsistent(
            dir.join("ensemble.json"),
            "is there, but the folder holds no member-NNN run folders",
        ));
    }
    Ok(out)
}

/// The report page of the ensemble folder `dir`, as HTML text.
pub fn report_html(dir: &Path) -> Result<String> {
    let paths = member_dirs(dir)?;
    let runs: Vec<RunFolder> = paths
        .iter()
        .map(|p| RunFolder::load(p))
        .collect::<std::result::Result<_, _>>()?;
    let names: Vec<String> = runs[0].bodies.iter().map(|b| b.id.name()).collect();
    for (p, r) in paths.iter().zip(&runs).skip(1) {
        if r.bodies.len() != names.len()
            || r.bodies.iter().zip(&names).any(|(b, n)| b.id.name() != *n)
        {
            return Err(inconsistent(
                p.join("bodies.csv"),
                format!(
                    "holds other bodies than {} (an ensemble's members share one model)",
                    paths[0].join("bodies.csv").display()
                ),
            ));
        }
    }
    let grid = DensityGrid::of_runs(&runs).map_err(|e| inconsistent(dir, e.to_string()))?;
    let density = crate::plot::svg_string(&DensityFigure::of_grid(
        &grid,
        format!("{} members", runs.len()),
    ))
    .map_err(|e| inconsistent(dir, e.to_string()))?;
    let density = super::plots::svg_element(&density).map_err(|m| inconsistent(dir, m))?;
    let member_names: Vec<String> = paths
        .iter()
        .map(|p| {
            p.file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default()
        })
        .collect();
    let b = &runs[0].bodies;
    let data = json!({
        "bodies": {
            "name": names,
            "type": b.iter().map(|b| b.id.type_name().to_string()).collect::<Vec<_>>(),
            "passive": b.iter().map(|b| u8::from(b.passive)).collect::<Vec<_>>(),
            "size": b.iter().flat_map(|b| b.half_extents.map(|h| 2.0 * h)).collect::<Vec<_>>(),
        },
        "members": runs.iter().zip(&member_names).enumerate().map(|(m, (r, name))| {
            let pos: Vec<f32> = r.final_poses.iter().flat_map(|p| p.position.map(|v| v as f32)).collect();
            let rot: Vec<f32> = r
                .final_poses
                .iter()
                .flat_map(|p| {
                    let [w, x, y, z] = p.orientation;
                    [x, y, z, w].map(|v| v as f32)
                })
                .collect();
            json!({
                "name": name,
                "colour": MEMBER_COLOURS[m % MEMBER_COLOURS.len()],
                "position": super::base64::encode_f32(&pos),
                "rotation": super::base64::encode_f32(&rot),
            })
        }).collect::<Vec<_>>(),
    });
    let mut rows = String::new();
    for (m, (r, name)) in runs.iter().zip(&member_names).enumerate() {
        let s = &r.summary;
        let link = if paths[m].join("report.html").is_file() {
            format!(r#"<a href="{0}/report.html">{0}</a>"#, escape(name))
        } else {
            escape(name)
        };
        let _ = write!(
            rows,
            r#"<tr data-member="{m}"><td><label><input type="checkbox" class="member-toggle" data-member="{m}" checked><span class="swatch" style="background:{}"></span></label>{link}</td><td>{}</td><td>{}</td><td>{}</td><td>{:.3}</td><td>{:.3}</td><td>{:.3}</td></tr>"#,
            MEMBER_COLOURS[m % MEMBER_COLOURS.len()],
            s.tc_s.map_or("none".to_string(), |t| t.to_string()),
            s.ruin_stage.as_ref().map_or("–".to_string(), |rs| format!(
                "{} at {} s",
                rs.stop.name(),
                rs.end_s
            )),
            s.connections.map_or("–".to_string(), |c| format!(
                "{} of {}",
                c.broken, c.total
            )),
            s.ruins.extent_beyond_footprint_m.max,
            s.ruins.max_debris_height_m,
            s.ruins.debris_footprint_area_m2,
        );
    }
    let name = super::html::folder_name(dir);
    let title = format!("fem2rbd ensemble report: {name}");
    let n = runs.len();
    let mut h = String::new();
    let _ = write!(
        h,
        r#"{head}<header><h1>{title}</h1><p id="headline">{n} members of one scenario, {bodies} bodies each: their final ruins overlaid, their key figures and the debris-density map.</p></header>
<section id="view"><h2>The members' final ruins, overlaid</h2>
<div id="viewport"><canvas id="scene-canvas" aria-label="the members' final ruins in 3-D"></canvas></div>
<div id="controls"><button id="view-3d" type="button">3-D view</button><button id="view-plan" type="button">plan view</button><button id="show-all" type="button">all members</button><span class="note">Tick members in the table to show or hide them.</span></div>
</section>
<section id="members"><h2>Members</h2>
<table id="member-table"><thead><tr><th>member</th><th>Tc (s)</th><th>ruin stage</th><th>connections broken</th><th>debris beyond footprint (m)</th><th>debris height (m)</th><th>debris area (m²)</th></tr></thead><tbody>{rows}</tbody></table>
</section>
<section id="density"><h2>Debris density</h2>
<figure data-plot="debris_density">{density}<figcaption>Share of the members with debris over each plan cell (cell {cell:.3} m; the original footprint dashed).</figcaption></figure>
</section>
<section id="rescue"><h2>Survivable voids over the members</h2>
{rescue}
</section>
<footer><details><summary>About this page</summary><p>Written by <code>fem2rbd report</code> from the ensemble folder alone; it works offline. It inlines three.js r187 and its OrbitControls (MIT licence below).</p><pre>{license}</pre></details></footer>
<script type="application/json" id="report-data">{json}</script>
<script>{THREE_BUNDLE}</script>
<script>{ENSEMBLE_JS}</script>
</body>
</html>
"#,
        head = super::html::head(&title, PAGE_CSS),
        title = escape(&title),
        bodies = names.len(),
        cell = grid.cell_m,
        rescue = super::rescue_map::section(dir)?,
        license = escape(THREE_LICENSE),
        json = script_json(&data),
    );
    Ok(h)
}

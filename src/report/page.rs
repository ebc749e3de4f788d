//! The page: the run folder's consistency checks, then the HTML document with its
//! sections (`view`, `figures`, `voids`, `bodies`, `plots`), the data ([`super::data`]) and the
//! inlined scripts ([`super::script`]).
use super::connections::Connection;
use super::data::{hex, page_data, stories};
use super::html::{escape, script_json};
use super::plots::Plot;
use super::script::{PAGE_CSS, PAGE_JS, THREE_BUNDLE, THREE_LICENSE};
use super::voids::RunVoids;
use super::{figures, ground_strip, inconsistent, Result};
use crate::output::palette::type_srgb;
use crate::output::run_folder::RunFolder;
use std::fmt::Write as _;

/// Checks that `summary.json` agrees with the tables (body counts, FE keyframes, Tc and
/// the ruin stage inside the timeline) and that the timeline has a frame.
pub fn check(run: &RunFolder) -> Result<()> {
    let dir = &run.dir;
    let (Some(first), Some(last)) = (run.frames.first(), run.frames.last()) else {
        return Err(inconsistent(
            dir.join("keyframes.csv"),
            "holds no frame; the report needs at least one",
        ));
    };
    let s = &run.summary;
    let summary = dir.join("summary.json");
    let passive = run.bodies.iter().filter(|b| b.passive).count();
    let active = run.bodies.len() - passive;
    if (s.bodies, s.foundation_blocks) != (active, passive) {
        return Err(inconsistent(
            summary,
            format!(
                "bodies = {} and foundation_blocks = {}, but bodies.csv has {active} active \
                 bodies and {passive} passive blocks",
                s.bodies, s.foundation_blocks
            ),
        ));
    }
    let fe = run.history.iter().filter(|h| h.fe).count();
    if s.keyframes_fe != fe {
        return Err(inconsistent(
            summary,
            format!(
                "keyframes_fe = {}, but history.csv has {fe} FE frames",
                s.keyframes_fe
            ),
        ));
    }
    // Times are written to 4 decimals in the tables and 6 in the summary.
    let tol = 1e-4;
    let inside = |t: f64| t >= first.0 - tol && t <= last.0 + tol;
    if let Some(tc) = s.tc_s {
        if !inside(tc) {
            return Err(inconsistent(
                summary,
                format!(
                    "tc_s = {tc} lies outside the timeline of keyframes.csv ({} – {} s)",
                    first.0, last.0
                ),
            ));
        }
    }
    if let Some(rs) = &s.ruin_stage {
        if !inside(rs.start_s) || !inside(rs.end_s) {
            return Err(inconsistent(
                summary,
                format!(
                    "ruin_stage {} – {} s lies outside the timeline of keyframes.csv ({} – {} s)",
                    rs.start_s, rs.end_s, first.0, last.0
                ),
            ));
        }
    }
    Ok(())
}

/// The table of bodies (`<table id="body-table">`): name, type, story, size, mass, final
/// centre (`ruins.csv`) and at rest; row `i` has `id="body-i"`.
fn body_table(run: &RunFolder) -> String {
    let (story, _) = stories(run);
    let mut s = String::from(
        r#"<table id="body-table"><thead><tr><th>#</th><th>name</th><th>type</th><th>story</th><th>size (m)</th><th>mass (kg)</th><th>final x (m)</th><th>final y (m)</th><th>final z (m)</th><th>at rest</th></tr></thead><tbody>"#,
    );
    for (i, b) in run.bodies.iter().enumerate() {
        let h = b.half_extents;
        let p = run.final_poses[i].position;
        let rest = match run.at_rest[i] {
            Some(true) => "yes",
            Some(false) => "no",
            None => "–",
        };
        let story = if b.passive {
            "foundation".to_string()
        } else {
            story[i].to_string()
        };
        let _ = write!(
            s,
            r#"<tr id="body-{i}" data-body="{i}"><td>{i}</td><td>{}</td><td><span class="swatch" style="background:{}"></span>{}</td><td>{story}</td><td>{:.3} × {:.3} × {:.3}</td><td>{:.1}</td><td>{:.3}</td><td>{:.3}</td><td>{:.3}</td><td>{rest}</td></tr>"#,
            escape(&b.id.name()),
            hex(type_srgb(b.id.type_name())),
            escape(b.id.type_name()),
            2.0 * h[0],
            2.0 * h[1],
            2.0 * h[2],
            b.mass_kg,
            p[0],
            p[1],
            p[2],
        );
    }
    s.push_str("</tbody></table>");
    s
}

/// The page of `run` (module docs of [`super`]).
pub fn render(
    run: &RunFolder,
    connections: Option<&[Connection]>,
    plots: &[Plot],
    voids: &RunVoids,
) -> Result<String> {
    check(run)?;
    let name = super::html::folder_name(&run.dir);
    let title = format!("fem2rbd report: {name}");
    let s = &run.summary;
    let t0 = run.frames.first().map_or(0.0, |f| f.0);
    let t1 = run.frames.last().map_or(0.0, |f| f.0);
    let mut data = page_data(run, connections);
    data["voids"] = super::voids::page_data(voids);
    let frames = run.frames.len();
    let n = run.bodies.len();
    // Seven 16-bit codes per body and frame (src/report/quantise.rs).
    let pose_bytes = frames * n * 7 * 2;
    let step_mm = data["position"]["step"].as_f64().unwrap_or(0.0) * 1e3;
    let mut h = String::new();
    let _ = write!(
        h,
        r#"{head}<header><h1>{title}</h1><p id="headline">{headline}</p></header>
<section id="view"><h2>Collapse and ruin in 3-D</h2>
<div id="viewport"><canvas id="scene-canvas" aria-label="the bodies in 3-D"></canvas><div id="legend"></div><div id="pick-info" hidden></div></div>
<div id="controls">
<button id="play" type="button">▶ play</button>
<label>speed <select id="speed"><option value="0.1">0.1×</option><option value="0.25">0.25×</option><option value="0.5">0.5×</option><option value="1" selected>1×</option><option value="2">2×</option><option value="4">4×</option></select></label>
<label>colour by <select id="colour-by"><option value="type">element type</option><option value="story">story</option>{connection_option}</select></label>
{voids_toggle}<button id="view-3d" type="button">3-D view</button><button id="view-plan" type="button">plan view</button>
{tc_button}<button id="goto-end" type="button">final ruin</button>
<span id="time-readout"></span>
</div>
<input id="time-slider" type="range" min="{t0}" max="{t1}" step="any" value="{t0}" list="time-marks" aria-label="time (s)">
<datalist id="time-marks">{tc_mark}</datalist>
{strip}
<p class="note">{strip_legend}</p>
<p class="note">Drag to orbit, scroll to zoom, right-drag to pan; click a body to see its row. Link to a moment with <code>#t=SECONDS</code> (also <code>&amp;colour=type|story|connection</code>, <code>&amp;view=plan</code>). Every keyframe of <code>keyframes.csv</code> is drawn ({frames} frames × {n} bodies; poses as 16-bit integers, {pose_mb:.2} MB before base64: centres on a grid of {step_mm:.3} mm, rotations to 6·10⁻⁵ rad), positions interpolated linearly and rotations by slerp between frames.</p>
</section>
<section id="figures"><h2>Key figures</h2>
{figures}
</section>
<section id="voids"><h2>Voids of the final ruin</h2>
{voids}
</section>
<section id="bodies"><h2>Bodies and their final positions</h2>
<details open><summary>{n} bodies (<code>bodies.csv</code>, final centres from <code>ruins.csv</code>)</summary>
{bodies}
</details>
</section>
<section id="plots"><h2>Figures of the run</h2>
{plots}
</section>
<footer><details><summary>About this page</summary><p>Written by <code>fem2rbd report</code> from the run folder alone; it works offline. It inlines three.js r187 and its OrbitControls (MIT licence below).</p><pre>{license}</pre></details></footer>
<script type="application/json" id="report-data">{json}</script>
<script>{THREE_BUNDLE}</script>
<script>{PAGE_JS}</script>
</body>
</html>
"#,
        head = super::html::head(&title, PAGE_CSS),
        title = escape(&title),
        headline = escape(&format!(
            "{} run: {} bodies and {} foundation blocks; {}; timeline {t0} – {t1} s.",
            s.mode.name(),
            s.bodies,
            s.foundation_blocks,
            match s.tc_s {
                Some(tc) => format!("collapse moment Tc = {tc} s ({})", s.tc_reason.name()),
                None => format!("no collapse moment ({})", s.tc_reason.name()),
            }
        )),
        connection_option = if connections.is_some() {
            r#"<option value="connection">connection state</option>"#
        } else {
            ""
        },
        voids_toggle = if matches!(voids, RunVoids::Analysed(a) if !a.voids.is_empty()) {
            r#"<label><input id="show-voids" type="checkbox" checked> voids at the final ruin</label>"#
        } else {
            ""
        },
        tc_button = if s.tc_s.is_some() {
            r#"<button id="goto-tc" type="button">Tc</button>"#
        } else {
            ""
        },
        tc_mark = match s.tc_s {
            Some(tc) => format!(r#"<option value="{tc}" label="Tc"></option>"#),
            None => String::new(),
        },
        strip = ground_strip::svg(run),
        strip_legend = ground_strip::legend(run),
        pose_mb = pose_bytes as f64 / 1e6,
        figures = figures::table(run, &super::voids::figure_rows(voids)),
        voids = super::voids::section(voids),
        bodies = body_table(run),
        plots = if plots.is_empty() {
            r#"<p class="note">No figures: <code>plots/*.svg</code> is not in the run folder (<code>fem2rbd plot RUN_DIR</code> draws them).</p>"#.to_string()
        } else {
            plots
                .iter()
                .map(|p| {
                    format!(
                        r#"<figure data-plot="{0}">{1}<figcaption>{0}</figcaption></figure>"#,
                        escape(&p.name),
                        p.svg
                    )
                })
                .collect::<Vec<_>>()
                .join("\n")
        },
        license = escape(THREE_LICENSE),
        json = script_json(&data),
    );
    Ok(h)
}

//! The run's key figures from `summary.json` as an HTML table (`<table id="key-figures">`),
//! one row per figure, `data-key` naming the summary field it shows and `data-value` its
//! number as read: Tc and why, the timeline, connection states, floor offsets and drops,
//! the slab overlap, debris extent and height, interpenetration, the energy and speed
//! checks, the wall times. Units and definitions: docs/scenario-format.md "Outputs".
use super::html::escape;
use crate::output::run_folder::RunFolder;
use crate::output::summary::RunSummary;
use std::fmt::Write as _;

/// One table row: the summary field, the label, the shown text and (for one number) its
/// value.
struct Row {
    key: String,
    label: String,
    text: String,
    value: Option<f64>,
}

fn row(key: &str, label: &str, text: String, value: Option<f64>) -> Row {
    Row {
        key: key.into(),
        label: label.into(),
        text,
        value,
    }
}

/// Metres with 3 decimals.
fn m(v: f64) -> String {
    format!("{v:.3} m")
}

fn list(v: &[f64], unit: &str) -> String {
    v.iter()
        .map(|x| format!("{x:.3}"))
        .collect::<Vec<_>>()
        .join(" / ")
        + unit
}

fn ok(b: bool) -> &'static str {
    if b {
        "passed"
    } else {
        "FAILED"
    }
}

/// The rows of `s` (module docs).
fn rows(s: &RunSummary, run: &RunFolder) -> Vec<Row> {
    let mut r = Vec::new();
    r.push(row("mode", "Mode", s.mode.name().into(), None));
    r.push(match s.tc_s {
        Some(tc) => row("tc_s", "Collapse moment Tc", format!("{tc} s"), Some(tc)),
        None => row("tc_s", "Collapse moment Tc", "none".into(), None),
    });
    r.push(row(
        "tc_reason",
        "Why the FE stage ended",
        format!("{}: {}", s.tc_reason.name(), s.tc_detail),
        None,
    ));
    let t0 = run.frames.first().map_or(0.0, |f| f.0);
    let t1 = run.frames.last().map_or(0.0, |f| f.0);
    r.push(row(
        "timeline",
        "Timeline",
        format!(
            "{t0} – {t1} s, {} frames ({} FE keyframes{})",
            run.frames.len(),
            s.keyframes_fe,
            match &s.ruin_stage {
                Some(rs) => format!(", ruin stage {} – {} s", rs.start_s, rs.end_s),
                None => String::new(),
            }
        ),
        Some(t1 - t0),
    ));
    r.push(row(
        "bodies",
        "Bodies",
        format!(
            "{} active, {} foundation blocks",
            s.bodies, s.foundation_blocks
        ),
        Some(s.bodies as f64),
    ));
    if let Some(rs) = &s.ruin_stage {
        r.push(row(
            "ruin_stage.stop",
            "Ruin stage stopped",
            format!(
                "{} at {} s; {} of {} bodies at rest (foundation blocks included)",
                rs.stop.name(),
                rs.end_s,
                rs.bodies_at_rest,
                s.bodies + s.foundation_blocks
            ),
            Some(rs.end_s),
        ));
    }
    if let Some(c) = &s.connections {
        r.push(row(
            "connections",
            "Connections at the end",
            format!(
                "{} intact, {} plastic, {} broken of {}",
                c.intact, c.plastic, c.broken, c.total
            ),
            Some(c.broken as f64),
        ));
    }
    let ru = &s.ruins;
    for f in &ru.floors {
        let d = f.centroid_displacement_m;
        r.push(row(
            &format!("ruins.floors[{}]", f.floor - 1),
            &format!("Floor {} (level {:.3} m)", f.floor, f.level_m),
            format!(
                "offset {} in plan, drop {} ({} slabs)",
                m(f.horizontal_offset_m),
                m(-d[2]),
                f.slabs
            ),
            Some(f.horizontal_offset_m),
        ));
    }
    if let Some(fd) = &s.floors_down {
        r.push(row(
            "floors_down",
            "Floors down",
            format!(
                "at {} s (lowest floor {:.0} % of its height down): drops {}, story offsets {}{}",
                fd.t_s,
                100.0 * fd.share,
                list(&fd.floor_drops_m, " m"),
                list(&fd.story_offsets_m, " m"),
                if fd.stories_above_whole {
                    "; the stories above came down whole"
                } else {
                    ""
                }
            ),
            Some(fd.t_s),
        ));
    }
    for o in &ru.slab_overlap {
        r.push(row(
            &format!("ruins.slab_overlap[{}-{}]", o.floors[0], o.floors[1]),
            &format!("Slab overlap, floors {} and {}", o.floors[0], o.floors[1]),
            format!(
                "{:.2} ({:.3} of {:.3} m²)",
                o.overlap_ratio, o.overlap_area_m2, o.upper_slab_area_m2
            ),
            Some(o.overlap_ratio),
        ));
    }
    let e = &ru.extent_beyond_footprint_m;
    r.push(row(
        "ruins.extent_beyond_footprint_m.max",
        "Debris beyond the footprint",
        format!(
            "{} at most (−x {:.3}, +x {:.3}, −y {:.3}, +y {:.3} m)",
            m(e.max),
            e.x_minus,
            e.x_plus,
            e.y_minus,
            e.y_plus
        ),
        Some(e.max),
    ));
    r.push(row(
        "ruins.max_debris_height_m",
        "Debris height",
        m(ru.max_debris_height_m),
        Some(ru.max_debris_height_m),
    ));
    r.push(row(
        "ruins.debris_footprint_area_m2",
        "Debris area in plan",
        format!(
            "{:.3} m² (building {:.3} m²)",
            ru.debris_footprint_area_m2, ru.original_footprint_area_m2
        ),
        Some(ru.debris_footprint_area_m2),
    ));
    let ip = &ru.interpenetration;
    r.push(row(
        "ruins.interpenetration",
        "Bodies inside each other",
        format!(
            "{} pairs over 10 mm, deepest {}{}",
            ip.pairs_over_10mm,
            m(ip.deepest_m),
            match &ip.deepest_pair {
                Some([a, b]) => format!(" ({a} and {b})"),
                None => String::new(),
            }
        ),
        Some(ip.deepest_m),
    ));
    if let Some(en) = s.ruin_stage.as_ref().and_then(|rs| rs.energy.as_ref()) {
        let sp = &en.settle_phase;
        r.push(row(
            "ruin_stage.energy.settle_phase",
            "Energy check (settle phase)",
            format!(
                "{}: largest rise {:.3e} of the initial potential energy (limit {:.0e})",
                ok(sp.ok),
                sp.max_rise_ratio,
                sp.limit_ratio
            ),
            Some(sp.max_rise_ratio),
        ));
        let v = &en.speed;
        r.push(row(
            "ruin_stage.energy.speed",
            "Speed check",
            format!(
                "{}: fastest body {:.2} m/s (bound {:.2} m/s){}",
                ok(v.ok),
                v.max_mps,
                v.bound_mps,
                match &v.max_body {
                    Some(b) => format!(", {b}"),
                    None => String::new(),
                }
            ),
            Some(v.max_mps),
        ));
        r.push(row(
            "ruin_stage.energy",
            "Energy ledger",
            format!(
                "initial potential {:.1} J; injected by the solver {:.1} J; ground work {:.1} J; dissipated {:.1} J",
                en.initial_potential_j, en.injected_j, en.end.ground_work_j, en.end.dissipated_j
            ),
            Some(en.injected_j),
        ));
    }
    if let Some(fc) = &s.fe_first_contact {
        r.push(row(
            "fe_first_contact",
            "FE alone: first contact",
            format!("at {} s: {}", fc.t_s, fc.detail),
            Some(fc.t_s),
        ));
    }
    r.push(match &s.wall_time_s {
        Some(w) => row(
            "wall_time_s",
            "Wall time",
            format!(
                "FE stage {:.1} s, ruin stage {:.1} s ({:.0} % inside Bullet)",
                w.fe,
                w.ruin,
                100.0 * w.ruin_bullet_share
            ),
            Some(w.fe + w.ruin),
        ),
        None => row("wall_time_s", "Wall time", "not recorded".into(), None),
    });
    r
}

/// The key-figures table of `run`, with the rescue rows `rescue` (key, label, text,
/// value: [`super::voids::figure_rows`]) after the ruin's.
pub fn table(run: &RunFolder, rescue: &[(String, String, String, Option<f64>)]) -> String {
    let mut s = String::from(r#"<table id="key-figures"><tbody>"#);
    let mut all = rows(&run.summary, run);
    let at = all
        .iter()
        .position(|r| r.key == "wall_time_s")
        .unwrap_or(all.len());
    all.splice(
        at..at,
        rescue.iter().map(|(k, l, t, v)| row(k, l, t.clone(), *v)),
    );
    for r in all {
        let value = match r.value {
            Some(v) => format!(r#" data-value="{v}""#),
            None => String::new(),
        };
        let _ = write!(
            s,
            r#"<tr data-key="{}"><th>{}</th><td{value}>{}</td></tr>"#,
            escape(&r.key),
            escape(&r.label),
            escape(&r.text)
        );
    }
    s.push_str("</tbody></table>");
    s
}

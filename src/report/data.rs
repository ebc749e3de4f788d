//! The data the report page animates, as one JSON object inside the page.
//!
//! * `times`: the keyframe times of `keyframes.csv`, s (as written, 4 decimals);
//!   `fe_frames`: how many of them are FE keyframes (`history.csv` `stage = fe`), the
//!   rest being ruin-stage frames; `tc`: the collapse moment Tc of `summary.json` (or
//!   `null`); `ruin_start`: the ruin stage's start (or `null`);
//! * `bodies`: per body, in `bodies.csv` order, `name`, `type`, `passive` (0/1), `story`
//!   (0 for passive blocks, else the story of [`Stories`]: the plot's definition), `size`
//!   (full box size along the box axes, m: twice the half extents), `mass` (kg), `final`
//!   (the final centre of `ruins.csv`, m) and `at_rest` (1, 0 or `null`);
//! * `position` and `rotation`: per frame and body, the box centre (x, y, z, m) and the
//!   unit quaternion of its axes in three.js's order (x, y, z, w), as 16-bit integers
//!   ([`super::quantise`]): `position` is `{origin, step, u16}` with `u16` the
//!   `frames × bodies × 3` codes (x = origin + step · code), `rotation` is `{scale, i16}`
//!   with `i16` the `frames × bodies × 4` codes (q = code / scale, then normalised), each
//!   little-endian in base64;
//! * `ground`: `top` (the base level: top of the passive foundations, else the lowest
//!   undeformed corner, m) and `disp`, the ground displacement of each frame
//!   (`history.csv`, `frames × 3` float32 in base64);
//! * `palettes`: the colours (sRGB hex) and legend names of each colouring: `type` (the
//!   one colour table of element types, [`crate::output::palette`]), `story`, and
//!   `connection` with `connections`: each connection's bodies and the times from which
//!   it is plastic and broken (`null`: never), when the run folder has `connections.csv`.
//!
//! Numbers are written by serde_json (shortest round-trip decimal), so the same run
//! folder gives the same text.
use super::connections::Connection;
use super::quantise::{quaternion_codes, PositionGrid, QUATERNION_SCALE};
use crate::output::palette::type_srgb;
use crate::output::run_folder::RunFolder;
use crate::plot::geometry::{base_level, Stories};
use serde_json::{json, Value};

/// Colours of stories 1, 2, … (cycled), sRGB: a sequential ramp from dark blue to
/// yellow (viridis stops).
const STORY_COLOURS: [[u8; 3]; 8] = [
    [68, 1, 84],
    [70, 50, 126],
    [54, 92, 141],
    [39, 127, 142],
    [31, 161, 135],
    [74, 193, 109],
    [160, 218, 57],
    [253, 231, 37],
];

/// Colour of the passive foundation blocks in the story colouring, sRGB.
const FOUNDATION_GREY: [u8; 3] = [120, 120, 120];

/// The connection states of a body, in legend order: no connection, all intact, one
/// plastic, one broken, all broken; and the FE stage (before the connections exist).
pub const CONNECTION_STATES: [(&str, [u8; 3]); 6] = [
    ("no connection", [150, 150, 150]),
    ("all intact", [46, 139, 87]),
    ("a connection plastic", [230, 170, 30]),
    ("a connection broken", [215, 90, 40]),
    ("all connections broken", [150, 20, 30]),
    ("FE stage (no connections yet)", [190, 190, 200]),
];

/// `#rrggbb` of an sRGB colour.
pub fn hex(c: [u8; 3]) -> String {
    format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2])
}

/// The story of each body (0 for passive blocks) and the number of stories.
pub fn stories(run: &RunFolder) -> (Vec<usize>, usize) {
    let s = Stories::from_bodies(&run.bodies);
    let of = run
        .bodies
        .iter()
        .map(|b| {
            if b.passive {
                0
            } else {
                s.of(b.pose0.position[2])
            }
        })
        .collect();
    (of, s.count())
}

/// The page data of `run` (module docs).
pub fn page_data(run: &RunFolder, connections: Option<&[Connection]>) -> Value {
    let n = run.bodies.len();
    let (story, n_stories) = stories(run);
    let grid = PositionGrid::covering(
        run.frames
            .iter()
            .flat_map(|f| f.1.iter().map(|p| p.position)),
    );
    let mut position = Vec::with_capacity(run.frames.len() * n * 3);
    let mut rotation = Vec::with_capacity(run.frames.len() * n * 4);
    for (_, poses) in &run.frames {
        for p in poses {
            position.extend(grid.encode(p.position));
            let [w, x, y, z] = p.orientation;
            rotation.extend(quaternion_codes([x, y, z, w]));
        }
    }
    let ground: Vec<f32> = run
        .history
        .iter()
        .flat_map(|h| h.ground_m.map(|v| v as f32))
        .collect();
    let type_names: Vec<String> = {
        let mut t: Vec<String> = run
            .bodies
            .iter()
            .map(|b| b.id.type_name().to_string())
            .collect();
        t.sort();
        t.dedup();
        t
    };
    let story_legend: Vec<Value> = std::iter::once(json!({
        "name": "foundation",
        "colour": hex(FOUNDATION_GREY),
    }))
    .chain((1..=n_stories).map(|s| {
        let level = Stories::from_bodies(&run.bodies).levels.get(s - 1).copied();
        json!({
            "name": match level {
                Some(l) => format!("story {s} (floor at {l:.2} m)"),
                None => format!("story {s}"),
            },
            "colour": hex(STORY_COLOURS[(s - 1) % STORY_COLOURS.len()]),
        })
    }))
    .collect();
    let connection_palette = connections.map(|cs| {
        json!({
            "states": CONNECTION_STATES
                .iter()
                .map(|(name, c)| json!({"name": name, "colour": hex(*c)}))
                .collect::<Vec<_>>(),
            "a": cs.iter().map(|c| c.bodies[0]).collect::<Vec<_>>(),
            "b": cs.iter().map(|c| c.bodies[1]).collect::<Vec<_>>(),
            "plastic_from": cs.iter().map(|c| c.plastic_from_s).collect::<Vec<_>>(),
            "broken_from": cs.iter().map(|c| c.broken_from_s).collect::<Vec<_>>(),
        })
    });
    json!({
        "times": run.frames.iter().map(|f| f.0).collect::<Vec<_>>(),
        "fe_frames": run.history.iter().filter(|h| h.fe).count(),
        "tc": run.summary.tc_s,
        "ruin_start": run.summary.ruin_stage.as_ref().map(|r| r.start_s),
        "bodies": {
            "name": run.bodies.iter().map(|b| b.id.name()).collect::<Vec<_>>(),
            "type": run.bodies.iter().map(|b| b.id.type_name().to_string()).collect::<Vec<_>>(),
            "passive": run.bodies.iter().map(|b| u8::from(b.passive)).collect::<Vec<_>>(),
            "story": story,
            "size": run.bodies.iter().flat_map(|b| b.half_extents.map(|h| 2.0 * h)).collect::<Vec<_>>(),
            "mass": run.bodies.iter().map(|b| b.mass_kg).collect::<Vec<_>>(),
            "final": run.final_poses.iter().flat_map(|p| p.position).collect::<Vec<_>>(),
            "at_rest": run.at_rest.iter().map(|a| a.map(u8::from)).collect::<Vec<_>>(),
        },
        "position": {
            "origin": grid.origin,
            "step": grid.step,
            "u16": super::base64::encode_u16(&position),
        },
        "rotation": {
            "scale": QUATERNION_SCALE,
            "i16": super::base64::encode_i16(&rotation),
        },
        "ground": {
            "top": base_level(&run.bodies).unwrap_or(0.0),
            "disp": super::base64::encode_f32(&ground),
        },
        "palettes": {
            "type": type_names
                .iter()
                .map(|t| json!({"name": t, "colour": hex(type_srgb(t))}))
                .collect::<Vec<_>>(),
            "story": story_legend,
            "connection": connection_palette,
        },
    })
}

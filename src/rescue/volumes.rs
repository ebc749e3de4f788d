//! The survivable voids of a `voids.json` as the static volumes of `collapse.glb`
//! ([`crate::output::gltf::VoidVolume`]): each survivable void's cells as the boxes of
//! `voids.json` (`boxes`, [`super::boxes`]), named `void-NN <pattern> <volume> m3` (its
//! number in `voids.csv`, its pattern, its volume at the model's scale), coloured as its
//! pattern in the void figures and the report ([`crate::output::palette::pattern_srgb`],
//! in linear light).
//!
//! The access routes to them as the lines of `collapse.glb`
//! ([`crate::output::gltf::RouteLine`]): for each survivable void the rescuer reaches, the
//! rescuer's route (`rescuer.path_m`), else, where the camera reaches it, the camera's
//! (`camera.path_m`); named `route-NN <kind> <crawl> m` (the void's number, who takes it,
//! the crawl length under debris at the model's scale) and coloured as in the void
//! figures: the rescuer's black, the camera's grey ([`crate::plot::voids`]).
//!
//! Read from the file's text, so that `fem2rbd run`, `fem2rbd voids` and `fem2rbd export
//! gltf` put the same nodes into the same bytes.
use crate::output::gltf::{RouteLine, VoidVolume};
use crate::output::palette::{pattern_srgb, srgb_to_linear};
use serde_json::Value;

/// The node name of void `number` (1 = largest).
pub fn node_name(number: u64, pattern: &str, volume_m3: f64) -> String {
    format!("void-{number:02} {pattern} {volume_m3:.4} m3")
}

/// The node name of the route of `kind` (`rescuer`, `camera`) to void `number` with
/// `route_m` of crawl under debris.
pub fn route_name(number: u64, kind: &str, route_m: f64) -> String {
    format!("route-{number:02} {kind} {route_m:.3} m")
}

/// sRGB colour of a route of `kind`, as the void figures draw it: the rescuer's black,
/// the camera's grey.
pub fn route_srgb(kind: &str) -> [u8; 3] {
    if kind == "rescuer" {
        [0, 0, 0]
    } else {
        [110, 110, 110]
    }
}

/// The `voids.json` text `text` parsed; `None` when it records an error or the ruin has no
/// grid (no voids to draw).
fn analysis(text: &str) -> Result<Option<Value>, String> {
    let js: Value = serde_json::from_str(text).map_err(|e| format!("not JSON: {e}"))?;
    Ok((js.get("error").is_none() && !js["grid"].is_null()).then_some(js))
}

/// The survivable voids of a parsed `voids.json`, in its order, with their numbers.
fn survivable_voids(js: &Value) -> Result<Vec<(u64, &Value)>, String> {
    let voids = js["voids"]
        .as_array()
        .ok_or_else(|| "has no `voids` list".to_string())?;
    voids
        .iter()
        .filter(|v| v["survivable"] == Value::Bool(true))
        .map(|v| {
            let n = v["void"]
                .as_u64()
                .ok_or_else(|| "a void without its number".to_string())?;
            Ok((n, v))
        })
        .collect()
}

/// The points (m) of a void's route of `kind` (`rescuer`, `camera`), `voids.json`
/// `<kind>.path_m`, void number `n`: `None` when the file has no `path_m` for it (an older
/// analysis); an error names a point that is not x, y, z and a route of fewer than two
/// points.
pub(crate) fn route_points(
    void: &Value,
    kind: &str,
    n: u64,
) -> Result<Option<Vec<[f64; 3]>>, String> {
    let Some(path) = void[kind]["path_m"].as_array() else {
        return Ok(None);
    };
    let points = path
        .iter()
        .map(|p| {
            let xyz: Vec<f64> = p
                .as_array()
                .map(|a| a.iter().filter_map(Value::as_f64).collect())
                .unwrap_or_default();
            <[f64; 3]>::try_from(xyz)
                .map_err(|_| format!("void {n}: `{kind}.path_m` point {p} is not x, y, z"))
        })
        .collect::<Result<Vec<_>, String>>()?;
    if points.len() < 2 {
        return Err(format!(
            "void {n}: `{kind}.path_m` has {} point(s), a route two or more",
            points.len()
        ));
    }
    Ok(Some(points))
}

/// The access routes of the survivable voids of the `voids.json` text `text` (module
/// docs), in its order; none when the file records an error or the ruin has no grid.
/// `Err` names what is wrong (the caller names the file).
pub fn route_lines(text: &str) -> Result<Vec<RouteLine>, String> {
    let Some(js) = analysis(text)? else {
        return Ok(Vec::new());
    };
    let mut out = Vec::new();
    for (n, v) in survivable_voids(&js)? {
        let Some(kind) = ["rescuer", "camera"]
            .into_iter()
            .find(|k| v[*k]["reached"] == Value::Bool(true))
        else {
            continue;
        };
        let access = &v[kind];
        let route_m = access["route_m"]
            .as_f64()
            .filter(|x| x.is_finite())
            .ok_or_else(|| format!("void {n}: {kind}.route_m is not a number"))?;
        let points = route_points(v, kind, n)?.ok_or_else(|| {
            format!(
                "void {n} has no `{kind}.path_m` (its route; the file is of an older analysis: \
                 `fem2rbd voids RUN_DIR` writes it again)"
            )
        })?;
        out.push(RouteLine {
            name: route_name(n, kind, route_m),
            kind: kind.to_string(),
            colour: srgb_to_linear(route_srgb(kind)),
            points,
        });
    }
    Ok(out)
}

/// The survivable voids of the `voids.json` text `text`, in its order (largest first);
/// none when the file records an error or the ruin has no grid. `Err` names what is
/// wrong (the caller names the file).
pub fn survivable_volumes(text: &str) -> Result<Vec<VoidVolume>, String> {
    let Some(js) = analysis(text)? else {
        return Ok(Vec::new());
    };
    let num = |v: &Value, what: &str| {
        v.as_f64()
            .filter(|x| x.is_finite())
            .ok_or_else(|| format!("{what} is not a number"))
    };
    let origin = [0, 1, 2]
        .map(|d| num(&js["grid"]["origin_m"][d], "grid.origin_m"))
        .into_iter()
        .collect::<Result<Vec<f64>, String>>()?;
    let h = num(&js["grid"]["cell_m"], "grid.cell_m")?;
    let mut out = Vec::new();
    for (n, v) in survivable_voids(&js)? {
        let pattern = v["pattern"]
            .as_str()
            .ok_or_else(|| format!("void {n} has no pattern"))?;
        let volume = num(&v["volume_m3"], &format!("void {n}'s volume_m3"))?;
        let boxes = v["boxes"].as_array().ok_or_else(|| {
            format!(
                "void {n} has no `boxes` (its cells; the file is of an older analysis: \
                 `fem2rbd voids RUN_DIR` writes it again)"
            )
        })?;
        let mut bounds = Vec::with_capacity(boxes.len());
        for b in boxes {
            let idx: Vec<u64> = b
                .as_array()
                .filter(|a| a.len() == 6)
                .map(|a| a.iter().filter_map(Value::as_u64).collect())
                .filter(|a: &Vec<u64>| a.len() == 6)
                .ok_or_else(|| format!("void {n}: box {b} is not 6 cell indices"))?;
            if (0..3).any(|d| idx[d] >= idx[d + 3]) {
                return Err(format!("void {n}: box {b} is empty"));
            }
            let at = |d: usize, k: u64| origin[d] + k as f64 * h;
            bounds.push([
                [at(0, idx[0]), at(1, idx[1]), at(2, idx[2])],
                [at(0, idx[3]), at(1, idx[4]), at(2, idx[5])],
            ]);
        }
        out.push(VoidVolume {
            name: node_name(n, pattern, volume),
            pattern: pattern.to_string(),
            colour: srgb_to_linear(pattern_srgb(pattern)),
            boxes: bounds,
        });
    }
    Ok(out)
}

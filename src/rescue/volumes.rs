//! The survivable voids of a `voids.json` as the static volumes of `collapse.glb`
//! ([`crate::output::gltf::VoidVolume`]): each survivable void's cells as the boxes of
//! `voids.json` (`boxes`, [`super::boxes`]), named `void-NN <pattern> <volume> m3` (its
//! number in `voids.csv`, its pattern, its volume at the model's scale), coloured as its
//! pattern in the void figures and the report ([`crate::output::palette::pattern_srgb`],
//! in linear light).
//!
//! Read from the file's text, so that `fem2rbd run`, `fem2rbd voids` and `fem2rbd export
//! gltf` put the same nodes into the same bytes.
use crate::output::gltf::VoidVolume;
use crate::output::palette::{pattern_srgb, srgb_to_linear};
use serde_json::Value;

/// The node name of void `number` (1 = largest).
pub fn node_name(number: u64, pattern: &str, volume_m3: f64) -> String {
    format!("void-{number:02} {pattern} {volume_m3:.4} m3")
}

/// The survivable voids of the `voids.json` text `text`, in its order (largest first);
/// none when the file records an error or the ruin has no grid. `Err` names what is
/// wrong (the caller names the file).
pub fn survivable_volumes(text: &str) -> Result<Vec<VoidVolume>, String> {
    let js: Value = serde_json::from_str(text).map_err(|e| format!("not JSON: {e}"))?;
    if js.get("error").is_some() || js["grid"].is_null() {
        return Ok(Vec::new());
    }
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
    let voids = js["voids"]
        .as_array()
        .ok_or_else(|| "has no `voids` list".to_string())?;
    let mut out = Vec::new();
    for v in voids {
        if v["survivable"] != Value::Bool(true) {
            continue;
        }
        let n = v["void"]
            .as_u64()
            .ok_or_else(|| "a void without its number".to_string())?;
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

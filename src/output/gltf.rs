//! Animated glTF 2.0 binary (`.glb`) of the bodies' motion: one file that Blender, three.js
//! and other viewers open and play.
//!
//! Layout of the file (glTF 2.0 specification, Khronos, §4.4 "Binary glTF layout"):
//!
//! * a 12-byte header (`glTF`, version 2, total length), a JSON chunk padded with spaces
//!   and a BIN chunk padded with zeros, each to a 4-byte boundary, all little-endian;
//! * **one shared box geometry**: a cube with corners at ±1 (24 vertices so that every
//!   face has its own flat normal, 36 `u16` indices). Each body's node carries
//!   `scale = half_extents`, so the cube becomes the body's box (node transform
//!   T·R·S, spec §3.5.3: the scale acts in the body's own frame, before its rotation).
//!   The geometry's accessors are shared by one mesh per element type, because in glTF the
//!   material belongs to the mesh primitive: mesh *i* = the cube with material *i*;
//! * **one PBR material per element type** (`AnimBody::type_name`, e.g. `Column`, `Beam`,
//!   `Slab`), with a fixed colour ([`type_colour`]), plus `Ground` for the ground box;
//! * **one node per body**, then one for the ground, then one static node per void of
//!   the ruin ([`VoidVolume`]: its boxes as one triangle mesh with `u32` indices, a
//!   translucent material per collapse pattern, alpha mode `BLEND`), then one static node
//!   per access route ([`RouteLine`]: a `LINES` primitive through its points, `u32`
//!   indices, one material per kind of route), all children of a root node;
//! * **one animation** with a `translation` and a `rotation` channel per body (and for the
//!   ground when it moves), LINEAR interpolation, all sharing one input accessor of the
//!   keyframe times (s) with its min/max. Rotations are written as glTF `x, y, z, w`
//!   normalised quaternions; consecutive keyframes have a non-negative dot product (the
//!   sign of each is chosen against the previous one), so the viewers' slerp takes the
//!   short way between keyframes, as the simulation did.
//!
//! **Axes.** Our data are Z-up, SI metres; glTF is Y-up (spec §3.4: "+Y is up"). The data
//! are written unchanged and the root node `Z-up to Y-up` carries the rotation of −90°
//! about X (quaternion `x, y, z, w = −√½, 0, 0, √½`), which maps our +Z to glTF +Y and our
//! +Y to glTF −Z — the same convention as Blender's glTF exporter. A viewer that
//! re-parents the bodies therefore sees the original Z-up numbers in each node.
//!
//! **Precision.** glTF stores keyframes as 32-bit floats: positions keep ~7 significant
//! digits (0.5 µm at 5 m, 0.1 mm at 1 km from the origin) and times must stay strictly
//! increasing once rounded to f32 (checked). The nodes' own rest pose and scale are JSON
//! numbers, written in full f64 precision.
//!
//! The output is deterministic: same scene, same bytes (materials are ordered by type
//! name, everything else in input order; `serde_json` writes the JSON).
//!
//! Checked by tests/it/output/gltf_roundtrip.rs (own GLB reader), tests/it/output/gltf_validator.rs (Khronos
//! validator: no errors, no warnings) and tests/it/output/gltf_three.rs (three.js plays the file);
//! [`run_scene`] (a run's timeline) by tests/it/output/gltf_export.rs.
use crate::output::error::{scene_bail as bail, scene_ensure as ensure};
use crate::output::run_folder::BodyInfo;
use crate::output::AtomicFile;
use crate::output::{AnimationError, OutputError};

/// What writing a scene returns.
type Result<T> = std::result::Result<T, AnimationError>;
use serde_json::{json, Map, Value};
use std::collections::BTreeMap;
use std::io::Write;
use std::path::Path;

/// A body pose at one keyframe ([`crate::bullet::Pose`]): position of the box centre (m,
/// Z-up world frame) and the unit quaternion `[w, x, y, z]` that rotates the body frame
/// into the world frame. The quaternion need not be normalised nor sign-continuous; the
/// writer does both.
pub use crate::bullet::Pose;

/// The element type given to the ground box's material.
pub(crate) const GROUND_TYPE: &str = "Ground";

/// Name of the root node that turns our Z-up frame into glTF's Y-up frame.
pub const ROOT_NODE_NAME: &str = "Z-up to Y-up";

/// One rigid box and its motion.
#[derive(Debug, Clone, PartialEq)]
pub struct AnimBody {
    /// Node name shown by viewers (e.g. the element id).
    pub name: String,
    /// Element type (`Column`, `Beam`, `Slab`, …): one material, one colour per type.
    pub type_name: String,
    /// Half sizes of the box along its own x, y, z axes (m), all > 0.
    pub half_extents: [f64; 3],
    /// One pose per entry of [`AnimatedScene::times_s`].
    pub poses: Vec<Pose>,
}

/// The ground: a flat box, either fixed or moving (an earthquake's ground motion).
#[derive(Debug, Clone, PartialEq)]
pub struct GroundBox {
    /// Half sizes of the box (m), all > 0; its top face is at `position.z + half_extents[2]`.
    pub half_extents: [f64; 3],
    /// Either one pose (a fixed ground) or one per entry of [`AnimatedScene::times_s`].
    pub poses: Vec<Pose>,
}

/// A void of the ruin as a static, translucent volume: boxes of free space under debris
/// (a survivable void of the rescue analysis, its cells merged into boxes; docs/rescue.md
/// §3).
#[derive(Debug, Clone, PartialEq)]
pub struct VoidVolume {
    /// Node name shown by viewers (e.g. `void-03 v 0.0927 m3`).
    pub name: String,
    /// Its collapse pattern: one material per pattern, named `void <pattern>`.
    pub pattern: String,
    /// Base colour of the pattern's material, linear RGB 0..1.
    pub colour: [f32; 3],
    /// The boxes, each `[min, max]` corner, m, in the data's Z-up frame.
    pub boxes: Vec<[[f64; 3]; 2]>,
}

/// An access route of the ruin as a static line: the route a rescuer or a search camera
/// takes from open air to a survivable void (docs/rescue.md §2, "Routes as lines").
#[derive(Debug, Clone, PartialEq)]
pub struct RouteLine {
    /// Node name shown by viewers (e.g. `route-03 rescuer 0.500 m`).
    pub name: String,
    /// Who takes it (`rescuer`, `camera`): one material per kind, named `route <kind>`.
    pub kind: String,
    /// Base colour of the kind's material, linear RGB 0..1.
    pub colour: [f32; 3],
    /// The line's points in order (at least two), m, in the data's Z-up frame.
    pub points: Vec<[f64; 3]>,
}

/// Opacity of a void's material ([`VoidVolume`]; alpha mode `BLEND`).
pub const VOID_ALPHA: f32 = 0.45;

/// Everything one animated glTF shows.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct AnimatedScene {
    /// The boxes, one node each, in this order.
    pub bodies: Vec<AnimBody>,
    /// The ground box (material [`GROUND_TYPE`]), if any.
    pub ground: Option<GroundBox>,
    /// Keyframe times (s): at least one, `>= 0`, strictly increasing (also once rounded to
    /// `f32`, glTF's time type).
    pub times_s: Vec<f64>,
    /// Voids of the final ruin, one static node each after the ground (none: no node).
    pub voids: Vec<VoidVolume>,
    /// Access routes of the final ruin, one static node each after the voids.
    pub routes: Vec<RouteLine>,
}

/// Writes `scene` as one glTF 2.0 binary file at `path`, atomically (never a half file).
pub fn write_glb(scene: &AnimatedScene, path: impl AsRef<Path>) -> Result<()> {
    let path = path.as_ref();
    let bytes = encode_glb(scene).map_err(|error| AnimationError::Gltf {
        path: path.to_path_buf(),
        error: Box::new(error),
    })?;
    let mut file = AtomicFile::create(path)?;
    file.write_all(&bytes)
        .map_err(OutputError::io("cannot write", path))?;
    Ok(file.commit()?)
}

/// The bytes of the `.glb` file [`write_glb`] writes.
pub fn encode_glb(scene: &AnimatedScene) -> Result<Vec<u8>> {
    let times = check_times(&scene.times_s)?;
    ensure!(
        !scene.bodies.is_empty() || scene.ground.is_some(),
        "the scene has no bodies and no ground: nothing to draw"
    );
    let mut bin = BinBuilder::default();

    // Shared box geometry.
    let (positions, normals, indices) = unit_box();
    let position = bin.push_f32(&positions, 3, Some(ARRAY_BUFFER), true);
    let normal = bin.push_f32(&normals, 3, Some(ARRAY_BUFFER), false);
    let index = bin.push_u16_indices(&indices);

    // One material and one mesh per element type, ordered by name.
    let mut types: BTreeMap<&str, usize> = BTreeMap::new();
    for (i, body) in scene.bodies.iter().enumerate() {
        ensure!(
            !body.type_name.trim().is_empty(),
            "body '{}' (#{i}) has an empty type_name",
            body.name
        );
        types.insert(body.type_name.as_str(), 0);
    }
    if scene.ground.is_some() {
        types.insert(GROUND_TYPE, 0);
    }
    let mut materials = Vec::new();
    let mut meshes = Vec::new();
    for (k, (name, slot)) in types.iter_mut().enumerate() {
        *slot = k;
        let [r, g, b] = type_colour(name);
        materials.push(json!({
            "name": name,
            "pbrMetallicRoughness": {
                "baseColorFactor": [r, g, b, 1.0],
                "metallicFactor": 0.0,
                "roughnessFactor": 0.9
            }
        }));
        meshes.push(json!({
            "name": format!("box {name}"),
            "primitives": [{
                "attributes": { "POSITION": position, "NORMAL": normal },
                "indices": index,
                "material": k,
                "mode": 4
            }]
        }));
    }

    // Nodes: 0 is the root, then the bodies, then the ground; the animation channels.
    let animated =
        !scene.bodies.is_empty() || scene.ground.as_ref().is_some_and(|g| g.poses.len() > 1);
    let time_accessor = if animated {
        bin.push_f32(&times, 1, None, true)
    } else {
        usize::MAX // never referenced: no channel is written
    };
    let mut nodes = vec![Value::Null];
    let mut samplers = Vec::new();
    let mut channels = Vec::new();
    for (i, body) in scene.bodies.iter().enumerate() {
        let label = format!("body '{}' (#{i})", body.name);
        ensure!(
            body.poses.len() == times.len(),
            "{label} has {} poses but the scene has {} keyframe times",
            body.poses.len(),
            times.len()
        );
        let node = nodes.len();
        let track = Track::new(&body.poses, &scene.times_s, &label)?;
        nodes.push(box_node(
            &body.name,
            types[body.type_name.as_str()],
            body.half_extents,
            &track,
            &label,
        )?);
        track.animate(node, time_accessor, &mut bin, &mut samplers, &mut channels);
    }
    if let Some(ground) = &scene.ground {
        let label = "the ground".to_string();
        ensure!(
            ground.poses.len() == 1 || ground.poses.len() == times.len(),
            "{label} has {} poses; give 1 (fixed ground) or one per keyframe time ({})",
            ground.poses.len(),
            times.len()
        );
        let node = nodes.len();
        let track = Track::new(&ground.poses, &scene.times_s, &label)?;
        nodes.push(box_node(
            "ground",
            types[GROUND_TYPE],
            ground.half_extents,
            &track,
            &label,
        )?);
        if track.translations.len() > 1 {
            track.animate(node, time_accessor, &mut bin, &mut samplers, &mut channels);
        }
    }
    // The voids: one material per pattern (ordered by name, after the types'), one mesh
    // and one static node per void.
    for v in &scene.voids {
        ensure!(
            !v.boxes.is_empty(),
            "void '{}' has no boxes: nothing to draw",
            v.name
        );
    }
    let patterns = materials_by_name(
        scene.voids.iter().map(|v| (v.pattern.as_str(), v.colour)),
        &mut materials,
        |name, c| {
            json!({
                "name": format!("void {name}"),
                "pbrMetallicRoughness": {
                    "baseColorFactor": [c[0], c[1], c[2], VOID_ALPHA],
                    "metallicFactor": 0.0,
                    "roughnessFactor": 1.0
                },
                "alphaMode": "BLEND"
            })
        },
    );
    for v in &scene.voids {
        let (positions, normals, indices) = boxes_mesh(&v.boxes);
        let position = bin.push_f32(&positions, 3, Some(ARRAY_BUFFER), true);
        let normal = bin.push_f32(&normals, 3, Some(ARRAY_BUFFER), false);
        let index = bin.push_u32_indices(&indices);
        meshes.push(json!({
            "name": v.name,
            "primitives": [{
                "attributes": { "POSITION": position, "NORMAL": normal },
                "indices": index,
                "material": patterns[v.pattern.as_str()],
                "mode": 4
            }]
        }));
        nodes.push(json!({ "name": v.name, "mesh": meshes.len() - 1 }));
    }
    // The routes: one material per kind (ordered by name, after the voids'), one mesh of
    // `LINES` (mode 1: segments between the index pairs 0–1, 1–2, …) and one static node
    // per route.
    for r in &scene.routes {
        ensure!(
            r.points.len() >= 2,
            "route '{}' has {} point(s): a line needs two",
            r.name,
            r.points.len()
        );
    }
    let kinds = materials_by_name(
        scene.routes.iter().map(|r| (r.kind.as_str(), r.colour)),
        &mut materials,
        |name, c| {
            json!({
                "name": format!("route {name}"),
                "pbrMetallicRoughness": {
                    "baseColorFactor": [c[0], c[1], c[2], 1.0],
                    "metallicFactor": 0.0,
                    "roughnessFactor": 1.0
                }
            })
        },
    );
    for r in &scene.routes {
        let positions: Vec<f32> = r.points.iter().flatten().map(|&c| c as f32).collect();
        let position = bin.push_f32(&positions, 3, Some(ARRAY_BUFFER), true);
        let indices: Vec<u32> = (1..r.points.len() as u32)
            .flat_map(|i| [i - 1, i])
            .collect();
        let index = bin.push_u32_indices(&indices);
        meshes.push(json!({
            "name": r.name,
            "primitives": [{
                "attributes": { "POSITION": position },
                "indices": index,
                "material": kinds[r.kind.as_str()],
                "mode": 1
            }]
        }));
        nodes.push(json!({ "name": r.name, "mesh": meshes.len() - 1 }));
    }

    let half = std::f64::consts::FRAC_1_SQRT_2;
    let mut root = json!({
        "name": ROOT_NODE_NAME,
        "rotation": [-half, 0.0, 0.0, half],
        "extras": { "note": "data are Z-up, SI metres and seconds; this node rotates them -90 deg about X into glTF's Y-up frame" }
    });
    if nodes.len() > 1 {
        root["children"] = json!((1..nodes.len()).collect::<Vec<_>>());
    }
    nodes[0] = root;

    let mut doc = json!({
        "asset": { "version": "2.0", "generator": concat!("fem2rbd ", env!("CARGO_PKG_VERSION")) },
        "scene": 0,
        "scenes": [{ "name": "fem2rbd", "nodes": [0] }],
        "nodes": nodes,
        "meshes": meshes,
        "materials": materials,
    });
    if animated {
        doc["animations"] =
            json!([{ "name": "motion", "samplers": samplers, "channels": channels }]);
    }
    let BinBuilder {
        mut data,
        views,
        accessors,
    } = bin;
    pad_to_4(&mut data, 0);
    doc["buffers"] = json!([{ "byteLength": data.len() }]);
    doc["bufferViews"] = Value::Array(views);
    doc["accessors"] = Value::Array(accessors);

    let mut json_chunk = serde_json::to_vec(&doc).map_err(|e| OutputError::Encode {
        what: "cannot serialise the glTF JSON".into(),
        message: e.to_string(),
    })?;
    pad_to_4(&mut json_chunk, b' ');
    let total = 12 + 8 + json_chunk.len() + 8 + data.len();
    let Ok(total_u32) = u32::try_from(total) else {
        bail!("glTF binary would be {total} bytes, over the 4 GiB GLB limit");
    };

    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(&GLB_MAGIC.to_le_bytes());
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&total_u32.to_le_bytes());
    out.extend_from_slice(&(json_chunk.len() as u32).to_le_bytes());
    out.extend_from_slice(&CHUNK_JSON.to_le_bytes());
    out.extend_from_slice(&json_chunk);
    out.extend_from_slice(&(data.len() as u32).to_le_bytes());
    out.extend_from_slice(&CHUNK_BIN.to_le_bytes());
    out.extend_from_slice(&data);
    Ok(out)
}

/// Half thickness of the ground slab of [`run_scene`], m.
pub(crate) const RUN_GROUND_HALF_THICKNESS_M: f64 = 0.05;

/// Margin of the ground slab of [`run_scene`] around the bodies' plan extent, m.
pub(crate) const RUN_GROUND_MARGIN_M: f64 = 2.0;

/// The animated scene of a run's timeline (what `collapse.glb` shows; used by
/// `fem2rbd run` and by `fem2rbd export gltf`, which rebuilds it from a run folder):
///
/// * one box per body of `bodies` (node name = body name, material = its type, scale =
///   its half extents) with the poses of `frames` (time s, one pose per body in body
///   order); a frame whose time rounds to the same `f32` as the previous one is left out
///   (glTF times must increase strictly in `f32`);
/// * a ground slab, half extents (a_x/2 + m, a_y/2 + m, t) with margin
///   m = [`RUN_GROUND_MARGIN_M`] and t = [`RUN_GROUND_HALF_THICKNESS_M`], where a is the
///   size of the box around the bodies' undeformed centres ± their largest half extent;
///   its top at the base level (the highest top of a passive body, else the bottom of
///   that box), centred under the bodies, moved at each frame by `ground_m` (the ground
///   displacement, m, one per frame).
pub fn run_scene(
    bodies: &[BodyInfo],
    frames: &[(f64, Vec<crate::bullet::Pose>)],
    ground_m: &[[f64; 3]],
) -> Result<AnimatedScene> {
    ensure!(
        ground_m.len() == frames.len(),
        "{} ground displacements for {} frames",
        ground_m.len(),
        frames.len()
    );
    let mut times: Vec<f64> = Vec::new();
    let mut keep: Vec<usize> = Vec::new();
    for (k, (t, poses)) in frames.iter().enumerate() {
        ensure!(
            poses.len() == bodies.len(),
            "frame {k} (t = {t} s) has {} poses for {} bodies",
            poses.len(),
            bodies.len()
        );
        if times.last().is_none_or(|p| (*t as f32) > (*p as f32)) {
            times.push(*t);
            keep.push(k);
        }
    }
    let anim = bodies
        .iter()
        .enumerate()
        .map(|(i, b)| AnimBody {
            name: b.id.name(),
            type_name: b.id.type_name().to_string(),
            half_extents: b.half_extents,
            poses: keep.iter().map(|&k| frames[k].1[i]).collect(),
        })
        .collect();
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for b in bodies {
        let r = b.half_extents.iter().copied().fold(0.0, f64::max);
        for k in 0..3 {
            lo[k] = lo[k].min(b.pose0.position[k] - r);
            hi[k] = hi[k].max(b.pose0.position[k] + r);
        }
    }
    let ground = if bodies.is_empty() {
        None
    } else {
        let he = [
            (hi[0] - lo[0]) / 2.0 + RUN_GROUND_MARGIN_M,
            (hi[1] - lo[1]) / 2.0 + RUN_GROUND_MARGIN_M,
            RUN_GROUND_HALF_THICKNESS_M,
        ];
        let base_z = bodies
            .iter()
            .filter(|b| b.passive)
            .map(|b| b.pose0.position[2] + b.half_extents[2])
            .fold(lo[2], f64::max);
        let c = [
            (lo[0] + hi[0]) / 2.0,
            (lo[1] + hi[1]) / 2.0,
            base_z - RUN_GROUND_HALF_THICKNESS_M,
        ];
        Some(GroundBox {
            half_extents: he,
            poses: keep
                .iter()
                .map(|&k| {
                    let d = ground_m[k];
                    Pose::at([c[0] + d[0], c[1] + d[1], c[2] + d[2]])
                })
                .collect(),
        })
    };
    Ok(AnimatedScene {
        bodies: anim,
        ground,
        times_s: times,
        voids: Vec::new(),
        routes: Vec::new(),
    })
}

/// Appends one material per distinct name of `items` to `materials`, in name order, each
/// made by `make` from the name and the colour of the first item of that name, and returns
/// each name's material index.
fn materials_by_name<'a>(
    items: impl Iterator<Item = (&'a str, [f32; 3])>,
    materials: &mut Vec<Value>,
    make: impl Fn(&str, [f32; 3]) -> Value,
) -> BTreeMap<&'a str, usize> {
    let mut colours: BTreeMap<&str, [f32; 3]> = BTreeMap::new();
    for (name, colour) in items {
        colours.entry(name).or_insert(colour);
    }
    colours
        .into_iter()
        .map(|(name, colour)| {
            materials.push(make(name, colour));
            (name, materials.len() - 1)
        })
        .collect()
}

/// Base colour (linear RGB, 0..1) of an element type's material: the shared colour
/// table ([`crate::output::palette`]) in linear light.
pub fn type_colour(type_name: &str) -> [f32; 3] {
    crate::output::palette::srgb_to_linear(crate::output::palette::type_srgb(type_name))
}

/// The shared box: a cube with corners at (±1, ±1, ±1), 4 vertices per face (24) so
/// each face has its own outward normal, and 2 counter-clockwise triangles per face seen
/// from outside (glTF front faces, spec §3.7.2.1). Returns flat xyz positions, flat xyz
/// normals and the triangle indices.
pub(crate) fn unit_box() -> (Vec<f32>, Vec<f32>, Vec<u16>) {
    let mut positions = Vec::with_capacity(72);
    let mut normals = Vec::with_capacity(72);
    let mut indices = Vec::with_capacity(36);
    for axis in 0..3 {
        // (u, v, axis) is a cyclic permutation of (x, y, z), so e_u × e_v = e_axis.
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        for sign in [1.0f32, -1.0] {
            let first = (positions.len() / 3) as u16;
            for (cu, cv) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                let mut p = [0.0f32; 3];
                p[axis] = sign;
                p[u] = cu;
                p[v] = cv;
                positions.extend_from_slice(&p);
                let mut n = [0.0f32; 3];
                n[axis] = sign;
                normals.extend_from_slice(&n);
            }
            let quad: [u16; 6] = if sign > 0.0 {
                [0, 1, 2, 0, 2, 3]
            } else {
                [0, 2, 1, 0, 3, 2]
            };
            indices.extend(quad.iter().map(|k| first + k));
        }
    }
    (positions, normals, indices)
}

/// One triangle mesh of axis-aligned boxes (`[min, max]` corners, m): the faces of
/// [`unit_box`] for each box, placed and sized, their normals unchanged (flat, outward).
/// Returns flat xyz positions, flat xyz normals and the triangle indices.
fn boxes_mesh(boxes: &[[[f64; 3]; 2]]) -> (Vec<f32>, Vec<f32>, Vec<u32>) {
    let (up, un, ui) = unit_box();
    let mut positions = Vec::with_capacity(boxes.len() * up.len());
    let mut normals = Vec::with_capacity(boxes.len() * un.len());
    let mut indices = Vec::with_capacity(boxes.len() * ui.len());
    for b in boxes {
        let first = (positions.len() / 3) as u32;
        for corner in up.chunks_exact(3) {
            for d in 0..3 {
                let c = 0.5 * (b[0][d] + b[1][d]);
                let h = 0.5 * (b[1][d] - b[0][d]);
                positions.push((c + h * f64::from(corner[d])) as f32);
            }
        }
        normals.extend_from_slice(&un);
        indices.extend(ui.iter().map(|&k| first + u32::from(k)));
    }
    (positions, normals, indices)
}

/// Converts one pose's quaternion `[w, x, y, z]` to glTF order `[x, y, z, w]`, normalised,
/// with its sign chosen so that its dot product with `previous` (glTF order) is >= 0.
pub(crate) fn gltf_rotation(q_wxyz: [f64; 4], previous: Option<[f64; 4]>) -> Option<[f64; 4]> {
    let [w, x, y, z] = q_wxyz;
    let norm = (w * w + x * x + y * y + z * z).sqrt();
    if !norm.is_finite() || norm < 1e-12 {
        return None;
    }
    let mut q = [x / norm, y / norm, z / norm, w / norm];
    if let Some(p) = previous {
        if p.iter().zip(&q).map(|(a, b)| a * b).sum::<f64>() < 0.0 {
            q = q.map(|c| -c);
        }
    }
    Some(q)
}

const GLB_MAGIC: u32 = 0x4654_6C67; // "glTF"
const CHUNK_JSON: u32 = 0x4E4F_534A; // "JSON"
const CHUNK_BIN: u32 = 0x004E_4942; // "BIN\0"
const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;
const FLOAT: u32 = 5126;
const UNSIGNED_SHORT: u32 = 5123;
const UNSIGNED_INT: u32 = 5125;

/// Keyframe times as f32, checked: non-empty, finite, >= 0, strictly increasing in f32.
fn check_times(times_s: &[f64]) -> Result<Vec<f32>> {
    ensure!(!times_s.is_empty(), "the scene has no keyframe times");
    let mut out: Vec<f32> = Vec::with_capacity(times_s.len());
    for (k, &t) in times_s.iter().enumerate() {
        ensure!(
            t.is_finite() && t >= 0.0,
            "keyframe time times_s[{k}] = {t} s must be finite and >= 0"
        );
        let t32 = t as f32;
        if let Some(&prev) = out.last() {
            if t32 <= prev {
                bail!(
                    "keyframe times must increase strictly: times_s[{k}] = {t} s follows \
                     times_s[{}] = {} s (compared as f32, glTF's time type)",
                    k - 1,
                    times_s[k - 1]
                );
            }
        }
        out.push(t32);
    }
    Ok(out)
}

/// One node's keyframes, converted to glTF's f32 and checked.
struct Track {
    translations: Vec<[f32; 3]>,
    rotations: Vec<[f32; 4]>,
    /// The first pose in full precision (glTF order, normalised) for the node's own TRS.
    first: ([f64; 3], [f64; 4]),
}

impl Track {
    fn new(poses: &[Pose], times_s: &[f64], label: &str) -> Result<Self> {
        ensure!(!poses.is_empty(), "{label} has no poses");
        let mut translations = Vec::with_capacity(poses.len());
        let mut rotations = Vec::with_capacity(poses.len());
        let mut previous = None;
        let mut first = None;
        for (k, pose) in poses.iter().enumerate() {
            let (p, q) = (&pose.position, &pose.orientation);
            let at = || format!("{label} at keyframe {k} (t = {} s)", times_s[k]);
            let p32 = p.map(|c| c as f32);
            ensure!(
                p32.iter().all(|c| c.is_finite()),
                "{}: position {p:?} m is not finite in f32",
                at()
            );
            let Some(r) = gltf_rotation(*q, previous) else {
                bail!("{}: quaternion {q:?} is zero or not finite", at());
            };
            previous = Some(r);
            first.get_or_insert((*p, r));
            translations.push(p32);
            rotations.push(r.map(|c| c as f32));
        }
        Ok(Self {
            translations,
            rotations,
            first: first.expect("at least one pose"),
        })
    }

    /// Adds the translation and rotation samplers and channels of node `node`.
    fn animate(
        &self,
        node: usize,
        input: usize,
        bin: &mut BinBuilder,
        samplers: &mut Vec<Value>,
        channels: &mut Vec<Value>,
    ) {
        let t: Vec<f32> = self.translations.iter().flatten().copied().collect();
        let r: Vec<f32> = self.rotations.iter().flatten().copied().collect();
        for (path, output) in [
            ("translation", bin.push_f32(&t, 3, None, false)),
            ("rotation", bin.push_f32(&r, 4, None, false)),
        ] {
            channels.push(
                json!({ "sampler": samplers.len(), "target": { "node": node, "path": path } }),
            );
            samplers.push(json!({ "input": input, "output": output, "interpolation": "LINEAR" }));
        }
    }
}

/// A body or ground node: the box mesh of its type, scaled to its half extents, placed
/// at its first pose (what a viewer shows when the animation is not playing).
fn box_node(
    name: &str,
    mesh: usize,
    half_extents: [f64; 3],
    track: &Track,
    label: &str,
) -> Result<Value> {
    ensure!(
        half_extents
            .iter()
            .all(|&h| h > 0.0 && (h as f32).is_finite() && (h as f32) > 0.0),
        "{label}: half_extents {half_extents:?} m must be finite and > 0"
    );
    // The node's own numbers are JSON doubles: written in full precision.
    Ok(json!({
        "name": name,
        "mesh": mesh,
        "translation": track.first.0,
        "rotation": track.first.1,
        "scale": half_extents,
    }))
}

/// The BIN chunk being built, with its buffer views and accessors (one view per accessor,
/// each starting on a 4-byte boundary).
#[derive(Default)]
struct BinBuilder {
    data: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl BinBuilder {
    fn push_view(&mut self, bytes: &[u8], target: Option<u32>) -> usize {
        pad_to_4(&mut self.data, 0);
        let mut view = Map::new();
        view.insert("buffer".into(), json!(0));
        view.insert("byteOffset".into(), json!(self.data.len()));
        view.insert("byteLength".into(), json!(bytes.len()));
        if let Some(target) = target {
            view.insert("target".into(), json!(target));
        }
        self.data.extend_from_slice(bytes);
        self.views.push(Value::Object(view));
        self.views.len() - 1
    }

    /// Adds an accessor of `values.len() / components` f32 elements of `components`
    /// components (SCALAR, VEC3 or VEC4); with `min_max`, their per-component bounds.
    fn push_f32(
        &mut self,
        values: &[f32],
        components: usize,
        target: Option<u32>,
        min_max: bool,
    ) -> usize {
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.push_view(&bytes, target);
        let kind = match components {
            1 => "SCALAR",
            3 => "VEC3",
            4 => "VEC4",
            _ => unreachable!("no accessor of {components} components is written"),
        };
        let mut accessor = json!({
            "bufferView": view,
            "componentType": FLOAT,
            "count": values.len() / components,
            "type": kind,
        });
        if min_max {
            let mut min = vec![f32::INFINITY; components];
            let mut max = vec![f32::NEG_INFINITY; components];
            for element in values.chunks_exact(components) {
                for (c, &v) in element.iter().enumerate() {
                    min[c] = min[c].min(v);
                    max[c] = max[c].max(v);
                }
            }
            // f32 -> f64 is exact, so the JSON numbers read back as the very f32 bounds.
            accessor["min"] = json!(min.iter().map(|&v| f64::from(v)).collect::<Vec<_>>());
            accessor["max"] = json!(max.iter().map(|&v| f64::from(v)).collect::<Vec<_>>());
        }
        self.accessors.push(accessor);
        self.accessors.len() - 1
    }

    fn push_u32_indices(&mut self, indices: &[u32]) -> usize {
        let bytes: Vec<u8> = indices.iter().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.push_view(&bytes, Some(ELEMENT_ARRAY_BUFFER));
        self.accessors.push(json!({
            "bufferView": view,
            "componentType": UNSIGNED_INT,
            "count": indices.len(),
            "type": "SCALAR",
        }));
        self.accessors.len() - 1
    }

    fn push_u16_indices(&mut self, indices: &[u16]) -> usize {
        let bytes: Vec<u8> = indices.iter().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.push_view(&bytes, Some(ELEMENT_ARRAY_BUFFER));
        self.accessors.push(json!({
            "bufferView": view,
            "componentType": UNSIGNED_SHORT,
            "count": indices.len(),
            "type": "SCALAR",
        }));
        self.accessors.len() - 1
    }
}

fn pad_to_4(bytes: &mut Vec<u8>, fill: u8) {
    while bytes.len() % 4 != 0 {
        bytes.push(fill);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_faces_are_flat_outward_and_counter_clockwise() {
        let (p, n, idx) = unit_box();
        assert_eq!((p.len(), n.len(), idx.len()), (72, 72, 36));
        let v = |i: u16| {
            [
                p[3 * i as usize],
                p[3 * i as usize + 1],
                p[3 * i as usize + 2],
            ]
        };
        for tri in idx.chunks_exact(3) {
            let (a, b, c) = (v(tri[0]), v(tri[1]), v(tri[2]));
            let e1 = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            let e2 = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
            let cross = [
                e1[1] * e2[2] - e1[2] * e2[1],
                e1[2] * e2[0] - e1[0] * e2[2],
                e1[0] * e2[1] - e1[1] * e2[0],
            ];
            for &k in tri {
                let nk = &n[3 * k as usize..3 * k as usize + 3];
                // Geometric normal of a triangle of half a 2x2 face has length 4.
                let dot: f32 = cross.iter().zip(nk).map(|(x, y)| x * y).sum();
                assert_eq!(dot, 4.0, "triangle {tri:?}");
                // The vertex lies on the face its normal points out of.
                let pk = v(k);
                let on_face: f32 = pk.iter().zip(nk).map(|(x, y)| x * y).sum();
                assert_eq!(on_face, 1.0);
            }
        }
    }

    #[test]
    fn rotation_is_reordered_normalised_and_sign_continuous() {
        // 90 deg about z, given unnormalised and with w first.
        let q = gltf_rotation([2.0, 0.0, 0.0, 2.0], None).unwrap();
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let close = |a: [f64; 4], b: [f64; 4]| a.iter().zip(&b).all(|(x, y)| (x - y).abs() < 1e-15);
        assert!(close(q, [0.0, 0.0, h, h]), "{q:?}");
        // The same rotation with the opposite sign is flipped back next to q.
        let q2 = gltf_rotation([-h, 0.0, 0.0, -h], Some(q)).unwrap();
        assert!(close(q2, q), "{q2:?}");
        assert!(gltf_rotation([0.0; 4], None).is_none());
        assert!(gltf_rotation([f64::NAN, 0.0, 0.0, 1.0], None).is_none());
    }
}

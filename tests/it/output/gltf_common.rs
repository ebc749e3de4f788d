//! Shared by the glTF tests: a scene of boxes on closed-form trajectories, and an
//! independent reader of the `.glb` container (header, JSON chunk, BIN chunk, accessors).
#![allow(dead_code)]

use fem2rbd::output::gltf::{AnimBody, AnimatedScene, GroundBox, Pose};
use serde_json::Value;

/// Gravity (m/s²) of the falling boxes.
pub const G: f64 = 9.81;

/// Body `i`'s closed-form motion: thrown from a grid point with a constant horizontal
/// velocity, falling under gravity, `z(t) = z0 + vz t − g t²/2`, and spinning at a
/// constant rate ω about a fixed unit axis, `q(t) = [cos(ωt/2), sin(ωt/2) a]`.
#[derive(Debug, Clone, Copy)]
pub struct Throw {
    pub p0: [f64; 3],
    pub v0: [f64; 3],
    pub axis: [f64; 3],
    pub omega_rad_s: f64,
}

impl Throw {
    pub fn of_body(i: usize) -> Self {
        let fi = i as f64;
        let axis = [1.0 + 0.3 * fi, -0.5 + 0.1 * fi, 2.0 - 0.05 * fi];
        let n = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
        Self {
            p0: [
                (i % 6) as f64 * 1.5 - 3.75,
                (i / 6) as f64 * 1.5 - 3.0,
                3.0 + 0.4 * fi,
            ],
            v0: [0.3 * (fi - 15.0) / 15.0, 0.2, 1.0 + 0.05 * fi],
            axis: axis.map(|c| c / n),
            // Up to ~13 rad/s: many turns over the 2 s, so q(t) changes sign repeatedly.
            omega_rad_s: 2.0 + 0.4 * fi,
        }
    }

    pub fn position(&self, t: f64) -> [f64; 3] {
        [
            self.p0[0] + self.v0[0] * t,
            self.p0[1] + self.v0[1] * t,
            self.p0[2] + self.v0[2] * t - 0.5 * G * t * t,
        ]
    }

    /// The rotation `[w, x, y, z]` at time `t`, continuous in time.
    pub fn quaternion(&self, t: f64) -> [f64; 4] {
        let half = 0.5 * self.omega_rad_s * t;
        let s = half.sin();
        [
            half.cos(),
            s * self.axis[0],
            s * self.axis[1],
            s * self.axis[2],
        ]
    }

    /// The same rotation as a physics engine may report it: sign chosen so that w >= 0,
    /// which makes the quaternion jump sign between keyframes; also scaled by a
    /// non-unit factor, which the writer must normalise away.
    pub fn reported_quaternion(&self, t: f64) -> [f64; 4] {
        let q = self.quaternion(t);
        let sign = if q[0] < 0.0 { -1.0 } else { 1.0 };
        q.map(|c| c * sign * 1.25)
    }
}

/// `n` times evenly spaced over [0, `duration_s`] (just 0 when `n` is 1).
pub fn times(n: usize, duration_s: f64) -> Vec<f64> {
    (0..n)
        .map(|k| duration_s * k as f64 / (n.max(2) - 1) as f64)
        .collect()
}

/// Ground motion of the moving ground (m): `x(t) = 0.1 sin(2π · 1.5 t)`, top face at z = 0.
pub fn ground_pose(t: f64) -> Pose {
    let x = 0.1 * (2.0 * std::f64::consts::PI * 1.5 * t).sin();
    Pose {
        position: [x, 0.0, -0.25],
        orientation: [1.0, 0.0, 0.0, 0.0],
    }
}

pub const TYPES: [&str; 3] = ["Column", "Beam", "Slab"];

/// `n_bodies` boxes falling and tumbling over `n_keys` keyframes in 2 s, plus a 20 m × 20 m
/// × 0.5 m ground box that shakes (`moving_ground`) or stays put.
pub fn falling_scene(n_bodies: usize, n_keys: usize, moving_ground: bool) -> AnimatedScene {
    let times_s = times(n_keys, 2.0);
    let bodies = (0..n_bodies)
        .map(|i| {
            let throw = Throw::of_body(i);
            AnimBody {
                name: format!("E{}", 100 + i),
                type_name: TYPES[i % 3].to_string(),
                half_extents: [0.15 + 0.01 * i as f64, 0.2, 0.4 + 0.02 * i as f64],
                poses: times_s
                    .iter()
                    .map(|&t| Pose {
                        position: throw.position(t),
                        orientation: throw.reported_quaternion(t),
                    })
                    .collect(),
            }
        })
        .collect();
    let ground = GroundBox {
        half_extents: [10.0, 10.0, 0.25],
        poses: if moving_ground {
            times_s.iter().map(|&t| ground_pose(t)).collect()
        } else {
            vec![ground_pose(0.0)]
        },
    };
    AnimatedScene {
        bodies,
        ground: Some(ground),
        times_s,
        voids: Vec::new(),
        routes: Vec::new(),
    }
}

/// A `.glb` file taken apart by the glTF 2.0 specification's §4.4 rules.
pub struct Glb {
    pub version: u32,
    pub declared_length: u32,
    pub json_chunk_len: usize,
    pub json: Value,
    pub bin: Vec<u8>,
}

fn u32_at(bytes: &[u8], at: usize) -> u32 {
    u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap())
}

impl Glb {
    pub fn parse(bytes: &[u8]) -> Self {
        assert!(
            bytes.len() >= 20,
            "file of {} bytes is too short",
            bytes.len()
        );
        assert_eq!(&bytes[0..4], b"glTF", "magic");
        let version = u32_at(bytes, 4);
        let declared_length = u32_at(bytes, 8);
        let json_len = u32_at(bytes, 12) as usize;
        assert_eq!(&bytes[16..20], b"JSON", "first chunk type");
        let json_bytes = &bytes[20..20 + json_len];
        let json: Value = serde_json::from_slice(json_bytes).expect("JSON chunk parses");
        let bin_at = 20 + json_len;
        let bin_len = u32_at(bytes, bin_at) as usize;
        assert_eq!(
            &bytes[bin_at + 4..bin_at + 8],
            b"BIN\0",
            "second chunk type"
        );
        let bin = bytes[bin_at + 8..bin_at + 8 + bin_len].to_vec();
        assert_eq!(
            bin_at + 8 + bin_len,
            bytes.len(),
            "no bytes after the BIN chunk"
        );
        Self {
            version,
            declared_length,
            json_chunk_len: json_len,
            json,
            bin,
        }
    }

    pub fn accessor(&self, index: usize) -> &Value {
        &self.json["accessors"][index]
    }

    /// Number of components of an accessor type.
    fn components(kind: &str) -> usize {
        match kind {
            "SCALAR" => 1,
            "VEC2" => 2,
            "VEC3" => 3,
            "VEC4" => 4,
            other => panic!("unexpected accessor type {other}"),
        }
    }

    /// The bytes of one accessor's elements, read through its buffer view (tightly packed
    /// when the view has no byteStride).
    fn accessor_bytes(&self, index: usize, component_size: usize) -> (Vec<u8>, usize) {
        let acc = self.accessor(index);
        let view = &self.json["bufferViews"][acc["bufferView"].as_u64().unwrap() as usize];
        assert!(
            view.get("byteStride").is_none(),
            "no interleaved views written"
        );
        let n = Self::components(acc["type"].as_str().unwrap());
        let count = acc["count"].as_u64().unwrap() as usize;
        let start = view["byteOffset"].as_u64().unwrap_or(0) as usize
            + acc["byteOffset"].as_u64().unwrap_or(0) as usize;
        let len = count * n * component_size;
        assert!(
            len <= view["byteLength"].as_u64().unwrap() as usize,
            "accessor {index} overruns its view"
        );
        (self.bin[start..start + len].to_vec(), n)
    }

    /// An accessor of 32-bit floats, as elements of its number of components.
    pub fn f32s(&self, index: usize) -> Vec<Vec<f32>> {
        assert_eq!(self.accessor(index)["componentType"], 5126, "FLOAT");
        let (bytes, n) = self.accessor_bytes(index, 4);
        let flat: Vec<f32> = bytes
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
            .collect();
        flat.chunks_exact(n).map(|c| c.to_vec()).collect()
    }

    /// An accessor of unsigned 16-bit indices.
    pub fn u16s(&self, index: usize) -> Vec<u16> {
        assert_eq!(
            self.accessor(index)["componentType"],
            5123,
            "UNSIGNED_SHORT"
        );
        let (bytes, _) = self.accessor_bytes(index, 2);
        bytes
            .chunks_exact(2)
            .map(|b| u16::from_le_bytes(b.try_into().unwrap()))
            .collect()
    }

    /// An accessor of unsigned 32-bit indices.
    pub fn u32s(&self, index: usize) -> Vec<u32> {
        assert_eq!(self.accessor(index)["componentType"], 5125, "UNSIGNED_INT");
        let (bytes, _) = self.accessor_bytes(index, 4);
        bytes
            .chunks_exact(4)
            .map(|b| u32::from_le_bytes(b.try_into().unwrap()))
            .collect()
    }

    /// The node index of the node named `name`.
    pub fn node_named(&self, name: &str) -> usize {
        self.json["nodes"]
            .as_array()
            .unwrap()
            .iter()
            .position(|n| n["name"] == name)
            .unwrap_or_else(|| panic!("no node named {name}"))
    }

    /// The (input, output) accessors animating `path` of node `node`, if any.
    pub fn channel(&self, node: usize, path: &str) -> Option<(usize, usize)> {
        let anim = &self.json["animations"][0];
        let channels = anim["channels"].as_array()?;
        let ch = channels
            .iter()
            .find(|c| c["target"]["node"] == node && c["target"]["path"] == path)?;
        let sampler = &anim["samplers"][ch["sampler"].as_u64().unwrap() as usize];
        assert_eq!(sampler["interpolation"], "LINEAR");
        Some((
            sampler["input"].as_u64().unwrap() as usize,
            sampler["output"].as_u64().unwrap() as usize,
        ))
    }
}

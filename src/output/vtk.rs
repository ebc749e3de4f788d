//! ParaView time series of the bodies' motion: one VTK XML unstructured grid (`.vtu`) per
//! keyframe and a `.pvd` collection that lists them with their times.
//!
//! Formats: "VTK File Formats", VTK User's Guide (Kitware, 11th ed.), §19.3 XML file
//! formats — `UnstructuredGrid` with `Points`, `Cells` (`connectivity`, `offsets`,
//! `types`) and `CellData`; `Collection` of `DataSet timestep=… file=…` for the `.pvd`.
//!
//! Each body (and the ground box) is one `VTK_HEXAHEDRON` cell (type 12) whose 8 corners
//! are `p + R(q) (s ⊙ h)` for the corner signs `s` in VTK's order: the bottom face
//! (−,−,−) (+,−,−) (+,+,−) (−,+,−), then the top face with the same x, y signs, so that
//! the first face's right-hand normal points to the second (positive volume). Points are
//! in our own Z-up frame, SI metres (ParaView has no preferred up axis). Cell data:
//! * `body_id` (Int32): index in [`AnimatedScene::bodies`], −1 for the ground;
//! * `element_type` (Int32): index of the body's type in the sorted list of type names,
//!   which each file states in the XML comment `element_type: 0=Beam 1=Column …`
//!   ([`GROUND_TYPE`] included when there is a ground).
//!
//! Numbers are written as ASCII in Rust's shortest round-trip form, so a reader gets the
//! very f64 values back and the same scene always gives the same bytes. Every file is
//! written atomically, the `.pvd` last, so it never lists a file that is not there yet.
use crate::output::error::scene_ensure as ensure;
use crate::output::gltf::{AnimatedScene, Pose, GROUND_TYPE};
use crate::output::{AnimationError, OutputError};

/// What writing a scene returns.
type Result<T> = std::result::Result<T, AnimationError>;
use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// VTK cell type of an 8-node hexahedron (vtkCellType.h).
pub(crate) const VTK_HEXAHEDRON: u8 = 12;

/// Corner signs of a box in VTK_HEXAHEDRON order.
pub const HEX_CORNERS: [[f64; 3]; 8] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
];

/// The folder of `.vtu` frames beside a `.pvd`, replaced as a whole at each write.
pub const VTK_FRAMES: crate::output::location::FolderKind = crate::output::location::FolderKind {
    name: "vtk-frames",
    owns: &["step_*"],
};

/// Writes `scene` as `pvd_path` (e.g. `out/collapse.pvd`) plus one `.vtu` per keyframe in
/// the folder beside it named after its stem (`out/collapse/step_000000.vtu`, …), which is
/// created if needed. Returns the `.vtu` paths in time order.
pub fn write_pvd(scene: &AnimatedScene, pvd_path: impl AsRef<Path>) -> Result<Vec<PathBuf>> {
    let pvd_path = pvd_path.as_ref();
    let stem = pvd_path
        .file_stem()
        .ok_or_else(|| {
            OutputError::Location(format!(
                "output path {} has no file name",
                pvd_path.display()
            ))
        })?
        .to_string_lossy()
        .into_owned();
    let folder = pvd_path.with_file_name(&stem);
    check_scene(scene)?;
    crate::output::location::check_output_file(pvd_path, "VTK output").or_else(|e| {
        // The .pvd's folder may not exist yet; it is created below.
        match pvd_path.parent() {
            Some(p) if !p.as_os_str().is_empty() && !p.exists() => {
                crate::output::location::check_output_dir(p, "VTK output folder")
            }
            _ => Err(e),
        }
    })?;
    if let Some(p) = pvd_path.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(p).map_err(OutputError::io("cannot create folder", p))?;
    }
    // The frames are written into a folder beside their target and swapped in as a
    // whole, with the .pvd renamed right after (crate::output::location): a shorter
    // run leaves no stale frames, an interrupted one no partial folder.
    let staged = crate::output::location::StagedDir::new(&folder, &VTK_FRAMES)?;

    let types = type_names(scene);
    let digits = scene
        .times_s
        .len()
        .saturating_sub(1)
        .to_string()
        .len()
        .max(6);
    let mut written = Vec::with_capacity(scene.times_s.len());
    let mut collection = String::from(
        "<?xml version=\"1.0\"?>\n\
         <VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"LittleEndian\">\n  <Collection>\n",
    );
    for (k, &t) in scene.times_s.iter().enumerate() {
        let name = format!("step_{k:0digits$}.vtu");
        let path = folder.join(&name);
        staged.write(&name, frame_vtu(scene, k, &types).as_bytes())?;
        writeln!(
            collection,
            "    <DataSet timestep=\"{t}\" part=\"0\" file=\"{}/{name}\"/>",
            xml_escape(&stem)
        )
        .expect("writing to a String");
        written.push(path);
    }
    collection.push_str("  </Collection>\n</VTKFile>\n");
    let mut pvd = crate::output::AtomicFile::create(pvd_path)?;
    std::io::Write::write_all(&mut pvd, collection.as_bytes())
        .map_err(OutputError::io("cannot write", pvd_path))?;
    staged.swap_in()?;
    pvd.commit()?;
    Ok(written)
}

/// The sorted element type names, as numbered by the `element_type` cell data.
pub(crate) fn type_names(scene: &AnimatedScene) -> Vec<String> {
    let mut names: BTreeSet<&str> = scene.bodies.iter().map(|b| b.type_name.as_str()).collect();
    if scene.ground.is_some() {
        names.insert(GROUND_TYPE);
    }
    names.into_iter().map(str::to_owned).collect()
}

/// The 8 corners (m) of a box of half sizes `h` at pose `(p, q)`, `q = [w, x, y, z]`
/// normalised here, in VTK_HEXAHEDRON order.
pub(crate) fn box_corners(pose: &Pose, h: [f64; 3]) -> [[f64; 3]; 8] {
    let (p, q) = (&pose.position, &pose.orientation);
    let n = q.iter().map(|c| c * c).sum::<f64>().sqrt();
    let [w, x, y, z] = q.map(|c| c / n);
    // Rotation matrix of a unit quaternion (e.g. Shoemake 1985).
    let r = [
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - w * z),
            2.0 * (x * z + w * y),
        ],
        [
            2.0 * (x * y + w * z),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - w * x),
        ],
        [
            2.0 * (x * z - w * y),
            2.0 * (y * z + w * x),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ];
    HEX_CORNERS.map(|s| {
        let local = [s[0] * h[0], s[1] * h[1], s[2] * h[2]];
        [0, 1, 2].map(|i| p[i] + r[i][0] * local[0] + r[i][1] * local[1] + r[i][2] * local[2])
    })
}

/// The `.vtu` text of keyframe `k`.
fn frame_vtu(scene: &AnimatedScene, k: usize, types: &[String]) -> String {
    let type_index = |name: &str| types.iter().position(|t| t == name).expect("type listed");
    // (pose, half extents, body id, type index) of every cell.
    let mut cells: Vec<(&Pose, [f64; 3], i64, usize)> = scene
        .bodies
        .iter()
        .enumerate()
        .map(|(i, b)| {
            (
                &b.poses[k],
                b.half_extents,
                i as i64,
                type_index(&b.type_name),
            )
        })
        .collect();
    if let Some(g) = &scene.ground {
        let pose = &g.poses[if g.poses.len() == 1 { 0 } else { k }];
        cells.push((pose, g.half_extents, -1, type_index(GROUND_TYPE)));
    }
    let n = cells.len();
    let legend: Vec<String> = types
        .iter()
        .enumerate()
        .map(|(i, t)| format!("{i}={}", xml_comment_safe(t)))
        .collect();

    let mut s = String::with_capacity(200 * n + 1000);
    let w = &mut s;
    let _ = writeln!(w, "<?xml version=\"1.0\"?>");
    let _ = writeln!(
        w,
        "<!-- fem2rbd keyframe {k}, t = {} s; Z-up, SI metres; element_type: {} -->",
        scene.times_s[k],
        legend.join(" ")
    );
    let _ = writeln!(
        w,
        "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">"
    );
    let _ = writeln!(w, "  <UnstructuredGrid>");
    let _ = writeln!(
        w,
        "    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{n}\">",
        8 * n
    );
    let _ = writeln!(w, "      <Points>");
    let _ = writeln!(w, "        <DataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\" format=\"ascii\">");
    for (pose, h, _, _) in &cells {
        for c in box_corners(pose, *h) {
            let _ = writeln!(w, "          {} {} {}", c[0], c[1], c[2]);
        }
    }
    let _ = writeln!(w, "        </DataArray>");
    let _ = writeln!(w, "      </Points>");
    let _ = writeln!(w, "      <Cells>");
    let _ = writeln!(
        w,
        "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">"
    );
    for c in 0..n {
        let ids: Vec<String> = (8 * c..8 * c + 8).map(|i| i.to_string()).collect();
        let _ = writeln!(w, "          {}", ids.join(" "));
    }
    let _ = writeln!(w, "        </DataArray>");
    let list = |w: &mut String, ty: &str, name: &str, values: Vec<String>| {
        let _ = writeln!(
            w,
            "        <DataArray type=\"{ty}\" Name=\"{name}\" format=\"ascii\">"
        );
        for chunk in values.chunks(16) {
            let _ = writeln!(w, "          {}", chunk.join(" "));
        }
        let _ = writeln!(w, "        </DataArray>");
    };
    list(
        w,
        "Int64",
        "offsets",
        (1..=n).map(|c| (8 * c).to_string()).collect(),
    );
    list(w, "UInt8", "types", vec![VTK_HEXAHEDRON.to_string(); n]);
    let _ = writeln!(w, "      </Cells>");
    let _ = writeln!(w, "      <CellData Scalars=\"element_type\">");
    list(
        w,
        "Int32",
        "body_id",
        cells.iter().map(|c| c.2.to_string()).collect(),
    );
    list(
        w,
        "Int32",
        "element_type",
        cells.iter().map(|c| c.3.to_string()).collect(),
    );
    let _ = writeln!(w, "      </CellData>");
    let _ = writeln!(w, "    </Piece>");
    let _ = writeln!(w, "  </UnstructuredGrid>");
    let _ = writeln!(w, "</VTKFile>");
    s
}

/// The checks the `.vtu` files need: times finite, >= 0, strictly increasing; one pose
/// per time (the ground: one, or one per time); finite positions; non-zero quaternions;
/// half extents > 0.
fn check_scene(scene: &AnimatedScene) -> Result<()> {
    let times = &scene.times_s;
    ensure!(!times.is_empty(), "the scene has no keyframe times");
    for (k, &t) in times.iter().enumerate() {
        ensure!(
            t.is_finite() && t >= 0.0,
            "keyframe time times_s[{k}] = {t} s must be finite and >= 0"
        );
        ensure!(
            k == 0 || t > times[k - 1],
            "keyframe times must increase strictly: times_s[{k}] = {t} s follows times_s[{}] = {} s",
            k - 1,
            times[k - 1]
        );
    }
    let check = |label: &str, poses: &[Pose], h: [f64; 3]| -> Result<()> {
        ensure!(
            h.iter().all(|&x| x.is_finite() && x > 0.0),
            "{label}: half_extents {h:?} m must be finite and > 0"
        );
        for (k, pose) in poses.iter().enumerate() {
            let (p, q) = (&pose.position, &pose.orientation);
            let at = || {
                format!(
                    "{label} at keyframe {k} (t = {} s)",
                    times[k.min(times.len() - 1)]
                )
            };
            ensure!(
                p.iter().all(|c| c.is_finite()),
                "{}: position {p:?} m is not finite",
                at()
            );
            let n = q.iter().map(|c| c * c).sum::<f64>().sqrt();
            ensure!(
                n.is_finite() && n >= 1e-12,
                "{}: quaternion {q:?} is zero or not finite",
                at()
            );
        }
        Ok(())
    };
    for (i, b) in scene.bodies.iter().enumerate() {
        let label = format!("body '{}' (#{i})", b.name);
        ensure!(
            b.poses.len() == times.len(),
            "{label} has {} poses but the scene has {} keyframe times",
            b.poses.len(),
            times.len()
        );
        check(&label, &b.poses, b.half_extents)?;
    }
    if let Some(g) = &scene.ground {
        ensure!(
            g.poses.len() == 1 || g.poses.len() == times.len(),
            "the ground has {} poses; give 1 (fixed ground) or one per keyframe time ({})",
            g.poses.len(),
            times.len()
        );
        check("the ground", &g.poses, g.half_extents)?;
    }
    Ok(())
}

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('"', "&quot;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// A type name fit for an XML comment (no `--`) and for the space-separated legend.
fn xml_comment_safe(s: &str) -> String {
    s.replace("--", "- -").replace(char::is_whitespace, "_")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hexahedron_corners_have_positive_volume_and_rotate_with_the_body() {
        // 90° about z: local x goes to world y.
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let pose = Pose {
            position: [1.0, 2.0, 3.0],
            orientation: [h, 0.0, 0.0, h],
        };
        let c = box_corners(&pose, [0.5, 0.25, 0.1]);
        let close = |a: [f64; 3], b: [f64; 3]| a.iter().zip(&b).all(|(x, y)| (x - y).abs() < 1e-12);
        // Corner (+,-,-): local (0.5, -0.25, -0.1) -> world (0.25, 0.5, -0.1) + p.
        assert!(close(c[1], [1.25, 2.5, 2.9]), "{:?}", c[1]);
        // Volume of the hexahedron via the triple product of its edges from corner 0.
        let e = |i: usize| [0, 1, 2].map(|k| c[i][k] - c[0][k]);
        let (a, b, d) = (e(1), e(3), e(4));
        let vol = a[0] * (b[1] * d[2] - b[2] * d[1]) - a[1] * (b[0] * d[2] - b[2] * d[0])
            + a[2] * (b[0] * d[1] - b[1] * d[0]);
        assert!((vol - 1.0 * 0.5 * 0.2).abs() < 1e-12, "volume {vol}");
    }
}

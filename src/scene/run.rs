//! Steps a built scene and writes body poses as CSV.
use super::assemble::Scene;
use super::SceneError;
use crate::output::AtomicFile;

/// What running a scene returns.
type Result<T> = std::result::Result<T, SceneError>;
use std::io::Write;
use std::path::Path;

/// The CSV header of a poses file.
pub const CSV_HEADER: &str = "step,time,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz";

/// Runs the scene for its duration and writes poses to `out`: the final state, or with
/// `every = Some(n)` the state at substeps 0, n, 2n, … and the last substep. Numbers are
/// written with `{:.17e}` (17 significant digits), which round-trips every f64 exactly.
pub fn run_scene(scene: &Scene, every: Option<u64>, out: &mut dyn Write) -> Result<()> {
    run_scene_with(scene, every, out, &mut |_, _| {})
}

/// Substeps between two progress reports of [`run_scene_with`] (at most; fewer near a
/// frame): about 0.2 s of work for a small scene in a debug build.
pub(crate) const PROGRESS_SUBSTEPS: u64 = 1000;

/// [`run_scene`], calling `progress(done, total)` (substeps) at least every
/// [`PROGRESS_SUBSTEPS`] substeps. Bullet steps one substep at a time whatever the chunk
/// size, so the output is byte-identical to [`run_scene`]'s.
pub(crate) fn run_scene_with(
    scene: &Scene,
    every: Option<u64>,
    out: &mut dyn Write,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<()> {
    if every == Some(0) {
        return Err(SceneError::Options("--frames must be >= 1 substep".into()));
    }
    let mut built = scene.build()?;
    writeln!(out, "{CSV_HEADER}")?;
    let h = scene.substep;
    let n = scene.num_substeps;
    let write_rows = |built: &super::BuiltScene, step: u64, out: &mut dyn Write| -> Result<()> {
        let t = step as f64 * h;
        let poses = built.world.poses()?;
        let vels = built.world.velocities()?;
        for (((name, _), p), v) in scene.bodies.iter().zip(&poses).zip(&vels) {
            write!(out, "{step},{t:.17e},{}", csv_field(name))?;
            for x in p
                .position
                .iter()
                .chain(&p.orientation)
                .chain(&v.linear)
                .chain(&v.angular)
            {
                write!(out, ",{x:.17e}")?;
            }
            writeln!(out)?;
        }
        Ok(())
    };
    // Substep by substep when kinematic bodies move (their targets are set before each
    // substep); otherwise in chunks up to the next frame.
    let moving = !scene.kinematic_motions.is_empty();
    let frame = every.unwrap_or(n.max(1));
    if every.is_some() {
        write_rows(&built, 0, out)?;
    }
    let mut done = 0u64;
    while done < n {
        let chunk = if moving {
            1
        } else {
            (frame - done % frame).min(n - done).min(PROGRESS_SUBSTEPS)
        };
        if moving {
            let t_next = (done + 1) as f64 * h;
            for m in &scene.kinematic_motions {
                built
                    .world
                    .set_kinematic_target(built.bodies[m.body], m.pose_at(t_next), None)?;
            }
        }
        let chunk32 = u32::try_from(chunk).unwrap_or(u32::MAX);
        built.world.step(h, chunk32)?;
        done += u64::from(chunk32);
        progress(done, n);
        if every.is_some_and(|k| done % k == 0) || done == n {
            write_rows(&built, done, out)?;
        }
    }
    if n == 0 && every.is_none() {
        write_rows(&built, 0, out)?;
    }
    Ok(())
}

/// Runs a scene file and writes its poses CSV atomically to `out_path` (nothing is
/// written if anything fails).
/// A scene with values outside their plausible ranges or bodies that start inside each
/// other is refused unless `allow_unusual` ([`super::plausibility`]).
pub fn run_scene_file(
    scene_path: &Path,
    out_path: &Path,
    every: Option<u64>,
    allow_unusual: bool,
) -> Result<()> {
    run_scene_file_with(scene_path, out_path, every, allow_unusual, &mut |_, _| {})
}

/// [`run_scene_file`] with a progress hook ([`run_scene_with`]).
pub fn run_scene_file_with(
    scene_path: &Path,
    out_path: &Path,
    every: Option<u64>,
    allow_unusual: bool,
    progress: &mut dyn FnMut(u64, u64),
) -> Result<()> {
    crate::output::location::check_output_file(out_path, "--out")?;
    crate::output::location::check_not_an_input(out_path, &[scene_path], "--out")?;
    let scene = Scene::load(scene_path)?;
    let findings = scene.unusual();
    if !findings.is_empty() && !allow_unusual {
        return Err(SceneError::Unusual {
            path: scene_path.to_path_buf(),
            findings,
        });
    }
    let mut file = AtomicFile::create(out_path)?;
    run_scene_with(&scene, every, &mut file, progress).map_err(|e| SceneError::Run {
        path: scene_path.to_path_buf(),
        error: Box::new(e),
    })?;
    Ok(file.commit()?)
}

/// RFC 4180 quoting, as every table fem2rbd writes ([`crate::output::csv_text`]).
fn csv_field(s: &str) -> String {
    crate::output::csv_text::field(s).into_owned()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Progress is reported in chunks of at most PROGRESS_SUBSTEPS up to the total, and
    /// the chunked run ends in exactly the state of one uninterrupted step call.
    #[test]
    fn progress_chunks_leave_the_output_unchanged() {
        let text = std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/data/scenes/drop.json"
        ))
        .unwrap();
        // 5 s at 240 substeps/s = 1200 substeps: two progress chunks (1000 + 200).
        let long =
            Scene::from_json(&text.replace("\"duration\": 2.0", "\"duration\": 5.0")).unwrap();
        assert_eq!(long.num_substeps, 1200);
        let mut calls = Vec::new();
        let mut out = Vec::new();
        run_scene_with(&long, None, &mut out, &mut |d, n| calls.push((d, n))).unwrap();
        assert_eq!(calls, [(1000, 1200), (1200, 1200)]);
        let mut built = long.build().unwrap();
        built.world.step(long.substep, 1200).unwrap();
        let z = built.world.poses().unwrap()[1].position[2];
        let text = String::from_utf8(out).unwrap();
        let row = text.lines().find(|l| l.contains(",box,")).unwrap();
        assert_eq!(row.split(',').nth(5).unwrap(), format!("{z:.17e}"));
        // With frames every 7 substeps: reports at every frame and every ≤ 1000 substeps.
        let mut calls = Vec::new();
        run_scene_with(&long, Some(7), &mut Vec::new(), &mut |d, n| {
            calls.push((d, n))
        })
        .unwrap();
        assert_eq!(calls.last(), Some(&(1200, 1200)));
        assert!(calls
            .windows(2)
            .all(|w| w[1].0 > w[0].0 && w[1].0 - w[0].0 <= 7));
    }
}

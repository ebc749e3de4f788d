//! TEMPORARY copy of the `crate::output::run_folder` interface (branch gltfx), so the
//! figures compile before it lands. Removed at the merge.
#![allow(missing_docs, dead_code)]
use crate::physics::Pose;

#[derive(Debug, Clone)]
pub struct BodyInfo {
    pub name: String,
    pub group: String,
    pub type_name: String,
    pub material: String,
    pub element: String,
    pub passive: bool,
    pub pose0: Pose,
    pub half_extents: [f64; 3],
    pub mass_kg: f64,
}

#[derive(Debug, Clone)]
pub struct HistoryRow {
    pub t_s: f64,
    pub fe: bool,
    pub roof_drift: Option<f64>,
    pub max_drop_m: Option<f64>,
    pub counts: Option<(usize, usize, usize)>,
    pub ground_m: [f64; 3],
}

#[derive(Debug, Clone)]
pub struct RunFolder {
    pub dir: std::path::PathBuf,
    pub bodies: Vec<BodyInfo>,
    pub frames: Vec<(f64, Vec<Pose>)>,
    pub history: Vec<HistoryRow>,
    pub final_poses: Vec<Pose>,
    pub at_rest: Vec<Option<bool>>,
    pub summary: serde_json::Value,
}

impl RunFolder {
    pub fn load(dir: &std::path::Path) -> anyhow::Result<RunFolder> {
        anyhow::bail!("run folder reader not merged yet ({})", dir.display())
    }
}

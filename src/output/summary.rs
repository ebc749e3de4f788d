//! `summary.json`: what a run found, every field documented with its unit in
//! `docs/scenario-format.md`. The schema only: the measures are computed from the poses in
//! [`crate::measure`] (plan areas in [`crate::plan_geometry`]) and the summary of a record
//! is assembled in `pipeline::write::run_summary`.
use crate::mode::Mode;
use crate::ruin::rest::RestSpeed;
use crate::ruin::stage::RuinStop;
use serde::{Deserialize, Serialize};

/// Rounds to 6 decimals (and −0 to 0), as every number of `summary.json`.
pub(crate) fn r6(x: f64) -> f64 {
    (x * 1e6).round() / 1e6 + 0.0
}
/// `summary.json` as a type: what the run writer serialises and every reader (the run
/// folder, `fem2rbd plot`, study collection, tests) deserialises. Field by field with units
/// in docs/scenario-format.md "Outputs". The file is written through a
/// [`serde_json::Value`], whose keys are ordered by name, so the bytes do not depend on the
/// field order here; numbers are rounded to 6 decimals (times 4 in `tc_detail`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunSummary {
    /// `hybrid`, `rigid` or `fe`.
    pub mode: Mode,
    /// Collapse moment Tc, s (`None`: no collapse, or the rigid mode).
    pub tc_s: Option<f64>,
    /// Why the FE stage ended.
    pub tc_reason: TcKind,
    /// The reason in words (criterion and values, or the diverged step).
    pub tc_detail: String,
    /// End time of the FE stage, s (`None` in the rigid mode).
    pub fe_end_s: Option<f64>,
    /// Elements the FE removed after their state determination failed in a step no
    /// fallback could make converge, in the order of removal (absent when none was).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub fe_removed_elements: Vec<RemovedElementSummary>,
    /// Geometric scale of the model against its prototype (the model's `scale`; absent in
    /// run folders written before it was recorded).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scale: Option<f64>,
    /// Active bodies.
    pub bodies: usize,
    /// Passive foundation blocks.
    pub foundation_blocks: usize,
    /// FE keyframes (25 fps up to Tc).
    pub keyframes_fe: usize,
    /// The ruin stage (absent when none ran).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ruin_stage: Option<RuinStageSummary>,
    /// Connection states at the end of the ruin stage (absent when none ran).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub connections: Option<ConnectionCounts>,
    /// Geometric measures of the ruins (module docs).
    pub ruins: RuinMeasures,
    /// FE-only runs: the FE's state where its bodies would first touch ([`crate::measure::first_contact`])
    /// and its ruin measures there (absent in runs with a ruin stage, or when no frame
    /// gets there).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fe_first_contact: Option<FeFirstContact>,
    /// The floors when the lowest floor is first 70 % of its height down ([`crate::measure::floors_down`];
    /// absent if it never gets there).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub floors_down: Option<FloorsDown>,
    /// Wall times, s (only with timing on: not byte-stable).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wall_time_s: Option<WallTimes>,
    /// The model's values outside their plausible ranges that the run accepted with
    /// `--allow-unusual` (absent when there are none).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub unusual_values: Vec<String>,
}

/// One entry of `fe_removed_elements`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RemovedElementSummary {
    /// The element's tag in the model.
    pub element: i64,
    /// Time of the last converged state, from which the FE went on without it, s.
    pub t_s: f64,
    /// The element's failure.
    pub reason: String,
}

/// `floors_down` ([`crate::measure::floors_down`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FloorsDown {
    /// The share of the lowest floor's height (0.7).
    pub share: f64,
    /// Time of the frame, s.
    pub t_s: f64,
    /// Each floor's drop, bottom up, m.
    pub floor_drops_m: Vec<f64>,
    /// Plan distance of each floor from the one below (floors 2–1, 3–2, …), m.
    pub story_offsets_m: Vec<f64>,
    /// The first story folds and the stories above come down whole.
    pub stories_above_whole: bool,
}

/// `fe_first_contact`: where the FE alone stops describing the building (a model without
/// contact), and the ruin measures of its bodies there.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FeFirstContact {
    /// Time of the keyframe, s.
    pub t_s: f64,
    /// What touches (`Slab:1:85 reaches the ground`, `floor 2 comes down onto floor 1`).
    pub detail: String,
    /// The ruin measures of the bodies at that keyframe.
    pub ruins: RuinMeasures,
}

/// `tc_reason`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TcKind {
    /// The collapse criterion was met.
    Criterion,
    /// A step did not converge first: hand-off at the last converged step.
    FeDiverged,
    /// The FE stage ended without collapse.
    NoCollapse,
    /// No FE stage (rigid mode). Read also as `physics_only`, the rigid mode's former name.
    #[serde(alias = "physics_only")]
    RigidOnly,
}

impl TcKind {
    /// The name written in the file.
    pub fn name(self) -> &'static str {
        match self {
            TcKind::Criterion => "criterion",
            TcKind::FeDiverged => "fe_diverged",
            TcKind::NoCollapse => "no_collapse",
            TcKind::RigidOnly => "rigid_only",
        }
    }
}

/// `ruin_stage`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RuinStageSummary {
    /// Start time (Tc, or 0), s.
    pub start_s: f64,
    /// End time, s.
    pub end_s: f64,
    /// Why it stopped.
    pub stop: RuinStop,
    /// Frames (25 fps), the start included.
    pub frames: usize,
    /// Bodies at rest at the end.
    pub bodies_at_rest: usize,
    /// Deepest penetration after the first frame, m.
    pub first_frame_penetration_m: f64,
    /// Deepest penetration at the end of any frame, m.
    pub max_penetration_m: f64,
    /// The energy ledger (`None` without frames).
    pub energy: Option<EnergySummary>,
    /// Bodies not at rest at the end, in body order.
    pub unsettled_bodies: Vec<UnsettledBody>,
    /// How the rest test measured point speeds (`frame_mean`, `instantaneous`;
    /// `crate::ruin::rest::RestSpeed`); absent in run folders of versions without it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rest_speed: Option<RestSpeed>,
    /// The dynamic body with the largest point speed from its velocities at the end, and
    /// that speed (m/s): the solver's substep chatter, which the frame-mean test leaves out.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub instantaneous_at_end: Option<UnsettledBody>,
}

/// One body not at rest at the end.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct UnsettledBody {
    /// Body name.
    pub body: String,
    /// Point speed relative to the ground, m/s.
    pub speed_mps: f64,
}

/// `connections`: states at the end of the ruin stage.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct ConnectionCounts {
    /// All connections.
    pub total: usize,
    /// Elastic (intact).
    pub intact: usize,
    /// Plastic.
    pub plastic: usize,
    /// Broken.
    pub broken: usize,
}

/// `ruin_stage.energy` (docs/ruin-numerics.md), J unless named otherwise.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EnergySummary {
    /// Potential energy of the undeformed building above the ground's top.
    pub initial_potential_j: f64,
    /// Energies at the start of the ruin stage.
    pub start: StartEnergy,
    /// Energies at the end and the ledger's totals.
    pub end: EndEnergy,
    /// Added by the solver over the stage.
    pub injected_j: f64,
    /// Largest addition in one substep.
    pub max_substep_injection_j: f64,
    /// Its time, s.
    pub max_substep_injection_at_s: f64,
    /// The settle phase's energy check.
    pub settle_phase: SettlePhase,
    /// The speed check.
    pub speed: SpeedCheck,
}

/// `energy.start`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StartEnergy {
    /// Kinetic (translational + rotational).
    pub kinetic_j: f64,
    /// Potential.
    pub potential_j: f64,
}

/// `energy.end`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EndEnergy {
    /// Kinetic (translational + rotational).
    pub kinetic_j: f64,
    /// Potential.
    pub potential_j: f64,
    /// Work done by the moving ground since the start.
    pub ground_work_j: f64,
    /// Taken out by Bullet's velocity damping since the start.
    pub damping_j: f64,
    /// E(start) + W_ground − E(end).
    pub dissipated_j: f64,
}

/// `energy.settle_phase`: the largest rise of the mechanical energy between two frames
/// after the record's end, against [`crate::measure::energy::SETTLE_RISE_LIMIT`] × the initial potential energy.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SettlePhase {
    /// Start of the settle phase (end of the record), s.
    pub from_s: f64,
    /// Frames in it.
    pub frames: usize,
    /// Largest rise.
    pub max_rise_j: f64,
    /// Its time, s (`None`: no rise).
    pub max_rise_at_s: Option<f64>,
    /// Largest rise / initial potential energy.
    pub max_rise_ratio: f64,
    /// [`crate::measure::energy::SETTLE_RISE_LIMIT`].
    pub limit_ratio: f64,
    /// `max_rise_ratio <= limit_ratio`.
    pub ok: bool,
}

/// `energy.speed`: the fastest body against √(v_Tc,max² + 2·g·H) + the peak ground speed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SpeedCheck {
    /// Largest centre speed of any dynamic body, m/s.
    pub max_mps: f64,
    /// Its body.
    pub max_body: Option<String>,
    /// Its time, s.
    pub max_at_s: Option<f64>,
    /// Largest centre speed at the start, m/s.
    pub start_max_mps: f64,
    /// Peak ground speed of the record, m/s.
    pub peak_ground_mps: f64,
    /// The bound, m/s.
    pub bound_mps: f64,
    /// `max_mps <= bound_mps`.
    pub ok: bool,
}

/// `wall_time_s` (s).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WallTimes {
    /// FE stage.
    pub fe: f64,
    /// Ruin stage (build + run). Read also as `physics`, its former name.
    #[serde(alias = "physics")]
    pub ruin: f64,
    /// Inside Bullet's step. Read also as `physics_in_bullet`.
    #[serde(alias = "physics_in_bullet")]
    pub ruin_in_bullet: f64,
    /// `ruin_in_bullet / ruin`. Read also as `physics_bullet_share`.
    #[serde(alias = "physics_bullet_share")]
    pub ruin_bullet_share: f64,
}

/// `ruins`: geometric measures of the final state (module docs), m and m². Measures of an
/// empty set of bodies are not finite and written as `null` (read back as NaN).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RuinMeasures {
    /// Plan AABB of the undeformed active bodies.
    pub original_footprint_m: Footprint,
    /// How far the debris reaches beyond it on each side.
    pub extent_beyond_footprint_m: Extent,
    /// Plan area of the union of the final projections.
    #[serde(deserialize_with = "nan_if_null")]
    pub debris_footprint_area_m2: f64,
    /// Area of the original footprint.
    #[serde(deserialize_with = "nan_if_null")]
    pub original_footprint_area_m2: f64,
    /// Highest final corner above the ground's top.
    #[serde(deserialize_with = "nan_if_null")]
    pub max_debris_height_m: f64,
    /// The floors, bottom up.
    pub floors: Vec<FloorMeasure>,
    /// Slab overlap of consecutive floors.
    pub slab_overlap: Vec<SlabOverlap>,
    /// Bodies that end inside each other (absent in summaries of versions without it).
    #[serde(default)]
    pub interpenetration: Interpenetration,
}

/// `interpenetration`: pairs of active bodies whose final boxes overlap
/// ([`crate::ruin::separation::box_overlap`], the separating-axis depth), m. Bodies that
/// may not touch ([`crate::ruin::separation`]) can end inside each other; contact
/// penetrations are millimetres.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Interpenetration {
    /// Pairs overlapping by more than [`INTERPENETRATION_COUNTED_M`].
    pub pairs_over_10mm: usize,
    /// The deepest overlap, m (0 if none).
    pub deepest_m: f64,
    /// The two bodies of the deepest overlap.
    pub deepest_pair: Option<[String; 2]>,
}

/// Overlap depth from which a pair counts in [`Interpenetration::pairs_over_10mm`], m.
pub const INTERPENETRATION_COUNTED_M: f64 = 0.01;

/// `original_footprint_m`: [min, max] along x and y.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Footprint {
    /// x range.
    #[serde(deserialize_with = "nan_if_null_2")]
    pub x: [f64; 2],
    /// y range.
    #[serde(deserialize_with = "nan_if_null_2")]
    pub y: [f64; 2],
}

/// `extent_beyond_footprint_m`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Extent {
    /// Beyond the −x side.
    #[serde(deserialize_with = "nan_if_null")]
    pub x_minus: f64,
    /// Beyond the +x side.
    #[serde(deserialize_with = "nan_if_null")]
    pub x_plus: f64,
    /// Beyond the −y side.
    #[serde(deserialize_with = "nan_if_null")]
    pub y_minus: f64,
    /// Beyond the +y side.
    #[serde(deserialize_with = "nan_if_null")]
    pub y_plus: f64,
    /// The largest of the four.
    #[serde(deserialize_with = "nan_if_null")]
    pub max: f64,
}

/// One floor.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FloorMeasure {
    /// Floor number from 1 (bottom).
    pub floor: usize,
    /// Undeformed level of its slab centres.
    pub level_m: f64,
    /// Slab bodies.
    pub slabs: usize,
    /// Displacement of the mass-weighted slab centroid.
    pub centroid_displacement_m: [f64; 3],
    /// Its horizontal length.
    pub horizontal_offset_m: f64,
}

/// The pancake measure of two consecutive floors.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SlabOverlap {
    /// Lower and upper floor numbers.
    pub floors: [usize; 2],
    /// Area of the intersection of their final slab projections.
    pub overlap_area_m2: f64,
    /// The upper floor's undeformed slab area.
    pub upper_slab_area_m2: f64,
    /// Their ratio (1 = fully stacked, 0 = no overlap).
    pub overlap_ratio: f64,
}

fn nan_if_null<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

fn nan_if_null_2<'de, D: serde::Deserializer<'de>>(d: D) -> Result<[f64; 2], D::Error> {
    let v = <[Option<f64>; 2]>::deserialize(d)?;
    Ok(v.map(|x| x.unwrap_or(f64::NAN)))
}

impl RunSummary {
    /// The `summary.json` text: pretty JSON (keys ordered by name) and a newline.
    pub fn to_json(&self) -> serde_json::Result<String> {
        Ok(serde_json::to_string_pretty(&serde_json::to_value(self)?)? + "\n")
    }
}

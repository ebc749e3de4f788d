//! The rescue maps of a collected study: per (model, mode, intensity), over every ok run of
//! that intensity (all records and ensemble members), the plan map of the chance of a
//! survivable void beneath each cell and of a route to one passing over it, the spread of
//! the void and pile measures and the voids that recur in one place
//! ([`crate::rescue::ensemble`], read from each run's `voids.csv` and `voids.json`):
//! `results/rescue/<model>__<mode>__<pga>g.csv` and `.json`.
//! Each run's own numbers (void count, survivable count and volume, pile height) also enter
//! its ruin measures as `rescue.*` ([`run_measures`]), so `ensemble.csv` gives their
//! statistics per (record, intensity).
use super::collect::RunRow;
use super::error::{Result, StudyError};
use super::format::Study;
use super::plan::{Plan, Store};
use crate::rescue::ensemble::{maps, read_member, Maps, Member, MemberRescue};
use std::collections::BTreeMap;
use std::path::Path;

fn rescue_error(e: crate::rescue::RescueError) -> StudyError {
    StudyError::Invalid(e.to_string())
}

/// The `rescue.*` measures of the run folder `dir` (none when its analysis failed):
/// `rescue.voids_count`, `rescue.survivable_count`, `rescue.survivable_volume_m3`,
/// `rescue.rescuer_reachable_survivable`, `rescue.max_height_m`, `rescue.mean_height_m`.
pub(crate) fn run_measures(dir: &Path) -> Result<BTreeMap<String, f64>> {
    let mut m = BTreeMap::new();
    let Ok(r) = read_member(dir).map_err(rescue_error)? else {
        return Ok(m);
    };
    let r: MemberRescue = r;
    let surv: Vec<_> = r.voids.iter().filter(|v| v.survivable).collect();
    m.insert("rescue.voids_count".into(), r.voids.len() as f64);
    m.insert("rescue.survivable_count".into(), surv.len() as f64);
    m.insert(
        "rescue.survivable_volume_m3".into(),
        surv.iter().map(|v| v.volume_m3).sum(),
    );
    m.insert(
        "rescue.rescuer_reachable_survivable".into(),
        surv.iter().filter(|v| v.rescuer).count() as f64,
    );
    m.insert("rescue.max_height_m".into(), r.max_height_m);
    m.insert("rescue.mean_height_m".into(), r.mean_height_m);
    Ok(m)
}

/// The rescue maps per (model, mode, intensity) over its ok runs with a ruin stage (rows
/// in plan order), each
/// run a member named by its id; file stem `<model>__<mode>__<pga>g` (as the density
/// grids).
pub(crate) fn rescue_maps(
    study: &Study,
    store: &Store,
    plan: &Plan,
    rows: &[RunRow],
) -> Result<Vec<(String, Maps)>> {
    let groups = super::collect::intensity_groups(study, plan, rows, |_, r| r.ruin_stop.is_some());
    let mut out = Vec::new();
    for ((mi, modi, g), entries) in groups {
        let mut members = Vec::new();
        for e in entries {
            let dir = store.run_dir(&e.id);
            members.push(Member {
                name: e.id.clone(),
                rescue: read_member(&dir).map_err(rescue_error)?,
            });
        }
        let (model, mode) = (&study.models[mi].name, study.modes[modi].name());
        let stem = format!("{model}__{mode}__{}.{:03}g", g / 1000, g % 1000);
        out.push((
            stem,
            maps(members, &store.runs_dir()).map_err(rescue_error)?,
        ));
    }
    Ok(out)
}

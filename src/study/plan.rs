//! The manifest: a study expanded into independent runs with stable ids.
//!
//! A run is one (model, record, mode, intensity). Its id is
//! `<model>__<record>__<mode>__<pga>g` with the PGA target to 0.001 g, e.g.
//! `frame3__elcentro__fe__0.350g`; it depends on nothing but those four values, so a run
//! keeps its id and its folder (`runs/<id>/`) whatever else the study contains.
//!
//! **Stripes** (`intensity.pga_g`): every combination, all in round 0.
//!
//! **IDA** (`[intensity.ida]`) is adaptive: each (model, record, mode) is a *sequence*
//! whose next intensity depends on the outcomes so far ([`next_intensity`]): step up from
//! `start_g` by `step_g` (the last step clamped to `max_g`) until a run collapses, then
//! bisect between the highest intensity without collapse below it (0 if none) and the
//! lowest with collapse, on the 0.001 g grid, until they are at most `tolerance_g` apart.
//! A run's *round* is its index in its sequence. The plan is recomputed from the run
//! folders at any time: it lists every run done so far plus the *frontier*, the one next
//! run of each unfinished sequence. Sequences are independent, so a local executor starts
//! a sequence's next run as soon as its previous one ends, and on Slurm each submitted
//! array covers the current frontier (`slurm/submit.sh` repeats until nothing is pending).
//! A sequence with a failed run stops there.
//!
//! Collapse, for the IDA, is a run with a collapse moment Tc (`summary.json` `tc_s` not
//! null: the criterion was met or the FE diverged first — non-convergence counts as
//! collapse, as usual in IDA practice).
use super::error::{At, Result};
use super::format::{IdaRule, Intensity, Study, MILLI_G};
use crate::output::summary::RunSummary;
use crate::pipeline::Mode;
use serde_json::Value;
use std::path::{Path, PathBuf};

/// One run of the manifest.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Entry {
    /// Stable id (module docs).
    pub id: String,
    /// Index in its IDA sequence (0 for stripes).
    pub round: u32,
    /// Index into [`Study::models`].
    pub model: usize,
    /// Index into [`Study::records`].
    pub record: usize,
    /// Mode.
    pub mode: Mode,
    /// Target intensity, milli-g.
    pub milli_g: u32,
    /// Ensemble member (0: unperturbed; always 0 without an ensemble).
    pub member: u32,
}

impl Entry {
    /// Target intensity, g.
    pub fn pga_g(&self) -> f64 {
        self.milli_g as f64 * MILLI_G
    }
}

/// The run id of (model, record, mode, intensity).
pub(crate) fn run_id(model: &str, record: &str, mode: Mode, milli_g: u32) -> String {
    format!(
        "{model}__{record}__{}__{}.{:03}g",
        mode.name(),
        milli_g / 1000,
        milli_g % 1000
    )
}

/// The run id of an ensemble member: [`run_id`] + `__m<member>` (three digits), e.g.
/// `frame3__FF01__hybrid__0.750g__m002`; without an ensemble (`members` = 1) the plain
/// [`run_id`].
pub fn member_id(
    model: &str,
    record: &str,
    mode: Mode,
    milli_g: u32,
    member: u32,
    members: u32,
) -> String {
    let id = run_id(model, record, mode, milli_g);
    if members > 1 {
        format!("{id}__m{member:03}")
    } else {
        id
    }
}

/// What became of a run.
#[derive(Debug, Clone, PartialEq)]
pub enum Outcome {
    /// Complete with a valid summary; `collapse`: it has a collapse moment Tc.
    Ok {
        /// Tc exists.
        collapse: bool,
    },
    /// Recorded as failed, with its error.
    Failed(String),
}

/// Where an IDA sequence stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SequenceState {
    /// A run is pending.
    Running,
    /// Collapse bracketed: highest intensity without collapse below the lowest with
    /// collapse (`lo`, 0 if none) and that lowest one (`hi`), milli-g.
    Collapse {
        /// Highest intensity without collapse below `hi`, milli-g (0: none run).
        lo: u32,
        /// Lowest intensity with collapse, milli-g.
        hi: u32,
    },
    /// No collapse up to `max_g`: the collapse intensity is right-censored there.
    NoCollapse {
        /// Highest intensity run, milli-g.
        max: u32,
    },
    /// A run failed; the sequence stopped.
    Failed,
}

/// The next step of an IDA sequence.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Next {
    /// Run this intensity (milli-g).
    Run(u32),
    /// The sequence is finished.
    Done(SequenceState),
}

/// The IDA rule (module docs) applied to a sequence's history of (milli-g, outcome), in
/// run order.
pub(crate) fn next_intensity(rule: &IdaRule, history: &[(u32, Outcome)]) -> Next {
    if history.is_empty() {
        return Next::Run(rule.start);
    }
    if history.iter().any(|(_, o)| matches!(o, Outcome::Failed(_))) {
        return Next::Done(SequenceState::Failed);
    }
    let collapsed = |o: &Outcome| matches!(o, Outcome::Ok { collapse: true });
    let hi = history
        .iter()
        .filter(|(_, o)| collapsed(o))
        .map(|(m, _)| *m)
        .min();
    match hi {
        None => {
            let last = history.iter().map(|(m, _)| *m).max().unwrap_or(0);
            if last >= rule.max {
                Next::Done(SequenceState::NoCollapse { max: last })
            } else {
                Next::Run((last + rule.step).min(rule.max))
            }
        }
        Some(hi) => {
            let lo = history
                .iter()
                .filter(|(m, o)| !collapsed(o) && *m < hi)
                .map(|(m, _)| *m)
                .max()
                .unwrap_or(0);
            let mid = lo + (hi - lo) / 2;
            if hi - lo <= rule.tolerance || mid <= lo || mid >= hi {
                Next::Done(SequenceState::Collapse { lo, hi })
            } else {
                Next::Run(mid)
            }
        }
    }
}

/// One IDA sequence (or, for stripes, one (model, record, mode) group).
#[derive(Debug, Clone, PartialEq)]
pub struct Sequence {
    /// Index into [`Study::models`].
    pub model: usize,
    /// Index into [`Study::records`].
    pub record: usize,
    /// Mode.
    pub mode: Mode,
    /// Where it stands (stripes: `Running` until all its runs are done, then
    /// `NoCollapse`/`Collapse` are not used — see [`Plan::finished`]).
    pub state: SequenceState,
}

/// The study expanded against the run folders present.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    /// Every run known so far, sorted by (round, model, record, mode, intensity).
    pub entries: Vec<Entry>,
    /// Outcome of each entry (same order), `None` = pending.
    pub outcomes: Vec<Option<Outcome>>,
    /// IDA sequences (empty for stripes).
    pub sequences: Vec<Sequence>,
}

impl Plan {
    /// Entries still to run.
    pub fn pending(&self) -> impl Iterator<Item = &Entry> {
        self.entries
            .iter()
            .zip(&self.outcomes)
            .filter(|(_, o)| o.is_none())
            .map(|(e, _)| e)
    }

    /// Nothing is pending (every run has an outcome and no sequence continues).
    pub fn finished(&self) -> bool {
        self.outcomes.iter().all(Option::is_some)
    }

    /// The manifest text: a header, then one line per entry
    /// (`id round model record mode pga_g`, tab-separated; an ensemble study adds
    /// `member`).
    pub fn manifest(&self, study: &Study) -> String {
        let ens = study.ensemble.members > 1;
        let mut s = String::from("id\tround\tmodel\trecord\tmode\tpga_g");
        s.push_str(if ens { "\tmember\n" } else { "\n" });
        for e in &self.entries {
            s.push_str(&format!(
                "{}\t{}\t{}\t{}\t{}\t{:.3}",
                e.id,
                e.round,
                study.models[e.model].name,
                study.records[e.record].name,
                e.mode.name(),
                e.pga_g()
            ));
            if ens {
                s.push_str(&format!("\t{}\n", e.member));
            } else {
                s.push('\n');
            }
        }
        s
    }
}

/// Expands `study` given the outcome of each run id so far (`outcome(id)`).
pub fn plan(study: &Study, outcome: &dyn Fn(&str) -> Option<Outcome>) -> Plan {
    let mut entries = Vec::new();
    let mut sequences = Vec::new();
    for (mi, m) in study.models.iter().enumerate() {
        for (ri, r) in study.records.iter().enumerate() {
            for &mode in &study.modes {
                let n = study.ensemble.members;
                let entry = |round: u32, milli_g: u32, member: u32| Entry {
                    id: member_id(&m.name, &r.name, mode, milli_g, member, n),
                    round,
                    model: mi,
                    record: ri,
                    mode,
                    milli_g,
                    member,
                };
                match &study.intensity {
                    Intensity::Stripes(list) => {
                        for &g in list {
                            entries.extend((0..n).map(|k| entry(0, g, k)));
                        }
                    }
                    Intensity::Ida(rule) => {
                        // Every member of an intensity is planned with it; member 0's
                        // outcome drives the sequence (the members share the FE stage,
                        // so they share its collapse moment).
                        let mut history = Vec::new();
                        let state = loop {
                            match next_intensity(rule, &history) {
                                Next::Done(s) => break s,
                                Next::Run(g) => {
                                    let e = entry(history.len() as u32, g, 0);
                                    let o = outcome(&e.id);
                                    entries.push(e);
                                    entries
                                        .extend((1..n).map(|k| entry(history.len() as u32, g, k)));
                                    match o {
                                        Some(o) => history.push((g, o)),
                                        None => break SequenceState::Running,
                                    }
                                }
                            }
                        };
                        sequences.push(Sequence {
                            model: mi,
                            record: ri,
                            mode,
                            state,
                        });
                    }
                }
            }
        }
    }
    let key = |e: &Entry| {
        (
            e.round,
            e.model,
            e.record,
            mode_rank(study, e.mode),
            e.milli_g,
            e.member,
        )
    };
    entries.sort_by_key(key);
    let outcomes = entries.iter().map(|e| outcome(&e.id)).collect();
    Plan {
        entries,
        outcomes,
        sequences,
    }
}

fn mode_rank(study: &Study, m: Mode) -> usize {
    study
        .modes
        .iter()
        .position(|x| *x == m)
        .unwrap_or(usize::MAX)
}

/// The study folder: `runs/<id>/` per run, `results/`, `slurm/`.
#[derive(Debug, Clone)]
pub struct Store {
    /// The study folder.
    pub dir: PathBuf,
}

/// File in a run folder that says how the run ended (written last, with the folder).
pub(crate) const STATUS_FILE: &str = "status.json";

impl Store {
    /// The store of a folder.
    pub fn new(dir: impl Into<PathBuf>) -> Store {
        Store { dir: dir.into() }
    }

    /// `runs/`.
    pub fn runs_dir(&self) -> PathBuf {
        self.dir.join("runs")
    }

    /// `runs/<id>/`.
    pub fn run_dir(&self, id: &str) -> PathBuf {
        self.runs_dir().join(id)
    }

    /// The outcome recorded in `runs/<id>/`: `Ok` only if `status.json` says ok and
    /// `summary.json` is valid JSON with `mode` and `tc_reason`; `Failed` as recorded;
    /// `None` if absent or incomplete (it will be run again).
    pub fn outcome(&self, id: &str) -> Option<Outcome> {
        let dir = self.run_dir(id);
        let status = read_json(&dir.join(STATUS_FILE)).ok()?;
        match status["status"].as_str()? {
            "ok" => {
                let s = read_summary(&dir.join("summary.json")).ok()?;
                Some(Outcome::Ok {
                    collapse: s.tc_s.is_some(),
                })
            }
            "failed" => Some(Outcome::Failed(
                status["error"].as_str().unwrap_or("?").to_string(),
            )),
            _ => None,
        }
    }

    /// The plan of `study` against this folder.
    pub fn plan(&self, study: &Study) -> Plan {
        plan(study, &|id| self.outcome(id))
    }
}

/// Reads a run's `summary.json` ([`RunSummary`]).
pub(crate) fn read_summary(path: &Path) -> Result<RunSummary> {
    let v = read_json(path)?;
    serde_json::from_value(v).at(|| format!("{}: not a run summary", path.display()))
}

/// Reads a JSON file; errors name it.
pub(crate) fn read_json(path: &Path) -> Result<Value> {
    let text = crate::model::limits::read_regular_file(path)
        .at(|| format!("cannot read {}", path.display()))?;
    serde_json::from_str(&text).at(|| format!("{}: not valid JSON", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    const RULE: IdaRule = IdaRule {
        start: 100,
        step: 200,
        max: 1000,
        tolerance: 25,
    };

    /// Drives the rule against a structure that collapses at and above `capacity`.
    fn drive(capacity: u32) -> (Vec<u32>, SequenceState) {
        let mut h = Vec::new();
        loop {
            match next_intensity(&RULE, &h) {
                Next::Run(g) => h.push((
                    g,
                    Outcome::Ok {
                        collapse: g >= capacity,
                    },
                )),
                Next::Done(s) => return (h.iter().map(|x| x.0).collect(), s),
            }
        }
    }

    #[test]
    fn ida_steps_then_bisects_to_the_tolerance() {
        // 100, 300, 500 (collapse) → bisect (300, 500): 400 (c), 350 (c), 325 (no) → 25 apart.
        let (runs, state) = drive(340);
        assert_eq!(runs, vec![100, 300, 500, 400, 350, 325]);
        assert_eq!(state, SequenceState::Collapse { lo: 325, hi: 350 });
    }

    #[test]
    fn ida_clamps_to_max_and_censors() {
        let (runs, state) = drive(5000);
        assert_eq!(runs, vec![100, 300, 500, 700, 900, 1000]);
        assert_eq!(state, SequenceState::NoCollapse { max: 1000 });
    }

    #[test]
    fn ida_collapse_at_start_bisects_down_from_zero() {
        // 100 (c) → bisect (0, 100): 50 (c), 25 (no) → 25 apart.
        let (runs, state) = drive(30);
        assert_eq!(runs, vec![100, 50, 25]);
        assert_eq!(state, SequenceState::Collapse { lo: 25, hi: 50 });
    }

    #[test]
    fn ida_stops_at_a_failure() {
        let h = vec![(100, Outcome::Failed("boom".into()))];
        assert_eq!(next_intensity(&RULE, &h), Next::Done(SequenceState::Failed));
    }

    #[test]
    fn ids_are_stable() {
        assert_eq!(
            run_id("frame3", "FF01", Mode::Fe, 350),
            "frame3__FF01__fe__0.350g"
        );
        assert_eq!(run_id("m", "r", Mode::Hybrid, 1205), "m__r__hybrid__1.205g");
    }
}

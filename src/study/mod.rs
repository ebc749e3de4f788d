//! Batch studies (`fem2rbd study …`): many independent runs of one base
//! scenario over models × records × modes × intensities — incremental dynamic analysis
//! (IDA), collapse fragility, ruin-scenario libraries — on one machine or on a Slurm
//! cluster.
//!
//! * [`format`] — the study file (`docs/study-format.md`), checked completely first;
//! * [`plan`] — the manifest of runs with stable ids, the adaptive IDA rule, the study
//!   folder ([`plan::Store`]: `runs/<id>/`, `results/`, `slurm/`);
//! * [`exec`] — one run in this process (its folder written atomically, failures
//!   recorded) and the local scheduler;
//! * [`slurm`] — sbatch job-array scripts and the submit loop;
//! * [`collect`] — completeness check and aggregation (`results/`);
//! * [`fragility`] — lognormal collapse fragility by maximum likelihood;
//! * [`rescue`] — the rescue maps and measures of the collected runs;
//! * [`plot`] — IDA and fragility figures of a collected study.
pub mod collect;
pub mod error;
pub mod exec;
pub mod format;
pub mod fragility;
pub mod lock;
pub mod plan;
pub mod plot;
pub mod rescue;
pub mod slurm;

pub use error::StudyError;
pub use format::Study;
pub use plan::{Entry, Outcome, Plan, Store};

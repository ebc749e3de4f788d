//! What a run does ([`Mode`]): the vocabulary shared by the scenario file, the study
//! file and `summary.json` (`mode`), below both the pipeline and the outputs.
use serde::{Deserialize, Serialize};

/// What runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "snake_case")]
pub enum Mode {
    /// FE until the collapse moment Tc, then Bullet with the remaining ground motion.
    Hybrid,
    /// Bullet alone from t = 0 on the undeformed model (BCB alone).
    Physics,
    /// FE only.
    Fe,
}

impl Mode {
    /// The name used in files.
    pub fn name(self) -> &'static str {
        match self {
            Mode::Hybrid => "hybrid",
            Mode::Physics => "physics",
            Mode::Fe => "fe",
        }
    }
}

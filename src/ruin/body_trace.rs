//! Debug trace of one body's substeps (off unless `FEM2RBD_BODY_TRACE=<file>` is set):
//! for the body named `FEM2RBD_BODY_TRACE_BODY` (e.g. `Column:3:34`), in every substep
//! ending in [`FEM2RBD_BODY_TRACE_FROM`, `FEM2RBD_BODY_TRACE_TO`] s, its velocity before
//! and after, and what acted on it: each constraint of its connections (enabled after the
//! substep, applied impulse of its first row, N·s, and the joint feedback force on the
//! body, N) and each contact with another body (points, smallest signed distance, m, and
//! the sum of the normal impulses, N·s). Written by the pipeline after the ruin stage
//! ([`super::stage::RuinStage::body_trace_report`]). Used to find where a body that
//! breaks the speed bound of `super::energy` gets its speed (docs/ruin-numerics.md §15).

use std::fmt::Write;

/// The trace's settings and rows.
#[derive(Debug)]
pub(crate) struct BodyTrace {
    pub(crate) path: std::path::PathBuf,
    /// Input index of the traced body.
    pub(crate) body: usize,
    pub(crate) from_s: f64,
    pub(crate) to_s: f64,
    /// Every input body's name.
    pub(crate) names: Vec<String>,
    rows: Vec<String>,
}

impl BodyTrace {
    /// The trace if `FEM2RBD_BODY_TRACE` is set and the body is found (`names`: the input
    /// bodies' names).
    pub(crate) fn from_env(names: &[String]) -> Option<BodyTrace> {
        let path = std::env::var_os("FEM2RBD_BODY_TRACE")?;
        let name = std::env::var("FEM2RBD_BODY_TRACE_BODY").ok()?;
        let body = names.iter().position(|n| *n == name)?;
        let num = |k: &str, d: f64| {
            std::env::var(k)
                .ok()
                .and_then(|v| v.parse::<f64>().ok())
                .unwrap_or(d)
        };
        Some(BodyTrace {
            path: path.into(),
            body,
            from_s: num("FEM2RBD_BODY_TRACE_FROM", 0.0),
            to_s: num("FEM2RBD_BODY_TRACE_TO", f64::INFINITY),
            rows: vec![format!("# body {name}")],
            names: names.to_vec(),
        })
    }

    /// Whether a substep ending at `t` is traced.
    pub(crate) fn wants(&self, t: f64) -> bool {
        t >= self.from_s && t <= self.to_s
    }

    /// One line of the trace.
    pub(crate) fn push(&mut self, line: String) {
        self.rows.push(line);
    }

    /// Where the trace goes and its text.
    pub(crate) fn report(&self) -> (std::path::PathBuf, String) {
        let mut f = String::new();
        for r in &self.rows {
            let _ = writeln!(f, "{r}");
        }
        (self.path.clone(), f)
    }
}

//! Debug trace of one body's substeps (off unless `fem2rbd run --trace-body NAME
//! --trace-body-file FILE` asks for it, [`super::settings::BodyTraceSettings`]): for the
//! body named NAME (e.g. `Column:3:34`), in every substep ending in [`--trace-from`,
//! `--trace-to`] s, its velocity before
//! and after, and what acted on it: each constraint of its connections (enabled after the
//! substep, applied impulse of its first row, N·s, and the joint feedback force on the
//! body, N) and each contact with another body (points, smallest signed distance, m, and
//! the sum of the normal impulses, N·s). Written by the pipeline after the ruin stage
//! ([`super::stage::RuinStage::body_trace_report`]). Used to find where a body that
//! breaks the speed bound of `super::energy` gets its speed (docs/ruin-numerics.md, "The monitor's frame").

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
    /// The trace of `settings` (`names`: the input bodies' names); an error naming the
    /// body when no input body has its name.
    pub(crate) fn new(
        settings: &super::settings::BodyTraceSettings,
        names: &[String],
    ) -> Result<BodyTrace, String> {
        let name = &settings.body;
        let body = names
            .iter()
            .position(|n| n == name)
            .ok_or_else(|| format!("no body named {name:?}"))?;
        Ok(BodyTrace {
            path: settings.path.clone(),
            body,
            from_s: settings.from_s,
            to_s: settings.to_s,
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

#[cfg(test)]
mod tests {
    use super::super::settings::BodyTraceSettings;
    use super::*;

    /// The body found by name and the window kept; an unknown body is an error naming it.
    #[test]
    fn the_trace_finds_its_body_by_name() {
        let names = vec!["Column:1:1".to_string(), "Beam:1:2".to_string()];
        let settings = |body: &str| BodyTraceSettings {
            path: "t.txt".into(),
            body: body.into(),
            from_s: 2.5,
            to_s: f64::INFINITY,
        };
        let t = BodyTrace::new(&settings("Beam:1:2"), &names).unwrap();
        assert_eq!((t.body, t.from_s, t.to_s), (1, 2.5, f64::INFINITY));
        assert!(t.wants(2.5) && !t.wants(2.4));
        let m = BodyTrace::new(&settings("Column:9:9"), &names).unwrap_err();
        assert!(m.contains("Column:9:9"), "{m}");
    }
}

//! Debug trace of one body's substeps (off unless `FEM2RBD_BODY_TRACE=<file>` is set):
//! for the body named `FEM2RBD_BODY_TRACE_BODY` (e.g. `Column:3:34`), in every substep
//! ending in [`FEM2RBD_BODY_TRACE_FROM`, `FEM2RBD_BODY_TRACE_TO`] s, its velocity before
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
    /// The trace if `FEM2RBD_BODY_TRACE` is set (`names`: the input bodies' names). An
    /// error (the variable's name and why) when the body is missing or unknown, or a time
    /// is not a number.
    pub(crate) fn from_env(names: &[String]) -> Result<Option<BodyTrace>, (&'static str, String)> {
        Self::from_vars(|k| std::env::var(k).ok(), names)
    }

    /// [`Self::from_env`] with the variables read by `var`.
    fn from_vars(
        var: impl Fn(&str) -> Option<String>,
        names: &[String],
    ) -> Result<Option<BodyTrace>, (&'static str, String)> {
        let Some(path) = var("FEM2RBD_BODY_TRACE") else {
            return Ok(None);
        };
        const BODY: &str = "FEM2RBD_BODY_TRACE_BODY";
        let name = var(BODY).ok_or((BODY, "not set".to_string()))?;
        let body = names
            .iter()
            .position(|n| *n == name)
            .ok_or_else(|| (BODY, format!("no body named {name:?}")))?;
        let num = |k: &'static str, d: f64| match var(k) {
            None => Ok(d),
            Some(v) => v
                .trim()
                .parse::<f64>()
                .map_err(|_| (k, format!("{v:?} is not a time in s"))),
        };
        Ok(Some(BodyTrace {
            path: path.into(),
            body,
            from_s: num("FEM2RBD_BODY_TRACE_FROM", 0.0)?,
            to_s: num("FEM2RBD_BODY_TRACE_TO", f64::INFINITY)?,
            rows: vec![format!("# body {name}")],
            names: names.to_vec(),
        }))
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
    use super::*;

    fn vars<'a>(pairs: &'a [(&'a str, &'a str)]) -> impl Fn(&str) -> Option<String> + 'a {
        move |k| {
            pairs
                .iter()
                .find(|(n, _)| *n == k)
                .map(|(_, v)| v.to_string())
        }
    }

    /// Off without the file variable; the body found by name and the window read; a
    /// missing or unknown body or a bad time is an error naming its variable.
    #[test]
    fn the_trace_is_read_from_its_variables() {
        let names = vec!["Column:1:1".to_string(), "Beam:1:2".to_string()];
        assert!(BodyTrace::from_vars(vars(&[]), &names).unwrap().is_none());
        let t = BodyTrace::from_vars(
            vars(&[
                ("FEM2RBD_BODY_TRACE", "t.txt"),
                ("FEM2RBD_BODY_TRACE_BODY", "Beam:1:2"),
                ("FEM2RBD_BODY_TRACE_FROM", " 2.5"),
            ]),
            &names,
        )
        .unwrap()
        .unwrap();
        assert_eq!((t.body, t.from_s, t.to_s), (1, 2.5, f64::INFINITY));
        assert!(t.wants(2.5) && !t.wants(2.4));
        let err = |extra: &[(&'static str, &'static str)]| {
            let mut v = vec![("FEM2RBD_BODY_TRACE", "t.txt")];
            v.extend_from_slice(extra);
            BodyTrace::from_vars(vars(&v), &names).unwrap_err()
        };
        assert_eq!(err(&[]).0, "FEM2RBD_BODY_TRACE_BODY");
        let (k, m) = err(&[("FEM2RBD_BODY_TRACE_BODY", "Column:9:9")]);
        assert_eq!(k, "FEM2RBD_BODY_TRACE_BODY");
        assert!(m.contains("Column:9:9"), "{m}");
        let (k, m) = err(&[
            ("FEM2RBD_BODY_TRACE_BODY", "Column:1:1"),
            ("FEM2RBD_BODY_TRACE_TO", "soon"),
        ]);
        assert_eq!(k, "FEM2RBD_BODY_TRACE_TO");
        assert!(m.contains("soon"), "{m}");
    }
}

//! What a run does ([`Mode`]): the vocabulary shared by the scenario file, the study
//! file and `summary.json` (`mode`), below both the pipeline and the outputs.
use serde::{Deserialize, Serialize};

/// What runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Mode {
    /// FE until the collapse moment Tc, then Bullet with the remaining ground motion.
    Hybrid,
    /// Every member a rigid box in Bullet from t = 0 on the undeformed model (BCB alone).
    /// Read also under its former name `physics`, with a warning ([`Mode::former_name`]).
    #[serde(alias = "physics")]
    Rigid,
    /// FE only.
    Fe,
}

impl Mode {
    /// The name used in files.
    pub fn name(self) -> &'static str {
        match self {
            Mode::Hybrid => "hybrid",
            Mode::Rigid => "rigid",
            Mode::Fe => "fe",
        }
    }

    /// The warning for a mode given by its former name (`physics`, now `rigid`: the
    /// `[physics]` table configures the ruin stage in every mode, so the mode that runs
    /// rigid bodies alone has a name of its own); `None` for a current name. `item` names
    /// where the name was read, e.g. `scenario.toml: mode`.
    pub fn former_name(name: &str, item: &str) -> Option<String> {
        (name == "physics").then(|| {
            format!(
                "warning: {item}: mode \"physics\" is now called \"rigid\" (rigid bodies \
                 alone from t = 0); the old name is read as \"rigid\""
            )
        })
    }

    /// Warns on stderr for each former mode name in a scenario's `mode` or a study's
    /// `modes` (TOML `text` of the file `file`, already parsed successfully).
    pub fn warn_former_names(text: &str, file: &str) {
        let Ok(table) = text.parse::<toml::Table>() else {
            return;
        };
        let mut names: Vec<(&str, &str)> = Vec::new();
        if let Some(m) = table.get("mode").and_then(toml::Value::as_str) {
            names.push(("mode", m));
        }
        if let Some(ms) = table.get("modes").and_then(toml::Value::as_array) {
            names.extend(
                ms.iter()
                    .filter_map(toml::Value::as_str)
                    .map(|m| ("modes", m)),
            );
        }
        for (key, name) in names {
            if let Some(w) = Mode::former_name(name, &format!("{file}: {key}")) {
                eprintln!("{w}");
            }
        }
    }

    /// Parses a mode given on the command line, warning on stderr for a former name.
    pub fn from_arg(arg: &str) -> Result<Mode, String> {
        if let Some(w) = Mode::former_name(arg, "--mode") {
            eprintln!("{w}");
        }
        match arg {
            "hybrid" => Ok(Mode::Hybrid),
            "rigid" | "physics" => Ok(Mode::Rigid),
            "fe" => Ok(Mode::Fe),
            other => Err(format!(
                "unknown mode {other:?}: the modes are hybrid, rigid and fe"
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_former_name_of_the_rigid_mode_is_read_and_warned_about() {
        assert_eq!(Mode::from_arg("physics"), Ok(Mode::Rigid));
        assert_eq!(Mode::from_arg("rigid"), Ok(Mode::Rigid));
        assert!(Mode::from_arg("bullet")
            .unwrap_err()
            .contains("hybrid, rigid and fe"));
        let w = Mode::former_name("physics", "s.toml: mode").unwrap();
        assert!(w.contains("s.toml: mode") && w.contains("\"rigid\""), "{w}");
        assert_eq!(Mode::former_name("rigid", "x"), None);
        #[derive(Deserialize)]
        struct T {
            mode: Mode,
        }
        let t: T = toml::from_str("mode = \"physics\"").unwrap();
        assert_eq!(t.mode, Mode::Rigid);
        for m in [Mode::Hybrid, Mode::Rigid, Mode::Fe] {
            assert_eq!(Mode::from_arg(m.name()), Ok(m));
        }
    }
}

//! The one ground-motion syntax of the command line, shared by `fem2rbd fe` and
//! `fem2rbd export opensees`:
//!
//! ```text
//! --gm DIR=PATH[,pga=G]      DIR = X, Y or Z; PATH a record file; G the target PGA in g
//! --gm DIR=PATH,G            the same, the PGA given bare
//! ```
//!
//! Without a PGA the record is used as recorded. The PGA must lie in
//! (0, [`MAX_PGA_G`]] g; a direction may be given once. [`read_components`] reads,
//! checks, scales and time-scales the records with the same code as a scenario's
//! `[[ground_motion]]`, so a record one command rejects every command rejects.
use super::{Format, GroundMotion, AXES};
use crate::model::limits::{check_range, show_number, MAX_PGA_G, TIME_SCALE};
use std::path::{Path, PathBuf};

/// One `--gm` component.
#[derive(Debug, Clone, PartialEq)]
pub struct ComponentArg {
    /// 0 = X, 1 = Y, 2 = Z.
    pub axis: usize,
    /// Record file.
    pub path: PathBuf,
    /// Target PGA (g); `None` = as recorded.
    pub pga_g: Option<f64>,
}

/// A `--gm` value that does not follow the syntax (module docs); names the value.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("--gm {arg:?}: {message}")]
pub struct GmArgError {
    /// The value as given.
    pub arg: String,
    /// What is wrong.
    pub message: String,
}

/// Parses one `--gm` value (module docs).
pub fn parse_component(s: &str) -> Result<ComponentArg, GmArgError> {
    let err = |m: String| GmArgError {
        arg: s.to_string(),
        message: m,
    };
    let (dir, rest) = s
        .split_once('=')
        .ok_or_else(|| err("expected DIR=PATH[,pga=G]".into()))?;
    let axis = dir
        .parse::<super::Direction>()
        .map_err(|_| {
            err(format!(
                "unknown direction {:?} (use X, Y or Z)",
                dir.trim().to_ascii_uppercase()
            ))
        })?
        .index();
    let mut parts = rest.split(',');
    let path = parts.next().unwrap_or("").trim();
    if path.is_empty() {
        return Err(err(
            "no record file given (expected DIR=PATH[,pga=G])".into()
        ));
    }
    let mut pga_g = None;
    for p in parts {
        if pga_g.is_some() {
            return Err(err("the PGA is given twice".into()));
        }
        let value = match p.split_once('=') {
            Some((k, v)) if k.trim().eq_ignore_ascii_case("pga") => v,
            Some((k, _)) => return Err(err(format!("unknown option {k:?} (only pga=G)"))),
            None => p,
        };
        let g: f64 = value
            .trim()
            .parse()
            .map_err(|_| err(format!("PGA {:?} is not a number", value.trim())))?;
        check_range("pga", g, 0.0, true, MAX_PGA_G, "g").map_err(|e| err(e.to_string()))?;
        pga_g = Some(g);
    }
    Ok(ComponentArg {
        axis,
        path: PathBuf::from(path),
        pga_g,
    })
}

/// Reads the records of `specs` (each one file, `format`), scales each to its PGA and
/// time-scales all by `time_scale` ∈ [`TIME_SCALE`]. Errors name the `--gm` value or the
/// file and line.
pub fn read_components(
    specs: &[ComponentArg],
    time_scale: f64,
    format: Format,
) -> anyhow::Result<GroundMotion> {
    check_range(
        "--time-scale",
        time_scale,
        TIME_SCALE.0,
        false,
        TIME_SCALE.1,
        "",
    )?;
    let mut paths: [Option<&Path>; 3] = [None; 3];
    let mut pga = [None; 3];
    for s in specs {
        if paths[s.axis].is_some() {
            anyhow::bail!("--gm: direction {} given twice", AXES[s.axis]);
        }
        paths[s.axis] = Some(s.path.as_path());
        pga[s.axis] = s.pga_g;
    }
    let mut gm = GroundMotion::from_files(paths, format)?;
    gm.scale_to_pga(pga)?;
    if time_scale != 1.0 {
        gm.time_scale(time_scale)?;
    }
    if gm.duration_s() <= 0.0 {
        anyhow::bail!(
            "--gm: the ground motion lasts {} s (a record needs at least two samples)",
            show_number(gm.duration_s())
        );
    }
    Ok(gm)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_grammar() {
        let a = parse_component("x=a.at2").unwrap();
        assert_eq!((a.axis, a.pga_g), (0, None));
        assert_eq!(parse_component("Y=b.at2,pga=0.3").unwrap().pga_g, Some(0.3));
        assert_eq!(parse_component("Z=c.at2,0.3").unwrap().axis, 2);
        for (bad, msg) in [
            ("X", "expected DIR=PATH"),
            ("W=a", "unknown direction"),
            ("X=", "no record file"),
            ("X=a,pga=abc", "is not a number"),
            ("X=a,0", "pga = 0 g: must be in (0, 5] g"),
            ("X=a,nan", "pga = NaN g"),
            ("X=a,50", "pga = 50 g"),
            ("X=a,0.1,0.2", "given twice"),
            ("X=a,scale=2", "unknown option"),
        ] {
            let e = parse_component(bad).unwrap_err().to_string();
            assert!(e.contains(msg) && e.contains(bad), "{bad}: {e}");
        }
    }
}

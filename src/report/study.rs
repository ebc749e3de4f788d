//! The report of a collected study folder (`fem2rbd study collect`: `results/study.json`,
//! `results/ida.csv`, `results/density/`, `results/rescue/`; docs/studies.md): one
//! self-contained page with
//!
//! * the study's key numbers (`study.json`: the runs, the failed ones, the intensity
//!   measure) and a table of the collapse fragilities (model, mode, method, collapses, the
//!   lognormal median θ and dispersion β, or why there is no fit);
//! * the IDA and fragility figures of `fem2rbd plot STUDY_DIR`
//!   ([`crate::study::plot::figures`]), inlined as SVG;
//! * per intensity (model, mode, PGA) the debris-density map and the rescue maps: the
//!   share of the intensity's runs with a survivable void beneath each plan cell (and one
//!   the rescuer or the camera reaches, or any void), the spread of their void and pile
//!   measures and where survivable voids recur (`results/rescue/<model>__<mode>__<pga>g.csv`
//!   and `.json`, drawn as in the ensemble report, [`super::rescue_map`]).
//!
//! No script is needed: the page is its figures and tables. Each intensity is a
//! `<section class="intensity" data-stem="<model>__<mode>__<pga>g">`.
use super::html::escape;
use super::plots::svg_element;
use super::script::PAGE_CSS;
use super::{inconsistent, ReportError, Result};
use serde_json::Value;
use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Whether `dir` is a collected study folder (it holds `results/study.json`).
pub fn is_study(dir: &Path) -> bool {
    crate::study::plot::is_study_folder(dir)
}

fn read_json(path: &Path) -> Result<Value> {
    let text = std::fs::read_to_string(path).map_err(|error| ReportError::Read {
        path: path.to_path_buf(),
        error,
    })?;
    serde_json::from_str(&text).map_err(|e| inconsistent(path, format!("not JSON: {e}")))
}

/// The stems `<model>__<mode>__<pga>g` of the files `results/<sub>/*.<ext>`, sorted.
fn stems(dir: &Path, sub: &str, ext: &str) -> Result<BTreeSet<String>> {
    let d = dir.join("results").join(sub);
    let mut out = BTreeSet::new();
    if !d.is_dir() {
        return Ok(out);
    }
    let entries = std::fs::read_dir(&d).map_err(|error| ReportError::Read {
        path: d.clone(),
        error,
    })?;
    for e in entries {
        let p = e
            .map_err(|error| ReportError::Read {
                path: d.clone(),
                error,
            })?
            .path();
        if p.extension().is_some_and(|x| x == ext) {
            if let Some(s) = p.file_stem() {
                out.insert(s.to_string_lossy().into_owned());
            }
        }
    }
    Ok(out)
}

fn num(v: &Value, digits: usize) -> String {
    v.as_f64()
        .map_or("–".to_string(), |x| format!("{x:.digits$}"))
}

/// The study page of the collected study folder `dir`, as HTML text.
pub fn report_html(dir: &Path) -> Result<String> {
    let sj_path = dir.join("results").join("study.json");
    let sj = read_json(&sj_path)?;
    let figures =
        crate::study::plot::figures(dir).map_err(|e| inconsistent(&sj_path, e.to_string()))?;
    let svg = |stem: &str, fig: &crate::study::plot::StudyFigure| -> Result<String> {
        let text = crate::plot::svg_string(fig).map_err(|e| inconsistent(dir, e.to_string()))?;
        svg_element(&text).map_err(|m| inconsistent(dir, format!("{stem}: {m}")))
    };
    let study = sj["study"].as_str().unwrap_or("study");
    let title = format!("fem2rbd study report: {study}");
    let mut h = super::html::head(&title, PAGE_CSS);
    let _ = write!(
        h,
        r#"<header><h1>{}</h1><p id="headline">{} runs ({} failed), intensity measure {}: the collapse fragilities, the IDA curves and, per intensity, the debris density and the chance of a survivable void.</p></header>"#,
        escape(&title),
        sj["runs"],
        sj["failed"].as_array().map_or(0, Vec::len),
        escape(sj["intensity_measure"].as_str().unwrap_or("?")),
    );
    // Fragilities.
    h.push_str(r#"<section id="fragility"><h2>Collapse fragility</h2><table id="fragility-table"><thead><tr><th>model</th><th>mode</th><th>method</th><th>collapses</th><th>no collapse</th><th>median θ (g)</th><th>dispersion β</th></tr></thead><tbody>"#);
    let empty = Vec::new();
    for fr in sj["fragility"].as_array().unwrap_or(&empty) {
        let fit = &fr["fit"];
        let (theta, beta) = if fit.is_object() {
            (num(&fit["median_g"], 3), num(&fit["beta"], 3))
        } else {
            (
                format!(
                    "no fit: {}",
                    escape(fr["fit_error"].as_str().unwrap_or("?"))
                ),
                "–".to_string(),
            )
        };
        let _ = write!(
            h,
            r#"<tr data-model="{m}" data-mode="{o}" data-median="{}"><td>{m}</td><td>{o}</td><td>{}</td><td>{}</td><td>{}</td><td>{theta}</td><td>{beta}</td></tr>"#,
            fit["median_g"],
            escape(fr["method"].as_str().unwrap_or("?")),
            fr["collapses"],
            fr["non_collapses"],
            m = escape(fr["model"].as_str().unwrap_or("?")),
            o = escape(fr["mode"].as_str().unwrap_or("?")),
        );
    }
    h.push_str("</tbody></table>");
    // IDA and fragility figures.
    h.push_str(r#"<div id="study-figures" class="plots">"#);
    for (stem, fig) in figures.iter().filter(|(s, _)| !s.starts_with("density_")) {
        let _ = write!(
            h,
            r#"<figure data-plot="{}">{}<figcaption>{}</figcaption></figure>"#,
            escape(stem),
            svg(stem, fig)?,
            escape(stem)
        );
    }
    h.push_str("</div></section>");
    // Per intensity: the debris density and the rescue maps.
    let density = stems(dir, "density", "json")?;
    let rescue = stems(dir, "rescue", "json")?;
    let all: BTreeSet<&String> = density.iter().chain(&rescue).collect();
    h.push_str(r#"<section id="intensities"><h2>Per intensity</h2>"#);
    if all.is_empty() {
        h.push_str(r#"<p class="note" id="intensities-none">No debris-density or rescue maps: the study has no run with a ruin stage (<code>results/density/</code>, <code>results/rescue/</code>).</p>"#);
    }
    for (n, stem) in all.iter().enumerate() {
        let label = stem.replace("__", ", ");
        let _ = write!(
            h,
            r#"<section class="intensity" data-stem="{s}"><h3>{}</h3>"#,
            escape(&label),
            s = escape(stem),
        );
        let dstem = format!("density_{}", stem.replace("__", "_"));
        if let Some((_, fig)) = figures.iter().find(|(s, _)| *s == dstem) {
            let _ = write!(
                h,
                r#"<figure data-plot="{d}">{}<figcaption>Share of the runs with debris over each plan cell (<code>results/density/{s}.json</code>).</figcaption></figure>"#,
                svg(&dstem, fig)?,
                d = escape(&dstem),
                s = escape(stem),
            );
        }
        if rescue.contains(*stem) {
            let base: PathBuf = dir.join("results").join("rescue");
            let _ = write!(
                h,
                r#"<h4>Survivable voids over the runs</h4>{}"#,
                super::rescue_map::section_of(
                    &base.join(format!("{stem}.csv")),
                    &base.join(format!("{stem}.json")),
                    &format!("-{n}"),
                )?
            );
        }
        h.push_str("</section>");
    }
    h.push_str(
        r#"</section>
<footer><details><summary>About this page</summary><p>Written by <code>fem2rbd report</code> from the study folder's <code>results/</code> alone; it works offline and needs no script.</p></details></footer>
</body>
</html>
"#,
    );
    Ok(h)
}

//! The run's own figures, `RUN_DIR/plots/*.svg` (written by `fem2rbd plot`), inlined in
//! the page in file-name order. An SVG's XML declaration and DOCTYPE are dropped; what
//! remains must be one `<svg …>…</svg>` element with no `<script>`, or the file is named
//! in an error.
use super::{inconsistent, ReportError, Result};
use std::path::Path;

/// One inlined figure: its file stem and its `<svg>` element.
#[derive(Debug, Clone, PartialEq)]
pub struct Plot {
    /// File stem (`ruin_plan`, …).
    pub name: String,
    /// The `<svg>` element.
    pub svg: String,
}

/// The figures of `dir/plots` (none when the folder does not exist).
pub fn load(dir: &Path) -> Result<Vec<Plot>> {
    let plots = dir.join("plots");
    if !plots.is_dir() {
        return Ok(Vec::new());
    }
    let read_err = |path: &Path| {
        let path = path.to_path_buf();
        move |error| ReportError::Read { path, error }
    };
    let mut files = Vec::new();
    for e in std::fs::read_dir(&plots).map_err(read_err(&plots))? {
        let p = e.map_err(read_err(&plots))?.path();
        if p.extension().is_some_and(|x| x == "svg") && p.is_file() {
            files.push(p);
        }
    }
    files.sort();
    let mut out = Vec::new();
    for p in files {
        let text = crate::model::limits::read_regular_file(&p).map_err(read_err(&p))?;
        out.push(Plot {
            name: p
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default(),
            svg: svg_element(&text).map_err(|m| inconsistent(&p, m))?,
        });
    }
    Ok(out)
}

/// The `<svg>` element of an SVG file's text (module docs).
pub fn svg_element(text: &str) -> std::result::Result<String, String> {
    let mut rest = text.trim_start();
    loop {
        if rest.starts_with("<?") {
            let end = rest.find("?>").ok_or("an unclosed <? … ?> declaration")?;
            rest = rest[end + 2..].trim_start();
        } else if rest.starts_with("<!DOCTYPE") || rest.starts_with("<!--") {
            let close = if rest.starts_with("<!--") { "-->" } else { ">" };
            let end = rest
                .find(close)
                .ok_or("an unclosed declaration or comment")?;
            rest = rest[end + close.len()..].trim_start();
        } else {
            break;
        }
    }
    let body = rest.trim_end();
    if !body.starts_with("<svg") || !body.ends_with("</svg>") {
        return Err("is not an SVG image (no <svg> … </svg> element)".into());
    }
    if body.to_ascii_lowercase().contains("<script") {
        return Err("holds a <script> element; the report inlines figures without scripts".into());
    }
    Ok(body.to_string())
}

#[cfg(test)]
mod tests {
    use super::svg_element;

    #[test]
    fn the_declaration_goes_and_the_element_stays() {
        let t = "<?xml version=\"1.0\"?>\n<!DOCTYPE svg>\n<svg width=\"2\"><rect/></svg>\n";
        assert_eq!(svg_element(t).unwrap(), "<svg width=\"2\"><rect/></svg>");
        assert!(svg_element("<html></html>")
            .unwrap_err()
            .contains("not an SVG"));
        assert!(svg_element("<svg><script>x</script></svg>")
            .unwrap_err()
            .contains("<script>"));
    }
}

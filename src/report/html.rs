//! HTML text: escaping of text and attribute values, and JSON that can sit inside a
//! `<script>` element.

/// `s` with `&`, `<`, `>`, `"` and `'` replaced by character references (HTML text and
/// quoted attribute values).
pub fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

/// The start of a report page up to `<body>`: document type, character set, viewport,
/// generator, the title (escaped here) and the page's style sheet `css`.
pub fn head(title: &str, css: &str) -> String {
    format!(
        r#"<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<meta name="generator" content="fem2rbd {version}">
<title>{title}</title>
<style>{css}</style>
</head>
<body>
"#,
        version = env!("CARGO_PKG_VERSION"),
        title = escape(title),
    )
}

/// The name a report gives the folder `dir`: its last component once resolved, else the
/// path as given.
pub fn folder_name(dir: &std::path::Path) -> String {
    dir.canonicalize()
        .ok()
        .and_then(|d| d.file_name().map(|n| n.to_string_lossy().into_owned()))
        .unwrap_or_else(|| dir.display().to_string())
}

/// JSON text safe inside `<script type="application/json">`: `<` (which only occurs in
/// strings) as `\u003c`, so no body name can close the element.
pub fn script_json(value: &serde_json::Value) -> String {
    value.to_string().replace('<', "\\u003c")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_folder_name_with_markup_cannot_add_to_the_head() {
        let h = head("fem2rbd report: <script>x</script>", "p{}");
        assert!(h.contains("<title>fem2rbd report: &lt;script&gt;x&lt;/script&gt;</title>"));
        assert_eq!(h.matches("<script").count(), 0);
    }

    #[test]
    fn escapes_markup_and_quotes() {
        assert_eq!(
            escape(r#"a<b & "c" 'd'>"#),
            "a&lt;b &amp; &quot;c&quot; &#39;d&#39;&gt;"
        );
    }

    #[test]
    fn script_json_cannot_close_the_script_and_parses_back() {
        let v = serde_json::json!({"name": "</script><b>x"});
        let text = script_json(&v);
        assert!(!text.contains('<'), "{text}");
        let back: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(back, v);
    }
}

//! `fem2rbd plot` needs no system font: plotters is built without its `ttf` feature (which
//! pulls font-kit → fontconfig / FreeType) and draws text with `ab_glyph` from the bundled
//! DejaVu Sans. This test fails if a system-font crate enters the dependency graph, and
//! checks that the bundled font and its licence are in place.
const ROOT: &str = env!("CARGO_MANIFEST_DIR");

#[test]
fn no_system_font_crates_in_the_lock_file() {
    let lock = std::fs::read_to_string(format!("{ROOT}/Cargo.lock")).unwrap();
    let names: Vec<&str> = lock
        .lines()
        .filter_map(|l| l.strip_prefix("name = \""))
        .map(|l| l.trim_end_matches('"'))
        .collect();
    assert!(names.contains(&"plotters") && names.contains(&"ab_glyph"));
    for bad in [
        "font-kit",
        "yeslogic-fontconfig-sys",
        "servo-fontconfig",
        "servo-fontconfig-sys",
        "freetype",
        "freetype-sys",
        "core-text",
        "dwrote",
    ] {
        assert!(!names.contains(&bad), "{bad} is in Cargo.lock");
    }
}

#[test]
fn bundled_font_and_licence() {
    let ttf = std::fs::read(format!("{ROOT}/data/fonts/DejaVuSans.ttf")).unwrap();
    // TrueType signature 0x00010000
    assert_eq!(&ttf[..4], &[0, 1, 0, 0]);
    assert_eq!(ttf.len(), 759_720, "DejaVu Sans 2.37 as shipped by Debian");
    let lic = std::fs::read_to_string(format!("{ROOT}/data/fonts/LICENSE-DejaVu.txt")).unwrap();
    assert!(lic.contains("Bitstream Vera Fonts Copyright"));
    assert!(lic.contains("Arev Fonts Copyright"));
    // it parses as a font and registers with plotters (text drawing: tests/it/plot/run_folder.rs)
    fem2rbd::plot::font::ensure_registered().unwrap();
}

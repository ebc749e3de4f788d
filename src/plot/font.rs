//! The one typeface of every figure: DejaVu Sans, shipped in `data/fonts/` (licence
//! `data/fonts/LICENSE-DejaVu.txt`) and compiled into the program, registered with
//! plotters' `ab_glyph` renderer under the family name [`FAMILY`]. PNG text therefore
//! needs no system font, fontconfig or FreeType; SVG text names the same family and is
//! laid out with the same metrics.
use super::{PlotError, Result};
use plotters::style::FontStyle;
use std::sync::OnceLock;

/// The font family name every figure asks for.
pub(crate) const FAMILY: &str = "sans-serif";

/// DejaVu Sans 2.37 (Debian `fonts-dejavu-core` 2.37-6), unmodified.
static DEJAVU_SANS: &[u8] = include_bytes!("../../data/fonts/DejaVuSans.ttf");

/// Registers the bundled font once per process (idempotent, thread-safe).
pub fn ensure_registered() -> Result<()> {
    static OK: OnceLock<bool> = OnceLock::new();
    let ok = *OK.get_or_init(|| {
        plotters::style::register_font(FAMILY, FontStyle::Normal, DEJAVU_SANS).is_ok()
    });
    if !ok {
        return Err(PlotError::Font);
    }
    Ok(())
}

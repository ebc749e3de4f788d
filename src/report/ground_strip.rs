//! The ground motion as a strip under the time slider: the ground displacement of each
//! frame (`history.csv`, x, y, z) against time on the slider's axis, the FE stage shaded,
//! Tc marked, an SVG of [`WIDTH`] × [`HEIGHT`] user units stretched to the slider's width.
//!
//! Time t maps to u = [`WIDTH`] · (t − t₀)/(t₁ − t₀) over the timeline [t₀, t₁];
//! displacement d to v = mid − d/d_max · half, with d_max the largest |d| of any
//! component (the strip's scale, written in its legend), half = 0.42 · [`HEIGHT`].
use super::html::escape;
use crate::output::run_folder::RunFolder;
use std::fmt::Write as _;

/// Width of the strip, SVG user units.
pub const WIDTH: f64 = 1000.0;
/// Height of the strip, SVG user units.
pub const HEIGHT: f64 = 80.0;

/// Colours of the x, y, z components.
const COMPONENT_COLOURS: [&str; 3] = ["#c0392b", "#2e86c1", "#7d8c2a"];

/// A step of 1, 2 or 5 × 10ⁿ s giving at most about 12 ticks over `span` s.
fn tick_step(span: f64) -> f64 {
    let raw = span / 12.0;
    let p = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * p)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * p)
}

/// The strip's SVG element (`id="ground-strip"`); the page moves its `#strip-cursor`.
pub fn svg(run: &RunFolder) -> String {
    let t0 = run.frames.first().map_or(0.0, |f| f.0);
    let t1 = run.frames.last().map_or(0.0, |f| f.0);
    let span = if t1 > t0 { t1 - t0 } else { 1.0 };
    let u = |t: f64| WIDTH * (t - t0) / span;
    let d_max = run
        .history
        .iter()
        .flat_map(|h| h.ground_m)
        .fold(0.0f64, |m, d| m.max(d.abs()));
    let mid = HEIGHT / 2.0;
    let half = 0.42 * HEIGHT;
    let v = |d: f64| {
        if d_max > 0.0 {
            mid - d / d_max * half
        } else {
            mid
        }
    };
    let mut s = String::new();
    let _ = write!(
        s,
        r#"<svg id="ground-strip" viewBox="0 0 {WIDTH} {HEIGHT}" preserveAspectRatio="none" role="img" aria-label="ground displacement against time">"#
    );
    let fe_end = run
        .history
        .iter()
        .filter(|h| h.fe)
        .map(|h| h.t_s)
        .fold(f64::NEG_INFINITY, f64::max);
    if fe_end.is_finite() {
        let _ = write!(
            s,
            r##"<rect x="0" y="0" width="{:.1}" height="{HEIGHT}" fill="#eef2f7"><title>FE stage</title></rect>"##,
            u(fe_end)
        );
    }
    let step = tick_step(span);
    let mut k = (t0 / step).ceil() as i64;
    while (k as f64) * step <= t1 + 1e-9 {
        let t = k as f64 * step;
        let _ = write!(
            s,
            r##"<line x1="{x:.1}" x2="{x:.1}" y1="{HEIGHT}" y2="{:.1}" stroke="#999" vector-effect="non-scaling-stroke"/>"##,
            HEIGHT - 6.0,
            x = u(t)
        );
        k += 1;
    }
    let _ = write!(
        s,
        r##"<line x1="0" x2="{WIDTH}" y1="{mid}" y2="{mid}" stroke="#bbb" vector-effect="non-scaling-stroke"/>"##
    );
    for (c, colour) in COMPONENT_COLOURS.iter().enumerate() {
        let points: Vec<String> = run
            .history
            .iter()
            .map(|h| format!("{:.2},{:.2}", u(h.t_s), v(h.ground_m[c])))
            .collect();
        let _ = write!(
            s,
            r#"<polyline fill="none" stroke="{colour}" stroke-width="1.5" vector-effect="non-scaling-stroke" points="{}"><title>ground {}</title></polyline>"#,
            points.join(" "),
            ["x", "y", "z"][c]
        );
    }
    if let Some(tc) = run.summary.tc_s {
        let _ = write!(
            s,
            r##"<line id="strip-tc" x1="{x:.2}" x2="{x:.2}" y1="0" y2="{HEIGHT}" stroke="#000" stroke-width="2" stroke-dasharray="4 3" vector-effect="non-scaling-stroke"><title>{}</title></line>"##,
            escape(&format!("Tc = {tc} s")),
            x = u(tc)
        );
    }
    let _ = write!(
        s,
        r##"<line id="strip-cursor" x1="0" x2="0" y1="0" y2="{HEIGHT}" stroke="#d00" stroke-width="2" vector-effect="non-scaling-stroke"/></svg>"##
    );
    s
}

/// The strip's legend (text under the strip): components, scale, ticks, Tc.
pub fn legend(run: &RunFolder) -> String {
    let d_max = run
        .history
        .iter()
        .flat_map(|h| h.ground_m)
        .fold(0.0f64, |m, d| m.max(d.abs()));
    let t0 = run.frames.first().map_or(0.0, |f| f.0);
    let t1 = run.frames.last().map_or(0.0, |f| f.0);
    let comps: Vec<String> = ["x", "y", "z"]
        .iter()
        .zip(COMPONENT_COLOURS)
        .map(|(n, c)| format!(r#"<span style="color:{c}">■ ground {n}</span>"#))
        .collect();
    let tc = match run.summary.tc_s {
        Some(tc) => format!(", dashed line: Tc = {tc} s"),
        None => String::new(),
    };
    format!(
        "{} — displacement, the strip spans ±{d_max:.3} m; ticks every {} s from {t0} s to {t1} s; shaded: FE stage{tc}",
        comps.join(" "),
        tick_step(if t1 > t0 { t1 - t0 } else { 1.0 })
    )
}

#[cfg(test)]
mod tests {
    use super::tick_step;

    #[test]
    fn ticks_are_1_2_5_steps_with_at_most_twelve_ticks() {
        assert_eq!(tick_step(12.0), 1.0);
        assert_eq!(tick_step(13.0), 2.0);
        assert_eq!(tick_step(3.0), 0.5);
        assert_eq!(tick_step(100.0), 10.0);
    }
}

//! Colours, text sizes and the legend panel shared by the figures.
//!
//! Element types have fixed fill colours ([`type_colour`]); a body's fill is its type
//! colour scaled towards black by its story ([`story_shade`]: the top story keeps the
//! type colour, the lowest is scaled by [`LOWEST_STORY_SHADE`]), so lower stories read
//! darker in the ruin figures.
use super::font::FAMILY;
use super::Result;
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;

/// Background of every figure.
pub const BACKGROUND: RGBColor = RGBColor(255, 255, 255);
/// Outline of the passive foundation blocks.
pub(crate) const FOUNDATION_OUTLINE: RGBColor = RGBColor(110, 110, 110);
/// The original-footprint outline (dashed).
pub(crate) const FOOTPRINT: RGBColor = RGBColor(0, 0, 0);
/// The ground line of the elevations.
pub const GROUND: RGBColor = RGBColor(120, 85, 40);
/// FE-stage curves.
pub const FE_STAGE: RGBColor = RGBColor(0, 90, 181);
/// Ruin-stage (Bullet) curves.
pub const PHYSICS_STAGE: RGBColor = RGBColor(220, 50, 32);
/// The Tc marker.
pub(crate) const TC_MARKER: RGBColor = RGBColor(60, 60, 60);
/// Intact connections.
pub const INTACT: RGBColor = RGBColor(0, 140, 90);
/// Plastic connections.
pub const PLASTIC: RGBColor = RGBColor(230, 140, 0);
/// Broken connections.
pub const BROKEN: RGBColor = RGBColor(200, 30, 30);
/// Light grid lines.
pub const GRID_LIGHT: RGBColor = RGBColor(238, 238, 238);
/// Major grid lines.
pub const GRID_BOLD: RGBColor = RGBColor(210, 210, 210);
/// Neutral swatch colour of the story legend.
pub(crate) const STORY_SWATCH: RGBColor = RGBColor(170, 170, 170);
/// Shade factor of the lowest story (the top story has 1).
pub(crate) const LOWEST_STORY_SHADE: f64 = 0.5;

/// Title text size, px.
pub(crate) const TITLE_PX: u32 = 20;
/// Axis label and legend text size, px.
pub(crate) const LABEL_PX: u32 = 16;
/// Tick label text size, px.
pub(crate) const TICK_PX: u32 = 14;

/// The known element types in legend order (one table with the glTF colours,
/// [`crate::output::palette`]).
pub use crate::output::palette::KNOWN_TYPES;

/// Fill colour of an element type ([`crate::output::palette::type_srgb`]).
pub fn type_colour(type_name: &str) -> RGBColor {
    let [r, g, b] = crate::output::palette::type_srgb(type_name);
    RGBColor(r, g, b)
}

/// Shade factor of story `story` (1-based) of `n`: 1 for the top story, linearly down to
/// [`LOWEST_STORY_SHADE`] for story 1.
pub(crate) fn story_shade(story: usize, n: usize) -> f64 {
    if n <= 1 {
        return 1.0;
    }
    let s = story.clamp(1, n);
    1.0 - (1.0 - LOWEST_STORY_SHADE) * (n - s) as f64 / (n - 1) as f64
}

/// `c` scaled by `f` (towards black), rounded per channel.
pub fn scaled(c: RGBColor, f: f64) -> RGBColor {
    let s = |v: u8| (f64::from(v) * f).round().clamp(0.0, 255.0) as u8;
    RGBColor(s(c.0), s(c.1), s(c.2))
}

/// Fill of a body of `type_name` in story `story` of `n`.
pub fn body_fill(type_name: &str, story: usize, n: usize) -> RGBColor {
    scaled(type_colour(type_name), story_shade(story, n))
}

/// Outline of a body filled with `fill`.
pub(crate) fn body_outline(fill: RGBColor) -> RGBColor {
    scaled(fill, 0.55)
}

/// The types present in `names`, known types first in [`KNOWN_TYPES`] order, then the
/// others sorted.
pub(crate) fn legend_types<'a>(names: impl IntoIterator<Item = &'a str>) -> Vec<String> {
    let mut set: std::collections::BTreeSet<&str> = names.into_iter().collect();
    let mut out: Vec<String> = Vec::new();
    for k in KNOWN_TYPES {
        if set.remove(k) {
            out.push(k.to_string());
        }
    }
    out.extend(set.into_iter().map(str::to_string));
    out
}

/// A tick-label formatter with as many decimals as a span of `span` m needs (steps of
/// about a tenth of it): 0 from 20 m, 1 from 2 m, 2 from 0.2 m, else 3.
pub(crate) fn tick_format(span: f64) -> impl Fn(&f64) -> String {
    let d = if span >= 20.0 {
        0
    } else if span >= 2.0 {
        1
    } else if span >= 0.2 {
        2
    } else {
        3
    };
    move |v: &f64| format!("{:.*}", d, v + 0.0)
}

/// A legend symbol.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Swatch {
    /// A heading line (no symbol).
    Heading,
    /// A filled square.
    Fill(RGBColor),
    /// An outlined square.
    Outline(RGBColor),
    /// A dashed line.
    Dashed(RGBColor),
    /// A solid line.
    Line(RGBColor),
    /// A filled triangle (a marker).
    Triangle(RGBColor),
}

/// Draws the legend `entries` top-down in `area` (one 22 px row each).
pub(crate) fn draw_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    entries: &[(Swatch, String)],
) -> Result<()>
where
    DB::ErrorType: 'static,
{
    let text = (FAMILY, LABEL_PX).into_font().color(&BLACK);
    let heading = (FAMILY, LABEL_PX, FontStyle::Normal)
        .into_font()
        .color(&RGBColor(40, 40, 40));
    let (x0, mut y) = (8, 40);
    for (swatch, label) in entries {
        let sym = [(x0, y), (x0 + 18, y + 14)];
        let mid = y + 7;
        match *swatch {
            Swatch::Heading => {
                if y > 40 {
                    y += 8;
                }
                area.draw(&Text::new(label.clone(), (x0, y), heading.clone()))?;
                y += 24;
                continue;
            }
            Swatch::Fill(c) => {
                area.draw(&Rectangle::new(sym, c.filled()))?;
                area.draw(&Rectangle::new(sym, body_outline(c).stroke_width(1)))?;
            }
            Swatch::Outline(c) => area.draw(&Rectangle::new(sym, c.stroke_width(2)))?,
            Swatch::Dashed(c) => area.draw(&DashedPathElement::new(
                vec![(x0, mid), (x0 + 18, mid)],
                4,
                3,
                c.stroke_width(2),
            ))?,
            Swatch::Line(c) => area.draw(&PathElement::new(
                vec![(x0, mid), (x0 + 18, mid)],
                c.stroke_width(2),
            ))?,
            Swatch::Triangle(c) => area.draw(&TriangleMarker::new((x0 + 9, mid), 6, c.filled()))?,
        }
        area.draw(&Text::new(label.clone(), (x0 + 26, y), text.clone()))?;
        y += 22;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shades() {
        assert_eq!(story_shade(3, 3), 1.0);
        assert_eq!(story_shade(1, 3), LOWEST_STORY_SHADE);
        assert!((story_shade(2, 3) - 0.75).abs() < 1e-12);
        assert_eq!(story_shade(1, 1), 1.0);
        assert_eq!(body_fill("Column", 1, 3), RGBColor(96, 29, 22));
        assert_eq!(body_fill("Beam", 2, 2), type_colour("Beam"));
    }

    #[test]
    fn legend_order() {
        let t = legend_types(["Slab", "Zeta", "Column", "Alpha", "Slab"]);
        assert_eq!(t, vec!["Column", "Slab", "Alpha", "Zeta"]);
        assert_eq!(type_colour("Zeta"), type_colour("Zeta"));
    }

    #[test]
    fn tick_decimals() {
        assert_eq!(tick_format(943.0)(&-400.0), "-400");
        assert_eq!(tick_format(7.7)(&1.5), "1.5");
        assert_eq!(tick_format(0.5)(&0.25), "0.25");
        assert_eq!(tick_format(0.05)(&-0.0), "0.000");
    }
}

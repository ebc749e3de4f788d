//! Physical plausibility of a building model: the ranges that a reinforced-concrete
//! building in SI units (m, kg, s, N, Pa) keeps. A value outside its range is almost
//! always a unit slip — millimetres typed as metres, GPa or MPa typed as Pa, a damping
//! ratio in percent — or an impossible building, and the model still runs: a 3 000 m
//! column, concrete of 30 Pa or 500 % damping give numbers, not an error. So the command
//! line refuses such a model before any work ([`unusual`] lists every finding with its
//! range and, where the value looks like one, the slip), unless the user says that the
//! value is meant (`--allow-unusual`, recorded in the run's summary).
//!
//! The ranges (one table, [`RANGES`]; `docs/reliability.md` lists them) are set well
//! outside what real buildings and laboratory models have:
//! * lengths: node coordinates within 2 km of the origin, line elements 5 mm to 200 m
//!   (the tallest stories are under 10 m; bridges' spans are not buildings), section
//!   sizes up to 10 m, shell thicknesses up to 5 m;
//! * moduli 0.1 GPa to 1 000 GPa (concrete 20–50 GPa, steel 200 GPa: Eurocode 2 Table 3.1,
//!   Eurocode 3 §3.2.6); concrete strengths 1–200 MPa (ultra-high-performance concrete
//!   reaches about 200 MPa); steel yield 0.1–3 GPa (prestressing strand about 1.9 GPa);
//! * densities up to 20 000 kg/m³ (steel 7 850, lead 11 340; tungsten 19 300);
//! * gravity 0–30 m/s² (Earth 9.81; 0 for tests without self-weight);
//! * model scale 1/100 to 10 (shaking-table models are 1/4 to 1/50);
//! * damping ratio 0–0.3 (RC buildings 0.02–0.07), anchor periods up to 20 s (the
//!   tallest buildings' first periods are under 10 s);
//! * a lumped nodal mass up to 10⁸ kg (a 100 m × 100 m floor of 1 t/m² is 10⁷ kg);
//! * the roles of members in the geometry ([`geometry`]): a beam no deeper than its
//!   story, a slab no thicker than its story, a column section no larger than the
//!   distance to the next column, a wall at most 4 times as thick as the columns that
//!   bound it (real walls are at most about as thick as their boundary columns).
use super::{ElementKind, MaterialLaw, Model, SectionKind, ShellLayer};
use std::collections::BTreeMap;

/// The kind of unit slip a quantity invites, which decides the hint.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Slip {
    /// None worth suggesting.
    None,
    /// A length: millimetres typed as metres (value / 1000).
    Millimetres,
    /// A modulus or strength in Pa: GPa or MPa typed as Pa.
    Pascals,
    /// A ratio typed in percent (value / 100).
    Percent,
    /// A density or an acceleration a thousand times too large (g/m³, mm/s²).
    Thousand,
}

/// A plausible range of one quantity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Range {
    /// What it is, e.g. "Young's modulus".
    pub what: &'static str,
    /// SI unit as written in messages.
    pub unit: &'static str,
    /// Least plausible value (inclusive).
    pub lo: f64,
    /// Largest plausible value (inclusive).
    pub hi: f64,
    /// The slip to suggest.
    pub slip: Slip,
}

const fn range(what: &'static str, unit: &'static str, lo: f64, hi: f64, slip: Slip) -> Range {
    Range {
        what,
        unit,
        lo,
        hi,
        slip,
    }
}

/// Model scale (prototype = 1).
pub const SCALE: Range = range("model scale", "", 0.01, 10.0, Slip::None);
/// Acceleration of gravity.
pub const GRAVITY: Range = range("gravity", "m/s²", 0.0, 30.0, Slip::Thousand);
/// Rayleigh damping ratio ξ.
pub const DAMPING_RATIO: Range = range("damping ratio", "", 0.0, 0.3, Slip::Percent);
/// Rayleigh damping anchor period.
pub const DAMPING_PERIOD: Range = range("damping anchor period", "s", 1e-3, 20.0, Slip::None);
/// A node coordinate.
pub const COORDINATE: Range = range("coordinate", "m", -2000.0, 2000.0, Slip::Millimetres);
/// The length of a line element.
pub const ELEMENT_LENGTH: Range = range("element length", "m", 0.005, 200.0, Slip::Millimetres);
/// A section's width or depth.
pub const SECTION_SIZE: Range = range("section size", "m", 0.005, 10.0, Slip::Millimetres);
/// A shell section's or layer's thickness.
pub const SHELL_THICKNESS: Range = range("thickness", "m", 1e-5, 5.0, Slip::Millimetres);
/// Young's (or the shear) modulus.
pub const MODULUS: Range = range("modulus", "Pa", 1e8, 1e12, Slip::Pascals);
/// Concrete compressive strength (magnitude).
pub const CONCRETE_STRENGTH: Range = range("concrete strength", "Pa", 1e6, 2e8, Slip::Pascals);
/// Steel yield strength.
pub const STEEL_YIELD: Range = range("steel yield strength", "Pa", 1e8, 3e9, Slip::Pascals);
/// Mass density.
pub const DENSITY: Range = range("density", "kg/m³", 0.0, 20_000.0, Slip::Thousand);
/// A lumped nodal mass.
pub const NODAL_MASS: Range = range("nodal mass", "kg", 0.0, 1e8, Slip::None);

/// A beam's depth over its story's height.
pub const BEAM_DEPTH_PER_STORY: Range =
    range("beam depth / story height", "", 0.0, 1.0, Slip::None);
/// A slab's thickness over its story's height.
pub const SLAB_PER_STORY: Range = range("slab thickness / story height", "", 0.0, 1.0, Slip::None);
/// A column's larger section size over the distance to the nearest other column.
pub const COLUMN_PER_BAY: Range = range("column size / bay", "", 0.0, 1.0, Slip::None);
/// A wall's thickness over the largest section size of the columns it touches.
pub const WALL_PER_COLUMN: Range = range("wall thickness / column size", "", 0.0, 4.0, Slip::None);

/// Every range, for the documentation's table.
pub const RANGES: [Range; 17] = [
    SCALE,
    GRAVITY,
    DAMPING_RATIO,
    DAMPING_PERIOD,
    COORDINATE,
    ELEMENT_LENGTH,
    SECTION_SIZE,
    SHELL_THICKNESS,
    MODULUS,
    CONCRETE_STRENGTH,
    STEEL_YIELD,
    DENSITY,
    NODAL_MASS,
    BEAM_DEPTH_PER_STORY,
    SLAB_PER_STORY,
    COLUMN_PER_BAY,
    WALL_PER_COLUMN,
];

/// One value outside its range.
#[derive(Debug, Clone, PartialEq)]
pub struct Unusual {
    /// The item and key, e.g. `material 3: fpc`.
    pub item: String,
    /// The value as given (SI).
    pub value: f64,
    /// Its range.
    pub range: Range,
}

/// `v` in engineering notation with the unit, e.g. `3e+10 Pa`, `0.05`.
fn show(v: f64, unit: &str) -> String {
    let n = if v != 0.0 && (v.abs() >= 1e5 || v.abs() < 1e-3) {
        format!("{v:e}")
    } else {
        format!("{v}")
    };
    if unit.is_empty() {
        n
    } else {
        format!("{n} {unit}")
    }
}

/// The value with fewer decimals than an `f64` prints (`0.1 * 3` → `0.3`).
fn tidy(v: f64) -> f64 {
    format!("{v:.9e}").parse().unwrap_or(v)
}

impl Unusual {
    /// What the value looks like a slip of, if anything: "did you mean 30 GPa?".
    pub fn hint(&self) -> Option<String> {
        let (v, r) = (self.value, &self.range);
        let within = |x: f64| x >= r.lo && x <= r.hi;
        match r.slip {
            Slip::None => None,
            Slip::Millimetres => within(tidy(v / 1000.0)).then(|| {
                format!(
                    "did you mean {} m? (the value looks like millimetres)",
                    tidy(v / 1000.0)
                )
            }),
            Slip::Percent => (v > 1.0 && within(tidy(v / 100.0))).then(|| {
                format!(
                    "did you mean {}? (the value looks like percent)",
                    tidy(v / 100.0)
                )
            }),
            Slip::Thousand => within(tidy(v / 1000.0)).then(|| {
                format!(
                    "did you mean {} {}? (the value is a thousand times too large)",
                    tidy(v / 1000.0),
                    r.unit
                )
            }),
            Slip::Pascals => {
                let a = v.abs();
                if within(tidy(a * 1e9)) && a < 1e4 {
                    Some(format!("did you mean {v} GPa ({} Pa)?", tidy(v * 1e9)))
                } else if within(tidy(a * 1e6)) && a < 1e7 {
                    Some(format!("did you mean {v} MPa ({} Pa)?", tidy(v * 1e6)))
                } else {
                    None
                }
            }
        }
    }
}

impl std::fmt::Display for Unusual {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let r = &self.range;
        write!(
            f,
            "{} = {} is outside the plausible {} range [{}, {}]",
            self.item,
            show(self.value, r.unit),
            r.what,
            show(r.lo, r.unit),
            show(r.hi, r.unit)
        )?;
        if let Some(h) = self.hint() {
            write!(f, ": {h}")?;
        }
        Ok(())
    }
}

/// Collects the findings of one model.
struct Findings(Vec<Unusual>);

impl Findings {
    fn check(&mut self, item: impl FnOnce() -> String, value: f64, range: Range) {
        if value.is_finite() && !(value >= range.lo && value <= range.hi) {
            self.0.push(Unusual {
                item: item(),
                value,
                range,
            });
        }
    }
}

/// Every value of `m` outside its plausible range (module docs), in file order: top-level
/// keys, nodes, materials, sections, elements, masses. Empty for a plausible model.
pub fn unusual(m: &Model) -> Vec<Unusual> {
    let mut f = Findings(Vec::new());
    f.check(|| "scale".into(), m.scale, SCALE);
    f.check(|| "gravity.g".into(), m.gravity.g, GRAVITY);
    if let Some(d) = &m.damping {
        if let Some(xi) = d.xi {
            f.check(|| "damping.xi".into(), xi, DAMPING_RATIO);
        }
        for (k, p) in d.periods.into_iter().flatten().enumerate() {
            f.check(|| format!("damping.periods[{k}]"), p, DAMPING_PERIOD);
        }
    }
    for n in &m.nodes {
        for (axis, v) in ["x", "y", "z"].iter().zip(n.xyz()) {
            f.check(|| format!("node {}: {axis}", n.tag), v, COORDINATE);
        }
    }
    for mt in &m.materials {
        let it = |k: &str| format!("material {}: {k}", mt.tag);
        f.check(|| it("density"), mt.density, DENSITY);
        match &mt.law {
            MaterialLaw::Elastic { e, .. } => f.check(|| it("E"), *e, MODULUS),
            MaterialLaw::Concrete01 { fpc, .. } | MaterialLaw::Concrete02 { fpc, .. } => {
                f.check(|| it("|fpc|"), fpc.abs(), CONCRETE_STRENGTH)
            }
            MaterialLaw::Steel01 { fy, e0, .. } | MaterialLaw::Steel02 { fy, e0, .. } => {
                f.check(|| it("Fy"), *fy, STEEL_YIELD);
                f.check(|| it("E0"), *e0, MODULUS);
            }
        }
    }
    for s in &m.sections {
        let it = |k: &str| format!("section {}: {k}", s.tag);
        match &s.kind {
            SectionKind::RcRect(r) => {
                f.check(|| it("b"), r.b, SECTION_SIZE);
                f.check(|| it("h"), r.h, SECTION_SIZE);
            }
            SectionKind::Elastic { e, g, .. } => {
                f.check(|| it("E"), *e, MODULUS);
                f.check(|| it("G"), *g, MODULUS);
            }
            SectionKind::Plate { e, h, density, .. } => {
                f.check(|| it("E"), *e, MODULUS);
                f.check(|| it("h"), *h, SHELL_THICKNESS);
                f.check(|| it("density"), *density, DENSITY);
            }
            SectionKind::LayeredShell { layers, .. } => {
                for (k, l) in layers.iter().enumerate() {
                    let il = |key: &str| format!("section {}: layer {k}: {key}", s.tag);
                    f.check(|| il("thickness"), l.thickness(), SHELL_THICKNESS);
                    match l {
                        ShellLayer::Elastic { e, .. } => f.check(|| il("E"), *e, MODULUS),
                        ShellLayer::Concrete { e, fc, .. } => {
                            f.check(|| il("E"), *e, MODULUS);
                            f.check(|| il("fc"), *fc, CONCRETE_STRENGTH);
                        }
                        ShellLayer::Rebar { .. } => {}
                    }
                }
            }
            SectionKind::Fiber { .. } => {}
        }
    }
    let nodes = m.node_map();
    for e in &m.elements {
        if let [i, j] = e.nodes() {
            if let (Some(a), Some(b)) = (nodes.get(i), nodes.get(j)) {
                let d = [b.x - a.x, b.y - a.y, b.z - a.z];
                let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                f.check(|| format!("element {}: length", e.tag), l, ELEMENT_LENGTH);
            }
        }
        if let ElementKind::ElasticStrip {
            e: modulus,
            g,
            width,
            thickness,
            density,
            ..
        } = &e.kind
        {
            let it = |k: &str| format!("element {}: {k}", e.tag);
            f.check(|| it("E"), *modulus, MODULUS);
            f.check(|| it("G"), *g, MODULUS);
            f.check(|| it("width"), *width, SECTION_SIZE);
            f.check(|| it("thickness"), *thickness, SHELL_THICKNESS);
            f.check(|| it("density"), *density, DENSITY);
        }
    }
    for ms in &m.masses {
        f.check(|| format!("mass on node {}: m", ms.node), ms.m, NODAL_MASS);
    }
    geometry(m, &mut f);
    f.0
}

/// The distance from each column line (x, y) to the nearest other one (farther than
/// [`LEVEL_TOL`]), keyed by the bits of x and y; lines without a neighbour are left out.
/// A sweep in x that stops once the x distance alone exceeds the best found, so a
/// regular grid of n lines costs about n √n.
fn bays(mut lines: Vec<[f64; 2]>) -> BTreeMap<(u64, u64), f64> {
    lines.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    lines.dedup();
    let mut out = BTreeMap::new();
    for (i, a) in lines.iter().enumerate() {
        let mut best = f64::INFINITY;
        let mut look = |b: &[f64; 2]| {
            if (b[0] - a[0]).abs() >= best {
                return false;
            }
            let d = (b[0] - a[0]).hypot(b[1] - a[1]);
            if d > LEVEL_TOL {
                best = best.min(d);
            }
            true
        };
        for b in lines[i + 1..].iter() {
            if !look(b) {
                break;
            }
        }
        for b in lines[..i].iter().rev() {
            if !look(b) {
                break;
            }
        }
        if best.is_finite() {
            out.insert((a[0].to_bits(), a[1].to_bits()), best);
        }
    }
    out
}

/// Two heights closer than this \[m\] are one level.
const LEVEL_TOL: f64 = 1e-6;

/// The roles of members in the geometry. An element whose nodes share one height
/// (to [`LEVEL_TOL`]) is horizontal (a beam, a slab strip, a slab shell or panel); a line
/// element whose ends share x and y is a column; a shell spanning heights is a wall. The
/// levels are the heights of horizontal elements' nodes and the lowest node; a story's
/// height is the distance from a level down to the next level. Only sizes the model
/// states are compared: the `b` and `h` of `rc_rect` sections and the thicknesses of
/// shells, strips and panels.
fn geometry(m: &Model, f: &mut Findings) {
    let nodes = m.node_map();
    let sections = m.section_map();
    let xyz = |t: &u32| nodes.get(t).map(|n| n.xyz());
    // Element points; elements with a missing node are left to validation.
    let pts = |e: &super::Element| -> Option<Vec<[f64; 3]>> { e.nodes().iter().map(xyz).collect() };
    let flat = |p: &[[f64; 3]]| p.iter().all(|q| (q[2] - p[0][2]).abs() <= LEVEL_TOL);
    let rc_size = |e: &super::Element| -> Option<(f64, f64)> {
        match &sections.get(&e.section()?)?.kind {
            SectionKind::RcRect(r) => Some((r.b, r.h)),
            _ => None,
        }
    };
    let thickness = |e: &super::Element| -> Option<f64> {
        match &e.kind {
            ElementKind::Shell { section, .. } => sections.get(section)?.shell_thickness(),
            ElementKind::Panel { thickness, .. } | ElementKind::ElasticStrip { thickness, .. } => {
                Some(*thickness)
            }
            _ => None,
        }
    };
    let mut levels = vec![m.nodes.iter().map(|n| n.z).fold(f64::INFINITY, f64::min)];
    let mut columns: Vec<(u32, [f64; 2], f64)> = Vec::new(); // (tag, x y, larger size)
    for e in &m.elements {
        let Some(p) = pts(e) else { continue };
        if p.len() >= 2 && flat(&p) {
            levels.push(p[0][2]);
        }
        if let ([a, b], Some((sb, sh))) = (p.as_slice(), rc_size(e)) {
            let dz = (b[2] - a[2]).abs();
            if dz > LEVEL_TOL && (b[0] - a[0]).hypot(b[1] - a[1]) <= LEVEL_TOL {
                columns.push((e.tag, [a[0], a[1]], sb.max(sh)));
            }
        }
    }
    levels.retain(|z| z.is_finite());
    levels.sort_by(f64::total_cmp);
    levels.dedup_by(|a, b| (*a - *b).abs() <= LEVEL_TOL);
    let story_below = |z: f64| -> Option<f64> {
        let below = levels.iter().rev().find(|&&l| l < z - LEVEL_TOL)?;
        Some(z - below)
    };
    let column_size: BTreeMap<u32, f64> = columns.iter().map(|c| (c.0, c.2)).collect();
    let bays = bays(columns.iter().map(|c| c.1).collect());
    // Columns by node, for the walls.
    let mut column_at_node: BTreeMap<u32, f64> = BTreeMap::new();
    for e in &m.elements {
        if let Some(&size) = column_size.get(&e.tag) {
            for n in e.nodes() {
                let s = column_at_node.entry(*n).or_insert(0.0);
                *s = s.max(size);
            }
        }
    }
    for e in &m.elements {
        let Some(p) = pts(e) else { continue };
        let tag = e.tag;
        if p.len() == 2 && flat(&p) {
            if let (Some((_, h)), Some(story)) = (rc_size(e), story_below(p[0][2])) {
                f.check(
                    || {
                        format!(
                            "element {tag}: beam depth h {h} m / story height {} m",
                            tidy(story)
                        )
                    },
                    h / story,
                    BEAM_DEPTH_PER_STORY,
                );
            }
        }
        if let Some(t) = thickness(e) {
            if flat(&p) {
                if let Some(story) = story_below(p[0][2]) {
                    f.check(
                        || {
                            format!(
                                "element {tag}: slab thickness {t} m / story height {} m",
                                tidy(story)
                            )
                        },
                        t / story,
                        SLAB_PER_STORY,
                    );
                }
            } else if matches!(
                e.kind,
                ElementKind::Shell { .. } | ElementKind::Panel { .. }
            ) {
                let size = e
                    .nodes()
                    .iter()
                    .filter_map(|n| column_at_node.get(n))
                    .fold(0.0f64, |a, &b| a.max(b));
                if size > 0.0 {
                    f.check(
                        || format!("element {tag}: wall thickness {t} m / column size {size} m"),
                        t / size,
                        WALL_PER_COLUMN,
                    );
                }
            }
        }
        if let Some(size) = column_size.get(&tag) {
            let key = (p[0][0].to_bits(), p[0][1].to_bits());
            if let Some(&bay) = bays.get(&key) {
                f.check(
                    || format!("element {tag}: column size {size} m / bay {} m", tidy(bay)),
                    size / bay,
                    COLUMN_PER_BAY,
                );
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn one(value: f64, range: Range) -> Unusual {
        Unusual {
            item: "x".into(),
            value,
            range,
        }
    }

    #[test]
    fn unit_slips_are_named() {
        let cases = [
            (30.0, MODULUS, "did you mean 30 GPa (30000000000 Pa)?"),
            (200.0, MODULUS, "did you mean 200 GPa"),
            (
                30_000.0,
                MODULUS,
                "did you mean 30000 MPa (30000000000 Pa)?",
            ),
            (
                22.5,
                CONCRETE_STRENGTH,
                "did you mean 22.5 MPa (22500000 Pa)?",
            ),
            (457.7, STEEL_YIELD, "did you mean 457.7 MPa (457700000 Pa)?"),
            (
                3000.0,
                ELEMENT_LENGTH,
                "did you mean 3 m? (the value looks like millimetres)",
            ),
            (
                5.0,
                DAMPING_RATIO,
                "did you mean 0.05? (the value looks like percent)",
            ),
            (9810.0, GRAVITY, "did you mean 9.81 m/s²?"),
            (2.5e6, DENSITY, "did you mean 2500 kg/m³?"),
        ];
        for (v, r, want) in cases {
            let u = one(v, r);
            assert!(u.to_string().contains(want), "{u}");
        }
        // No hint where no slip fits: 500 s is not a period in any unit of time we take.
        let u = one(500.0, DAMPING_PERIOD);
        assert_eq!(
            u.to_string(),
            "x = 500 s is outside the plausible damping anchor period range [0.001 s, 20 s]"
        );
        assert_eq!(one(1e-9, SCALE).hint(), None);
        // A ratio under 1 is not read as percent.
        assert_eq!(one(0.35, DAMPING_RATIO).hint(), None);
        assert_eq!(one(1e30, NODAL_MASS).hint(), None);
    }

    #[test]
    fn the_ranges_hold_their_bounds() {
        for r in RANGES {
            assert!(r.lo < r.hi, "{}", r.what);
            for v in [r.lo, r.hi, 0.5 * (r.lo + r.hi)] {
                let mut f = Findings(Vec::new());
                f.check(|| "x".into(), v, r);
                assert!(f.0.is_empty(), "{} {v}", r.what);
            }
            let mut f = Findings(Vec::new());
            f.check(|| "x".into(), r.hi * 1.01 + 1e-12, r);
            f.check(|| "x".into(), r.lo - 1e-12 - r.lo.abs() * 0.01, r);
            assert_eq!(f.0.len(), 2, "{}", r.what);
        }
    }
}

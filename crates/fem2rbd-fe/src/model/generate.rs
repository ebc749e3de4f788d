//! Generator of regular RC frames (`fem2rbd generate frame`).
//!
//! The layout and numbering follow the reference `gen_frame3.py`
//! (tests/fixtures/opensees-frame3, data/frame3-standin/reference-frame3.json), so that the defaults ([`FrameParams::default`])
//! reproduce `frame3.json`: the same nodes and tags, elements, fibers, materials,
//! masses, gravity loads and damping.
//!
//! Plan grid: grid lines at every column line and at every mid-span, indices
//! i = 0..=2·nx (X) and j = 0..=2·ny (Y); columns stand at even (i, j); beams run along
//! the column lines with a node at mid-span; each bay panel has a centre node at odd
//! (i, j). The slab of each panel is its mass (slab ρ·t·Lx·Ly plus its share of the
//! added mass, split corners 1/24, edge mid-nodes 1/12, centre 1/2 — total mass and polar
//! inertia m(Lx²+Ly²)/12 of a uniform panel) plus 4 elastic diagonal strips corner →
//! centre whose X-brace gives the panel's racking stiffness G·t:
//! A = G·t·d³ / (2·E·Lx·Ly), d = √(Lx²+Ly²) (= G·t·L·√2/E for a square).
use super::*;

/// Parameters of a regular RC frame. SI units. Defaults = the reference frame3.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameParams {
    /// Model name.
    pub name: String,
    /// Bay spans in X (m).
    pub spans_x: Vec<f64>,
    /// Bay spans in Y (m).
    pub spans_y: Vec<f64>,
    /// Story heights, bottom up (m).
    pub story_heights: Vec<f64>,
    /// Column width along X and along Y (m) (section b × h).
    pub column: [f64; 2],
    /// Beam width and depth (m).
    pub beam: [f64; 2],
    /// Slab thickness (m).
    pub slab_thickness: f64,
    /// Face → core boundary (stirrup centre line) (m).
    pub cover: f64,
    /// Face → longitudinal bar centre (m).
    pub bar_offset: f64,
    /// Column longitudinal bar diameter (m).
    pub column_bar_diameter: f64,
    /// Beam longitudinal bar diameter (m).
    pub beam_bar_diameter: f64,
    /// Column bars per face (corners counted on both faces); ≥ 2.
    pub column_bars_per_face: u32,
    /// Beam bars in the top and in the bottom layer, [top, bottom]; each ≥ 2.
    pub beam_bars: [u32; 2],
    /// Concrete Young's modulus per story/floor (Pa).
    pub ec: Vec<f64>,
    /// Concrete compressive strength per story/floor (Pa, positive).
    pub fc: Vec<f64>,
    /// Core confinement factor K (f'cc = K f'c).
    pub confinement: f64,
    /// Strain at which the cover concrete reaches its residual stress (negative).
    pub cover_epscu: f64,
    /// Strain at which the core concrete reaches its residual stress (negative).
    pub core_epscu: f64,
    /// Residual stress of both concretes as a fraction of their peak, fpcu = r·fpc (0..1).
    pub residual: f64,
    /// Concrete Poisson's ratio (G = E / (2(1+ν))).
    pub nu: f64,
    /// Bar yield strength (Pa).
    pub fy: f64,
    /// Bar Young's modulus (Pa).
    pub es: f64,
    /// Concrete density (kg/m³).
    pub concrete_density: f64,
    /// Bar density (kg/m³); frame3 leaves bar mass out (0).
    pub steel_density: f64,
    /// Added mass per floor (kg), one value for all floors or one per floor.
    pub added_mass: Vec<f64>,
    /// Share of each bay's added mass put on the bay-centre node (0..1); the rest is
    /// spread like the slab (corners 1/24, edge mid-nodes 1/12, centre 1/2). 0 gives a
    /// uniformly spread ballast; larger values lower the polar inertia (torsion period).
    pub ballast_centre: f64,
    /// Elements per column per story.
    pub column_elements: u32,
    /// Elements per half beam span.
    pub beam_elements: u32,
    /// Column core fibers [ny, nz].
    pub column_fibers: [u32; 2],
    /// Beam core fibers [ny, nz].
    pub beam_fibers: [u32; 2],
    /// Geometric transformation of every member.
    pub transformation: TransfKind,
    /// Beam-column formulation.
    pub formulation: Formulation,
    /// Integration points per beam-column.
    pub points: u32,
    /// Model scale (e.g. 0.25).
    pub scale: f64,
    /// Gravity (m/s²).
    pub g: f64,
    /// Rayleigh damping ratio.
    pub xi: f64,
    /// First anchor period (s); the second is T1/3.
    pub t1: f64,
}

impl Default for FrameParams {
    fn default() -> Self {
        FrameParams {
            name: "frame3-quarter-scale-stand-in".into(),
            spans_x: vec![1.5],
            spans_y: vec![1.5],
            story_heights: vec![1.0, 1.0, 1.0],
            column: [0.100, 0.100],
            beam: [0.075, 0.150],
            slab_thickness: 0.030,
            cover: 0.012,
            bar_offset: 0.013,
            column_bar_diameter: 0.0035,
            beam_bar_diameter: 0.0035,
            column_bars_per_face: 3,
            beam_bars: [3, 3],
            ec: vec![25.0e9, 27.0e9, 23.0e9],
            fc: vec![22.5e6, 23.9e6, 15.6e6],
            confinement: 1.1,
            cover_epscu: -0.004,
            core_epscu: -0.012,
            residual: 0.2,
            nu: 0.2,
            fy: 457.7e6,
            es: 200.0e9,
            concrete_density: 2500.0,
            steel_density: 0.0,
            added_mass: vec![2699.75],
            ballast_centre: 0.0,
            column_elements: 2,
            beam_elements: 1,
            column_fibers: [8, 8],
            beam_fibers: [4, 10],
            transformation: TransfKind::Corotational,
            formulation: Formulation::Force,
            points: 5,
            scale: 0.25,
            g: 9.81,
            xi: 0.05,
            t1: 0.316,
        }
    }
}

/// Generator parameters that cannot make a frame: out of range, inconsistent, or a frame
/// that fails validation.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FrameError {
    /// Parameters that do not fit together (bars that do not fit, a per-story list of the
    /// wrong length, …); the message names them.
    #[error("{0}")]
    Params(String),
    /// A parameter outside its range ([`PARAM_RANGES`]).
    #[error(transparent)]
    Range(#[from] super::limits::RangeError),
    /// A count over its bound.
    #[error(transparent)]
    Limit(#[from] super::limits::LimitError),
    /// The generated model fails validation.
    #[error(transparent)]
    Model(#[from] super::ModelError),
}

macro_rules! bail {
    ($($t:tt)*) => {
        return Err(FrameError::Params(format!($($t)*)))
    };
}

fn per_floor(v: &[f64], n: usize, what: &str) -> Result<Vec<f64>, FrameError> {
    match v.len() {
        1 => Ok(vec![v[0]; n]),
        k if k == n => Ok(v.to_vec()),
        k => bail!("{what}: give 1 value or one per story ({n}), not {k}"),
    }
}

/// Bars of a perimeter arrangement with `n` bars per face at ±a: sorted by z, then y.
fn perimeter_bars(a: f64, n: u32, area: f64) -> Vec<Bar> {
    let pos: Vec<f64> = (0..n)
        .map(|k| -a + k as f64 * (2.0 * a) / (n - 1) as f64)
        .collect();
    let mut bars = Vec::new();
    for (kz, &z) in pos.iter().enumerate() {
        let edge = kz == 0 || kz + 1 == n as usize;
        for (ky, &y) in pos.iter().enumerate() {
            if edge || ky == 0 || ky + 1 == n as usize {
                bars.push(Bar(y, z, area));
            }
        }
    }
    bars
}

/// Bars must be real, lie inside the section and not overlap: bar diameter > 0, the bar
/// offset (face → bar centre) at least half a diameter, and the clear spacing between
/// neighbouring bar centres along a face (2a/(n − 1) − d, a = half the face minus the
/// offset) positive.
fn check_reinforcement(p: &FrameParams) -> Result<(), FrameError> {
    let faces = [
        (
            "column",
            p.column[0].min(p.column[1]),
            p.column_bar_diameter,
            p.column_bars_per_face,
        ),
        (
            "beam",
            p.beam[0],
            p.beam_bar_diameter,
            p.beam_bars[0].max(p.beam_bars[1]),
        ),
    ];
    for (what, side, d, n) in faces {
        if !(d > 0.0 && d.is_finite()) {
            bail!("{what} bar diameter {d} m must be positive");
        }
        if p.bar_offset < d / 2.0 {
            bail!(
                "{what} bars of {d} m stick out of the section: bar offset {} m < d/2",
                p.bar_offset
            );
        }
        let a = side / 2.0 - p.bar_offset;
        if a <= 0.0 {
            bail!(
                "{what} section {side} m wide leaves no room for its bars: they sit at the \
                 bar offset {} m from each face, so the section must be wider than {} m",
                p.bar_offset,
                2.0 * p.bar_offset
            );
        }
        let clear = 2.0 * a / (n - 1) as f64 - d;
        if clear <= 0.0 {
            bail!(
                "{n} {what} bars of {d} m do not fit on a {side} m face (clear spacing {clear:.4} m)"
            );
        }
    }
    Ok(())
}

/// Concrete law parameters: 0 < K (confinement), 0 ≤ residual ≤ 1, and each crushing
/// strain εcu negative and past the peak strain εc0 = −2f′c/Ec of every story (core:
/// −2K·f′c/Ec).
fn check_concrete(p: &FrameParams, ec: &[f64], fc: &[f64]) -> Result<(), FrameError> {
    if !(p.confinement > 0.0 && p.confinement.is_finite()) {
        bail!("confinement factor {} must be positive", p.confinement);
    }
    if !(0.0..=1.0).contains(&p.residual) {
        bail!("concrete residual share {} must lie in 0..1", p.residual);
    }
    for (s, (&e, &f)) in ec.iter().zip(fc).enumerate() {
        if !(e > 0.0 && f > 0.0) {
            bail!("story {}: ec and fc must be positive", s + 1);
        }
        for (what, eps, k) in [
            ("cover", p.cover_epscu, 1.0),
            ("core", p.core_epscu, p.confinement),
        ] {
            let eps0 = -2.0 * k * f / e;
            if eps.partial_cmp(&eps0) != Some(std::cmp::Ordering::Less) {
                bail!(
                    "story {}: {what} crushing strain {eps} must be negative and beyond the \
                     peak strain {eps0:.5}",
                    s + 1
                );
            }
        }
    }
    Ok(())
}

/// Valid ranges of the generator's parameters (SI units), checked by [`check_params`]
/// before anything is built; the option of `fem2rbd generate frame` has the same name
/// with `-` for `_`. Counts are bounded so that the model stays within the resource
/// bounds of [`super::limits`]; physical values so that they describe reinforced
/// concrete (E of concrete 1 to 100 GPa, f′c 1 to 200 MPa, steel E 100 to 400 GPa,
/// f_y 100 MPa to 3 GPa, damping ratio 0 to 1).
pub(crate) const PARAM_RANGES: &[(&str, f64, bool, f64, &str)] = &[
    // (name, low, low excluded, high, unit)
    ("spans_x", 0.1, false, 100.0, "m"),
    ("spans_y", 0.1, false, 100.0, "m"),
    ("stories", 0.1, false, 100.0, "m"),
    ("column", 0.01, false, 10.0, "m"),
    ("beam", 0.01, false, 10.0, "m"),
    ("slab_thickness", 0.001, false, 2.0, "m"),
    ("cover", 0.0, true, 1.0, "m"),
    ("bar_offset", 0.0, true, 1.0, "m"),
    ("column_bar_diameter", 0.0, true, 0.2, "m"),
    ("beam_bar_diameter", 0.0, true, 0.2, "m"),
    ("ec", 1e9, false, 1e11, "Pa"),
    ("fc", 1e6, false, 2e8, "Pa"),
    ("confinement", 1.0, false, 3.0, ""),
    ("cover_epscu", -1.0, false, 0.0, ""),
    ("core_epscu", -1.0, false, 0.0, ""),
    ("residual", 0.0, false, 1.0, ""),
    ("fy", 1e8, false, 3e9, "Pa"),
    ("es", 1e11, false, 4e11, "Pa"),
    ("concrete_density", 0.0, false, 20000.0, "kg/m³"),
    ("steel_density", 0.0, false, 20000.0, "kg/m³"),
    ("added_mass", 0.0, false, 1e9, "kg"),
    ("ballast_centre", 0.0, false, 1.0, ""),
    ("scale", 0.0, true, 10.0, ""),
    ("g", 0.0, false, 100.0, "m/s²"),
    ("xi", 0.0, false, 1.0, ""),
    ("t1", 0.0, true, 100.0, "s"),
];

/// Largest counts of the generator: bays per direction (the node-tag scheme holds 49),
/// stories, elements per member, bars per face, core fibres per direction.
pub(crate) const MAX_BAYS: usize = 49;
/// Largest number of stories.
pub(crate) const MAX_STORIES: usize = 200;
/// Largest number of elements per column per story and per half beam span.
pub(crate) const MAX_ELEMENTS_PER_MEMBER: u32 = 50;
/// Largest number of bars per column face or beam layer.
pub(crate) const MAX_BARS: u32 = 50;
/// Largest number of core fibres per direction.
pub(crate) const MAX_CORE_FIBERS: u32 = 100;

/// Checks every parameter against its range ([`PARAM_RANGES`], the `MAX_*` counts) and
/// the element count of the frame against [`super::limits::MAX_ELEMENTS`], naming the
/// parameter. Nothing is built before this passes.
pub(crate) fn check_params(p: &FrameParams) -> Result<(), FrameError> {
    use super::limits::{check, check_range};
    let range = |name: &str| {
        let r = PARAM_RANGES
            .iter()
            .find(|r| r.0 == name)
            .expect("every parameter has a range");
        (r.1, r.2, r.3, r.4)
    };
    let one = |name: &str, v: f64| -> Result<(), FrameError> {
        let (lo, open, hi, unit) = range(name);
        Ok(check_range(name, v, lo, open, hi, unit)?)
    };
    let list = |name: &str, v: &[f64]| -> Result<(), FrameError> {
        let (lo, open, hi, unit) = range(name);
        for (k, x) in v.iter().enumerate() {
            check_range(format!("{name}[{}]", k + 1), *x, lo, open, hi, unit)?;
        }
        Ok(())
    };
    for (name, n, max) in [
        ("spans_x", p.spans_x.len(), MAX_BAYS),
        ("spans_y", p.spans_y.len(), MAX_BAYS),
        ("stories", p.story_heights.len(), MAX_STORIES),
    ] {
        if n == 0 {
            bail!("{name}: give at least one value");
        }
        check(name, "count", n as u64, max as u64)?;
    }
    for (name, n, max) in [
        (
            "column_elements",
            p.column_elements,
            MAX_ELEMENTS_PER_MEMBER,
        ),
        ("beam_elements", p.beam_elements, MAX_ELEMENTS_PER_MEMBER),
        ("column_bars_per_face", p.column_bars_per_face, MAX_BARS),
        ("beam_bars (top)", p.beam_bars[0], MAX_BARS),
        ("beam_bars (bottom)", p.beam_bars[1], MAX_BARS),
        ("column_fibers (ny)", p.column_fibers[0], MAX_CORE_FIBERS),
        ("column_fibers (nz)", p.column_fibers[1], MAX_CORE_FIBERS),
        ("beam_fibers (ny)", p.beam_fibers[0], MAX_CORE_FIBERS),
        ("beam_fibers (nz)", p.beam_fibers[1], MAX_CORE_FIBERS),
    ] {
        if n == 0 {
            bail!("{name} = 0: must be at least 1");
        }
        check(name, "count", u64::from(n), u64::from(max))?;
    }
    list("spans_x", &p.spans_x)?;
    list("spans_y", &p.spans_y)?;
    list("stories", &p.story_heights)?;
    list("column", &p.column)?;
    list("beam", &p.beam)?;
    list("ec", &p.ec)?;
    list("fc", &p.fc)?;
    list("added_mass", &p.added_mass)?;
    // A column at least as large as a bay would overlap its neighbour.
    let size = p.column[0].max(p.column[1]);
    for (name, spans) in [("spans_x", &p.spans_x), ("spans_y", &p.spans_y)] {
        if let Some((k, span)) = spans.iter().enumerate().find(|(_, s)| size >= **s) {
            bail!(
                "column section {} m × {} m is not smaller than the bay {name}[{}] = {span} m: \
                 neighbouring columns would overlap",
                p.column[0],
                p.column[1],
                k + 1
            );
        }
    }
    for (name, v) in [
        ("slab_thickness", p.slab_thickness),
        ("cover", p.cover),
        ("bar_offset", p.bar_offset),
        ("column_bar_diameter", p.column_bar_diameter),
        ("beam_bar_diameter", p.beam_bar_diameter),
        ("confinement", p.confinement),
        ("cover_epscu", p.cover_epscu),
        ("core_epscu", p.core_epscu),
        ("residual", p.residual),
        ("fy", p.fy),
        ("es", p.es),
        ("concrete_density", p.concrete_density),
        ("steel_density", p.steel_density),
        ("ballast_centre", p.ballast_centre),
        ("scale", p.scale),
        ("g", p.g),
        ("xi", p.xi),
        ("t1", p.t1),
    ] {
        one(name, v)?;
    }
    // Elements of the frame (module docs): columns, beams along both directions with
    // `beam_elements` per half span, 4 strips and 4 panels per bay and floor.
    let (nx, ny, ns) = (
        p.spans_x.len() as u64,
        p.spans_y.len() as u64,
        p.story_heights.len() as u64,
    );
    let columns = (nx + 1) * (ny + 1) * ns * u64::from(p.column_elements);
    let beams = (nx * (ny + 1) + ny * (nx + 1)) * 2 * u64::from(p.beam_elements) * ns;
    let slabs = 8 * nx * ny * ns;
    check(
        "frame",
        "element count",
        columns + beams + slabs,
        super::limits::MAX_ELEMENTS as u64,
    )?;
    Ok(())
}

/// Builds the frame model. Errors on inconsistent parameters.
// The story loops index several per-story arrays (concrete, heights, masses) and tags.
#[allow(clippy::needless_range_loop)]
pub fn frame(p: &FrameParams) -> Result<Model, FrameError> {
    let ns = p.story_heights.len();
    let (nx, ny) = (p.spans_x.len(), p.spans_y.len());
    if ns == 0 || nx == 0 || ny == 0 {
        bail!("need at least one story and one bay in X and in Y");
    }
    if p.column_elements == 0 || p.beam_elements == 0 {
        bail!("column and beam element counts must be at least 1");
    }
    if p.column_bars_per_face < 2 || p.beam_bars.iter().any(|&n| n < 2) {
        bail!("need at least 2 bars per column face and 2 beam bars per layer");
    }
    let ec = per_floor(&p.ec, ns, "ec")?;
    let fc = per_floor(&p.fc, ns, "fc")?;
    let added = per_floor(&p.added_mass, ns, "added mass")?;
    check_reinforcement(p)?;
    check_concrete(p, &ec, &fc)?;
    if !(0.0..=1.0).contains(&p.ballast_centre) {
        bail!("ballast centre share {} must lie in 0..1", p.ballast_centre);
    }
    check_params(p)?;
    let pi = std::f64::consts::PI;
    let col_bar_area = pi * p.column_bar_diameter.powi(2) / 4.0;
    let beam_bar_area = pi * p.beam_bar_diameter.powi(2) / 4.0;

    // grid coordinates (half-span resolution)
    let grid = |spans: &[f64]| -> Vec<f64> {
        let mut c = vec![0.0];
        for s in spans {
            let last = *c.last().unwrap();
            c.push(last + s / 2.0);
            c.push(last + s);
        }
        c
    };
    let (gx, gy) = (grid(&p.spans_x), grid(&p.spans_y));
    let mut zf = vec![0.0];
    for h in &p.story_heights {
        zf.push(zf.last().unwrap() + h);
    }
    // tags: the reference scheme 100f + 10i + j + 1 (column mid-height 100(s-1)+50+10i+j+1)
    // fits grids up to 2 x 2 bays; larger grids use 10000f + 100i + j + 1.
    let compact = nx <= 2 && ny <= 2;
    let node_tag = |f: usize, i: usize, j: usize| -> u32 {
        if compact {
            (100 * f + 10 * i + j + 1) as u32
        } else {
            (10000 * f + 100 * i + j + 1) as u32
        }
    };
    let mut next_extra: u32 = if compact {
        10001
    } else {
        (10000 * (ns + 1) + 1) as u32
    };

    // ------------------------------------------------------------ materials
    let mut materials = Vec::new();
    for f in 0..ns {
        let (fcf, e) = (fc[f], ec[f]);
        let ft = 0.33 * (fcf / 1e6).sqrt() * 1e6;
        materials.push(Material {
            tag: (2 * f + 1) as u32,
            name: format!("cover_F{}", f + 1),
            density: p.concrete_density,
            law: MaterialLaw::Concrete02 {
                fpc: -fcf,
                epsc0: -2.0 * fcf / e,
                fpcu: -p.residual * fcf,
                epscu: p.cover_epscu,
                lambda: 0.1,
                ft,
                ets: ft / 0.002,
            },
        });
        let fcc = p.confinement * fcf;
        materials.push(Material {
            tag: (2 * f + 2) as u32,
            name: format!("core_F{}", f + 1),
            density: p.concrete_density,
            law: MaterialLaw::Concrete02 {
                fpc: -fcc,
                epsc0: -2.0 * fcc / e,
                fpcu: -p.residual * fcc,
                epscu: p.core_epscu,
                lambda: 0.1,
                ft,
                ets: ft / 0.002,
            },
        });
    }
    let steel_tag = (2 * ns + 1) as u32;
    materials.push(Material {
        tag: steel_tag,
        name: "rebar".into(),
        density: p.steel_density,
        law: MaterialLaw::Steel02 {
            fy: p.fy,
            e0: p.es,
            b: 0.01,
            r0: 18.0,
            cr1: 0.925,
            cr2: 0.15,
            a: None,
        },
    });

    // ------------------------------------------------------------- sections
    let mut sections = Vec::new();
    for f in 0..ns {
        let gc = ec[f] / (2.0 * (1.0 + p.nu));
        let [cb, ch] = p.column;
        let a = cb.min(ch) / 2.0 - p.bar_offset;
        // torsion constant of a rectangle b<=h: J = b³h(1/3 − 0.21 b/h (1 − b⁴/(12h⁴)))
        // (Roark, Formulas for Stress and Strain, Table 10.7); for a square the
        // reference uses 0.1406 b⁴.
        let rect_j = |b: f64, h: f64| {
            let (b, h) = (b.min(h), b.max(h));
            b.powi(3) * h * (1.0 / 3.0 - 0.21 * b / h * (1.0 - b.powi(4) / (12.0 * h.powi(4))))
        };
        let jc = if cb == ch {
            0.1406 * cb.powi(4)
        } else {
            rect_j(cb, ch)
        };
        let bars = if cb == ch {
            perimeter_bars(a, p.column_bars_per_face, col_bar_area)
        } else {
            let (ay, az) = (cb / 2.0 - p.bar_offset, ch / 2.0 - p.bar_offset);
            perimeter_bars(1.0, p.column_bars_per_face, col_bar_area)
                .into_iter()
                .map(|b| Bar(b.0 * ay, b.1 * az, b.2))
                .collect()
        };
        sections.push(Section {
            tag: (2 * f + 1) as u32,
            name: format!("column_S{}", f + 1),
            kind: SectionKind::RcRect(RcRect {
                b: cb,
                h: ch,
                cover: p.cover,
                core_material: (2 * f + 2) as u32,
                cover_material: (2 * f + 1) as u32,
                core_fibers: p.column_fibers,
                cover_layers: 1,
                bar_material: steel_tag,
                bars,
                gj: gc * jc,
            }),
        });
        let [bb, bh] = p.beam;
        let ay = bb / 2.0 - p.bar_offset;
        let az = bh / 2.0 - p.bar_offset;
        let mut bars = Vec::new();
        // bottom layer (local z = −az) first, then the top layer
        for (z, n) in [(-az, p.beam_bars[1]), (az, p.beam_bars[0])] {
            for k in 0..n {
                // Evenly spaced across the width; for 3 bars this is exactly −ay, 0, ay.
                let y = -ay + k as f64 * 2.0 * ay / (n - 1) as f64;
                bars.push(Bar(y, z, beam_bar_area));
            }
        }
        sections.push(Section {
            tag: (2 * f + 2) as u32,
            name: format!("beam_F{}", f + 1),
            kind: SectionKind::RcRect(RcRect {
                b: bb,
                h: bh,
                cover: p.cover,
                core_material: (2 * f + 2) as u32,
                cover_material: (2 * f + 1) as u32,
                core_fibers: p.beam_fibers,
                cover_layers: 1,
                bar_material: steel_tag,
                bars,
                gj: gc * rect_j(bb, bh),
            }),
        });
    }

    // ---------------------------------------------------------------- nodes
    let col_pos: Vec<(usize, usize)> = (0..=ny)
        .flat_map(|j| (0..=nx).map(move |i| (2 * i, 2 * j)))
        .collect();
    let mid_pos: Vec<(usize, usize)> = (0..=2 * ny)
        .flat_map(|j| (0..=2 * nx).map(move |i| (i, j)))
        .filter(|(i, j)| (i % 2) + (j % 2) == 1)
        .collect();
    let centre_pos: Vec<(usize, usize)> = (0..ny)
        .flat_map(|j| (0..nx).map(move |i| (2 * i + 1, 2 * j + 1)))
        .collect();
    let mut nodes = Vec::new();
    for f in 0..=ns {
        let mut pts = col_pos.clone();
        if f > 0 {
            pts.extend(&mid_pos);
            pts.extend(&centre_pos);
        }
        for (i, j) in pts {
            nodes.push(Node {
                tag: node_tag(f, i, j),
                x: gx[i],
                y: gy[j],
                z: zf[f],
            });
        }
    }
    let mut col_chain = BTreeMap::new();
    for s in 1..=ns {
        for &(i, j) in &col_pos {
            let mut chain = vec![node_tag(s - 1, i, j)];
            for k in 1..p.column_elements {
                let z = zf[s - 1] + k as f64 * p.story_heights[s - 1] / p.column_elements as f64;
                let t = if compact && p.column_elements == 2 {
                    (100 * (s - 1) + 50 + 10 * i + j + 1) as u32
                } else {
                    next_extra += 1;
                    next_extra - 1
                };
                nodes.push(Node {
                    tag: t,
                    x: gx[i],
                    y: gy[j],
                    z,
                });
                chain.push(t);
            }
            chain.push(node_tag(s, i, j));
            col_chain.insert((s, i, j), chain);
        }
    }
    let supports = col_pos
        .iter()
        .map(|&(i, j)| Support {
            node: node_tag(0, i, j),
            dofs: [1; 6],
        })
        .collect();

    let transformations = vec![
        Transformation {
            tag: 1,
            kind: p.transformation,
            vecxz: [1.0, 0.0, 0.0],
        },
        Transformation {
            tag: 2,
            kind: p.transformation,
            vecxz: [0.0, 0.0, 1.0],
        },
    ];

    // ------------------------------------------------------------- elements
    let mut elements = Vec::new();
    let mut etag = 1u32;
    let beam_column = |nodes: [u32; 2], section: u32, transf: u32| ElementKind::BeamColumn {
        nodes,
        section,
        transf,
        formulation: p.formulation,
        points: p.points,
        integration: None,
    };
    for s in 1..=ns {
        for &(i, j) in &col_pos {
            let chain = &col_chain[&(s, i, j)];
            for w in chain.windows(2) {
                elements.push(Element {
                    tag: etag,
                    rigid_body: true,
                    type_name: "Column".into(),
                    group: Group(s.to_string()),
                    kind: beam_column([w[0], w[1]], (2 * s - 1) as u32, 1),
                });
                etag += 1;
            }
        }
    }
    let mut masses = Vec::new();
    // Slab quarter panels (rigid-body model only), tagged after every FE element:
    // (floor, corner nodes counter-clockwise seen from above).
    let mut panels: Vec<(usize, [u32; 4])> = Vec::new();
    for fl in 1..=ns {
        let f = fl - 1;
        // beam lines: along X at every column line j, then along Y at every column line i
        let mut lines: Vec<Vec<(usize, usize)>> = Vec::new();
        for j in (0..=2 * ny).step_by(2) {
            lines.push((0..=2 * nx).map(|i| (i, j)).collect());
        }
        for i in (0..=2 * nx).step_by(2) {
            lines.push((0..=2 * ny).map(|j| (i, j)).collect());
        }
        for line in &lines {
            for w in line.windows(2) {
                let (pp, q) = (w[0], w[1]);
                let mut seq = vec![node_tag(fl, pp.0, pp.1)];
                for k in 1..p.beam_elements {
                    let wt = k as f64 / p.beam_elements as f64;
                    let x = (1.0 - wt) * gx[pp.0] + wt * gx[q.0];
                    let y = (1.0 - wt) * gy[pp.1] + wt * gy[q.1];
                    nodes.push(Node {
                        tag: next_extra,
                        x,
                        y,
                        z: zf[fl],
                    });
                    seq.push(next_extra);
                    next_extra += 1;
                }
                seq.push(node_tag(fl, q.0, q.1));
                for w in seq.windows(2) {
                    elements.push(Element {
                        tag: etag,
                        rigid_body: true,
                        type_name: "Beam".into(),
                        group: Group(fl.to_string()),
                        kind: beam_column([w[0], w[1]], (2 * fl) as u32, 2),
                    });
                    etag += 1;
                }
            }
        }
        let e = ec[f];
        let gc = e / (2.0 * (1.0 + p.nu));
        let t = p.slab_thickness;
        let total_area: f64 = p.spans_x.iter().sum::<f64>() * p.spans_y.iter().sum::<f64>();
        for &(ci, cj) in &centre_pos {
            let (lx, ly) = (p.spans_x[ci / 2], p.spans_y[cj / 2]);
            let area = if lx == ly {
                gc * t * lx * 2f64.sqrt() / e
            } else {
                let d = (lx * lx + ly * ly).sqrt();
                gc * t * d.powi(3) / (2.0 * e * lx * ly)
            };
            let width = area / t;
            let centre = node_tag(fl, ci, cj);
            let corners = [
                (ci - 1, cj - 1),
                (ci + 1, cj - 1),
                (ci - 1, cj + 1),
                (ci + 1, cj + 1),
            ];
            for &(i, j) in &corners {
                elements.push(Element {
                    tag: etag,
                    rigid_body: false,
                    type_name: "Slab".into(),
                    group: Group(fl.to_string()),
                    kind: ElementKind::ElasticStrip {
                        nodes: [node_tag(fl, i, j), centre],
                        transf: 2,
                        e,
                        g: gc,
                        width,
                        thickness: t,
                        density: 0.0,
                    },
                });
                etag += 1;
            }
            for &(i, j) in &corners {
                // floor corner, edge mid-node, bay centre, edge mid-node; reversed when
                // that order turns clockwise
                let ccw = (ci as i64 - i as i64) * (cj as i64 - j as i64) > 0;
                let q = if ccw {
                    [(i, j), (ci, j), (ci, cj), (i, cj)]
                } else {
                    [(i, j), (i, cj), (ci, cj), (ci, j)]
                };
                panels.push((fl, q.map(|(a, b)| node_tag(fl, a, b))));
            }
            let share = added[f] * (lx * ly / total_area);
            let ms = p.concrete_density * t * lx * ly + share * (1.0 - p.ballast_centre);
            let centre_extra = share * p.ballast_centre;
            for &(i, j) in &corners {
                masses.push(NodalMass {
                    node: node_tag(fl, i, j),
                    m: ms / 24.0,
                    rotational: None,
                });
            }
            for (i, j) in [(ci, cj - 1), (ci - 1, cj), (ci + 1, cj), (ci, cj + 1)] {
                masses.push(NodalMass {
                    node: node_tag(fl, i, j),
                    m: ms / 12.0,
                    rotational: None,
                });
            }
            masses.push(NodalMass {
                node: centre,
                m: ms / 2.0 + centre_extra,
                rotational: None,
            });
        }
    }

    for (fl, q) in panels {
        elements.push(Element {
            tag: etag,
            rigid_body: true,
            type_name: "Slab".into(),
            group: Group(fl.to_string()),
            kind: ElementKind::Panel {
                nodes: q,
                thickness: p.slab_thickness,
                density: 0.0,
            },
        });
        etag += 1;
    }

    let model = Model {
        name: p.name.clone(),
        description: format!(
            "Regular RC frame generated by fem2rbd: {nx} x {ny} bays, {ns} stories; fiber \
             columns and beams, slab as lumped mass plus 4 elastic diagonal strips per bay \
             (FE only) and 4 quarter panels per bay (rigid bodies only)."
        ),
        scale: p.scale,
        gravity: Gravity {
            g: p.g,
            load_steps: 10,
        },
        damping: Some(Damping {
            xi: Some(p.xi),
            periods: Some([p.t1, p.t1 / 3.0]),
            a0: None,
            a1: None,
        }),
        materials,
        sections,
        transformations,
        nodes,
        supports,
        elements,
        masses,
    };
    model
        .validate()
        .map_err(|e| e.in_file(format!("generated frame {:?}", p.name)))?;
    Ok(model)
}

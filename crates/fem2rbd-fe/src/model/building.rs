//! Generator of RC frame–shear-wall buildings (`fem2rbd generate building`): the regular
//! frame of [`super::generate::frame`] plus shear walls meshed into layered shells.
//!
//! **Walls.** A wall segment fills one bay of one column line in one story
//! ([`WallSpec`]: `x0:2:1-7` = along X on column line j = 0, bay 2, stories 1 to 7). Its
//! mid-surface runs through the column and beam axes; it is meshed into
//! `wall_mesh[0]` × `wall_mesh[1]` (along × up) four-node `shell` elements, a multiple of
//! the frame's nodes on that bay (2·`beam_elements` along, `column_elements` up) so that
//! the wall's edge nodes are the column and beam nodes: the wall is tied to its boundary
//! frame node by node. Nodes are shared by coordinates (rounded to 1 µm); new nodes at the
//! base are fixed like the column feet. An opening (door, window) is a rectangle of mesh
//! cells left out (`:open=A0-A1/U0-U1`, cells A0..A1 along and U0..U1 up, 0-based, end
//! exclusive). A story with fewer wall segments than the one below is a soft / weak story.
//!
//! **Section** (`layered_shell`, one per story, OpenSees `LayeredShell`): from the face
//! inwards, cover concrete `wall_cover`, a vertical then a horizontal smeared rebar layer
//! (thickness ρ_v·t/2 and ρ_h·t/2: half the reinforcement per face, ρ = A_s/(t·s) per
//! direction), `wall_core_layers` core concrete layers sharing the rest of the thickness
//! equally, and the mirror image; Σ thicknesses = t. Concrete layers: the story's E and
//! f′c, f_t = 0.33·√f′c (MPa; as the frame's Concrete02, ACI 318-14 §19.2.3.1 modulus of
//! rupture with λ = 1 times 0.33/0.62), ν = `nu`; bars: the frame's Steel02. Density: the
//! concrete's over the concrete layers and the steel's over the rebar layers when
//! `steel_density` > 0, else the concrete's over the whole thickness (as the frame leaves
//! bar mass out): ρ_sec = (ρ_c·t_c + ρ_s'·t_s)/t.
//!
//! **Beams over walls.** By default the frame's beams stay on the wall lines (a wall with
//! a boundary frame); with `beams_over_walls = false` the beam segments over and under a
//! wall are left out (the wall carries the floor directly; the slab then sits on it).
//!
//! **Names.** Wall elements are `type_name = "Wall"`, group `W<story>` (their own BCB
//! element group, as BCB's "RC Walls" preset), so rigid bodies are `Wall:W3:1234`.
//! Element tags follow the frame's; node tags of new nodes follow the frame's largest.
use super::generate::{frame, FrameParams};
use super::*;
use anyhow::{anyhow, bail, Context};

/// The column line a wall runs on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WallLine {
    /// Along X on column line `j` (0 = y = 0, …, ny).
    X(usize),
    /// Along Y on column line `i` (0 = x = 0, …, nx).
    Y(usize),
}

/// A rectangle of mesh cells left out of a wall segment (0-based, end exclusive).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Opening {
    /// Cells along the wall: start, end.
    pub along: [u32; 2],
    /// Cells up the wall: start, end.
    pub up: [u32; 2],
}

/// Wall segments on one bay of one column line over a range of stories.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct WallSpec {
    /// Column line.
    pub line: WallLine,
    /// Bay along the line, 1-based.
    pub bay: usize,
    /// First and last story, 1-based, inclusive.
    pub stories: [usize; 2],
    /// Optional opening, the same in every story of the range.
    pub opening: Option<Opening>,
}

impl WallSpec {
    /// Parses `x0:2:1-7`, `y3:1:2`, `x1:1:1-2:open=1-3/0-2` (module docs).
    pub fn parse(s: &str) -> anyhow::Result<WallSpec> {
        let err = || {
            anyhow!(
                "wall {s:?}: expected LINE:BAY:STORIES[:open=A0-A1/U0-U1], e.g. x0:2:1-7 \
                 (along X on column line 0, bay 2, stories 1 to 7)"
            )
        };
        let parts: Vec<&str> = s.trim().split(':').collect();
        if !(3..=4).contains(&parts.len()) {
            return Err(err());
        }
        let num = |t: &str| t.trim().parse::<usize>().map_err(|_| err());
        let range = |t: &str| -> anyhow::Result<[usize; 2]> {
            match t.split_once('-') {
                Some((a, b)) => Ok([num(a)?, num(b)?]),
                None => Ok([num(t)?, num(t)?]),
            }
        };
        let line = match parts[0].trim().split_at_checked(1) {
            Some(("x" | "X", k)) => WallLine::X(num(k)?),
            Some(("y" | "Y", k)) => WallLine::Y(num(k)?),
            _ => return Err(err()),
        };
        let opening = match parts.get(3) {
            None => None,
            Some(o) => {
                let o = o.trim().strip_prefix("open=").ok_or_else(err)?;
                let (a, u) = o.split_once('/').ok_or_else(err)?;
                let (a, u) = (range(a)?, range(u)?);
                Some(Opening {
                    along: [a[0] as u32, a[1] as u32],
                    up: [u[0] as u32, u[1] as u32],
                })
            }
        };
        Ok(WallSpec {
            line,
            bay: num(parts[1])?,
            stories: range(parts[2])?,
            opening,
        })
    }
}

/// Parameters of a frame–shear-wall building. SI units.
#[derive(Debug, Clone, PartialEq)]
pub struct BuildingParams {
    /// The frame (bays, stories, columns, beams, slabs, masses, per-story concrete).
    pub frame: FrameParams,
    /// Wall segments.
    pub walls: Vec<WallSpec>,
    /// Wall thickness (m), one value or one per story.
    pub wall_thickness: Vec<f64>,
    /// Vertical reinforcement ratio ρ_v = A_s/(t·s) (both faces together).
    pub wall_rho_vertical: f64,
    /// Horizontal reinforcement ratio ρ_h.
    pub wall_rho_horizontal: f64,
    /// Cover concrete layer thickness per face (m).
    pub wall_cover: f64,
    /// Core concrete layers.
    pub wall_core_layers: u32,
    /// Wall mesh per bay and story: cells along, cells up; `None` = the frame's nodes
    /// (2·beam_elements × column_elements).
    pub wall_mesh: Option<[u32; 2]>,
    /// Keep the frame's beams on the wall lines (default true).
    pub beams_over_walls: bool,
}

impl Default for BuildingParams {
    fn default() -> Self {
        BuildingParams {
            frame: FrameParams::default(),
            walls: Vec::new(),
            wall_thickness: vec![0.2],
            wall_rho_vertical: 0.0025,
            wall_rho_horizontal: 0.0025,
            wall_cover: 0.02,
            wall_core_layers: 4,
            wall_mesh: None,
            beams_over_walls: true,
        }
    }
}

/// The layered section of a wall of thickness `t` (module docs): the layers bottom to
/// top and the section density.
#[allow(clippy::too_many_arguments)]
pub fn wall_layers(
    t: f64,
    cover: f64,
    core_layers: u32,
    rho_v: f64,
    rho_h: f64,
    concrete: (f64, f64, f64, f64),
    steel_tag: u32,
) -> anyhow::Result<Vec<ShellLayer>> {
    let (e, nu, fc, ft) = concrete;
    let (tv, th) = (rho_v * t / 2.0, rho_h * t / 2.0);
    let core = t - 2.0 * (cover + tv + th);
    if core.is_nan() || core <= 0.0 || core_layers == 0 {
        bail!(
            "wall of {t} m: cover {cover} m and rebar layers {tv:.5} + {th:.5} m per face \
             leave no core ({core:.4} m), or no core layers"
        );
    }
    let conc = |thickness: f64| ShellLayer::Concrete {
        thickness,
        e,
        nu,
        fc,
        ft,
    };
    let bar = |thickness: f64, angle: f64| ShellLayer::Rebar {
        thickness,
        material: steel_tag,
        angle,
    };
    let mut face = vec![conc(cover)];
    if tv > 0.0 {
        face.push(bar(tv, 90.0));
    }
    if th > 0.0 {
        face.push(bar(th, 0.0));
    }
    let mut layers = face.clone();
    for _ in 0..core_layers {
        layers.push(conc(core / f64::from(core_layers)));
    }
    layers.extend(face.into_iter().rev());
    Ok(layers)
}

type Key = [i64; 3];
fn key(p: [f64; 3]) -> Key {
    p.map(|x| (x * 1e6).round() as i64)
}

/// Builds the building (module docs). Errors name the wall or parameter at fault.
pub fn building(p: &BuildingParams) -> anyhow::Result<Model> {
    let f = &p.frame;
    let ns = f.story_heights.len();
    let (nx, ny) = (f.spans_x.len(), f.spans_y.len());
    let mut m = frame(f)?;
    let thick = match p.wall_thickness.len() {
        1 => vec![p.wall_thickness[0]; ns],
        k if k == ns => p.wall_thickness.clone(),
        k => bail!("wall_thickness: give 1 value or one per story ({ns}), not {k}"),
    };
    for (k, t) in thick.iter().enumerate() {
        super::limits::check_range(
            format!("wall_thickness[{}]", k + 1),
            *t,
            0.01,
            false,
            5.0,
            "m",
        )?;
    }
    for (name, v, hi) in [
        ("wall_rho_vertical", p.wall_rho_vertical, 0.2),
        ("wall_rho_horizontal", p.wall_rho_horizontal, 0.2),
        ("wall_cover", p.wall_cover, 1.0),
    ] {
        super::limits::check_range(name, v, 0.0, false, hi, "")?;
    }
    if p.wall_core_layers == 0 || p.wall_core_layers > 50 {
        bail!("wall_core_layers = {}: give 1 to 50", p.wall_core_layers);
    }
    let base = [2 * f.beam_elements, f.column_elements];
    let mesh = p.wall_mesh.unwrap_or(base);
    for k in 0..2 {
        if mesh[k] == 0 || mesh[k] % base[k] != 0 || mesh[k] > 200 {
            bail!(
                "wall_mesh {}x{}: cells along must be a multiple of 2·beam_elements = {} and \
                 cells up a multiple of column_elements = {} (at most 200), so that the \
                 wall's edge nodes are the frame's",
                mesh[0],
                mesh[1],
                base[0],
                base[1]
            );
        }
    }
    // Grid and floors.
    let grid = |spans: &[f64]| -> Vec<f64> {
        let mut c = vec![0.0];
        for s in spans {
            c.push(c.last().unwrap() + s);
        }
        c
    };
    let (gx, gy) = (grid(&f.spans_x), grid(&f.spans_y));
    let mut zf = vec![0.0];
    for h in &f.story_heights {
        zf.push(zf.last().unwrap() + h);
    }
    // Check the walls and list (story, line, bay, opening) once each.
    let mut segs: Vec<(usize, WallLine, usize, Option<Opening>)> = Vec::new();
    for (k, w) in p.walls.iter().enumerate() {
        let item = format!(
            "wall {} ({:?} bay {} stories {:?})",
            k + 1,
            w.line,
            w.bay,
            w.stories
        );
        let (lines, bays) = match w.line {
            WallLine::X(_) => (ny, nx),
            WallLine::Y(_) => (nx, ny),
        };
        let line_index = match w.line {
            WallLine::X(j) | WallLine::Y(j) => j,
        };
        if line_index > lines {
            bail!("{item}: column line {line_index} does not exist (0..={lines})");
        }
        if w.bay == 0 || w.bay > bays {
            bail!("{item}: bay {} does not exist (1..={bays})", w.bay);
        }
        let [s0, s1] = w.stories;
        if s0 == 0 || s1 < s0 || s1 > ns {
            bail!("{item}: stories {s0}-{s1} are not within 1..={ns}");
        }
        if let Some(o) = w.opening {
            let ok = |r: [u32; 2], n: u32| r[0] < r[1] && r[1] <= n;
            if !ok(o.along, mesh[0]) || !ok(o.up, mesh[1]) {
                bail!(
                    "{item}: opening cells {:?} along / {:?} up do not fit the {}x{} mesh",
                    o.along,
                    o.up,
                    mesh[0],
                    mesh[1]
                );
            }
            if o.along == [0, mesh[0]] && o.up == [0, mesh[1]] {
                bail!("{item}: the opening leaves no wall");
            }
        }
        for s in s0..=s1 {
            if segs
                .iter()
                .any(|g| g.0 == s && g.1 == w.line && g.2 == w.bay)
            {
                bail!("{item}: story {s} of this bay already has a wall");
            }
            segs.push((s, w.line, w.bay, w.opening));
        }
    }
    segs.sort_by_key(|g| {
        let (dir, l) = match g.1 {
            WallLine::X(j) => (0, j),
            WallLine::Y(i) => (1, i),
        };
        (g.0, dir, l, g.2)
    });

    // Wall sections: one per story that has walls.
    let steel_tag = m
        .materials
        .iter()
        .find(|x| x.name == "rebar")
        .map(|x| x.tag)
        .ok_or_else(|| anyhow!("the frame has no rebar material"))?;
    let ec = if f.ec.len() == 1 {
        vec![f.ec[0]; ns]
    } else {
        f.ec.clone()
    };
    let fcs = if f.fc.len() == 1 {
        vec![f.fc[0]; ns]
    } else {
        f.fc.clone()
    };
    let mut next_sec = m.sections.iter().map(|s| s.tag).max().unwrap_or(0) + 1;
    let mut wall_sec = BTreeMap::new();
    for s in 1..=ns {
        if !segs.iter().any(|g| g.0 == s) {
            continue;
        }
        let t = thick[s - 1];
        let fc = fcs[s - 1];
        let ft = 0.33 * (fc / 1e6).sqrt() * 1e6;
        let layers = wall_layers(
            t,
            p.wall_cover,
            p.wall_core_layers,
            p.wall_rho_vertical,
            p.wall_rho_horizontal,
            (ec[s - 1], f.nu, fc, ft),
            steel_tag,
        )
        .with_context(|| format!("story {s}"))?;
        let t_rebar: f64 = layers
            .iter()
            .filter(|l| matches!(l, ShellLayer::Rebar { .. }))
            .map(ShellLayer::thickness)
            .sum();
        let rho_s = if f.steel_density > 0.0 {
            f.steel_density
        } else {
            f.concrete_density
        };
        let density = (f.concrete_density * (t - t_rebar) + rho_s * t_rebar) / t;
        m.sections.push(Section {
            tag: next_sec,
            name: format!("wall_S{s}"),
            kind: SectionKind::LayeredShell { layers, density },
        });
        wall_sec.insert(s, next_sec);
        next_sec += 1;
    }

    // Beams over / under walls, when left out.
    let on_segment = |a: [f64; 3], b: [f64; 3], line: WallLine, bay: usize, z: f64| -> bool {
        let eps = 1e-6;
        let (lo, hi, fixed, c) = match line {
            WallLine::X(j) => (gx[bay - 1], gx[bay], gy[j], (0, 1)),
            WallLine::Y(i) => (gy[bay - 1], gy[bay], gx[i], (1, 0)),
        };
        [a, b].iter().all(|q| {
            (q[2] - z).abs() < eps
                && (q[c.1] - fixed).abs() < eps
                && q[c.0] > lo - eps
                && q[c.0] < hi + eps
        })
    };
    if !p.beams_over_walls {
        let nodes: BTreeMap<u32, [f64; 3]> = m.nodes.iter().map(|n| (n.tag, n.xyz())).collect();
        m.elements.retain(|e| {
            if e.type_name != "Beam" {
                return true;
            }
            let [a, b] = [nodes[&e.nodes()[0]], nodes[&e.nodes()[1]]];
            !segs.iter().any(|&(s, line, bay, _)| {
                on_segment(a, b, line, bay, zf[s]) || on_segment(a, b, line, bay, zf[s - 1])
            })
        });
    }

    // Mesh.
    let mut at: BTreeMap<Key, u32> = m.nodes.iter().map(|n| (key(n.xyz()), n.tag)).collect();
    let mut next_node = m.nodes.iter().map(|n| n.tag).max().unwrap_or(0) + 1;
    let mut next_el = m.elements.iter().map(|e| e.tag).max().unwrap_or(0) + 1;
    let first_wall = next_el;
    let mut walls = Vec::new();
    for &(s, line, bay, opening) in &segs {
        let (z0, z1) = (zf[s - 1], zf[s]);
        let (p0, p1, dir) = match line {
            WallLine::X(j) => ([gx[bay - 1], gy[j]], [gx[bay], gy[j]], [1.0, 0.0, 0.0]),
            WallLine::Y(i) => ([gx[i], gy[bay - 1]], [gx[i], gy[bay]], [0.0, 1.0, 0.0]),
        };
        let mut node = |a: u32, u: u32| -> u32 {
            let (sa, su) = (
                f64::from(a) / f64::from(mesh[0]),
                f64::from(u) / f64::from(mesh[1]),
            );
            let xyz = [
                p0[0] + sa * (p1[0] - p0[0]),
                p0[1] + sa * (p1[1] - p0[1]),
                z0 + su * (z1 - z0),
            ];
            *at.entry(key(xyz)).or_insert_with(|| {
                let tag = next_node;
                next_node += 1;
                m.nodes.push(Node {
                    tag,
                    x: xyz[0],
                    y: xyz[1],
                    z: xyz[2],
                });
                if xyz[2] == 0.0 {
                    m.supports.push(Support {
                        node: tag,
                        dofs: [1; 6],
                    });
                }
                tag
            })
        };
        for u in 0..mesh[1] {
            for a in 0..mesh[0] {
                if let Some(o) = opening {
                    if (o.along[0]..o.along[1]).contains(&a) && (o.up[0]..o.up[1]).contains(&u) {
                        continue;
                    }
                }
                let q = [
                    node(a, u),
                    node(a + 1, u),
                    node(a + 1, u + 1),
                    node(a, u + 1),
                ];
                walls.push(Element {
                    tag: next_el,
                    type_name: "Wall".into(),
                    group: Group(format!("W{s}")),
                    rigid_body: true,
                    kind: ElementKind::Shell {
                        nodes: q,
                        section: wall_sec[&s],
                        local_x: Some(dir),
                        corotational: true,
                    },
                });
                next_el += 1;
            }
        }
    }
    let n_walls = walls.len();
    m.elements.extend(walls);
    if m.elements.len() > super::limits::MAX_ELEMENTS {
        bail!(
            "the building has {} elements, more than {}",
            m.elements.len(),
            super::limits::MAX_ELEMENTS
        );
    }
    m.description = format!(
        "RC frame-shear-wall building generated by fem2rbd: {nx} x {ny} bays, {ns} stories; \
         fiber columns and beams, slab as lumped mass plus 4 elastic diagonal strips per bay \
         (FE only) and 4 quarter panels per bay (rigid bodies only); {} wall segments meshed \
         into {n_walls} layered shells (tags {first_wall}..), {}.",
        segs.len(),
        if p.beams_over_walls {
            "beams kept over walls"
        } else {
            "no beams over walls"
        }
    );
    m.validate().map_err(|e| super::ModelError {
        file: format!("generated building {:?}", f.name),
        ..e
    })?;
    Ok(m)
}

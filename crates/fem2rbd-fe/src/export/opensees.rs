//! Export of a model and its analysis to a self-contained openseespy script.
//!
//! The script builds the same model (nodes, supports, materials, fiber sections,
//! elements with their transformations, lumped masses), applies gravity in load-control
//! steps then `loadConst`, adds Rayleigh damping `a0·M + a1·K_initial`
//! (`ops.rayleigh(a0, 0, a1, 0)`), uniform excitation from AT2 records scaled to their
//! PGA, and integrates with Newmark (γ = 0.5, β = 0.25) + Newton and the fallbacks of the
//! reference `run_frame3.py`. Commands: `eigen [N]`, `gravity`, `pushover SPEC.json`,
//! `print-json [out.json]` (OpenSees' `printModel -JSON`), `th [out.csv]`.
//! openseespy 3.7.1 is imported after preloading its bundled BLAS/LAPACK.
use crate::model::limits::{check_range, show_number, FE_DT, MAX_PGA_G, MAX_TIME_S, TIME_SCALE};
use crate::model::{
    strip_properties, ElementKind, Formulation, Integration, Model, SectionKind, ShellLayer,
};
use crate::motion::MotionError;
use crate::motion::{read_record, Format, GroundMotion};

/// A script that cannot be written: options out of range, a record that cannot be read or
/// scaled, an element the exporter cannot express.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ExportError {
    /// An option outside its physical range (`--dt`, `--time-scale`, …).
    #[error(transparent)]
    Range(#[from] crate::model::limits::RangeError),
    /// A count over its resource bound (`docs/reliability.md`).
    #[error(transparent)]
    Limit(#[from] crate::model::limits::LimitError),
    /// A ground-motion record that cannot be read.
    #[error(transparent)]
    Motion(#[from] MotionError),
    /// A record that cannot be scaled as asked.
    #[error("ground-motion file {}: {error}", path.display())]
    Record {
        /// The record file.
        path: std::path::PathBuf,
        /// What is wrong.
        error: MotionError,
    },
    /// Ground-motion options that do not fit together.
    #[error("{0}")]
    Options(String),
    /// An element the script cannot express.
    #[error("element {element}: {message}")]
    Element {
        /// Element tag.
        element: u32,
        /// What is wrong.
        message: String,
    },
    /// A record file whose path cannot be resolved.
    #[error("ground-motion file {}: {error}", path.display())]
    Io {
        /// The record file.
        path: std::path::PathBuf,
        /// The operating system's error.
        error: std::io::Error,
    },
    /// Formatting the script failed.
    #[error(transparent)]
    Write(#[from] std::fmt::Error),
}

/// What writing the script returns.
type Result<T> = std::result::Result<T, ExportError>;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::PathBuf;

/// Element variant of the export: the FE stage's own [`Variant`]. Force-based exports use
/// Lobatto and displacement-based Legendre integration unless the element names a rule;
/// elastic exports use each section's initial stiffnesses (EA, EIy, EIz, GJ).
pub use crate::fe::build::Variant;

/// One ground-motion component: direction 1 = X, 2 = Y, 3 = Z; AT2 file; target PGA (g).
#[derive(Debug, Clone, PartialEq)]
pub struct GroundMotionInput {
    /// OpenSees DOF direction (1, 2, 3).
    pub direction: u8,
    /// Record file (PEER AT2, values in g).
    pub path: PathBuf,
    /// Target peak ground acceleration (g); `None` = as recorded.
    pub pga_g: Option<f64>,
}

/// Options of the OpenSees export.
#[derive(Debug, Clone, PartialEq)]
pub struct OpenSeesOptions {
    /// Ground-motion components.
    pub ground_motions: Vec<GroundMotionInput>,
    /// Time-scale factor applied to the record time step (similitude).
    pub time_scale: f64,
    /// Analysis time step (s).
    pub dt: f64,
    /// Analysis duration (s); default the shortest record.
    pub duration: Option<f64>,
    /// Element variant ([`Variant::AsModel`]: as each element says).
    pub variant: Variant,
    /// Stop when a free node's uz < −stop_uz (m); default 1 m × model scale.
    pub stop_uz: Option<f64>,
}

impl Default for OpenSeesOptions {
    fn default() -> Self {
        OpenSeesOptions {
            ground_motions: Vec::new(),
            time_scale: 1.0,
            dt: 0.005,
            duration: None,
            variant: Variant::AsModel,
            stop_uz: None,
        }
    }
}

const PRELOAD: &str = r#"
def _preload():
    """openseespylinux 3.7.1 ships libblas/liblapack/libgfortran in openseespylinux/lib
    but its opensees.so has no RPATH there; load them globally before the import."""
    spec = importlib.util.find_spec("openseespylinux")
    if spec is None or spec.origin is None:
        return
    libdir = os.path.join(os.path.dirname(spec.origin), "lib")
    for name in ("libquadmath.so.0", "libgfortran.so.4", "libgomp.so.1",
                 "libblas.so.3", "liblapack.so.3"):
        path = os.path.join(libdir, name)
        if os.path.exists(path):
            ctypes.CDLL(path, mode=ctypes.RTLD_GLOBAL)


_preload()
try:
    import openseespy.opensees as ops  # noqa: E402
except ImportError as err:
    raise SystemExit(f"openseespy is not installed or does not load ({err}); "
                     "pip install openseespy==3.7.1.2") from err
"#;

const TEMPLATE: &str = include_str!("opensees_template.py");

/// Python float literal that round-trips.
fn f(x: f64) -> String {
    format!("{x:?}")
}

/// Python string literal.
fn s(x: &str) -> String {
    serde_json::to_string(x).unwrap_or_else(|_| "\"\"".into())
}

/// Writes the openseespy script for `model`. `source` names the model file in comments.
pub fn opensees_script(model: &Model, source: &str, opts: &OpenSeesOptions) -> Result<String> {
    // The same ranges as `fem2rbd fe` and a scenario (crate::model::limits).
    check_range("--dt", opts.dt, FE_DT.0, false, FE_DT.1, "s")?;
    check_range(
        "--time-scale",
        opts.time_scale,
        TIME_SCALE.0,
        false,
        TIME_SCALE.1,
        "",
    )?;
    if let Some(d) = opts.duration {
        check_range("--duration", d, 0.0, true, MAX_TIME_S, "s")?;
    }
    if let Some(z) = opts.stop_uz {
        check_range("--stop-uz", z, 0.0, true, 100.0, "m")?;
    }
    // Every record is read and checked as `fe` reads it (AT2 only: the script reads
    // AT2), scaled to its PGA (an all-zero record cannot be) and time-scaled, and the
    // analysis length bounded, before the script is written.
    let mut gm_check = GroundMotion::default();
    for gm in &opts.ground_motions {
        if !(1..=3).contains(&gm.direction) {
            return Err(ExportError::Options(format!(
                "ground-motion direction {} must be 1, 2 or 3",
                gm.direction
            )));
        }
        let axis = usize::from(gm.direction - 1);
        if gm_check.components[axis].is_some() {
            return Err(ExportError::Options(format!(
                "--gm: direction {} given twice",
                ["X", "Y", "Z"][axis]
            )));
        }
        let mut rec = read_record(&gm.path, Format::At2)?.pop().ok_or_else(|| {
            ExportError::Options(format!("{}: no record read", gm.path.display()))
        })?;
        if let Some(g) = gm.pga_g {
            let in_file = |error: MotionError| ExportError::Record {
                path: gm.path.clone(),
                error,
            };
            check_range("pga", g, 0.0, true, MAX_PGA_G, "g").map_err(|e| in_file(e.into()))?;
            rec.scale_to_pga(g).map_err(in_file)?;
        }
        rec.time_scale(opts.time_scale)?;
        gm_check.components[axis] = Some(rec);
    }
    if !opts.ground_motions.is_empty() {
        let t_end = opts.duration.unwrap_or_else(|| gm_check.duration_s());
        if t_end.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return Err(ExportError::Options(
                "--gm: the ground motion lasts 0 s (a record needs at least two samples)".into(),
            ));
        }
        crate::model::limits::grid_count(
            format!(
                "analysis of {} s with --dt {} s",
                show_number(t_end),
                show_number(opts.dt)
            ),
            "time steps",
            t_end,
            opts.dt,
            crate::model::limits::MAX_FE_STEPS,
        )?;
    }
    let mats = model.material_map();
    let secs = model.section_map();
    let fix = model.fixity();
    let mut o = String::new();
    let w = &mut o;
    writeln!(w, "#!/usr/bin/env python3")?;
    writeln!(
        w,
        "\"\"\"openseespy model {} written by `fem2rbd export opensees` from {}.\n",
        s(&model.name),
        s(source)
    )?;
    writeln!(w, "Usage:\n  python3 {{this file}} eigen [N]     periods and mode shares (JSON on the last line)\n  python3 {{this file}} gravity       gravity analysis; free-node displacements as JSON\n  python3 {{this file}} th [out.csv]  gravity + time history; node displacements to CSV\n  python3 {{this file}} print-json [out.json]  the model as OpenSees' printModel -JSON writes it\nUnits: SI (m, kg, s, N, Pa).\n\"\"\"")?;
    writeln!(w, "import ctypes\nimport importlib.util\nimport json\nimport math\nimport os\nimport re\nimport sys")?;
    w.push_str(PRELOAD);
    let variant_name = match opts.variant {
        Variant::AsModel => "as-model",
        Variant::Force => "force",
        Variant::Disp => "disp",
        Variant::Elastic => "elastic",
    };
    writeln!(w, "\nVARIANT = {}", s(variant_name))?;
    writeln!(w, "G = {}  # m/s^2", f(model.gravity.g))?;
    writeln!(w, "GRAVITY_STEPS = {}", model.gravity.load_steps)?;
    match model.rayleigh() {
        Some((a0, a1)) => writeln!(
            w,
            "RAYLEIGH = ({}, {})  # C = a0 M + a1 K_initial (1/s, s)",
            f(a0),
            f(a1)
        )?,
        None => writeln!(w, "RAYLEIGH = None")?,
    }
    writeln!(w, "DT = {}  # s", f(opts.dt))?;
    writeln!(w, "TIME_SCALE = {}", f(opts.time_scale))?;
    match opts.duration {
        Some(d) => writeln!(w, "DURATION = {}  # s", f(d))?,
        None => writeln!(w, "DURATION = None  # the shortest record")?,
    }
    let stop = opts.stop_uz.unwrap_or(model.scale);
    writeln!(
        w,
        "STOP_UZ = {}  # m; stop when a free node sinks below -STOP_UZ",
        f(stop)
    )?;
    writeln!(
        w,
        "GROUND_MOTIONS = [  # (direction 1=X 2=Y 3=Z, AT2 file, target PGA in g or None)"
    )?;
    for gm in &opts.ground_motions {
        if !(1..=3).contains(&gm.direction) {
            return Err(ExportError::Options(format!(
                "ground-motion direction {} must be 1, 2 or 3",
                gm.direction
            )));
        }
        let p = std::fs::canonicalize(&gm.path).map_err(|error| ExportError::Io {
            path: gm.path.clone(),
            error,
        })?;
        writeln!(
            w,
            "    ({}, {}, {}),",
            gm.direction,
            s(&p.display().to_string()),
            gm.pga_g.map_or_else(|| "None".to_string(), f)
        )?;
    }
    writeln!(w, "]")?;

    // node data for mode shares and recorders
    let lumped = model.lumped_masses();
    let massed: BTreeMap<u32, [f64; 6]> = lumped
        .into_iter()
        .filter(|(t, m)| fix.get(t) != Some(&[1; 6]) && m.iter().any(|v| *v != 0.0))
        .collect();
    writeln!(w, "NODE_XYZ = {{")?;
    for n in &model.nodes {
        writeln!(w, "    {}: ({}, {}, {}),", n.tag, f(n.x), f(n.y), f(n.z))?;
    }
    writeln!(w, "}}")?;
    writeln!(
        w,
        "FREE_NODES = [{}]",
        model
            .nodes
            .iter()
            .filter(|n| fix.get(&n.tag) != Some(&[1; 6]))
            .map(|n| n.tag.to_string())
            .collect::<Vec<_>>()
            .join(", ")
    )?;
    writeln!(
        w,
        "SUPPORT_NODES = [{}]  # nodes with at least one fixed DOF (reactions)",
        fix.keys()
            .map(|t| t.to_string())
            .collect::<Vec<_>>()
            .join(", ")
    )?;
    writeln!(
        w,
        "MASSES = {{  # lumped: nodal masses + element self-weight (kg, kg m^2); fully fixed nodes left out"
    )?;
    for (t, m) in &massed {
        let v: Vec<String> = m.iter().map(|x| f(*x)).collect();
        writeln!(w, "    {t}: ({}),", v.join(", "))?;
    }
    writeln!(w, "}}")?;
    writeln!(w, "GRAVITY_LOADS = [  # (node, Fz = -m g in N)")?;
    for (t, fz) in model.gravity_loads() {
        writeln!(w, "    ({t}, {}),", f(fz))?;
    }
    writeln!(w, "]")?;

    // ---------------------------------------------------------------- build()
    writeln!(
        w,
        "\n\ndef build():\n    \"\"\"Creates the model in OpenSees.\"\"\""
    )?;
    writeln!(
        w,
        "    ops.wipe()\n    ops.model(\"basic\", \"-ndm\", 3, \"-ndf\", 6)"
    )?;
    for n in &model.nodes {
        writeln!(
            w,
            "    ops.node({}, {}, {}, {})",
            n.tag,
            f(n.x),
            f(n.y),
            f(n.z)
        )?;
    }
    for sp in &model.supports {
        let d: Vec<String> = sp.dofs.iter().map(|x| x.to_string()).collect();
        writeln!(w, "    ops.fix({}, {})", sp.node, d.join(", "))?;
    }
    writeln!(
        w,
        "    for tag, m in MASSES.items():\n        ops.mass(tag, *m)"
    )?;
    for t in &model.transformations {
        writeln!(
            w,
            "    ops.geomTransf({}, {}, {}, {}, {})",
            s(t.kind.opensees_name()),
            t.tag,
            f(t.vecxz[0]),
            f(t.vecxz[1]),
            f(t.vecxz[2])
        )?;
    }
    let elastic_all = opts.variant == Variant::Elastic;
    // materials and sections used by nonlinear beam-columns and shells
    let mut used_secs = std::collections::BTreeSet::new();
    for e in &model.elements {
        match &e.kind {
            ElementKind::BeamColumn { section, .. } if !elastic_all => {
                used_secs.insert(*section);
            }
            ElementKind::Shell { section, .. } => {
                used_secs.insert(*section);
            }
            _ => {}
        }
    }
    let mut used_mats = std::collections::BTreeSet::new();
    for st in &used_secs {
        used_mats.extend(secs[st].material_refs());
    }
    for mt in &model.materials {
        if !used_mats.contains(&mt.tag) {
            continue;
        }
        let params: Vec<String> = mt
            .parameters()
            .into_iter()
            .filter(|(n, _)| *n != "density")
            .map(|(_, v)| f(v))
            .collect();
        writeln!(
            w,
            "    ops.uniaxialMaterial({}, {}, {})",
            s(mt.type_name()),
            mt.tag,
            params.join(", ")
        )?;
    }
    let mut nd_tag = 1u32;
    for st in &used_secs {
        let sec = secs[st];
        match &sec.kind {
            SectionKind::Fiber { .. } | SectionKind::RcRect(_) => {
                writeln!(
                    w,
                    "    ops.section(\"Fiber\", {}, \"-GJ\", {})",
                    sec.tag,
                    f(sec.gj().unwrap_or(0.0))
                )?;
                for fb in sec.fibers().unwrap_or_default() {
                    writeln!(
                        w,
                        "    ops.fiber({}, {}, {}, {})",
                        f(fb.y()),
                        f(fb.z()),
                        f(fb.area()),
                        fb.material()
                    )?;
                }
            }
            SectionKind::Elastic {
                e, g, a, iy, iz, j, ..
            } => writeln!(
                w,
                "    ops.section(\"Elastic\", {}, {}, {}, {}, {}, {}, {})",
                sec.tag,
                f(*e),
                f(*a),
                f(*iz),
                f(*iy),
                f(*g),
                f(*j)
            )?,
            SectionKind::Plate { e, nu, h, .. } => writeln!(
                w,
                "    ops.section(\"ElasticMembranePlateSection\", {}, {}, {}, {}, 0.0)",
                sec.tag,
                f(*e),
                f(*nu),
                f(*h)
            )?,
            SectionKind::LayeredShell { layers, .. } => {
                // nDMaterial tags are their own namespace in OpenSees: numbered here in
                // section and layer order.
                let mut args = Vec::new();
                for l in layers {
                    let tag = match l {
                        ShellLayer::Elastic { e, nu, .. } => {
                            writeln!(
                                w,
                                "    ops.nDMaterial(\"ElasticIsotropic\", {nd_tag}, {}, {})",
                                f(*e),
                                f(*nu)
                            )?;
                            writeln!(
                                w,
                                "    ops.nDMaterial(\"PlateFiber\", {}, {nd_tag})",
                                nd_tag + 1
                            )?;
                            nd_tag += 2;
                            nd_tag - 1
                        }
                        ShellLayer::Concrete { e, nu, fc, ft, .. } => {
                            writeln!(
                                w,
                                "    ops.nDMaterial(\"PlasticDamageConcretePlaneStress\", {nd_tag}, {}, {}, {}, {})",
                                f(*e),
                                f(*nu),
                                f(*ft),
                                f(*fc)
                            )?;
                            writeln!(
                                w,
                                "    ops.nDMaterial(\"PlateFromPlaneStress\", {}, {nd_tag}, {})  # G = E / (2 (1 + nu))",
                                nd_tag + 1,
                                f(e / (2.0 * (1.0 + nu)))
                            )?;
                            nd_tag += 2;
                            nd_tag - 1
                        }
                        ShellLayer::Rebar {
                            material, angle, ..
                        } => {
                            writeln!(
                                w,
                                "    ops.nDMaterial(\"PlateRebar\", {nd_tag}, {material}, {})",
                                f(*angle)
                            )?;
                            nd_tag += 1;
                            nd_tag - 1
                        }
                    };
                    args.push(format!("{tag}, {}", f(l.thickness())));
                }
                writeln!(
                    w,
                    "    ops.section(\"LayeredShell\", {}, {}, {})  # layers bottom to top: nDMaterial, thickness (m)",
                    sec.tag,
                    layers.len(),
                    args.join(", ")
                )?;
            }
        }
    }
    // beam integrations: one tag per (section, rule, points)
    let mut integ: BTreeMap<(u32, &'static str, u32), u32> = BTreeMap::new();
    for e in &model.elements {
        let ElementKind::BeamColumn {
            nodes,
            section,
            transf,
            formulation,
            points,
            integration,
        } = &e.kind
        else {
            continue;
        };
        let (i, j) = (nodes[0], nodes[1]);
        if elastic_all {
            let q = secs[section].elastic_equivalent(&mats);
            writeln!(
                w,
                "    ops.element(\"elasticBeamColumn\", {}, {i}, {j}, {}, 1.0, 1.0, {}, {}, {}, {transf})  # E = G = 1: A, J, Iy, Iz carry EA, GJ, EIy, EIz",
                e.tag,
                f(q.ea),
                f(q.gj),
                f(q.eiy),
                f(q.eiz)
            )?;
            continue;
        }
        let form = match opts.variant {
            Variant::Force => Formulation::Force,
            Variant::Disp => Formulation::Disp,
            _ => *formulation,
        };
        let rule = match (integration, form) {
            (Some(Integration::Lobatto), _) | (None, Formulation::Force) => "Lobatto",
            (Some(Integration::Legendre), _) | (None, Formulation::Disp) => "Legendre",
        };
        let next = integ.len() as u32 + 1;
        let itag = *integ.entry((*section, rule, *points)).or_insert_with(|| {
            writeln!(
                w,
                "    ops.beamIntegration({}, {next}, {section}, {points})",
                s(rule)
            )
            .ok();
            next
        });
        match form {
            Formulation::Force => writeln!(
                w,
                "    ops.element(\"forceBeamColumn\", {}, {i}, {j}, {transf}, {itag}, \"-iter\", 50, 1e-12)",
                e.tag
            )?,
            Formulation::Disp => writeln!(
                w,
                "    ops.element(\"dispBeamColumn\", {}, {i}, {j}, {transf}, {itag})",
                e.tag
            )?,
        }
    }
    let xyz: BTreeMap<u32, [f64; 3]> = model.nodes.iter().map(|n| (n.tag, n.xyz())).collect();
    for e in &model.elements {
        match &e.kind {
            ElementKind::ElasticBeamColumn {
                nodes,
                section,
                transf,
            } => {
                let SectionKind::Elastic {
                    e: em,
                    g,
                    a,
                    iy,
                    iz,
                    j,
                    ..
                } = &secs[section].kind
                else {
                    return Err(ExportError::Element {
                        element: e.tag,
                        message: format!("section {section} is not elastic"),
                    });
                };
                writeln!(
                    w,
                    "    ops.element(\"elasticBeamColumn\", {}, {}, {}, {}, {}, {}, {}, {}, {}, {transf})",
                    e.tag,
                    nodes[0],
                    nodes[1],
                    f(*a),
                    f(*em),
                    f(*g),
                    f(*j),
                    f(*iy),
                    f(*iz)
                )?;
            }
            ElementKind::ElasticStrip {
                nodes,
                transf,
                e: em,
                g,
                width,
                thickness,
                ..
            } => {
                let (a, iy, iz, j) = strip_properties(*width, *thickness);
                writeln!(
                    w,
                    "    ops.element(\"elasticBeamColumn\", {}, {}, {}, {}, {}, {}, {}, {}, {}, {transf})  # strip {} x {} m",
                    e.tag,
                    nodes[0],
                    nodes[1],
                    f(a),
                    f(*em),
                    f(*g),
                    f(j),
                    f(iy),
                    f(iz),
                    f(*width),
                    f(*thickness)
                )?;
            }
            ElementKind::Shell {
                nodes,
                section,
                local_x,
                corotational,
            } => {
                if matches!(secs[section].kind, SectionKind::LayeredShell { .. }) || *corotational {
                    // ASDShellQ4 with an explicit local x: without `-local`, OpenSees 3.7.1
                    // swaps the 0° and 90° PlateRebar layers.
                    let v = match local_x {
                        Some(v) => *v,
                        None => {
                            let (Some(a), Some(b)) = (xyz.get(&nodes[0]), xyz.get(&nodes[1]))
                            else {
                                return Err(ExportError::Element {
                                    element: e.tag,
                                    message: "unknown node".into(),
                                });
                            };
                            [b[0] - a[0], b[1] - a[1], b[2] - a[2]]
                        }
                    };
                    writeln!(
                        w,
                        "    ops.element(\"ASDShellQ4\", {}, {}, {}, {}, {}, {section}{}, \"-local\", {}, {}, {})",
                        e.tag,
                        nodes[0],
                        nodes[1],
                        nodes[2],
                        nodes[3],
                        if *corotational { ", \"-corotational\"" } else { "" },
                        f(v[0]),
                        f(v[1]),
                        f(v[2])
                    )?;
                } else {
                    writeln!(
                        w,
                        "    ops.element(\"ShellMITC4\", {}, {}, {}, {}, {}, {section})",
                        e.tag, nodes[0], nodes[1], nodes[2], nodes[3]
                    )?;
                }
            }
            ElementKind::BeamColumn { .. } | ElementKind::Panel { .. } => {} // panels: no FE
        }
    }
    o.push_str(TEMPLATE);
    Ok(o)
}

//! Importer for the reference JSON layout of `data/frame3-standin/reference-frame3.json`
//! (written by `gen_frame3.py`; layout described in that folder's README).
//!
//! Mapping: `uniaxial_materials` → materials (density 0: the JSON lumps all mass into
//! `nodal_masses`); `sections` (type Fiber) → fiber sections; `fixed_nodes` → supports;
//! `geom_transforms` → transformations; `beam_column` elements → force-based beam-columns
//! (5 Lobatto points, as the reference runs); `elastic_beam_column` elements → elastic
//! beam-columns with one elastic section per distinct property set (tags after the
//! largest fiber-section tag); `nodal_masses` → nodal masses; `damping` a0/a1 → explicit
//! Rayleigh coefficients. Element `group` column/beam/slab_strip becomes type name
//! Column/Beam/Slab and the `story`/`floor` number the material group. `scale` is read
//! from a top-level `scale` key if present, else 1.
use super::section::ImportedElasticSections;
use super::*;
use serde_json::Value;

/// What an import step says when it fails (the caller adds the file).
type Result<T> = std::result::Result<T, InvalidValue>;

/// Turns a missing value (`Option`) or a failed step into a message naming the item.
trait Say<T> {
    fn say(self, what: impl FnOnce() -> String) -> Result<T>;
}

impl<T> Say<T> for Option<T> {
    fn say(self, what: impl FnOnce() -> String) -> Result<T> {
        self.ok_or_else(|| InvalidValue(what()))
    }
}

impl<T> Say<T> for Result<T> {
    fn say(self, what: impl FnOnce() -> String) -> Result<T> {
        self.map_err(|e| InvalidValue(format!("{}: {e}", what())))
    }
}

macro_rules! bail {
    ($($t:tt)*) => {
        return Err(InvalidValue(format!($($t)*)))
    };
}
fn num(v: &Value, key: &str, what: &str) -> Result<f64> {
    v.get(key)
        .and_then(Value::as_f64)
        .say(|| format!("{what}: missing number `{key}`"))
}

fn tag(v: &Value, key: &str, what: &str) -> Result<u32> {
    v.get(key)
        .and_then(Value::as_u64)
        .and_then(|t| u32::try_from(t).ok())
        .say(|| format!("{what}: missing tag `{key}`"))
}

fn arr<'a>(v: &'a Value, key: &str) -> Result<&'a Vec<Value>> {
    v.get(key)
        .and_then(Value::as_array)
        .say(|| format!("missing array `{key}`"))
}

/// Whether JSON text is in the reference layout (a root object with `uniaxial_materials`).
pub(crate) fn is_reference_layout(text: &str) -> bool {
    serde_json::from_str::<Value>(text)
        .ok()
        .is_some_and(|v| v.get("uniaxial_materials").is_some())
}

/// The JSON document of the input file `path` (`what` names it in the bounds' message),
/// with the file's name for the messages: a syntax error names the line.
pub(crate) fn read_json_file(
    path: &Path,
    what: &'static str,
) -> std::result::Result<(String, Value), ModelError> {
    let text = limits::read_input_file(path, what)?;
    let file = path.display().to_string();
    let v = serde_json::from_str(&text).map_err(|e| ModelError::Syntax {
        at: Location {
            file: file.clone(),
            line: Some(e.line()),
            item: None,
        },
        message: format!("not valid JSON: {e}"),
    })?;
    Ok((file, v))
}

/// An import error of the whole file `file`.
pub(crate) fn import_error(file: &str, message: String) -> ModelError {
    ModelError::Import {
        at: Location {
            file: file.to_string(),
            line: None,
            item: None,
        },
        message,
    }
}

/// Reads a reference-layout JSON file into a validated [`Model`].
pub fn import_reference_json(path: impl AsRef<Path>) -> std::result::Result<Model, ModelError> {
    let (file, v) = read_json_file(path.as_ref(), "model file")?;
    let model = from_value(&v)
        .map_err(|e| import_error(&file, format!("cannot import reference model: {e}")))?;
    model.validate().map_err(|e| e.in_file(file.clone()))?;
    Ok(model)
}

/// Top-level keys the importer reads into the model.
const READ_KEYS: &[&str] = &[
    "uniaxial_materials",
    "sections",
    "nodes",
    "fixed_nodes",
    "geom_transforms",
    "elements",
    "nodal_masses",
    "damping",
    "name",
    "description",
    "scale",
    "gravity",
];

/// Top-level keys the importer checks against the imported model (and refuses when they
/// disagree): `ndm` = 3, `ndf` = 6, SI `units`, `total_mass_kg` and the nodal
/// `gravity_loads` equal to those of the imported masses.
const CHECKED_KEYS: &[&str] = &["ndm", "ndf", "units", "total_mass_kg", "gravity_loads"];

/// Top-level keys that describe how the reference model was made or run, not the model:
/// the generator's `parameters`, the reference run's `analysis` settings and its
/// `ground_motion` (a scenario or the command line gives these to fem2rbd,
/// docs/model-format.md).
const DESCRIPTIVE_KEYS: &[&str] = &["parameters", "analysis", "ground_motion"];

/// Refuses any top-level key the importer would otherwise leave unread: shells, ties,
/// loads or any other content it does not import is named, never dropped.
fn check_keys(v: &Value) -> Result<()> {
    let Some(obj) = v.as_object() else {
        bail!("the file is not a JSON object");
    };
    let unknown: Vec<String> = obj
        .iter()
        .filter(|(k, _)| {
            let k = k.as_str();
            !READ_KEYS.contains(&k) && !CHECKED_KEYS.contains(&k) && !DESCRIPTIVE_KEYS.contains(&k)
        })
        .map(|(k, val)| match val.as_array() {
            Some(a) => format!("`{k}` ({} items)", a.len()),
            None => format!("`{k}`"),
        })
        .collect();
    if !unknown.is_empty() {
        bail!(
            "{} not imported: the reference-JSON importer reads frames of fibre and elastic \
             beam-columns ({}); write shells, ties and loads in a TOML model \
             (docs/model-format.md)",
            unknown.join(", "),
            READ_KEYS.join(", ")
        );
    }
    Ok(())
}

/// Checks the [`CHECKED_KEYS`] present in `v` against the imported `model`.
fn check_against(v: &Value, model: &Model) -> Result<()> {
    for (key, want) in [("ndm", 3), ("ndf", 6)] {
        if let Some(x) = v.get(key) {
            if x.as_u64() != Some(want) {
                bail!(
                    "`{key}` = {x}: fem2rbd models are 3-D with 6 DOFs per node ({key} = {want})"
                );
            }
        }
    }
    if let Some(units) = v.get("units") {
        let si = [
            ("length", "m"),
            ("mass", "kg"),
            ("time", "s"),
            ("force", "N"),
            ("stress", "Pa"),
        ];
        let obj = units
            .as_object()
            .say(|| "`units` is not an object".into())?;
        for (k, val) in obj {
            let want = si.iter().find(|(q, _)| q == k).map(|(_, u)| *u);
            match (want, val.as_str()) {
                (Some(u), Some(got)) if got == u => {}
                (Some(u), _) => bail!("`units.{k}` = {val}: the model is read in SI ({k} in {u})"),
                (None, _) => {
                    bail!("`units.{k}`: unknown quantity (length, mass, time, force, stress)")
                }
            }
        }
    }
    let masses = model.lumped_masses();
    if let Some(total) = v.get("total_mass_kg") {
        let total = total
            .as_f64()
            .say(|| "`total_mass_kg` is not a number".into())?;
        let fixity = model.fixity();
        let ours: f64 = masses
            .iter()
            .filter(|(t, _)| fixity.get(t) != Some(&[1; 6]))
            .map(|(_, m)| m[2])
            .sum();
        if (ours - total).abs() > 1e-9 * total.abs().max(1.0) {
            bail!(
                "`total_mass_kg` = {total} kg, but the imported nodal masses and element \
                 self-weight of the nodes that are not fully fixed add up to {ours} kg"
            );
        }
    }
    if let Some(g) = v.get("gravity_loads") {
        let loads = g
            .get("loads")
            .and_then(Value::as_array)
            .say(|| "`gravity_loads` has no array `loads`".into())?;
        let ours: std::collections::BTreeMap<u32, f64> =
            model.gravity_loads().into_iter().collect();
        if loads.len() != ours.len() {
            bail!(
                "`gravity_loads` has {} loads, the imported masses give {} (Fz = -m g at every \
                 massed node that is not fully fixed)",
                loads.len(),
                ours.len()
            );
        }
        for l in loads {
            let t = tag(l, "tag", "gravity load")?;
            let fz = num(l, "Fz", &format!("gravity load at node {t}"))?;
            let mine = ours
                .get(&t)
                .say(|| format!("`gravity_loads`: node {t} has no mass in the imported model"))?;
            if (mine - fz).abs() > 1e-9 * fz.abs().max(1.0) {
                bail!("`gravity_loads`: node {t} Fz = {fz} N, the imported masses give {mine} N");
            }
        }
    }
    Ok(())
}

fn from_value(v: &Value) -> Result<Model> {
    check_keys(v)?;
    let model = build_model(v)?;
    check_against(v, &model)?;
    Ok(model)
}

fn build_model(v: &Value) -> Result<Model> {
    let mut materials = Vec::new();
    for m in arr(v, "uniaxial_materials")? {
        let t = tag(m, "tag", "material")?;
        let what = format!("material {t}");
        let ty = m.get("type").and_then(Value::as_str).unwrap_or("");
        let law = match ty {
            "Concrete02" => MaterialLaw::Concrete02 {
                fpc: num(m, "fpc", &what)?,
                epsc0: num(m, "epsc0", &what)?,
                fpcu: num(m, "fpcu", &what)?,
                epscu: num(m, "epscu", &what)?,
                lambda: num(m, "lambda", &what)?,
                ft: num(m, "ft", &what)?,
                ets: num(m, "Ets", &what)?,
            },
            "Concrete01" => MaterialLaw::Concrete01 {
                fpc: num(m, "fpc", &what)?,
                epsc0: num(m, "epsc0", &what)?,
                fpcu: num(m, "fpcu", &what)?,
                epscu: num(m, "epscU", &what)?,
            },
            "Steel02" => MaterialLaw::Steel02 {
                fy: num(m, "Fy", &what)?,
                e0: num(m, "E0", &what)?,
                b: num(m, "b", &what)?,
                r0: num(m, "R0", &what)?,
                cr1: num(m, "cR1", &what)?,
                cr2: num(m, "cR2", &what)?,
                a: None,
            },
            "Steel01" => MaterialLaw::Steel01 {
                fy: num(m, "Fy", &what)?,
                e0: num(m, "E0", &what)?,
                b: num(m, "b", &what)?,
            },
            "Elastic" => MaterialLaw::Elastic {
                e: num(m, "E", &what)?,
                eta: 0.0,
                e_neg: None,
            },
            other => bail!("{what}: unsupported type {other:?}"),
        };
        materials.push(Material {
            tag: t,
            name: m
                .get("name")
                .and_then(Value::as_str)
                .unwrap_or("")
                .to_string(),
            density: 0.0,
            law,
        });
    }

    let mut sections = Vec::new();
    for s in arr(v, "sections")? {
        let t = tag(s, "tag", "section")?;
        let what = format!("section {t}");
        if let Some(ty) = s.get("type").and_then(Value::as_str) {
            if ty != "Fiber" {
                bail!(
                    "{what}: type {ty:?} is not imported (the reference-JSON importer reads \
                     fibre sections; write layered shells in a TOML model, docs/model-format.md)"
                );
            }
        }
        let mut fibers = Vec::new();
        for f in arr(s, "fibers").say(|| what.clone())? {
            let f = f.as_array().filter(|f| f.len() == 4);
            let f = f.say(|| format!("{what}: a fiber is not [y, z, area, mat]"))?;
            let g = |k: usize| f[k].as_f64().say(|| format!("{what}: bad fiber"));
            let mat = f[3]
                .as_u64()
                .and_then(|t| u32::try_from(t).ok())
                .say(|| format!("{what}: bad fiber material"))?;
            fibers.push(Fiber(g(0)?, g(1)?, g(2)?, mat));
        }
        sections.push(Section {
            tag: t,
            name: s
                .get("name")
                .and_then(Value::as_str)
                .unwrap_or("")
                .to_string(),
            kind: SectionKind::Fiber {
                gj: num(s, "GJ", &what)?,
                fibers,
                width: None,
                depth: None,
            },
        });
    }

    let mut nodes = Vec::new();
    for n in arr(v, "nodes")? {
        let t = tag(n, "tag", "node")?;
        let what = format!("node {t}");
        nodes.push(Node {
            tag: t,
            x: num(n, "x", &what)?,
            y: num(n, "y", &what)?,
            z: num(n, "z", &what)?,
        });
    }

    let mut supports = Vec::new();
    for f in arr(v, "fixed_nodes")? {
        let t = tag(f, "tag", "fixed node")?;
        let d = arr(f, "dofs")?;
        if d.len() != 6 {
            bail!("fixed node {t}: dofs must have 6 entries");
        }
        let mut dofs = [0u8; 6];
        for (k, x) in d.iter().enumerate() {
            dofs[k] = x.as_u64().unwrap_or(2).min(2) as u8;
        }
        supports.push(Support { node: t, dofs });
    }

    let mut transformations = Vec::new();
    for g in arr(v, "geom_transforms")? {
        let t = tag(g, "tag", "transformation")?;
        let kind = match g.get("type").and_then(Value::as_str).unwrap_or("") {
            "Linear" => TransfKind::Linear,
            "PDelta" => TransfKind::Pdelta,
            "Corotational" => TransfKind::Corotational,
            other => bail!("transformation {t}: unknown type {other:?}"),
        };
        let vx = arr(g, "vecxz")?;
        if vx.len() != 3 {
            bail!("transformation {t}: vecxz must have 3 entries");
        }
        let c = |k: usize| vx[k].as_f64().say(|| "vecxz entry is not a number".into());
        transformations.push(Transformation {
            tag: t,
            kind,
            vecxz: [c(0)?, c(1)?, c(2)?],
        });
    }

    let mut elements = Vec::new();
    let mut elastic =
        ImportedElasticSections::new(sections.iter().map(|s| s.tag).max().unwrap_or(0) + 1);
    for e in arr(v, "elements")? {
        let t = tag(e, "tag", "element")?;
        let what = format!("element {t}");
        let en = arr(e, "nodes").say(|| what.clone())?;
        let node = |k: usize| -> Result<u32> {
            en.get(k)
                .and_then(Value::as_u64)
                .and_then(|x| u32::try_from(x).ok())
                .say(|| format!("{what}: bad node list"))
        };
        let nodes2 = [node(0)?, node(1)?];
        let type_name = match e.get("group").and_then(Value::as_str).unwrap_or("") {
            "column" => "Column",
            "beam" => "Beam",
            "slab_strip" => "Slab",
            other if !other.is_empty() => other,
            _ => "Element",
        }
        .to_string();
        let group = e
            .get("story")
            .or_else(|| e.get("floor"))
            .and_then(Value::as_u64)
            .map_or_else(|| "1".to_string(), |g| g.to_string());
        let transf = tag(e, "transf", &what)?;
        let kind = match e.get("type").and_then(Value::as_str).unwrap_or("") {
            "beam_column" => ElementKind::BeamColumn {
                nodes: nodes2,
                section: tag(e, "section", &what)?,
                transf,
                formulation: Formulation::Force,
                points: 5,
                integration: None,
            },
            "elastic_beam_column" => {
                let p = [
                    num(e, "E", &what)?,
                    num(e, "G", &what)?,
                    num(e, "A", &what)?,
                    num(e, "Iy", &what)?,
                    num(e, "Iz", &what)?,
                    num(e, "J", &what)?,
                    0.0,
                ];
                ElementKind::ElasticBeamColumn {
                    nodes: nodes2,
                    section: elastic.tag_of(p),
                    transf,
                }
            }
            other => bail!("{what}: unsupported type {other:?}"),
        };
        let rigid_body = e.get("group").and_then(Value::as_str) != Some("slab_strip");
        elements.push(Element {
            tag: t,
            rigid_body,
            type_name,
            group: Group(group),
            kind,
        });
    }
    sections.extend(elastic.into_sections());

    let mut masses = Vec::new();
    for m in arr(v, "nodal_masses")? {
        let t = tag(m, "tag", "nodal mass")?;
        let what = format!("nodal mass of node {t}");
        let (mx, my, mz) = (
            num(m, "mx", &what)?,
            num(m, "my", &what)?,
            num(m, "mz", &what)?,
        );
        if mx != my || my != mz {
            bail!("{what}: mx, my, mz differ; the model format has one translational mass");
        }
        let r = [
            num(m, "mrx", &what)?,
            num(m, "mry", &what)?,
            num(m, "mrz", &what)?,
        ];
        masses.push(NodalMass {
            node: t,
            m: mz,
            rotational: if r == [0.0; 3] { None } else { Some(r) },
        });
    }

    let damping = match v.get("damping") {
        Some(d) => Some(Damping {
            xi: None,
            periods: None,
            a0: Some(num(d, "a0_mass", "damping")?),
            a1: Some(num(d, "a1_initial_stiffness", "damping")?),
        }),
        None => None,
    };

    Ok(Model {
        name: v
            .get("name")
            .and_then(Value::as_str)
            .unwrap_or("")
            .to_string(),
        description: v
            .get("description")
            .and_then(Value::as_str)
            .unwrap_or("")
            .to_string(),
        scale: v.get("scale").and_then(Value::as_f64).unwrap_or(1.0),
        gravity: Gravity {
            g: v.get("gravity").and_then(Value::as_f64).unwrap_or(9.81),
            load_steps: 10,
        },
        damping,
        materials,
        sections,
        transformations,
        nodes,
        supports,
        elements,
        masses,
    })
}

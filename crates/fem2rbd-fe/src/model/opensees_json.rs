//! Importer for the model that OpenSees writes with `print -JSON` (openseespy
//! `printModel('-JSON', '-file', f)`): the `StructuralAnalysisModel` object that
//! `Domain::Print` writes with the flag `OPS_PRINT_PRINTMODEL_JSON` (OpenSees
//! `SRC/domain/domain/Domain.cpp`; each material, section, transformation, element and node
//! writes its own entry in its `Print` method).
//!
//! What the print holds, and so what is imported (docs/model-format.md, "OpenSees print
//! -JSON"):
//! - `uniaxialMaterials`: `Concrete01`, `Concrete02` (`ratio` is λ), `Steel01` (without
//!   isotropic hardening, a1 = a3 = 0), `Steel02` (a1…a4; σ_ini = 0), `ElasticMaterial`;
//!   density 0: OpenSees keeps no material density, the masses are the nodes' `mass`;
//! - `ndMaterials`, only as the layers of a `LayeredShellFiberSection`: `PlateFiberMaterial`
//!   of an `ElasticIsotropicMaterial` (ρ = 0), `PlateFromPlaneStressMaterial` of a
//!   `PlasticDamageConcretePlaneStress` with its default β, Ap, An, Bn and G = E/(2(1+ν)),
//!   `PlateRebarMaterial` of a uniaxial material;
//! - `sections`: `FiberSection3d` (with its `torsion` G·J), `ElasticSection3d`,
//!   `ElasticMembranePlateSection` (Em = Ep), `LayeredShellFiberSection`;
//! - `crdTransformations`: `LinearCrdTransf3d`, `PDeltaCrdTransf3d`, `CorotCrdTransf3d`
//!   without joint offsets;
//! - `nodes` (3-D, 6 DOFs) with their `mass` (mx = my = mz);
//! - `elements`: `ForceBeamColumn3d` and `DispBeamColumn3d` with one section at every
//!   point, Lobatto or Legendre, no mass per length; `ElasticBeam3d` without releases (one
//!   elastic section per distinct property set, tags after the largest section tag);
//!   `ShellMITC4` with an elastic plate section; `ASDShellQ4`.
//!
//! The print carries no supports, equalDOF ties, loads, damping or analysis: the imported
//! model has no supports unless [`Supports::FixLowest`] asks for them. An `ASDShellQ4`'s
//! `-local` axis and `-corotational` flag are not in the print either: the imported shell
//! takes the model format's default local x (from its first node to its second) and small
//! displacements. The numbers hold the six significant digits of OpenSees' output stream.
//! Elements are named by their geometry: a line element steeper than 45° is a `Column`,
//! other line elements `Beam`s, a shell in a vertical plane a `Wall`, other shells
//! `Slab`s; every element is in group 1. Anything else in the file is refused with its item
//! named.
use super::section::ImportedElasticSections;
use super::*;
use serde_json::{Map, Value};

/// What an import step says when it fails (the caller adds the file).
type Result<T> = std::result::Result<T, InvalidValue>;

macro_rules! bail {
    ($($t:tt)*) => {
        return Err(InvalidValue(format!($($t)*)))
    };
}

/// The supports the imported model gets (the print has none).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Supports {
    /// No supports: the model as printed.
    #[default]
    None,
    /// All six DOFs fixed at every node at the lowest z of the model.
    FixLowest,
}

/// Whether JSON text is an OpenSees print (a root object with `StructuralAnalysisModel`).
pub(crate) fn is_print_layout(text: &str) -> bool {
    serde_json::from_str::<Value>(text)
        .ok()
        .is_some_and(|v| v.get("StructuralAnalysisModel").is_some())
}

/// Reads an OpenSees `print -JSON` file into a validated [`Model`] with the given
/// supports.
pub fn import_opensees_json(
    path: impl AsRef<Path>,
    supports: Supports,
) -> std::result::Result<Model, ModelError> {
    let (file, v) = super::reference_json::read_json_file(path.as_ref(), "OpenSees JSON file")?;
    let mut model = from_value(&v).map_err(|e| {
        super::reference_json::import_error(&file, format!("cannot import the OpenSees model: {e}"))
    })?;
    if supports == Supports::FixLowest {
        model.supports = lowest_nodes(&model)
            .into_iter()
            .map(|node| Support { node, dofs: [1; 6] })
            .collect();
    }
    model.validate().map_err(|e| e.in_file(file.clone()))?;
    Ok(model)
}

/// What a `model` imported with `supports` has only because the print did not carry it,
/// one line each (the module docs): its supports (none, or the lowest nodes
/// [`Supports::FixLowest`] fixed), its shells' small displacements and default local x,
/// and the damping, ties, loads and analysis it lacks. `fem2rbd import opensees-json`
/// prints them.
pub fn import_notes(model: &Model, supports: Supports) -> Vec<String> {
    let mut notes = Vec::new();
    match supports {
        Supports::None => notes.push(
            "the print has no supports, so neither has the model: add [[support]] entries, \
             or import with --fix-lowest"
                .to_string(),
        ),
        Supports::FixLowest => {
            let n = lowest_nodes(model).len();
            notes.push(format!(
                "{n} node{} at the lowest z = {} m fixed in all six DOFs (--fix-lowest); the \
                 print has no supports",
                if n == 1 { "" } else { "s" },
                lowest_z(model)
            ));
        }
    }
    let shells = model
        .elements
        .iter()
        .filter(|e| matches!(e.kind, ElementKind::Shell { .. }))
        .count();
    if shells > 0 {
        notes.push(format!(
            "{shells} shell{} with small displacements and the local x from the first node to \
             the second: the print carries neither ASDShellQ4's -corotational nor -local; set \
             `corotational` and `local_x` where the OpenSees model had them",
            if shells == 1 { "" } else { "s" }
        ));
    }
    notes.push(
        "no [damping], equalDOF ties, loads or analysis (the print carries none): the model \
         has the default gravity; the scenario gives the ground motion"
            .to_string(),
    );
    notes
}

/// The lowest z of `model`'s nodes, m.
fn lowest_z(model: &Model) -> f64 {
    model
        .nodes
        .iter()
        .map(|n| n.z)
        .fold(f64::INFINITY, f64::min)
}

/// The tags of the nodes at the lowest z of `model`, in tag order.
fn lowest_nodes(model: &Model) -> Vec<u32> {
    let z0 = lowest_z(model);
    let mut tags: Vec<u32> = model
        .nodes
        .iter()
        .filter(|n| n.z == z0)
        .map(|n| n.tag)
        .collect();
    tags.sort_unstable();
    tags
}

/// One object of the print with its keys checked off as they are read: what is left
/// unread is refused ([`Entry::done`]).
struct Entry<'a> {
    what: String,
    obj: &'a Map<String, Value>,
    read: Vec<&'static str>,
}

impl<'a> Entry<'a> {
    fn new(v: &'a Value, what: impl Into<String>) -> Result<Self> {
        let what = what.into();
        let Some(obj) = v.as_object() else {
            bail!("{what} is not a JSON object");
        };
        Ok(Entry {
            what,
            obj,
            read: Vec::new(),
        })
    }

    fn get(&mut self, key: &'static str) -> Option<&'a Value> {
        self.read.push(key);
        self.obj.get(key)
    }

    fn value(&mut self, key: &'static str) -> Result<&'a Value> {
        match self.get(key) {
            Some(v) => Ok(v),
            None => bail!("{}: missing `{key}`", self.what),
        }
    }

    fn num(&mut self, key: &'static str) -> Result<f64> {
        let v = self.value(key)?;
        match v.as_f64() {
            Some(x) => Ok(x),
            None => bail!("{}: `{key}` = {v} is not a number", self.what),
        }
    }

    fn text(&mut self, key: &'static str) -> Result<&'a str> {
        let v = self.value(key)?;
        match v.as_str() {
            Some(x) => Ok(x),
            None => bail!("{}: `{key}` = {v} is not a string", self.what),
        }
    }

    /// A tag written as a number (nodes, elements) or a string (materials, sections,
    /// transformations).
    fn tag(&mut self, key: &'static str) -> Result<u32> {
        let v = self.value(key)?;
        let t = match v {
            Value::String(s) => s.parse::<u32>().ok(),
            v => v.as_u64().and_then(|t| u32::try_from(t).ok()),
        };
        match t {
            Some(t) => Ok(t),
            None => bail!("{}: `{key}` = {v} is not a tag", self.what),
        }
    }

    fn array(&mut self, key: &'static str) -> Result<&'a Vec<Value>> {
        let v = self.value(key)?;
        match v.as_array() {
            Some(a) => Ok(a),
            None => bail!("{}: `{key}` is not an array", self.what),
        }
    }

    /// An array of `n` numbers.
    fn numbers(&mut self, key: &'static str, n: usize) -> Result<Vec<f64>> {
        let a = self.array(key)?;
        let x: Option<Vec<f64>> = a.iter().map(Value::as_f64).collect();
        match x {
            Some(x) if x.len() == n => Ok(x),
            _ => bail!("{}: `{key}` is not {n} numbers", self.what),
        }
    }

    /// An array of tags (numbers or strings).
    fn tags(&mut self, key: &'static str) -> Result<Vec<u32>> {
        let what = self.what.clone();
        self.array(key)?
            .iter()
            .map(|v| {
                let t = match v {
                    Value::String(s) => s.parse::<u32>().ok(),
                    v => v.as_u64().and_then(|t| u32::try_from(t).ok()),
                };
                t.ok_or_else(|| InvalidValue(format!("{what}: `{key}` holds {v}, not a tag")))
            })
            .collect()
    }

    /// A number that must equal `want` (a setting fem2rbd does not model otherwise).
    fn expect(&mut self, key: &'static str, want: f64, why: &str) -> Result<()> {
        let x = self.num(key)?;
        if x != want {
            bail!("{}: `{key}` = {x}; {why}", self.what);
        }
        Ok(())
    }

    /// Refuses the keys not read.
    fn done(self) -> Result<()> {
        let left: Vec<String> = self
            .obj
            .keys()
            .filter(|k| !self.read.contains(&k.as_str()))
            .map(|k| format!("`{k}`"))
            .collect();
        if !left.is_empty() {
            bail!("{}: {} not imported", self.what, left.join(", "));
        }
        Ok(())
    }
}

/// Whether a value the print holds agrees with the one fem2rbd derives from other printed
/// values: within three roundings to six significant digits (2e-5, relative).
fn agrees(printed: f64, derived: f64) -> bool {
    (printed - derived).abs() <= 2e-5 * derived.abs().max(f64::MIN_POSITIVE)
}

fn from_value(v: &Value) -> Result<Model> {
    let mut root = Entry::new(v, "the file")?;
    let sam = root.value("StructuralAnalysisModel")?;
    root.done()?;
    let mut sam = Entry::new(sam, "`StructuralAnalysisModel`")?;
    let description = sam.text("description")?.to_string();
    // Who made the model (`engineer`, `BIM`): text that fem2rbd has no field for, kept in
    // the description when it says something.
    let engineer = sam.text("engineer")?;
    let bim = sam.text("BIM")?;
    check_units(sam.value("units")?)?;
    let mut props = Entry::new(sam.value("properties")?, "`properties`")?;
    let mut geom = Entry::new(sam.value("geometry")?, "`geometry`")?;
    sam.done()?;

    let materials = uniaxial_materials(props.array("uniaxialMaterials")?)?;
    let nd = nd_materials(props.array("ndMaterials")?)?;
    let (mut sections, mut nd_used) = (Vec::new(), std::collections::BTreeSet::new());
    for s in props.array("sections")? {
        sections.push(section(s, &nd, &mut nd_used)?);
    }
    if let Some(t) = nd.keys().find(|t| !nd_used.contains(*t)) {
        bail!(
            "ndMaterial {t}: used by no layered shell section (fem2rbd keeps nD materials only \
             as the layers of a shell section)"
        );
    }
    let transformations = props
        .array("crdTransformations")?
        .iter()
        .map(transformation)
        .collect::<Result<Vec<_>>>()?;
    props.done()?;

    let (mut nodes, mut masses) = (Vec::new(), Vec::new());
    for n in geom.array("nodes")? {
        let (node, mass) = node(n)?;
        nodes.push(node);
        masses.extend(mass);
    }
    let node_xyz: BTreeMap<u32, [f64; 3]> = nodes.iter().map(|n| (n.tag, n.xyz())).collect();
    let mut elastic =
        ImportedElasticSections::new(sections.iter().map(|s| s.tag).max().unwrap_or(0) + 1);
    let layered: std::collections::BTreeSet<u32> = sections
        .iter()
        .filter(|s| matches!(s.kind, SectionKind::LayeredShell { .. }))
        .map(|s| s.tag)
        .collect();
    let mut elements = Vec::new();
    for e in geom.array("elements")? {
        elements.push(element(e, &mut elastic, &node_xyz, &layered)?);
    }
    geom.done()?;
    sections.extend(elastic.into_sections());

    let mut about: Vec<String> = Vec::new();
    if !description.is_empty() {
        about.push(description);
    }
    if !engineer.is_empty() {
        about.push(format!("engineer: {engineer}"));
    }
    if !bim.is_empty() && bim != "unknown" {
        about.push(format!("BIM: {bim}"));
    }
    Ok(Model {
        name: String::new(),
        description: about.join("; "),
        scale: 1.0,
        gravity: Gravity::default(),
        damping: None,
        materials,
        sections,
        transformations,
        nodes,
        supports: Vec::new(),
        elements,
        masses,
    })
}

/// `units`: each empty (openseespy writes them so) or the SI unit fem2rbd reads.
fn check_units(v: &Value) -> Result<()> {
    let mut u = Entry::new(v, "`units`")?;
    for (key, si) in [
        ("force", "N"),
        ("length", "m"),
        ("time", "s"),
        ("temperature", ""),
    ] {
        let Some(val) = u.get(key) else { continue };
        match val.as_str() {
            Some("") => {}
            Some(x) if x == si => {}
            _ => bail!("`units.{key}` = {val}: the model is read in SI (N, m, s, no temperature)"),
        }
    }
    u.done()
}

fn uniaxial_materials(list: &[Value]) -> Result<Vec<Material>> {
    let mut out = Vec::new();
    for m in list {
        let mut e = Entry::new(m, "a uniaxial material")?;
        let tag = e.tag("name")?;
        e.what = format!("uniaxialMaterial {tag}");
        let ty = e.text("type")?;
        let law = match ty {
            "Concrete01" | "Concrete02" => {
                let (fpc, epsc0) = (e.num("fc")?, e.num("epsc")?);
                let ec = e.num("Ec")?;
                if !agrees(ec, 2.0 * fpc / epsc0) {
                    bail!(
                        "{}: `Ec` = {ec} is not 2 fc / epsc = {}",
                        e.what,
                        2.0 * fpc / epsc0
                    );
                }
                let (fpcu, epscu) = (e.num("fcu")?, e.num("epscu")?);
                if ty == "Concrete01" {
                    MaterialLaw::Concrete01 {
                        fpc,
                        epsc0,
                        fpcu,
                        epscu,
                    }
                } else {
                    MaterialLaw::Concrete02 {
                        fpc,
                        epsc0,
                        fpcu,
                        epscu,
                        lambda: e.num("ratio")?,
                        ft: e.num("ft")?,
                        ets: e.num("Ets")?,
                    }
                }
            }
            "Steel01" => {
                let law = MaterialLaw::Steel01 {
                    fy: e.num("fy")?,
                    e0: e.num("E")?,
                    b: e.num("b")?,
                };
                let why = "fem2rbd's Steel01 has no isotropic hardening (a1 = a3 = 0)";
                e.expect("a1", 0.0, why)?;
                e.expect("a3", 0.0, why)?;
                // a2 and a4 scale the hardening that a1 = a3 = 0 switches off.
                e.num("a2")?;
                e.num("a4")?;
                law
            }
            "Steel02" => {
                let a = [e.num("a1")?, e.num("a2")?, e.num("a3")?, e.num("a4")?];
                e.expect("sigini", 0.0, "fem2rbd's Steel02 has no initial stress")?;
                MaterialLaw::Steel02 {
                    fy: e.num("fy")?,
                    e0: e.num("E")?,
                    b: e.num("b")?,
                    r0: e.num("R0")?,
                    cr1: e.num("cR1")?,
                    cr2: e.num("cR2")?,
                    // OpenSees' defaults (Steel02.cpp) switch isotropic hardening off
                    a: (a != [0.0, 1.0, 0.0, 1.0]).then_some(a),
                }
            }
            "ElasticMaterial" => {
                let (epos, eneg) = (e.num("Epos")?, e.num("Eneg")?);
                MaterialLaw::Elastic {
                    e: epos,
                    eta: e.num("eta")?,
                    e_neg: (eneg != epos).then_some(eneg),
                }
            }
            other => bail!(
                "{}: type {other:?} is not imported (Concrete01, Concrete02, Steel01, Steel02, \
                 ElasticMaterial)",
                e.what
            ),
        };
        e.done()?;
        out.push(Material {
            tag,
            name: String::new(),
            density: 0.0,
            law,
        });
    }
    Ok(out)
}

/// The nD materials of the print, by tag (read into shell layers by [`section`]).
fn nd_materials(list: &[Value]) -> Result<BTreeMap<u32, &Value>> {
    let mut out = BTreeMap::new();
    for m in list {
        let mut e = Entry::new(m, "an nD material")?;
        let tag = e.tag("name")?;
        if out.insert(tag, m).is_some() {
            bail!("ndMaterial {tag}: the tag is used twice");
        }
    }
    Ok(out)
}

/// One layer of a layered shell section: `thickness` (m) of the nD material `tag`.
/// The nD materials it reads go into `used`.
fn shell_layer(
    nd: &BTreeMap<u32, &Value>,
    tag: u32,
    thickness: f64,
    used: &mut std::collections::BTreeSet<u32>,
) -> Result<ShellLayer> {
    used.insert(tag);
    let find = |t: u32, by: &str| {
        nd.get(&t)
            .copied()
            .ok_or_else(|| InvalidValue(format!("{by}: unknown ndMaterial {t}")))
    };
    let mut e = Entry::new(find(tag, "a layered section")?, format!("ndMaterial {tag}"))?;
    e.read.push("name");
    let layer = match e.text("type")? {
        "PlateFiberMaterial" => {
            let inner = e.tag("material")?;
            used.insert(inner);
            let what = format!("ndMaterial {inner} (in PlateFiberMaterial {tag})");
            let mut m = Entry::new(find(inner, &e.what)?, what)?;
            m.read.push("name");
            if m.text("type")? != "ElasticIsotropicMaterial" {
                bail!(
                    "{}: a PlateFiberMaterial is imported around an ElasticIsotropicMaterial",
                    m.what
                );
            }
            let layer = ShellLayer::Elastic {
                thickness,
                e: m.num("E")?,
                nu: m.num("nu")?,
            };
            m.expect(
                "rho",
                0.0,
                "the mass of an imported model is its nodes' `mass` (ρ = 0)",
            )?;
            m.done()?;
            layer
        }
        "PlateFromPlaneStressMaterial" => {
            let inner = e.tag("material")?;
            used.insert(inner);
            let g = e.num("G")?;
            let what = format!("ndMaterial {inner} (in PlateFromPlaneStressMaterial {tag})");
            let mut m = Entry::new(find(inner, &e.what)?, what)?;
            m.read.push("name");
            if m.text("type")? != "PlasticDamageConcretePlaneStress" {
                bail!(
                    "{}: a PlateFromPlaneStressMaterial is imported around a \
                     PlasticDamageConcretePlaneStress",
                    m.what
                );
            }
            let (em, nu) = (m.num("E")?, m.num("nu")?);
            // fem2rbd's concrete layer has OpenSees' default plasticity and damage
            // parameters (PlasticDamageConcretePlaneStress.cpp) and G = E / (2 (1 + ν)).
            let why = "fem2rbd's concrete layer has OpenSees' default Ap 0.5, An 2, Bn 0.75, β 0.6";
            m.expect("Ap", 0.5, why)?;
            m.expect("An", 2.0, why)?;
            m.expect("Bn", 0.75, why)?;
            m.expect("beta", 0.6, why)?;
            if !agrees(g, em / (2.0 * (1.0 + nu))) {
                bail!(
                    "{}: `G` = {g} is not E / (2 (1 + nu)) = {}, the transverse shear \
                     modulus of fem2rbd's concrete layer",
                    e.what,
                    em / (2.0 * (1.0 + nu))
                );
            }
            let layer = ShellLayer::Concrete {
                thickness,
                e: em,
                nu,
                fc: m.num("fc")?,
                ft: m.num("ft")?,
            };
            m.done()?;
            layer
        }
        "PlateRebarMaterial" => ShellLayer::Rebar {
            thickness,
            material: e.tag("material")?,
            angle: e.num("angle")?,
        },
        other => bail!(
            "{}: type {other:?} is not imported as a shell layer (PlateFiberMaterial, \
             PlateFromPlaneStressMaterial, PlateRebarMaterial)",
            e.what
        ),
    };
    e.done()?;
    Ok(layer)
}

fn section(
    v: &Value,
    nd: &BTreeMap<u32, &Value>,
    nd_used: &mut std::collections::BTreeSet<u32>,
) -> Result<Section> {
    let mut e = Entry::new(v, "a section")?;
    let tag = e.tag("name")?;
    e.what = format!("section {tag}");
    let kind = match e.text("type")? {
        "FiberSection3d" => {
            if !e.obj.contains_key("torsion") {
                bail!(
                    "{}: no `torsion`; fem2rbd's fibre sections have an elastic G·J",
                    e.what
                );
            }
            let gj = e.num("torsion")?;
            let mut fibers = Vec::new();
            for f in e.array("fibers")? {
                let mut fe = Entry::new(f, format!("a fibre of section {tag}"))?;
                let c = fe.numbers("coord", 2)?;
                let area = fe.num("area")?;
                let mat = fe.tag("material")?;
                fe.done()?;
                fibers.push(Fiber(c[0], c[1], area, mat));
            }
            SectionKind::Fiber {
                gj,
                fibers,
                width: None,
                depth: None,
            }
        }
        "ElasticSection3d" => SectionKind::Elastic {
            e: e.num("E")?,
            g: e.num("G")?,
            a: e.num("A")?,
            iy: e.num("Iy")?,
            iz: e.num("Iz")?,
            j: e.num("Jx")?,
            mass_per_length: 0.0,
            width: None,
            depth: None,
        },
        "ElasticMembranePlateSection" => {
            let (em, ep) = (e.num("Em")?, e.num("Ep")?);
            if em != ep {
                bail!(
                    "{}: `Em` = {em} and `Ep` = {ep} differ; fem2rbd's plate has one modulus",
                    e.what
                );
            }
            SectionKind::Plate {
                e: em,
                nu: e.num("nu")?,
                h: e.num("thickness")?,
                density: e.num("masspervolume")?,
            }
        }
        "LayeredShellFiberSection" => {
            let total = e.num("totalThickness")?;
            let mut layers = Vec::new();
            for (k, l) in e.array("fibers")?.iter().enumerate() {
                let mut le = Entry::new(l, format!("layer {} of section {tag}", k + 1))?;
                let n = le.num("layer")?;
                if n != (k + 1) as f64 {
                    bail!("{}: `layer` = {n}, expected {}", le.what, k + 1);
                }
                let thickness = le.num("thickness")?;
                let mat = le.tag("material")?;
                le.done()?;
                layers.push(shell_layer(nd, mat, thickness, nd_used)?);
            }
            let sum: f64 = layers.iter().map(ShellLayer::thickness).sum();
            if !agrees(total, sum) {
                bail!(
                    "section {tag}: `totalThickness` = {total} is not the sum of the layers' \
                     thicknesses, {sum}"
                );
            }
            SectionKind::LayeredShell {
                layers,
                density: 0.0,
            }
        }
        other => bail!(
            "{}: type {other:?} is not imported (FiberSection3d, ElasticSection3d, \
             ElasticMembranePlateSection, LayeredShellFiberSection)",
            e.what
        ),
    };
    e.done()?;
    Ok(Section {
        tag,
        name: String::new(),
        kind,
    })
}

fn transformation(v: &Value) -> Result<Transformation> {
    let mut e = Entry::new(v, "a transformation")?;
    let tag = e.tag("name")?;
    e.what = format!("crdTransformation {tag}");
    let kind = match e.text("type")? {
        "LinearCrdTransf3d" => TransfKind::Linear,
        "PDeltaCrdTransf3d" => TransfKind::Pdelta,
        "CorotCrdTransf3d" => TransfKind::Corotational,
        other => bail!(
            "{}: type {other:?} is not imported (LinearCrdTransf3d, PDeltaCrdTransf3d, \
             CorotCrdTransf3d)",
            e.what
        ),
    };
    let v = e.numbers("vecInLocXZPlane", 3)?;
    e.done()?;
    Ok(Transformation {
        tag,
        kind,
        vecxz: [v[0], v[1], v[2]],
    })
}

fn node(v: &Value) -> Result<(Node, Option<NodalMass>)> {
    let mut e = Entry::new(v, "a node")?;
    let tag = e.tag("name")?;
    e.what = format!("node {tag}");
    e.expect("ndf", 6.0, "fem2rbd's nodes have 6 DOFs")?;
    let c = e.array("crd")?;
    if c.len() != 3 {
        bail!(
            "{}: {} coordinates; fem2rbd's models are 3-D",
            e.what,
            c.len()
        );
    }
    let c = e.numbers("crd", 3)?;
    let mass = if e.obj.contains_key("mass") {
        let m = e.numbers("mass", 6)?;
        if m[0] != m[1] || m[1] != m[2] {
            bail!(
                "{}: `mass` has mx, my, mz = {}, {}, {}; the model format has one \
                 translational mass",
                e.what,
                m[0],
                m[1],
                m[2]
            );
        }
        m.iter().any(|x| *x != 0.0).then(|| NodalMass {
            node: tag,
            m: m[0],
            rotational: (m[3..] != [0.0; 3]).then(|| [m[3], m[4], m[5]]),
        })
    } else {
        None
    };
    e.done()?;
    Ok((
        Node {
            tag,
            x: c[0],
            y: c[1],
            z: c[2],
        },
        mass,
    ))
}

/// The name of an element by its geometry: `Column` (a line steeper than 45°), `Beam`,
/// `Wall` (a shell whose normal is within 45° of horizontal) or `Slab`.
fn type_name(nodes: &[[f64; 3]]) -> &'static str {
    let d = |a: [f64; 3], b: [f64; 3]| [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    match nodes {
        [a, b] => {
            let v = d(*a, *b);
            if v[2].abs() > v[0].hypot(v[1]) {
                "Column"
            } else {
                "Beam"
            }
        }
        [a, b, c, dd] => {
            let (p, q) = (d(*a, *c), d(*b, *dd));
            let n = [
                p[1] * q[2] - p[2] * q[1],
                p[2] * q[0] - p[0] * q[2],
                p[0] * q[1] - p[1] * q[0],
            ];
            if n[2].abs() < n[0].hypot(n[1]) {
                "Wall"
            } else {
                "Slab"
            }
        }
        _ => "Element",
    }
}

fn element(
    v: &Value,
    elastic: &mut ImportedElasticSections,
    xyz: &BTreeMap<u32, [f64; 3]>,
    layered: &std::collections::BTreeSet<u32>,
) -> Result<Element> {
    let mut e = Entry::new(v, "an element")?;
    let tag = e.tag("name")?;
    e.what = format!("element {tag}");
    let ty = e.text("type")?;
    let nodes = e.tags("nodes")?;
    let want = if ty.starts_with("Shell") || ty == "ASDShellQ4" {
        4
    } else {
        2
    };
    if nodes.len() != want {
        bail!("{}: {} nodes, a {ty} has {want}", e.what, nodes.len());
    }
    let coords: Vec<[f64; 3]> = nodes
        .iter()
        .map(|n| {
            xyz.get(n)
                .copied()
                .ok_or_else(|| InvalidValue(format!("element {tag}: unknown node {n}")))
        })
        .collect::<Result<_>>()?;
    let two = || [nodes[0], nodes[1]];
    let kind = match ty {
        "ForceBeamColumn3d" | "DispBeamColumn3d" => {
            let secs = e.tags("sections")?;
            let Some(&section) = secs.first() else {
                bail!("{}: no sections", e.what);
            };
            if secs.iter().any(|s| *s != section) {
                bail!(
                    "{}: sections {secs:?} differ along the element; fem2rbd's beam-columns \
                     have one section",
                    e.what
                );
            }
            let mut ie = Entry::new(e.value("integration")?, format!("{}'s integration", e.what))?;
            let rule = match ie.text("type")? {
                "Lobatto" => Integration::Lobatto,
                "Legendre" => Integration::Legendre,
                other => bail!(
                    "{}: rule {other:?} is not imported (Lobatto, Legendre)",
                    ie.what
                ),
            };
            ie.done()?;
            e.expect(
                "massperlength",
                0.0,
                "the mass of an imported beam-column is its nodes' `mass`",
            )?;
            let formulation = if ty == "ForceBeamColumn3d" {
                Formulation::Force
            } else {
                Formulation::Disp
            };
            let default = match formulation {
                Formulation::Force => Integration::Lobatto,
                Formulation::Disp => Integration::Legendre,
            };
            ElementKind::BeamColumn {
                nodes: two(),
                section,
                transf: e.tag("crdTransformation")?,
                formulation,
                points: secs.len() as u32,
                integration: (rule != default).then_some(rule),
            }
        }
        "ElasticBeam3d" => {
            let p = [
                e.num("E")?,
                e.num("G")?,
                e.num("A")?,
                e.num("Iy")?,
                e.num("Iz")?,
                e.num("Jx")?,
                e.num("massperlength")?,
            ];
            let why = "fem2rbd's elastic beam-columns have no end releases";
            e.expect("releasez", 0.0, why)?;
            e.expect("releasey", 0.0, why)?;
            ElementKind::ElasticBeamColumn {
                nodes: two(),
                section: elastic.tag_of(p),
                transf: e.tag("crdTransformation")?,
            }
        }
        "ShellMITC4" | "ASDShellQ4" => {
            let section = e.tag("section")?;
            if ty == "ShellMITC4" && layered.contains(&section) {
                bail!(
                    "{}: a ShellMITC4 with the layered section {section}; fem2rbd computes \
                     layered shells as ASDShellQ4",
                    e.what
                );
            }
            ElementKind::Shell {
                nodes: [nodes[0], nodes[1], nodes[2], nodes[3]],
                section,
                local_x: None,
                corotational: false,
            }
        }
        other => bail!(
            "{}: type {other:?} is not imported (ForceBeamColumn3d, DispBeamColumn3d, \
             ElasticBeam3d, ShellMITC4, ASDShellQ4)",
            e.what
        ),
    };
    e.done()?;
    Ok(Element {
        tag,
        type_name: type_name(&coords).to_string(),
        group: Group("1".into()),
        rigid_body: true,
        kind,
    })
}

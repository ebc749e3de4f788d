//! Parsing with file:line errors, and semantic validation of a model.
use super::source_map::{line_of, SourceMap};
use super::{limits, ElementKind, InvalidValue, Model, SectionKind};
use std::collections::{BTreeMap, BTreeSet};

/// Where a model error is: the file as given, the 1-based line when known and the item
/// (e.g. "element 17") when known. Shown as `file:line: item`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Location {
    /// File name as given.
    pub file: String,
    /// 1-based line, when known.
    pub line: Option<usize>,
    /// The offending item, e.g. "element 17", when known.
    pub item: Option<String>,
}

impl std::fmt::Display for Location {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.file)?;
        if let Some(l) = self.line {
            write!(f, ":{l}")?;
        }
        if let Some(item) = &self.item {
            write!(f, ": {item}")?;
        }
        Ok(())
    }
}

/// A model that cannot be used: the file cannot be read, does not parse, or breaks a
/// rule of `docs/model-format.md`. Every variant but [`ModelError::File`] carries its
/// [`Location`]; the message is `file:line: item: what is wrong`.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ModelError {
    /// The model file cannot be read (missing, not a file, too large, unreadable).
    #[error(transparent)]
    File(#[from] super::limits::InputFileError),
    /// Not valid TOML / JSON, or not the model's schema (unknown key, wrong type).
    #[error("{at}: {message}")]
    Syntax {
        /// Where.
        at: Location,
        /// The parser's message.
        message: String,
    },
    /// A tag defined twice (or a node supported twice).
    #[error("{at}: {message}")]
    Duplicate {
        /// Where.
        at: Location,
        /// What is repeated.
        message: String,
    },
    /// A reference to a node, material, section or transformation that does not exist.
    #[error("{at}: {message}")]
    UnknownReference {
        /// Where.
        at: Location,
        /// What is missing.
        message: String,
    },
    /// Degenerate geometry: zero length or area, repeated nodes, a parallel `vecxz`.
    #[error("{at}: {message}")]
    Geometry {
        /// Where.
        at: Location,
        /// What is degenerate.
        message: String,
    },
    /// A value out of its range, not finite, or inconsistent with another.
    #[error("{at}: {message}")]
    Value {
        /// Where.
        at: Location,
        /// Which value and its rule.
        message: String,
    },
    /// A count over its resource bound (`docs/reliability.md`).
    #[error("{at}: {}", .limit.short())]
    Limit {
        /// Where.
        at: Location,
        /// The count and its ceiling.
        limit: super::limits::LimitError,
    },
    /// An imported file (the reference layout of `frame3.json`, OpenSees' `print -JSON`)
    /// that cannot be imported.
    #[error("{at}: {message}")]
    Import {
        /// Where.
        at: Location,
        /// What is missing or unsupported.
        message: String,
    },
}

impl ModelError {
    /// Where the error is (`None` for a file that cannot be read).
    pub fn location(&self) -> Option<&Location> {
        match self {
            ModelError::File(_) => None,
            ModelError::Syntax { at, .. }
            | ModelError::Duplicate { at, .. }
            | ModelError::UnknownReference { at, .. }
            | ModelError::Geometry { at, .. }
            | ModelError::Value { at, .. }
            | ModelError::Limit { at, .. }
            | ModelError::Import { at, .. } => Some(at),
        }
    }

    /// The same error with its location's file renamed (e.g. for a generated model).
    pub fn in_file(mut self, file: impl Into<String>) -> Self {
        let file = file.into();
        match &mut self {
            ModelError::File(_) => {}
            ModelError::Syntax { at, .. }
            | ModelError::Duplicate { at, .. }
            | ModelError::UnknownReference { at, .. }
            | ModelError::Geometry { at, .. }
            | ModelError::Value { at, .. }
            | ModelError::Limit { at, .. }
            | ModelError::Import { at, .. } => at.file = file,
        }
        self
    }
}

/// The kind of a validation failure, to build the [`ModelError`] variant.
#[derive(Clone, Copy)]
enum Kind {
    Duplicate,
    Unknown,
    Geometry,
    Value,
}

impl Kind {
    fn error(self, at: Location, message: String) -> ModelError {
        match self {
            Kind::Duplicate => ModelError::Duplicate { at, message },
            Kind::Unknown => ModelError::UnknownReference { at, message },
            Kind::Geometry => ModelError::Geometry { at, message },
            Kind::Value => ModelError::Value { at, message },
        }
    }
}

/// Minimum length (m) of a line element and minimum shell area (m²).
const MIN_LENGTH: f64 = 1e-9;

pub(super) fn parse_and_validate(
    text: &str,
    file: &str,
    is_json: bool,
) -> Result<Model, ModelError> {
    let (model, map) = if is_json {
        let map = SourceMap::from_json(text);
        check_counts(file, &map)?;
        let model: Model = serde_json::from_str(text).map_err(|e| {
            let item = if top_level_key_error(&e.to_string()) {
                Some("top level".to_string())
            } else {
                map.item_at(e.line())
                    .map(|(k, i)| format!("{k} item {}", i + 1))
            };
            ModelError::Syntax {
                at: Location {
                    file: file.to_string(),
                    line: Some(e.line()),
                    item,
                },
                message: e.to_string(),
            }
        })?;
        (model, map)
    } else {
        let map = SourceMap::from_toml(text);
        check_counts(file, &map)?;
        let model: Model = toml::from_str(text).map_err(|e| {
            let line = e.span().map(|s| line_of(text, s.start));
            let item = if top_level_key_error(e.message()) {
                Some("top level".to_string())
            } else {
                line.and_then(|l| map.item_at(l))
                    .map(|(k, i)| format!("{k} item {}", i + 1))
            };
            ModelError::Syntax {
                at: Location {
                    file: file.to_string(),
                    line,
                    item,
                },
                message: toml_message(text, &e),
            }
        })?;
        (model, map)
    };
    validate(&model, file, &map)?;
    Ok(model)
}

/// The TOML parser's message, with the key named when it is given twice in one table
/// (the parser says only "duplicate key").
fn toml_message(text: &str, e: &toml::de::Error) -> String {
    let message = e.message().trim();
    let key = e
        .span()
        .and_then(|s| text.get(s))
        .map(str::trim)
        .filter(|k| !k.is_empty() && k.len() <= 100 && !k.contains('\n'));
    match key {
        Some(key) if message == "duplicate key" => {
            format!("duplicate key {key}: each key is given once per item")
        }
        _ => message.to_string(),
    }
}

/// The node and element bounds, checked on the items the source map counted, before the
/// model is built from the text (a file of 10⁶ nodes is refused without allocating them).
fn check_counts(file: &str, map: &SourceMap) -> Result<(), ModelError> {
    let cx = Ctx { file, map };
    for (key, what, bound) in [
        ("node", "node count", limits::MAX_NODES),
        ("element", "element count", limits::MAX_ELEMENTS),
    ] {
        limits::check("model", what, map.item_count(key) as u64, bound as u64)
            .map_err(|e| cx.key_limit(key, e))?;
    }
    Ok(())
}

/// An unknown key at the top level (serde lists the top-level keys): it must not be
/// attributed to the array item that happens to precede it in the file.
fn top_level_key_error(message: &str) -> bool {
    message.contains("unknown field")
        && message.contains("`transformation`, `node`, `support`, `element`, `mass`")
}

struct Ctx<'a> {
    file: &'a str,
    map: &'a SourceMap,
}

impl Ctx<'_> {
    fn at_item(&self, key: &str, index: usize, item: String) -> Location {
        Location {
            file: self.file.to_string(),
            line: self.map.item_line(key, index),
            item: Some(item),
        }
    }
    fn at_key(&self, key: &str) -> Location {
        Location {
            file: self.file.to_string(),
            line: self.map.key_line(key),
            item: Some(key.to_string()),
        }
    }
    fn item(
        &self,
        kind: Kind,
        key: &str,
        index: usize,
        item: String,
        message: impl std::fmt::Display,
    ) -> ModelError {
        kind.error(self.at_item(key, index, item), message.to_string())
    }
    fn key(&self, kind: Kind, key: &str, message: impl std::fmt::Display) -> ModelError {
        kind.error(self.at_key(key), message.to_string())
    }
    fn item_limit(
        &self,
        key: &str,
        index: usize,
        item: String,
        limit: limits::LimitError,
    ) -> ModelError {
        ModelError::Limit {
            at: self.at_item(key, index, item),
            limit,
        }
    }
    fn key_limit(&self, key: &str, limit: limits::LimitError) -> ModelError {
        ModelError::Limit {
            at: self.at_key(key),
            limit,
        }
    }
}

fn finite(vals: &[(&str, f64)]) -> Result<(), InvalidValue> {
    for (n, v) in vals {
        if !v.is_finite() {
            return Err(InvalidValue(format!("{n} is not finite ({v})")));
        }
    }
    Ok(())
}

pub(super) fn validate(m: &Model, file: &str, map: &SourceMap) -> Result<(), ModelError> {
    let cx = Ctx { file, map };

    // ---- top level
    if !(m.scale.is_finite() && m.scale > 0.0) {
        return Err(cx.key(
            Kind::Value,
            "scale",
            format!("scale = {} must be positive", m.scale),
        ));
    }
    if !(m.gravity.g.is_finite() && m.gravity.g >= 0.0) {
        return Err(cx.key(
            Kind::Value,
            "gravity",
            format!("g = {} must be >= 0", m.gravity.g),
        ));
    }
    if m.gravity.load_steps == 0 {
        return Err(cx.key(Kind::Value, "gravity", "load_steps must be at least 1"));
    }
    // ---- resource bounds (docs/reliability.md), before anything is sized by them
    limits::check(
        "gravity",
        "load_steps",
        u64::from(m.gravity.load_steps),
        u64::from(limits::MAX_LOAD_STEPS),
    )
    .map_err(|e| cx.key_limit("gravity", e))?;
    limits::check(
        "model",
        "node count",
        m.nodes.len() as u64,
        limits::MAX_NODES as u64,
    )
    .map_err(|e| cx.key_limit("node", e))?;
    limits::check(
        "model",
        "element count",
        m.elements.len() as u64,
        limits::MAX_ELEMENTS as u64,
    )
    .map_err(|e| cx.key_limit("element", e))?;
    if let Some(d) = &m.damping {
        let vals: Vec<f64> = [d.xi, d.a0, d.a1]
            .into_iter()
            .flatten()
            .chain(d.periods.into_iter().flatten())
            .collect();
        if vals.iter().any(|v| !v.is_finite()) {
            return Err(cx.key(Kind::Value, "damping", "a value is not finite"));
        }
        match d.coefficients() {
            None => {
                return Err(cx.key(
                    Kind::Value,
                    "damping",
                    "give either xi and periods = [Ti, Tj], or a0 and a1",
                ))
            }
            Some((a0, a1)) if a0 < 0.0 || a1 < 0.0 => {
                return Err(cx.key(Kind::Value, "damping", "coefficients must not be negative"))
            }
            _ => {}
        }
        if let Some(p) = d.periods {
            if p[0] <= 0.0 || p[1] <= 0.0 || p[0] == p[1] {
                return Err(cx.key(
                    Kind::Value,
                    "damping",
                    format!("periods {p:?} must be positive and distinct"),
                ));
            }
        }
    }

    // ---- nodes
    let mut nodes = BTreeMap::new();
    for (i, n) in m.nodes.iter().enumerate() {
        let it = || format!("node {}", n.tag);
        if nodes.insert(n.tag, n).is_some() {
            return Err(cx.item(Kind::Duplicate, "node", i, it(), "duplicate node tag"));
        }
        finite(&[("x", n.x), ("y", n.y), ("z", n.z)])
            .map_err(|e| cx.item(Kind::Value, "node", i, it(), e))?;
    }

    // ---- materials
    let mut mats = BTreeMap::new();
    for (i, mt) in m.materials.iter().enumerate() {
        let it = || format!("material {}", mt.tag);
        if mats.insert(mt.tag, mt).is_some() {
            return Err(cx.item(
                Kind::Duplicate,
                "material",
                i,
                it(),
                "duplicate material tag",
            ));
        }
        mt.check()
            .map_err(|e| cx.item(Kind::Value, "material", i, it(), e))?;
    }

    // ---- sections
    let mut secs = BTreeMap::new();
    for (i, s) in m.sections.iter().enumerate() {
        let it = || format!("section {}", s.tag);
        if secs.insert(s.tag, s).is_some() {
            return Err(cx.item(Kind::Duplicate, "section", i, it(), "duplicate section tag"));
        }
        limits::check(
            format!("section {}", s.tag),
            "fibre count",
            s.fiber_count(),
            limits::MAX_FIBERS_PER_SECTION,
        )
        .map_err(|e| cx.item_limit("section", i, it(), e))?;
        s.check()
            .map_err(|e| cx.item(Kind::Value, "section", i, it(), e))?;
        for r in s.material_refs() {
            if !mats.contains_key(&r) {
                return Err(cx.item(
                    Kind::Unknown,
                    "section",
                    i,
                    it(),
                    format!("unknown material {r}"),
                ));
            }
        }
    }

    // ---- transformations
    let mut transfs = BTreeMap::new();
    for (i, t) in m.transformations.iter().enumerate() {
        let it = || format!("transformation {}", t.tag);
        if transfs.insert(t.tag, t).is_some() {
            return Err(cx.item(
                Kind::Duplicate,
                "transformation",
                i,
                it(),
                "duplicate transformation tag",
            ));
        }
        let v = t.vecxz;
        finite(&[("vecxz[0]", v[0]), ("vecxz[1]", v[1]), ("vecxz[2]", v[2])])
            .map_err(|e| cx.item(Kind::Value, "transformation", i, it(), e))?;
        if v.iter().all(|c| *c == 0.0) {
            return Err(cx.item(Kind::Value, "transformation", i, it(), "vecxz is zero"));
        }
    }

    // ---- supports
    let mut supported = BTreeSet::new();
    for (i, s) in m.supports.iter().enumerate() {
        let it = || format!("support of node {}", s.node);
        if !nodes.contains_key(&s.node) {
            return Err(cx.item(
                Kind::Unknown,
                "support",
                i,
                it(),
                format!("unknown node {}", s.node),
            ));
        }
        if !supported.insert(s.node) {
            return Err(cx.item(
                Kind::Duplicate,
                "support",
                i,
                it(),
                "node is supported twice",
            ));
        }
        if s.dofs.iter().any(|d| *d > 1) {
            return Err(cx.item(
                Kind::Value,
                "support",
                i,
                it(),
                "dofs must be 0 (free) or 1 (fixed)",
            ));
        }
    }

    // ---- elements
    let mut elems = BTreeSet::new();
    let node_map = m.node_map();
    for (i, e) in m.elements.iter().enumerate() {
        let it = || format!("element {}", e.tag);
        let err = |kind: Kind, msg: String| cx.item(kind, "element", i, it(), msg);
        if !elems.insert(e.tag) {
            return Err(err(Kind::Duplicate, "duplicate element tag".into()));
        }
        if e.type_name.trim().is_empty() || e.type_name.contains(':') {
            return Err(err(
                Kind::Value,
                format!(
                    "type_name {:?} must be non-empty and contain no ':'",
                    e.type_name
                ),
            ));
        }
        if e.group.0.trim().is_empty() || e.group.0.contains(':') {
            return Err(err(
                Kind::Value,
                format!("group {:?} must be non-empty and contain no ':'", e.group.0),
            ));
        }
        let mut pts = Vec::new();
        for n in e.nodes() {
            match nodes.get(n) {
                Some(p) => pts.push(p.xyz()),
                None => return Err(err(Kind::Unknown, format!("unknown node {n}"))),
            }
        }
        let distinct: BTreeSet<_> = e.nodes().iter().collect();
        if distinct.len() != e.nodes().len() {
            return Err(err(
                Kind::Geometry,
                format!("repeats a node in {:?}", e.nodes()),
            ));
        }
        if let Some(st) = e.section() {
            let Some(sec) = secs.get(&st) else {
                return Err(err(Kind::Unknown, format!("unknown section {st}")));
            };
            let ok = match (&e.kind, &sec.kind) {
                (ElementKind::BeamColumn { .. }, _) => sec.is_beam_section(),
                (ElementKind::ElasticBeamColumn { .. }, k) => {
                    matches!(k, SectionKind::Elastic { .. })
                }
                (ElementKind::Shell { .. }, _) => sec.is_shell_section(),
                (ElementKind::ElasticStrip { .. } | ElementKind::Panel { .. }, _) => true,
            };
            if !ok {
                return Err(err(
                    Kind::Value,
                    format!(
                        "section {st} is of the wrong kind for a {} element",
                        e.kind_name()
                    ),
                ));
            }
        }
        if let Some(tt) = e.transf() {
            let Some(t) = transfs.get(&tt) else {
                return Err(err(Kind::Unknown, format!("unknown transformation {tt}")));
            };
            let (a, b) = (pts[0], pts[1]);
            let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            if len < MIN_LENGTH {
                return Err(err(
                    Kind::Geometry,
                    format!(
                        "has zero length (nodes {} and {} coincide)",
                        e.nodes()[0],
                        e.nodes()[1]
                    ),
                ));
            }
            let v = t.vecxz;
            let vn = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            let c = [
                d[1] * v[2] - d[2] * v[1],
                d[2] * v[0] - d[0] * v[2],
                d[0] * v[1] - d[1] * v[0],
            ];
            let s = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt() / (len * vn);
            if s < 1e-6 {
                return Err(err(
                    Kind::Geometry,
                    format!(
                        "vecxz {:?} of transformation {tt} is parallel to the element axis",
                        v
                    ),
                ));
            }
        }
        match &e.kind {
            ElementKind::BeamColumn {
                points,
                integration,
                formulation,
                ..
            } => {
                let lobatto = match integration {
                    Some(r) => *r == super::Integration::Lobatto,
                    None => *formulation == super::Formulation::Force,
                };
                let min = if lobatto { 2 } else { 1 };
                if *points < min || *points > 10 {
                    return Err(err(
                        Kind::Value,
                        format!(
                            "points = {points} must be in {min}..=10 for this integration rule"
                        ),
                    ));
                }
            }
            ElementKind::ElasticStrip {
                e: em,
                g,
                width,
                thickness,
                density,
                ..
            } => {
                finite(&[
                    ("E", *em),
                    ("G", *g),
                    ("width", *width),
                    ("thickness", *thickness),
                    ("density", *density),
                ])
                .map_err(|e| err(Kind::Value, e.0))?;
                for (n, v) in [
                    ("E", *em),
                    ("G", *g),
                    ("width", *width),
                    ("thickness", *thickness),
                ] {
                    if v <= 0.0 {
                        return Err(err(Kind::Value, format!("{n} = {v} must be positive")));
                    }
                }
                if *density < 0.0 {
                    return Err(err(
                        Kind::Value,
                        format!("density = {density} must not be negative"),
                    ));
                }
            }
            ElementKind::Panel {
                thickness, density, ..
            } => {
                finite(&[("thickness", *thickness), ("density", *density)])
                    .map_err(|e| err(Kind::Value, e.0))?;
                if *thickness <= 0.0 {
                    return Err(err(
                        Kind::Value,
                        format!("thickness = {thickness} must be positive"),
                    ));
                }
                if *density < 0.0 {
                    return Err(err(
                        Kind::Value,
                        format!("density = {density} must not be negative"),
                    ));
                }
                if super::area_in(&node_map, e).unwrap_or(0.0) < MIN_LENGTH * MIN_LENGTH {
                    return Err(err(Kind::Geometry, "has zero area".into()));
                }
            }
            ElementKind::Shell { local_x, .. } => {
                if super::area_in(&node_map, e).unwrap_or(0.0) < MIN_LENGTH * MIN_LENGTH {
                    return Err(err(Kind::Geometry, "has zero area".into()));
                }
                if let Some(v) = local_x {
                    finite(&[
                        ("local_x[0]", v[0]),
                        ("local_x[1]", v[1]),
                        ("local_x[2]", v[2]),
                    ])
                    .map_err(|e| err(Kind::Value, e.0))?;
                    // Normal of the quadrilateral: cross product of its diagonals.
                    let d1: Vec<f64> = (0..3).map(|k| pts[2][k] - pts[0][k]).collect();
                    let d2: Vec<f64> = (0..3).map(|k| pts[3][k] - pts[1][k]).collect();
                    let nrm = [
                        d1[1] * d2[2] - d1[2] * d2[1],
                        d1[2] * d2[0] - d1[0] * d2[2],
                        d1[0] * d2[1] - d1[1] * d2[0],
                    ];
                    let dot =
                        |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
                    let (vn, nn) = (dot(v, v).sqrt(), dot(&nrm, &nrm).sqrt());
                    if vn == 0.0 {
                        return Err(err(Kind::Geometry, "local_x is zero".into()));
                    }
                    let in_plane = (1.0 - (dot(v, &nrm) / (vn * nn)).powi(2)).max(0.0).sqrt();
                    if in_plane < 1e-6 {
                        return Err(err(
                            Kind::Geometry,
                            format!("local_x {v:?} is normal to the shell's plane"),
                        ));
                    }
                }
            }
            ElementKind::ElasticBeamColumn { .. } => {}
        }
    }

    // ---- fibre states: Σ points × fibres over beam-columns
    let mut states: u64 = 0;
    for e in &m.elements {
        if let ElementKind::BeamColumn {
            points, section, ..
        } = &e.kind
        {
            let n = secs.get(section).map_or(0, |s| s.fiber_count());
            states = states.saturating_add(u64::from(*points).saturating_mul(n));
        }
    }
    limits::check(
        "model",
        "fibre states (points × fibres over all beam-columns)",
        states,
        limits::MAX_FIBER_STATES,
    )
    .map_err(|e| cx.key_limit("element", e))?;

    // ---- masses
    for (i, nm) in m.masses.iter().enumerate() {
        let it = || format!("mass {} (node {})", i + 1, nm.node);
        if !nodes.contains_key(&nm.node) {
            return Err(cx.item(
                Kind::Unknown,
                "mass",
                i,
                it(),
                format!("unknown node {}", nm.node),
            ));
        }
        let mut vals = vec![("m", nm.m)];
        if let Some(r) = nm.rotational {
            vals.extend([
                ("rotational[0]", r[0]),
                ("rotational[1]", r[1]),
                ("rotational[2]", r[2]),
            ]);
        }
        finite(&vals).map_err(|e| cx.item(Kind::Value, "mass", i, it(), e))?;
        if vals.iter().any(|(_, v)| *v < 0.0) {
            return Err(cx.item(Kind::Value, "mass", i, it(), "mass must not be negative"));
        }
    }
    Ok(())
}

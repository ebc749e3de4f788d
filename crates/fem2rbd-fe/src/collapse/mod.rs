//! Collapse criteria (paper §2): when the FE stage hands off to the
//! rigid-body stage (the collapse moment Tc).
//!
//! A pure module: it reads the model's geometry once ([`Structure`]) and then judges
//! nodal displacement fields fed to a [`CollapseMonitor`], one per converged FE step.
//! Displacements are the FE's (relative to the moving ground, m).
//!
//! - **Main members** are the beam-column elements (`beam_column` and
//!   `elastic_beam_column`, i.e. the columns and beams); their nodes are the *main
//!   nodes*. Slab strips, shells and rigid-body-only panels are not main members.
//! - [`Criterion::VerticalDrop`] (the paper's Criterion 4, its default): collapse when a
//!   main node's downward displacement −u_z reaches `threshold_m`; the paper's 1 m at
//!   full scale becomes 1 m × `model.scale` ([`Criterion::paper_default`]; 0.25 m for
//!   frame3).
//! - [`Criterion::StoryDrift`]: collapse when an inter-story drift ratio reaches `ratio`
//!   (1/50 GB50011 [`GB50011_DRIFT`], 0.04 FEMA 356 [`FEMA356_DRIFT`], or a user value).
//!   Floor levels: the distinct heights z of the supported nodes and of the nodes of
//!   non-vertical main members (beams), merged within 1 mm; a column's intermediate
//!   mesh nodes are not levels. Story s lies between levels s and s+1. Its column
//!   lines are the pairs (bottom, top) of main nodes at those two levels with the same
//!   plan position (within 1 mm) joined by a chain of vertical main members (columns
//!   within 45° of vertical). Drift of story s = max over its column lines of
//!   |Δu_h| / h_s, with Δu_h the horizontal (X, Y) displacement of the top node minus
//!   that of the bottom node and h_s = z_{s+1} − z_s. This is the inter-story drift
//!   ratio of GB 50011-2010 §5.5 and FEMA 356 Table C1-3, measured per column line
//!   (not at the floor's centre of mass), so torsion counts at the corner columns.
// `!(x > 0.0)` is used on purpose: it also rejects NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::model::{ElementKind, Model};

/// A collapse monitor that cannot be set up.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum CollapseError {
    /// A main member whose node is not in the model.
    #[error("element {element}: unknown node")]
    UnknownNode {
        /// Element tag.
        element: u32,
    },
    /// A vertical-drop threshold that is not positive (m).
    #[error("vertical-drop threshold must be > 0 m, got {0}")]
    Threshold(f64),
    /// A drift limit that is not positive and finite.
    #[error("drift limit must be > 0, got {0}")]
    DriftLimit(f64),
    /// The drift criterion on a model without a story of columns.
    #[error("the model has no story with a column line; use the vertical-drop criterion")]
    NoStories,
}

/// What setting up a monitor returns.
type Result<T> = std::result::Result<T, CollapseError>;
use std::collections::BTreeMap;

/// GB 50011-2010 elasto-plastic drift limit of RC frames, 1/50.
pub const GB50011_DRIFT: f64 = 1.0 / 50.0;
/// FEMA 356 collapse-prevention transient drift of concrete frames, 4 %.
pub const FEMA356_DRIFT: f64 = 0.04;

/// Level merge tolerance (m).
const LEVEL_TOL_M: f64 = 1e-3;

/// A collapse criterion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Criterion {
    /// A main node's downward displacement reaches `threshold_m` (m).
    VerticalDrop {
        /// Threshold (m), > 0.
        threshold_m: f64,
    },
    /// An inter-story drift ratio reaches `ratio` (dimensionless), > 0.
    StoryDrift {
        /// Limit, e.g. [`GB50011_DRIFT`] or [`FEMA356_DRIFT`].
        ratio: f64,
    },
}

impl Criterion {
    /// The paper's Criterion 4: vertical drop of 1 m × `model.scale`.
    pub fn paper_default(model: &Model) -> Criterion {
        Criterion::VerticalDrop {
            threshold_m: model.scale,
        }
    }
}

/// One column line of a story: bottom and top node tags.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ColumnLine {
    /// Node at the story's bottom level.
    pub bottom: u32,
    /// Node at the story's top level.
    pub top: u32,
}

/// What the criteria need of the model's geometry (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Structure {
    /// Node tags in model order (the index of a displacement slice).
    pub node_tags: Vec<u32>,
    /// Indices (into `node_tags`) of the main nodes, ascending.
    pub main_nodes: Vec<usize>,
    /// Floor levels z (m), ascending.
    pub levels: Vec<f64>,
    /// Column lines per story (story s between `levels[s]` and `levels[s + 1]`).
    pub stories: Vec<Vec<ColumnLine>>,
    index: BTreeMap<u32, usize>,
}

fn is_main(kind: &ElementKind) -> bool {
    matches!(
        kind,
        ElementKind::BeamColumn { .. } | ElementKind::ElasticBeamColumn { .. }
    )
}

impl Structure {
    /// Reads main nodes, floor levels and column lines from the model (module docs).
    pub fn of_model(model: &Model) -> Result<Structure> {
        let nodes = model.node_map();
        let node_tags: Vec<u32> = model.nodes.iter().map(|n| n.tag).collect();
        let index: BTreeMap<u32, usize> =
            node_tags.iter().enumerate().map(|(i, t)| (*t, i)).collect();
        let mut main = std::collections::BTreeSet::new();
        let mut level_z: Vec<f64> = model
            .supports
            .iter()
            .filter_map(|s| nodes.get(&s.node).map(|n| n.z))
            .collect();
        // vertical main members as an adjacency (lower node -> upper node)
        let mut up: BTreeMap<u32, Vec<u32>> = BTreeMap::new();
        for e in model.elements.iter().filter(|e| is_main(&e.kind)) {
            let [i, j] = e.nodes() else { continue };
            let (Some(a), Some(b)) = (nodes.get(i), nodes.get(j)) else {
                return Err(CollapseError::UnknownNode { element: e.tag });
            };
            main.insert(index[i]);
            main.insert(index[j]);
            let d = [b.x - a.x, b.y - a.y, b.z - a.z];
            let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            if d[2].abs() >= std::f64::consts::FRAC_1_SQRT_2 * len {
                let (lo, hi) = if d[2] > 0.0 { (*i, *j) } else { (*j, *i) };
                up.entry(lo).or_default().push(hi);
            } else {
                level_z.extend([a.z, b.z]);
            }
        }
        level_z.sort_by(f64::total_cmp);
        let mut levels: Vec<f64> = Vec::new();
        for z in level_z {
            match levels.last() {
                Some(&l) if z - l <= LEVEL_TOL_M => {}
                _ => levels.push(z),
            }
        }
        let level_of = |z: f64| levels.iter().position(|l| (z - l).abs() <= LEVEL_TOL_M);
        let mut stories = vec![Vec::new(); levels.len().saturating_sub(1)];
        for (&lo, _) in up.iter() {
            let Some(s) = level_of(nodes[&lo].z) else {
                continue;
            };
            if s + 1 >= levels.len() {
                continue;
            }
            // follow the column chain up to the next level
            let mut cur = lo;
            let top = loop {
                let Some(next) = up.get(&cur).and_then(|v| v.first()) else {
                    break None;
                };
                cur = *next;
                let z = nodes[&cur].z;
                if level_of(z) == Some(s + 1) {
                    break Some(cur);
                }
                if z > levels[s + 1] + LEVEL_TOL_M {
                    break None;
                }
            };
            if let Some(top) = top {
                let (b, t) = (nodes[&lo], nodes[&top]);
                if (b.x - t.x).hypot(b.y - t.y) <= LEVEL_TOL_M {
                    stories[s].push(ColumnLine { bottom: lo, top });
                }
            }
        }
        Ok(Structure {
            node_tags,
            main_nodes: main.into_iter().collect(),
            levels,
            stories,
            index,
        })
    }

    /// Index of a node tag in the model's node order.
    pub fn index_of(&self, tag: u32) -> Option<usize> {
        self.index.get(&tag).copied()
    }

    /// Story heights h_s (m).
    pub fn story_heights(&self) -> Vec<f64> {
        self.levels.windows(2).map(|w| w[1] - w[0]).collect()
    }

    /// The largest downward displacement −u_z over main nodes (m) and its node tag.
    /// `u[i]` is the translation (m) of the model's i-th node.
    pub fn max_drop(&self, u: &[[f64; 3]]) -> (f64, u32) {
        let mut best = (f64::NEG_INFINITY, 0);
        for &i in &self.main_nodes {
            let d = -u[i][2];
            if d > best.0 {
                best = (d, self.node_tags[i]);
            }
        }
        best
    }

    /// Drift ratio of every story (module docs) with its governing column line.
    pub fn story_drifts(&self, u: &[[f64; 3]]) -> Vec<(f64, Option<ColumnLine>)> {
        let h = self.story_heights();
        self.stories
            .iter()
            .zip(h)
            .map(|(lines, h)| {
                let mut best = (0.0, None);
                for c in lines {
                    let (b, t) = (u[self.index[&c.bottom]], u[self.index[&c.top]]);
                    let r = (t[0] - b[0]).hypot(t[1] - b[1]) / h;
                    if r > best.0 || best.1.is_none() {
                        best = (r, Some(*c));
                    }
                }
                best
            })
            .collect()
    }
}

/// Why the criterion was met.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Trigger {
    /// A main node dropped.
    VerticalDrop {
        /// Node tag.
        node: u32,
        /// Its downward displacement (m).
        drop_m: f64,
        /// The threshold (m).
        threshold_m: f64,
    },
    /// A story drifted.
    StoryDrift {
        /// Story number, 1-based (story 1 between the base and floor 1).
        story: usize,
        /// The governing column line.
        column: ColumnLine,
        /// Its drift ratio.
        ratio: f64,
        /// The limit.
        limit: f64,
    },
}

/// The first step at which the criterion was met.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CollapseEvent {
    /// Step number as fed to [`CollapseMonitor::observe`].
    pub step: usize,
    /// Time (s) as fed.
    pub time_s: f64,
    /// Why.
    pub trigger: Trigger,
}

impl std::fmt::Display for CollapseEvent {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.trigger {
            Trigger::VerticalDrop {
                node,
                drop_m,
                threshold_m,
            } => write!(
                f,
                "collapse at t = {} s (step {}): node {node} dropped {drop_m} m ≥ {threshold_m} m",
                self.time_s, self.step
            ),
            Trigger::StoryDrift {
                story,
                column,
                ratio,
                limit,
            } => write!(
                f,
                "collapse at t = {} s (step {}): story {story} drift {ratio} ≥ {limit} \
                 (column nodes {}–{})",
                self.time_s, self.step, column.bottom, column.top
            ),
        }
    }
}

/// Watches the converged FE steps for the collapse criterion.
#[derive(Debug, Clone)]
pub struct CollapseMonitor {
    criterion: Criterion,
    structure: Structure,
    event: Option<CollapseEvent>,
}

impl CollapseMonitor {
    /// A monitor of `criterion` over the model. Errors on a non-positive threshold or
    /// (drift criterion) a model without stories.
    pub fn new(model: &Model, criterion: Criterion) -> Result<CollapseMonitor> {
        let structure = Structure::of_model(model)?;
        match criterion {
            Criterion::VerticalDrop { threshold_m } if !(threshold_m > 0.0) => {
                return Err(CollapseError::Threshold(threshold_m));
            }
            Criterion::StoryDrift { ratio } if !(ratio > 0.0 && ratio.is_finite()) => {
                return Err(CollapseError::DriftLimit(ratio));
            }
            Criterion::StoryDrift { .. } if structure.stories.iter().all(Vec::is_empty) => {
                return Err(CollapseError::NoStories);
            }
            _ => {}
        }
        Ok(CollapseMonitor {
            criterion,
            structure,
            event: None,
        })
    }

    /// The geometry read from the model.
    pub fn structure(&self) -> &Structure {
        &self.structure
    }

    /// The criterion.
    pub fn criterion(&self) -> Criterion {
        self.criterion
    }

    /// The first event, if any.
    pub fn event(&self) -> Option<&CollapseEvent> {
        self.event.as_ref()
    }

    /// Feeds one converged step: `u[i]` is the translation (m) of the model's i-th node.
    /// Returns the event once the criterion has been met (the first one; later steps are
    /// not judged again). With the drift criterion the event names the story of largest
    /// drift among those at or over the limit. Panics if `u` has not one entry per node.
    pub fn observe(&mut self, step: usize, time_s: f64, u: &[[f64; 3]]) -> Option<&CollapseEvent> {
        if self.event.is_some() {
            return self.event.as_ref();
        }
        assert_eq!(
            u.len(),
            self.structure.node_tags.len(),
            "one displacement per model node"
        );
        let trigger = match self.criterion {
            Criterion::VerticalDrop { threshold_m } => {
                let (drop_m, node) = self.structure.max_drop(u);
                (drop_m >= threshold_m).then_some(Trigger::VerticalDrop {
                    node,
                    drop_m,
                    threshold_m,
                })
            }
            Criterion::StoryDrift { ratio: limit } => self
                .structure
                .story_drifts(u)
                .into_iter()
                .enumerate()
                .filter_map(|(s, (r, c))| Some((s, r, c?)))
                .filter(|(_, r, _)| *r >= limit)
                .max_by(|a, b| a.1.total_cmp(&b.1).then(b.0.cmp(&a.0)))
                .map(|(s, ratio, column)| Trigger::StoryDrift {
                    story: s + 1,
                    column,
                    ratio,
                    limit,
                }),
        };
        self.event = trigger.map(|trigger| CollapseEvent {
            step,
            time_s,
            trigger,
        });
        self.event.as_ref()
    }

    /// Like [`observe`](Self::observe) with displacements given per node tag.
    pub fn observe_with(
        &mut self,
        step: usize,
        time_s: f64,
        u_of: impl Fn(u32) -> [f64; 3],
    ) -> Option<&CollapseEvent> {
        let u: Vec<[f64; 3]> = self.structure.node_tags.iter().map(|&t| u_of(t)).collect();
        self.observe(step, time_s, &u)
    }
}

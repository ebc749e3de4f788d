//! The finite-element domain: nodes (6 DOF each), supports, lumped nodal masses,
//! elements, nodal loads, the equation numbering of the free DOFs, and the committed
//! and trial nodal response.
//!
//! Conventions follow OpenSees (`Domain`, `Node`, `LoadPattern`, `RCM` numberer):
//! - DOF order per node: `[ux, uy, uz, rx, ry, rz]` (m, rad), global axes.
//! - Supports (`fix`) remove DOFs from the equations; their displacement stays zero
//!   (uniform base excitation is expressed in relative motion, as OpenSees'
//!   `UniformExcitation`).
//! - Loads: a *constant* part (held after [`Domain::load_const`], like OpenSees'
//!   `loadConst -time 0.0`) plus one reference pattern scaled by the load factor λ.
//!
//! Element nodes (two for beam-columns, four for shells) are addressed by their index in
//! the node array ([`Element::nodes`]); [`Domain::node_index`] maps a node tag to that
//! index.

use std::collections::BTreeMap;

use crate::fe::element::{Element, RemovedElement};
use crate::fe::element::{ElementError, EndDisplacements, Prepare, MAX_ELEMENT_NODES};

/// Degrees of freedom per node.
pub(crate) const NDF: usize = 6;

/// Equation number of a constrained (fixed) DOF.
const FIXED: usize = usize::MAX;
/// Fewest elements worth a thread of their own in [`Domain::update_elements`] (below it the
/// spawn costs more than the fibre work it saves).
const MIN_ELEMENTS_PER_THREAD: usize = 16;

/// Fewest elements worth a thread of their own in [`Domain::prepare_elements`]: forming
/// one beam-column's global tangent takes about a microsecond, so below a few hundred
/// elements a thread's spawn and join cost more than it saves (frame3, 96 elements,
/// stays sequential; the 7-story frame, 2 646 elements, splits).
const MIN_PREPARE_PER_THREAD: usize = 512;

/// Threads for element state determination when none are given: the machine's available
/// parallelism (the binaries' `--threads` passes another number down as a value,
/// [`Domain::set_threads`]). Results do not depend on it.
pub fn default_threads() -> usize {
    std::thread::available_parallelism().map_or(1, usize::from)
}

/// The first error of `results`, after consuming all of them (no short cut: every item's
/// side effect happens, as in a plain loop).
fn first_err<E>(results: impl Iterator<Item = Result<(), E>>) -> Result<(), E> {
    let mut first = Ok(());
    for r in results {
        if first.is_ok() {
            first = r;
        }
    }
    first
}

/// One node: its tag in the model and its coordinates (m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Node {
    /// Tag (id) in the model.
    pub tag: i64,
    /// Global coordinates `[x, y, z]` (m).
    pub coords: [f64; 3],
}

/// Invalid domain input; each variant names the offending item.
#[derive(Debug, Clone, thiserror::Error, PartialEq)]
pub enum DomainError {
    /// Two nodes share a tag.
    #[error("node {0}: duplicate node tag")]
    DuplicateNode(i64),
    /// A coordinate, mass or load value is NaN or infinite, or a mass is negative.
    #[error("node {tag}: invalid {what}")]
    InvalidNodeValue {
        /// The node's tag.
        tag: i64,
        /// Which value.
        what: &'static str,
    },
    /// A node index is out of range.
    #[error("node index {0} out of range")]
    NodeIndex(usize),
    /// An element refers to a node that does not exist, twice to the same node, or to
    /// fewer than 2 or more than [`MAX_ELEMENT_NODES`] nodes.
    #[error("element {tag}: bad nodes {nodes:?}")]
    ElementNodes {
        /// The element's tag.
        tag: i64,
        /// Its node indices.
        nodes: Vec<usize>,
    },
    /// Two elements share a tag.
    #[error("element {0}: duplicate element tag")]
    DuplicateElement(i64),
    /// An element index is out of range.
    #[error("element index {0} out of range")]
    ElementIndex(usize),
    /// An element removed twice.
    #[error("element {0}: already removed")]
    AlreadyRemoved(i64),
}

/// Nodes, supports, masses, elements, loads and nodal response of one model.
#[derive(Debug, Default)]
pub struct Domain {
    nodes: Vec<Node>,
    node_by_tag: BTreeMap<i64, usize>,
    fixed: Vec<[bool; NDF]>,
    /// DOFs held at their current value because no element is left at the node and the
    /// DOF has no mass ([`Domain::remove_element`]): out of the equations like a fixed
    /// DOF, but no support (no reaction).
    held: Vec<[bool; NDF]>,
    mass: Vec<[f64; NDF]>,
    elements: Vec<Box<dyn Element>>,
    element_by_tag: BTreeMap<i64, usize>,
    constant_load: Vec<[f64; NDF]>,
    pattern_load: Vec<[f64; NDF]>,
    /// Load factor λ of the reference pattern.
    load_factor: f64,
    /// Pseudo-time (static) or time (transient), s.
    time: f64,
    /// Equation number per node DOF (`FIXED` when constrained); empty until numbered.
    eq: Vec<[usize; NDF]>,
    neq: usize,
    disp: Vec<[f64; NDF]>,
    vel: Vec<[f64; NDF]>,
    acc: Vec<[f64; NDF]>,
    disp_c: Vec<[f64; NDF]>,
    vel_c: Vec<[f64; NDF]>,
    acc_c: Vec<[f64; NDF]>,
    /// Displacements last handed to the elements (for `EndDisplacements::delta`).
    disp_seen: Vec<[f64; NDF]>,
    /// Threads for element state determination ([`Domain::update_elements`]).
    threads: usize,
}

fn finite(v: &[f64]) -> bool {
    v.iter().all(|x| x.is_finite())
}

impl Domain {
    /// An empty domain.
    /// Element state determination uses [`default_threads`] threads.
    pub fn new() -> Self {
        Self {
            threads: default_threads(),
            ..Self::default()
        }
    }

    /// Adds a node and returns its index. Invalidates the equation numbering.
    pub fn add_node(&mut self, tag: i64, coords: [f64; 3]) -> Result<usize, DomainError> {
        if self.node_by_tag.contains_key(&tag) {
            return Err(DomainError::DuplicateNode(tag));
        }
        if !finite(&coords) {
            return Err(DomainError::InvalidNodeValue {
                tag,
                what: "coordinates",
            });
        }
        let i = self.nodes.len();
        self.nodes.push(Node { tag, coords });
        self.node_by_tag.insert(tag, i);
        self.fixed.push([false; NDF]);
        self.held.push([false; NDF]);
        self.mass.push([0.0; NDF]);
        self.constant_load.push([0.0; NDF]);
        self.pattern_load.push([0.0; NDF]);
        for v in [
            &mut self.disp,
            &mut self.vel,
            &mut self.acc,
            &mut self.disp_c,
            &mut self.vel_c,
            &mut self.acc_c,
            &mut self.disp_seen,
        ] {
            v.push([0.0; NDF]);
        }
        self.eq.clear();
        Ok(i)
    }

    /// Index of the node with this tag.
    pub fn node_index(&self, tag: i64) -> Option<usize> {
        self.node_by_tag.get(&tag).copied()
    }

    /// All nodes, in index order.
    pub fn nodes(&self) -> &[Node] {
        &self.nodes
    }

    fn check_node(&self, node: usize) -> Result<(), DomainError> {
        if node < self.nodes.len() {
            Ok(())
        } else {
            Err(DomainError::NodeIndex(node))
        }
    }

    /// Fixes the DOFs flagged `true` (OpenSees `fix`); adds to earlier fixities.
    pub fn fix(&mut self, node: usize, dofs: [bool; NDF]) -> Result<(), DomainError> {
        self.check_node(node)?;
        for (f, d) in self.fixed[node].iter_mut().zip(dofs) {
            *f |= d;
        }
        self.eq.clear();
        Ok(())
    }

    /// Fixed flags of a node.
    pub fn fixity(&self, node: usize) -> [bool; NDF] {
        self.fixed[node]
    }

    /// Sets the lumped mass of a node: `[mx, my, mz]` (kg) and `[mrx, mry, mrz]` (kg·m²);
    /// rotational masses may be zero.
    pub fn set_mass(&mut self, node: usize, mass: [f64; NDF]) -> Result<(), DomainError> {
        self.check_node(node)?;
        if !finite(&mass) || mass.iter().any(|&m| m < 0.0) {
            let tag = self.nodes[node].tag;
            return Err(DomainError::InvalidNodeValue { tag, what: "mass" });
        }
        self.mass[node] = mass;
        Ok(())
    }

    /// Lumped mass of a node.
    pub fn mass(&self, node: usize) -> [f64; NDF] {
        self.mass[node]
    }

    /// Adds an element; its nodes must exist and be distinct. Returns its index.
    pub fn add_element(&mut self, element: Box<dyn Element>) -> Result<usize, DomainError> {
        let tag = element.tag();
        let nodes = element.nodes();
        let repeated = (1..nodes.len()).any(|i| nodes[..i].contains(&nodes[i]));
        if repeated
            || !(2..=MAX_ELEMENT_NODES).contains(&nodes.len())
            || nodes.iter().any(|&n| n >= self.nodes.len())
        {
            return Err(DomainError::ElementNodes {
                tag,
                nodes: nodes.to_vec(),
            });
        }
        if self.element_by_tag.contains_key(&tag) {
            return Err(DomainError::DuplicateElement(tag));
        }
        let i = self.elements.len();
        self.element_by_tag.insert(tag, i);
        self.elements.push(element);
        self.eq.clear();
        Ok(i)
    }

    /// The elements, in insertion order.
    pub fn elements(&self) -> &[Box<dyn Element>] {
        &self.elements
    }

    /// Index of the element with this tag.
    pub fn element_index(&self, tag: i64) -> Option<usize> {
        self.element_by_tag.get(&tag).copied()
    }

    /// Removes element `index` from the analysis at the current time (OpenSees
    /// `remove element`): it is replaced by a [`RemovedElement`] with the same tag and
    /// nodes, which has no force and no stiffness. The nodal masses stay as they are.
    /// Returns the indices of the element's nodes that no element holds any more.
    ///
    /// A node without elements keeps its translational mass and moves under its loads
    /// (gravity) and the ground motion: free flight, which Newmark's effective stiffness
    /// (M/(βΔt²) on the diagonal) solves without any stiffness. Its DOFs without mass
    /// (the rotations, as the models lump no rotational inertia) would be singular:
    /// they are held at their current value and leave the equations, like a fixed DOF
    /// but without a reaction ([`Domain::held`]). The numbering is then invalidated: an
    /// analysis goes on with a new one ([`Domain::number_dofs`]).
    ///
    /// Error: `index` out of range, or the element already removed.
    pub fn remove_element(&mut self, index: usize) -> Result<Vec<usize>, DomainError> {
        let Some(el) = self.elements.get(index) else {
            return Err(DomainError::ElementIndex(index));
        };
        if el.removed_at().is_some() {
            return Err(DomainError::AlreadyRemoved(el.tag()));
        }
        let (tag, nodes) = (el.tag(), el.nodes().to_vec());
        self.elements[index] = Box::new(RemovedElement::new(tag, &nodes, self.time));
        let held_by_an_element = |node: usize| {
            self.elements
                .iter()
                .any(|e| e.removed_at().is_none() && e.nodes().contains(&node))
        };
        let orphans: Vec<usize> = nodes
            .into_iter()
            .filter(|&n| !held_by_an_element(n))
            .collect();
        for &n in &orphans {
            for k in 0..NDF {
                if !self.fixed[n][k] && self.mass[n][k] == 0.0 && !self.held[n][k] {
                    self.held[n][k] = true;
                    self.eq.clear();
                }
            }
        }
        Ok(orphans)
    }

    /// DOFs of a node held at their value since no element is left there
    /// ([`Domain::remove_element`]).
    pub fn held(&self, node: usize) -> [bool; NDF] {
        self.held[node]
    }

    /// Adds a nodal load (N, N·m) to the reference load pattern (scaled by λ).
    pub fn add_nodal_load(&mut self, node: usize, load: [f64; NDF]) -> Result<(), DomainError> {
        self.check_node(node)?;
        if !finite(&load) {
            let tag = self.nodes[node].tag;
            return Err(DomainError::InvalidNodeValue { tag, what: "load" });
        }
        for (p, l) in self.pattern_load[node].iter_mut().zip(load) {
            *p += l;
        }
        Ok(())
    }

    /// OpenSees `loadConst -time 0.0`: the current loads λ·P_ref become constant, the
    /// reference pattern is emptied, λ and the time are reset to zero.
    pub fn load_const(&mut self) {
        let lf = self.load_factor;
        for (c, p) in self.constant_load.iter_mut().zip(&mut self.pattern_load) {
            for k in 0..NDF {
                c[k] += lf * p[k];
                p[k] = 0.0;
            }
        }
        self.load_factor = 0.0;
        self.time = 0.0;
    }

    /// Load factor λ of the reference pattern.
    pub fn load_factor(&self) -> f64 {
        self.load_factor
    }

    /// Sets λ.
    pub fn set_load_factor(&mut self, lambda: f64) {
        self.load_factor = lambda;
    }

    /// Current (pseudo-)time, s.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Sets the (pseudo-)time, s.
    pub fn set_time(&mut self, t: f64) {
        self.time = t;
    }

    /// Numbers the free DOFs: nodes in reverse Cuthill-McKee order of the element
    /// connectivity graph (deterministic: BFS from a minimum-degree node, neighbours by
    /// increasing degree then index; one component after another), then the free DOFs
    /// of each node in DOF order. Returns the number of equations.
    pub fn number_dofs(&mut self) -> usize {
        let n = self.nodes.len();
        let mut adj: Vec<Vec<usize>> = vec![Vec::new(); n];
        for e in &self.elements {
            let nodes = e.nodes();
            for &a in nodes {
                adj[a].extend(nodes.iter().copied().filter(|&b| b != a));
            }
        }
        for a in &mut adj {
            a.sort_unstable();
            a.dedup();
        }
        let deg: Vec<usize> = adj.iter().map(Vec::len).collect();
        let mut visited = vec![false; n];
        let mut order = Vec::with_capacity(n);
        loop {
            let start = (0..n).filter(|&i| !visited[i]).min_by_key(|&i| (deg[i], i));
            let Some(start) = start else { break };
            visited[start] = true;
            let mut head = order.len();
            order.push(start);
            while head < order.len() {
                let v = order[head];
                head += 1;
                let mut nb: Vec<usize> = adj[v].iter().copied().filter(|&w| !visited[w]).collect();
                nb.sort_unstable_by_key(|&w| (deg[w], w));
                for w in nb {
                    visited[w] = true;
                    order.push(w);
                }
            }
        }
        order.reverse();
        self.eq = vec![[FIXED; NDF]; n];
        let mut next = 0;
        for &v in &order {
            for k in 0..NDF {
                if !self.fixed[v][k] && !self.held[v][k] {
                    self.eq[v][k] = next;
                    next += 1;
                }
            }
        }
        self.neq = next;
        next
    }

    /// Whether [`Domain::number_dofs`] is current.
    pub fn is_numbered(&self) -> bool {
        self.eq.len() == self.nodes.len()
    }

    /// Number of equations (free DOFs).
    pub fn num_equations(&self) -> usize {
        self.neq
    }

    /// Equation number of a node DOF, `None` when fixed (or not numbered yet).
    pub fn equation(&self, node: usize, dof: usize) -> Option<usize> {
        let e = *self.eq.get(node)?.get(dof)?;
        (e != FIXED).then_some(e)
    }

    /// Equation numbers of an element's `6 n` DOFs, node by node (`None` for fixed DOFs).
    pub fn element_equations(&self, element: usize) -> Vec<Option<usize>> {
        self.elements[element]
            .nodes()
            .iter()
            .flat_map(|&a| (0..NDF).map(move |k| (a, k)))
            .map(|(a, k)| self.equation(a, k))
            .collect()
    }

    /// Diagonal of the lumped mass matrix over the equations (kg, kg·m²).
    pub fn mass_diagonal(&self) -> Vec<f64> {
        let mut m = vec![0.0; self.neq];
        for (node, mass) in self.mass.iter().enumerate() {
            for k in 0..NDF {
                if let Some(e) = self.equation(node, k) {
                    m[e] = mass[k];
                }
            }
        }
        m
    }

    /// Influence vector ι of a uniform base motion along global axis `dir` (0 = X,
    /// 1 = Y, 2 = Z): 1 on the free translational DOFs in that direction, else 0.
    pub fn influence_vector(&self, dir: usize) -> Vec<f64> {
        let mut iota = vec![0.0; self.neq];
        for node in 0..self.nodes.len() {
            if let Some(e) = self.equation(node, dir) {
                iota[e] = 1.0;
            }
        }
        iota
    }

    /// External load over the equations: constant loads + λ·reference pattern.
    pub fn external_load(&self, out: &mut [f64]) {
        out.iter_mut().for_each(|x| *x = 0.0);
        for node in 0..self.nodes.len() {
            for k in 0..NDF {
                if let Some(e) = self.equation(node, k) {
                    out[e] =
                        self.constant_load[node][k] + self.load_factor * self.pattern_load[node][k];
                }
            }
        }
    }

    /// Reference pattern over the equations.
    pub fn reference_load(&self, out: &mut [f64]) {
        out.iter_mut().for_each(|x| *x = 0.0);
        for node in 0..self.nodes.len() {
            for k in 0..NDF {
                if let Some(e) = self.equation(node, k) {
                    out[e] = self.pattern_load[node][k];
                }
            }
        }
    }

    /// Assembles the element resisting forces of the trial state over the equations,
    /// summed in element order (each element's force written into one stack buffer,
    /// [`Element::resisting_force_into`]).
    pub fn resisting_force(&self, out: &mut [f64]) {
        out.iter_mut().for_each(|x| *x = 0.0);
        self.for_each_element_force(|node, k, f| {
            if let Some(e) = self.equation(node, k) {
                out[e] += f;
            }
        });
    }

    /// Calls `add(node, dof, force)` for every component of every element's resisting
    /// force of the trial state, in element order (the order every sum over them keeps).
    fn for_each_element_force(&self, mut add: impl FnMut(usize, usize, f64)) {
        let mut f = [0.0; NDF * MAX_ELEMENT_NODES];
        for el in &self.elements {
            let n = el.nodes().len();
            el.resisting_force_into(&mut f[..NDF * n]);
            for (a, &node) in el.nodes().iter().enumerate() {
                for k in 0..NDF {
                    add(node, k, f[NDF * a + k]);
                }
            }
        }
    }

    /// Support reactions of the trial state, per node with at least one fixed DOF:
    /// R = F_int − P at the fixed DOFs (N, N·m), zero at the free ones, where F_int is the
    /// elements' resisting force at the node and P the applied load (constant + λ·reference).
    /// This is OpenSees' `reactions` without `-dynamic`: static equilibrium, no inertia or
    /// damping force. Returned in node order: `(node index, [Rx, Ry, Rz, Mx, My, Mz])`.
    pub fn reactions(&self) -> Vec<(usize, [f64; NDF])> {
        let mut f_int = vec![[0.0; NDF]; self.nodes.len()];
        self.for_each_element_force(|node, k, f| f_int[node][k] += f);
        (0..self.nodes.len())
            .filter(|&node| self.fixed[node].iter().any(|&x| x))
            .map(|node| {
                let mut r = [0.0; NDF];
                for k in 0..NDF {
                    if self.fixed[node][k] {
                        r[k] = f_int[node][k]
                            - self.constant_load[node][k]
                            - self.load_factor * self.pattern_load[node][k];
                    }
                }
                (node, r)
            })
            .collect()
    }

    fn gather(&self, field: &[[f64; NDF]], out: &mut [f64]) {
        for node in 0..self.nodes.len() {
            for k in 0..NDF {
                if let Some(e) = self.equation(node, k) {
                    out[e] = field[node][k];
                }
            }
        }
    }

    /// Trial displacements over the equations.
    pub fn trial_displacement_eq(&self, out: &mut [f64]) {
        self.gather(&self.disp, out)
    }
    /// Committed displacements, velocities and accelerations over the equations.
    pub fn committed_eq(&self, u: &mut [f64], v: &mut [f64], a: &mut [f64]) {
        self.gather(&self.disp_c, u);
        self.gather(&self.vel_c, v);
        self.gather(&self.acc_c, a);
    }

    /// Sets the trial displacements, velocities and accelerations from equation vectors
    /// (fixed DOFs stay zero) and hands the end displacements to every element
    /// ([`Element::set_trial`]), with `delta` = change since the state last handed over.
    /// An element error is returned as is (a failed iteration).
    pub fn set_trial_eq(
        &mut self,
        u: &[f64],
        v: Option<&[f64]>,
        a: Option<&[f64]>,
    ) -> Result<(), ElementError> {
        for node in 0..self.nodes.len() {
            for k in 0..NDF {
                if let Some(e) = self.equation(node, k) {
                    self.disp[node][k] = u[e];
                    if let Some(v) = v {
                        self.vel[node][k] = v[e];
                    }
                    if let Some(a) = a {
                        self.acc[node][k] = a[e];
                    }
                }
            }
        }
        crate::fe::profile::timed(crate::fe::profile::Phase::ElementUpdate, || {
            self.update_elements()
        })
    }

    /// Element state determination for the current trial displacements: every element's
    /// `set_trial` (fibre strains → stresses, section and element forces and tangents).
    ///
    /// This is most of an FE step's work, and each element depends only on its own end
    /// displacements, so the elements are split into [`Domain::threads`] contiguous chunks
    /// that run on scoped threads. The result is bit-for-bit the same for any thread
    /// count: no element reads another's state, nothing is summed across elements here
    /// (assembly stays sequential, in element order), and the error reported is the first
    /// in element order, as in a sequential loop (which also updates every element).
    fn update_elements(&mut self) -> Result<(), ElementError> {
        let (disp, seen) = (&self.disp, &self.disp_seen);
        let update = |el: &mut Box<dyn Element>| -> Result<(), ElementError> {
            let mut total = [0.0; NDF * MAX_ELEMENT_NODES];
            let mut delta = [0.0; NDF * MAX_ELEMENT_NODES];
            let n = el.nodes().len();
            for (i, &a) in el.nodes().iter().enumerate() {
                for k in 0..NDF {
                    total[NDF * i + k] = disp[a][k];
                    delta[NDF * i + k] = disp[a][k] - seen[a][k];
                }
            }
            el.set_trial(&EndDisplacements {
                total: &total[..NDF * n],
                delta: &delta[..NDF * n],
            })
        };
        // Every element is updated even after an error; the first error in order wins.
        let first_error = |chunk: &mut [Box<dyn Element>]| first_err(chunk.iter_mut().map(update));
        let n = self.elements.len();
        let threads = self
            .threads
            .clamp(1, n.div_ceil(MIN_ELEMENTS_PER_THREAD).max(1));
        let result = if threads == 1 {
            first_error(&mut self.elements)
        } else {
            let chunk = n.div_ceil(threads);
            std::thread::scope(|scope| {
                let workers: Vec<_> = self
                    .elements
                    .chunks_mut(chunk)
                    .map(|c| scope.spawn(move || first_error(c)))
                    .collect();
                first_err(
                    workers
                        .into_iter()
                        .map(|w| w.join().unwrap_or_else(|p| std::panic::resume_unwind(p))),
                )
            })
        };
        self.disp_seen.clone_from(&self.disp);
        result
    }

    /// [`Element::prepare`] of every element, on [`Domain::threads`] threads when the
    /// domain is large enough (at least `MIN_PREPARE_PER_THREAD` = 512 elements a thread):
    /// contiguous chunks of elements, each forming and keeping its own matrices. Nothing
    /// is summed here and a prepared matrix is the same bits as one formed on first read,
    /// so the assembly that follows (sequential, in element order) gives the same result
    /// for any thread count.
    pub fn prepare_elements(&self, what: Prepare) {
        let n = self.elements.len();
        let threads = self.threads.clamp(1, (n / MIN_PREPARE_PER_THREAD).max(1));
        if threads == 1 {
            return;
        }
        let chunk = n.div_ceil(threads);
        std::thread::scope(|scope| {
            for c in self.elements.chunks(chunk) {
                scope.spawn(move || c.iter().for_each(|e| e.prepare(what)));
            }
        });
    }

    /// `f(index, element)` for every element, the results in element order; the caller
    /// sums them (assembly) in element order. Sequential on purpose: the maps are reads of
    /// what [`Domain::update_elements`] (threaded) already formed — resisting forces,
    /// tangents, damping products — and threading them cost more than it saved (measured
    /// with `bench_fe`: frame3 residual 0.047 → 0.99 ms/step and assembly 0.44 → 1.05 ms/step on
    /// 2 threads; on the 7-story frame residual 23 → 66 and assembly 90 → 108 ms/step,
    /// docs/performance.md).
    pub fn map_elements<T>(&self, f: impl Fn(usize, &dyn Element) -> T) -> Vec<T> {
        self.elements
            .iter()
            .enumerate()
            .map(|(i, e)| f(i, e.as_ref()))
            .collect()
    }

    /// Threads used for element state determination (1 = sequential). Results do not
    /// depend on it.
    pub fn threads(&self) -> usize {
        self.threads
    }

    /// Sets the threads used for element state determination (0 or 1 = sequential).
    pub fn set_threads(&mut self, threads: usize) {
        self.threads = threads.max(1);
    }

    /// Sets initial conditions: displacements, velocities and accelerations over the
    /// equations (fixed DOFs zero), updates the elements and commits. For free
    /// vibration give a consistent acceleration (M ü₀ = P − C u̇₀ − F(u₀)).
    pub fn set_initial_state(
        &mut self,
        u: &[f64],
        v: &[f64],
        a: &[f64],
    ) -> Result<(), ElementError> {
        if !self.is_numbered() {
            self.number_dofs();
        }
        let res = self.set_trial_eq(u, Some(v), Some(a));
        if res.is_ok() {
            self.commit();
        } else {
            self.revert_to_last_commit();
        }
        res
    }

    /// Tells every element the time increment Δt (s) of the step about to be iterated
    /// ([`Element::set_time_increment`]); the transient integrator calls it before each
    /// (sub)step. Static analyses leave it at its pseudo-time default of 1.
    pub fn set_time_increment(&mut self, dt: f64) {
        self.for_each_element_mut(|el| el.set_time_increment(dt));
    }

    /// Accepts the trial state (nodes and elements).
    pub fn commit(&mut self) {
        self.disp_c.clone_from(&self.disp);
        self.vel_c.clone_from(&self.vel);
        self.acc_c.clone_from(&self.acc);
        self.for_each_element_mut(|el| el.commit_state());
    }

    /// `f` on every element, on [`Domain::threads`] threads in contiguous chunks when the
    /// domain has at least `MIN_PREPARE_PER_THREAD` elements a thread (a commit copies
    /// every fibre's state: light work per element, worth a thread only in large models).
    /// For work that only changes each element's own state (no sums across elements), so
    /// the result does not depend on the thread count.
    fn for_each_element_mut(&mut self, f: impl Fn(&mut Box<dyn Element>) + Sync) {
        let n = self.elements.len();
        let threads = self.threads.clamp(1, (n / MIN_PREPARE_PER_THREAD).max(1));
        if threads == 1 {
            self.elements.iter_mut().for_each(f);
            return;
        }
        let chunk = n.div_ceil(threads);
        let f = &f;
        std::thread::scope(|scope| {
            for c in self.elements.chunks_mut(chunk) {
                scope.spawn(move || c.iter_mut().for_each(f));
            }
        });
    }

    /// Returns nodes and elements to the last committed state.
    pub fn revert_to_last_commit(&mut self) {
        self.disp.clone_from(&self.disp_c);
        self.vel.clone_from(&self.vel_c);
        self.acc.clone_from(&self.acc_c);
        self.disp_seen.clone_from(&self.disp_c);
        self.for_each_element_mut(|el| el.revert_to_last_commit());
    }

    /// Committed displacement of a node `[ux, uy, uz, rx, ry, rz]` (m, rad).
    pub fn displacement(&self, node: usize) -> [f64; NDF] {
        self.disp_c[node]
    }
    /// Committed velocity of a node (m/s, rad/s), relative to the ground.
    pub fn velocity(&self, node: usize) -> [f64; NDF] {
        self.vel_c[node]
    }
    /// Committed acceleration of a node (m/s², rad/s²), relative to the ground.
    pub fn acceleration(&self, node: usize) -> [f64; NDF] {
        self.acc_c[node]
    }
    /// Trial displacement of a node.
    pub fn trial_displacement(&self, node: usize) -> [f64; NDF] {
        self.disp[node]
    }
}

//! Section and member capacities from the FE model itself: what a fibre
//! section can still carry, found by pushing a copy of it from its current state.
//!
//! Nothing here depends on the rigid-body stage; the ruin stage consumes the plain
//! numbers ([`MemberCapacity`]).
//!
//! # Section pushes ([`section_capacity`])
//!
//! A copy of the section (any [`Section`]: its materials carry their whole history, so a
//! section taken at the collapse moment Tc gives its *residual* capacity, a virgin copy
//! its undamaged capacity) is driven monotonically, step by step, each step committed:
//!
//! * **Axial**: ε₀ from its current value by −Δε_a (compression) or +Δε_a (tension),
//!   curvatures held; the capacity is the peak |N| on the way (N).
//! * **Bending about local z (Mz) and y (My)**, each in both senses: the curvature grows
//!   from its current value by up to κ_max = ε_x / c, c = √3·√(EI/EA) (the half depth of a
//!   rectangle with the section's initial radius of gyration), the other curvature held,
//!   while ε₀ is solved every step so that N equals the given axial load N_g (Newton on
//!   ∂N/∂ε₀, bisection when the tangent is not positive). The capacity is the smaller of
//!   the two senses' peak |M| (N·m) — Bullet's breaking rows are symmetric. The push stops
//!   early once |M| falls below `drop_ratio` × its peak after the peak (the conventional
//!   ultimate curvature, Park, R. (1988), "Ductility evaluation from laboratory and
//!   analytical testing", Proc. 9th WCEE, Tokyo–Kyoto, vol. VIII, 605–616: 20 % drop).
//!   If no ε₀ carries N_g (the residual section cannot hold its axial load) the moment
//!   capacity is 0 and [`SectionCapacity::carries_axial_load`] is false.
//! * **Curvatures**: per axis, the curvature still available before the ultimate
//!   (κ_u − κ_now in the push direction, the smaller of the two senses, 1/m) and the yield
//!   curvature of the bilinear idealisation through 0.75·M_peak (κ_y = κ(0.75 M)/0.75;
//!   Park 1988, as above).
//!
//! Settings ([`PushSettings`]): 120 steps per push (the bending pushes spaced
//! quadratically, κ_k = κ_max·(k/120)², fine through cracking and yield), Δε_a = 0.01
//! (4–5 times the yield strain of the bars, beyond the concrete peak), ε_x = 0.2
//! extreme-fibre strain change (wide enough that the 20 % drop usually ends the push;
//! some frame3 pushes at gravity still end at κ_max, rotation left 0.2 rad), drop ratio 0.8.
//!
//! # Shear ([`aci_shear`])
//!
//! ACI 318-14 §22.5.6.1 (members with axial compression) and §22.5.7.1 (axial tension),
//! SI form: V_c = 0.17·(1 + N_u/(14·A_g))·λ·√f′c·b_w·d (compression, N_u > 0) or
//! V_c = 0.17·(1 + N_u/(3.5·A_g))·λ·√f′c·b_w·d ≥ 0 (tension, N_u < 0), with f′c in MPa,
//! b_w, d in mm, A_g in mm², N_u in N, V_c in N; λ = 1 (normal-weight concrete); d = the
//! distance from the compression face to the centroid of the farthest bar row. Stirrups
//! (V_s = A_v·f_yt·d/s, §22.5.10.5.3) are not part of fem2rbd's section data, so V_s = 0:
//! the shear capacity is the concrete's alone, a lower bound.
//!
//! # Sliding shear ([`shear_friction`])
//!
//! A Bullet connection's shear rows resist sliding of one body against the other across
//! the contact, i.e. across a cut through the member. Its capacity is ACI 318-14 §22.9
//! shear friction (monolithic concrete, μ = 1.4), see [`shear_friction`]. V_c above is
//! reported alongside ([`EndCapacity::diagonal_tension_n`]): the fibre FE has no
//! diagonal-tension failure, so handing it to Bullet would add a failure mode the FE
//! building does not have (measured in docs/handoff.md).
//!
//! # Members ([`member_capacities_against`])
//!
//! Per beam-column element with an `rc_rect` section: the end integration points' section
//! capacities (the points nearest node i and node j) at the element's gravity axial load
//! (from [`axial_loads`] after gravity), the sliding shear and ACI V_c at that load, and
//! whether the end has lost its load path ([`EndCapacity::lost`], see there).

use crate::fe::build::{BuildOptions, BuiltDomain};
use crate::fe::section::Section;
use crate::fe::FeError;
use crate::model::{ElementKind, Model, SectionKind};

/// What a capacity computation returns.
type Result<T> = std::result::Result<T, FeError>;

/// A member whose capacity cannot be computed.
fn cap(item: String, message: String) -> FeError {
    FeError::Capacity { item, message }
}
use nalgebra::Vector4;
use std::collections::BTreeMap;

/// How the section pushes run (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PushSettings {
    /// Steps per push.
    pub steps: usize,
    /// Axial strain change of the axial pushes, Δε_a (–).
    pub axial_strain: f64,
    /// Extreme-fibre strain change of the bending pushes, ε_x (–).
    pub extreme_strain: f64,
    /// The bending push ends when |M| < drop_ratio × peak after the peak.
    pub drop_ratio: f64,
}

impl Default for PushSettings {
    fn default() -> Self {
        PushSettings {
            steps: 120,
            axial_strain: 0.01,
            extreme_strain: 0.2,
            drop_ratio: 0.8,
        }
    }
}

/// Capacities of one section at one axial load (module docs). Index 0 of the pairs is
/// bending about local z (Mz, curvature κz), index 1 about local y (My, κy).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SectionCapacity {
    /// The axial load N_g the bending pushes hold, N (tension positive).
    pub axial_load_n: f64,
    /// Peak compressive force of the axial push, N (≥ 0).
    pub compression_n: f64,
    /// Peak tensile force of the axial push, N (≥ 0).
    pub tension_n: f64,
    /// Moment capacity [about z, about y], N·m (≥ 0; the weaker sense).
    pub moment_nm: [f64; 2],
    /// Curvature still available before the ultimate, [κz, κy], 1/m (≥ 0, weaker sense).
    pub curvature_left: [f64; 2],
    /// Yield curvature of the bilinear idealisation, [κz, κy], 1/m.
    pub curvature_yield: [f64; 2],
    /// Curvature at the start of the pushes (the section's current state), [κz, κy], 1/m.
    pub curvature_now: [f64; 2],
    /// Whether some ε₀ carries N_g in every bending push.
    pub carries_axial_load: bool,
}

/// Copy of `s` in its last committed state.
fn committed_copy(s: &dyn Section) -> Box<dyn Section> {
    let mut c = s.boxed_clone();
    c.revert_to_last_commit();
    c
}

/// Peak |N| of a monotonic axial push by `delta` (module docs).
fn axial_push(s: &dyn Section, delta: f64, steps: usize) -> f64 {
    let mut sec = committed_copy(s);
    let e0 = sec.deformation();
    let mut peak: f64 = 0.0;
    for k in 1..=steps {
        let mut e = e0;
        e[0] += delta * k as f64 / steps as f64;
        sec.set_trial_deformation(&e);
        sec.commit_state();
        let n = sec.resultant()[0];
        if delta < 0.0 {
            peak = peak.max(-n);
        } else {
            peak = peak.max(n);
        }
    }
    peak
}

/// Solves ε₀ so that N(ε₀, κ) = n (trial states only). Returns the trial deformation or
/// `None` when no ε₀ within ±0.05 of the start carries n.
fn solve_axial(sec: &mut dyn Section, e: Vector4<f64>, n: f64, n_ref: f64) -> Option<Vector4<f64>> {
    let tol = 1e-7 * n_ref.max(1.0);
    let mut t = e;
    for _ in 0..30 {
        sec.set_trial_deformation(&t);
        let r = sec.resultant()[0] - n;
        if r.abs() <= tol {
            return Some(t);
        }
        let k = sec.tangent()[(0, 0)];
        if !(k > 0.0 && k.is_finite()) {
            break;
        }
        let step = r / k;
        if !step.is_finite() || step.abs() > 0.01 {
            break;
        }
        t[0] -= step;
    }
    // Bracket and bisect: N grows with ε₀ for every material in its loading branch.
    let f = |sec: &mut dyn Section, x: f64| {
        let mut q = e;
        q[0] = x;
        sec.set_trial_deformation(&q);
        sec.resultant()[0] - n
    };
    let x0 = e[0];
    let f0 = f(sec, x0);
    let dir = if f0 > 0.0 { -1.0 } else { 1.0 };
    let mut lo = x0;
    let mut flo = f0;
    let mut hi = x0;
    let mut found = false;
    let mut d = 1e-4;
    while d <= 0.05 + 1e-12 {
        hi = x0 + dir * d;
        let fh = f(sec, hi);
        if fh.signum() != flo.signum() || fh == 0.0 {
            found = true;
            break;
        }
        lo = hi;
        flo = fh;
        d *= 2.0;
    }
    if !found {
        return None;
    }
    for _ in 0..80 {
        let mid = 0.5 * (lo + hi);
        let fm = f(sec, mid);
        if fm.abs() <= tol {
            lo = mid;
            break;
        }
        if fm.signum() == flo.signum() {
            lo = mid;
            flo = fm;
        } else {
            hi = mid;
        }
    }
    let mut q = e;
    q[0] = lo;
    sec.set_trial_deformation(&q);
    Some(q)
}

/// One bending push: axis 0 = κz (resultant Mz), 1 = κy (My); `sign` ±1.
/// Returns (peak |M|, curvature left, yield curvature, carried N).
fn bending_push(
    s: &dyn Section,
    axis: usize,
    sign: f64,
    n: f64,
    kappa_max: f64,
    n_ref: f64,
    st: &PushSettings,
) -> (f64, f64, f64, bool) {
    let mut sec = committed_copy(s);
    let e_start = sec.deformation();
    let i = 1 + axis;
    let mut path: Vec<(f64, f64)> = vec![(0.0, 0.0)];
    let mut peak: f64 = 0.0;
    let mut k_ult = kappa_max;
    let mut prev = e_start;
    for step in 1..=st.steps {
        // Quadratic spacing: fine steps through cracking and yield, coarse ones beyond.
        let dk = kappa_max * (step as f64 / st.steps as f64).powi(2);
        let mut e = prev;
        e[i] = e_start[i] + sign * dk;
        let Some(sol) = solve_axial(sec.as_mut(), e, n, n_ref) else {
            // No ε₀ carries N any more: the ultimate of this push. At the first step the
            // section cannot carry its axial load at all.
            if step == 1 {
                return (0.0, 0.0, 0.0, false);
            }
            k_ult = path.last().map_or(0.0, |p| p.0);
            break;
        };
        sec.set_trial_deformation(&sol);
        sec.commit_state();
        prev = sol;
        let m = (sign * sec.resultant()[i]).max(0.0);
        peak = peak.max(m);
        path.push((dk, m));
        if peak > 0.0 && m < st.drop_ratio * peak {
            k_ult = dk;
            break;
        }
    }
    // Yield curvature: the secant through 0.75·M_peak (first crossing on the path).
    let mut k_yield = 0.0;
    for w in path.windows(2) {
        let ((k0, m0), (k1, m1)) = (w[0], w[1]);
        if m1 >= 0.75 * peak && peak > 0.0 {
            let k75 = if m1 > m0 {
                k0 + (k1 - k0) * (0.75 * peak - m0) / (m1 - m0)
            } else {
                k1
            };
            k_yield = k75 / 0.75;
            break;
        }
    }
    (peak, k_ult, k_yield, true)
}

/// The capacities of `section` (from its last committed state) at the axial load
/// `axial_load_n` (N, tension positive) — module docs.
pub(crate) fn section_capacity(
    section: &dyn Section,
    axial_load_n: f64,
    st: &PushSettings,
) -> SectionCapacity {
    let k0 = section.initial_tangent();
    let ea = k0[(0, 0)].max(f64::MIN_POSITIVE);
    let compression_n = axial_push(section, -st.axial_strain, st.steps);
    let tension_n = axial_push(section, st.axial_strain, st.steps);
    let n_ref = compression_n.max(tension_n).max(axial_load_n.abs());
    let now = section.deformation();
    let mut moment_nm = [0.0; 2];
    let mut left = [0.0; 2];
    let mut yield_k = [0.0; 2];
    let mut carries = true;
    for axis in 0..2 {
        let ei = k0[(1 + axis, 1 + axis)].max(f64::MIN_POSITIVE);
        let c = 3f64.sqrt() * (ei / ea).sqrt();
        let kappa_max = st.extreme_strain / c;
        let mut m = f64::INFINITY;
        let mut l = f64::INFINITY;
        let mut y = f64::INFINITY;
        for sign in [1.0, -1.0] {
            let (mp, kl, ky, ok) =
                bending_push(section, axis, sign, axial_load_n, kappa_max, n_ref, st);
            carries &= ok;
            m = m.min(mp);
            l = l.min(kl);
            y = y.min(ky);
        }
        moment_nm[axis] = m;
        left[axis] = l;
        yield_k[axis] = y;
    }
    SectionCapacity {
        axial_load_n,
        compression_n,
        tension_n,
        moment_nm,
        curvature_left: left,
        curvature_yield: yield_k,
        curvature_now: [now[1], now[2]],
        carries_axial_load: carries,
    }
}

/// ACI 318-14 §22.5.6.1 / §22.5.7.1 concrete shear strength V_c, N (module docs).
/// `fc_mpa` f′c (MPa), `bw_mm`, `d_mm` (mm), `ag_mm2` (mm²), `nu_n` axial force, N,
/// **compression positive** (ACI's sign).
pub(crate) fn aci_shear(fc_mpa: f64, bw_mm: f64, d_mm: f64, ag_mm2: f64, nu_n: f64) -> f64 {
    let factor = if nu_n >= 0.0 {
        1.0 + nu_n / (14.0 * ag_mm2)
    } else {
        (1.0 + nu_n / (3.5 * ag_mm2)).max(0.0)
    };
    0.17 * factor * fc_mpa.sqrt() * bw_mm * d_mm
}

/// ACI 318-14 §22.9 shear friction across a cut through monolithic concrete, N:
/// V_n = μ·(A_vf·f_y·r_t + N_u) with μ = 1.4λ (§22.9.4.2, Table 22.9.4.2, λ = 1), A_vf
/// the bars crossing the plane (mm²), f_y (MPa), N_u the permanent compression across it
/// (N, compression positive; tension subtracts, §22.9.4.3–5), limited by §22.9.4.4:
/// V_n ≤ r_c·min(0.2·f′c·A_c, (3.3 + 0.08·f′c)·A_c, 11·A_c) (MPa, mm² → N). r_t, r_c ≤ 1
/// are the residual fractions of the section's tension (bars) and compression (concrete)
/// capacities (1 undamaged).
pub(crate) fn shear_friction(
    fc_mpa: f64,
    fy_mpa: f64,
    avf_mm2: f64,
    ac_mm2: f64,
    nu_n: f64,
    r_t: f64,
    r_c: f64,
) -> f64 {
    let v = 1.4 * (avf_mm2 * fy_mpa * r_t + nu_n).max(0.0);
    let cap = (0.2 * fc_mpa * ac_mm2)
        .min((3.3 + 0.08 * fc_mpa) * ac_mm2)
        .min(11.0 * ac_mm2);
    v.min(cap * r_c)
}

/// Capacities at one element end (module docs). Local axes as the element's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EndCapacity {
    /// ξ = x/L of the integration point used.
    pub xi: f64,
    /// The section's capacities at the gravity axial load.
    pub section: SectionCapacity,
    /// Shear (sliding) capacity of the cut section along local y and local z, N: ACI
    /// shear friction ([`shear_friction`]) with the residual ratios.
    pub shear_n: [f64; 2],
    /// Diagonal-tension shear strength V_c along local y and z, N ([`aci_shear`]; for
    /// reports: the fibre FE does not model this failure mode).
    pub diagonal_tension_n: [f64; 2],
    /// Rotation the end can still take before its ultimate, rad: the smaller over the two
    /// axes of κ_left · L_p, with the plastic hinge length L_p = half the section depth in
    /// that bending direction (Park, R. & Paulay, T. (1975), *Reinforced Concrete
    /// Structures*, Wiley, §6.4: L_p ≈ 0.5·d to 1.0·d; the lower end).
    pub rotation_left: f64,
    /// Whether this end has lost its load path: it cannot carry its gravity axial load
    /// any more, or its residual moment capacity about both axes is below
    /// [`LOST_MOMENT_RATIO`] of the undamaged one (bars ruptured, core crushed through).
    pub lost: bool,
}

/// The residual moment fraction (of the undamaged capacity) below which an end counts as
/// lost (both axes).
pub(crate) const LOST_MOMENT_RATIO: f64 = 0.1;

/// Capacities of one beam-column element.
#[derive(Debug, Clone, PartialEq)]
pub struct MemberCapacity {
    /// Model element tag.
    pub element: u32,
    /// Local axes [x, y, z] (unit, global components) of the undeformed element.
    pub axes: [[f64; 3]; 3],
    /// Undeformed positions of node i and node j, m.
    pub nodes: [[f64; 3]; 2],
    /// End i and end j.
    pub ends: [EndCapacity; 2],
    /// Undamaged capacities of the same ends (for the residual ratios).
    pub undamaged: [EndCapacity; 2],
}

/// Axial force N (N, tension positive) of every section, by element tag, in
/// integration-point order.
pub type AxialLoads = BTreeMap<u32, Vec<f64>>;

/// The gravity axial loads ([`axial_loads`] after gravity) and the member capacities of
/// the model in its gravity state ([`member_capacities_against`]): the undamaged building.
pub fn gravity_capacities(
    model: &Model,
    build: &BuildOptions,
    st: &PushSettings,
) -> Result<(AxialLoads, BTreeMap<u32, MemberCapacity>)> {
    let prepared =
        crate::fe::run::prepare(model, build, 1).map_err(|e| e.within("gravity analysis"))?;
    gravity_capacities_of(model, &prepared.built, st)
}

/// As [`gravity_capacities`] on a domain already in its gravity state (`built` from
/// [`crate::fe::run::prepare`]), so that the caller builds the domain once.
pub fn gravity_capacities_of(
    model: &Model,
    built: &BuiltDomain,
    st: &PushSettings,
) -> Result<(AxialLoads, BTreeMap<u32, MemberCapacity>)> {
    let loads = axial_loads(built);
    // The gravity state is the undamaged building: it is its own reference.
    let caps = capacities_impl(model, built, &loads, st, Reference::Same)?;
    Ok((loads, caps))
}

/// The axial force of every section of every element of a built domain, by tag.
pub(crate) fn axial_loads(built: &BuiltDomain) -> BTreeMap<u32, Vec<f64>> {
    let mut out = BTreeMap::new();
    for (&tag, &i) in &built.element_index {
        let secs = built.domain.elements()[i].sections();
        if secs.is_empty() {
            continue;
        }
        out.insert(tag, secs.iter().map(|(_, s)| s.resultant()[0]).collect());
    }
    out
}

/// Per beam-column element with an `rc_rect` section: end capacities of the sections in
/// `built` (their current committed state: residual at Tc, or undamaged for a fresh
/// domain) at the gravity axial loads `gravity` (module docs). Elements without sections
/// (elastic) or with other section kinds are skipped.
///
/// `reference` (the capacities of the same model in its gravity state,
/// [`gravity_capacities`]) supplies the undamaged values; `None` pushes virgin copies
/// of the sections.
pub fn member_capacities_against(
    model: &Model,
    built: &BuiltDomain,
    gravity: &BTreeMap<u32, Vec<f64>>,
    st: &PushSettings,
    reference: Option<&BTreeMap<u32, MemberCapacity>>,
) -> Result<BTreeMap<u32, MemberCapacity>> {
    capacities_impl(
        model,
        built,
        gravity,
        st,
        reference.map_or(Reference::Virgin, Reference::Map),
    )
}

/// Where the undamaged capacities come from.
enum Reference<'a> {
    /// Push virgin copies of the sections.
    Virgin,
    /// The sections are undamaged themselves (gravity state).
    Same,
    /// Given.
    Map(&'a BTreeMap<u32, MemberCapacity>),
}

fn capacities_impl(
    model: &Model,
    built: &BuiltDomain,
    gravity: &BTreeMap<u32, Vec<f64>>,
    st: &PushSettings,
    reference: Reference,
) -> Result<BTreeMap<u32, MemberCapacity>> {
    let sections = model.section_map();
    let materials = model.material_map();
    let nodes = model.node_map();
    let transfs = model.transformation_map();
    let mut out = BTreeMap::new();
    for e in &model.elements {
        let ElementKind::BeamColumn {
            section, nodes: en, ..
        } = &e.kind
        else {
            continue;
        };
        let Some(s) = sections.get(section) else {
            continue;
        };
        let SectionKind::RcRect(rc) = &s.kind else {
            continue;
        };
        let Some(&idx) = built.element_index.get(&e.tag) else {
            continue;
        };
        let secs = built.domain.elements()[idx].sections();
        if secs.is_empty() {
            continue;
        }
        let item = || format!("element {}", e.tag);
        let n_g = gravity
            .get(&e.tag)
            .ok_or_else(|| cap(item(), "no gravity axial load".into()))?;
        if n_g.len() != secs.len() {
            return Err(cap(
                item(),
                format!("{} gravity loads for {} sections", n_g.len(), secs.len()),
            ));
        }
        let axes = Model::local_axes_in(&nodes, &transfs, e)
            .ok_or_else(|| cap(item(), "no local axes".into()))?;
        let fc = materials
            .get(&rc.cover_material)
            .and_then(|m| match &m.law {
                crate::model::material::MaterialLaw::Concrete01 { fpc, .. }
                | crate::model::material::MaterialLaw::Concrete02 { fpc, .. } => {
                    Some(fpc.abs() / 1e6)
                }
                _ => None,
            })
            .ok_or_else(|| {
                cap(
                    item(),
                    format!("cover material {} is not Concrete01/02", rc.cover_material),
                )
            })?;
        // Effective depths (mm): half the dimension + the farthest bar row.
        let ymax = rc.bars.iter().map(|b| b.0.abs()).fold(0.0, f64::max);
        let zmax = rc.bars.iter().map(|b| b.1.abs()).fold(0.0, f64::max);
        let (b_mm, h_mm) = (rc.b * 1000.0, rc.h * 1000.0);
        let dy = (rc.b / 2.0 + ymax) * 1000.0; // shear along y: depth along y
        let dz = (rc.h / 2.0 + zmax) * 1000.0;
        let ag = b_mm * h_mm;
        let bar_area_mm2 = rc.bars.iter().map(|b| b.2).sum::<f64>() * 1e6;
        let fy_mpa = materials
            .get(&rc.bar_material)
            .and_then(|m| match &m.law {
                crate::model::material::MaterialLaw::Steel01 { fy, .. }
                | crate::model::material::MaterialLaw::Steel02 { fy, .. } => Some(fy / 1e6),
                _ => None,
            })
            .ok_or_else(|| {
                cap(
                    item(),
                    format!("bar material {} is not Steel01/02", rc.bar_material),
                )
            })?;
        let ends_at = |which: usize| -> usize {
            let mut best = 0;
            for (k, (xi, _)) in secs.iter().enumerate() {
                let target = if which == 0 { 0.0 } else { 1.0 };
                if (xi - target).abs() < (secs[best].0 - target).abs() {
                    best = k;
                }
            }
            best
        };
        let mut ends = Vec::with_capacity(2);
        let mut undamaged = Vec::with_capacity(2);
        for which in 0..2 {
            let k = ends_at(which);
            let (xi, sec) = secs[k];
            let n = n_g[k];
            let now = section_capacity(sec, n, st);
            let from_map = match &reference {
                Reference::Map(r) => r.get(&e.tag).map(|m| m.undamaged[which].section),
                _ => None,
            };
            let und = match (&reference, from_map) {
                (_, Some(u)) => u,
                (Reference::Same, _) => now,
                _ => {
                    let mut fresh = sec.boxed_clone();
                    fresh.revert_to_start();
                    section_capacity(fresh.as_ref(), n, st)
                }
            };
            let nu = -n; // ACI: compression positive
                         // Diagonal tension (member shear; the fibre FE does not model it): reported.
            let vc = [
                aci_shear(fc, h_mm, dy, ag, nu),
                aci_shear(fc, b_mm, dz, ag, nu),
            ];
            // Sliding across the cut section: shear friction, residual with the bars'
            // tension capacity and the concrete's compression capacity.
            let ratio = |a: f64, b: f64| if b > 0.0 { (a / b).min(1.0) } else { 1.0 };
            let rt = ratio(now.tension_n, und.tension_n);
            let rc_ = ratio(now.compression_n, und.compression_n);
            let vf0 = shear_friction(fc, fy_mpa, bar_area_mm2, ag, nu, 1.0, 1.0);
            let vf = shear_friction(fc, fy_mpa, bar_area_mm2, ag, nu, rt, rc_);
            let lost = !now.carries_axial_load
                || (0..2).all(|a| now.moment_nm[a] < LOST_MOMENT_RATIO * und.moment_nm[a]);
            // κz bends across the width b (along y), κy across the depth h (along z).
            let lp = [rc.b / 2.0, rc.h / 2.0];
            let rot = |c: &SectionCapacity| {
                (0..2)
                    .map(|a| c.curvature_left[a] * lp[a])
                    .fold(f64::INFINITY, f64::min)
            };
            ends.push(EndCapacity {
                xi,
                section: now,
                shear_n: [vf, vf],
                diagonal_tension_n: vc,
                rotation_left: if lost { 0.0 } else { rot(&now) },
                lost,
            });
            undamaged.push(EndCapacity {
                xi,
                section: und,
                shear_n: [vf0, vf0],
                diagonal_tension_n: vc,
                rotation_left: rot(&und),
                lost: false,
            });
        }
        let [ni, nj] = *en;
        let p = |t: u32| {
            nodes
                .get(&t)
                .map(|n| n.xyz())
                .ok_or_else(|| cap(item(), format!("unknown node {t}")))
        };
        out.insert(
            e.tag,
            MemberCapacity {
                element: e.tag,
                axes,
                nodes: [p(ni)?, p(nj)?],
                ends: [ends[0], ends[1]],
                undamaged: [undamaged[0], undamaged[1]],
            },
        );
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fe::material::{Steel01, Steel01Params, UniaxialMaterial};
    use crate::fe::section::fiber::FiberSection;

    /// A b × h rectangle of elastic–perfectly-plastic steel fibres (ny × nz), fy in Pa.
    fn epp_rect(b: f64, h: f64, ny: usize, nz: usize, fy: f64) -> FiberSection {
        let mut fibers: Vec<(f64, f64, f64, Box<dyn UniaxialMaterial>)> = Vec::new();
        let (dy, dz) = (b / ny as f64, h / nz as f64);
        for i in 0..ny {
            for j in 0..nz {
                let m = Steel01::new(Steel01Params::new(fy, 200e9, 0.0)).unwrap();
                fibers.push((
                    -b / 2.0 + (i as f64 + 0.5) * dy,
                    -h / 2.0 + (j as f64 + 0.5) * dz,
                    dy * dz,
                    Box::new(m),
                ));
            }
        }
        FiberSection::new(fibers, 1e6).unwrap()
    }

    /// Closed forms of an EPP rectangle: N_p = fy·b·h; M_p about y (depth h along z) =
    /// fy·b·h²/4·(1 − (N/N_p)²), about z = fy·h·b²/4·(1 − (N/N_p)²) (plastic interaction
    /// of a rectangle, e.g. Neal, *The plastic methods of structural analysis*, §6.2).
    /// Fibre discretisation error of a 40-layer mesh is below 0.1 %.
    #[test]
    fn epp_rectangle_matches_plastic_closed_forms() {
        let (b, h, fy) = (0.1, 0.2, 300e6);
        let s = epp_rect(b, h, 40, 40, fy);
        let np = fy * b * h;
        let st = PushSettings::default();
        for ratio in [0.0, -0.3, 0.5] {
            let n = ratio * np;
            let c = section_capacity(&s, n, &st);
            assert!(
                (c.compression_n - np).abs() < 1e-9 * np,
                "{}",
                c.compression_n
            );
            assert!((c.tension_n - np).abs() < 1e-9 * np);
            let f = 1.0 - ratio * ratio;
            let my = fy * b * h * h / 4.0 * f;
            let mz = fy * h * b * b / 4.0 * f;
            let ey = (c.moment_nm[1] - my).abs() / my;
            let ez = (c.moment_nm[0] - mz).abs() / mz;
            assert!(
                ey < 2e-3,
                "N/Np {ratio}: My {} vs {my} ({ey})",
                c.moment_nm[1]
            );
            assert!(
                ez < 2e-3,
                "N/Np {ratio}: Mz {} vs {mz} ({ez})",
                c.moment_nm[0]
            );
            assert!(c.carries_axial_load);
            // Yield curvature of the bilinear idealisation: the EPP section yields at
            // κ = 2εy/h and reaches 0.75 Mp while still nearly elastic at N = 0.
            if ratio == 0.0 {
                let ky = 2.0 * fy / 200e9 / h;
                let k = c.curvature_yield[1];
                assert!(k > 0.9 * ky && k < 1.6 * ky, "κy {k} vs first yield {ky}");
            }
        }
    }

    /// An axial load beyond the squash load cannot be carried: moment 0, flagged.
    #[test]
    fn load_beyond_squash_is_not_carried() {
        let (b, h, fy) = (0.1, 0.1, 300e6);
        let s = epp_rect(b, h, 10, 10, fy);
        let c = section_capacity(&s, -1.2 * fy * b * h, &PushSettings::default());
        assert!(!c.carries_axial_load);
        assert_eq!(c.moment_nm, [0.0, 0.0]);
    }

    /// ACI 318-14 by hand: f′c = 25 MPa, 300 × 500 mm, d = 450 mm, N_u = 0 →
    /// V_c = 0.17·5·300·450 = 114 750 N; N_u = 14·A_g → twice that; tension
    /// N_u = −3.5·A_g → 0.
    #[test]
    fn aci_shear_by_hand() {
        let ag = 300.0 * 500.0;
        assert!((aci_shear(25.0, 300.0, 450.0, ag, 0.0) - 114_750.0).abs() < 1e-6);
        assert!((aci_shear(25.0, 300.0, 450.0, ag, 14.0 * ag) - 229_500.0).abs() < 1e-6);
        assert_eq!(aci_shear(25.0, 300.0, 450.0, ag, -3.5 * ag), 0.0);
        assert_eq!(aci_shear(25.0, 300.0, 450.0, ag, -10.0 * ag), 0.0);
    }

    /// ACI 318-14 §22.9 by hand: f′c = 22.5 MPa, fy = 457.7 MPa, 12 bars of 9.621 mm²,
    /// A_c = 100 × 100 mm: μ·A_vf·f_y = 1.4·115.45·457.7 = 73 979 N, above the limit
    /// 0.2·22.5·10 000 = 45 000 N; without bars and with N_u = 10 kN: 14 000 N; residual
    /// r_c = 0.5 halves the limit.
    #[test]
    fn shear_friction_by_hand() {
        let avf = 12.0 * 9.621;
        let v = shear_friction(22.5, 457.7, avf, 1e4, 0.0, 1.0, 1.0);
        assert!((v - 45_000.0).abs() < 1e-6, "{v}");
        let v = shear_friction(22.5, 457.7, 0.0, 1e4, 10_000.0, 1.0, 1.0);
        assert!((v - 14_000.0).abs() < 1e-6, "{v}");
        let v = shear_friction(22.5, 457.7, avf, 1e4, 0.0, 1.0, 0.5);
        assert!((v - 22_500.0).abs() < 1e-6, "{v}");
        let v = shear_friction(22.5, 457.7, avf, 1e4, -1e6, 1.0, 1.0);
        assert_eq!(v, 0.0);
    }
}

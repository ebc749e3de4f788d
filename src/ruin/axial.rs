//! The axial (normal) rows of a connection: BCB's two one-way rows or one two-way row, the
//! two-way row's breaking rule, and a debug trace of the axial error's sign changes.
//!
//! **BCB's form** ([`AxialRows::Bcb`], CT 22 rows 0 and 1, `super::connection`):
//! compression is a `btGeneric6DofConstraint` whose normal axis X has the limits
//! [0, 99999] m, tension one with [−99999, 0] m. Bullet makes a limit row only while the
//! limit is violated (`btTranslationalLimitMotor::testLimitValue`) and, for lo ≠ hi, lets
//! it push one way only (`btGeneric6DofConstraint::get_limit_motor_info2`: impulse bounds
//! (−∞, 0] below the lower limit, [0, ∞) above the upper). So in any substep the axial
//! load is carried by the compression row when the axial offset x (below) is negative and
//! by the tension row when it is positive — never by both — and the row that takes over
//! after a sign change of x starts its Gauss–Seidel solve from zero.
//!
//! **Two-way row** ([`AxialRows::TwoWay`]): row 0 locks X at [0, 0] (Bullet: "limited low
//! and high simultaneously", impulse bounds (−∞, ∞)), so one row carries compression and
//! tension and a sign change of x does not hand the load to another constraint. Row 1
//! (tension) is kept as a constraint without locked axes (no solver rows) so that the
//! connection keeps BCB's seven constraints and the monitor's indices. Bullet's own
//! breaking test is sign-blind (|λ| ≥ threshold, and it clamps the row's impulse at
//! ±threshold), so the stage sets row 0's Bullet threshold before every substep to the
//! breaking impulse of the sense the row pushed in during the last substep (the smaller
//! of the two after a substep without impulse), enables the row again when Bullet
//! disabled it below the breaking impulse of the sense it pushed in, and applies the
//! strength of that sense after every substep ([`two_way_breaks`]):
//!
//! the row breaks in compression when λ·s_c ≥ C·κ·Δt, in tension when −λ·s_c ≥ T·κ·Δt,
//!
//! with λ the row's applied impulse in the substep (N·s, Bullet's row sign), s_c = −1 the
//! sign of a compressive impulse (Bullet's row Jacobian is +X on body A, and a row that
//! pushes B away along +X applies −X to A; checked in `tests/it/ruin/axial_rows.rs`),
//! C and T the connection's compression and tension strengths (N), κ BCB's linear
//! correction 2.2 and Δt the substep (s) — BCB's own breaking impulses (docs/bcb.md
//! §3.1), each in its own sense. As in BCB, a break in one sense leaves the other: the
//! stage turns row 0 into BCB's one-way row of the other sense (limits [−99999, 0] m or
//! [0, 99999] m, that sense's breaking impulse; `World::set_constraint_limit`), and when
//! that breaks too the placeholder row 1 is disabled with it. Differences from BCB remain
//! in the substep in which the load reverses: a compression that follows a tensile
//! substep is clamped at T·κ·Δt for that substep (if T < C), and a tension that follows a
//! compressive substep can transmit up to C·κ·Δt in the substep in which it breaks the row
//! (BCB's tension row would have been clamped at T·κ·Δt); measured on frame3 LC5
//! rigid-only, such breaks carried at most 1.8 times T·κ·Δt. The one-way row left after
//! a break acts from the next substep on.
//! A connection with no strength in one sense (an FE-derived residual capacity gone in that
//! sense, docs/handoff.md §3) keeps BCB's two one-way rows: the row without strength starts
//! broken and the other one holds as in BCB.
//!
//! **Trace** (debugging, off unless `fem2rbd run --trace-axial FILE` asks for it,
//! [`super::settings::AxialTraceSettings`]): after every substep from `--trace-from` s
//! on, the sign of every elastic connection's
//! axial offset x, its changes (in BCB's form: a hand-over between the compression and the
//! tension row) and the **kicks** — a dynamic body whose centre velocity changes by more
//! than `--trace-axial-kick` m/s (default 0.1) in one substep — and whether a
//! connection of that body changed sign just before (the rows of the kicked substep were
//! chosen on a new sign). Written by the pipeline after the ruin stage (`RuinStage::axial_trace_report`).

use nalgebra::Isometry3;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::fmt::Write;

/// How a connection's axial (normal) direction is held while it is elastic (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AxialRows {
    /// BCB's CT 22: a one-way compression row and a one-way tension row.
    #[default]
    Bcb,
    /// One two-way locked row, broken by the stage in the sense it pushes
    /// ([`two_way_breaks`]).
    TwoWay,
}

/// Which senses a two-way axial row still holds (the stage's bookkeeping).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AxialLeft {
    /// The two-way row: compression and tension.
    Both,
    /// Broken in tension: BCB's one-way compression row is left.
    Compression,
    /// Broken in compression: BCB's one-way tension row is left.
    Tension,
    /// Broken in both senses.
    None,
}

/// Bullet's sign of a compressive (pushing apart) impulse of the axial row (module docs).
pub const COMPRESSION_SIGN: f64 = -1.0;

/// The two-way axial row's breaking rule (module docs): `impulse` the row's applied
/// impulse in the substep (N·s, Bullet's sign), `compression_ns` and `tension_ns` BCB's
/// breaking impulses C·κ·Δt and T·κ·Δt (N·s). True when the impulse reaches the breaking
/// impulse of the sense it acts in.
pub fn two_way_breaks(impulse: f64, compression_ns: f64, tension_ns: f64) -> bool {
    let pushing = impulse * COMPRESSION_SIGN;
    if pushing >= 0.0 {
        pushing >= compression_ns && pushing > 0.0
    } else {
        -pushing >= tension_ns
    }
}

/// The axial offset x of a connection (m): the position of its frame on body B relative to
/// its frame on body A along the frame's X axis (the normal A → B), in A's frame — Bullet's
/// `btGeneric6DofConstraint::calculateLinearInfo` with `useLinearReferenceFrameA`. x < 0:
/// B has moved towards A (compression).
pub fn axial_offset(
    pose_a: &Isometry3<f64>,
    pose_b: &Isometry3<f64>,
    frame_a: &Isometry3<f64>,
    frame_b: &Isometry3<f64>,
) -> f64 {
    let fa = pose_a * frame_a;
    let fb = pose_b * frame_b;
    let d = fa.rotation.inverse() * (fb.translation.vector - fa.translation.vector);
    d.x
}

/// The debug trace of the module docs.
pub(crate) struct AxialTrace {
    path: std::path::PathBuf,
    from_s: f64,
    kick_mps: f64,
    names: Vec<String>,
    prev_sign: Vec<Option<i8>>,
    prev_vel: Option<Vec<[f64; 3]>>,
    /// Bodies with a sign change after the previous substep.
    switched_prev: Vec<bool>,
    counts: AxialCounts,
    kick_rows: Vec<String>,
    break_rows: Vec<String>,
}

/// What [`AxialTrace`] counts from `FEM2RBD_AXIAL_TRACE_FROM` on.
#[derive(Default)]
struct AxialCounts {
    /// Substeps traced.
    substeps: u64,
    /// Sign changes of each connection's axial offset.
    switches: BTreeMap<usize, u64>,
    /// Body velocity jumps over the kick threshold.
    kicks: u64,
    /// Kicks of a body one of whose connections changed sign in the substep before.
    kicks_after_switch: u64,
    /// Kicks of a body one of whose connections changed sign in the same substep.
    kicks_same_substep: u64,
    /// Dynamic bodies × substeps traced (the baseline).
    body_substeps: u64,
    /// Of those, the ones after a sign change of one of the body's connections.
    body_substeps_after_switch: u64,
}

impl AxialTrace {
    /// The trace of `settings` over the input bodies `names` and `connections`
    /// connections.
    pub(crate) fn new(
        settings: &super::settings::AxialTraceSettings,
        names: Vec<String>,
        connections: usize,
    ) -> AxialTrace {
        let n = names.len();
        AxialTrace {
            path: settings.path.clone(),
            from_s: settings.from_s,
            kick_mps: settings.kick_mps,
            names,
            prev_sign: vec![None; connections],
            prev_vel: None,
            switched_prev: vec![false; n],
            counts: AxialCounts::default(),
            kick_rows: Vec::new(),
            break_rows: Vec::new(),
        }
    }

    /// After one substep ending at `t`: `axial[c]` the offset of connection c if its axial
    /// rows are on, its bodies, and the dynamic bodies' velocities (`None`: passive).
    pub(crate) fn after_substep(
        &mut self,
        t: f64,
        axial: &[Option<f64>],
        pairs: &[(usize, usize)],
        vels: &[Option<[f64; 3]>],
    ) {
        let mut switched_now = vec![false; self.names.len()];
        for (c, x) in axial.iter().enumerate() {
            let s = x.map(|x| if x < 0.0 { -1i8 } else { 1 });
            if let (Some(p), Some(s)) = (self.prev_sign[c], s) {
                if p != s && t >= self.from_s {
                    *self.counts.switches.entry(c).or_default() += 1;
                    switched_now[pairs[c].0] = true;
                    switched_now[pairs[c].1] = true;
                }
            }
            self.prev_sign[c] = s;
        }
        let cur: Vec<[f64; 3]> = vels.iter().map(|v| v.unwrap_or([0.0; 3])).collect();
        if t >= self.from_s {
            if let Some(prev) = &self.prev_vel {
                self.counts.substeps += 1;
                for (i, v) in vels.iter().enumerate() {
                    if v.is_none() {
                        continue;
                    }
                    self.counts.body_substeps += 1;
                    if self.switched_prev[i] {
                        self.counts.body_substeps_after_switch += 1;
                    }
                    let dv = (0..3)
                        .map(|k| (cur[i][k] - prev[i][k]).powi(2))
                        .sum::<f64>()
                        .sqrt();
                    if dv > self.kick_mps {
                        self.counts.kicks += 1;
                        if self.switched_prev[i] {
                            self.counts.kicks_after_switch += 1;
                        }
                        if switched_now[i] {
                            self.counts.kicks_same_substep += 1;
                        }
                        self.kick_rows.push(format!(
                            "{t:.4},{},{dv:.4},{},{}",
                            self.names[i], self.switched_prev[i], switched_now[i]
                        ));
                    }
                }
            }
        }
        self.prev_vel = Some(cur);
        self.switched_prev = switched_now;
    }

    /// A two-way row broke at `t` with impulse `lambda` (N·s) against the breaking
    /// impulses `c_ns`, `t_ns` (any time, not only from the trace's start).
    pub(crate) fn note_break(
        &mut self,
        t: f64,
        connection: usize,
        lambda: f64,
        c_ns: f64,
        t_ns: f64,
    ) {
        self.break_rows.push(format!(
            "{t:.4},{connection},{lambda:.6},{c_ns:.6},{t_ns:.6}"
        ));
    }

    /// Where the trace goes and its text (`pairs`: each connection's bodies). The
    /// pipeline writes it (`crate::pipeline::ruin_stage`): only `output` writes files.
    pub(crate) fn report(&self, pairs: &[(usize, usize)]) -> (std::path::PathBuf, String) {
        let mut f = String::new();
        // Writing into a String cannot fail.
        let _ = self.write_into(&mut f, pairs);
        (self.path.clone(), f)
    }

    fn write_into(&self, f: &mut String, pairs: &[(usize, usize)]) -> std::fmt::Result {
        let total: u64 = self.counts.switches.values().sum();
        let rate = |a: u64, b: u64| if b > 0 { a as f64 / b as f64 } else { f64::NAN };
        writeln!(
            f,
            "# axial trace from t = {} s, kick > {} m/s",
            self.from_s, self.kick_mps
        )?;
        writeln!(f, "substeps {}", self.counts.substeps)?;
        writeln!(f, "sign_changes {total}")?;
        writeln!(f, "connections_changing {}", self.counts.switches.len())?;
        writeln!(f, "kicks {}", self.counts.kicks)?;
        writeln!(
            f,
            "kicks_after_change {} ({:.3})",
            self.counts.kicks_after_switch,
            rate(self.counts.kicks_after_switch, self.counts.kicks)
        )?;
        writeln!(
            f,
            "kicks_same_substep_change {} ({:.3})",
            self.counts.kicks_same_substep,
            rate(self.counts.kicks_same_substep, self.counts.kicks)
        )?;
        writeln!(
            f,
            "baseline body_substeps_after_change {} of {} ({:.4})",
            self.counts.body_substeps_after_switch,
            self.counts.body_substeps,
            rate(
                self.counts.body_substeps_after_switch,
                self.counts.body_substeps
            )
        )?;
        let mut top: Vec<(&usize, &u64)> = self.counts.switches.iter().collect();
        top.sort_by(|a, b| b.1.cmp(a.1).then(a.0.cmp(b.0)));
        for (c, k) in top.iter().take(25) {
            let (a, b) = pairs[**c];
            writeln!(f, "conn {c} {} - {}: {k}", self.names[a], self.names[b])?;
        }
        writeln!(f, "# two-way breaks: t,connection,impulse,C_ns,T_ns")?;
        for r in &self.break_rows {
            writeln!(f, "{r}")?;
        }
        writeln!(f, "# kicks: t,body,dv,change_before,change_same")?;
        for r in &self.kick_rows {
            writeln!(f, "{r}")?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn breaking_rule_uses_the_strength_of_the_sense() {
        // compressive impulse (Bullet sign −): 5 against C = 4 breaks, against C = 6 not
        assert!(two_way_breaks(-5.0, 4.0, 1.0));
        assert!(!two_way_breaks(-5.0, 6.0, 1.0));
        // tensile impulse (+): 2 against T = 1 breaks, against T = 3 not, whatever C
        assert!(two_way_breaks(2.0, 100.0, 1.0));
        assert!(!two_way_breaks(2.0, 0.5, 3.0));
    }
}

//! `keyframes.csv`: every body's pose on one timeline at 25 frames/s, the FE stage's
//! keyframes (from the FE state, up to Tc) then the ruin stage's frames (after Tc).
//! Columns `t,name,x,y,z,qw,qx,qy,qz`: time s (4 decimals), position m (6 decimals),
//! unit quaternion (8 decimals); rows by time, then body order.
use crate::bullet::Pose;
use crate::output::csv_text::field;
use std::fmt::Write as _;

/// Header line.
pub const HEADER: &str = "t,name,x,y,z,qw,qx,qy,qz";

/// The CSV text of `frames` (time, one pose per body in `names` order).
pub fn keyframes_csv(names: &[&str], frames: &[(f64, &[Pose])]) -> String {
    let mut s = String::from(HEADER);
    s.push('\n');
    let names: Vec<_> = names.iter().map(|n| field(n)).collect();
    for (t, poses) in frames {
        for (name, p) in names.iter().zip(poses.iter()) {
            let (x, q) = (p.position, p.orientation);
            let _ = writeln!(
                s,
                "{:.4},{name},{:.6},{:.6},{:.6},{:.8},{:.8},{:.8},{:.8}",
                t + 0.0,
                x[0] + 0.0,
                x[1] + 0.0,
                x[2] + 0.0,
                q[0] + 0.0,
                q[1] + 0.0,
                q[2] + 0.0,
                q[3] + 0.0
            );
        }
    }
    s
}

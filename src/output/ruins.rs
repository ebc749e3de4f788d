//! `ruins.csv`: where every rigid body ended up. One row per body in body order:
//! `name,group,type,material,element,x,y,z,qw,qx,qy,qz,at_rest` — position in m
//! (6 decimals), orientation as a unit quaternion (8 decimals), `at_rest` 1/0 (the ruin
//! stage's rest test per body; `-` when no ruin stage ran).
use crate::body::BodyId;
use crate::bullet::Pose;
use crate::output::csv_text::field;
use std::fmt::Write as _;

/// Header line of `ruins.csv`.
pub const HEADER: &str = "name,group,type,material,element,x,y,z,qw,qx,qy,qz,at_rest";

/// One body's identity columns.
#[derive(Debug, Clone, PartialEq)]
pub struct RuinRow<'a> {
    /// Identity (columns `name,group,type,material,element`).
    pub id: &'a BodyId,
    /// Final pose.
    pub pose: Pose,
    /// At rest (None = no ruin stage).
    pub at_rest: Option<bool>,
}

/// The CSV text.
pub fn ruins_csv(rows: &[RuinRow]) -> String {
    let mut s = String::from(HEADER);
    s.push('\n');
    for r in rows {
        let p = r.pose.position;
        let q = r.pose.orientation;
        let rest = match r.at_rest {
            Some(true) => "1",
            Some(false) => "0",
            None => "-",
        };
        let _ = writeln!(
            s,
            "{},{},{},{},{},{:.6},{:.6},{:.6},{:.8},{:.8},{:.8},{:.8},{rest}",
            field(&r.id.name()),
            field(r.id.group()),
            field(r.id.body_type().as_str()),
            field(r.id.material()),
            field(&r.id.element_field()),
            p[0] + 0.0,
            p[1] + 0.0,
            p[2] + 0.0,
            q[0] + 0.0,
            q[1] + 0.0,
            q[2] + 0.0,
            q[3] + 0.0
        );
    }
    s
}

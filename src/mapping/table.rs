//! The rigid-body table: one CSV line per body, for `fem2rbd map`.
//! Building the text is here; writing it is the caller's (through `output::atomic`).
//!
//! Columns: `name, group, type, material, element, kind, cx, cy, cz, qw, qx, qy, qz,
//! hx, hy, hz, mass_kg, ixx, iyy, izz` — centre (m), unit quaternion (w, x, y, z) of the
//! box axes, half extents along local x, y, z (m), mass (kg), principal inertia about the
//! centre along the local axes (kg·m², uniform box). Numbers use Rust's shortest
//! round-trip form, so the same bodies give the same bytes.

use super::geometry::RigidBox;
use std::fmt::Write;

/// The CSV header line (without newline).
pub const HEADER: &str =
    "name,group,type,material,element,kind,cx,cy,cz,qw,qx,qy,qz,hx,hy,hz,mass_kg,ixx,iyy,izz";

/// RFC 4180 quoting, as every table fem2rbd writes ([`crate::output::csv_text`]).
fn field(s: &str) -> String {
    crate::output::csv_text::field(s).into_owned()
}

/// The whole table, header first, one line per body in the given order.
pub fn bodies_csv(bodies: &[RigidBox]) -> String {
    let mut out = String::from(HEADER);
    out.push('\n');
    for b in bodies {
        let q = b.quaternion_wxyz();
        let i = b.principal_inertia_kgm2();
        let _ = write!(
            out,
            "{},{},{},{},{},{:?}",
            field(&b.id.name()),
            field(b.id.group()),
            field(b.id.body_type().as_str()),
            field(b.id.material()),
            b.id.element_field(),
            b.kind
        );
        for v in b
            .centre
            .iter()
            .chain(&q)
            .chain(&b.half_extents)
            .chain(std::iter::once(&b.mass_kg))
            .chain(&i)
        {
            let _ = write!(out, ",{v}");
        }
        out.push('\n');
    }
    out
}

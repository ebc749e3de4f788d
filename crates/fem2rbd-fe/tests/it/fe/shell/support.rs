//! The wall mesh the shell tests share.
use std::fmt::Write as _;

/// Model text: `header` (name, materials, the `[[section]]` tag 10), then a vertical wall
/// in the XZ plane, `b` wide and `h` tall (m), meshed `nx` × `nz` with shell elements
/// `Wall` of section 10, its base (z = 0) fixed. Node tags 100·j + i + 1.
pub fn wall_mesh(header: &str, b: f64, h: f64, nx: usize, nz: usize) -> String {
    let mut t = String::from(header);
    let tag = |i: usize, j: usize| 100 * j + i + 1;
    for j in 0..=nz {
        for i in 0..=nx {
            writeln!(
                t,
                "[[node]]\ntag = {}\nx = {:?}\ny = 0.0\nz = {:?}",
                tag(i, j),
                b * i as f64 / nx as f64,
                h * j as f64 / nz as f64
            )
            .unwrap();
        }
    }
    for i in 0..=nx {
        writeln!(
            t,
            "[[support]]\nnode = {}\ndofs = [1, 1, 1, 1, 1, 1]",
            tag(i, 0)
        )
        .unwrap();
    }
    let mut e = 1;
    for j in 0..nz {
        for i in 0..nx {
            writeln!(
                t,
                "[[element]]\ntag = {e}\ntype_name = \"Wall\"\ngroup = 1\ntype = \"shell\"\nnodes = [{}, {}, {}, {}]\nsection = 10",
                tag(i, j),
                tag(i + 1, j),
                tag(i + 1, j + 1),
                tag(i, j + 1)
            )
            .unwrap();
            e += 1;
        }
    }
    t
}

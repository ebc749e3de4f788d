//! Support reactions summed over the building and split by element group: what a base
//! shear is, and which part of it the walls carry.
//!
//! The reaction of a supported node is R = F_int − P at its fixed DOFs
//! ([`Domain::reactions`], OpenSees `reactions` without `-dynamic`: no inertia or damping
//! force). The base shear along a direction is V = −ΣR. Split by element group it is
//! −Σ of each group's element resisting forces at the supported DOFs: `frame` for the
//! 2-node beam-columns, `wall` for the 4-node shells; the groups add up to V when no load
//! is applied at a support in that direction. Units N and N·m.
use crate::fe::domain::{Domain, NDF};
use crate::fe::element::MAX_ELEMENT_NODES;

/// The summed reactions of a state and the base shear carried by each element group.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ReactionSum {
    /// ΣR over the supported nodes `[Rx, Ry, Rz, Mx, My, Mz]` (N, N·m; the moments are the
    /// sums of the nodal reaction moments, not moments about a point).
    pub total: [f64; NDF],
    /// Base shear along x and y carried by the beam-columns (N).
    pub frame: [f64; 2],
    /// Base shear along x and y carried by the shells (N).
    pub wall: [f64; 2],
}

impl ReactionSum {
    /// The reactions of the domain's trial state (the committed one after a commit).
    pub fn of(domain: &Domain) -> Self {
        let mut out = ReactionSum::default();
        for (_, r) in domain.reactions() {
            for k in 0..NDF {
                out.total[k] += r[k];
            }
        }
        let mut f = [0.0; NDF * MAX_ELEMENT_NODES];
        for el in domain.elements() {
            let n = el.nodes().len();
            el.resisting_force_into(&mut f[..NDF * n]);
            let group = if n == 2 {
                &mut out.frame
            } else {
                &mut out.wall
            };
            for (a, &node) in el.nodes().iter().enumerate() {
                let fixed = domain.fixity(node);
                for d in 0..2 {
                    if fixed[d] {
                        group[d] -= f[NDF * a + d];
                    }
                }
            }
        }
        out
    }

    /// Base shear V = −ΣR along `d` (0 = x, 1 = y), N.
    pub fn base_shear(&self, d: usize) -> f64 {
        -self.total[d]
    }
}

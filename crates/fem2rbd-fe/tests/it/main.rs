//! The integration tests of `fem2rbd-fe`, as one test crate (one link after a change),
//! laid out like `src/`: `fe/element/*` tests the elements, `fe/verify/*` compares whole
//! analyses with OpenSees, and so on. Shared helpers sit in each folder's `support.rs`.
//! Files of the repository (models, records, OpenSees fixtures) are found from
//! [`repo_root`].
#![allow(clippy::needless_range_loop)]

use std::path::PathBuf;

/// The repository's top folder (this crate lives in `crates/fem2rbd-fe`).
pub fn repo_root() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

mod collapse {
    mod criteria;
}
mod export {
    mod closed_form;
}
mod fe {
    mod analysis {
        mod algorithms;
        mod divergence;
        mod frame3;
        mod lanczos;
        mod modal;
        mod solver;
        mod static_analysis;
        mod support;
        mod threads;
        mod transient;
    }
    mod element {
        mod cantilever;
        mod disp_damping;
        mod elastica;
        mod opensees;
        mod plastic;
        mod section;
        mod state;
        mod support;
    }
    mod material {
        mod opensees;
        mod protocol;
    }
    mod shell {
        mod building;
        mod corotational;
        mod frame_modal;
        mod model;
        mod nonlinear;
        mod stiffness;
        mod support;
        mod wall;
    }
    mod verify {
        mod case1;
        mod lc1;
        mod lc5;
        mod modal;
        mod pushover;
        mod support;
    }
}
mod model {
    pub(crate) mod building;
    mod errors;
    mod frame3;
    mod generate;
}
mod motion {
    mod integrate;
    mod read;
}

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

/// Runs an OpenSees script or driver (`python3 …` with openseespy 3.7.1), asserts that it
/// succeeded (its output in the message otherwise) and returns the JSON object on the
/// last line of its standard output that starts with `{` — how every exported script and
/// test driver reports its results.
pub fn openseespy_json(cmd: &mut std::process::Command) -> serde_json::Value {
    let out = cmd
        .output()
        .expect("python3 with openseespy 3.7.1 (setup.sh installs it)");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "script failed (is openseespy 3.7.1 installed?):\n{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let last = stdout
        .lines()
        .rfind(|l| l.starts_with('{'))
        .unwrap_or_else(|| panic!("no JSON line in the script's output:\n{stdout}"));
    serde_json::from_str(last).expect("the script's last JSON line")
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
        mod building_modes;
        mod divergence;
        mod frame3;
        mod lanczos;
        mod modal;
        mod removal;
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
        mod implex;
        mod model;
        mod nonlinear;
        mod rw2;
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
    mod reference_import;
}
mod motion {
    mod integrate;
    mod read;
}

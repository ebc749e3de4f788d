//! The integration tests of `fem2rbd`, as one test crate (one link after a change), laid
//! out like `src/`: `cli/*` runs the real binary, `physics/*` includes the pybullet
//! cross-checks, `pipeline/*` whole runs with insta snapshots. The structural stages are
//! tested in `crates/fem2rbd-fe/tests/it`.
#![allow(clippy::needless_range_loop)]

mod support;

mod cli {
    mod export_opensees;
    mod fe;
    mod full_disk;
    mod hostile_inputs;
    mod import_opensees;
    mod interrupt;
    mod model;
    mod own_files;
    mod pushover;
    mod tower15_modal;
}
mod mapping {
    mod frame3;
    mod geometry;
    mod handoff_frame3;
    mod model_frame3;
    mod model_panels;
    mod overlap;
    mod shell_walls;
}
pub(crate) mod output {
    pub(crate) mod gltf_common;
    mod gltf_export;
    mod gltf_roundtrip;
    mod gltf_three;
    mod gltf_validator;
    mod gltf_vtk;
}
mod bullet {
    mod jointsolve;
    mod pybullet_debris;
    mod pybullet_scenes;
    mod stock_bullet;
    mod world;
}
mod pipeline {
    mod concrete_integration;
    mod ensemble;
    mod ensemble_distribution;
    mod groups_measures;
    mod handoff_continuity;
    mod library_slab;
    mod run_frame3;
    mod settings;
    mod wall_building;
}
mod plot {
    mod fonts;
    mod run_folder;
}
mod report {
    mod browser;
    mod command;
    mod ensemble;
    mod frame3;
    mod gltf_voids;
    pub(crate) mod study;
}
mod rescue {
    mod chambers;
    mod cli;
    pub(crate) mod ensemble;
    mod footprint;
    mod occupancy;
    mod plots;
    mod rebuild;
    mod route_map;
    mod routes;
    mod scene;
    mod stories;
    mod voids;
}
mod repo {
    mod anyhow_edge;
    mod docs;
    mod module_graph;
    mod no_env;
    mod no_unsafe;
    mod test_layout;
}
mod ruin {
    mod axial_rows;
    mod closed_form;
    mod contacts;
    mod landing;
    mod monitor;
    mod separation;
    mod speed;
    mod stage_ground;
    mod stage_statics;
    mod thresholds;
}
mod scene {
    mod cli;
    mod plausibility;
}
mod study {
    mod ensemble;
    mod fragility;
    mod local;
    mod ruins;
    mod slurm;
}

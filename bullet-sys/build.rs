//! Builds the C++ shim against Debian's double-precision Bullet and generates its Rust
//! declarations with bindgen (from the shim header only — never from Bullet's C++ headers).
//!
//! The shim is the C API (`shim/bullet_shim.cpp`) and the solver extensions, one file each
//! ([`SHIM_SOURCES`]). The extensions hold altered copies of Bullet's
//! `btSequentialImpulseConstraintSolver` code and were checked, bit for bit or against their
//! validation, against the versions in [`CHECKED_BULLET_VERSIONS`] only: any other version
//! is refused at build time.
//!
//! Override variables:
//! - `BULLET_SYS_PKG_CONFIG_NAME`: the pkg-config package to probe (default `bullet-float64`).
//!   Only a double-precision package works: the ABI self-check rejects anything else at run time.
//!
//! Emits `cargo:version=<modversion>` and `cargo:include=<dir>` so that dependents can read
//! `DEP_BULLET_VERSION` / `DEP_BULLET_INCLUDE`.
use std::{env, path::PathBuf};

/// The shim's C++ sources: the C API, then one file per solver extension (`shim/solvers.h`
/// is their private header).
const SHIM_SOURCES: [&str; 7] = [
    "shim/bullet_shim.cpp",
    "shim/solver_lean.cpp",
    "shim/solver_joint_setup.cpp",
    "shim/solver_packed_sweep.cpp",
    "shim/solver_warm_joint.cpp",
    "shim/solver_direct_joint.cpp",
    "shim/solver_parallel_island.cpp",
];

/// Bullet versions (pkg-config modversion) whose `btSequentialImpulseConstraintSolver` the
/// solver extensions were checked against: Debian 12's libbullet-dev 3.24.
const CHECKED_BULLET_VERSIONS: [&str; 1] = ["3.24"];

const DEBIAN_HINT: &str = "install Debian's Bullet development files and pkg-config:\n    \
     apt-get install libbullet-dev pkg-config libclang-dev clang\n\
     (libbullet-dev ships bullet-float64.pc, the double-precision build this crate needs)";

fn main() {
    println!("cargo:rerun-if-changed=shim/bullet_shim.h");
    println!("cargo:rerun-if-changed=shim/solvers.h");
    for file in SHIM_SOURCES {
        println!("cargo:rerun-if-changed={file}");
    }
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-env-changed=BULLET_SYS_PKG_CONFIG_NAME");
    println!("cargo:rerun-if-env-changed=PKG_CONFIG_PATH");
    println!("cargo:rerun-if-env-changed=LIBCLANG_PATH");

    let pc_name =
        env::var("BULLET_SYS_PKG_CONFIG_NAME").unwrap_or_else(|_| "bullet-float64".to_string());
    let lib = match pkg_config::Config::new().probe(&pc_name) {
        Ok(lib) => lib,
        Err(e) => {
            panic!("pkg-config could not find `{pc_name}` (Bullet 3.24, double precision): {e}\n{DEBIAN_HINT}")
        }
    };
    if !CHECKED_BULLET_VERSIONS.contains(&lib.version.as_str()) {
        panic!(
            "pkg-config package `{pc_name}` is Bullet {}, but the shim's solver extensions \
             (bullet-sys/shim/solver_*.cpp, altered copies of Bullet's \
             btSequentialImpulseConstraintSolver code) were checked against Bullet {} only.\n\
             Either install Debian 12's libbullet-dev 3.24 (apt-get install libbullet-dev on \
             Debian 12 bookworm), \
             or check every extension against the new version's \
             btSequentialImpulseConstraintSolver (the tests named in each file's header: \
             tests/it/bullet/stock_bullet.rs, tests/it/ruin/speed.rs, \
             tests/it/bullet/jointsolve.rs) and add the version to CHECKED_BULLET_VERSIONS \
             in bullet-sys/build.rs.",
            lib.version,
            CHECKED_BULLET_VERSIONS.join(", ")
        );
    }
    if !lib.defines.keys().any(|k| k == "BT_USE_DOUBLE_PRECISION") {
        panic!(
            "pkg-config package `{pc_name}` does not define BT_USE_DOUBLE_PRECISION: \
             fem2rbd needs the double-precision Bullet (`bullet-float64`)\n{DEBIAN_HINT}"
        );
    }

    // Eigen (header-only) for the shim's direct joint solve (Eigen::SimplicialLDLT).
    let eigen = match pkg_config::Config::new()
        .cargo_metadata(false)
        .probe("eigen3")
    {
        Ok(e) => e.include_paths,
        Err(_) => {
            let dir = PathBuf::from("/usr/include/eigen3");
            if !dir.join("Eigen/SparseCholesky").exists() {
                panic!(
                    "Eigen 3 not found (pkg-config `eigen3`, nor /usr/include/eigen3): the shim's \
                     direct joint solve needs it:\n    apt-get install libeigen3-dev"
                );
            }
            vec![dir]
        }
    };

    let mut build = cc::Build::new();
    build
        .cpp(true)
        .files(SHIM_SOURCES)
        .include("shim")
        .flag("-std=c++17")
        // The packed sweep repeats Bullet's row arithmetic operation for operation; no fused
        // multiply-adds, so it stays the same bits as the library's own function.
        .flag("-ffp-contract=off");
    for p in lib.include_paths.iter().chain(&eigen) {
        build.include(p);
    }
    // Forward the package's defines (BT_USE_DOUBLE_PRECISION) so the shim's btScalar
    // matches the library it links against.
    for (k, v) in &lib.defines {
        build.define(k, v.as_deref());
    }
    build.compile("bullet_shim");

    let bindings = bindgen::Builder::default()
        .header("shim/bullet_shim.h")
        .allowlist_function("bs_.*")
        .allowlist_type("bs_.*")
        .allowlist_var("BS_.*")
        .prepend_enum_name(false)
        .derive_default(true)
        .parse_callbacks(Box::new(bindgen::CargoCallbacks::new()))
        .generate()
        .unwrap_or_else(|e| {
            panic!("bindgen failed on shim/bullet_shim.h: {e}\n(it needs libclang: apt-get install libclang-dev clang)")
        });
    let out = PathBuf::from(env::var("OUT_DIR").expect("OUT_DIR set by cargo"));
    bindings
        .write_to_file(out.join("bindings.rs"))
        .expect("cannot write bindings.rs");

    println!("cargo:version={}", lib.version);
    if let Some(inc) = lib.include_paths.first() {
        println!("cargo:include={}", inc.display());
    }
}

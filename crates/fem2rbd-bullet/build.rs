//! Reads the Bullet version that `bullet-sys` linked (its `cargo:version` metadata, seen
//! here as `DEP_BULLET_VERSION` because bullet-sys declares `links = "bullet"`) and exposes
//! it to the crate as `FEM2RBD_BULLET_VERSION`, as `LINKED_BULLET_PKG_VERSION` (shown by `fem2rbd --version`).
fn main() {
    println!("cargo:rerun-if-env-changed=DEP_BULLET_VERSION");
    let version = std::env::var("DEP_BULLET_VERSION").unwrap_or_else(|_| "unknown".to_string());
    println!("cargo:rustc-env=FEM2RBD_BULLET_VERSION={version}");
}

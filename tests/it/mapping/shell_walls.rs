//! Layered-shell walls in the rigid-body mapping (`tests/fixtures/wall-layered-1x6.toml`,
//! the wall of `crates/fem2rbd-fe/tests/it/fe/shell/model.rs`).
use fem2rbd::mapping::{self, MapOptions};
use fem2rbd::model::Model;

/// A layered-shell wall maps to one box per element, named `Wall:1:tag`, as thick as
/// the section (Σ layer thicknesses) and as large as the element (0.5 m × 0.5 m).
#[test]
fn layered_wall_elements_map_to_boxes_of_the_section_thickness() {
    let model =
        Model::load(crate::support::root().join("tests/fixtures/wall-layered-1x6.toml")).unwrap();
    let mapped = mapping::map_to_boxes(
        &mapping::from_model(&model).unwrap(),
        &MapOptions::default(),
    )
    .unwrap();
    assert_eq!(mapped.bodies.len(), 24);
    let thick = 4.0 * 0.05 + 2.0 * 0.002 + 2.0 * 0.0005;
    for (k, b) in mapped.bodies.iter().enumerate() {
        assert_eq!(b.id.name(), format!("Wall:1:{}", k + 1));
        let mut h = b.half_extents;
        h.sort_by(f64::total_cmp);
        assert!((h[0] - thick / 2.0).abs() < 1e-12, "{:?}", b.half_extents);
        assert!(
            (h[1] - 0.25).abs() < 1e-12 && (h[2] - 0.25).abs() < 1e-12,
            "{h:?}"
        );
    }
}

//! A frame–shear-wall building from the generator (`model::building`: fibre beam-columns,
//! two walls along X on layered ASDShellQ4 shells sharing the frame's nodes) through the
//! FE domain (`build_domain` + `modal_analysis`, what `fem2rbd modal` runs) against
//! openseespy's `eigen` on the exported script: the first 6 periods to 1e-6, and the
//! building's 6 modes (the default selection) against OpenSees's modes at the indices
//! fem2rbd's Sturm count gives them, to 1e-6. The
//! generator writes its walls `corotational` (exported `ASDShellQ4 -corotational`); both
//! programs take the model as it is (the corotational tangent of the undeformed state).
//! Needs python3 with openseespy 3.7.1.
use std::process::Command;

use fem2rbd_fe::export::{opensees_script, OpenSeesOptions};
use fem2rbd_fe::fe::analysis::modal::{modal_analysis, ModalSettings, ModeSelection};
use fem2rbd_fe::fe::build::{build_domain, BuildOptions};
use fem2rbd_fe::model::building::{building, BuildingParams, WallSpec};
use fem2rbd_fe::model::generate::FrameParams;
use fem2rbd_fe::model::ElementKind;

#[test]
fn wall_building_periods_through_the_domain_match_opensees() {
    let p = BuildingParams {
        frame: FrameParams {
            name: "wall-building".into(),
            ..crate::model::building::small_frame()
        },
        walls: ["x0:1:1-2", "x1:1:1-2"]
            .iter()
            .map(|w| WallSpec::parse(w).unwrap())
            .collect(),
        wall_thickness: vec![0.2],
        ..BuildingParams::default()
    };
    let model = building(&p).unwrap();
    assert!(model.elements.iter().any(|e| matches!(
        e.kind,
        ElementKind::Shell {
            corotational: true,
            ..
        }
    )));
    let n_modes = 6;
    let mut built = build_domain(&model, &BuildOptions::default()).unwrap();
    let modal = modal_analysis(
        &mut built.domain,
        &ModalSettings {
            selection: ModeSelection::Lowest,
            modes: n_modes,
            ..Default::default()
        },
    )
    .unwrap();
    let building_modes = modal_analysis(
        &mut built.domain,
        &ModalSettings {
            modes: n_modes,
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(building_modes.selection, ModeSelection::Building);
    let highest = *building_modes.index.iter().max().unwrap();

    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("b.py");
    std::fs::write(
        &path,
        opensees_script(&model, "b.toml", &OpenSeesOptions::default()).unwrap(),
    )
    .unwrap();
    let v: serde_json::Value = crate::openseespy_json(
        Command::new("python3")
            .arg(&path)
            .args(["eigen", &n_modes.max(highest).to_string()]),
    );
    for (k, t) in modal.periods.iter().enumerate() {
        let t_os = v["modes"][k]["T"].as_f64().unwrap();
        let d = (t - t_os) / t_os;
        eprintln!(
            "mode {}: fem2rbd {t:.9} s, OpenSees {t_os:.9} s ({d:+.2e})",
            k + 1
        );
        assert!(d.abs() < 1e-6, "mode {}: {t} vs {t_os}", k + 1);
    }
    for (k, (t, index)) in building_modes
        .periods
        .iter()
        .zip(&building_modes.index)
        .enumerate()
    {
        let t_os = v["modes"][index - 1]["T"].as_f64().unwrap();
        let d = (t - t_os) / t_os;
        eprintln!(
            "building mode {} (index {index}): fem2rbd {t:.9} s, OpenSees {t_os:.9} s ({d:+.2e})",
            k + 1
        );
        assert!(d.abs() < 1e-6, "building mode {}: {t} vs {t_os}", k + 1);
    }
}

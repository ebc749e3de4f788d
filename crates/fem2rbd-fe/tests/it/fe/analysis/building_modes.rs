//! The building's modes (`ModeSelection::Building`, the default) on a generated
//! three-story, 3 × 3-bay frame–wall building whose bays carry their floor mass at the
//! slab centre nodes, as the library stand-in's do: 27 local vertical slab modes lie
//! below its first translation. The sparse path (load-dependent Ritz vectors, exact
//! refinement, Sturm numbering, the bound on what the skipped modes carry) against every
//! mode of the dense solver on the same domain.
use fem2rbd_fe::fe::analysis::building_modes::BUILDING_MODE_MASS_RATIO;
use fem2rbd_fe::fe::analysis::modal::{
    modal_analysis, EigenMethod, ModalResult, ModalSettings, ModeSelection,
};
use fem2rbd_fe::fe::build::{build_domain, BuildOptions};
use fem2rbd_fe::model::building::{building, BuildingParams, WallSpec};
use fem2rbd_fe::model::generate::FrameParams;
use fem2rbd_fe::model::Model;

/// 3 × 3 bays of 8 m × 7.9 m, stories 3.6, 2.7 and 2.7 m, 0.8 m columns, 0.4 × 0.8 m
/// beams, a 0.15 m slab with 450 t added per floor, and one wall bay on each facade (a
/// pinwheel): the library stand-in's bays on a small plan.
fn slab_building() -> Model {
    let p = BuildingParams {
        frame: FrameParams {
            name: "slab-modes".into(),
            spans_x: vec![8.0, 8.0, 8.0],
            spans_y: vec![7.9, 7.9, 7.9],
            story_heights: vec![3.6, 2.7, 2.7],
            column: [0.8, 0.8],
            beam: [0.4, 0.8],
            slab_thickness: 0.15,
            ec: vec![32.5e9],
            fc: vec![26.8e6],
            added_mass: vec![450_000.0],
            scale: 1.0,
            ..FrameParams::default()
        },
        walls: ["x0:1:1-3", "x3:2:1-3", "y0:2:1-3", "y3:1:1-3"]
            .iter()
            .map(|w| WallSpec::parse(w).unwrap())
            .collect(),
        wall_thickness: vec![0.3],
        ..BuildingParams::default()
    };
    building(&p).unwrap()
}

fn modes(
    model: &Model,
    modes: usize,
    selection: ModeSelection,
    method: EigenMethod,
) -> ModalResult {
    let mut built = build_domain(model, &BuildOptions::default()).unwrap();
    modal_analysis(
        &mut built.domain,
        &ModalSettings {
            modes,
            selection,
            method,
            ..Default::default()
        },
    )
    .unwrap()
}

fn lateral(r: &ModalResult, k: usize) -> [f64; 3] {
    let e = r.effective_mass_ratio[k];
    [e[0], e[1], r.torsion_mass_ratio[k]]
}

const LANCZOS: EigenMethod = EigenMethod::Lanczos {
    tol: 1e-10,
    max_restarts: 200,
};

#[test]
fn the_building_modes_are_the_exact_modes_past_the_slab_modes() {
    let model = slab_building();
    let built = build_domain(&model, &BuildOptions::default()).unwrap();
    let massed = built
        .domain
        .mass_diagonal()
        .iter()
        .filter(|&&m| m > 0.0)
        .count();
    drop(built);
    // Every mode, by the dense solver.
    let all = modes(
        &model,
        massed,
        ModeSelection::Lowest,
        EigenMethod::DenseCondensed,
    );
    assert_eq!(all.periods.len(), massed);
    // With every mode, the effective masses sum to the whole mass in X, Y, Z and torsion.
    for d in 0..3 {
        let s: f64 = all.effective_mass_ratio.iter().map(|r| r[d]).sum();
        assert!((s - 1.0).abs() < 1e-9, "direction {d}: {s}");
    }
    let s: f64 = all.torsion_mass_ratio.iter().sum();
    assert!((s - 1.0).abs() < 1e-9, "torsion: {s}");
    // The lowest modes with at least 1 % along X, Y or in torsion, by their index.
    let n = 6;
    let want: Vec<usize> = (0..massed)
        .filter(|&k| {
            lateral(&all, k)
                .iter()
                .any(|&r| r >= BUILDING_MODE_MASS_RATIO)
        })
        .take(n)
        .collect();
    // The phenomenon: local slab modes, vertical, lie below the first translation.
    assert_eq!(want[0], 27, "slab modes below T1: {:?}", &all.periods[..30]);
    for k in 0..want[0] {
        assert!(lateral(&all, k).iter().all(|&r| r < 1e-3), "mode {}", k + 1);
    }

    let sparse = modes(&model, n, ModeSelection::Building, LANCZOS);
    let dense = modes(
        &model,
        n,
        ModeSelection::Building,
        EigenMethod::DenseCondensed,
    );
    for r in [&sparse, &dense] {
        assert_eq!(r.selection, ModeSelection::Building);
        let index: Vec<usize> = want.iter().map(|k| k + 1).collect();
        assert_eq!(r.index, index);
        for (j, &k) in want.iter().enumerate() {
            let (t, t_all) = (r.periods[j], all.periods[k]);
            assert!(
                ((t - t_all) / t_all).abs() < 1e-8,
                "mode {}: {t} vs {t_all}",
                k + 1
            );
            for (a, b) in lateral(r, j).iter().zip(lateral(&all, k)) {
                assert!((a - b).abs() < 1e-8, "mode {}: {a} vs {b}", k + 1);
            }
        }
        // Skipped: every mode below the last reported one that is not reported.
        let last = *want.last().unwrap();
        assert_eq!(r.skipped.count, last + 1 - n);
        let exact: [f64; 3] = std::array::from_fn(|d| {
            (0..last)
                .filter(|k| !want.contains(k))
                .map(|k| lateral(&all, k)[d])
                .sum()
        });
        for d in 0..3 {
            let b = r.skipped.mass_ratio_bound[d];
            assert!(
                b >= exact[d] - 1e-12,
                "direction {d}: bound {b} < {}",
                exact[d]
            );
        }
        eprintln!(
            "skipped {} modes: exact {exact:?}, bound {:?}",
            r.skipped.count, r.skipped.mass_ratio_bound
        );
    }
    // The dense solver reports the exact sums. The sparse path finds the 15 local modes
    // between the building's (indices 32–46) and bounds the 27 below T1 from the
    // moments: under 1 % in each direction, so none of them can be a building mode.
    for d in 0..3 {
        let (b, e) = (
            sparse.skipped.mass_ratio_bound[d],
            dense.skipped.mass_ratio_bound[d],
        );
        assert!(
            b > e && b < BUILDING_MODE_MASS_RATIO,
            "direction {d}: {b} vs {e}"
        );
    }
    // Same input, same bits.
    let again = modes(&model, n, ModeSelection::Building, LANCZOS);
    assert_eq!(again.periods, sparse.periods);
    assert_eq!(again.shapes, sparse.shapes);
}

/// The lowest modes stay one option: the slab modes first, numbered 1, 2, …
#[test]
fn the_lowest_modes_are_the_slab_modes_with_their_own_numbers() {
    let model = slab_building();
    let r = modes(&model, 3, ModeSelection::Lowest, LANCZOS);
    assert_eq!(r.index, [1, 2, 3]);
    assert_eq!(r.skipped.count, 0);
    for k in 0..3 {
        assert!(
            lateral(&r, k).iter().all(|&x| x < 1e-3),
            "{:?}",
            lateral(&r, k)
        );
    }
}

//! The frame generator beyond frame3: multi-bay plans, mesh refinement, mass totals.
use fem2rbd_fe::model::generate::{frame, FrameError, FrameParams};
use fem2rbd_fe::model::{ElementKind, ModelError};

/// Total mass in closed form: concrete of every column and beam (full b×h over the
/// centre-line lengths, as the reference lumps it), slab ρ t A and the added mass.
fn closed_total(p: &FrameParams) -> f64 {
    let (lx, ly): (f64, f64) = (p.spans_x.iter().sum(), p.spans_y.iter().sum());
    let (nx, ny) = (p.spans_x.len() as f64, p.spans_y.len() as f64);
    let h: f64 = p.story_heights.iter().sum();
    let ns = p.story_heights.len() as f64;
    let rho = p.concrete_density;
    let cols = (nx + 1.0) * (ny + 1.0) * h * p.column[0] * p.column[1] * rho;
    let beam_len = (ny + 1.0) * lx + (nx + 1.0) * ly;
    let beams = ns * beam_len * p.beam[0] * p.beam[1] * rho;
    let slab = ns * rho * p.slab_thickness * lx * ly;
    cols + beams
        + slab
        + p.added_mass.iter().sum::<f64>() * if p.added_mass.len() == 1 { ns } else { 1.0 }
}

#[test]
fn multi_bay_frame_counts_masses_and_names() {
    let p = FrameParams {
        spans_x: vec![4.0, 5.0, 4.0],
        spans_y: vec![6.0, 5.0],
        story_heights: vec![3.6, 3.0],
        column: [0.4, 0.5],
        beam: [0.25, 0.6],
        slab_thickness: 0.12,
        ec: vec![30e9],
        fc: vec![30e6, 25e6],
        added_mass: vec![50_000.0, 40_000.0],
        column_elements: 3,
        beam_elements: 2,
        ..FrameParams::default()
    };
    let m = frame(&p).unwrap();
    let total = m.total_mass();
    let want = closed_total(&p);
    assert!((total / want - 1.0).abs() < 1e-12, "{total} vs {want}");
    // counts: 12 columns x 2 stories x 3 elements; beams per floor: (3 lines x 3 spans
    // + 4 lines x 2 spans) x 2 halves x 2 elements; 6 panels x (4 strips + 4 quarter
    // panels) per floor
    let count = |name: &str| m.elements.iter().filter(|e| e.type_name == name).count();
    assert_eq!(count("Column"), 12 * 2 * 3);
    assert_eq!(count("Beam"), 2 * (3 * 3 + 4 * 2) * 2 * 2);
    assert_eq!(count("Slab"), 2 * 6 * 4 * 2);
    let panels = m.elements.iter().filter(|e| !e.in_fe()).count();
    assert_eq!(panels, 2 * 6 * 4);
    // every element's length is positive and every group is its story
    for e in &m.elements {
        let size = m.element_length(e).or_else(|| m.shell_area(e)).unwrap();
        assert!(size > 0.1, "element {} size {size}", e.tag);
        assert!(["1", "2"].contains(&e.group.0.as_str()));
    }
    // the core concrete of story 2 is 25 MPa x 1.1
    let core2 = m.materials.iter().find(|x| x.name == "core_F2").unwrap();
    assert!((core2.parameters()[0].1 + 1.1 * 25e6).abs() < 1e-6);
    // a rectangular panel's strips: A = G t d³ / (2 E Lx Ly)
    let strip = m
        .elements
        .iter()
        .find_map(|e| match &e.kind {
            ElementKind::ElasticStrip {
                e,
                g,
                width,
                thickness,
                nodes,
                ..
            } => Some((*e, *g, *width, *thickness, *nodes)),
            _ => None,
        })
        .unwrap();
    let (e, g, w, t, _) = strip;
    let d = (16.0f64 + 36.0).sqrt();
    assert!((w * t - g * t * d.powi(3) / (2.0 * e * 4.0 * 6.0)).abs() < 1e-12);
    // node tags unique (validated) and deterministic
    assert_eq!(frame(&p).unwrap(), m);
}

#[test]
fn refined_frame3_mesh_keeps_mass_and_geometry() {
    let base = frame(&FrameParams::default()).unwrap();
    let fine = frame(&FrameParams {
        column_elements: 4,
        beam_elements: 2,
        ..FrameParams::default()
    })
    .unwrap();
    assert_eq!(fine.elements.len(), 4 * 3 * 4 + 3 * 4 * 2 * 2 + 12 + 12);
    assert!((fine.total_mass() / base.total_mass() - 1.0).abs() < 1e-12);
    let want = closed_total(&FrameParams::default());
    assert!((base.total_mass() / want - 1.0).abs() < 1e-12);
}

#[test]
fn bad_generator_parameters_are_errors() {
    let e = frame(&FrameParams {
        fc: vec![20e6, 25e6],
        ..FrameParams::default()
    })
    .unwrap_err();
    assert!(matches!(e, FrameError::Params(_)), "{e}");
    assert!(
        e.to_string()
            .contains("fc: give 1 value or one per story (3), not 2"),
        "{e}"
    );
    let e = frame(&FrameParams {
        spans_x: vec![],
        ..FrameParams::default()
    })
    .unwrap_err();
    assert!(
        matches!(&e, FrameError::Params(m) if m.contains("at least one story")),
        "{e}"
    );
    let e = frame(&FrameParams {
        cover: 0.06,
        ..FrameParams::default()
    })
    .unwrap_err();
    assert!(
        matches!(&e, FrameError::Model(ModelError::Value { message, .. }) if message.contains("leaves no core")),
        "{e}"
    );
}

#[test]
fn reinforcement_concrete_and_ballast_options_reach_the_model() {
    use fem2rbd_fe::model::{MaterialLaw, SectionKind};
    let base = FrameParams::default();
    let p = FrameParams {
        column_bar_diameter: 0.005,
        beam_bar_diameter: 0.004,
        column_bars_per_face: 4,
        beam_bars: [5, 3],
        cover_epscu: -0.0035,
        core_epscu: -0.008,
        residual: 0.1,
        ballast_centre: 0.25,
        ..base.clone()
    };
    let m = frame(&p).unwrap();
    let pi = std::f64::consts::PI;
    let (a_col, a_beam) = (pi * 0.005f64.powi(2) / 4.0, pi * 0.004f64.powi(2) / 4.0);
    for s in &m.sections {
        let SectionKind::RcRect(rc) = &s.kind else {
            panic!("{}: not rc_rect", s.name)
        };
        if s.name.starts_with("column") {
            // 4 per face: 12 bars on the perimeter at ±(0.05 − 0.013) m
            assert_eq!(rc.bars.len(), 12, "{}", s.name);
            assert!(rc.bars.iter().all(|b| (b.2 - a_col).abs() < 1e-15));
            let a = 0.05 - 0.013;
            assert!(rc
                .bars
                .iter()
                .all(|b| (b.0.abs() - a).abs() < 1e-12 || (b.1.abs() - a).abs() < 1e-12));
        } else {
            // 3 bottom (local z < 0), 5 top, beam bar area
            let bottom = rc.bars.iter().filter(|b| b.1 < 0.0).count();
            let top = rc.bars.iter().filter(|b| b.1 > 0.0).count();
            assert_eq!((top, bottom), (5, 3), "{}", s.name);
            assert!(rc.bars.iter().all(|b| (b.2 - a_beam).abs() < 1e-15));
        }
    }
    for mat in &m.materials {
        if let MaterialLaw::Concrete02 {
            fpc, fpcu, epscu, ..
        } = mat.law
        {
            assert!((fpcu - 0.1 * fpc).abs() < 1e-6, "{}", mat.name);
            let want = if mat.name.starts_with("core") {
                -0.008
            } else {
                -0.0035
            };
            assert_eq!(epscu, want, "{}", mat.name);
        }
    }
    // Ballast: the same total mass; the bay-centre node gets 1/2 of the slab and of the
    // spread ballast plus the centre share, ms = ρ t L² + (1 − c) M.
    let b = frame(&base).unwrap();
    assert!((m.total_mass() / b.total_mass() - 1.0).abs() < 1e-12);
    let centre = |mm: &fem2rbd_fe::model::Model| {
        mm.masses
            .iter()
            .filter(|x| x.node == 112)
            .map(|x| x.m)
            .sum::<f64>()
    };
    let slab = 2500.0 * 0.03 * 1.5 * 1.5;
    let added = 2699.75;
    let want = (slab + 0.75 * added) / 2.0 + 0.25 * added;
    assert!((centre(&m) - want).abs() < 1e-9, "{} vs {want}", centre(&m));
    assert!((centre(&b) - (slab + added) / 2.0).abs() < 1e-9);
}

#[test]
fn bad_reinforcement_and_concrete_parameters_are_errors() {
    let d = FrameParams::default();
    let cases: Vec<(FrameParams, &str)> = vec![
        (
            FrameParams {
                column_bars_per_face: 9,
                column_bar_diameter: 0.01,
                ..d.clone()
            },
            "9 column bars of 0.01 m do not fit",
        ),
        (
            FrameParams {
                beam_bar_diameter: 0.03,
                ..d.clone()
            },
            "beam bars of 0.03 m stick out of the section",
        ),
        (
            FrameParams {
                beam_bars: [3, 1],
                ..d.clone()
            },
            "2 beam bars per layer",
        ),
        (
            FrameParams {
                cover_epscu: -0.001,
                ..d.clone()
            },
            "cover crushing strain -0.001",
        ),
        (
            FrameParams {
                residual: 1.2,
                ..d.clone()
            },
            "residual share 1.2",
        ),
        (
            FrameParams {
                ballast_centre: -0.1,
                ..d.clone()
            },
            "ballast centre share -0.1",
        ),
    ];
    for (p, want) in cases {
        let e = frame(&p).unwrap_err().to_string();
        assert!(e.contains(want), "{e} (want {want:?})");
    }
}

//! `fem2rbd plot` on a synthetic run folder written with the project's own writers: the
//! PNG pixels at known body centres carry the body's type colour (darker for the lower
//! story), background outside the bodies, the SVG has one filled polygon per active body
//! whose vertices map back to the body's projected corners through the axis transform,
//! far debris gives an overview + near-footprint pair of panels, the time histories draw
//! the FE and ruin-stage curves and Tc, the same folder gives the same bytes, and a
//! missing file is named.
//!
//! The building: a passive foundation block, two stories of one column each (story 1:
//! column 1 and slab 2 at 3.1 m; story 2: column 3, beam 5 and slab 4 at 6.1 m). Its
//! final state (exact numbers below): column 1 lies along x at (−1.5, 3.0), column 3
//! along y at (−1.0, −1.5), slab 4 lies on slab 2 near (1.2, 1.1), beam 5 lies along y
//! at (3.5, −1.0). Timeline: FE keyframes 0 … 1.0 s (Tc), ruin-stage frames to 2.0 s.
use fem2rbd::body::BodyId;
use fem2rbd::bullet::Pose;
use fem2rbd::output::history::{bodies_csv, history_csv, BodyRow, HistoryFrame};
use fem2rbd::output::keyframes::keyframes_csv;
use fem2rbd::output::ruins::{ruins_csv, RuinRow};
use fem2rbd::plot::geometry::View;
use fem2rbd::plot::ruin::RuinFigure;
use fem2rbd::plot::{self, style, RunFolder};
use std::f64::consts::FRAC_1_SQRT_2 as H;
use std::path::Path;

struct Body {
    name: &'static str,
    ty: &'static str,
    passive: bool,
    pose0: Pose,
    he: [f64; 3],
    fin: Pose,
}

fn at(p: [f64; 3]) -> Pose {
    Pose::at(p)
}

fn rot_z(p: [f64; 3], deg: f64) -> Pose {
    let a = deg.to_radians() / 2.0;
    Pose {
        position: p,
        orientation: [a.cos(), 0.0, 0.0, a.sin()],
    }
}

/// The synthetic building; `beam_at` is the final centre of the beam.
fn building(beam_at: [f64; 3]) -> Vec<Body> {
    vec![
        Body {
            name: "Foundation:base:1",
            ty: "Foundation",
            passive: true,
            pose0: at([0.0, 0.0, -0.15]),
            he: [0.3, 0.3, 0.15],
            fin: at([0.0, 0.0, -0.15]),
        },
        Body {
            name: "Column:1:1",
            ty: "Column",
            passive: false,
            pose0: at([0.0, 0.0, 1.5]),
            he: [0.15, 0.15, 1.5],
            // 90° about y: the long local z axis along world x
            fin: Pose {
                position: [-1.5, 3.0, 0.15],
                orientation: [H, 0.0, H, 0.0],
            },
        },
        Body {
            name: "Slab:1:2",
            ty: "Slab",
            passive: false,
            pose0: at([1.0, 1.0, 3.1]),
            he: [1.2, 1.2, 0.1],
            fin: rot_z([1.0, 1.0, 0.1], 30.0),
        },
        Body {
            name: "Column:1:3",
            ty: "Column",
            passive: false,
            pose0: at([0.0, 0.0, 4.6]),
            he: [0.15, 0.15, 1.4],
            // 90° about x: the long local z axis along world y
            fin: Pose {
                position: [-1.0, -1.5, 0.15],
                orientation: [H, H, 0.0, 0.0],
            },
        },
        Body {
            name: "Slab:1:4",
            ty: "Slab",
            passive: false,
            pose0: at([1.0, 1.0, 6.1]),
            he: [1.2, 1.2, 0.1],
            fin: rot_z([1.2, 1.1, 0.3], 10.0),
        },
        Body {
            name: "Beam:1:5",
            ty: "Beam",
            passive: false,
            pose0: at([1.0, 0.0, 5.85]),
            he: [1.0, 0.15, 0.15],
            fin: rot_z(beam_at, 90.0),
        },
    ]
}

const TC: f64 = 1.0;
const GROUND_Z_END: f64 = 0.02;

/// Writes the run folder of `bodies` into `dir` with the project's writers.
fn write_run(dir: &Path, bodies: &[Body], mode: &str) {
    let ids: Vec<BodyId> = bodies.iter().map(|b| b.name.parse().unwrap()).collect();
    for (b, id) in bodies.iter().zip(&ids) {
        assert_eq!(id.type_name(), b.ty);
    }
    let rows: Vec<BodyRow> = bodies
        .iter()
        .zip(&ids)
        .map(|(b, id)| BodyRow {
            id,
            passive: b.passive,
            pose0: b.pose0,
            half_extents: b.he,
            mass_kg: if b.passive { 0.0 } else { 100.0 },
        })
        .collect();
    // 51 frames at 25 fps; positions move linearly from undeformed to final, the
    // orientation switches at Tc (both unit quaternions)
    let n = 50;
    let frames: Vec<(f64, Vec<Pose>)> = (0..=n)
        .map(|k| {
            let t = k as f64 * 0.04;
            let f = k as f64 / n as f64;
            let poses = bodies
                .iter()
                .map(|b| {
                    let mut p = [0.0; 3];
                    for (d, pd) in p.iter_mut().enumerate() {
                        *pd = b.pose0.position[d] + f * (b.fin.position[d] - b.pose0.position[d]);
                    }
                    Pose {
                        position: p,
                        orientation: if t <= TC + 1e-9 {
                            b.pose0.orientation
                        } else {
                            b.fin.orientation
                        },
                    }
                })
                .collect();
            (t, poses)
        })
        .collect();
    let names: Vec<&str> = bodies.iter().map(|b| b.name).collect();
    let fr: Vec<(f64, &[Pose])> = frames.iter().map(|(t, p)| (*t, p.as_slice())).collect();
    let hf: Vec<HistoryFrame> = frames
        .iter()
        .map(|(t, p)| HistoryFrame {
            t_s: *t,
            fe: mode == "hybrid" && *t <= TC + 1e-9,
            poses: p,
            counts: (mode == "rigid" || *t > TC + 1e-9).then(|| {
                let broken = ((t - TC).max(0.0) * 5.0).round() as usize;
                (6 - broken.min(6), 1, broken.min(6))
            }),
            ground_m: [0.0, 0.0, GROUND_Z_END * t / 2.0],
            energy: None,
        })
        .collect();
    let ruins: Vec<RuinRow> = bodies
        .iter()
        .zip(&ids)
        .map(|(b, id)| RuinRow {
            id,
            pose: b.fin,
            at_rest: Some(true),
        })
        .collect();
    let tc = if mode == "hybrid" {
        format!("{TC}")
    } else {
        "null".to_string()
    };
    let reason = if mode == "hybrid" {
        "criterion"
    } else {
        "rigid_only"
    };
    std::fs::write(dir.join("bodies.csv"), bodies_csv(&rows)).unwrap();
    std::fs::write(dir.join("keyframes.csv"), keyframes_csv(&names, &fr)).unwrap();
    std::fs::write(dir.join("history.csv"), history_csv(&rows, &hf)).unwrap();
    std::fs::write(dir.join("ruins.csv"), ruins_csv(&ruins)).unwrap();
    std::fs::write(
        dir.join("summary.json"),
        format!(
            "{{\"mode\": \"{mode}\", \"tc_s\": {tc}, \"tc_reason\": \"{reason}\", \"tc_detail\": \"\", \
             \"fe_end_s\": {tc}, \"bodies\": 5, \"foundation_blocks\": 1, \"keyframes_fe\": 26, \
             \"ruins\": {{\"original_footprint_m\": {{\"x\": [-0.2, 2.2], \"y\": [-0.2, 2.2]}}, \
             \"extent_beyond_footprint_m\": {{\"x_minus\": 0, \"x_plus\": 0, \"y_minus\": 0, \"y_plus\": 0, \"max\": 0}}, \
             \"debris_footprint_area_m2\": 0, \"original_footprint_area_m2\": 0, \"max_debris_height_m\": 0, \
             \"floors\": [], \"slab_overlap\": []}}}}\n"
        ),
    )
    .unwrap();
}

fn near_run() -> (tempfile::TempDir, RunFolder) {
    let dir = tempfile::tempdir().unwrap();
    write_run(dir.path(), &building([3.5, -1.0, 0.15]), "hybrid");
    let run = RunFolder::load(dir.path()).unwrap();
    (dir, run)
}

/// Decodes an 8-bit RGB PNG: (width, height, pixels).
fn decode(png_bytes: &[u8]) -> (u32, u32, Vec<u8>) {
    let dec = png::Decoder::new(std::io::Cursor::new(png_bytes));
    let mut reader = dec.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!(info.color_type, png::ColorType::Rgb);
    assert_eq!(info.bit_depth, png::BitDepth::Eight);
    buf.truncate(info.buffer_size());
    (info.width, info.height, buf)
}

fn pixel(img: &(u32, u32, Vec<u8>), x: f64, y: f64) -> (u8, u8, u8) {
    // plotters floors the mapped coordinate (+1e-3)
    let (xi, yi) = ((x + 1e-3).floor() as usize, (y + 1e-3).floor() as usize);
    let i = (yi * img.0 as usize + xi) * 3;
    (img.2[i], img.2[i + 1], img.2[i + 2])
}

fn rgb(c: plotters::style::RGBColor) -> (u8, u8, u8) {
    (c.0, c.1, c.2)
}

fn hex(c: plotters::style::RGBColor) -> String {
    format!("#{:02X}{:02X}{:02X}", c.0, c.1, c.2)
}

/// The `points` of every `<polygon>` with fill `fill` in an SVG.
fn polygons_with_fill(svg: &str, fill: &str) -> Vec<Vec<(f64, f64)>> {
    svg.lines()
        .filter(|l| l.starts_with("<polygon") && l.contains(&format!("fill=\"{fill}\"")))
        .map(|l| {
            let s = l.split("points=\"").nth(1).unwrap();
            let s = &s[..s.find('"').unwrap()];
            s.split_whitespace()
                .map(|p| {
                    let (x, y) = p.split_once(',').unwrap();
                    (x.parse().unwrap(), y.parse().unwrap())
                })
                .collect()
        })
        .collect()
}

#[test]
fn plan_png_pixels_have_the_body_colours() {
    let (_d, run) = near_run();
    let fig = RuinFigure::new(&run, View::Plan);
    assert_eq!(fig.panels().len(), 1, "all debris near: one panel");
    let map = fig.pixel_maps().unwrap()[0];
    // equal aspect: one metre spans the same pixels on both axes (to a pixel's rounding)
    let (x0, y0) = map.to_px([0.0, 0.0]);
    let (x1, y1) = map.to_px([1.0, 1.0]);
    assert!(((x1 - x0) - (y0 - y1)).abs() < 1e-6, "{x0} {x1} {y0} {y1}");
    assert!(x1 - x0 > 50.0, "scale {} px/m", x1 - x0);

    let img = decode(&plot::png_bytes(&fig).unwrap());
    assert_eq!((img.0, img.1), (1150, 900));
    let col1 = pixel(&img, map.to_px([-1.5, 3.0]).0, map.to_px([-1.5, 3.0]).1);
    let col3 = pixel(&img, map.to_px([-1.0, -1.5]).0, map.to_px([-1.0, -1.5]).1);
    let beam = pixel(&img, map.to_px([3.5, -1.0]).0, map.to_px([3.5, -1.0]).1);
    let slab4 = pixel(&img, map.to_px([1.2, 1.1]).0, map.to_px([1.2, 1.1]).1);
    // the top story keeps the type colour; story 1 of 2 is scaled by one half
    assert_eq!(col3, rgb(style::type_colour("Column")));
    assert_eq!(col1, rgb(style::body_fill("Column", 1, 2)));
    for (a, b) in [(col1.0, col3.0), (col1.1, col3.1), (col1.2, col3.2)] {
        assert!(
            (f64::from(a) - 0.5 * f64::from(b)).abs() <= 0.5,
            "{col1:?} {col3:?}"
        );
    }
    assert_eq!(beam, rgb(style::type_colour("Beam")));
    assert_eq!(slab4, rgb(style::type_colour("Slab")));
    // slab 2's centre (1.0, 1.0) lies under slab 4, which is higher: drawn over it
    let under = pixel(&img, map.to_px([1.0, 1.0]).0, map.to_px([1.0, 1.0]).1);
    assert_eq!(under, rgb(style::type_colour("Slab")));
    // slab 2 (story 1, darker) shows where slab 4 does not reach: 95 % of the way to
    // its corner (1.2, −1.2) turned 30° — 0.047 m outside slab 4 (turned 10°)
    let (c, s30) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
    let p = [
        1.0 + 0.95 * (1.2 * c + 1.2 * s30),
        1.0 + 0.95 * (1.2 * s30 - 1.2 * c),
    ];
    let s2 = pixel(&img, map.to_px(p).0, map.to_px(p).1);
    assert_eq!(s2, rgb(style::body_fill("Slab", 1, 2)), "at {p:?}");
    // outside every body: background or a grid line, never a body colour
    for q in [[3.0, 2.9], [-2.5, -2.5], [3.0, 1.0]] {
        let c = pixel(&img, map.to_px(q).0, map.to_px(q).1);
        assert!(
            [style::BACKGROUND, style::GRID_LIGHT, style::GRID_BOLD]
                .iter()
                .any(|g| rgb(*g) == c),
            "{q:?}: {c:?}"
        );
    }
}

#[test]
fn plan_svg_polygons_map_back_to_the_corners() {
    let (_d, run) = near_run();
    let fig = RuinFigure::new(&run, View::Plan);
    let svg = plot::svg_string(&fig).unwrap();
    // one filled polygon per active body (the foundation is an outline)
    assert_eq!(svg.matches("<polygon").count(), 5);
    let map = fig.pixel_maps().unwrap()[0];
    // column 1 lying along x: x ∈ [−3.0, 0.0], y ∈ [2.85, 3.15]
    let polys = polygons_with_fill(&svg, &hex(style::body_fill("Column", 1, 2)));
    assert_eq!(polys.len(), 1);
    let m_per_px = (map.bounds.x[1] - map.bounds.x[0]) / f64::from(map.px[1] - 1 - map.px[0]);
    let want = [[-3.0, 2.85], [0.0, 2.85], [0.0, 3.15], [-3.0, 3.15]];
    let got: Vec<[f64; 2]> = polys[0].iter().map(|&(x, y)| map.to_m(x, y)).collect();
    assert_eq!(got.len(), 4, "{got:?}");
    for w in want {
        let d = got
            .iter()
            .map(|g| (g[0] - w[0]).hypot(g[1] - w[1]))
            .fold(f64::INFINITY, f64::min);
        assert!(
            d <= 1.5 * m_per_px,
            "corner {w:?}: nearest {d} m, got {got:?}"
        );
    }
    // the original footprint: dashed, from the undeformed corners x, y ∈ [−0.2, 2.2]
    assert!(svg.contains("original footprint"));
    // text is laid out with the bundled font and named by family
    assert!(svg.contains("font-family=\"sans-serif\""));
    assert!(svg.contains("mode hybrid, Tc = 1.000 s (criterion)"));
}

#[test]
fn elevation_has_the_final_ground_line() {
    let (_d, run) = near_run();
    let fig = RuinFigure::new(&run, View::ElevationXz);
    let map = fig.pixel_maps().unwrap()[0];
    let img = decode(&plot::png_bytes(&fig).unwrap());
    // ground: top of the foundation (0.0) + final ground z 0.02 m; at x = −3.1 no body
    let (x, y) = map.to_px([-3.1, GROUND_Z_END]);
    let rows: Vec<(u8, u8, u8)> = (-1..=1).map(|d| pixel(&img, x, y + f64::from(d))).collect();
    assert!(rows.contains(&rgb(style::GROUND)), "{rows:?}");
    // one metre above it: background or grid
    let (x, y) = map.to_px([-3.1, 1.0 + GROUND_Z_END]);
    let above = pixel(&img, x, y);
    assert!(
        [style::BACKGROUND, style::GRID_LIGHT, style::GRID_BOLD]
            .iter()
            .any(|g| rgb(*g) == above),
        "{above:?}"
    );
    // column 1 seen from −y: x ∈ [−3, 0], z ∈ [0, 0.3]; in front of slab 2 (y = 1.0)
    let (x, y) = map.to_px([-1.5, 0.15]);
    assert_eq!(pixel(&img, x, y), rgb(style::body_fill("Column", 1, 2)));
    // the vertical range grows upwards only: the ground is in the lower fifth
    let (_, gy) = map.to_px([0.0, GROUND_Z_END]);
    assert!(gy > f64::from(map.py[0]) + 0.8 * f64::from(map.py[1] - map.py[0]));
}

#[test]
fn far_debris_gives_an_overview_and_a_near_panel() {
    let dir = tempfile::tempdir().unwrap();
    write_run(dir.path(), &building([100.0, 50.0, 0.15]), "hybrid");
    let run = RunFolder::load(dir.path()).unwrap();
    let fig = RuinFigure::new(&run, View::Plan);
    let panels = fig.panels();
    assert_eq!(panels.len(), 2);
    // overview holds the beam at 100 m; near window = footprint ± its side (2.4 m)
    assert!(panels[0].data.x[1] > 101.0 && panels[0].data.y[1] > 51.0);
    let w = panels[1].data;
    assert!(
        (w.x[0] + 2.6).abs() < 1e-6 && (w.x[1] - 4.6).abs() < 1e-6,
        "{w:?}"
    );
    let svg = plot::svg_string(&fig).unwrap();
    // 5 polygons in the overview, 4 in the near panel (the beam is far); a dot per body
    assert_eq!(svg.matches("<polygon").count(), 9);
    assert_eq!(svg.matches("<circle").count(), 5);
    assert!(svg.contains("near the original footprint: 4 of 5 bodies"));
    let maps = fig.pixel_maps().unwrap();
    let img = decode(&plot::png_bytes(&fig).unwrap());
    let (x, y) = maps[1].to_px([-1.5, 3.0]);
    assert_eq!(pixel(&img, x, y), rgb(style::body_fill("Column", 1, 2)));
    let (x, y) = maps[0].to_px([100.0, 50.0]);
    assert_eq!(pixel(&img, x, y), rgb(style::type_colour("Beam")));
    assert!(
        maps[1].px[0] > maps[0].px[1],
        "near panel right of the overview"
    );
}

/// Every `<polyline>` stroke colour of an SVG with its count.
fn polylines_with_stroke(svg: &str, stroke: &str) -> usize {
    svg.lines()
        .filter(|l| l.starts_with("<polyline") && l.contains(&format!("stroke=\"{stroke}\"")))
        .count()
}

#[test]
fn histories_draw_both_stages_and_tc() {
    let (_d, run) = near_run();
    let h = plot::history::HistoryFigure::new(&run);
    let svg = plot::svg_string(&h).unwrap();
    // drift and drop panels: one FE and one ruin-stage curve each, plus the legend lines
    assert_eq!(polylines_with_stroke(&svg, &hex(style::FE_STAGE)), 3);
    assert_eq!(polylines_with_stroke(&svg, &hex(style::PHYSICS_STAGE)), 3);
    // Tc: a label in each panel and in the legend
    assert_eq!(
        svg.matches("Tc = 1.000 s").count(),
        4,
        "title + 2 panels + legend"
    );
    let c = plot::connections::ConnectionsFigure::new(&run);
    let curves = c.curves();
    // ruin-stage frames only: t = 1.04 … 2.0 s, 25 frames; last counts (1, 1, 5)
    assert_eq!(curves[0].points.len(), 25);
    assert_eq!(curves[0].points.last(), Some(&(2.0, 1.0)));
    assert_eq!(curves[2].points.last(), Some(&(2.0, 5.0)));
    let svg = plot::svg_string(&c).unwrap();
    for col in [style::INTACT, style::PLASTIC, style::BROKEN] {
        assert_eq!(polylines_with_stroke(&svg, &hex(col)), 2, "curve + legend");
    }
}

#[test]
fn rigid_mode_without_tc_and_fe_run_without_counts() {
    let dir = tempfile::tempdir().unwrap();
    write_run(dir.path(), &building([3.5, -1.0, 0.15]), "rigid");
    let run = RunFolder::load(dir.path()).unwrap();
    let svg = plot::svg_string(&plot::history::HistoryFigure::new(&run)).unwrap();
    assert!(svg.contains("mode rigid, no Tc (rigid_only)"));
    assert!(!svg.contains("Tc ="));
    assert_eq!(polylines_with_stroke(&svg, &hex(style::FE_STAGE)), 0);
    // no counts at all: the connections figure says so
    let mut run = run;
    for r in &mut run.history {
        r.counts = None;
    }
    let svg = plot::svg_string(&plot::connections::ConnectionsFigure::new(&run)).unwrap();
    assert!(svg.contains("no ruin stage in this run: no connection counts"));
    assert_eq!(polylines_with_stroke(&svg, &hex(style::BROKEN)), 0);
}

#[test]
fn cli_writes_every_figure_reproducibly() {
    let dir = tempfile::tempdir().unwrap();
    write_run(dir.path(), &building([3.5, -1.0, 0.15]), "hybrid");
    let run_dir = dir.path().to_str().unwrap();
    let cli = |extra: &[&str]| {
        let mut args = vec!["fem2rbd", "--quiet", "plot", run_dir];
        args.extend_from_slice(extra);
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_fem2rbd"))
            .args(&args[1..])
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    };
    cli(&[]);
    let plots = dir.path().join("plots");
    let names = [
        "ruin_plan",
        "ruin_elevation_xz",
        "ruin_elevation_yz",
        "history",
        "connections",
    ];
    let read_all = |d: &Path, ext: &str| -> Vec<Vec<u8>> {
        names
            .iter()
            .map(|n| std::fs::read(d.join(format!("{n}.{ext}"))).unwrap())
            .collect()
    };
    let (png1, svg1) = (read_all(&plots, "png"), read_all(&plots, "svg"));
    for p in &png1 {
        assert_eq!(&p[..8], b"\x89PNG\r\n\x1a\n");
    }
    // again, into another folder, SVG only: the same bytes
    let other = dir.path().join("again");
    cli(&["--out", other.to_str().unwrap(), "--format", "svg"]);
    assert_eq!(read_all(&other, "svg"), svg1);
    assert!(!other.join("ruin_plan.png").exists());
    cli(&["--out", other.to_str().unwrap(), "--format", "png"]);
    assert_eq!(read_all(&other, "png"), png1);
    // no temporary files left
    let leftovers: Vec<_> = std::fs::read_dir(&plots)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.'))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
}

#[test]
fn a_missing_file_is_named() {
    let dir = tempfile::tempdir().unwrap();
    write_run(dir.path(), &building([3.5, -1.0, 0.15]), "hybrid");
    std::fs::remove_file(dir.path().join("history.csv")).unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_fem2rbd"))
        .args(["plot", dir.path().to_str().unwrap()])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let msg = String::from_utf8_lossy(&out.stderr);
    assert!(msg.contains("history.csv"), "{msg}");
    assert!(!dir.path().join("plots").exists(), "nothing written");
}

/// A figure set is written all or nothing: when one figure cannot be written (its name
/// is taken by a folder), no other figure of the set appears and no temporary file is
/// left.
#[test]
fn a_figure_set_is_written_all_or_nothing() {
    let dir = tempfile::tempdir().unwrap();
    write_run(dir.path(), &building([3.5, -1.0, 0.15]), "hybrid");
    let out = dir.path().join("figs");
    std::fs::create_dir_all(out.join("history.svg")).unwrap();
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_fem2rbd"))
        .args(["--quiet", "plot", dir.path().to_str().unwrap(), "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("history.svg"), "{err}");
    let left: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(left, ["history.svg"], "only the blocking folder remains");
}

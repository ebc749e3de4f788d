//! The frame3 report in a real browser: Debian's headless Chromium (`apt-get install
//! chromium`), driven by tests/report/check.mjs through playwright-core (pinned in
//! tests/report/package.json, installed by scripts/setup-node.sh), loads the page from the
//! file alone (any network request fails the test) and reports what it shows; this test
//! asserts it against the run folder's own numbers:
//!
//! * the page raised no JavaScript error and logged none;
//! * the scene draws one box per row of `bodies.csv`, the body table has one row per body;
//! * the time slider spans the timeline of `keyframes.csv`, and the page's frame times are
//!   its times;
//! * the key-figure table shows `summary.json`'s Tc; the `plots/*.svg` are all inlined;
//!   connection-state colouring is offered (the run has `connections.csv`);
//! * at rest, the world box of the drawn active bodies (each instance's unit cube through
//!   its matrix) is the ruin's extent of `summary.json` (original footprint ± debris
//!   extent per side, top = base level + final ground z + debris height) to 2 mm
//!   (float32 poses, 6-decimal summary), and the 3-D view shows all of it on the canvas;
//! * in a plan-view screenshot at rest, the pixels in element colours span the drawn
//!   active bodies' box projected through the camera, to 3 px;
//! * clicking the highest body in plan view shows that body's row;
//! * screenshots before Tc, at Tc and at rest are PNGs of the view, all different;
//! * at the final ruin, one void mesh per void of `voids.json`, named `void-N`, each
//!   drawn as the boxes of `voids.json` whose volumes (each instance's matrix
//!   determinant) add up to its volume in `voids.csv`, one voids-table row per row of `voids.csv`, an entry or breach marker per
//!   survivable void as `voids.csv` says, a route line per survivable void the rescuer (or
//!   else the camera) reaches through the points of its route in `voids.json`, the rescue
//!   key figures of `voids.json`; clicking
//!   a row highlights its mesh and clicking a void in the view highlights its row.
//!
//! Fails (does not skip) when node, playwright-core or chromium is missing.
use super::frame3::run_dir;
use fem2rbd::output::run_folder::RunFolder;
use fem2rbd::plan_geometry::corners;
use serde_json::Value;
use std::path::Path;
use std::process::Command;

/// Width, height and 8-bit RGB pixels of a PNG file (RGB or RGBA, 8 bits).
fn decode_png(path: &Path) -> (usize, usize, Vec<u8>) {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!(info.bit_depth, png::BitDepth::Eight, "{}", path.display());
    let channels = match info.color_type {
        png::ColorType::Rgb => 3,
        png::ColorType::Rgba => 4,
        other => panic!("{}: colour type {other:?}", path.display()),
    };
    let (w, h) = (info.width as usize, info.height as usize);
    let mut rgb = Vec::with_capacity(w * h * 3);
    for y in 0..h {
        let row = &buf[y * info.line_size..];
        for x in 0..w {
            rgb.extend_from_slice(&row[x * channels..x * channels + 3]);
        }
    }
    (w, h, rgb)
}

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("{v} is not a number"))
}

#[test]
fn frame3_report_in_headless_chromium() {
    let dir = run_dir();
    let run = RunFolder::load(dir).unwrap();
    let s = &run.summary;
    let tc = s.tc_s.expect("the CI scenario collapses");
    let t0 = run.frames[0].0;
    let t1 = run.frames.last().unwrap().0;
    let shots = Path::new(env!("CARGO_TARGET_TMPDIR")).join("report-frame3/shots");
    std::fs::create_dir_all(&shots).unwrap();
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/report/check.mjs");
    let out = Command::new("node")
        .arg(&script)
        .arg(dir.join("report.html"))
        .arg(&shots)
        .arg(format!("before_tc={}", 0.5 * tc))
        .arg(format!("at_tc={tc}"))
        .arg(format!("at_rest={t1}"))
        .output()
        .unwrap_or_else(|e| {
            panic!("cannot run `node` ({e}): install Node.js >= 18, then run scripts/setup-node.sh")
        });
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success(),
        "check.mjs failed (chromium: `apt-get install chromium`; playwright-core: \
         scripts/setup-node.sh): {stderr}"
    );
    let r: Value = serde_json::from_slice(&out.stdout).expect("check.mjs prints JSON");
    eprintln!("{}", serde_json::to_string_pretty(&r["pick"]).unwrap());

    assert_eq!(r["errors"], serde_json::json!([]), "JavaScript errors");
    let n = run.bodies.len();
    assert_eq!(n, 88, "frame3: 84 mapped bodies + 4 foundation blocks");
    assert_eq!(r["bodies_in_scene"], n);
    assert_eq!(r["body_rows"], n);
    assert_eq!(f(&r["slider_min"]), t0);
    assert_eq!(f(&r["slider_max"]), t1);
    let times: Vec<f64> = r["times"].as_array().unwrap().iter().map(f).collect();
    let want: Vec<f64> = run.frames.iter().map(|fr| fr.0).collect();
    assert_eq!(times, want);
    let shown_tc: f64 = r["key_figure_tc"].as_str().unwrap().parse().unwrap();
    assert_eq!(shown_tc, tc);
    assert!(
        r["key_figure_tc_text"]
            .as_str()
            .unwrap()
            .contains(&tc.to_string()),
        "{}",
        r["key_figure_tc_text"]
    );
    let svgs = std::fs::read_dir(dir.join("plots"))
        .unwrap()
        .filter(|e| {
            e.as_ref()
                .unwrap()
                .path()
                .extension()
                .is_some_and(|x| x == "svg")
        })
        .count();
    assert!(svgs >= 5, "fem2rbd plot wrote {svgs} SVGs");
    assert_eq!(r["plots"], svgs);
    assert_eq!(
        r["colour_options"],
        serde_json::json!(["type", "story", "connection"])
    );

    // The ruin's extent, from summary.json and the tables.
    let ru = &s.ruins;
    let fp = &ru.original_footprint_m;
    let e = &ru.extent_beyond_footprint_m;
    let base = run
        .bodies
        .iter()
        .filter(|b| b.passive)
        .flat_map(|b| corners(&b.pose0, b.half_extents))
        .map(|c| c[2])
        .fold(f64::NEG_INFINITY, f64::max);
    let ground_z = run.history.last().unwrap().ground_m[2];
    let lo: Vec<f64> = r["rest_world_min"]
        .as_array()
        .unwrap()
        .iter()
        .map(f)
        .collect();
    let hi: Vec<f64> = r["rest_world_max"]
        .as_array()
        .unwrap()
        .iter()
        .map(f)
        .collect();
    let tol = 2e-3;
    // A side with debris beyond the footprint: the drawn box reaches exactly there; a side
    // without: the drawn box stays within the footprint.
    let side = |drawn: f64, edge: f64, beyond: f64, outward: f64, what: &str| {
        if beyond > 0.0 {
            let want = edge + outward * beyond;
            assert!(
                (drawn - want).abs() < tol,
                "{what}: drawn {drawn}, ruin {want}"
            );
        } else {
            assert!(
                outward * (drawn - edge) < tol,
                "{what}: drawn {drawn} beyond {edge}"
            );
        }
    };
    side(lo[0], fp.x[0], e.x_minus, -1.0, "−x");
    side(hi[0], fp.x[1], e.x_plus, 1.0, "+x");
    side(lo[1], fp.y[0], e.y_minus, -1.0, "−y");
    side(hi[1], fp.y[1], e.y_plus, 1.0, "+y");
    let top = base + ground_z + ru.max_debris_height_m;
    assert!(
        (hi[2] - top).abs() < tol,
        "top: drawn {}, ruin {top}",
        hi[2]
    );
    eprintln!(
        "drawn ruin at rest: x {:.3}…{:.3}, y {:.3}…{:.3}, top {:.3} m",
        lo[0], hi[0], lo[1], hi[1], hi[2]
    );

    // The 3-D view frames the whole ruin, and not as a speck.
    let px: Vec<f64> = r["rest_pixels"].as_array().unwrap().iter().map(f).collect();
    let (w, h) = (f(&r["canvas"][0]), f(&r["canvas"][1]));
    assert!(
        px[0] >= 0.0 && px[1] >= 0.0 && px[2] <= w && px[3] <= h,
        "drawn bodies {px:?} outside the {w}×{h} canvas"
    );
    assert!(
        (px[2] - px[0]) > 0.2 * w || (px[3] - px[1]) > 0.2 * h,
        "drawn bodies {px:?} are a speck on the {w}×{h} canvas"
    );

    // The plan-view picture at rest: its saturated pixels (the element colours; the
    // ground, grid, background and the grey foundations are near-grey) outside the
    // legend span the drawn active bodies' projected box, to 3 px.
    let (w_px, h_px, rgb) = decode_png(Path::new(r["plan_shot"].as_str().unwrap()));
    let legend: Vec<f64> = r["plan_legend"].as_array().unwrap().iter().map(f).collect();
    let mut seen = [
        f64::INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
    ];
    for y in 0..h_px {
        for x in 0..w_px {
            let (xf, yf) = (x as f64 + 0.5, y as f64 + 0.5);
            if xf >= legend[0] && xf <= legend[2] && yf >= legend[1] && yf <= legend[3] {
                continue;
            }
            let p = &rgb[3 * (y * w_px + x)..3 * (y * w_px + x) + 3];
            let sat = i32::from(*p.iter().max().unwrap()) - i32::from(*p.iter().min().unwrap());
            if sat >= 50 {
                seen = [
                    seen[0].min(x as f64),
                    seen[1].min(y as f64),
                    seen[2].max(x as f64 + 1.0),
                    seen[3].max(y as f64 + 1.0),
                ];
            }
        }
    }
    let want: Vec<f64> = r["plan_pixels"].as_array().unwrap().iter().map(f).collect();
    eprintln!("plan view at rest: bodies drawn over pixels {seen:?}, projected {want:?}");
    for k in 0..4 {
        assert!(
            (seen[k] - want[k]).abs() <= 3.0,
            "plan view: pixels {seen:?}, projected box {want:?}"
        );
    }

    // Picking.
    let pick = &r["pick"];
    assert_eq!(pick["shown"], pick["wanted"], "{pick}");
    let i = pick["wanted"].as_u64().unwrap() as usize;
    assert_eq!(pick["row_name"], run.bodies[i].id.name());

    // Screenshots: PNGs of the view, each time a different picture.
    let mut pictures = Vec::new();
    for (shot, t) in r["shots"]
        .as_array()
        .unwrap()
        .iter()
        .zip([0.5 * tc, tc, t1])
    {
        assert!((f(&shot["t"]) - t).abs() < 1e-9);
        let bytes = std::fs::read(shot["file"].as_str().unwrap()).unwrap();
        assert_eq!(&bytes[1..4], b"PNG", "{shot}");
        let readout = shot["readout"].as_str().unwrap();
        assert!(readout.contains(&format!("t = {t:.3} s")), "{readout}");
        pictures.push(bytes);
    }
    assert_eq!(pictures.len(), 3);
    assert!(pictures[0] != pictures[1] && pictures[1] != pictures[2]);

    check_voids(dir, &r);
}

/// The voids of the final ruin on the page against `voids.json` and `voids.csv`.
fn check_voids(dir: &Path, r: &Value) {
    let vj: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("voids.json")).unwrap()).unwrap();
    let csv = std::fs::read_to_string(dir.join("voids.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    // No quoted field holds a comma before `breach_m` (the body lists are `;`-separated).
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    let count = vj["voids_count"].as_u64().unwrap() as usize;
    assert!(count > 0, "the CI ruin has voids");
    let v = &r["voids"];
    eprintln!(
        "voids: {count} in voids.json, {} meshes, {} rows, markers {}",
        v["in_scene"],
        v["rows"].as_array().unwrap().len(),
        v["markers"]
    );
    assert_eq!(v["shown"], true);
    assert_eq!(v["in_scene"], count);
    assert_eq!(v["meshes"].as_array().unwrap().len(), count);
    assert_eq!(rows.len(), count);
    let row_numbers: Vec<u64> = (1..=count as u64).collect();
    assert_eq!(v["rows"], serde_json::json!(row_numbers));
    assert_eq!(v["none"], Value::Null);
    // Each mesh is its void's cells: named for it, visible, its boxes, its volume.
    for (n, (m, row)) in v["meshes"]
        .as_array()
        .unwrap()
        .iter()
        .zip(&rows)
        .enumerate()
    {
        assert_eq!(m["name"], format!("void-{}", n + 1));
        assert_eq!(
            m["boxes"],
            vj["voids"][n]["boxes"].as_array().unwrap().len()
        );
        assert_eq!(m["visible"], true);
        let want: f64 = row[col("volume_m3")].parse().unwrap();
        let drawn = f(&m["volume"]);
        assert!(
            (drawn - want).abs() <= 1e-6 + 1e-4 * want,
            "void {}: drawn volume {drawn}, voids.csv {want}",
            n + 1
        );
    }
    // Markers: an entry cone per survivable void the rescuer reaches, a breach cube per
    // survivable void it does not reach behind debris.
    let mut markers = Vec::new();
    for row in &rows {
        if row[col("survivable")] != "1" {
            continue;
        }
        let n = row[col("void")];
        if row[col("rescuer_access")] == "1" {
            markers.push(format!("entry-{n}"));
        } else if row[col("breach_m")].parse::<f64>().unwrap() > 0.0 {
            markers.push(format!("breach-{n}"));
        }
    }
    assert_eq!(v["markers"], serde_json::json!(markers));
    // Route lines: the rescuer's route of voids.json to each survivable void it reaches
    // (`route-N`), else the camera's to one the camera reaches (`camera-route-N`), drawn
    // as segments whose ends are the route's points (float32 matrices: to 10 µm) and shown
    // with the voids.
    let mut want_routes = Vec::new();
    for (n, vv) in vj["voids"].as_array().unwrap().iter().enumerate() {
        if vv["survivable"] != true {
            continue;
        }
        let (name, path) = if vv["rescuer"]["reached"] == true {
            (format!("route-{}", n + 1), &vv["rescuer"]["path_m"])
        } else if vv["camera"]["reached"] == true {
            (format!("camera-route-{}", n + 1), &vv["camera"]["path_m"])
        } else {
            continue;
        };
        let flat: Vec<f64> = path
            .as_array()
            .unwrap()
            .iter()
            .flat_map(|p| p.as_array().unwrap().iter().map(f))
            .collect();
        assert!(flat.len() >= 6, "{name}: a route has two points at least");
        want_routes.push((name, flat));
    }
    let drawn = v["routes"].as_array().unwrap();
    assert!(
        !want_routes.is_empty(),
        "the CI ruin has reached survivable voids"
    );
    assert_eq!(drawn.len(), want_routes.len(), "{drawn:?}");
    for (d, (name, flat)) in drawn.iter().zip(&want_routes) {
        assert_eq!(d["name"], name.as_str());
        assert_eq!(d["visible"], true, "{name}");
        let pts: Vec<f64> = d["points"].as_array().unwrap().iter().map(f).collect();
        assert_eq!(pts.len(), flat.len(), "{name}");
        for (a, b) in pts.iter().zip(flat) {
            assert!((a - b).abs() <= 1e-5, "{name}: {a} vs {b}");
        }
    }
    // The rescue key figures are voids.json's.
    assert_eq!(f(&v["key_voids_count"]), count as f64);
    assert_eq!(f(&v["key_survivable_count"]), f(&vj["survivable_count"]));
    assert_eq!(
        f(&v["key_survivable_volume"]),
        f(&vj["survivable_volume_m3"])
    );
    assert_eq!(f(&v["key_pile_height"]), f(&vj["rubble"]["max_height_m"]));
    // Picking: a row highlights its mesh; a click on a void highlights its row.
    let rp = &r["void_row_pick"];
    assert_eq!(rp["picked"], rp["wanted"], "{rp}");
    assert_eq!(rp["row"], rp["wanted"].to_string());
    assert_eq!(f(&rp["opacity"]), 0.85);
    let vp = &r["void_view_pick"];
    assert!(vp["wanted"].as_i64().unwrap() > 0, "{vp}");
    assert_eq!(vp["picked"], vp["wanted"], "{vp}");
    assert_eq!(vp["row"], vp["wanted"], "{vp}");
    let shot = std::fs::read(r["void_shot"].as_str().unwrap()).unwrap();
    assert_eq!(&shot[1..4], b"PNG");
}

//! The rescue figures (`fem2rbd::plot::voids`), read back from their SVG: the voids of a
//! hand-built ruin as boxes of their pattern's colour at their places and sizes, with the
//! rescuer's entry and the breach marked; an ensemble's rescue map with one shaded cell per
//! cell of `rescue_map.csv` with a survivable void beneath, and its recurring place; the
//! rescuer's routes on it, one square per cell a route passes over and one triangle per
//! cell where a route leaves open air.
use super::ensemble::{hand_built_ensemble, read_map, read_route_map, table_at};
use super::route_map::corridor_ensemble;
use super::scene::*;
use fem2rbd::plot::geometry::View;
use fem2rbd::plot::voids::{
    pattern_colour, read_voids, route_colour, share_colour, RescueMapFigure, VoidsFigure,
};
use fem2rbd::plot::{svg_string, Figure};
use std::process::Command;

fn hex(c: plotters::style::RGBColor) -> String {
    format!("#{:02X}{:02X}{:02X}", c.0, c.1, c.2)
}

/// An attribute of an SVG element line.
fn attr(line: &str, name: &str) -> Option<String> {
    let key = format!(" {name}=\"");
    let s = line.split(key.as_str()).nth(1)?;
    Some(s[..s.find('"')?].to_string())
}

/// (x, y, width, height) of every `<rect>` whose `fill` is `fill` (and, when given, whose
/// `opacity` is `opacity`).
fn rects(svg: &str, fill: &str, opacity: Option<&str>) -> Vec<[f64; 4]> {
    svg.lines()
        .filter(|l| l.starts_with("<rect") && attr(l, "fill").as_deref() == Some(fill))
        .filter(|l| opacity.is_none() || attr(l, "opacity").as_deref() == opacity)
        .map(|l| ["x", "y", "width", "height"].map(|k| attr(l, k).unwrap().parse().unwrap()))
        .collect()
}

/// How many text elements read `s`.
fn texts(svg: &str, s: &str) -> usize {
    svg.lines().filter(|l| l.trim() == s).count()
}

/// A table (void 1: 3.0 × 2.0 m in plan, 2.0 m clear, the rescuer reaches it) and the
/// closed box 6 m along x (an enclosed 1.6 × 1.6 × 1.2 m room no one reaches: breach 0.2 m).
#[test]
fn the_voids_plan_draws_each_void_at_its_place_and_size() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let (mut boxes, c) = table_at([0.0; 3], 0);
    boxes.extend(shifted(&closed_box(), [6.0, 0.0, 0.0]));
    write_run(dir, &boxes, &c, 1.0);
    let out = Command::new(env!("CARGO_BIN_EXE_fem2rbd"))
        .args(["--quiet", "voids"])
        .arg(dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let voids = read_voids(dir).unwrap().unwrap();
    let surv: Vec<_> = voids.iter().filter(|v| v.survivable).collect();
    assert_eq!(surv.len(), 2, "{voids:?}");
    let table = surv.iter().find(|v| v.rescuer_entry.is_some()).unwrap();
    let room = surv.iter().find(|v| v.breach.is_some()).unwrap();

    let fig = VoidsFigure::new(None, View::Plan, voids.clone());
    assert_eq!(fig.name(), "voids_plan");
    let svg = svg_string(&fig).unwrap();
    // One filled box per survivable void, in its pattern's colour, half transparent.
    let filled = |v: &fem2rbd::plot::voids::PlotVoid| {
        rects(&svg, &hex(pattern_colour(&v.pattern)), Some("0.45"))
    };
    let total: usize = voids
        .iter()
        .map(|v| v.pattern.as_str())
        .collect::<std::collections::BTreeSet<_>>()
        .into_iter()
        .map(|p| rects(&svg, &hex(pattern_colour(p)), Some("0.45")).len())
        .sum();
    assert_eq!(total, 2);
    let (rt, rr) = (filled(table), filled(room));
    let t = rt.iter().max_by(|a, b| a[2].total_cmp(&b[2])).unwrap();
    let r = rr.iter().min_by(|a, b| a[2].total_cmp(&b[2])).unwrap();
    // Equal aspect: the table 3.0 × 2.0 m, the room 1.6 × 1.6 m (to a pixel).
    let ppm = t[2] / (table.bounds[1][0] - table.bounds[0][0]);
    assert!((t[2] / t[3] - 1.5).abs() < 0.02, "{t:?}");
    assert!(
        (r[2] - 1.6 * ppm).abs() <= 1.5 && (r[3] - 1.6 * ppm).abs() <= 1.5,
        "{r:?}"
    );
    // Their left edges apart by what voids.csv gives (the room's 5.2 m against the
    // table's −1.5 m), to a pixel and a half.
    let dx = (room.bounds[0][0] - table.bounds[0][0]) * ppm;
    assert!((r[0] - t[0] - dx).abs() <= 1.5, "{} vs {dx}", r[0] - t[0]);
    // Their top edges: the table reaches y = 1.0, the room y = 0.8, 0.2 m lower.
    let dy = (table.bounds[1][1] - room.bounds[1][1]) * ppm;
    assert!((r[1] - t[1] - dy).abs() <= 1.5, "{} vs {dy}", r[1] - t[1]);
    // One entry marker (a black triangle) and one breach cross.
    let black_polygons = svg
        .lines()
        .filter(|l| l.starts_with("<polygon") && attr(l, "fill").as_deref() == Some("#000000"))
        .count();
    assert_eq!(black_polygons, 1, "{svg}");
    let cross_strokes = svg
        .lines()
        .filter(|l| {
            l.starts_with("<line")
                && attr(l, "stroke").as_deref() == Some("#000000")
                && attr(l, "stroke-width").as_deref() == Some("2")
        })
        .count();
    assert_eq!(cross_strokes, 2, "the × at the room's breach: two strokes");
    // The numbers of the survivable voids are written beside them.
    assert_eq!(texts(&svg, &format!("void {}", table.number)), 1);
    assert_eq!(texts(&svg, &format!("void {}", room.number)), 1);
}

/// The rescue map of the hand-built ensemble: one shaded square per cell of
/// `rescue_map.csv` with a survivable void beneath, in the colour of its share; the place
/// that recurs (the table, 3 of 4) outlined and labelled 75 %.
#[test]
fn the_rescue_map_shades_each_cell_by_its_share() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    hand_built_ensemble(dir);
    fem2rbd::rescue::ensemble::write_maps(dir).unwrap();
    let fig = RescueMapFigure::load(dir).unwrap().unwrap();
    let svg = svg_string(&fig).unwrap();
    let rows = read_map(&dir.join("rescue_map.csv"));
    let mut sizes = Vec::new();
    for share in [0.25, 0.5, 0.75] {
        let want = rows.iter().filter(|r| r.4[1] == share).count();
        assert!(want > 0);
        // The legend shows 25, 50, 75 and 100 % swatches, one rect each.
        let got = rects(&svg, &hex(share_colour(share)), None);
        assert_eq!(got.len(), want + 1, "share {share}");
        sizes.extend(got.into_iter().map(|r| (r[2], r[3])));
    }
    // The map's cells are squares of one size (the legend swatches are 18 × 14 px).
    let cells: Vec<_> = sizes.iter().filter(|s| s.0 != 18.0).collect();
    assert!(cells
        .iter()
        .all(|s| (s.0 - cells[0].0).abs() <= 1.0 && (s.0 - s.1).abs() <= 1.0));
    // The recurring place's label and the legend's two 75 % swatches (voids, routes).
    assert_eq!(texts(&svg, "75 %"), 3);
    assert_eq!(
        texts(&svg, "25 %"),
        2,
        "only the legend: the far table does not recur"
    );
}

/// The `points` of an SVG element's line, as x, y pairs (px).
fn points(line: &str) -> Vec<[f64; 2]> {
    attr(line, "points")
        .unwrap()
        .split_whitespace()
        .map(|p| {
            let mut xy = p.split(',').map(|t| t.parse::<f64>().unwrap());
            [xy.next().unwrap(), xy.next().unwrap()]
        })
        .collect()
}

/// The points of every black `<polyline>` (the routes, and the legend's short strokes).
fn black_polylines(svg: &str) -> Vec<Vec<[f64; 2]>> {
    svg.lines()
        .filter(|l| l.starts_with("<polyline") && attr(l, "stroke").as_deref() == Some("#000000"))
        .map(points)
        .collect()
}

/// The room down a corridor (`routes.rs`): the plan draws the rescuer's route of
/// `voids.json` as one black line of two points, 2.9 m long along x (to 1.5 px at the
/// figure's scale, read from the room's box), starting 2.05 m to the left of the room's
/// box (its left edge at the door's x = −1.0, the route at x = −3.05 m), with an entry
/// triangle at its start.
#[test]
fn the_voids_plan_draws_the_rescuers_route() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    write_run(dir, &room_down_a_corridor(), &[], 1.0);
    let out = Command::new(env!("CARGO_BIN_EXE_fem2rbd"))
        .args(["--quiet", "voids"])
        .arg(dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let voids = read_voids(dir).unwrap().unwrap();
    let room = voids.iter().find(|v| v.number == 1).unwrap().clone();
    let route = room
        .rescuer_route
        .clone()
        .expect("voids.json holds the route");
    assert_eq!(route.len(), 2, "{route:?}");
    assert!((route[0][0] + 3.05).abs() < 1e-9 && (route[1][0] + 0.15).abs() < 1e-9);
    let fig = VoidsFigure::new(None, View::Plan, voids.clone());
    let svg = svg_string(&fig).unwrap();
    // The room's box (1.8 × 1.6 m with its doorway) among the filled boxes of its colour
    // (the corridor's, 2.0 × 0.8 m, is of the same pattern).
    let (bw, bh) = (
        room.bounds[1][0] - room.bounds[0][0],
        room.bounds[1][1] - room.bounds[0][1],
    );
    let r = rects(&svg, &hex(pattern_colour(&room.pattern)), Some("0.45"))
        .into_iter()
        .find(|r| (r[2] / r[3] - bw / bh).abs() < 0.02)
        .expect("the room's box");
    let ppm = r[2] / bw;
    // The route among the black polylines (the axes', the legend's strokes): the one of
    // two points 2.9 m long at the figure's scale.
    let all = black_polylines(&svg);
    let lines: Vec<_> = all
        .iter()
        .filter(|p| p.len() == 2 && ((p[1][0] - p[0][0]) - 2.9 * ppm).abs() <= 1.5)
        .collect();
    assert_eq!(lines.len(), 1, "one route line at {ppm} px/m: {all:?}");
    let l = lines[0];
    assert!((l[1][1] - l[0][1]).abs() <= 1.5, "along x: {l:?}");
    let left = (route[0][0] - room.bounds[0][0]) * ppm;
    assert!(
        (l[0][0] - r[0] - left).abs() <= 1.5,
        "{} vs {left}",
        l[0][0] - r[0]
    );
    // The entry triangle's centre at the line's start.
    let tri = polygons(&svg, "#000000");
    // One per reached survivable void: the room's and the corridor's (also survivable).
    assert_eq!(tri.len(), 2);
    let centre =
        |t: &Vec<[f64; 2]>| [0, 1].map(|k| t.iter().map(|p| p[k]).sum::<f64>() / t.len() as f64);
    assert!(
        tri.iter().any(|t| {
            let c = centre(t);
            (c[0] - l[0][0]).abs() <= 2.0 && (c[1] - l[0][1]).abs() <= 3.0
        }),
        "no triangle at the line's start {:?}: {tri:?}",
        l[0]
    );
}

/// The points of every `<polygon>` filled `fill`.
fn polygons(svg: &str, fill: &str) -> Vec<Vec<[f64; 2]>> {
    svg.lines()
        .filter(|l| l.starts_with("<polygon") && attr(l, "fill").as_deref() == Some(fill))
        .map(points)
        .collect()
}

/// The rescue map of the corridor ensemble (`route_map.rs`: the rescuer's routes pass
/// over 6 cells of row 3 in both members and 2 in one, and leave open air in 2 cells, in
/// one member each): 6 dark orange squares of the share 1 and 2 of 0.5 (plus a legend
/// swatch each), each half a map cell wide, centred on one row, a cell apart from each
/// other; 2 black triangles (plus the legend's) at the centres of the two cells where
/// the routes leave open air, the first two of the row. A map without the route columns
/// is refused naming the file and the column.
#[test]
fn the_rescue_map_draws_the_rescuers_routes() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    corridor_ensemble(dir);
    fem2rbd::rescue::ensemble::write_maps(dir).unwrap();
    let routes = read_route_map(&dir.join("rescue_map.csv"));
    let fig = RescueMapFigure::load(dir).unwrap().unwrap();
    let svg = svg_string(&fig).unwrap();
    // The map's own cells (not the 18 × 14 px legend swatches).
    let map_rects = |c| {
        rects(&svg, &hex(c), None)
            .into_iter()
            .filter(|r| r[2] != 18.0)
            .collect::<Vec<_>>()
    };
    let full = map_rects(route_colour(1.0));
    let half = map_rects(route_colour(0.5));
    assert_eq!(full.len(), 6, "{svg}");
    assert_eq!(half.len(), 2);
    assert_eq!(rects(&svg, &hex(route_colour(1.0)), None).len(), 7);
    for share in [0.5, 1.0] {
        let want = routes.iter().filter(|r| r.4[0] == share).count();
        assert_eq!(map_rects(route_colour(share)).len(), want);
    }
    // A map cell's width from the survivable shares' squares (the room's cells).
    let cell = rects(&svg, &hex(share_colour(1.0)), None)
        .into_iter()
        .chain(rects(&svg, &hex(share_colour(0.5)), None))
        .map(|r| r[2])
        .find(|w| *w != 18.0)
        .expect("a survivable cell");
    let mut all: Vec<[f64; 4]> = full.iter().chain(&half).copied().collect();
    all.sort_by(|a, b| a[0].total_cmp(&b[0]));
    let centre = |r: &[f64; 4]| [r[0] + r[2] / 2.0, r[1] + r[3] / 2.0];
    for r in &all {
        assert!((r[2] - cell / 2.0).abs() <= 1.0 && (r[3] - cell / 2.0).abs() <= 1.0);
        assert!(
            (centre(r)[1] - centre(&all[0])[1]).abs() <= 1.0,
            "one row: {all:?}"
        );
    }
    for w in all.windows(2) {
        assert!(
            (centre(&w[1])[0] - centre(&w[0])[0] - cell).abs() <= 1.0,
            "a cell apart: {all:?}"
        );
    }
    // The ends of the row are the half shares.
    assert!(half.iter().any(|r| r[0] == all[0][0]));
    assert!(half.iter().any(|r| r[0] == all[7][0]));
    // The entries: two triangles (and the legend's) centred on the row's first two cells.
    let tri = polygons(&svg, "#000000");
    assert_eq!(tri.len(), 3, "{tri:?}");
    let mid = |t: &Vec<[f64; 2]>| {
        let n = t.len() as f64;
        [
            t.iter().map(|p| p[0]).sum::<f64>() / n,
            t.iter().map(|p| p[1]).sum::<f64>() / n,
        ]
    };
    for r in &all[..2] {
        let c = centre(r);
        assert!(
            tri.iter().any(|t| {
                let m = mid(t);
                (m[0] - c[0]).abs() <= 1.5 && (m[1] - c[1]).abs() <= 3.0
            }),
            "no triangle at {c:?}: {tri:?}"
        );
    }

    // A map of an older analysis, without the route columns.
    let csv = std::fs::read_to_string(dir.join("rescue_map.csv")).unwrap();
    let old: String = csv
        .lines()
        .map(|l| l.split(',').take(8).collect::<Vec<_>>().join(",") + "\n")
        .collect();
    std::fs::write(dir.join("rescue_map.csv"), old).unwrap();
    let e = RescueMapFigure::load(dir).unwrap_err().to_string();
    assert!(
        e.contains("rescue_map.csv") && e.contains("`p_route_rescuer`"),
        "{e}"
    );
}

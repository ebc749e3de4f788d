//! Access routes as lines (`src/rescue/route.rs`): a hand-built ruin whose route is known.
use super::scene::*;

/// The room down a corridor (scale 1, 0.1 m cells). The room's most spacious cells (0.75 m
/// from the ground, the roof and the walls; the door lets the set reach 0.65 m into the
/// room from its −x wall's inner face) nearest the door lie at x = −0.15 m,
/// y = ±0.05 m, z = 0.75 or 0.85 m; the least crawl under debris runs straight along the
/// corridor's axis from its mouth at x = −3.0 m: 29 covered cells, 2.9 m, entering
/// through the debris' −x side. The line is two points: the open cell before the mouth
/// (x = −3.05 m) and the reached cell's centre, at the same y and z. The rescuer (0.6 m)
/// and the camera take the same line.
#[test]
fn the_route_to_a_room_down_a_corridor_is_the_corridor() {
    let a = analysed(&room_down_a_corridor(), &[], 1.0, 0.1);
    assert_eq!(a.voids.len(), 2, "{}", a.voids_csv());
    let room = &a.voids[0];
    close(
        room.void.volume_m3,
        1.6 * 1.6 * 1.6 + 0.2 * 0.8 * 1.6,
        1e-9,
        "room and door",
    );
    close(a.voids[1].void.volume_m3, 2.0 * 0.8 * 1.6, 1e-9, "corridor");
    let r = room.rescuer.as_ref().expect("the rescuer reaches the room");
    close(r.route_m, 2.9, 1e-9, "crawl length");
    assert_eq!(r.entry, "x-");
    assert_eq!(r.path_m.len(), 2, "{:?}", r.path_m);
    let (start, end) = (r.path_m[0], r.path_m[1]);
    close(end[0], -0.15, 1e-9, "end x");
    assert!(
        [-0.05, 0.05].iter().any(|y| (end[1] - y).abs() < 1e-9),
        "end y {}",
        end[1]
    );
    assert!(
        [0.75, 0.85].iter().any(|z| (end[2] - z).abs() < 1e-9),
        "end z {}",
        end[2]
    );
    close(
        start[0],
        -3.05,
        1e-9,
        "start x: the open cell before the mouth",
    );
    close(start[1], end[1], 1e-9, "straight along x: y");
    close(start[2], end[2], 1e-9, "straight along x: z");
    let c = room.camera.as_ref().expect("the camera reaches the room");
    assert_eq!(c.path_m, r.path_m);
    close(c.route_m, 2.9, 1e-9, "camera crawl length");
    // voids.json carries the line and its tolerance.
    let js = a.json();
    assert_eq!(js["route_tolerance_m"], 0.1);
    let p = &js["voids"][0]["rescuer"]["path_m"];
    assert_eq!(p.as_array().unwrap().len(), 2);
    close(p[0][0].as_f64().unwrap(), -3.05, 1e-9, "voids.json start x");
    close(p[1][0].as_f64().unwrap(), -0.15, 1e-9, "voids.json end x");
}

/// The table (one covered cell from the open side, `voids.rs`): the line is one cell step
/// from the open cell outside the slab's edge into the first covered cell, h = 0.1 m long,
/// along the entry side's axis.
#[test]
fn the_route_under_a_table_is_one_step_in_from_its_side() {
    let (boxes, cons) = table();
    let a = analysed(&boxes, &cons, 1.0, 0.1);
    let r = a.voids[0].rescuer.as_ref().unwrap();
    assert_eq!(r.path_m.len(), 2, "{:?}", r.path_m);
    let d: Vec<f64> = (0..3).map(|k| r.path_m[1][k] - r.path_m[0][k]).collect();
    let axis = match r.entry {
        "x-" | "x+" => 0,
        "y-" | "y+" => 1,
        e => panic!("entry {e}"),
    };
    let sign = if r.entry.ends_with('-') { 1.0 } else { -1.0 };
    for (k, dk) in d.iter().enumerate() {
        let want = if k == axis { sign * 0.1 } else { 0.0 };
        close(*dk, want, 1e-9, "one step inwards");
    }
}

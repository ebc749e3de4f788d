#!/usr/bin/env python3
"""Where the farthest pieces of a ruin come from: for every body that ends farther beyond
the original footprint than 2/3 of the building's height (the planning rule), the largest
jump of its horizontal velocity relative to the ground between two keyframes after the
hand-off (a kick), when and how high it happened; the ground's largest plan
displacement over the run; and the pieces that rise after the hand-off (a launch): for
every body the largest rise of its centre above its lowest point since the hand-off,
read between keyframes, and how many rise more than 1 m and 2 m.

Usage: python3 scripts/far-pieces.py RUN_DIR
Reads bodies.csv, ruins.csv, keyframes.csv and summary.json of a run folder (fem2rbd run).
"""
import csv
import json
import math
import sys
from collections import defaultdict


def vertical_half_extent(b):
    """Half the vertical extent of a box of `bodies.csv`: sum over its local axes of
    |R[2][k]| h_k, R the rotation of the quaternion (qw, qx, qy, qz)."""
    w, x, y, z = (float(b[k]) for k in ("qw", "qx", "qy", "qz"))
    row = (2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y))
    return sum(abs(r) * float(b[k]) for r, k in zip(row, ("hx", "hy", "hz")))


def main(run):
    summary = json.load(open(f"{run}/summary.json"))
    fp = summary["ruins"]["original_footprint_m"]
    (x0, x1), (y0, y1) = fp["x"], fp["y"]
    bodies = {r["name"]: r for r in csv.DictReader(open(f"{run}/bodies.csv"))}
    standing = [b for b in bodies.values() if b["passive"] == "0"]
    top = max(float(b["cz"]) + vertical_half_extent(b) for b in standing)
    base = min(float(b["cz"]) - vertical_half_extent(b) for b in standing)
    height = top - base
    limit = 2.0 / 3.0 * height

    def beyond(x, y):
        return math.hypot(max(x0 - x, 0.0, x - x1), max(y0 - y, 0.0, y - y1))

    def side(x, y):
        dx = max(x0 - x, 0.0, x - x1)
        dy = max(y0 - y, 0.0, y - y1)
        if dx >= dy:
            return "x-" if x < x0 else "x+"
        return "y-" if y < y0 else "y+"

    far = {}
    sides = {}
    for r in csv.DictReader(open(f"{run}/ruins.csv")):
        x, y = float(r["x"]), float(r["y"])
        d = beyond(x, y)
        if d > limit:
            far[r["name"]] = d
            sides[r["name"]] = side(x, y)
    ground_name = next(n for n, b in bodies.items() if b["passive"] == "1")
    g0 = (float(bodies[ground_name]["cx"]), float(bodies[ground_name]["cy"]))
    tc = summary.get("ruin_stage", {}).get("start_s", 0.0)
    track = defaultdict(list)
    lowest = {}  # body -> (z, t): its lowest centre since the hand-off
    rise = {}  # body -> (rise m, from z m, from t s, top t s)
    with open(f"{run}/keyframes.csv") as f:
        rows = csv.reader(f)
        next(rows)
        for t, name, x, y, z, *_ in rows:
            if name in far or name == ground_name:
                track[name].append((float(t), float(x), float(y), float(z)))
            t, z = float(t), float(z)
            if t < tc or name == ground_name:
                continue
            low = lowest.get(name)
            if low is None or z < low[0]:
                low = lowest[name] = (z, t)
            if z - low[0] > rise.get(name, (0.0,))[0]:
                rise[name] = (z - low[0], low[0], low[1], t)
    ground = track[ground_name]
    gmax = max(ground, key=lambda p: math.hypot(p[1] - g0[0], p[2] - g0[1]))
    print(f"building height {height:.2f} m; 2/3 of it {limit:.2f} m; hand-off {tc:.3f} s")
    print(
        f"ground: largest plan displacement {math.hypot(gmax[1] - g0[0], gmax[2] - g0[1]):.2f} m "
        f"at {gmax[0]:.2f} s; at the end {math.hypot(ground[-1][1] - g0[0], ground[-1][2] - g0[1]):.2f} m"
    )
    gvel = {}
    for a, b in zip(ground, ground[1:]):
        dt = b[0] - a[0]
        gvel[b[0]] = ((b[1] - a[1]) / dt, (b[2] - a[2]) / dt)
    at_tc = min(gvel, key=lambda t: abs(t - tc))
    print(
        "ground velocity at the hand-off: vx {:.2f} m/s, vy {:.2f} m/s (between keyframes)".format(
            *gvel[at_tc]
        )
    )
    print(f"{len(far)} bodies end more than {limit:.2f} m beyond the footprint")
    print("body,type,side,beyond_m,kick_mps,kick_at_s,kick_z_m,max_speed_mps")
    kicks = []
    for name, d in sorted(far.items(), key=lambda kv: -kv[1]):
        tr = track[name]
        vel = []
        for a, b in zip(tr, tr[1:]):
            dt = b[0] - a[0]
            g = gvel.get(b[0], (0.0, 0.0))
            vel.append((b[0], (b[1] - a[1]) / dt - g[0], (b[2] - a[2]) / dt - g[1], (b[3] - a[3]) / dt, b[3]))
        best = (0.0, 0.0, 0.0)
        vmax = 0.0
        for p, q in zip(vel, vel[1:]):
            if q[0] <= tc:
                continue
            jump = math.hypot(q[1] - p[1], q[2] - p[2])
            vmax = max(vmax, math.sqrt(q[1] ** 2 + q[2] ** 2 + q[3] ** 2))
            if jump > best[0]:
                best = (jump, q[0], q[4])
        kicks.append(best[0])
        print(f"{name},{bodies[name]['type']},{sides[name]},{d:.2f},{best[0]:.2f},{best[1]:.2f},{best[2]:.2f},{vmax:.2f}")
    counts = {s: list(sides.values()).count(s) for s in ("x-", "x+", "y-", "y+")}
    print("sides: " + ", ".join(f"{k} {v}" for k, v in counts.items()))
    if kicks:
        kicks.sort()
        print(f"largest horizontal kick per body: median {kicks[len(kicks) // 2]:.1f} m/s, max {kicks[-1]:.1f} m/s")
    launched = sorted(rise.items(), key=lambda kv: -kv[1][0])
    print(
        f"rise of a centre above its lowest point since the hand-off: {sum(r[0] > 1.0 for _, r in launched)} "
        f"bodies more than 1 m, {sum(r[0] > 2.0 for _, r in launched)} more than 2 m; the largest:"
    )
    print("body,rise_m,from_z_m,from_t_s,top_t_s,ends_beyond_m")
    for name, (r, z, t0, t1) in launched[:10]:
        print(f"{name},{r:.2f},{z:.2f},{t0:.2f},{t1:.2f},{far.get(name, 0.0):.2f}")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])

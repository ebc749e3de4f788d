#!/usr/bin/env python3
"""How deep the pieces of each connection lie inside each other when the connection yields
or breaks: for every connection that turns plastic or breaks by END_S (the earlier of
`connections.csv` `time_plastic_s` and `time_broken_s`), the overlap depth of its two
boxes at that keyframe (the separating-axis depth over the 15 axes of two boxes, m; the
monitor acts at keyframe times, so the keyframe holds the poses it saw). With
`connected_pairs_touch = "once_yielded"` that is when the pair's collision exemption is
lifted, and Bullet's contact then pushes the pieces apart at its Baumgarte velocity
ERP·depth/h (docs/ruin-numerics.md, "At full scale"). Prints the counts by depth, the deepest pairs,
and Σ ½·m_red·(ERP·depth/h)² as an order of magnitude of that push-out energy (m_red the
pair's reduced mass; the passive body's partner's mass for a foundation).

Usage: python3 scripts/released-overlaps.py RUN_DIR END_S [ERP (0.2)] [H_S (0.005)]
Reads bodies.csv, connections.csv and keyframes.csv of a run folder (fem2rbd run).
"""
import csv
import math
import sys


def rotation_axes(qw, qx, qy, qz):
    """The box's local axes in the world (the columns of the rotation matrix)."""
    r = [[1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qw * qz), 2 * (qx * qz + qw * qy)],
         [2 * (qx * qy + qw * qz), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qw * qx)],
         [2 * (qx * qz - qw * qy), 2 * (qy * qz + qw * qx), 1 - 2 * (qx * qx + qy * qy)]]
    return [[r[0][k], r[1][k], r[2][k]] for k in range(3)]


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def overlap_depth(a, b):
    """The smallest overlap of the projections of boxes a and b = (centre, axes, half
    extents) over the 15 separating axes, m (negative: apart)."""
    (ca, aa, ea), (cb, ab, eb) = a, b
    t = [cb[i] - ca[i] for i in range(3)]
    depth = math.inf
    for axis in aa + ab + [cross(x, y) for x in aa for y in ab]:
        n = math.sqrt(dot(axis, axis))
        if n < 1e-9:
            continue
        axis = [x / n for x in axis]
        ra = sum(ea[k] * abs(dot(aa[k], axis)) for k in range(3))
        rb = sum(eb[k] * abs(dot(ab[k], axis)) for k in range(3))
        depth = min(depth, ra + rb - abs(dot(t, axis)))
    return depth


def main(run, end_s, erp, h):
    body = {}
    for r in csv.DictReader(open(f"{run}/bodies.csv")):
        body[r["name"]] = ([float(r[k]) for k in ("hx", "hy", "hz")], float(r["mass_kg"]),
                           r["passive"] == "1")
    wanted, released = set(), []
    for r in csv.DictReader(open(f"{run}/connections.csv")):
        times = [float(x) for x in (r["time_plastic_s"], r["time_broken_s"]) if x]
        if times and min(times) <= end_s:
            t = round(min(times), 4)
            released.append((t, r["a"], r["b"]))
            wanted.update({(t, r["a"]), (t, r["b"])})
    pose = {}
    with open(f"{run}/keyframes.csv") as f:
        next(f)
        for line in f:
            t, name, rest = line.split(",", 2)
            t = round(float(t), 4)
            if t > end_s + 0.05:
                break
            if (t, name) in wanted:
                pose[(t, name)] = [float(x) for x in rest.split(",")]
    rows = []
    for t, a, b in released:
        if (t, a) not in pose or (t, b) not in pose:
            continue
        box = lambda n: (pose[(t, n)][:3], rotation_axes(*pose[(t, n)][3:7]), body[n][0])
        d = overlap_depth(box(a), box(b))
        (ma, pa), (mb, pb) = body[a][1:], body[b][1:]
        m = mb if pa else ma if pb else ma * mb / (ma + mb)
        rows.append((d, m, t, a, b))
    inside = [x for x in rows if x[0] > 0]
    print(f"{len(rows)} connections yielded or broke by {end_s:g} s; their pieces overlap in "
          f"{len(inside)}: {sum(x[0] > 0.01 for x in inside)} by more than 10 mm, "
          f"{sum(x[0] > 0.1 for x in inside)} by more than 0.1 m, "
          f"{sum(x[0] > 0.3 for x in inside)} by more than 0.3 m")
    energy = sum(0.5 * m * (erp * d / h) ** 2 for d, m, *_ in inside)
    print(f"sum of 1/2 m_red (ERP depth / h)^2 with ERP {erp:g}, h {h:g} s: "
          f"{energy / 1e3:.1f} kJ")
    print("deepest: depth_m, reduced_mass_kg, t_s, a, b")
    for d, m, t, a, b in sorted(inside, reverse=True)[:10]:
        print(f"  {d:.3f}, {m:.0f}, {t:.2f}, {a}, {b}")


if __name__ == "__main__":
    if len(sys.argv) not in (3, 4, 5):
        sys.exit(__doc__)
    main(sys.argv[1], float(sys.argv[2]),
         float(sys.argv[3]) if len(sys.argv) > 3 else 0.2,
         float(sys.argv[4]) if len(sys.argv) > 4 else 0.005)

#!/usr/bin/env python3
"""Collapse stages of a run folder as one PNG: the bodies' boxes seen in elevation at
chosen times (the paper's Figure 13 for the library: 2.01 ... 18.43 s), one panel per
time, from `bodies.csv` (half extents, type) and `keyframes.csv` (poses on the
timeline). Needs numpy only (no matplotlib): boxes are projected and filled by a small
rasteriser, the PNG is written with zlib.

    python3 scripts/collapse-stages.py RUN_DIR OUT.png [--view x|y] [--times t1,t2,...]

--view x: seen from -Y (horizontal axis X); y: seen from +X (horizontal axis Y).
Each panel takes the last keyframe at or before its time; a time beyond the run's end
shows the last frame and says so in the panel's label line on stdout.
"""
import argparse
import csv
import struct
import sys
import zlib

import numpy as np

PAPER_TIMES = [2.01, 3.01, 3.64, 4.26, 5.51, 6.97, 14.26, 18.43]
COLOURS = {  # RGB per body type
    "Column": (200, 60, 50),
    "Beam": (60, 110, 200),
    "Slab": (150, 150, 150),
    "Wall": (220, 170, 60),
    "Foundation": (60, 60, 60),
}


def quat_matrix(w, x, y, z):
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ])


def hull(points):
    """Convex hull (Andrew's monotone chain), counter-clockwise."""
    pts = sorted(set(map(tuple, points)))
    if len(pts) < 3:
        return pts

    def cross(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    lower, upper = [], []
    for p in pts:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    for p in reversed(pts):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    return lower[:-1] + upper[:-1]


def fill(img, poly, colour):
    """Fills a convex polygon (pixel coordinates) into img (H x W x 3)."""
    h, w, _ = img.shape
    ys = [p[1] for p in poly]
    y0, y1 = max(int(np.floor(min(ys))), 0), min(int(np.ceil(max(ys))), h - 1)
    n = len(poly)
    for y in range(y0, y1 + 1):
        yc = y + 0.5
        xs = []
        for k in range(n):
            (ax, ay), (bx, by) = poly[k], poly[(k + 1) % n]
            if (ay <= yc < by) or (by <= yc < ay):
                xs.append(ax + (yc - ay) * (bx - ax) / (by - ay))
        if len(xs) >= 2:
            xa, xb = max(int(round(min(xs))), 0), min(int(round(max(xs))), w)
            if xb > xa:
                img[y, xa:xb] = colour


def write_png(path, img):
    h, w, _ = img.shape
    raw = b"".join(b"\x00" + img[y].astype(np.uint8).tobytes() for y in range(h))

    def chunk(kind, data):
        c = struct.pack(">I", len(data)) + kind + data
        return c + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    with open(path, "wb") as fh:
        fh.write(png)


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("run_dir")
    ap.add_argument("out")
    ap.add_argument("--view", choices=["x", "y"], default="x")
    ap.add_argument("--times", default=",".join(map(str, PAPER_TIMES)))
    ap.add_argument("--panel-px", type=int, default=400, help="panel width in pixels")
    a = ap.parse_args(argv[1:])
    times = [float(t) for t in a.times.split(",")]
    bodies = {r["name"]: r for r in csv.DictReader(open(f"{a.run_dir}/bodies.csv"))}
    frames = {}
    for r in csv.DictReader(open(f"{a.run_dir}/keyframes.csv")):
        frames.setdefault(float(r["t"]), {})[r["name"]] = r
    tk = sorted(frames)
    if not tk:
        sys.exit(f"{a.run_dir}/keyframes.csv: no frames")
    axis = 0 if a.view == "x" else 1
    corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
    # Plot window from the undeformed building, with room for the debris.
    cs = np.array([[float(b["cx"]), float(b["cy"]), float(b["cz"])] for b in bodies.values()])
    hmin, hmax = cs[:, axis].min(), cs[:, axis].max()
    span = hmax - hmin
    u0, u1 = hmin - 0.3 * span, hmax + 0.3 * span
    z0, z1 = -1.0, cs[:, 2].max() + 3.0
    pw = a.panel_px
    scale = pw / (u1 - u0)
    ph = int(np.ceil((z1 - z0) * scale))
    img = np.full((ph, pw * len(times), 3), 255, dtype=np.uint8)
    for k, t in enumerate(times):
        before = [x for x in tk if x <= t + 1e-9]
        tf = before[-1] if before else tk[0]
        note = "" if t <= tk[-1] + 1e-9 else f" (run ends at {tk[-1]:.2f} s: last frame)"
        print(f"panel {k + 1}: t = {t:.2f} s -> frame {tf:.2f} s{note}")
        fr = frames[tf]
        # far bodies first so the near face is drawn last
        depth_axis = 1 - axis
        order = sorted(fr, key=lambda n: -float(fr[n]["y" if depth_axis == 1 else "x"]))
        for n in order:
            b, r = bodies[n], fr[n]
            half = np.array([float(b["hx"]), float(b["hy"]), float(b["hz"])])
            rot = quat_matrix(*(float(r[q]) for q in ("qw", "qx", "qy", "qz")))
            c = np.array([float(r["x"]), float(r["y"]), float(r["z"])])
            pts = c + (corners * half) @ rot.T
            proj = [((p[axis] - u0) * scale + k * pw, (z1 - p[2]) * scale) for p in pts]
            colour = COLOURS.get(b["type"], (0, 0, 0))
            fill(img, hull(proj), colour)
        img[:, k * pw] = (0, 0, 0)
        zg = int((z1 - 0.0) * scale)
        if 0 <= zg < ph:
            img[zg, k * pw:(k + 1) * pw] = (0, 0, 0)
    write_png(a.out, img)
    print(f"{a.out}: {len(times)} panels, {img.shape[1]} x {img.shape[0]} px")


if __name__ == "__main__":
    main(sys.argv)

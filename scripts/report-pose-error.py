#!/usr/bin/env python3
"""The error of the poses a report page draws against the run's keyframes
(docs/report.md, "Data and size"). Usage:

    python3 scripts/report-pose-error.py RUN_DIR [REPORT.html]

Reads the page data of REPORT.html (default RUN_DIR/report.html), decodes the box
centres and quaternions as the page does (src/report/page.js: origin + step · code;
code / 32 767, normalised) and compares them with RUN_DIR/keyframes.csv, every body at
every frame. Prints the page's size and what its data holds, then the largest centre
error (the largest over x, y and z, m), the largest rotation error (rad) and the
largest displacement of a box corner (centre error plus the corner's move under the
rotation error, m, with the box sizes of the page data), each with the body and the
time where it occurs.
"""
import base64
import json
import re
import sys

import numpy as np

run_dir = sys.argv[1]
report = sys.argv[2] if len(sys.argv) > 2 else run_dir + "/report.html"
html = open(report, "rb").read()
m = re.search(rb'<script type="application/json" id="report-data">(.*?)</script>', html, re.S)
data = json.loads(m.group(1))
names = data["bodies"]["name"]
n = len(names)
times = data["times"]
f = len(times)

pos_data = data["position"]
codes = np.frombuffer(base64.b64decode(pos_data["u16"]), dtype="<u2").astype(np.float64)
pos = np.array(pos_data["origin"]) + pos_data["step"] * codes.reshape(f, n, 3)
q = np.frombuffer(base64.b64decode(data["rotation"]["i16"]), dtype="<i2").astype(np.float64)
q = q.reshape(f, n, 4)
q /= np.linalg.norm(q, axis=2, keepdims=True)

# keyframes.csv: t,name,x,y,z,qw,qx,qy,qz, frame by frame in bodies.csv order.
kf = np.loadtxt(run_dir + "/keyframes.csv", delimiter=",", skiprows=1, usecols=(2, 3, 4, 5, 6, 7, 8))
kf = kf.reshape(f, n, 7)
true_pos = kf[:, :, 0:3]
true_q = kf[:, :, [4, 5, 6, 3]]  # x, y, z, w as the page
true_q /= np.linalg.norm(true_q, axis=2, keepdims=True)


def matrices(qq):
    x, y, z, w = (qq[..., k] for k in range(4))
    return np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)], -1),
            np.stack([2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)], -1),
            np.stack([2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)], -1),
        ],
        -2,
    )


centre_err = np.abs(pos - true_pos).max(axis=2)
dot = np.abs((q * true_q).sum(axis=2)).clip(0.0, 1.0)
angle = 2 * np.arccos(dot)
half = 0.5 * np.array(data["bodies"]["size"]).reshape(n, 3)
dr = matrices(q) - matrices(true_q)  # f × n × 3 × 3
corner = 0.0
where_corner = (0, 0)
for sx in (-1, 1):
    for sy in (-1, 1):
        for sz in (-1, 1):
            local = half * np.array([sx, sy, sz])  # n × 3
            move = np.einsum("fnij,nj->fni", dr, local) + (pos - true_pos)
            d = np.linalg.norm(move, axis=2)
            k = np.unravel_index(np.argmax(d), d.shape)
            if d[k] > corner:
                corner, where_corner = d[k], k


def at(k):
    return f"{names[k[1]]} at t = {times[k[0]]} s"


kc = np.unravel_index(np.argmax(centre_err), centre_err.shape)
ka = np.unravel_index(np.argmax(angle), angle.shape)
print(f"report: {len(html)} bytes; {f} frames x {n} bodies; position step {pos_data['step']:.6g} m")
print(f"largest centre error: {centre_err[kc]:.3e} m ({at(kc)})")
print(f"largest rotation error: {angle[ka]:.3e} rad ({at(ka)})")
print(f"largest corner displacement: {corner:.3e} m ({at(where_corner)})")

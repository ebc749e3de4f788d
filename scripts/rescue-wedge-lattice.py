#!/usr/bin/env python3
"""The lean-to wedge's void volume counted independently of fem2rbd (docs/rescue.md §4).

The hand-built lean-to of tests/it/rescue/scene.rs (`lean_to(40)`: a 2.0 m wall
x in [0, 0.2], a 0.2 m slab at 40 deg from the wall's top inner edge (0.2, 2.0) to the
ground, 3.0 m wide) on the grid `fem2rbd voids` builds for it (origin 0.8 m + 2 cells
beyond the slab's undeformed end, ground at z = 0). Each cell of the cross-section is
solid when at least half of a 100 x 100 point lattice lies in the slab or the wall; a
free cell under a solid one is covered. Prints the void volume (covered cells x h^2 x
3.0 m) for each cell size and the exact 6.0 / tan 40 deg.

Usage: python3 scripts/rescue-wedge-lattice.py [h ...]   (default 0.2 0.1 0.05)
"""
import sys

import numpy as np


def wedge_volume(h, deg=40.0, margin=0.6, width=3.0):
    th = np.radians(deg)
    n = np.array([np.sin(th), np.cos(th)])
    p1 = np.array([0.2, 2.0])
    length = 2.2 / np.sin(th)
    pad = margin + 2 * h
    # The grid's x origin: the slab's undeformed end (centre 1.3 m, half length/2) - pad.
    x0 = 1.3 - length / 2 - pad
    nx = int(np.ceil((0.2 + 2.2 / np.tan(th) + 2 * pad) / h)) + 2
    nz = int(np.ceil(2.6 / h))
    s = (np.arange(100) + 0.5) / 100
    solid = np.zeros((nx, nz), bool)
    for i in range(nx):
        for k in range(nz):
            X, Z = np.meshgrid(x0 + (i + s) * h, (k + s) * h, indexing="ij")
            d = (X - p1[0]) * n[0] + (Z - p1[1]) * n[1]
            u = (X - p1[0]) * np.cos(th) - (Z - p1[1]) * np.sin(th)
            slab = (d >= 0) & (d <= 0.2) & (u >= 0) & (u <= length)
            wall = (X >= 0) & (X <= 0.2) & (Z <= 2.0)
            solid[i, k] = (slab | wall).mean() >= 0.5
    covered = 0
    for i in range(nx):
        top = max([k + 1 for k in range(nz) if solid[i, k]], default=0)
        covered += sum(1 for k in range(top) if not solid[i, k])
    return covered * h * h * width


if __name__ == "__main__":
    cells = [float(a) for a in sys.argv[1:]] or [0.2, 0.1, 0.05]
    exact = 6.0 / np.tan(np.radians(40.0))
    for h in cells:
        print(f"cell {h} m: {wedge_volume(h):.5f} m3 (exact {exact:.5f})")

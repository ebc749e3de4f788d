"""Reads .vtu files with meshio (an independent VTK XML reader; pip package `meshio`) and
prints, as one JSON list, each file's points, cells and cell data, for tests/it/output/gltf_vtk.rs.

Usage: python3 tests/gltf/read_vtu.py FILE.vtu...
Exit status 3 when meshio is not installed (pip install meshio==5.3.5).
"""
import json
import sys

try:
    import meshio
except ImportError as e:
    print(f"meshio is not installed (pip install meshio==5.3.5): {e}", file=sys.stderr)
    sys.exit(3)


def as_json(path):
    mesh = meshio.read(path)
    return {
        "points": mesh.points.tolist(),
        "cells": [{"type": b.type, "data": b.data.tolist()} for b in mesh.cells],
        "cell_data": {n: [a.tolist() for a in arrays] for n, arrays in mesh.cell_data.items()},
    }


print(json.dumps([as_json(path) for path in sys.argv[1:]]))

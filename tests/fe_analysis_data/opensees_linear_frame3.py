#!/usr/bin/env python3
"""frame3, elastic variant, with *Linear* geometric transformations in openseespy:
the same model as the Rust test element (geometrically linear Euler-Bernoulli), so
the analysis layers can be compared number for number.

Prints one JSON object: eigen periods (initial stiffness), gravity sag of node 312,
and the LC1 roof-centre (312) history ux, uy, uz for t <= --tmax.
Analysis exactly as tests/fixtures/opensees-frame3/run_frame3.py: gravity in 10
LoadControl steps (NormDispIncr 1e-10/50, Newton), loadConst -time 0, Rayleigh
5 % at T1 and T1/3 on the initial stiffness, Newmark 0.5/0.25, dt 0.005,
NormDispIncr 1e-8/50, UniformExcitation X/Y/Z from Path series (-dt, -factor).
"""
import argparse
import json
import math
import os
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "tests", "opensees"))
try:
    from ops_import import ops  # noqa: E402
except Exception as exc:  # pragma: no cover
    sys.stderr.write("openseespy is required (pip install openseespy==3.7.1): %s\n" % exc)
    sys.exit(2)


def read_at2(path):
    with open(path) as fh:
        lines = fh.read().splitlines()
    m = re.search(r"NPTS=\s*(\d+),\s*DT=\s*([\d.Ee+-]+)", lines[3])
    npts, dt = int(m.group(1)), float(m.group(2))
    vals = [float(x) for ln in lines[4:] for x in ln.split()]
    assert len(vals) == npts
    return dt, vals


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--tmax", type=float, default=6.0)
    args = ap.parse_args()
    with open(os.path.join(ROOT, "data", "frame3-standin", "reference-frame3.json")) as fh:
        model = json.load(fh)
    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    for n in model["nodes"]:
        ops.node(n["tag"], n["x"], n["y"], n["z"])
    for fx in model["fixed_nodes"]:
        ops.fix(fx["tag"], *fx["dofs"])
    for m in model["nodal_masses"]:
        ops.mass(m["tag"], m["mx"], m["my"], m["mz"], m["mrx"], m["mry"], m["mrz"])
    for gt in model["geom_transforms"]:
        ops.geomTransf("Linear", gt["tag"], *gt["vecxz"])
    secs = {s["tag"]: s for s in model["sections"]}
    for e in model["elements"]:
        i, j = e["nodes"]
        if e["type"] == "elastic_beam_column":
            ops.element("elasticBeamColumn", e["tag"], i, j, e["A"], e["E"], e["G"], e["J"],
                        e["Iy"], e["Iz"], e["transf"])
        else:
            q = secs[e["section"]]["elastic_equivalent"]
            ops.element("elasticBeamColumn", e["tag"], i, j, q["EA"], 1.0, 1.0, q["GJ"],
                        q["EIy"], q["EIz"], e["transf"])
    lam = ops.eigen("-fullGenLapack", 9)
    periods = [2 * math.pi / math.sqrt(x) for x in lam]

    ops.timeSeries("Linear", 1)
    ops.pattern("Plain", 1, 1)
    for ld in model["gravity_loads"]["loads"]:
        ops.load(ld["tag"], 0.0, 0.0, ld["Fz"], 0.0, 0.0, 0.0)
    ops.constraints("Plain")
    ops.numberer("RCM")
    ops.system("UmfPack")
    ops.test("NormDispIncr", 1e-10, 50)
    ops.algorithm("Newton")
    ops.integrator("LoadControl", 0.1)
    ops.analysis("Static")
    assert ops.analyze(10) == 0
    ops.loadConst("-time", 0.0)
    ops.wipeAnalysis()
    sag = ops.nodeDisp(312, 3)

    t1 = periods[0]
    wi = 2 * math.pi / t1
    wj = 3 * wi
    a0 = 2 * 0.05 * wi * wj / (wi + wj)
    a1 = 2 * 0.05 / (wi + wj)
    ops.rayleigh(a0, 0.0, a1, 0.0)
    pga = model["ground_motion"]["load_cases_pga_g"]["LC1"]
    g = model["gravity"]
    for k, (dirn, key) in enumerate([(1, "X"), (2, "Y"), (3, "Z")]):
        rdt, vals = read_at2(os.path.join(ROOT, "data", "ground-motions", model["ground_motion"]["files"][key]))
        scale = pga[k] / max(abs(v) for v in vals)
        ops.timeSeries("Path", 10 + k, "-dt", rdt, "-values", *vals, "-factor", scale * g)
        ops.pattern("UniformExcitation", 10 + k, dirn, "-accel", 10 + k)
    ops.constraints("Plain")
    ops.numberer("RCM")
    ops.system("UmfPack")
    ops.test("NormDispIncr", 1e-8, 50)
    ops.algorithm("Newton")
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")
    hist = []
    nsteps = int(round(args.tmax / 0.005))
    for _ in range(nsteps):
        if ops.analyze(1, 0.005) != 0:
            sys.stderr.write("OpenSees step failed at t = %g\n" % ops.getTime())
            sys.exit(3)
        hist.append([ops.getTime()] + [ops.nodeDisp(312, d) for d in (1, 2, 3)])
    print(json.dumps({"periods": periods, "sag_312": sag, "a0": a0, "a1": a1, "history": hist}))


if __name__ == "__main__":
    main()

"""Runs the elastic portal of the element-removal test in OpenSees (openseespy) with
`remove element` at a given time, for crates/fem2rbd-fe/tests/it/fe/analysis/removal.rs.

Usage: python3 portal_removal.py case.json  -> prints JSON {"t": [...], "ux": [[node 3, node 4] per step]}

The case gives the nodes (the first two fixed), the nodal masses, the elements
(elasticBeamColumn, Linear transformation with vecxz, section A E G J Iy Iz), the ground
acceleration in X at every step end (a Path series on the step grid), the step dt, the
number of steps and the step after which element `remove` is removed. Newmark (1/2, 1/4),
Newton, NormDispIncr 1e-12, RCM, UmfPack, no damping.
"""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ops_or_exit import ops  # noqa: E402


def main(path):
    with open(path) as f:
        case = json.load(f)
    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    for k, (x, y, z) in enumerate(case["nodes"]):
        ops.node(k + 1, x, y, z)
    ops.fix(1, 1, 1, 1, 1, 1, 1)
    ops.fix(2, 1, 1, 1, 1, 1, 1)
    for node, m in case["masses"]:
        ops.mass(node, *m)
    for k, e in enumerate(case["elements"]):
        p = e["props"]
        ops.geomTransf("Linear", k + 1, *e["vecxz"])
        ops.element("elasticBeamColumn", e["tag"], *e["nodes"], p["A"], p["E"], p["G"], p["J"],
                    p["Iy"], p["Iz"], k + 1)
    dt = case["dt"]
    ops.timeSeries("Path", 1, "-dt", dt, "-values", *case["ag"])
    ops.pattern("UniformExcitation", 1, 1, "-accel", 1)
    ops.constraints("Plain")
    ops.numberer("RCM")
    ops.system("UmfPack")
    ops.test("NormDispIncr", 1e-12, 50)
    ops.algorithm("Newton")
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")
    t, ux = [0.0], [[0.0, 0.0]]
    for step in range(1, case["steps"] + 1):
        if ops.analyze(1, dt) != 0:
            raise SystemExit(f"step {step} did not converge")
        t.append(ops.getTime())
        ux.append([ops.nodeDisp(3, 1), ops.nodeDisp(4, 1)])
        if step == case["remove_after"]:
            ops.remove("element", case["remove"])
    print(json.dumps({"t": t, "ux": ux}))


if __name__ == "__main__":
    main(sys.argv[1])

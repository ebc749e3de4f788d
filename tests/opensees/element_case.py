"""Runs one static beam-column case in OpenSees (openseespy) for the fe_element_opensees test.

Usage: python3 element_case.py case.json   -> prints JSON {"u": [[6 dofs] per node], "iters": [...]}

The case (written by crates/fem2rbd-fe/tests/it/fe/element/opensees.rs) gives nodes, the fixed node, one
material (Elastic or ElasticPP), one symmetric fiber section with -GJ, elements
(elasticBeamColumn / forceBeamColumn Lobatto / dispBeamColumn Legendre) with a
geomTransf (Linear / PDelta / Corotational + vecxz), a nodal load pattern and the
number of load-control steps. Newton with NormDispIncr 1e-12, 100 iterations.
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
    ops.fix(case["fixed"] + 1, 1, 1, 1, 1, 1, 1)
    mat = case["material"]
    if mat["type"] == "Elastic":
        ops.uniaxialMaterial("Elastic", 1, mat["E"])
    elif mat["type"] == "Steel01":
        ops.uniaxialMaterial("Steel01", 1, mat["fy"], mat["E"], mat["b"])
    else:
        ops.uniaxialMaterial("ElasticPP", 1, mat["E"], mat["fy"] / mat["E"])
    ops.section("Fiber", 1, "-GJ", case["GJ"])
    for y, z, a in case["fibers"]:
        ops.fiber(y, z, a, 1)
    for k, el in enumerate(case["elements"]):
        tag = k + 1
        ops.geomTransf(el["transf"], tag, *el["vecxz"])
        i, j = el["nodes"][0] + 1, el["nodes"][1] + 1
        if el["type"] == "elastic":
            p = el["props"]
            ops.element("elasticBeamColumn", tag, i, j, p["A"], p["E"], p["G"], p["J"],
                        p["Iy"], p["Iz"], tag)
        elif el["type"] == "force":
            ops.beamIntegration("Lobatto", tag, 1, el["n_ip"])
            ops.element("forceBeamColumn", tag, i, j, tag, tag, "-iter", 50, 1e-12)
        else:
            ops.beamIntegration("Legendre", tag, 1, el["n_ip"])
            ops.element("dispBeamColumn", tag, i, j, tag, tag)
    ops.timeSeries("Linear", 1)
    ops.pattern("Plain", 1, 1)
    for node, load in case["loads"]:
        ops.load(node + 1, *load)
    ops.system("FullGeneral")
    ops.numberer("Plain")
    ops.constraints("Plain")
    ops.test("NormDispIncr", 1e-12, 100, 0)
    ops.algorithm("Newton")
    # Either `steps` equal increments to λ = 1, or a load-factor path `lambdas`
    # (total factors after each step; LoadControl with the matching increments).
    lambdas = case.get("lambdas") or [(k + 1) / case["steps"] for k in range(case["steps"])]
    iters = []
    history = []
    lam = 0.0
    for target in lambdas:
        ops.integrator("LoadControl", target - lam)
        ops.analysis("Static")
        if ops.analyze(1) != 0:
            print("OpenSees analysis failed", file=sys.stderr)
            sys.exit(3)
        lam = target
        iters.append(ops.testIter())
        history.append([ops.nodeDisp(len(case["nodes"]), d + 1) for d in range(6)])
    u = [[ops.nodeDisp(k + 1, d + 1) for d in range(6)] for k in range(len(case["nodes"]))]
    print(json.dumps({"u": u, "iters": iters, "tip_history": history}))


if __name__ == "__main__":
    main(sys.argv[1])

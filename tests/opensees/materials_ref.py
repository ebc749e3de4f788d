"""Reference stress-strain histories of OpenSees uniaxial materials (openseespy).

Drives each material through several cyclic strain histories with
`testUniaxialMaterial` / `setStrain` (which calls setTrialStrain and then
commitState: one commit per step) and prints one JSON document on stdout:

  {"openseespy": version, "cases": [{"name", "type", "params" (OpenSees names),
    "stress_scale", "tangent_scale", "histories": [{"name", "strain_bits", "stress_bits",
    "tangent_bits"}]}]}

Every float array is given as the IEEE-754 bit patterns (unsigned 64-bit
integers, `*_bits`) so that the Rust side reads exactly the same doubles
(a decimal round trip through a JSON parser need not be exact). Used by
tests/materials_opensees.rs, which drives fem2rbd's materials through the same
strains with the same commit pattern and compares.
"""
import json
import math
import os
import struct
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
try:
    from ops_import import ops  # noqa: E402
except Exception as exc:  # pragma: no cover - reported to the Rust test
    sys.stderr.write(
        "materials_ref.py: cannot import openseespy (%s); install it with "
        "`pip install openseespy==3.7.1` (scripts/setup.sh does)\n" % exc)
    sys.exit(3)

# frame3's materials (../data/frame3-standin/reference-frame3.json) plus the
# other laws and option branches.
FT = 1565327.4417833479
ETS = 782663720.8916739
STEEL = {"Fy": 457.7e6, "E0": 2.0e11, "b": 0.01}
CASES = [
    ("cover_F1", "Concrete02",
     [("fpc", -22.5e6), ("epsc0", -0.0018), ("fpcu", -4.5e6), ("epscu", -0.004),
      ("lambda", 0.1), ("ft", FT), ("Ets", ETS)]),
    ("core_F1", "Concrete02",
     [("fpc", -24750000.000000004), ("epsc0", -0.0019800000000000004),
      ("fpcu", -4950000.000000001), ("epscu", -0.012),
      ("lambda", 0.1), ("ft", FT), ("Ets", ETS)]),
    ("concrete02_defaults", "Concrete02",
     [("fpc", -30e6), ("epsc0", -0.002), ("fpcu", -6e6), ("epscu", -0.006)]),
    ("cover_concrete01", "Concrete01",
     [("fpc", -22.5e6), ("epsc0", -0.0018), ("fpcu", -4.5e6), ("epscu", -0.004)]),
    ("core_concrete01", "Concrete01",
     [("fpc", -24.75e6), ("epsc0", -0.00198), ("fpcu", -4.95e6), ("epscu", -0.012)]),
    ("rebar_steel02", "Steel02",
     [("Fy", 457.7e6), ("E0", 2e11), ("b", 0.01), ("R0", 18.0), ("cR1", 0.925),
      ("cR2", 0.15)]),
    ("steel02_defaults", "Steel02", [("Fy", 457.7e6), ("E0", 2e11), ("b", 0.01)]),
    ("steel02_isotropic", "Steel02",
     [("Fy", 457.7e6), ("E0", 2e11), ("b", 0.01), ("R0", 18.0), ("cR1", 0.925),
      ("cR2", 0.15), ("a1", 0.04), ("a2", 1.0), ("a3", 0.04), ("a4", 1.0)]),
    ("steel02_sigInit", "Steel02",
     [("Fy", 457.7e6), ("E0", 2e11), ("b", 0.01), ("R0", 18.0), ("cR1", 0.925),
      ("cR2", 0.15), ("a1", 0.0), ("a2", 1.0), ("a3", 0.0), ("a4", 1.0),
      ("sigInit", 120e6)]),
    ("rebar_steel01", "Steel01", [("Fy", 457.7e6), ("E0", 2e11), ("b", 0.01)]),
    ("steel01_isotropic", "Steel01",
     [("Fy", 457.7e6), ("E0", 2e11), ("b", 0.01), ("a1", 0.04), ("a2", 3.0),
      ("a3", 0.04), ("a4", 3.0)]),
    ("elastic", "Elastic", [("E", 2e11)]),
    ("elastic_eneg", "Elastic", [("E", 2e11), ("eta", 0.0), ("Eneg", 1e11)]),
]

# Waypoints in units of the material's reference strain (|epsc0| for concrete,
# Fy/E0 for steel, 1e-3 for elastic); positive = tension.
HISTORIES = [
    ("growing_cycles",
     [0, 1, -1, 2, -2, 4, -4, 8, -8, 12, -12, 0]),
    ("partial_unload_reload",
     [0, -1.5, -0.8, -2, -1.2, -3, 0.5, -2.5, -4, -3.5, -6, 1, -1, -7.5, -5,
      -9, 2, -3, 3, -10]),
    ("tension_first",
     [0, 0.01, 0.02, -0.01, 0.03, 0.5, 0.2, 1.5, 0.4, 3, -0.5, 2, -2, 6, -6, 10]),
    ("small_reversals",
     [0, 0.3, 0.2, 0.6, 0.5, 0.9, 0.8, 1.3, 1.1, 2, 1.8, 3, 2.9, -0.3, -0.2,
      -0.6, -0.5, -1.0, -0.9, -1.5, -1.3, -2.2, -2.0, -3.2, -3.1, 0.5, 0.4, 2.5]),
    ("past_crushing",
     [0, -1, -2.5, -1.8, -3.5, 0.3, -5, -4.8, -8, -7.9, 1.2, -11, -10.5, -14,
      -13, 0.8, -16]),
]
STEPS_PER_UNIT = 25


def ref_strain(mtype, p):
    if mtype.startswith("Concrete"):
        return abs(p["epsc0"])
    if mtype.startswith("Steel"):
        return p["Fy"] / p["E0"]
    return 1e-3


def discretise(points, ref):
    strains = [0.0]
    for a, b in zip(points[:-1], points[1:]):
        n = max(1, int(math.ceil(abs(b - a) * STEPS_PER_UNIT)))
        for k in range(1, n + 1):
            strains.append(ref * (a + (b - a) * k / n))
    return strains


def random_walk(ref, n=600, seed=12345):
    """Deterministic random walk (LCG) with frequent reversals of random size."""
    state = seed
    eps = 0.0
    out = [0.0]
    for _ in range(n):
        state = (1103515245 * state + 12345) % (2 ** 31)
        u = state / float(2 ** 31) - 0.5
        eps += ref * 0.9 * u - 0.002 * eps  # mild pull back towards zero
        out.append(eps)
    return out


def bits(xs):
    return [struct.unpack("<Q", struct.pack("<d", x))[0] for x in xs]


def run(mtype, params, strains):
    ops.wipe()
    ops.uniaxialMaterial(mtype, 1, *[v for _, v in params])
    ops.testUniaxialMaterial(1)
    stress, tangent = [], []
    for e in strains:
        ops.setStrain(e)
        stress.append(ops.getStress())
        tangent.append(ops.getTangent())
    return stress, tangent


def main():
    cases = []
    for name, mtype, plist in CASES:
        p = dict(plist)
        ref = ref_strain(mtype, p)
        if mtype.startswith("Concrete"):
            s_scale, t_scale = abs(p["fpc"]), 2 * abs(p["fpc"] / p["epsc0"])
        elif mtype.startswith("Steel"):
            s_scale, t_scale = p["Fy"], p["E0"]
        else:
            s_scale, t_scale = p["E"] * ref, p["E"]
        hists = [(h, discretise(pts, ref)) for h, pts in HISTORIES]
        hists.append(("random_walk", random_walk(ref)))
        out = []
        for hname, strains in hists:
            stress, tangent = run(mtype, plist, strains)
            out.append({"name": hname, "strain_bits": bits(strains),
                        "stress_bits": bits(stress), "tangent_bits": bits(tangent)})
        cases.append({"name": name, "type": mtype, "params": p,
                      "stress_scale": s_scale, "tangent_scale": t_scale,
                      "histories": out})
    ops.wipe()
    try:
        from importlib.metadata import version
        ver = version("openseespy")
    except Exception:
        ver = "unknown"
    json.dump({"openseespy": ver, "cases": cases}, sys.stdout)
    sys.stdout.write("\n")


if __name__ == "__main__":
    main()

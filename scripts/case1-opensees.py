#!/usr/bin/env python3
"""OpenSees reference numbers of the calibrated Case 1 frame (data/frame3/model.toml).

Runs openseespy on the scripts written by `fem2rbd export opensees` (the same model,
masses, damping, gravity and Newmark/Newton sequence with the reference fallbacks) and
writes data/frame3/opensees-case1.json:

* `modes`: the first 9 periods of the initial stiffness with effective-mass shares
  (X, Y, Z, RZ); `periods`: T(X), T(Y), T(torsion), picked by the largest share.
* `load_cases`: LC1, LC2, LC3 (whole records) and LC5 (to the collapse criterion), El
  Centro RSN6 X <- ELC180, Y <- ELC270, Z <- ELC-UP scaled to the paper's PGAs, time
  compressed by TIME_SCALE (t' = 0.5 t, the 1/4-scale similitude), dt = 0.005 s. Per case:
  peak |ux|, |uy| of the roof-centre node 312 (m, relative to the table) and their times,
  the peak roof drift (corner node 301, SRSS of X and Y, / 3 m), the first times the roof
  drift passes 5 % and 10 %, Tc = first step with a free node at uz < -0.25 m (the
  paper's criterion at 1/4 scale), the divergence time if any, fallback steps, wall time.
* `lc1_window`: node 312 ux, uy (m) at every step of the first LC1_WINDOW s of LC1, for
  the CI test crates/fem2rbd-fe/tests/it/fe/verify/case1.rs.
* `pushover`: +X after gravity, lateral load proportional to m*z at every massed free
  node, displacement control of node 312 in 1 mm steps (with the reference fallbacks) to
  5 % roof drift: base shear over weight V/W and roof drift, peak V/W.

Usage: python3 scripts/case1-opensees.py [--bin target/release/fem2rbd]
                                         [--out data/frame3/opensees-case1.json]
                                         [--jobs 2]
Takes about 15 minutes on 2 cores (each whole record is 5,345 steps).
"""
import argparse
import concurrent.futures
import csv
import importlib.util
import json
import math
import os
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MODEL = os.path.join(ROOT, "data", "frame3", "model.toml")
GM = os.path.join(ROOT, "data", "ground-motions", "RSN6_IMPVALL.I_I-")
TIME_SCALE = 0.5
DT = 0.005
LC1_WINDOW = 3.0
ROOF_CENTRE, ROOF_CORNER, ROOF_HEIGHT = 312, 301, 3.0
LOAD_CASES = {
    "LC1": (0.10, 0.08, 0.06),
    "LC2": (0.36, 0.32, 0.28),
    "LC3": (0.84, 0.55, 0.54),
    "LC5": (0.93, 1.19, 0.57),
}


def export(binary, out, pga=None, duration=None):
    """Writes the openseespy script of the model (with a load case if pga is given)."""
    cmd = [binary, "export", "opensees", MODEL, "-o", out, "--time-scale", str(TIME_SCALE),
           "--dt", str(DT), "--quiet"]
    if pga is not None:
        for d, rec, p in zip("XYZ", ("ELC180", "ELC270", "ELC-UP"), pga):
            cmd += ["--gm", f"{d}={GM}{rec}.AT2,{p}"]
    if duration is not None:
        cmd += ["--duration", str(duration)]
    subprocess.run(cmd, check=True)


def last_json(stdout):
    return json.loads(stdout.strip().splitlines()[-1])


def eigen(script):
    r = subprocess.run([sys.executable, script, "eigen", "9"], check=True,
                       capture_output=True, text=True)
    modes = last_json(r.stdout)["modes"]
    pick = {k: max(modes, key=lambda m: m[k])["T"] for k in ("X", "Y", "RZ")}
    return modes, {"x": pick["X"], "y": pick["Y"], "torsion": pick["RZ"]}


def time_history(script, csv_path):
    t0 = time.time()
    r = subprocess.run([sys.executable, script, "th", csv_path], check=True,
                       capture_output=True, text=True)
    summary = last_json(r.stdout)
    summary["wall_s"] = round(time.time() - t0, 1)
    return summary


def read_columns(csv_path):
    with open(csv_path) as fh:
        rows = list(csv.reader(fh))
    head = rows[0]
    cols = {h: [float(r[i]) for r in rows[1:]] for i, h in enumerate(head)}
    return cols


def measures(cols):
    t = cols["t"]
    out = {}
    for k in ("ux", "uy"):
        y = cols[f"{k}_{ROOF_CENTRE}"]
        i = max(range(len(y)), key=lambda j: abs(y[j]))
        out[f"peak_{k}_{ROOF_CENTRE}_m"] = abs(y[i])
        out[f"t_peak_{k}_s"] = t[i]
    drift = [math.hypot(a, b) / ROOF_HEIGHT
             for a, b in zip(cols[f"ux_{ROOF_CORNER}"], cols[f"uy_{ROOF_CORNER}"])]
    out["peak_roof_drift"] = max(drift)
    for name, lim in (("t_drift_5pct_s", 0.05), ("t_drift_10pct_s", 0.10)):
        out[name] = next((ti for ti, d in zip(t, drift) if d > lim), None)
    uz = [k for k in cols if k.startswith("uz_")]
    out["tc_s"] = next((t[i] for i in range(len(t))
                        if min(cols[k][i] for k in uz) < -0.25), None)
    out["min_uz_m"] = min(min(cols[k]) for k in uz)
    return out


def load_case(binary, tmp, name):
    script = os.path.join(tmp, f"{name}.py")
    export(binary, script, LOAD_CASES[name])
    csv_path = os.path.join(tmp, f"{name}.csv")
    s = time_history(script, csv_path)
    cols = read_columns(csv_path)
    res = {"pga_g": list(LOAD_CASES[name]), "end_s": s["t_end"], "steps": s["steps"],
           "fallback_steps": s["fallback_steps"], "t_diverge_s": s["t_diverge"],
           "wall_s": s["wall_s"]}
    res.update(measures(cols))
    os.remove(csv_path)
    return name, res


def lc1_window(binary, tmp):
    script = os.path.join(tmp, "lc1_window.py")
    export(binary, script, LOAD_CASES["LC1"], duration=LC1_WINDOW)
    csv_path = os.path.join(tmp, "lc1_window.csv")
    time_history(script, csv_path)
    cols = read_columns(csv_path)
    return {"duration_s": LC1_WINDOW, "node": ROOF_CENTRE, "t": cols["t"],
            "ux": cols[f"ux_{ROOF_CENTRE}"], "uy": cols[f"uy_{ROOF_CENTRE}"]}


def pushover(binary, tmp, max_drift=0.05, step=0.001):
    script = os.path.join(tmp, "pushover_model.py")
    export(binary, script)
    spec = importlib.util.spec_from_file_location("case1_model", script)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    ops = mod.ops
    mod.build()
    if mod.gravity() != 0:
        raise SystemExit("pushover: gravity failed")
    masses = {t: m for t, m in mod.MASSES.items()}
    sum_mz = sum(m[0] * mod.NODE_XYZ[t][2] for t, m in masses.items())
    weight = sum(m[0] for m in masses.values()) * mod.G
    ops.timeSeries("Linear", 2)
    ops.pattern("Plain", 2, 2)
    for t, m in masses.items():
        ops.load(t, m[0] * mod.NODE_XYZ[t][2], 0.0, 0.0, 0.0, 0.0, 0.0)
    ops.constraints("Plain")
    ops.numberer("RCM")
    ops.system("UmfPack")
    ops.test("NormDispIncr", 1e-8, 100)
    ops.algorithm("Newton")
    ops.integrator("DisplacementControl", ROOF_CENTRE, 1, step)
    ops.analysis("Static")
    curve = [(0.0, 0.0)]
    algos = [("ModifiedNewton", "-initial"), ("KrylovNewton",), ("NewtonLineSearch", 0.8)]
    while ops.nodeDisp(ROOF_CENTRE, 1) / ROOF_HEIGHT < max_drift:
        ok = ops.analyze(1)
        for alg in algos:
            if ok == 0:
                break
            ops.algorithm(*alg)
            ops.test("NormDispIncr", 1e-8, 200)
            ok = ops.analyze(1)
            ops.algorithm("Newton")
            ops.test("NormDispIncr", 1e-8, 100)
        if ok != 0:
            break
        lam = ops.getLoadFactor(2)
        curve.append((ops.nodeDisp(ROOF_CENTRE, 1) / ROOF_HEIGHT, lam * sum_mz / weight))
    peak = max(curve, key=lambda c: c[1])
    return {"weight_n": weight, "peak_v_over_w": peak[1], "roof_drift_at_peak": peak[0],
            "end_roof_drift": curve[-1][0],
            "curve": [[round(d, 6), round(v, 6)] for d, v in curve[::5]]}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bin", default=os.path.join(ROOT, "target", "release", "fem2rbd"))
    ap.add_argument("--out", default=os.path.join(ROOT, "data", "frame3", "opensees-case1.json"))
    ap.add_argument("--jobs", type=int, default=2)
    a = ap.parse_args()
    import importlib.metadata
    version = importlib.metadata.version("openseespy")
    with tempfile.TemporaryDirectory() as tmp:
        base = os.path.join(tmp, "model.py")
        export(a.bin, base)
        modes, periods = eigen(base)
        print("periods", periods, flush=True)
        result = {
            "description": "OpenSees (openseespy) runs of data/frame3/model.toml exported by "
                           "`fem2rbd export opensees`; made by scripts/case1-opensees.py",
            "openseespy": version,
            "model": "data/frame3/model.toml",
            "time_scale": TIME_SCALE,
            "dt_s": DT,
            "collapse_uz_m": 0.25,
            "modes": modes,
            "periods": periods,
        }
        with concurrent.futures.ThreadPoolExecutor(a.jobs) as ex:
            futs = [ex.submit(load_case, a.bin, tmp, n) for n in ("LC5", "LC3", "LC2", "LC1")]
            win = ex.submit(lc1_window, a.bin, tmp)
            lcs = {}
            for f in futs:
                name, res = f.result()
                print(name, {k: v for k, v in res.items()}, flush=True)
                lcs[name] = res
            result["load_cases"] = {k: lcs[k] for k in sorted(lcs)}
            result["lc1_window"] = win.result()
        result["pushover"] = pushover(a.bin, tmp)
        print("pushover peak V/W %.4f at %.2f %% roof drift"
              % (result["pushover"]["peak_v_over_w"],
                 100 * result["pushover"]["roof_drift_at_peak"]), flush=True)
    tmp_out = a.out + ".tmp"
    with open(tmp_out, "w") as fh:
        json.dump(result, fh, indent=1)
        fh.write("\n")
    os.replace(tmp_out, a.out)
    print("wrote", a.out)


if __name__ == "__main__":
    main()

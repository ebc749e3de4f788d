#!/usr/bin/env python3
"""fem2rbd against OpenSees and the paper on the calibrated Case 1 frame.

Runs `fem2rbd modal` and `fem2rbd fe` (release binary) on data/frame3/model.toml for the
load cases of scripts/case1-opensees.py (same records, PGAs, time scale 0.5, dt), takes
the same measures (roof-centre node 312 peaks, roof drift of corner node 301, first time
a free node is below uz = -0.25 m), and prints a Markdown table next to the stored
OpenSees numbers (data/frame3/opensees-case1.json) and the paper's.

Usage: python3 scripts/case1-compare.py [--bin target/release/fem2rbd] [--variant model]
                                        [--time-scale 0.5] [--lc5-duration 6] [--jobs 2]
LC1-LC3 run their whole records (26.7 s at time scale 0.5); LC5 runs --lc5-duration s.
"""
import argparse
import concurrent.futures
import importlib.util
import json
import os
import subprocess
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
spec = importlib.util.spec_from_file_location("case1_os", os.path.join(HERE, "case1-opensees.py"))
c1 = importlib.util.module_from_spec(spec)
spec.loader.exec_module(c1)

PAPER = {"x": 0.316, "y": 0.316, "torsion": 0.178, "LC5_tc": 3.88}


def modal(binary, variant):
    r = subprocess.run([binary, "modal", c1.MODEL, "--modes", "9", "--variant", variant],
                       check=True, capture_output=True, text=True)
    out = {}
    for ln in r.stdout.splitlines()[1:]:
        f = ln.split()
        key = {"X": "x", "Y": "y", "torsion": "torsion"}.get(f[-1])
        if key and key not in out:
            out[key] = float(f[1])
    return out


def run(binary, tmp, name, variant, ts, duration):
    out = os.path.join(tmp, name)
    cmd = [binary, "fe", c1.MODEL, "--variant", variant, "--time-scale", str(ts),
           "--dt", str(c1.DT), "--out", out, "--quiet"]
    for d, rec, p in zip("XYZ", ("ELC180", "ELC270", "ELC-UP"), c1.LOAD_CASES[name]):
        cmd += ["--gm", f"{d}={c1.GM}{rec}.AT2,pga={p}"]
    if duration:
        cmd += ["--duration", str(duration)]
    subprocess.run(cmd, check=True)
    cols = c1.read_columns(os.path.join(out, "nodes.csv"))
    cols = {k: v[1:] for k, v in cols.items()}  # drop t = 0 (OpenSees rows start at dt)
    # stop where the exported OpenSees script stops: the first step with uz < -0.25 m
    uz = [k for k in cols if k.startswith("uz_")]
    stop = next((i for i in range(len(cols["t"])) if min(cols[k][i] for k in uz) < -0.25),
                None)
    if stop is not None:
        cols = {k: v[: stop + 1] for k, v in cols.items()}
    with open(os.path.join(out, "fe_summary.json")) as fh:
        s = json.load(fh)
    res = c1.measures(cols)
    res.update({"end_s": s["stop"]["time"], "stop": s["stop"]["reason"],
                "fallback_steps": s["fallback_steps"], "wall_s": round(s["wall_time_s"], 1)})
    return name, res


def fmt(v, scale=1.0, nd=1):
    return "-" if v is None else f"{v * scale:.{nd}f}"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bin", default=os.path.join(c1.ROOT, "target", "release", "fem2rbd"))
    ap.add_argument("--variant", default="model")
    ap.add_argument("--time-scale", type=float, default=c1.TIME_SCALE)
    ap.add_argument("--lc5-duration", type=float, default=6.0)
    ap.add_argument("--jobs", type=int, default=2)
    a = ap.parse_args()
    with open(os.path.join(c1.ROOT, "data", "frame3", "opensees-case1.json")) as fh:
        ref = json.load(fh)
    per = modal(a.bin, a.variant)
    with tempfile.TemporaryDirectory() as tmp:
        with concurrent.futures.ThreadPoolExecutor(a.jobs) as ex:
            futs = [ex.submit(run, a.bin, tmp, n, a.variant, a.time_scale,
                              a.lc5_duration if n == "LC5" else None)
                    for n in ("LC5", "LC3", "LC2", "LC1")]
            res = dict(f.result() for f in futs)
    print(f"variant {a.variant}, time scale {a.time_scale}")
    print("| quantity | fem2rbd | OpenSees | paper |")
    print("|---|---|---|---|")
    for k, label in (("x", "T1 (X)"), ("y", "T2 (Y)"), ("torsion", "T torsion")):
        print(f"| {label}, s | {per[k]:.4f} | {ref['periods'][k]:.4f} | {PAPER[k]} |")
    for n in ("LC1", "LC2", "LC3", "LC5"):
        o = ref["load_cases"][n]
        f = res[n]
        print(f"| {n} peak roof X (node 312), mm | {fmt(f['peak_ux_312_m'], 1e3)} at "
              f"{f['t_peak_ux_s']:.2f} s | {fmt(o['peak_ux_312_m'], 1e3)} at "
              f"{o['t_peak_ux_s']:.2f} s | {'< ~60' if n != 'LC5' else ''} |")
        print(f"| {n} peak roof Y, mm | {fmt(f['peak_uy_312_m'], 1e3)} | "
              f"{fmt(o['peak_uy_312_m'], 1e3)} | |")
        print(f"| {n} first 5 % / 10 % roof drift, s | {fmt(f['t_drift_5pct_s'], nd=3)} / "
              f"{fmt(f['t_drift_10pct_s'], nd=3)} | {fmt(o['t_drift_5pct_s'], nd=3)} / "
              f"{fmt(o['t_drift_10pct_s'], nd=3)} | |")
        print(f"| {n} Tc (uz < -0.25 m), s | {fmt(f['tc_s'], nd=3)} | {fmt(o['tc_s'], nd=3)} | "
              f"{PAPER['LC5_tc'] if n == 'LC5' else 'none'} |")
    print()
    for n in ("LC1", "LC2", "LC3", "LC5"):
        f = res[n]
        print(f"{n}: fem2rbd end {f['end_s']:.3f} s ({f['stop']}), fallback steps "
              f"{f['fallback_steps']}, wall {f['wall_s']} s; OpenSees end "
              f"{ref['load_cases'][n]['end_s']:.3f} s, fallback steps "
              f"{ref['load_cases'][n]['fallback_steps']}, wall {ref['load_cases'][n]['wall_s']} s")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""fem2rbd's FE time history of the library stand-in against OpenSees on the exported model.

The library stand-in (data/library/model.toml, docs/case2.md) under the scenario's ground
motion (data/library/elcentro-4g.toml: El Centro 1940 RSN6, ELC180 in X and ELC270 in Y,
each scaled to a PGA of 4.0789 g, record time scale 1, dt = 0.005 s, Rayleigh 5 % from
the model's [damping]), from t = 0 to DURATION (default 2.0 s; the paper's Tc is 1.76 s):

* `opensees`: `fem2rbd export opensees` with that motion and duration, then the exported
  script's `th` (gravity in 10 load steps, Newmark 1/2, 1/4, Newton with the reference
  fallbacks: Newton, ModifiedNewton -initial, KrylovNewton, NewtonLineSearch 0.8 at
  h/1 ... h/16; it stops at the end, at divergence, or when a free node sinks 1 m). Its
  control series (below) go to data/library/opensees-th.csv, its summary (end, reason,
  steps, fallback steps, CPU time) to data/library/opensees-th.json.
* `fem2rbd`: `fem2rbd fe` on the same model and record over the same span (release
  binary); the same control series go to WORK/fem2rbd-th.csv, its summary to
  WORK/fem2rbd-th.json.
* `compare` (default `all` = the three in turn): a Markdown table on stdout and the plot
  docs/case2/opensees-th.png.

Control series per recorded step (m): ux, uy, uz of the roof centre 70607 (24, 23.7,
19.8 m), the roof corners 70001 (0, 0) and 71213 (48, 47.4), the story-3 floor centre
30607 (z = 9.0 m); the drift ratio of each story s (max over its columns of the SRSS of
the horizontal displacement difference of the column's top and bottom node, over the
story height, the definition of fem2rbd's collapse::Structure); the largest horizontal
displacement of a roof node; the lowest uz over the main nodes (nodes of beam-column
elements; the paper's Criterion 4 is that one drops 1 m) and which node.

Usage: python3 scripts/library-opensees.py [all|opensees|fem2rbd|compare]
           [--bin target/release/fem2rbd] [--duration 2.0] [--work out/library-opensees]
Needs openseespy and matplotlib. OpenSees takes tens of CPU minutes.
"""
import argparse
import csv
import json
import math
import os
import resource
import subprocess
import sys
import time
import tomllib

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MODEL = os.path.join(ROOT, "data", "library", "model.toml")
GM = os.path.join(ROOT, "data", "ground-motions", "RSN6_IMPVALL.I_I-")
COMPONENTS = (("X", "ELC180"), ("Y", "ELC270"))
PGA_G = 4.0789
DT = 0.005
DROP_M = 1.0  # the paper's Criterion 4 at scale 1
PAPER_TC = 1.76
PAPER_DISP_AT_TC = 0.97
CONTROL = {70607: "roof centre", 70001: "roof corner (0, 0)", 71213: "roof corner (48, 47.4)",
           30607: "story-3 floor centre"}
OS_CSV = os.path.join(ROOT, "data", "library", "opensees-th.csv")
OS_JSON = os.path.join(ROOT, "data", "library", "opensees-th.json")
PLOT = os.path.join(ROOT, "docs", "case2", "opensees-th.png")


def gm_args():
    return [f"{d}={GM}{rec}.AT2,pga={PGA_G}" for d, rec in COMPONENTS]


class Geometry:
    """Main nodes, columns per story and roof nodes of the model."""

    def __init__(self, path=MODEL):
        with open(path, "rb") as fh:
            m = tomllib.load(fh)
        xyz = {n["tag"]: (n["x"], n["y"], n["z"]) for n in m["node"]}
        bc = [e for e in m["element"] if e["type"] in ("beam_column", "elastic_beam_column")]
        self.main = sorted({t for e in bc for t in e["nodes"]})
        levels = sorted({round(xyz[t][2], 3) for t in self.main})
        self.heights = [b - a for a, b in zip(levels, levels[1:])]
        self.columns = [[] for _ in self.heights]  # per story: (bottom, top, height)
        for e in bc:
            a, b = e["nodes"]
            pa, pb = xyz[a], xyz[b]
            dz = pb[2] - pa[2]
            if abs(dz) < 1e-6 or math.hypot(pb[0] - pa[0], pb[1] - pa[1]) > abs(dz):
                continue  # not within 45 deg of vertical
            if dz < 0:
                a, b, pa, pb, dz = b, a, pb, pa, -dz
            s = levels.index(round(pa[2], 3))
            self.columns[s].append((a, b, dz))
        top = levels[-1]
        self.roof = sorted(t for t in self.main if abs(xyz[t][2] - top) < 1e-3)
        self.stories = len(self.heights)


def header():
    h = ["t"]
    for n in CONTROL:
        h += [f"ux_{n}", f"uy_{n}", f"uz_{n}"]
    return h + [f"drift_{s + 1}" for s in range(7)] + ["roof_max_h", "min_uz_main",
                                                        "min_uz_node"]


def reduce(full_csv, geo, out_csv, skip_t0=False):
    """Reads a per-node displacement CSV (`t,ux_N,uy_N,uz_N[,rx_N,...]`; a node without
    columns is fixed) and writes the control series of every row to out_csv."""
    with open(full_csv) as fh, open(out_csv + ".tmp", "w", newline="") as oh:
        r = csv.reader(fh)
        head = next(r)
        col = {h: i for i, h in enumerate(head)}

        def idx(n):
            return tuple(col.get(f"{c}_{n}") for c in ("ux", "uy", "uz"))

        need = {n: idx(n) for n in set(geo.main) | set(CONTROL)}
        w = csv.writer(oh)
        w.writerow(header())
        for row in r:
            if len(row) != len(head):
                break  # a partial last line (a run still writing)
            t = float(row[0])
            if skip_t0 and t == 0.0:
                continue
            u = {n: tuple(0.0 if i is None else float(row[i]) for i in ix)
                 for n, ix in need.items()}
            out = [t]
            for n in CONTROL:
                out += list(u[n])
            for cols in geo.columns:
                out.append(max(math.hypot(u[b][0] - u[a][0], u[b][1] - u[a][1]) / h
                               for a, b, h in cols))
            out.append(max(math.hypot(u[n][0], u[n][1]) for n in geo.roof))
            low = min(geo.main, key=lambda n: u[n][2])
            out += [u[low][2], low]
            w.writerow(["%.9g" % v for v in out])
    os.replace(out_csv + ".tmp", out_csv)


def read_series(path):
    with open(path) as fh:
        r = csv.reader(fh)
        head = next(r)
        rows = [[float(v) for v in row] for row in r]
    return {h: [row[i] for row in rows] for i, h in enumerate(head)}


def child_cpu_s():
    ru = resource.getrusage(resource.RUSAGE_CHILDREN)
    return ru.ru_utime + ru.ru_stime


def run_opensees(a):
    script = os.path.join(a.work, "library_th.py")
    full = os.path.join(a.work, "opensees_nodes.csv")
    cmd = [a.bin, "export", "opensees", MODEL, "-o", script, "--dt", str(DT),
           "--duration", str(a.duration), "--quiet"]
    for g in gm_args():
        cmd += ["--gm", g]
    subprocess.run(cmd, check=True)
    cpu0, t0 = child_cpu_s(), time.time()
    r = subprocess.run([sys.executable, script, "th", full], check=True, capture_output=True,
                       text=True)
    s = json.loads(r.stdout.strip().splitlines()[-1])
    s.update({"cpu_s": round(child_cpu_s() - cpu0, 1), "wall_s": round(time.time() - t0, 1)})
    finish_opensees(s, full)


def finish_opensees(s, full):
    import importlib.metadata
    geo = Geometry()
    reduce(full, geo, OS_CSV)
    if s.get("stopped_by_hand"):
        t = read_series(OS_CSV)["t"]
        s.update({"t_end": t[-1], "steps": len(t)})
    s.update({"description": "openseespy run of data/library/model.toml exported by "
                             "`fem2rbd export opensees` under El Centro ELC180 (X) + ELC270 (Y) "
                             f"at {PGA_G} g, dt {DT} s; made by scripts/library-opensees.py",
              "openseespy": importlib.metadata.version("openseespy")})
    with open(OS_JSON, "w") as fh:
        json.dump(s, fh, indent=1)
        fh.write("\n")
    print("opensees:", s, flush=True)


def run_fem2rbd(a):
    out = os.path.join(a.work, "fe")
    cmd = [a.bin, "fe", MODEL, "--dt", str(DT), "--duration", str(a.duration), "--out", out,
           "--quiet"]
    for g in gm_args():
        cmd += ["--gm", g]
    cpu0, t0 = child_cpu_s(), time.time()
    r = subprocess.run(cmd, capture_output=True, text=True)
    cpu, wall = child_cpu_s() - cpu0, time.time() - t0
    summ = os.path.join(out, "fe_summary.json")
    if not os.path.exists(summ):
        raise SystemExit(f"fem2rbd fe failed ({r.returncode}): {r.stderr}")
    with open(summ) as fh:
        fs = json.load(fh)
    s = {"stop": fs["stop"], "t_end": fs["end_time_s"], "steps": fs["steps"],
         "fallback_steps": fs["fallback_steps"], "cpu_s": round(cpu, 1),
         "wall_s": round(wall, 1), "exit": r.returncode}
    reduce(os.path.join(out, "nodes.csv"), Geometry(), os.path.join(a.work, "fem2rbd-th.csv"),
           skip_t0=True)
    with open(os.path.join(a.work, "fem2rbd-th.json"), "w") as fh:
        json.dump(s, fh, indent=1)
        fh.write("\n")
    print("fem2rbd:", s, flush=True)


def first(t, ys, pred):
    return next((ti for ti, y in zip(t, ys) if pred(y)), None)


def at(series, key, tq):
    """Value of series[key] at the recorded time closest to tq (None beyond the end)."""
    t = series["t"]
    if not t or tq > t[-1] + 1e-9:
        return None
    i = min(range(len(t)), key=lambda k: abs(t[k] - tq))
    return series[key][i]


def fmt(v, scale=1.0, nd=3):
    return "–" if v is None else f"{v * scale:.{nd}f}"


def compare(a):
    f = read_series(os.path.join(a.work, "fem2rbd-th.csv"))
    o = read_series(OS_CSV)
    with open(os.path.join(a.work, "fem2rbd-th.json")) as fh:
        fs = json.load(fh)
    with open(OS_JSON) as fh:
        osum = json.load(fh)
    geo = Geometry()
    n = min(len(f["t"]), len(o["t"]))
    assert all(abs(f["t"][k] - o["t"][k]) < 1e-6 for k in range(n)), "time grids differ"
    t = o["t"][:n]
    tc = {k: first(s["t"], s["min_uz_main"], lambda v: v < -DROP_M) for k, s in
          (("f", f), ("o", o))}
    print(f"common span 0 – {t[-1]:.3f} s ({n} steps)\n")
    print("| quantity | fem2rbd | OpenSees |")
    print("|---|---|---|")

    def end(s):
        if "reason" in s.get("stop", {}):
            return f"{s['t_end']:.3f} s ({s['stop']['reason']})"
        why = ("stopped by hand (machine time), still converging" if s.get("stopped_by_hand")
               else "diverged" if s.get("t_diverge") is not None else
               "a free node 1 m down" if s.get("t_stop_uz") is not None else "completed")
        return f"{s['t_end']:.3f} s ({why})"

    print(f"| end of the analysis | {end(fs)} | {end(osum)} |")
    print(f"| steps (with fallbacks) | {fs['steps']} ({fs['fallback_steps']}) | "
          f"{osum['steps'] or n} ({fmt(osum['fallback_steps'], nd=0)}) |")
    print(f"| CPU time | {fs['cpu_s']:.0f} s | {fmt(osum['cpu_s'], nd=0)} s |")
    print(f"| Tc: a main node 1 m down (paper {PAPER_TC} s) | {fmt(tc['f'])} s | "
          f"{fmt(tc['o'])} s |")
    for c, name in (("ux", "X"), ("uy", "Y")):
        k = f"{c}_70607"
        pf = max(range(len(f["t"])), key=lambda i: abs(f[k][i]))
        po = max(range(len(o["t"])), key=lambda i: abs(o[k][i]))
        print(f"| peak roof-centre {name} (70607), m | {f[k][pf]:+.4f} at {f['t'][pf]:.3f} s | "
              f"{o[k][po]:+.4f} at {o['t'][po]:.3f} s |")
        d = [f[k][i] - o[k][i] for i in range(n)]
        peak = max(abs(v) for v in o[k][:n])
        dmax = max(abs(v) for v in d)
        rms = math.sqrt(sum(v * v for v in d) / n)
        print(f"| roof-centre {name}: max / RMS difference over the common span | "
              f"{dmax * 1e3:.1f} / {rms * 1e3:.1f} mm | {100 * dmax / peak:.1f} / "
              f"{100 * rms / peak:.1f} % of OpenSees's peak |")
        for lim in (1e-4, 1e-3, 1e-2, 0.1):
            tl = first(t, d, lambda v: abs(v) > lim)
            print(f"| roof-centre {name}: first |difference| > {lim * 1e3:g} mm | "
                  f"{fmt(tl)} s | |")
    for tq in (1.0, 1.5, PAPER_TC) + tuple(v for v in (tc["f"], tc["o"]) if v):
        fd = [at(f, f"drift_{s + 1}", tq) for s in range(geo.stories)]
        od = [at(o, f"drift_{s + 1}", tq) for s in range(geo.stories)]
        show = lambda ds: " / ".join(fmt(v, 100, 2) for v in ds)
        print(f"| story drifts 1–7 at {tq:.3f} s, % | {show(fd)} | {show(od)} |")
        print(f"| largest roof displacement at {tq:.3f} s (paper {PAPER_DISP_AT_TC} m at Tc), m | "
              f"{fmt(at(f, 'roof_max_h', tq))} | {fmt(at(o, 'roof_max_h', tq))} |")
        print(f"| lowest main-node uz at {tq:.3f} s, m | {fmt(at(f, 'min_uz_main', tq))} | "
              f"{fmt(at(o, 'min_uz_main', tq))} |")
    plot(f, o, tc, geo)


def plot(f, o, tc, geo):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(2, 2, figsize=(11, 7), sharex=True)
    styles = (("fem2rbd", f, dict(color="tab:blue", lw=1.4)),
              ("OpenSees", o, dict(color="tab:red", lw=1.2, ls="--")))
    panels = ((ax[0, 0], "ux_70607", "roof centre ux (m)"),
              (ax[0, 1], "uy_70607", "roof centre uy (m)"),
              (ax[1, 1], "min_uz_main", "lowest main-node uz (m)"))
    for a, key, lab in panels:
        for name, s, st in styles:
            a.plot(s["t"], s[key], label=name, **st)
        a.set_ylabel(lab)
    worst = max(range(geo.stories), key=lambda s: max(o[f"drift_{s + 1}"] + f[f"drift_{s + 1}"]))
    for s in sorted({2, worst}):
        for name, ser, st in styles:
            ax[1, 0].plot(ser["t"], [100 * v for v in ser[f"drift_{s + 1}"]],
                          label=f"{name}, story {s + 1}",
                          **dict(st, alpha=1.0 if s == 2 else 0.5))
    ax[1, 0].set_ylabel("story drift ratio (%)")
    ax[1, 1].axhline(-DROP_M, color="grey", lw=0.8)
    for a in ax.flat:
        a.axvline(PAPER_TC, color="black", lw=0.8, ls=":")
        for k, (name, _, st) in zip(("f", "o"), styles):
            if tc[k]:
                a.axvline(tc[k], color=st["color"], lw=0.8, ls="-.")
        a.grid(alpha=0.3)
        a.legend(fontsize=8)
    for a in ax[1]:
        a.set_xlabel("t (s)")
    fig.suptitle("Library stand-in, El Centro X+Y at 4.08 g: fem2rbd FE vs OpenSees on the "
                 f"exported model (dotted: paper's Tc {PAPER_TC} s)", fontsize=10)
    fig.tight_layout()
    fig.savefig(PLOT, dpi=110)
    print("wrote", PLOT)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("stage", nargs="?", default="all",
                    choices=("all", "opensees", "fem2rbd", "compare", "reduce-opensees"))
    ap.add_argument("--bin", default=os.path.join(ROOT, "target", "release", "fem2rbd"))
    ap.add_argument("--duration", type=float, default=2.0)
    ap.add_argument("--work", default=os.path.join(ROOT, "out", "library-opensees"))
    ap.add_argument("--summary", help="reduce-opensees: a file ending with the script's JSON line")
    ap.add_argument("--cpu-s", type=float, help="reduce-opensees: the run's CPU time (s)")
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    if a.stage in ("all", "opensees"):
        run_opensees(a)
    if a.stage == "reduce-opensees":
        # An OpenSees run made by hand (`python3 WORK/library_th.py th WORK/opensees_nodes.csv`,
        # e.g. in the background): with --summary its JSON line; without, a run stopped
        # before its end (the rows written so far, `WORK/opensees_nodes.csv.tmp`).
        full = os.path.join(a.work, "opensees_nodes.csv")
        if a.summary:
            with open(a.summary) as fh:
                s = json.loads(fh.read().strip().splitlines()[-1])
        else:
            full += ".tmp"
            with open(full) as fh:
                rows = [ln for ln in fh.read().splitlines()[1:] if ln.count(",") > 0]
            # the last line may be partial: drop it unless complete
            t_end = float(rows[-2].split(",")[0]) if len(rows) > 1 else 0.0
            s = {"t_end": t_end, "steps": None, "fallback_steps": None, "t_stop_uz": None,
                 "t_diverge": None, "stopped_by_hand": True}
        s["cpu_s"] = a.cpu_s
        finish_opensees(s, full)
    if a.stage in ("all", "fem2rbd"):
        run_fem2rbd(a)
    if a.stage in ("all", "compare"):
        compare(a)


if __name__ == "__main__":
    main()

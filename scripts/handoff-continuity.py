#!/usr/bin/env python3
"""Hand-off continuity benchmark (docs/handoff.md).

Runs `fem2rbd` (release) on a model under LC5 and compares the Bullet building with the FE
alone on the same time axis:

  (a) roof drift and maximum drop in the 0.5 s after each hand-off, hybrid vs FE alone;
  (b) the time the hybrid run reaches the 0.25 m-at-full-scale drop (1 m x scale) against
      the FE's own Tc;
  (c) the undamaged Bullet building under gravity alone (a ground record of zeros, 3 s):
      largest sag and roof drift, against the FE under the same zero record;
  (d) optional (--ruins): final ruin measures of each hand-off at 200/400/800 substeps/s,
      against the FE alone at its first contact (summary.json `fe_first_contact`: the
      last keyframe a model without contact describes, i.e. the FE's own ruin mode).

  (e) optional (--pushover): static lateral strength. A slow ground-acceleration ramp
      in X (0.03 g/s; then a pulse that brings the ground back to rest, so the ruin
      stage's zero-end baseline leaves the ramp as it is) is an inertial pushover under
      load control: the FE alone (the model's formulation and force-based), and the
      Bullet building (rigid-only, undamaged) with each connection model and with
      100 and 400 iterations; per run the roof-to-base drift at 0.03 and 0.15 g and the
      ground acceleration at which it reaches 2 % (the frame has run away past its peak).

Each of (a)-(c) is run with both connection models, BCB's Formula Assistant ("formula")
and the FE-derived one ("fe"). Usage:

  python3 scripts/handoff-continuity.py [--model data/frame3/model.toml]
      [--time-scale 0.5] [--out out/handoff] [--ruins] [--reuse] [--connections fe]
      [--physics 'linear_correction = 1; bending_correction = 1']

--reuse keeps every run folder that already has a summary.json (rerun by deleting it);
--connections limits (a)-(c) to the listed connection models (default: formula,fe).
(d) says whether the ruin mode is the same everywhere: each slab overlap's range over all
hand-offs and substeps ≤ 0.2 (the benchmark's target). --ruin-ensemble N [--ruin-sps 200,400]
runs (d) as distributions instead of single runs: an ensemble of N members (seed 1,
member 0 the hand-off itself, the others with its velocities perturbed by up to 1e-4 m/s)
per hand-off and substep, because one ensemble's own members already spread their slab
overlaps by more than 0.2 (docs/ruin-numerics.md, "Convergence"); it prints each setting's
distribution and the range of the mean overlaps over all settings. THREADS sets the
ensembles' worker threads (default 2); with --reuse an ensemble with an ensemble.json is kept. FEM2RBD=path
overrides the binary.

Writes OUT/table.md (the tables of docs/handoff.md) and keeps every run folder, so
`fem2rbd plot OUT/<run>` draws the tool's own plots of any of them. Needs
`cargo build --release` first (the script calls target/release/fem2rbd).
"""
import argparse
import csv
import json
import os
import statistics
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.environ.get("FEM2RBD", os.path.join(ROOT, "target", "release", "fem2rbd"))
REUSE = False
EXTRA = ""  # extra [physics] lines of every Bullet run (--physics)
GM = os.path.join(ROOT, "data", "ground-motions")
LC5 = [("RSN6_IMPVALL.I_I-ELC180.AT2", "X", 0.93),
       ("RSN6_IMPVALL.I_I-ELC270.AT2", "Y", 1.19),
       ("RSN6_IMPVALL.I_I-ELC-UP.AT2", "Z", 0.57)]
HANDOFFS = [("drift_1_50", 'criterion = "drift_1_50"'),
            ("drift_3pct", 'criterion = "drift"\nratio = 0.03'),
            ("drift_4pct", 'criterion = "drift_4pct"'),
            ("vertical_drop", 'criterion = "vertical_drop"')]


def scenario(path, model, out, mode, ts, collapse, physics, zeros=None, fe_extra=""):
    lines = [f'model = "{model}"', f'mode = "{mode}"', f'output = "{out}"', ""]
    if zeros:
        lines += ["[[ground_motion]]", f'file = "{zeros}"', 'direction = "X"', ""]
    else:
        for f, d, g in LC5:
            lines += ["[[ground_motion]]", f'file = "{os.path.join(GM, f)}"',
                      f'direction = "{d}"', f"pga_g = {g}", f"time_scale = {ts}", ""]
    lines += ["[fe]", "dt = 0.005", fe_extra, "", "[collapse]", collapse, "",
              "[physics]", physics, EXTRA if mode != "fe" else "", ""]
    with open(path, "w") as fh:
        fh.write("\n".join(lines))


def run(path, extra=(), marker="summary.json"):
    """Runs scenario `path` (fem2rbd `run` with `extra` arguments) unless --reuse and its
    folder already has `marker`."""
    if REUSE and os.path.isfile(os.path.join(path[:-len(".toml")], marker)):
        return
    r = subprocess.run([BIN, "--quiet", "run", path, *extra], capture_output=True, text=True)
    if r.returncode != 0:
        sys.stderr.write(r.stderr)
        raise SystemExit(f"fem2rbd failed on {path}")


def history(folder):
    with open(os.path.join(folder, "history.csv")) as fh:
        return [{k: (float(v) if k not in ("stage",) and v != "" else v)
                 for k, v in row.items()} for row in csv.DictReader(fh)]


def summary(folder):
    with open(os.path.join(folder, "summary.json")) as fh:
        return json.load(fh)


def floor1_down(folder):
    """summary.json's `floors_down`: the floors when floor 1 has first come 70 % of its
    height down (the last moments before a floor lands; the same measure for the FE alone
    and the ruin stage). (t, drops per floor, plan offset of each floor against the one
    below, stories above whole) or None."""
    fd = summary(folder).get("floors_down")
    if not fd:
        return None
    return fd["t_s"], fd["floor_drops_m"], fd["story_offsets_m"], fd["stories_above_whole"]


def fmt_down(fd):
    if fd is None:
        return "never | – | –"
    t, drops, rel, _ = fd
    return (f"{t:.2f} | {', '.join(f'{z:.2f}' for z in drops)} | "
            f"{', '.join(f'{r:.2f}' for r in rel)}")


def whole_above(fd):
    """Story 1 folds and the stories above come down whole (the FE's mode)."""
    return fd is not None and fd[3]


def ruin_cells(ru):
    """A summary's `ruins`: (slab overlaps, floor centroid z displacements, and the table
    cells of the floor offsets, floor drops and slab overlaps)."""
    floors = ru.get("floors", [])
    ov = [o["overlap_ratio"] for o in ru.get("slab_overlap", [])]
    dz = [f["centroid_displacement_m"][2] for f in floors]
    return (ov, dz,
            ", ".join(f"{f['horizontal_offset_m']:.2f}" for f in floors),
            ", ".join(f"{-z:.2f}" for z in dz),
            ", ".join(f"{o:.2f}" for o in ov))


def ruin_ensembles(p, out, model, ts, n, sps_list):
    """(d) as distributions (--ruin-ensemble): per hand-off and substep an ensemble of n."""
    p(f"### (d) as distributions: an ensemble of {n} members per hand-off and substep\n")
    p("| hand-off | steps/s | at rest | slab overlap 1–2: mean ± std (min–max) | 2–3 | "
      "floor 1 70 % down (members; t s) | FE's fold (stories above whole) | fastest m/s (bound met) |")
    p("|---|---|---|---|---|---|---|---|")
    means = []
    for name, crit in HANDOFFS:
        for sps in sps_list:
            d = os.path.join(out, f"ruin-ens-{name}-{sps}")
            scenario(d + ".toml", model, d, "hybrid", ts, crit,
                     f"steps_per_second = {sps}\nsettle_s = 5.0\nstop_at_rest = true")
            run(d + ".toml", ("--ensemble", str(n), "--seed", "1",
                              "--threads", os.environ.get("THREADS", "2")), "ensemble.json")
            members = sorted(os.path.join(d, m) for m in os.listdir(d) if m.startswith("member-"))
            ss = [summary(m) for m in members]
            ovs = [ruin_cells(s.get("ruins", {}))[0] for s in ss]
            k = min(len(o) for o in ovs)
            cells, mu = [], []
            for j in range(k):
                xs = [o[j] for o in ovs]
                m = statistics.mean(xs)
                mu.append(m)
                cells.append(f"{m:.2f} ± {statistics.stdev(xs):.2f} ({min(xs):.2f}–{max(xs):.2f})")
            means.append((name, sps, mu))
            downs = [floor1_down(m) for m in members]
            ts_down = [fd[0] for fd in downs if fd is not None]
            rest = sum(s.get("ruin_stage", {}).get("stop") == "at_rest" for s in ss)
            sp = [s.get("ruin_stage", {}).get("energy", {}).get("speed", {}) for s in ss]
            down = (f"{len(ts_down)} of {len(members)}; {min(ts_down):.2f}–{max(ts_down):.2f}"
                    if ts_down else f"0 of {len(members)}")
            p(f"| {name} | {sps} | {rest} of {len(members)} | {' | '.join(cells)} | {down} | "
              f"{sum(whole_above(fd) for fd in downs)} of {len(members)} | "
              f"{max(x.get('max_mps', float('nan')) for x in sp):.1f} "
              f"({sum(bool(x.get('ok')) for x in sp)} of {len(members)}) |")
    p("")
    k = min(len(m) for _, _, m in means)
    rng = [max(m[j] for _, _, m in means) - min(m[j] for _, _, m in means) for j in range(k)]
    verdict = "met" if all(r <= 0.2 for r in rng) else "not met"
    p("Range of the ensemble-mean slab overlaps over all hand-offs and substeps, per floor pair: "
      + ", ".join(f"{r:.2f}" for r in rng)
      + f" (the 0.2 criterion applied to the means: {verdict}).\n")


def at(rows, t):
    """The row at the first frame time >= t (FE and physics rows share the 25 fps axis)."""
    for r in rows:
        if r["t"] >= t - 1e-9:
            return r
    return rows[-1]


def window(rows, t0, t1):
    return [r for r in rows if t0 - 1e-9 <= r["t"] <= t1 + 1e-9]


def first_drop(rows, thr):
    for r in rows:
        if r["max_drop_m"] >= thr:
            return r["t"]
    return None


RAMP_RATE_G = 0.03  # g/s: halving it lowers every capacity by 0.01-0.03 g (docs/handoff.md)
RAMP_PEAK_G = 0.36


def ramp_record(path, rate_g=RAMP_RATE_G, peak_g=RAMP_PEAK_G, h=0.005, g=9.80665):
    """Writes a two-column record (m/s²): a(t) rises at rate_g·g per second to peak_g·g,
    then a linear pulse as long as the ramp brings the ground's velocity and displacement
    back to zero at the end (the ruin stage's zero-end baseline then changes nothing).
    Returns the ramp's duration, s."""
    t1 = peak_g / rate_g
    n = int(round(2 * t1 / h)) + 1
    after = [i * h > t1 + 1e-9 for i in range(n)]
    a = [0.0 if after[i] else rate_g * g * i * h for i in range(n)]
    b0 = [1.0 if after[i] else 0.0 for i in range(n)]
    b1 = [i * h - t1 if after[i] else 0.0 for i in range(n)]

    def end(x):  # the stage's average-acceleration integration: (v, d) at the end
        v = d = 0.0
        for i in range(1, n):
            s = x[i - 1] + x[i]
            d += h * v + 0.25 * h * h * s
            v += 0.5 * h * s
        return v, d
    (v0, d0), (v1, d1), (v2, d2) = end(a), end(b0), end(b1)
    det = v1 * d2 - v2 * d1
    c0, c1 = (-v0 * d2 + v2 * d0) / det, (-v1 * d0 + v0 * d1) / det
    with open(path, "w") as fh:
        for i in range(n):
            fh.write(f"{i * h:.3f} {a[i] + c0 * b0[i] + c1 * b1[i]:.9f}\n")
    return t1


def roof_to_base_drift(folder):
    """(t, drift) per frame: mass-weighted X displacement of the roof bodies (history.csv's
    roof: centres within 5 % of the height above the foundations' top below the highest
    centre) less that of the lowest bodies (the base pieces), over the height between
    them. From the base pieces, not the ground: bodies joined to the kinematic ground
    lead it by v_g·h, centimetres under a ramp (docs/handoff.md, "The static lateral strength")."""
    with open(os.path.join(folder, "bodies.csv")) as fh:
        rows = list(csv.DictReader(fh))
    b = {r["name"]: (float(r["cx"]), float(r["cz"]), float(r["mass_kg"]))
         for r in rows if r["passive"] != "1" and float(r["mass_kg"]) > 0}
    base = max((float(r["cz"]) + float(r["hz"]) for r in rows if r["passive"] == "1"), default=0.0)
    top = max(v[1] for v in b.values())
    low = min(v[1] for v in b.values())
    roof_z = top - 0.05 * (top - base)
    acc = {}
    with open(os.path.join(folder, "keyframes.csv")) as fh:
        for r in csv.DictReader(fh):
            if r["name"] not in b:
                continue
            cx, cz, m = b[r["name"]]
            s = acc.setdefault(float(r["t"]), [0.0, 0.0, 0.0, 0.0])
            dx = float(r["x"]) - cx
            if cz >= roof_z - 1e-12:
                s[0] += m * dx
                s[1] += m
            if cz <= low + 1e-6:
                s[2] += m * dx
                s[3] += m
    return [(t, (s[0] / s[1] - s[2] / s[3]) / (top - low)) for t, s in sorted(acc.items())]


def pushover_row(folder):
    """Drift (%) at 0.03 g and 0.15 g and the ground acceleration (g) at 2 % drift."""
    dr = roof_to_base_drift(folder)
    at = {round(t * RAMP_RATE_G, 4): d for t, d in dr}
    cap = next((t * RAMP_RATE_G for t, d in dr if abs(d) >= 0.02), None)
    return (abs(at.get(0.03, float("nan"))) * 100, abs(at.get(0.15, float("nan"))) * 100, cap)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--model", default=os.path.join(ROOT, "data", "frame3", "model.toml"))
    ap.add_argument("--time-scale", type=float, default=0.5)
    ap.add_argument("--scale", type=float, default=0.25, help="model scale (drop = 1 m x scale)")
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "handoff"))
    ap.add_argument("--t-end", type=float, default=6.0, help="end of the LC5 runs, s")
    ap.add_argument("--ruins", action="store_true", help="(d): full ruin runs at 200/400/800")
    ap.add_argument("--ruin-ensemble", type=int, default=0, metavar="N",
                    help="(d) as distributions: an ensemble of N members per hand-off and substep")
    ap.add_argument("--ruin-sps", default="200,400", help="substeps/s of --ruin-ensemble")
    ap.add_argument("--pushover", action="store_true", help="(e): static strength by a slow ramp")
    ap.add_argument("--reuse", action="store_true", help="keep run folders with a summary.json")
    ap.add_argument("--connections", default="formula,fe", help="connection models of (a)-(c)")
    ap.add_argument("--physics", default="",
                    help="extra [physics] keys for every Bullet run, ';'-separated, "
                         "e.g. 'linear_correction = 1; bending_correction = 1'")
    a = ap.parse_args()
    global EXTRA
    EXTRA = "\n".join(k.strip() for k in a.physics.split(";") if k.strip())
    global REUSE
    REUSE = a.reuse
    cms = [c for c in a.connections.split(",") if c]
    out = os.path.abspath(a.out)
    os.makedirs(out, exist_ok=True)
    model = os.path.abspath(a.model)
    thr = 1.0 * a.scale
    ts = a.time_scale

    # The FE alone (no stop at the criterion) on the same axis.
    fe = os.path.join(out, "fe")
    scenario(fe + ".toml", model, fe, "fe", ts, 'criterion = "vertical_drop"', "",
             fe_extra=f"duration = {a.t_end}")
    run(fe + ".toml")
    fe_rows = history(fe)
    # The FE's Tc: its collapse monitor (a main node drops 1 m x scale), as summary.json
    # reports it (history.csv's max_drop_m is of body centres, which drop less).
    fe_tc = summary(fe).get("tc_s")

    # (c) gravity alone: a record of zeros, 3 s.
    zeros = os.path.join(out, "zeros.txt")
    with open(zeros, "w") as fh:
        for i in range(601):
            fh.write(f"{i * 0.005:.3f} 0.0\n")
    grav = {}
    for cm in cms:
        d = os.path.join(out, f"gravity-{cm}")
        scenario(d + ".toml", model, d, "rigid", ts, 'criterion = "vertical_drop"',
                 f'time_limit_s = 3.0\nstop_at_rest = false\nconnections = "{cm}"', zeros=zeros)
        run(d + ".toml")
        grav[cm] = history(d)
    d = os.path.join(out, "gravity-fe-only")
    scenario(d + ".toml", model, d, "fe", ts, 'criterion = "vertical_drop"', "", zeros=zeros,
             fe_extra="duration = 3.0")
    run(d + ".toml")
    grav["FE alone"] = history(d)

    lines = []
    p = lines.append
    p(f"Model `{os.path.relpath(model, ROOT)}`, LC5 at time scale {ts}; drop threshold {thr} m; "
      f"FE alone reaches it at **{fe_tc} s**.\n")
    p("### (c) Gravity alone (ground record of zeros, 3 s)\n")
    p("| building | largest sag (mm) | at t (s) | largest roof drift (%) | sag at 3 s (mm) | drift at 3 s (%) | connections i/p/b at 3 s |")
    p("|---|---|---|---|---|---|---|")
    for name, rows in grav.items():
        m = max(rows, key=lambda r: r["max_drop_m"])
        dr = max(abs(r["roof_drift"]) for r in rows)
        last = rows[-1]
        cnt = (f"{int(last['intact'])}/{int(last['plastic'])}/{int(last['broken'])}"
               if last["intact"] != "" else "–")
        label = name if name == "FE alone" else f"Bullet, `{name}` connections"
        p(f"| {label} | {m['max_drop_m'] * 1000:.2f} | {m['t']:.2f} | {dr * 100:.4f} | "
          f"{last['max_drop_m'] * 1000:.2f} | {abs(last['roof_drift']) * 100:.4f} | {cnt} |")
    p("")

    p("### (a), (b) Hand-offs under LC5 against the FE alone\n")
    p("| hand-off | connections | Tc (s) | start i/p/b | roof drift +0.5 s hybrid / FE (%) | max drop +0.5 s hybrid / FE (m) | drop reached (s) | FE Tc (s) | half-way (s) | target (b) |")
    p("|---|---|---|---|---|---|---|---|---|---|")
    for name, crit in HANDOFFS:
        for cm in cms:
            d = os.path.join(out, f"{name}-{cm}")
            scenario(d + ".toml", model, d, "hybrid", ts, crit,
                     f'time_limit_s = {a.t_end}\nstop_at_rest = false\nconnections = "{cm}"')
            run(d + ".toml")
            s = summary(d)
            tc = s.get("tc_s")
            if tc is None:
                p(f"| {name} | {cm} | – ({s['tc_reason']}) | | | | | | | |")
                continue
            rows = history(d)
            ph = [r for r in rows if r["stage"] in ("ruin", "physics")]
            st = ph[0]
            w = window(rows, tc, tc + 0.5)
            wf = window(fe_rows, tc, tc + 0.5)
            dh = max(abs(r["roof_drift"]) for r in w) * 100
            df = max(abs(r["roof_drift"]) for r in wf) * 100 if wf else float("nan")
            mh = max(r["max_drop_m"] for r in w)
            mf = max(r["max_drop_m"] for r in wf) if wf else float("nan")
            tdrop = first_drop(ph, thr)
            half = tc + 0.5 * (fe_tc - tc) if fe_tc else None
            ok = "–" if half is None else ("met" if (tdrop is None or tdrop >= half) else "not met")
            p(f"| {name} | {cm} | {tc:.2f} | {int(st['intact'])}/{int(st['plastic'])}/{int(st['broken'])} | "
              f"{dh:.2f} / {df:.2f} | {mh:.3f} / {mf:.3f} | "
              f"{'none by %.1f' % a.t_end if tdrop is None else '%.2f' % tdrop} | {fe_tc} | "
              f"{'–' if half is None else '%.2f' % half} | {ok} |")
    p("")

    if a.ruins:
        p("### (d) Final ruins per hand-off and substep (FE-derived connections)\n")
        p("| hand-off | steps/s | stop, end (s) | floor offsets (m) | floor drops (m) | slab overlap 1–2, 2–3 | debris area (m²) | extent (m) | max speed (m/s) | unsettled |")
        p("|---|---|---|---|---|---|---|---|---|---|")
        overlaps, drops, downs = [], [], []
        fc = summary(fe).get("fe_first_contact")
        if fc:
            ru = fc["ruins"]
            fe_ov, fe_dz, fl, dz, ov = ruin_cells(ru)
            p(f"| FE alone, at its first contact ({fc['detail']}) | – | –, {fc['t_s']:.2f} | {fl} | {dz} | {ov} | "
              f"{ru['debris_footprint_area_m2']:.2f} | {ru['extent_beyond_footprint_m']['max']:.2f} | – | – |")
        else:
            fe_ov, fe_dz = None, None
        for name, crit in HANDOFFS:
            for sps in (200, 400, 800):
                d = os.path.join(out, f"ruin-{name}-{sps}")
                scenario(d + ".toml", model, d, "hybrid", ts, crit,
                         f"steps_per_second = {sps}\nsettle_s = 5.0\nstop_at_rest = true")
                run(d + ".toml")
                s = summary(d)
                ru = s.get("ruins", {})
                rs = s.get("ruin_stage", {})
                ov_v, dz_v, fl, dz, ov = ruin_cells(ru)
                overlaps.append(ov_v)
                drops.append(dz_v)
                downs.append((name, sps, floor1_down(d)))
                sp = rs.get("energy", {}).get("speed", {}).get("max_mps", float("nan"))
                p(f"| {name} | {sps} | {rs.get('stop', '-')}, {rs.get('end_s', float('nan')):.2f} | {fl} | {dz} | {ov} | "
                  f"{ru.get('debris_footprint_area_m2', float('nan')):.2f} | "
                  f"{ru.get('extent_beyond_footprint_m', {}).get('max', float('nan')):.2f} | {sp:.1f} | "
                  f"{len(rs.get('unsettled_bodies', []))} |")
        p("")
        if overlaps and all(len(o) == len(overlaps[0]) for o in overlaps):
            rng = [max(o[k] for o in overlaps) - min(o[k] for o in overlaps) for k in range(len(overlaps[0]))]
            verdict = "met" if all(r <= 0.2 for r in rng) else "not met"
            p("Slab-overlap spread (max − min over all hand-offs and substeps), per floor pair "
              "(1–2, 2–3, ...): " + ", ".join(f"{r:.2f}" for r in rng)
              + f" (target: every spread ≤ 0.2, i.e. all runs within 0.2 of each other: {verdict}).\n")
            if fe_ov is not None and len(fe_ov) == len(overlaps[0]):
                # The FE's own mode: every slab overlap within 0.2 of the FE's at its first
                # contact and every floor's drop within 0.3 m of the FE's (a standing frame,
                # or a story above that also came down, is another mode).
                near = sum(all(abs(o[k] - fe_ov[k]) <= 0.2 for k in range(len(fe_ov)))
                           and len(z) == len(fe_dz)
                           and all(abs(z[k] - fe_dz[k]) <= 0.3 for k in range(len(fe_dz)))
                           for o, z in zip(overlaps, drops))
                p(f"Runs in the FE's own mode at its first contact (every slab overlap within 0.2 of "
                  f"{', '.join(f'{o:.2f}' for o in fe_ov)} and every floor drop within 0.3 m of "
                  f"{', '.join(f'{-z:.2f}' for z in fe_dz)}): {near} of {len(overlaps)}.\n")

    if a.ruins:
        p("### (d) Before the ground: the floors when floor 1 is 70 % of its height down\n")
        p("The last moments a model without contact describes: the FE's own collapse against "
          "the ruin stage's, on the same measure (summary.json `floors_down`: drops of each floor, plan offset "
          "of each floor against the one below).\n")
        p("| run | steps/s | t (s) | floor drops (m) | story offsets 2–1, 3–2 (m) | stories above whole |")
        p("|---|---|---|---|---|---|")
        fd = floor1_down(fe)
        p(f"| FE alone | – | {fmt_down(fd)} | {'yes' if whole_above(fd) else 'no'} |")
        for name, sps, fd in downs:
            p(f"| {name} | {sps} | {fmt_down(fd)} | {'yes' if whole_above(fd) else 'no'} |")
        n_whole = sum(whole_above(fd) for _, _, fd in downs)
        p(f"\nRuns whose first story folds with the stories above whole (every floor's drop within "
          f"0.15 × floor 1's height of floor 1's, every story offset ≤ 0.25 × that height; "
          f"summary.json `floors_down`), as the FE's: {n_whole} of {len(downs)}.\n")

    if a.ruin_ensemble:
        ruin_ensembles(p, out, model, ts, a.ruin_ensemble, [int(x) for x in a.ruin_sps.split(",")])

    if a.pushover:
        p("### (e) Static lateral strength: a slow ground ramp (%.2f g/s)\n" % RAMP_RATE_G)
        ramp = os.path.join(out, "ramp.txt")
        t1 = ramp_record(ramp)
        runs = [("FE alone, the model's formulation", "fe", "model", None),
                ("FE alone, force-based", "fe", "force", None)]
        for cm in cms:
            for it in (100, 400):
                runs.append((f"Bullet, `{cm}` connections, {it} iterations", "rigid", None,
                             f'connections = "{cm}"\nsolver_iterations = {it}'))
        p("| building | roof-to-base drift at 0.03 g (%) | at 0.15 g (%) | ground acceleration at 2 % drift (g) |")
        p("|---|---|---|---|")
        for label, mode, variant, phys in runs:
            tag = f"push-{variant}" if mode == "fe" else "push-" + phys.split('"')[1] + "-" + phys.split("= ")[-1]
            d = os.path.join(out, tag)
            lines_ = [f'model = "{model}"', f'mode = "{mode}"', f'output = "{d}"', "",
                      "[[ground_motion]]", f'file = "{ramp}"', 'direction = "X"', "",
                      "[collapse]", 'criterion = "vertical_drop"', ""]
            if mode == "fe":
                lines_ += ["[fe]", "dt = 0.005", f"duration = {t1}", f'variant = "{variant}"']
            else:
                # EXTRA first: the run's own connections and iterations override it.
                extra = "\n".join(k for k in EXTRA.split("\n")
                                   if not k.startswith(("connections", "solver_iterations")))
                lines_ += ["[physics]", f"time_limit_s = {t1}", "stop_at_rest = false", extra, phys]
            with open(d + ".toml", "w") as fh:
                fh.write("\n".join(lines_) + "\n")
            run(d + ".toml")
            d3, d15, cap = pushover_row(d)
            p(f"| {label} | {d3:.3f} | {d15:.3f} | {'none by %.2f' % RAMP_PEAK_G if cap is None else '%.3f' % cap} |")
        p("")

    text = "\n".join(lines)
    with open(os.path.join(out, "table.md"), "w") as fh:
        fh.write(text + "\n")
    print(text)


if __name__ == "__main__":
    main()

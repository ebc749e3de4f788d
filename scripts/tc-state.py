#!/usr/bin/env python3
"""The building's state at the hand-off moment Tc (or any time) from a run folder: the
figures the paper reports for its library case (Zheng et al. 2020, §5.2: Tc, the
maximum lateral displacement at Tc, the story where the damage concentrates), read from
the run's own files only (`summary.json`, `bodies.csv`, `keyframes.csv`, `history.csv`,
`connections.csv`; docs/scenario-format.md).

    python3 scripts/tc-state.py RUN_DIR [--time T] [--json OUT.json]

Definitions (SI units):
* floor k: the slab bodies whose undeformed centre lies at the k-th distinct slab level
  (levels closer than 0.05 m merged); its displacement u_k is the mass-weighted mean of
  its slab centres' displacements (keyframe pose − undeformed pose), relative to the
  ground (history.csv's ground_x/ground_y at that time, m).
* story k spans floor k−1 (the ground, u_0 = 0, for k = 1) to floor k; its drift ratio is
  |u_k − u_{k−1}|_plan / (z_k − z_{k−1}).
* maximum lateral displacement: the largest plan displacement relative to the ground of
  any non-passive body centre at that time, m (the paper's "0.97 m at Tc").
* a connection's story: the story of the lower of its two bodies (by undeformed centre
  height); its start state at Tc (connections.csv `start_state`) counts as damage there.
"""
import argparse
import csv
import json
import math
import sys
from collections import defaultdict


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("run_dir")
    ap.add_argument("--time", type=float, help="time to read (default: Tc, else the FE end)")
    ap.add_argument("--json", help="also write the figures as JSON here")
    args = ap.parse_args()
    d = args.run_dir.rstrip("/")

    summary = json.load(open(f"{d}/summary.json"))
    t = args.time
    if t is None:
        t = summary.get("tc_s")
        if t is None:
            t = summary.get("fe_end_s")
    if t is None:
        sys.exit(f"{d}/summary.json: no tc_s or fe_end_s; give --time")

    bodies = [b for b in read_csv(f"{d}/bodies.csv") if b["passive"] == "0"]
    init = {b["name"]: (float(b["cx"]), float(b["cy"]), float(b["cz"])) for b in bodies}
    mass = {b["name"]: float(b["mass_kg"]) for b in bodies}
    kind = {b["name"]: b["type"] for b in bodies}

    # The keyframe time at or before t (keyframes are at k/25 s and at Tc).
    times = sorted({float(r["t"]) for r in read_csv(f"{d}/history.csv")})
    tk = max((x for x in times if x <= t + 1e-9), default=None)
    if tk is None:
        sys.exit(f"{d}/history.csv: no frame at or before t = {t}")
    hist = {float(r["t"]): r for r in read_csv(f"{d}/history.csv")}
    g = hist[tk]
    gx, gy = float(g["ground_x"]), float(g["ground_y"])

    pose = {}
    with open(f"{d}/keyframes.csv", newline="") as f:
        for r in csv.DictReader(f):
            if abs(float(r["t"]) - tk) < 1e-9 and r["name"] in init:
                pose[r["name"]] = (float(r["x"]), float(r["y"]), float(r["z"]))
    missing = [n for n in init if n not in pose]
    if missing:
        sys.exit(f"{d}/keyframes.csv: no pose at t = {tk:.4f} for {missing[0]} "
                 f"(and {len(missing) - 1} more)")

    def rel(n):
        (x0, y0, z0), (x, y, z) = init[n], pose[n]
        return x - x0 - gx, y - y0 - gy, z - z0

    # Floors from the slab levels.
    slab_z = sorted({round(init[n][2], 3) for n in init if kind[n] == "Slab"})
    levels = []
    for z in slab_z:
        if not levels or z - levels[-1] > 0.05:
            levels.append(z)
    floors = []
    for z in levels:
        members = [n for n in init if kind[n] == "Slab" and abs(init[n][2] - z) <= 0.05]
        m = sum(mass[n] for n in members)
        ux = sum(mass[n] * rel(n)[0] for n in members) / m
        uy = sum(mass[n] * rel(n)[1] for n in members) / m
        floors.append({"level_m": z, "ux_m": ux, "uy_m": uy, "slabs": len(members)})
    stories = []
    below = (0.0, 0.0, 0.0)
    z_ground = min(init[n][2] for n in init)  # lowest centre: first story's bottom half
    z_prev = 0.0 if z_ground >= 0.0 else z_ground
    for k, fl in enumerate(floors, start=1):
        h = fl["level_m"] - z_prev
        du = math.hypot(fl["ux_m"] - below[0], fl["uy_m"] - below[1])
        stories.append({"story": k, "height_m": h, "drift_ratio": du / h})
        below = (fl["ux_m"], fl["uy_m"], 0.0)
        z_prev = fl["level_m"]

    def story_of(z):
        for k, fl in enumerate(floors, start=1):
            if z <= fl["level_m"] + 0.05:
                return k
        return len(floors)

    lateral = max(((math.hypot(*rel(n)[:2]), n) for n in init))
    drop = max(((-rel(n)[2], n) for n in init))

    damage = defaultdict(lambda: {"intact": 0, "plastic": 0, "broken": 0})
    try:
        for r in read_csv(f"{d}/connections.csv"):
            za = init.get(r["a"], (0, 0, math.inf))[2]
            zb = init.get(r["b"], (0, 0, math.inf))[2]
            damage[story_of(min(za, zb))][r["start_state"]] += 1
    except FileNotFoundError:
        pass

    out = {
        "run": d,
        "time_s": tk,
        "tc_s": summary.get("tc_s"),
        "tc_detail": summary.get("tc_detail"),
        "max_lateral_displacement_m": lateral[0],
        "max_lateral_body": lateral[1],
        "max_drop_m": drop[0],
        "max_drop_body": drop[1],
        "floors": floors,
        "stories": stories,
        "connections_at_start_by_story": {str(k): v for k, v in sorted(damage.items())},
    }
    print(f"{d}: t = {tk:.4f} s (Tc = {out['tc_s']}; {out['tc_detail']})")
    print(f"max lateral displacement {lateral[0]:.3f} m ({lateral[1]}); "
          f"max drop {drop[0]:.3f} m ({drop[1]})")
    print("story  height_m  drift_%   connections intact/plastic/broken at start")
    for s in stories:
        c = damage.get(s["story"])
        cs = f"{c['intact']}/{c['plastic']}/{c['broken']}" if c else "-"
        print(f"{s['story']:5d}  {s['height_m']:8.3f}  {100 * s['drift_ratio']:7.3f}   {cs}")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(out, f, indent=1)
            f.write("\n")


if __name__ == "__main__":
    main()

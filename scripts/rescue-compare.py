#!/usr/bin/env python3
"""Compares two rescue analyses of the same ruin (two run folders' voids.csv and
voids.json): every measure must be equal, the access and breach costs too (whether the
rescuer and the camera reach each void, the route lengths, the breach thickness); only
the choice among routes of equal length may differ: the entry sides, the route lines
(`path_m`) and the breach's first cell and side. Prints how many voids differ in each of
those, and exits 1 if anything else differs.

    python3 scripts/rescue-compare.py BEFORE_DIR AFTER_DIR
"""
import csv
import json
import sys

# voids.csv columns that may differ where routes of equal length tie.
TIES_CSV = ["rescuer_entry", "camera_entry", "breach_x", "breach_y", "breach_z", "breach_side"]
# The costs, checked by name so that the report lists them.
COSTS_CSV = ["rescuer_access", "rescuer_route_m", "camera_access", "camera_route_m", "breach_m"]


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    a_dir, b_dir = sys.argv[1:]
    a, b = rows(f"{a_dir}/voids.csv"), rows(f"{b_dir}/voids.csv")
    bad = []
    if len(a) != len(b):
        sys.exit(f"voids.csv: {len(a)} voids against {len(b)}")
    if list(a[0].keys()) != list(b[0].keys()):
        sys.exit("voids.csv: the columns differ")
    counts = {c: 0 for c in TIES_CSV}
    for ra, rb in zip(a, b):
        for col in ra:
            if ra[col] == rb[col]:
                continue
            if col in TIES_CSV:
                counts[col] += 1
            else:
                bad.append(f"voids.csv void {ra['void']} {col}: {ra[col]} against {rb[col]}")
    ja = json.load(open(f"{a_dir}/voids.json"))
    jb = json.load(open(f"{b_dir}/voids.json"))
    paths = {"rescuer": 0, "camera": 0}
    for key in ja:
        if key != "voids" and ja[key] != jb[key]:
            bad.append(f"voids.json {key} differs")
    for va, vb in zip(ja["voids"], jb["voids"]):
        for key in va:
            if va[key] == vb[key]:
                continue
            if key in paths:
                ka, kb = dict(va[key]), dict(vb[key])
                if ka.get("path_m") != kb.get("path_m"):
                    paths[key] += 1
                for k in ("path_m", "entry"):
                    ka.pop(k, None)
                    kb.pop(k, None)
                if ka != kb:
                    bad.append(f"voids.json void {va['void']} {key}: {ka} against {kb}")
            elif key == "breach":
                ka, kb = dict(va[key]), dict(vb[key])
                for k in ("at_m", "side"):
                    ka.pop(k, None)
                    kb.pop(k, None)
                if ka != kb:
                    bad.append(f"voids.json void {va['void']} breach: {ka} against {kb}")
            else:
                bad.append(f"voids.json void {va['void']} {key} differs")
    reached = {
        who: sum(1 for r in a if r[f"{who}_access"] == "1") for who in ("rescuer", "camera")
    }
    print(f"{len(a)} voids; equal in every measure and in {', '.join(COSTS_CSV)}: "
          f"{'no' if bad else 'yes'}")
    print(f"reached: rescuer {reached['rescuer']}, camera {reached['camera']}")
    for col, n in counts.items():
        print(f"  {col} differs in {n} voids")
    for who, n in paths.items():
        print(f"  {who} path_m differs in {n} voids")
    for line in bad[:20]:
        print("DIFFERS:", line)
    if bad:
        print(f"{len(bad)} differences beyond the ties")
        sys.exit(1)


main()

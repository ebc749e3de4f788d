#!/usr/bin/env python3
"""The voids and rubble of a run folder's rescue analysis as docs/rescue.md gives them
(§5b, the library ruin). Usage: python3 scripts/rescue-table.py RUN_DIR [N]

Reads RUN_DIR/voids.csv, voids.json and summary.json (fem2rbd run or fem2rbd voids) and
prints, in Markdown: the counts and volumes of the voids, by pattern, and of the
survivable ones; how the survivable ones are reached (rescuer, camera only, breach) and
how far under debris; where they lie (height bands of their centroids, inside or beyond
the original footprint of summary.json); the rubble measures and each story's volume
loss; and a table of the N largest survivable voids (default 10).
"""
import collections
import csv
import json
import statistics
import sys

run_dir = sys.argv[1]
top = int(sys.argv[2]) if len(sys.argv) > 2 else 10
rows = list(csv.DictReader(open(f"{run_dir}/voids.csv")))
vj = json.load(open(f"{run_dir}/voids.json"))
summary = json.load(open(f"{run_dir}/summary.json"))
surv = [r for r in rows if r["survivable"] == "1"]


def vol(rs):
    return sum(float(r["volume_m3"]) for r in rs)


def counts(rs):
    c = collections.Counter(r["pattern"] for r in rs)
    return ", ".join(f"{k} {v}" for k, v in c.most_common())


stage = summary.get("ruin_stage") or {}
print(
    f"ruin stage: stop {stage.get('stop')} at {stage.get('end_s')} s, "
    f"{stage.get('bodies_at_rest')} bodies at rest; Tc {summary.get('tc_s')} s ({summary.get('tc_reason')})"
)
print(f"voids: {len(rows)} in {vj['regions_count']} regions, {vol(rows):.1f} m³; {counts(rows)}")
print(f"survivable: {len(surv)}, {vol(surv):.1f} m³; {counts(surv)}")
lying_only = sum(r["lying_fits"] == "1" and r["sitting_fits"] == "0" for r in surv)
print(f"  a sitting adult fits in {len(surv) - lying_only}, a lying one only in {lying_only}")
v = [float(r["volume_m3"]) for r in surv]
if v:
    print(f"  volume median {statistics.median(v):.2f} m³, largest {max(v):.2f} m³, {sum(x >= 5 for x in v)} of 5 m³ or more")
res = [r for r in surv if r["rescuer_access"] == "1"]
cam = [r for r in surv if r["rescuer_access"] == "0" and r["camera_access"] == "1"]
neither = [r for r in surv if r["rescuer_access"] == "0" and r["camera_access"] == "0"]
print(f"  rescuer reaches {len(res)} ({vol(res):.1f} m³), entry sides "
      + ", ".join(f"{k} {n}" for k, n in collections.Counter(r["rescuer_entry"] for r in res).most_common()))
if res:
    rm = [float(r["rescuer_route_m"]) for r in res]
    print(f"    under debris: median {statistics.median(rm):g} m, longest {max(rm):g} m, "
          f"{sum(x <= 1.0 for x in rm)} within 1 m")
print(f"  camera only {len(cam)}" + (
    f", under debris median {statistics.median(float(r['camera_route_m']) for r in cam):g} m, "
    f"longest {max(float(r['camera_route_m']) for r in cam):g} m" if cam else ""))
print(f"  neither: {len(neither)}" + (
    f", breach median {statistics.median(float(r['breach_m']) for r in neither):g} m" if neither else ""))
cd = [float(r["cover_depth_m"]) for r in surv]
if cd:
    print(f"  cover depth median {statistics.median(cd):g} m, deepest {max(cd):g} m")
bands = collections.Counter(int(float(r["centroid_z"]) // 1) for r in surv)
print("  centroid height bands (m): " + ", ".join(f"{k}–{k + 1}: {n}" for k, n in sorted(bands.items())))
fp = (summary.get("ruins") or {}).get("original_footprint_m")
if fp:
    inside = sum(
        fp["x"][0] <= float(r["centroid_x"]) <= fp["x"][1] and fp["y"][0] <= float(r["centroid_y"]) <= fp["y"][1]
        for r in surv
    )
    print(f"  centroid inside the original footprint: {inside}, beyond it: {len(surv) - inside}")
rb = vj.get("rubble") or {}
if rb:
    ext = rb["extent_m"]
    over = rb["extent_over_height"]
    print(
        f"rubble: building height {rb['building_height_m']} m; pile max {rb['max_height_m']} m, mean "
        f"{rb['mean_height_m']:.2f} m; porosity {rb['porosity']:.2f}; beyond the footprint "
        + ", ".join(f"{k} {ext[k]:.1f} m ({over[k]:.2f} H)" for k in ext)
    )
for s in vj.get("stories") or []:
    print(
        f"story {s['story']} (ceiling {s['ceiling_z_m']} m): {s['free_volume_before_m3']:g} → "
        f"{s['free_volume_after_m3']:g} m³, loss {s['volume_loss']:.2f}"
    )
print()
print("| void | volume m³ | clear height m | inscribed radius m | fits | pattern | tilt ° | held by | roof | centroid x, y, z m | cover m | access |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|")
for r in sorted(surv, key=lambda r: int(r["void"]))[:top]:
    fits = " ".join(x for x, k in (("L", "lying_fits"), ("S", "sitting_fits")) if r[k] == "1")
    tilt = f"{float(r['roof_tilt_deg']):.1f}" if r["roof_tilt_deg"] else "—"
    held = r["held_by"] or "—"
    if r["rescuer_access"] == "1":
        acc = f"rescuer from {r['rescuer_entry']}, {float(r['rescuer_route_m']):g} m under debris"
    elif r["camera_access"] == "1":
        acc = f"camera only, {float(r['camera_route_m']):g} m"
    else:
        acc = f"breach {float(r['breach_m']):g} m from {r['breach_side']}"
    print(
        f"| {r['void']} | {float(r['volume_m3']):.2f} | {float(r['clear_height_m']):g} | "
        f"{float(r['inscribed_radius_m']):.2f} | {fits} | {r['pattern']} | {tilt} | {held} | "
        f"`{r['roof_bodies'].split(';')[0]}` | {float(r['centroid_x']):.1f}, {float(r['centroid_y']):.1f}, "
        f"{float(r['centroid_z']):.1f} | {float(r['cover_depth_m']):g} | {acc} |"
    )

#!/usr/bin/env bash
# Case 1 (docs/case1.md): frame3 under LC5 in the three modes, their plots, and the
# sensitivity of the ruin distribution to Bullet's substep (200 / 400 / 800 steps/s).
# Usage: bash scripts/case1-ruins.sh [OUT_DIR]   (default out/case1; ~5 min in release)
# Writes OUT_DIR/<run>/ (run folders with plots/), OUT_DIR/table.md (the figures quoted in
# docs/case1.md) and copies the plan and history figures into docs/case1/.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
out=${1:-out/case1}
mkdir -p "$out" docs/case1
out=$(cd "$out" && pwd)
cargo build --release --quiet
bin=target/release/fem2rbd

# A copy of data/frame3/lc5.toml with absolute paths and extra [physics] keys.
scenario() { # name extra-physics-lines
  sed -e "s#^model = \"model.toml\"#model = \"$root/data/frame3/model.toml\"#" \
      -e "s#\"\.\./ground-motions/#\"$root/data/ground-motions/#" \
      -e "s#^output = .*#output = \"$out/$1\"#" \
      data/frame3/lc5.toml > "$out/$1.toml"
  printf '%b\n' "$2" >> "$out/$1.toml"
}

for mode in hybrid rigid fe; do
  $bin --quiet run data/frame3/lc5.toml --mode $mode --out "$out/$mode"
  $bin --quiet plot "$out/$mode"
done
for sps in 400 800; do
  for mode in hybrid rigid; do
    scenario "$mode-sps$sps" "steps_per_second = $sps"
    $bin --quiet run "$out/$mode-sps$sps.toml" --mode $mode
  done
done
for mode in hybrid rigid; do
  for f in ruin_plan history; do
    cp "$out/$mode/plots/$f.png" "docs/case1/$mode-$f.png"
  done
done
cp "$out/hybrid/plots/connections.png" docs/case1/hybrid-connections.png

python3 - "$out" > "$out/table.md" <<'PY'
import json, sys, os
out = sys.argv[1]
runs = ["hybrid", "hybrid-sps400", "hybrid-sps800", "rigid", "rigid-sps400", "rigid-sps800", "fe"]
print("| run | Tc (s, why) | ruin stage end (s, stop) | connections i/p/b | floor offsets 1, 2, 3 (m) | floor drops 1, 2, 3 (m) | overlap 1–2, 2–3 | debris area (m²) | extent (m) | height (m) | max penetration (m) |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
for r in runs:
    p = os.path.join(out, r, "summary.json")
    if not os.path.exists(p):
        continue
    s = json.load(open(p))
    tc = s.get("tc_s")
    tc = f"{tc:.3f} ({s['tc_reason']})" if tc is not None else s["tc_reason"]
    rs = s.get("ruin_stage")
    ru = s.get("ruins", {})
    c = s.get("connections")
    fl = ru.get("floors", [])
    ov = ru.get("slab_overlap", [])
    f = lambda xs: ", ".join(f"{x:.2f}" for x in xs)
    print("| " + " | ".join([
        r, tc,
        f"{rs['end_s']:.2f}, {rs['stop']}" if rs else "–",
        f"{c['intact']}/{c['plastic']}/{c['broken']}" if c else "–",
        f([x["horizontal_offset_m"] for x in fl]),
        f([-x["centroid_displacement_m"][2] for x in fl]),
        f([x["overlap_ratio"] for x in ov]),
        f"{ru.get('debris_footprint_area_m2', 0):.2f}",
        f"{ru.get('extent_beyond_footprint_m', {}).get('max', 0):.2f}",
        f"{ru.get('max_debris_height_m', 0):.2f}",
        f"{rs['max_penetration_m']:.3f}" if rs else "–",
    ]) + " |")
PY
cat "$out/table.md"

#!/usr/bin/env bash
# Convergence of the ruin measures of frame3 LC5 (docs/ruin-numerics.md): runs the shipped
# scenario data/frame3/lc5.toml in the hybrid and physics modes at 200 / 400 / 800
# substeps/s (100 solver iterations) and at 200 iterations (200 substeps/s), release build,
# then prints the table (Markdown) with scripts/ruin-table.py.
#
#   bash scripts/ruin-convergence.sh [OUT_DIR] [MODES]      (default out/ruin-convergence, "hybrid physics")
#
# Extra [physics] lines for every run can be given in RUIN_EXTRA (e.g. RUIN_EXTRA='joint_erp = 0.05').
# Each run takes 15-60 s on a free core (800 substeps/s: about 4 times longer).
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${1:-out/ruin-convergence}
MODES=${2:-hybrid physics}
ROOT=$PWD
mkdir -p "$OUT/scenarios"
cargo build --release --quiet
for mode in $MODES; do
  for cfg in "200 100" "400 100" "800 100" "200 200"; do
    set -- $cfg
    name="$mode-sps$1-it$2"
    sc="$OUT/scenarios/$name.toml"
    sed -e "s#^model = \"model.toml\"#model = \"$ROOT/data/frame3/model.toml\"#" \
        -e "s#file = \"\.\./#file = \"$ROOT/data/#" \
        data/frame3/lc5.toml > "$sc"
    printf 'steps_per_second = %s\nsolver_iterations = %s\n%s\n' "$1" "$2" "${RUIN_EXTRA:-}" >> "$sc"
    echo "== $name" >&2
    ./target/release/fem2rbd run "$sc" --mode "$mode" --out "$OUT/$name" --quiet
  done
done
python3 scripts/ruin-table.py "$OUT"/*-sps*-it*

#!/usr/bin/env bash
# Ruin-stage speed of a full-scale 7-story building (docs/performance.md, "Ruin stage"):
# writes the 6 x 4-bay, 7-story frame with `fem2rbd generate frame` (7.5 m bays,
# 3.6 m stories, 0.7 m columns, scale 1), a rigid-only El Centro scenario (X 0.93 g,
# Y 1.19 g, Z 0.57 g as frame3 LC5, real time), and runs bench_ruin on it: wall time per
# simulated second with each setting side by side (alternated runs), Bullet's profile
# zones and the island statistics.
#
#   bash scripts/ruin-speed.sh [OUT_DIR] [SIM_SECONDS] [ROUNDS] [CONFIGS] [BUILDING]
#   (defaults: out/ruin-speed, 1, 3, "t1+bullet,t1,t2", frame7)
#
# CONFIGS: tN = N solver threads, +bullet = Bullet's own solver sweep (the "before" of the
# lean iterations), +lean = the lean sweep (the "before" of the packed one), +threads = the
# packed sweep always on the threads, +sleep = sleeping on (bench_ruin's docs). BUILDING = library runs the
# same benchmark on the library stand-in's rigid-only scenario
# (data/library/elcentro-4g-rigid.toml: 2 703 bodies, 9 095 connections) instead.
# Run it under `nice -n 10` on a shared machine; compare the CPU columns.
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${1:-out/ruin-speed}
SIM=${2:-1}
ROUNDS=${3:-3}
CONFIGS=${4:-t1+bullet,t1,t2}
BUILDING=${5:-frame7}
ROOT=$PWD
mkdir -p "$OUT"
cargo build --release --quiet --bin fem2rbd --bin bench_ruin
if [ "$BUILDING" = library ]; then
  exec ./target/release/bench_ruin data/library/elcentro-4g-rigid.toml --time "$SIM" --rounds "$ROUNDS" --configs "$CONFIGS"
elif [ "$BUILDING" != frame7 ]; then
  echo "ruin-speed.sh: BUILDING must be frame7 or library, not '$BUILDING'" >&2
  exit 2
fi
./target/release/fem2rbd generate frame --spans-x 7.5,7.5,7.5,7.5,7.5,7.5 --spans-y 7.5,7.5,7.5,7.5 \
  --stories 3.6,3.6,3.6,3.6,3.6,3.6,3.6 \
  --column 0.7x0.7 --beam 0.35x0.7 --slab-thickness 0.15 --scale 1 --ec 30e9 --fc 30e6 \
  --added-mass 200000 --formulation disp --quiet -o "$OUT/model.toml"
cat > "$OUT/physics.toml" <<TOML
model = "model.toml"
mode = "rigid"
output = "run"

[[ground_motion]]
file = "$ROOT/data/ground-motions/RSN6_IMPVALL.I_I-ELC180.AT2"
direction = "X"
pga_g = 0.93

[[ground_motion]]
file = "$ROOT/data/ground-motions/RSN6_IMPVALL.I_I-ELC270.AT2"
direction = "Y"
pga_g = 1.19

[[ground_motion]]
file = "$ROOT/data/ground-motions/RSN6_IMPVALL.I_I-ELC-UP.AT2"
direction = "Z"
pga_g = 0.57

[physics]
stop_at_rest = false
TOML
./target/release/bench_ruin "$OUT/physics.toml" --time "$SIM" --rounds "$ROUNDS" --configs "$CONFIGS"

#!/usr/bin/env bash
# Convergence of the ruin measures of frame3 LC5 against the ensemble spread
# (docs/ruin-numerics.md, "Convergence"). Per mode (hybrid, rigid):
#   1. an ensemble of N members at BCB's setting (200 substeps/s, 100 iterations;
#      `fem2rbd run --ensemble N --seed S`, member 0 = the unperturbed run),
#   2. the same scenario at 400 and 800 substeps/s (100 iterations) and at 200 iterations,
# then prints, with scripts/ruin-convergence-table.py, the ensemble spread of every ruin
# measure and the convergence table: a variant agrees on a measure when it differs from
# the unperturbed run (member 0) by at most max(10 % of it (0.1 for ratios), the ensemble
# spread = max - min over the members).
#
#   bash scripts/ruin-convergence.sh [OUT_DIR] [MODES]   (default out/ruin-convergence, "hybrid rigid")
#
# Environment: ENSEMBLE (members, default 8), SEED (default 1), THREADS (ensemble worker
# threads, default 2), FEM2RBD (the binary, default target/release/fem2rbd, built first),
# RUIN_EXTRA (extra [physics] lines for every run, e.g. 'experimental.joint_erp = 0.05'),
# VARIANT_ENSEMBLE (default 0; N > 0 also runs every variant as an ensemble of N members,
# same seed, into MODE-spsX-itY-ens, and the table compares the distributions: a single
# run of a chaotic pile is one sample, docs/ruin-numerics.md, "The error reduction per second").
# VARIANTS (default "400/100 800/100 200/200"): the variants, each SPS/IT or
# SPS/IT/KEY=VALUE[,KEY=VALUE...] with extra [physics] lines (e.g.
# "200/100/experimental.joint_solve=direct", "200/100/experimental.joint_warmstart=0"); a variant's folder is
# MODE-spsSPS-itIT[-KEY-VALUE...] (string values unquoted in the name: VALUE='"direct"' gives
# -experimental.joint_solve-direct). SINGLE_RUNS=0 skips the single variant runs (step 2) when only the
# distributions are wanted.
# After the tables of scripts/ruin-convergence-table.py, with VARIANT_ENSEMBLE set,
# scripts/ruin-convergence-doubling.py prints the doubling table (docs/ruin-convergence.md):
# every pair of ensembles whose Gauss–Seidel sweeps per second differ by a factor of two,
# and every variant with extra lines against the plain one of the same sweeps.
# Each ensemble's wall time (seconds, all members, THREADS worker threads) goes to
# OUT/NAME.wall_s. Runs whose summary.json / ensemble.json exist are kept (delete them to
# rerun).
# Cost on two free cores: a hybrid run about 50 s, rigid-only 30 s, 800 substeps/s about
# 3 times longer; the whole table (2 ensembles of 8 + 6 variants) took 39 min on the
# shared 2-core machine.
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${1:-out/ruin-convergence}
MODES=${2:-hybrid rigid}
N=${ENSEMBLE:-8}
SEED=${SEED:-1}
THREADS=${THREADS:-2}
ROOT=$PWD
if [ -z "${FEM2RBD:-}" ]; then
  cargo build --release --quiet
  FEM2RBD=./target/release/fem2rbd
fi
mkdir -p "$OUT/scenarios"
scenario() { # name sps iterations
  local sc="$OUT/scenarios/$1.toml"
  sed -e "s#^model = \"model.toml\"#model = \"$ROOT/data/frame3/model.toml\"#" \
      -e "s#file = \"\.\./#file = \"$ROOT/data/#" \
      data/frame3/lc5.toml > "$sc"
  printf 'steps_per_second = %s\nsolver_iterations = %s\n%s\n' "$2" "$3" "${RUIN_EXTRA:-}" >> "$sc"
  echo "$sc"
}
VARIANTS=${VARIANTS:-400/100 800/100 200/200}
variant_name() { # SPS/IT[/KEY=VALUE,...] -> spsSPS-itIT[-KEY-VALUE...]
  local sps it extra name
  IFS=/ read -r sps it extra <<< "$1"
  name="sps$sps-it$it"
  if [ -n "$extra" ]; then
    name="$name-$(printf '%s' "$extra" | tr -d '"' | tr '=,' '--')"
  fi
  echo "$name"
}
variant_scenario() { # output-name SPS/IT[/KEY=VALUE,...]
  local sps it extra
  IFS=/ read -r sps it extra <<< "$2"
  RUIN_EXTRA="${RUIN_EXTRA:-}
$(printf '%s' "$extra" | tr ',' '\n')" scenario "$1" "$sps" "$it"
}
for mode in $MODES; do
  name="$mode-ensemble"
  if [ ! -f "$OUT/$name/ensemble.json" ]; then
    echo "== $name ($N members, seed $SEED)" >&2
    start=$(date +%s)
    "$FEM2RBD" run "$(scenario "$name" 200 100)" --mode "$mode" --out "$OUT/$name" \
      --ensemble "$N" --seed "$SEED" --threads "$THREADS" --quiet
    echo $(( $(date +%s) - start )) > "$OUT/$name.wall_s"
  fi
  if [ "${SINGLE_RUNS:-1}" != 0 ]; then
    for v in $VARIANTS; do
      name="$mode-$(variant_name "$v")"
      [ -f "$OUT/$name/summary.json" ] && continue
      echo "== $name" >&2
      "$FEM2RBD" run "$(variant_scenario "$name" "$v")" --mode "$mode" --out "$OUT/$name" --quiet
    done
  fi
  if [ "${VARIANT_ENSEMBLE:-0}" -gt 0 ]; then
    for v in $VARIANTS; do
      name="$mode-$(variant_name "$v")-ens"
      [ -f "$OUT/$name/ensemble.json" ] && continue
      echo "== $name ($VARIANT_ENSEMBLE members, seed $SEED)" >&2
      start=$(date +%s)
      "$FEM2RBD" run "$(variant_scenario "$name" "$v")" --mode "$mode" --out "$OUT/$name" \
        --ensemble "$VARIANT_ENSEMBLE" --seed "$SEED" --threads "$THREADS" --quiet
      echo $(( $(date +%s) - start )) > "$OUT/$name.wall_s"
    done
  fi
done
python3 scripts/ruin-convergence-table.py "$OUT" $MODES
if [ "${VARIANT_ENSEMBLE:-0}" -gt 0 ]; then
  python3 scripts/ruin-convergence-doubling.py "$OUT" $MODES
fi

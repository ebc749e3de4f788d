#!/bin/bash
# Remeasures the build-structure numbers (build time after a one-line change, test binary
# size), debug (test) profile:
#   1. `cargo test --workspace --no-run` after a one-line change in src/cli/run.rs (a
#      comment line appended, the file restored after each build): median and all of
#      RUNS builds (default 3);
#   2. the disk size of the test binaries that build produces;
#   3. the number of tests (`cargo test --workspace -- --list`);
#   4. the FE crate without Bullet: `cargo tree -p fem2rbd-fe` has no bullet-sys /
#      fem2rbd-bullet, and `cargo build -p fem2rbd-fe` succeeds with libclang and the
#      Bullet pkg-config files hidden (LIBCLANG_PATH, PKG_CONFIG_LIBDIR pointed nowhere);
#   5. cycles: `output` modules importing `pipeline`;
#   6. `anyhow` in library code (code lines outside src/main.rs, src/cli/, src/bin/);
#   7. clippy: `cargo clippy --workspace --all-targets -- -D warnings`.
# Run it on an idle machine: the timings are wall-clock.
# Usage: scripts/measure-structure.sh        (RUNS=5 scripts/measure-structure.sh)
set -u
cd "$(dirname "$0")/.."
RUNS=${RUNS:-3}
F=src/cli/run.rs
BACKUP=$(mktemp /tmp/measure-structure.XXXXXX)
cp -p "$F" "$BACKUP"
restore() { cp -p "$BACKUP" "$F"; rm -f "$BACKUP"; }
trap restore EXIT

echo "# fem2rbd structure ($(git rev-parse --short HEAD), $(date -u +%FT%TZ), $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg))"

# Warm-up: everything built once, untimed.
cargo test --workspace --no-run -q >/dev/null 2>&1 || { echo "warm-up build failed"; exit 1; }

times=()
for i in $(seq "$RUNS"); do
    echo "// measure-structure: one-line change $i" >> "$F"
    t0=$(date +%s.%N)
    cargo test --workspace --no-run -q >/dev/null 2>&1 || { echo "build $i failed"; exit 1; }
    t1=$(date +%s.%N)
    cp -p "$BACKUP" "$F"
    touch "$F"
    times+=("$(echo "$t1 - $t0" | bc)")
done
# Back to the source as committed (untimed), listing the test executables.
exes=$(cargo test --workspace --no-run --message-format=json 2>/dev/null |
    python3 -c 'import json,sys
for l in sys.stdin:
    try: m = json.loads(l)
    except ValueError: continue
    if m.get("reason") == "compiler-artifact" and m.get("executable") and m["profile"]["test"]:
        print(m["executable"])')
median=$(printf '%s\n' "${times[@]}" | sort -g | awk '{a[NR]=$1} END {print (NR%2 ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2)}')
printf 'test build after a one-line change in %s: median %.1f s of %s (%s)\n' \
    "$F" "$median" "$RUNS" "$(printf '%.1f ' "${times[@]}" | sed 's/ $//')"

n_exe=$(echo "$exes" | grep -c .)
bytes=$(echo "$exes" | xargs du -cb | tail -1 | cut -f1)
printf 'test binaries: %d, %.2f GB\n' "$n_exe" "$(echo "$bytes / 1000000000" | bc -l)"

tests=$(cargo test --workspace -q -- --list 2>/dev/null | grep -c ': test$')
echo "tests: $tests (cargo test --workspace -- --list)"

if cargo tree -p fem2rbd-fe -e normal,build 2>/dev/null | grep -Eq 'bullet-sys|fem2rbd-bullet'; then
    echo "fem2rbd-fe: DEPENDS ON BULLET (cargo tree)"
elif LIBCLANG_PATH=/nonexistent PKG_CONFIG_LIBDIR=/nonexistent \
    cargo build -q -p fem2rbd-fe >/dev/null 2>&1; then
    echo "fem2rbd-fe: builds without Bullet and libclang (no bullet-sys in cargo tree)"
else
    echo "fem2rbd-fe: cargo build -p fem2rbd-fe FAILED"
fi

cycles=$(grep -lE 'crate::pipeline|super::super::pipeline' src/output/*.rs 2>/dev/null | wc -l)
echo "output modules importing pipeline (cycle): $cycles"

library_anyhow=$(grep -rn --include='*.rs' anyhow src crates/*/src |
    grep -vE '^(src/main\.rs|src/cli/|src/bin/)' |
    awk -F: '{ line = $0; sub(/^[^:]*:[^:]*:/, "", line); sub(/\/\/.*/, "", line);
               if (line ~ /anyhow/) n++ } END { print n + 0 }')
edge_anyhow=$(grep -rn --include='*.rs' anyhow src/main.rs src/cli src/bin | wc -l)
echo "anyhow in library code: $library_anyhow lines (at the binary's edge: $edge_anyhow)"

clippy_out=$(cargo clippy --workspace --all-targets --message-format=short -- -D warnings 2>&1)
if [ $? -eq 0 ]; then
    echo "clippy -D warnings: clean"
else
    echo "clippy -D warnings: $(echo "$clippy_out" | grep -cE ': (warning|error)') findings"
fi

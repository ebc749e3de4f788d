#!/bin/bash
# Measures fem2rbd's time and memory estimate (src/estimate.rs, docs/reliability.md)
# against the actual wall time, CPU time (user + sys) and peak RSS of the same runs
# (/usr/bin/time -v), release build. Prints one line per case:
#   case  est_s  wall_s  cpu_s  est/wall  est/cpu  est_mib  rss_mib  est/rss
# Usage: cargo build --release && scripts/measure-estimate.sh [CASE...]
# Cases: fe3 fe3-1step fe3-elastic fe4 wall phys3 hyb3 hyb4 scene lc5 (default: all).
set -u
cd "$(dirname "$0")/.."
B=${FEM2RBD:-target/release/fem2rbd}
T=$(mktemp -d /tmp/fem2rbd-estimate.XXXXXX)
trap 'rm -rf "$T"' EXIT
G=data/ground-motions
GM="--gm X=$G/RSN6_IMPVALL.I_I-ELC180.AT2,pga=0.93 --gm Y=$G/RSN6_IMPVALL.I_I-ELC270.AT2,pga=1.19 --gm Z=$G/RSN6_IMPVALL.I_I-ELC-UP.AT2,pga=0.57 --time-scale 0.5"
# A 4-story 2 x 2-bay frame of frame3's members (the generator's defaults otherwise).
$B --quiet generate frame --stories 1.0,1.0,1.0,1.0 --spans-x 1.5,1.5 --spans-y 1.5,1.5 \
    --ec 25e9 --fc 22.5e6 --added-mass 2699.75 --output "$T/frame4.toml" || exit 1
# Scenarios: LC5 of frame3 (data/frame3/lc5.toml) with the ruin stage cut at 4 s of
# simulated time so that every case takes seconds to a minute.
scen() { # name model mode extra-physics-lines
    sed -e "s|^model = .*|model = \"$(pwd)/$2\"|" -e "s|^mode = .*|mode = \"$3\"|" \
        -e "s|\.\./ground-motions|$(pwd)/$G|" -e "s|^output = .*|output = \"$T/out-$1\"|" \
        -e "s|^stop_at_rest = true|stop_at_rest = false\ntime_limit_s = 4.0|" \
        data/frame3/lc5.toml > "$T/$1.toml"
}
scen phys3 data/frame3/model.toml rigid
scen hyb3 data/frame3/model.toml hybrid
# LC5 as shipped: the hybrid run to rest, with its rescue analysis.
sed -e "s|^model = .*|model = \"$(pwd)/data/frame3/model.toml\"|" -e "s|\.\./ground-motions|$(pwd)/$G|" \
    -e "s|^output = .*|output = \"$T/out-lc5\"|" data/frame3/lc5.toml > "$T/lc5.toml"
mkdir -p "$T/m" && cp "$T/frame4.toml" "$T/m/frame4.toml"
sed -e "s|^model = .*|model = \"$T/m/frame4.toml\"|" "$T/hyb3.toml" > "$T/hyb4.toml"
sed -i "s|^output = .*|output = \"$T/out-hyb4\"|" "$T/hyb4.toml"

run_case() { # name, estimate command..., -- run command...
    local name=$1; shift
    local est=() cmd=()
    while [ "$1" != "--" ]; do est+=("$1"); shift; done; shift
    cmd=("$@")
    local line
    line=$("${est[@]}") || { echo "$name: estimate failed" >&2; return; }
    local es em
    es=$(sed -n 's/.*seconds=\([^ ]*\).*/\1/p' <<<"$line")
    em=$(sed -n 's/.*peak_mib=\([^ ]*\).*/\1/p' <<<"$line")
    /usr/bin/time -v -o "$T/time.txt" "${cmd[@]}" >/dev/null 2>"$T/err.txt" || {
        echo "$name: run failed: $(tail -3 "$T/err.txt")" >&2; }
    local wall cpu rss
    wall=$(awk -F': ' '/Elapsed \(wall clock\)/{n=split($2,a,":"); s=0; for(i=1;i<=n;i++) s=s*60+a[i]; print s}' "$T/time.txt")
    cpu=$(awk -F': ' '/User time/{u=$2} /System time/{s=$2} END{print u+s}' "$T/time.txt")
    rss=$(awk -F': ' '/Maximum resident/{print $2/1024}' "$T/time.txt")
    awk -v n="$name" -v es="$es" -v w="$wall" -v c="$cpu" -v em="$em" -v r="$rss" -v l="$line" 'BEGIN{
        printf "%-12s est %7.2f s  wall %7.2f s  cpu %7.2f s  est/wall %5.2f  est/cpu %5.2f  est %6.1f MiB  rss %6.1f MiB  est/rss %5.2f   [%s]\n",
            n, es, w, c, es/w, es/c, em, r, em/r, l }'
}

want() { [ $# -eq 0 ] && return 0; for c in "${CASES[@]}"; do [ "$c" = "$1" ] && return 0; done; return 1; }
CASES=("$@")
[ ${#CASES[@]} -eq 0 ] && CASES=(fe3 fe3-1step fe3-elastic fe4 wall phys3 hyb3 hyb4 scene lc5)
for c in "${CASES[@]}"; do
    case $c in
    fe3) run_case fe3 $B fe data/frame3/model.toml $GM --duration 3 --out "$T/fe" --estimate \
            -- $B --quiet fe data/frame3/model.toml $GM --duration 3 --out "$T/fe" ;;
    fe3-1step) run_case fe3-1step $B fe data/frame3/model.toml $GM --duration 0.005 --out "$T/fe" --estimate \
            -- $B --quiet fe data/frame3/model.toml $GM --duration 0.005 --out "$T/fe" ;;
    fe3-elastic) run_case fe3-elastic $B fe data/frame3/model.toml $GM --duration 3 --variant elastic --out "$T/fe" --estimate \
            -- $B --quiet fe data/frame3/model.toml $GM --duration 3 --variant elastic --out "$T/fe" ;;
    fe4) run_case fe4 $B fe "$T/frame4.toml" $GM --duration 3 --out "$T/fe" --estimate \
            -- $B --quiet fe "$T/frame4.toml" $GM --duration 3 --out "$T/fe" ;;
    wall) run_case wall $B fe tests/fixtures/wall-layered-1x6.toml $GM --duration 1 --out "$T/fe" --estimate \
            -- $B --quiet fe tests/fixtures/wall-layered-1x6.toml $GM --duration 1 --out "$T/fe" ;;
    phys3) run_case phys3 $B run "$T/phys3.toml" --estimate -- $B --quiet run "$T/phys3.toml" ;;
    hyb3) run_case hyb3 $B run "$T/hyb3.toml" --estimate -- $B --quiet run "$T/hyb3.toml" ;;
    lc5) run_case lc5 $B run "$T/lc5.toml" --estimate -- $B --quiet run "$T/lc5.toml" ;;
    hyb4) run_case hyb4 $B run "$T/hyb4.toml" --estimate -- $B --quiet run "$T/hyb4.toml" ;;
    scene) sed 's/"duration": 2.0/"duration": 20.0/' data/scenes/pile.json > "$T/pile.json"
        run_case scene $B scene "$T/pile.json" --out "$T/pile.csv" --estimate \
            -- $B --quiet scene "$T/pile.json" --out "$T/pile.csv" ;;
    *) echo "unknown case $c" >&2 ;;
    esac
done

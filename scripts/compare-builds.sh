#!/usr/bin/env bash
# Times two builds of the library against each other on a machine whose speed drifts from minute
# to minute (docs/performance.md): the same benchmark or render, with each build's library, in
# quick alternation (bench) or at the same time on one thread each (render), and the median of
# the paired ratios B/A, which the drift moves far less than either time.
#
#   scripts/compare-builds.sh DIR_A DIR_B ROUNDS bench FILTER
#   scripts/compare-builds.sh DIR_A DIR_B ROUNDS render RENDER_ARGS...
#
# DIR_A and DIR_B each hold a copy of a build's libglintscope.so.0.1 (for example
# `mkdir a && cp -L build/lib/libglintscope.so.0.1 a/`); the benchmark and the app are this
# checkout's build/, which load the library through LD_LIBRARY_PATH. bench: FILTER should select
# one benchmark; each run takes --benchmark_min_time=0.3, and the order of A and B alternates per
# round. render: the user seconds of `glintscope --threads 1 render RENDER_ARGS -o TMP.exr` (a
# light sweep's `--png X` in RENDER_ARGS becomes a temporary PNG of each build's own).
set -euo pipefail
if [ $# -lt 5 ]; then
    sed -n '2,15p' "$0" | sed 's/^# \{0,1\}//' >&2
    exit 2
fi
a=$(realpath -m "$1") b=$(realpath -m "$2") rounds=$3 mode=$4  # absolute: the script runs from the checkout
shift 4
cd "$(dirname "$0")/.."
for dir in "$a" "$b"; do
    [ -e "$dir/libglintscope.so.0.1" ] || { echo "compare-builds: no libglintscope.so.0.1 in $dir" >&2; exit 2; }
done
[[ "$rounds" =~ ^[1-9][0-9]*$ ]] || { echo "compare-builds: ROUNDS must be a positive integer, got '$rounds'" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

bench_time() {  # the first selected benchmark's CPU time with the library in $1
    LD_LIBRARY_PATH=$1 build/bench/glintscope_bench --benchmark_filter="$filter" --benchmark_min_time=0.3 \
        2>/dev/null | awk '/^BM_/ {print $4; exit}'
}
render_time() {  # user seconds of the render with the library in $1, its output in $2; its error if it fails
    local args=() previous=
    for arg in "${render_args[@]}"; do  # each build's own --png (a light sweep's frames and video)
        if [ "$previous" = --png ]; then args+=("$2.png"); else args+=("$arg"); fi
        previous=$arg
    done
    if ! LD_LIBRARY_PATH=$1 /usr/bin/time -f '%U' -o "$2.time" build/app/glintscope --threads 1 render \
        "${args[@]}" -o "$2" >/dev/null 2>"$2.err"; then
        echo "compare-builds: the render with $1 failed: $(tail -1 "$2.err")" >&2
        return 1
    fi
    tail -1 "$2.time"
}

case "$mode" in
    bench)
        filter=$1
        for ((round = 1; round <= rounds; ++round)); do
            if ((round % 2)); then x=$(bench_time "$a"); y=$(bench_time "$b"); else y=$(bench_time "$b"); x=$(bench_time "$a"); fi
            echo "$x $y"
        done >"$work/pairs"
        ;;
    render)
        render_args=("$@")
        for ((round = 1; round <= rounds; ++round)); do
            render_time "$a" "$work/a.exr" >"$work/x" &
            first=$!
            render_time "$b" "$work/b.exr" >"$work/y" &
            second=$!
            status=0
            wait "$first" || status=1
            wait "$second" || status=1
            [ "$status" = 0 ] || exit 1
            echo "$(cat "$work/x") $(cat "$work/y")"
        done >"$work/pairs"
        ;;
    *)
        echo "compare-builds: mode must be bench or render, got '$mode'" >&2
        exit 2
        ;;
esac

python3 - "$work/pairs" <<'PY'
import statistics, sys
pairs = [tuple(map(float, line.split())) for line in open(sys.argv[1]) if len(line.split()) == 2]
if not pairs:
    sys.exit("compare-builds: no timings (does the filter select a benchmark, do the renders run?)")
ratios = [b / a for a, b in pairs]
for a, b in pairs:
    print(f"A {a:10.4g}   B {b:10.4g}   B/A {b / a:.3f}")
quartiles = statistics.quantiles(ratios, n=4) if len(ratios) > 1 else [ratios[0]] * 3
print(f"median A {statistics.median(a for a, _ in pairs):.4g}, B {statistics.median(b for _, b in pairs):.4g}; "
      f"B/A median {statistics.median(ratios):.3f} (quartiles {quartiles[0]:.3f}-{quartiles[2]:.3f}, {len(ratios)} pairs)")
PY

#!/bin/sh
# What `make bench` runs: one line per benchmark program (build/bin/sepal-bench-<name>,
# from tests/bench/<name>.cpp). Usage: sh tests/bench/run.sh BUILD_DIR OUT_DIR
# Each line prints its wall time; OUT_DIR/bench-times.txt keeps them (the budget is 15 minutes
# on 2 cores, issue 20), so a bench that grows shows up in the next run.
set -e
build="$1"; out="$2"; bin="$build/bin"
mkdir -p "$out"
times="$out/bench-times.txt"
: > "$times.tmp"
start=$(date +%s)
bench() {
    name="$1"; shift
    t0=$(date +%s)
    "$@"
    t1=$(date +%s)
    [ -n "$SEPAL_BENCH_PARSE_ONLY" ] && return 0
    printf '%-12s %5d s\n' "$name" $((t1 - t0)) | tee -a "$times.tmp" >&2
}
bench factor      "$bin/sepal-bench-factor" all --out "$out"
bench runtime     "$bin/sepal-bench-runtime" --out "$out" --build "$build"
bench extremes    "$bin/sepal-bench-extremes" --out "$out"
bench tradeoff    "$bin/sepal-bench-tradeoff" --out "$out"
bench cost        "$bin/sepal-bench-cost" --out "$out"
bench fidelity    "$bin/sepal-bench-fidelity" --out "$out"
bench ports       "$bin/sepal-bench-ports" --out "$out" --build "$(cd "$build" && pwd)"
bench database    "$bin/sepal-bench-database" --out "$out"
bench acquire     "$bin/sepal-bench-acquire" --out "$out"
bench sampling    "$bin/sepal-bench-sampling" all --out "$out"
bench ist         "$bin/sepal-bench-ist" --out "$out"
bench homomorphic "$bin/sepal-bench-homomorphic" --out "$out"
[ -n "$SEPAL_BENCH_PARSE_ONLY" ] && exit 0
printf '%-12s %5d s\n' total $(($(date +%s) - start)) | tee -a "$times.tmp" >&2
mv "$times.tmp" "$times"

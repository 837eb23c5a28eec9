#!/bin/sh
# What `make bench` runs: one line per benchmark program (build/bin/sepal-bench-<name>,
# from tests/bench/<name>.cpp). Usage: sh tests/bench/run.sh BUILD_DIR OUT_DIR
set -e
build="$1"; out="$2"; bin="$build/bin"
mkdir -p "$out"
"$bin/sepal-bench-factor" all --out "$out"
"$bin/sepal-bench-runtime" "$out" "$build"
"$bin/sepal-bench-extremes" "$out"
"$bin/sepal-bench-tradeoff" --out "$out"
"$bin/sepal-bench-ports" "$out" "$(cd "$build" && pwd)"
"$bin/sepal-bench-acquire" --out "$out"

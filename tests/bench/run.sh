#!/bin/sh
# What `make bench` runs: one line per benchmark program (build/bin/sepal-bench-<name>,
# from tests/bench/<name>.cpp). Usage: sh tests/bench/run.sh BUILD_DIR OUT_DIR
set -e
build="$1"; out="$2"; bin="$build/bin"
mkdir -p "$out"
"$bin/sepal-bench-factor" all --out "$out"
"$bin/sepal-bench-runtime" --out "$out" --build "$build"
"$bin/sepal-bench-extremes" --out "$out"
"$bin/sepal-bench-tradeoff" --out "$out"
"$bin/sepal-bench-cost" --out "$out"
"$bin/sepal-bench-fidelity" --out "$out"
"$bin/sepal-bench-ports" --out "$out" --build "$(cd "$build" && pwd)"
"$bin/sepal-bench-database" --out "$out"
"$bin/sepal-bench-acquire" --out "$out"
"$bin/sepal-bench-sampling" all --out "$out"
"$bin/sepal-bench-ist" --out "$out"
"$bin/sepal-bench-homomorphic" --out "$out"

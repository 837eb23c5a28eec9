#!/bin/sh
# What `make bench` runs: one line per benchmark program (build/bin/sepal-bench-<name>,
# from tests/bench/<name>.cpp). Usage: sh tests/bench/run.sh BUILD_DIR OUT_DIR
# Each line prints its wall time and its processor-seconds; OUT_DIR/bench-times.txt keeps them
# (the budget is 15 minutes on 2 cores), so a bench that grows shows up in the next run.
#
# Two phases. First the programs that are mostly timing (frames, set-up, binary sizes) run one
# at a time, and homomorphic, which fills both cores by itself. Then two lanes of programs
# run at once, each in its own process group: most of
# their work is arithmetic that leaves a core idle part of the time (one lane alone used 1.3
# to 1.8 of the 2 cores), and wherever they time something a user plans with (bake seconds,
# frame ms, sampler ns, planner seconds) they do it inside a BenchQuiet section
# (tests/bench/quiet.h), which stops the other lane meanwhile. A lane's per-program seconds
# in bench-times.txt are wall time shared with the other lane. Each lane's output (the tables
# the programs print) goes to OUT/bench-lane-a.log and -b.log; the JSON and markdown files
# are the same as ever.
# Internal: run.sh --lane NAME BUILD_DIR OUT_DIR runs one lane.
set -e
lane=""
if [ "$1" = "--lane" ]; then lane="$2"; shift 2; fi
build="$1"; out="$2"; bin="$build/bin"
mkdir -p "$out"
times="$out/bench-times.txt"
lanes="$out/.bench-lanes"
# Processor-seconds (user + system) of this shell's finished children, from the file the
# `times` builtin wrote (it must run in this shell: a subshell has no children of its own).
# Wall seconds move with the machine's state by a fifth or more within hours; processor-
# seconds show better what a change cut, and two lanes can at best halve their sum.
cpu_file="$out/.bench-cpu${lane:+.$lane}"
cpu_read() {
    awk 'NR == 2 { split($1, u, "m"); split($2, s, "m"); printf "%.2f", u[1] * 60 + u[2] + s[1] * 60 + s[2] }' "$cpu_file"
}
bench() {
    name="$1"; shift
    t0=$(date +%s)
    times > "$cpu_file"; c0=$(cpu_read)
    "$@"
    t1=$(date +%s)
    times > "$cpu_file"; c1=$(cpu_read)
    # A program that died inside a quiet section must not leave the other lane stopped.
    resume_lanes
    [ -n "$SEPAL_BENCH_PARSE_ONLY" ] && return 0
    cpu=$(awk -v a="$c0" -v b="$c1" 'BEGIN { printf "%d", b - a + 0.5 }')
    line=$(printf '%-12s %5d s %5d cpu-s%s' "$name" $((t1 - t0)) "$cpu" "${lane:+ (lane $lane)}")
    echo "$line" >> "$times.$lane.tmp"
    # A lane's own output goes to its log; its timing lines also reach the terminal (fd 3).
    if [ -n "$lane" ]; then echo "$line" >&3; else echo "$line" >&2; fi
}
resume_lanes() {
    [ -n "$SEPAL_BENCH_LANES" ] && [ -f "$SEPAL_BENCH_LANES" ] || return 0
    for g in $(cat "$SEPAL_BENCH_LANES"); do kill -CONT -"$g" 2>/dev/null || true; done
}
# Split so that the lanes take about as long (each program's seconds: docs/performance.md).
lane_a() {
    bench tradeoff    "$bin/sepal-bench-tradeoff" --out "$out"
    bench fidelity    "$bin/sepal-bench-fidelity" --out "$out"
    bench acquire     "$bin/sepal-bench-acquire" --out "$out"
    bench factor      "$bin/sepal-bench-factor" all --out "$out"
    bench rgb565      "$bin/sepal-bench-fidelity" --rgb565 --out "$out"
}
lane_b() {
    bench extremes    "$bin/sepal-bench-extremes" --out "$out"
    bench ist         "$bin/sepal-bench-ist" --out "$out"
    bench sampling    "$bin/sepal-bench-sampling" all --out "$out"
    bench database    "$bin/sepal-bench-database" --out "$out"
    bench light-range "$bin/sepal-bench-fidelity" --ranges --out "$out"
}
# A finished lane leaves the list (in place, under the lock: a reused process-group id must
# never be stopped), and resumes the others.
leave_lanes() {
    resume_lanes
    rm -f "$cpu_file"
    flock "$SEPAL_BENCH_LANES" sh -c 'grep -v "^$1\$" "$0" > "$0.tmp"; cat "$0.tmp" > "$0"; rm -f "$0.tmp"' \
        "$SEPAL_BENCH_LANES" $$ || true
}
if [ -n "$lane" ]; then
    trap leave_lanes EXIT
    # The lane's process group (setsid made this shell its leader), for the others' quiet sections.
    echo $$ >> "$SEPAL_BENCH_LANES.new"
    while [ ! -f "$SEPAL_BENCH_LANES" ]; do sleep 0.1; done  # until both lanes are listed
    "lane_$lane"
    exit 0
fi

: > "$times..tmp"
start=$(date +%s)
# Phase 1: one at a time.
bench runtime     "$bin/sepal-bench-runtime" --out "$out" --build "$build"
bench cost        "$bin/sepal-bench-cost" --out "$out"
bench ports       "$bin/sepal-bench-ports" --out "$out" --build "$(cd "$build" && pwd)"
# homomorphic fills both cores alone (77 processor-seconds in 52 s), so it runs by itself: in
# a lane it made that lane 78 s longer than the other (each program's seconds:
# docs/performance.md).
bench homomorphic "$bin/sepal-bench-homomorphic" --out "$out"
# Phase 2: two lanes at once.
if [ -n "$SEPAL_BENCH_PARSE_ONLY" ]; then
    lane_a
    lane_b
    rm -f "$cpu_file" "$times..tmp"
    exit 0
fi
rm -f "$lanes" "$lanes.new" "$times.a.tmp" "$times.b.tmp"
export SEPAL_BENCH_LANES="$lanes"
echo "bench: two lanes from here; their output goes to $out/bench-lane-a.log and -b.log" >&2
exec 3>&2
setsid -w sh "$0" --lane a "$build" "$out" > "$out/bench-lane-a.log" 2>&1 & pa=$!
setsid -w sh "$0" --lane b "$build" "$out" > "$out/bench-lane-b.log" 2>&1 & pb=$!
# An interrupted make must not leave the lanes running in their own sessions.
stop_lanes() {
    for g in $(cat "$lanes" "$lanes.new" 2>/dev/null); do kill -CONT -"$g" 2>/dev/null; kill -TERM -"$g" 2>/dev/null; done
}
trap 'stop_lanes; exit 130' INT TERM
tries=0
while [ "$(cat "$lanes.new" 2>/dev/null | wc -l)" -lt 2 ]; do
    tries=$((tries + 1))
    if [ $tries -gt 300 ]; then echo "bench: the lanes did not start" >&2; stop_lanes; exit 1; fi
    sleep 0.1
done
mv "$lanes.new" "$lanes"
ra=0; rb=0
wait $pa || ra=$?
wait $pb || rb=$?
trap - INT TERM
rm -f "$lanes" "$lanes.new"
cat "$times.a.tmp" "$times.b.tmp" >> "$times..tmp" 2>/dev/null || true
rm -f "$times.a.tmp" "$times.b.tmp"
if [ $ra -ne 0 ] || [ $rb -ne 0 ]; then
    echo "bench: lane a exited $ra, lane b exited $rb (the end of each lane's log:)" >&2
    tail -n 5 "$out/bench-lane-a.log" "$out/bench-lane-b.log" >&2
    rm -f "$cpu_file"
    exit 1
fi
times > "$cpu_file"
printf '%-12s %5d s %5.0f cpu-s\n' total $(($(date +%s) - start)) "$(cpu_read)" | tee -a "$times..tmp" >&2
rm -f "$cpu_file"
mv "$times..tmp" "$times"

#!/bin/sh
# make fuzz: runs each harness (build DIR/bin/fuzz-NAME) for SECONDS on its corpus, seeded
# from fixtures/: fixtures/fuzz-seeds/NAME and fixtures/fuzz/NAME (regression inputs), plus
# the heads of the Cornell files (cornell) and the golden PNGs without their signature (png).
# Prints one line per harness (exec count, corpus size, result) and writes them to
# DIR/report.txt; crashers go to DIR/crashes/NAME/. Exit status 1 when any harness failed.
#   usage: tests/fuzz/run.sh DIR SECONDS TIMEOUT NAME...
dir="$1"; seconds="$2"; timeout="$3"; shift 3
report="$dir/report.txt"
: > "$report"
status=0
for name in "$@"; do
  corpus="$dir/corpus/$name"; crashes="$dir/crashes/$name"; log="$dir/log/$name.txt"
  mkdir -p "$corpus" "$crashes" "$dir/log"
  for f in fixtures/fuzz-seeds/"$name"/* fixtures/fuzz/"$name"/*; do
    [ -f "$f" ] && cp "$f" "$corpus/seed-$(basename "$f")"
  done
  case "$name" in
    cornell) for f in fixtures/cornell/*.brdf; do head -c 8192 "$f" > "$corpus/seed-$(basename "$f")"; done ;;
    png) for f in fixtures/golden/*.png; do tail -c +9 "$f" > "$corpus/seed-$(basename "$f")"; done ;;
  esac


  limit="$timeout"
  # ASan's default for allocations is 3 GB; libFuzzer's RSS limit 2 GB: the readers' own
  # bounds (images up to 16384^2, 2 GB files) must keep inside them.
  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 ASAN_OPTIONS=detect_leaks=1 \
    "$dir/bin/fuzz-$name" -max_total_time="$seconds" -timeout="$limit" -rss_limit_mb=2560 \
      -print_final_stats=1 -artifact_prefix="$crashes/" "$corpus" > "$log" 2>&1
  rc=$?
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
  files=$(ls "$corpus" | wc -l)
  found=$(ls "$crashes" | wc -l)
  if [ "$rc" = 0 ] && [ "$found" = 0 ]; then result=ok; else result="FAILED (exit $rc, $found inputs in $crashes, log $log)"; status=1; fi
  line=$(printf '%-12s %10s execs in %ss, corpus %5s files: %s' "$name" "${runs:-?}" "$seconds" "$files" "$result")
  echo "$line" | tee -a "$report"
done
exit $status

#!/bin/sh
# Runs a doctest binary, keeps its log next to it, and ends with the plain closing line
# "tests: N passed, N failed" that CI reads. Exit status is the runner's.
bin="$1"; shift
log="$(dirname "$bin")/../test.log"
status_file=$(mktemp)
{ "$bin" "$@" 2>&1; echo $? > "$status_file"; } | tee "$log"
status=$(cat "$status_file"); rm -f "$status_file"
line=$(grep -E '^\[doctest\] test cases:' "$log" | tail -n 1)
passed=$(echo "$line" | sed -nE 's/.*\| *([0-9]+) passed.*/\1/p')
failed=$(echo "$line" | sed -nE 's/.*\| *([0-9]+) failed.*/\1/p')
if [ -n "$passed" ]; then
  echo "tests: ${passed} passed, ${failed:-0} failed"
else
  echo "tests: runner printed no summary (exit status $status)"
  [ "$status" = 0 ] && status=1
fi
exit "$status"

#!/bin/sh
# make check-functions: no function in offline/ or runtime/ over 150 lines (named phases read
# better than one long body). The count is the body's lines (tests/function_length.awk).
set -eu
cd "$(dirname "$0")/.."
limit=150
bad=$(find offline runtime -name '*.cpp' | sort | xargs awk -v LIMIT=$limit -f tests/function_length.awk)
if [ -n "$bad" ]; then
    echo "check-functions: over $limit lines (split into named phases):"
    echo "$bad" | sed 's/^/  /'
    exit 1
fi

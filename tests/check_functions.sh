#!/bin/sh
# make check-functions: no function in offline/ or runtime/ over 150 lines (named phases read
# better than one long body). The functions listed below are over it today and may not grow;
# split one and delete its line. The count is the body's lines (tests/function_length.awk).
set -eu
cd "$(dirname "$0")/.."
limit=150
allowed='
offline/bake/bake.cpp bake 338
offline/cli/cmd_render.cpp run_render 188
offline/database/database.cpp BrdfDatabase::open 216
offline/sampling/factored_fit.cpp fit_one 227
runtime/src/asset.cpp sepal_asset_parse 297
runtime/src/emulate_gles1.cpp emulate_object 213
'
bad=$(find offline runtime -name '*.cpp' | sort | xargs awk -v LIMIT=$limit -f tests/function_length.awk |
    while IFS= read -r line; do
        file=${line%%:*}
        n=$(echo "$line" | sed 's/^[^:]*:[0-9]*: \([0-9]*\) lines: .*/\1/')
        ok=0
        for name in $(echo "$allowed" | awk -v f="$file" '$1 == f { print $2 ":" $3 }'); do
            fn=${name%:*}; max=${name##*:}
            case "$line" in *"$fn("*) [ "$n" -le "$max" ] && ok=1 ;; esac
        done
        [ $ok = 1 ] || echo "  $line"
    done)
if [ -n "$bad" ]; then
    echo "check-functions: over $limit lines (split into named phases, or a listed one grew):"
    echo "$bad"
    exit 1
fi

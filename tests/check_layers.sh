#!/bin/sh
# make check-layers: the include graph between folders of runtime/, offline/ and ports/ has
# no loop, and dependencies point one way (docs/architecture.md):
#   runtime   -> runtime only
#   offline/* -> offline/*, runtime; offline/cli (the tools) also ports/common, ports/headless
#   ports/*   -> ports/*, runtime
# and the offline-only libraries (tinygltf, Eigen, nlohmann-json, CLI11) stay out of runtime/ and ports/.
# A quoted include names its folder by its first component ("sepal/..." is the runtime's API,
# "brdf/..." offline/brdf, "headless/..." ports/headless); one without a folder is its own.
set -eu
cd "$(dirname "$0")/.."
edges=$(mktemp)
trap 'rm -f "$edges"' EXIT
# One grep over every file, one awk to name each edge: "from to file include".
find runtime offline ports -name '*.cpp' -o -name '*.h' | sort | xargs grep -H '^[[:space:]]*#[[:space:]]*include[[:space:]]*"[^"]*/' |
awk -v offline="$(ls offline | tr '\n' ' ')" -v ports="$(ls ports | tr '\n' ' ')" '
    BEGIN { n = split(offline, a, " "); for (i = 1; i <= n; ++i) off[a[i]] = 1
            n = split(ports, a, " "); for (i = 1; i <= n; ++i) prt[a[i]] = 1 }
    {
        file = substr($0, 1, index($0, ":") - 1)
        inc = $0; sub(/^[^"]*"/, "", inc); sub(/".*/, "", inc)
        split(file, p, "/"); from = (p[1] == "runtime") ? "runtime" : p[1] "/" p[2]
        top = inc; sub(/\/.*/, "", top)
        if (top == "sepal") to = "runtime"
        else if (top in off) to = "offline/" top
        else if (top in prt) to = "ports/" top
        else next  # generated text (shaders/), third_party
        if (from != to) print from, to, file, inc
    }' > "$edges"
bad=$(awk '
    { ok = 0 }
    $1 == "runtime" { ok = ($2 == "runtime") }
    $1 ~ /^offline\// { ok = ($2 ~ /^offline\// || $2 == "runtime" ||
                             ($1 == "offline/cli" && ($2 == "ports/common" || $2 == "ports/headless"))) }
    $1 ~ /^ports\// { ok = ($2 ~ /^ports\// || $2 == "runtime") }
    !ok { print "  " $3 " includes \"" $4 "\": " $1 " may not depend on " $2 }' "$edges")
if [ -n "$bad" ]; then
    echo "check-layers: dependencies against the layering (tools -> offline -> runtime; ports -> runtime):"
    echo "$bad"
    exit 1
fi
third=$(grep -rnE '^[[:space:]]*#[[:space:]]*include[[:space:]]*[<"](tiny_gltf\.h|mesh/tiny_gltf\.h|Eigen/|nlohmann/|CLI/)' runtime ports || true)
if [ -n "$third" ]; then
    echo "check-layers: offline-only libraries included from runtime/ or ports/ (docs/architecture.md):"
    echo "$third" | sed 's/^/  /'
    exit 1
fi
if ! loop=$(cut -d' ' -f1-2 "$edges" | sort -u | tsort 2>&1 >/dev/null) || [ -n "$loop" ]; then
    echo "check-layers: the folders include each other in a loop (each must sit above the other):"
    members=$(echo "$loop" | sed -n 's/^tsort: \([^ ]*\)$/\1/p' | tr '\n' ' ')
    awk -v m=" $members" 'index(m, " " $1 " ") && index(m, " " $2 " ") { print "  " $1 " -> " $2 "  (" $3 ": " $4 ")" }' "$edges" | sort -u -k1,3
    exit 1
fi

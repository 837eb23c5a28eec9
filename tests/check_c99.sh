#!/bin/sh
# make check-c99: every public header compiles as C99 (-pedantic -Werror), and so does the
# usage block each opens with. A usage block is the run of "//   " lines (three spaces or
# more) after "// Usage"; its "#include" lines go to file scope, "$ " lines are shell and
# skipped, the rest becomes the body of a C function. The names a block uses without
# declaring them are the program's own data, declared below (a block's own declarations
# shadow them).
set -eu
cd "$(dirname "$0")/.."
CC=${CC:-cc}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/sepal"
cp ports/headless/sepal_headless.h "$tmp/sepal/"   # where make install puts it
flags="-std=c99 -pedantic -Wall -Wextra -Werror -Iruntime/include -Iports -I$tmp -x c -fsyntax-only"

printf '#include "sepal/sepal.h"\n#include "headless/sepal_headless.h"\nint main(void) { return SEPAL_VERSION_MAJOR; }\n' |
    $CC $flags - || { echo "check-c99: runtime/include/sepal/*.h or the headless port's header is not C99 (above)"; exit 1; }

status=0
blocks=0
for h in runtime/include/sepal/*.h ports/headless/sepal_headless.h; do
    awk '/^\/\/ Usage/ { u = 1; next } u && /^\/\/   / { print substr($0, 6); next } u { exit }' "$h" > "$tmp/block"
    [ -s "$tmp/block" ] || continue
    blocks=$((blocks + 1))
    src="$tmp/$(basename "$h" .h).c"
    {
        printf '#include <stdio.h>\n#include <stdlib.h>\n#include <string.h>\n'
        printf '#include "sepal/sepal.h"\n#include "sepal/sepal_headless.h"\n'
        grep '^#include' "$tmp/block" || true
        cat <<'GIVEN'
/* The program's own data and functions, as the usage blocks take them. */
extern const void* bytes; extern size_t size;
extern sepal_error err; extern sepal_caps caps; extern sepal_mesh mesh; extern sepal_scene scene;
extern sepal_draw_stats stats; extern sepal_material mat; extern const sepal_light lights[2];
extern float view[16], proj[16]; extern int width, height; extern uint8_t pixels[];
enum { W = 64, H = 64 };
extern const float clip_positions[]; extern const float attributes[]; extern int n_vertices;
extern const uint16_t idx[]; extern int n; extern int my_state;
void shade(void* user, int x, int y, float depth, const float* varyings);
extern float wo[3]; extern float L;
struct engine_vertex { float p[3]; uint32_t color; float n[3], t[4], uv[2]; };
extern const struct engine_vertex engine_vertices[]; extern const uint16_t engine_indices[];
extern int vertex_count, index_count;
float Li(const float wi[3]); float f(const float wi[3], const float wo[3]);
GIVEN
        printf 'int usage_block(void);\nint usage_block(void) {\n#line 1 "%s usage block"\n' "$h"
        grep -v '^#include' "$tmp/block" | grep -v '^\$ ' || true
        printf '    return 0;\n}\n'
    } > "$src"
    if ! $CC $flags "$src"; then
        echo "check-c99: the usage block of $h is not C99 (above; line 1 is the line after '// Usage')"
        status=1
    fi
done
[ "$blocks" -ge 8 ] || { echo "check-c99: found $blocks usage blocks, expected every header's"; exit 1; }
exit $status

// Messages that said something untrue or nothing: bake-scene's unknown top-level keys, ist
// render's blend maps of -1, the camera message for an OBJ too large to frame, and flags a
// command does not have.
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "cli/cli.h"
#include "test_util.h"
#include "util/image.h"
#include "util/io.h"

namespace {

bool contains(const std::string& s, const std::string& what) { return s.find(what) != std::string::npos; }

void put(const std::string& path, const std::string& text) {
    std::string err;
    REQUIRE_MESSAGE(sepal::write_file_atomic(path, text.data(), text.size(), &err), err);
}

}  // namespace

TEST_CASE("bake-scene: an unknown top-level key is refused, naming it") {
    const std::string dir = sepal_test::temp_dir();
    put(dir + "/scene.json",
        "{\"materials\": [{\"name\": \"m\", \"spec\": \"lambert\"}],"
        " \"view\": [{\"name\": \"hall\", \"flags\": \"--mesh torus\"}]}");
    std::string out;
    CHECK(sepal_test::run_cmd("bake-scene", {dir + "/scene.json", "-o", dir + "/out"}, &out) == 2);
    CHECK_MESSAGE(contains(out, "unknown top-level key \"view\" (known: materials, views)"), out);
    put(dir + "/views.json",
        "{\"materials\": [{\"name\": \"m\", \"spec\": \"lambert\"}],"
        " \"views\": [{\"name\": \"hall\", \"flag\": \"--mesh torus\"}]}");
    CHECK(sepal_test::run_cmd("bake-scene", {dir + "/views.json", "-o", dir + "/out"}, &out) == 2);
    CHECK_MESSAGE(contains(out, "views[0]: unknown key \"flag\""), out);
}

TEST_CASE("ist render: a blend map of negative weights is refused, naming the map and texel") {
    const std::string dir = sepal_test::temp_dir();
    const std::string svbrdf = dir + "/card", tree = dir + "/card.tree";
    std::string out, err;
    REQUIRE_MESSAGE(sepal_test::run_cmd("ist", {"generate", "-o", svbrdf, "--size", "12", "--materials", "2"}, &out) == 0,
                    out);
    REQUIRE_MESSAGE(
        sepal_test::run_cmd("ist", {"decompose", svbrdf, "-o", tree, "--terms", "1", "--res", "8"}, &out) == 0, out);
    sepal::Image blend;
    REQUIRE_MESSAGE(sepal::read_image(tree + "/blend/0.pfm", &blend, &err), err);
    for (float& w : blend.data) w = -1.0f;
    REQUIRE(sepal::write_pfm(tree + "/blend/0.pfm", blend, &err));
    CHECK(sepal_test::run_cmd("ist", {"render", tree, "-o", dir + "/r.png", "--backend", "cpu", "--size", "16x16"},
                              &out) == 2);
    CHECK_MESSAGE(contains(out, "blend map 0 at texel (0, 0) has weight -1"), out);
    CHECK(!contains(out, "--cap"));
}

TEST_CASE("render: an OBJ too large to frame says so, not that the camera's eye equals its target") {
    const std::string dir = sepal_test::temp_dir();
    // A unit triangle 1e30 along y: the camera placed 3.2 radii back along -y rounds onto it.
    put(dir + "/huge.obj", "v 0 1e30 0\nv 1 1e30 0\nv 0 1e30 1\nf 1 2 3\n");
    std::string out;
    CHECK(sepal_test::run_cmd("render", {"lambert", "--mesh", dir + "/huge.obj", "--size", "16x16", "-o",
                                         dir + "/r.png"},
                              &out) == 2);
    CHECK(!contains(out, "eye equals target"));
    CHECK(!contains(out, "up is parallel"));
    CHECK_MESSAGE(contains(out, "huge.obj: the mesh's bounding sphere"), out);
    CHECK(contains(out, "give --camera"));
}

// Issue 21's command-line classes of bad input, one regression test each: numbers are range
// checked before conversion (no wraparound), JSON numbers that overflow are refused, a failed
// command leaves none of its outputs, and the messages name what would be accepted.
#include <doctest/doctest.h>

#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "cli/cli.h"
#include "test_util.h"

namespace {

bool exists(const std::string& path) {
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (f) std::fclose(f);
    return f != nullptr;
}

void write_text(const std::string& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

int run(sepal::CommandFn fn, const std::vector<std::string>& args, std::string* out) {
    return sepal_test::run_cmd(fn, args, out);
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

}  // namespace

TEST_CASE("bad input, class 5: --max-passes beyond int range is refused, not wrapped") {
    const std::string dir = sepal_test::temp_dir();
    std::string out;
    for (const char* v : {"4294967297", "2147483648", "0", "-1", "1e3"}) {
        CAPTURE(v);
        CHECK(run(sepal::cmd_bake, {"lambert", "--max-passes", v, "-o", dir + "/a.sepal"}, &out) == 2);
        CHECK(contains(out, "--max-passes"));
    }
    CHECK_FALSE(exists(dir + "/a.sepal"));
}

TEST_CASE("bad input, classes 2 and 3: scene JSON numbers out of range or overflowing are refused") {
    const std::string dir = sepal_test::temp_dir();
    std::string out;
    const char* cases[][2] = {
        {R"({"materials":[{"name":"a","spec":"lambert","max_passes":1e12}]})", "max_passes"},
        {R"({"materials":[{"name":"a","spec":"lambert","max_passes":2147483648}]})", "max_passes"},
        {R"({"materials":[{"name":"a","spec":"lambert","bits":1e30}]})", "bits"},
        {R"({"materials":[{"name":"a","spec":"lambert","max_error":1e4294967295}]})", "overflow"},
        {R"({"materials":[{"name":"a","spec":"lambert","max_error":0.1e-2147483648}]})", ""},
        {R"({"materials":[{"name":"a","name":"b","spec":"lambert"}]})", "duplicate key"},
    };
    for (const auto& c : cases) {
        CAPTURE(c[0]);
        write_text(dir + "/s.json", c[0]);
        const int code = run(sepal::cmd_bake_scene, {dir + "/s.json", "-o", dir + "/out"}, &out);
        CHECK(code != 0);
        CHECK(contains(out, c[1]));
    }
}

TEST_CASE("bad input, class 8: a command that fails part-way leaves none of its outputs") {
    const std::string dir = sepal_test::temp_dir();
    std::string out;
    // render: the PNG is written, then the PFM cannot be.
    CHECK(run(sepal::cmd_render, {"lambert", "--size", "16x16", "-o", dir + "/r.png", "--float", "/nonexistent/x.pfm"},
              &out) == 2);
    CHECK_FALSE(exists(dir + "/r.png"));
    // bake: the asset is written, then the export folder cannot be.
    CHECK(run(sepal::cmd_bake, {"lambert", "--param", "gs-half", "--res", "8", "--terms", "1", "-o", dir + "/b.sepal",
                                "--export", "/proc/sepal-cannot"},
              &out) == 2);
    CHECK_FALSE(exists(dir + "/b.sepal"));
    // diff: a heatmap named .txt would hold PNG bytes: refused before anything is written.
    REQUIRE(run(sepal::cmd_render, {"lambert", "--size", "16x16", "-o", dir + "/a.png"}, &out) == 0);
    CHECK(run(sepal::cmd_diff, {dir + "/a.png", dir + "/a.png", "--heatmap", dir + "/h.txt"}, &out) == 2);
    CHECK(contains(out, "name them .png"));
    CHECK_FALSE(exists(dir + "/h.txt"));
    // ... and with the heatmap written, a sheet that cannot be takes the heatmap with it.
    CHECK(run(sepal::cmd_diff, {dir + "/a.png", dir + "/a.png", "--heatmap", dir + "/h.png", "--sheet",
                                "/nonexistent/s.png"},
              &out) == 2);
    CHECK_FALSE(exists(dir + "/h.png"));
}

TEST_CASE("bad input, class 10: scene flags refuse what they cannot draw, and say what they accept") {
    const std::string dir = sepal_test::temp_dir();
    std::string out;
    CHECK(run(sepal::cmd_render, {"lambert", "--size", "16x16", "--background", "-1,-1,-1", "-o", dir + "/b.png"},
              &out) == 2);
    CHECK(contains(out, "each channel >= 0"));
    CHECK_FALSE(exists(dir + "/b.png"));
    CHECK(run(sepal::cmd_render, {"lambert", "--size", "16x16", "--fov", "1", "-o", dir + "/f.png"}, &out) == 2);
    CHECK(contains(out, "both ends excluded"));
}

TEST_CASE("bad input, class 1: MERL header dims whose product overflows int64 are reported, not wrapped") {
    const std::string dir = sepal_test::temp_dir();
    // Three dims of 2^31 - 1: their product (~9.9e27) overflows a signed 64-bit integer.
    std::string bytes(12, '\0');
    for (int k = 0; k < 3; ++k) {
        bytes[size_t(4 * k) + 0] = char(0xff);
        bytes[size_t(4 * k) + 1] = char(0xff);
        bytes[size_t(4 * k) + 2] = char(0xff);
        bytes[size_t(4 * k) + 3] = char(0x7f);
    }
    write_text(dir + "/big.binary", bytes);
    std::string out;
    CHECK(run(sepal::cmd_info, {dir + "/big.binary"}, &out) == 2);
    CHECK(contains(out, "2147483647 x 2147483647 x 2147483647"));
    CHECK(contains(out, "(product about 9.9e+27)"));
}

TEST_CASE("bad input, class 6: a factorization larger than the machine is refused before it allocates") {
    const std::string dir = sepal_test::temp_dir();
    std::string out;
    CHECK(run(sepal::cmd_bake, {"lambert", "--param", "gs-half", "--res", "256", "--terms", "1", "--method", "acls",
                                "--max-memory", "1e30", "-o", dir + "/m.sepal"},
              &out) == 2);
    CHECK(contains(out, "MB of memory"));
    CHECK_FALSE(exists(dir + "/m.sepal"));
}

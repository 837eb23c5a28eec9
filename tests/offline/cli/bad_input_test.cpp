// The command-line classes of bad input, one regression test each: numbers are range
// checked before conversion (no wraparound), JSON numbers that overflow are refused, a failed
// command leaves none of its outputs, and the messages name what would be accepted.
#include <doctest/doctest.h>

#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "cli/cli.h"
#include "sepal/sepal_asset.h"
#include "test_util.h"

namespace {

bool exists(const std::string& path) {
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (f) std::fclose(f);
    return f != nullptr;
}

void write_text(const std::string& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

int run(const char* command, const std::vector<std::string>& args, std::string* out) {
    return sepal_test::run_cmd(command, args, out);
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

}  // namespace

TEST_CASE("bad input, class 5: --max-passes beyond int range is refused, not wrapped") {
    const std::string dir = sepal_test::temp_dir();
    std::string out;
    for (const char* v : {"4294967297", "2147483648", "0", "-1", "1e3"}) {
        CAPTURE(v);
        CHECK(run("bake", {"lambert", "--max-passes", v, "-o", dir + "/a.sepal"}, &out) == 2);
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
        const int code = run("bake-scene", {dir + "/s.json", "-o", dir + "/out"}, &out);
        CHECK(code != 0);
        CHECK(contains(out, c[1]));
    }
}

TEST_CASE("bad input, class 8: a command that fails part-way leaves none of its outputs") {
    const std::string dir = sepal_test::temp_dir();
    std::string out;
    // render: the PNG is written, then the PFM cannot be.
    CHECK(run("render", {"lambert", "--size", "16x16", "-o", dir + "/r.png", "--float", "/nonexistent/x.pfm"},
              &out) == 2);
    CHECK_FALSE(exists(dir + "/r.png"));
    // bake: the asset is written, then the export folder cannot be.
    CHECK(run("bake", {"lambert", "--param", "gs-half", "--res", "8", "--terms", "1", "-o", dir + "/b.sepal",
                                "--export", "/proc/sepal-cannot"},
              &out) == 2);
    CHECK_FALSE(exists(dir + "/b.sepal"));
    // diff: a heatmap named .txt would hold PNG bytes: refused before anything is written.
    REQUIRE(run("render", {"lambert", "--size", "16x16", "-o", dir + "/a.png"}, &out) == 0);
    CHECK(run("diff", {dir + "/a.png", dir + "/a.png", "--heatmap", dir + "/h.txt"}, &out) == 2);
    CHECK(contains(out, "name them .png"));
    CHECK_FALSE(exists(dir + "/h.txt"));
    // ... and with the heatmap written, a sheet that cannot be takes the heatmap with it.
    CHECK(run("diff", {dir + "/a.png", dir + "/a.png", "--heatmap", dir + "/h.png", "--sheet",
                                "/nonexistent/s.png"},
              &out) == 2);
    CHECK_FALSE(exists(dir + "/h.png"));
}

TEST_CASE("bad input, class 10: scene flags refuse what they cannot draw, and say what they accept") {
    const std::string dir = sepal_test::temp_dir();
    std::string out;
    CHECK(run("render", {"lambert", "--size", "16x16", "--background", "-1,-1,-1", "-o", dir + "/b.png"},
              &out) == 2);
    CHECK(contains(out, "each channel >= 0"));
    CHECK_FALSE(exists(dir + "/b.png"));
    CHECK(run("render", {"lambert", "--size", "16x16", "--fov", "1", "-o", dir + "/f.png"}, &out) == 2);
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
    CHECK(run("info", {dir + "/big.binary"}, &out) == 2);
    CHECK(contains(out, "2147483647 x 2147483647 x 2147483647"));
    CHECK(contains(out, "(product about 9.9e+27)"));
}

TEST_CASE("bad input, class 6: a factorization larger than the machine is refused before it allocates") {
    const std::string dir = sepal_test::temp_dir();
    std::string out;
    CHECK(run("bake", {"lambert", "--param", "gs-half", "--res", "256", "--terms", "1", "--method", "acls",
                                "--max-memory", "1e30", "-o", dir + "/m.sepal"},
              &out) == 2);
    CHECK(contains(out, "MB of memory"));
    CHECK_FALSE(exists(dir + "/m.sepal"));
}

TEST_CASE("bad input, class 10: OBJ and spec messages say what is wrong") {
    const std::string dir = sepal_test::temp_dir();
    std::string out;
    write_text(dir + "/empty.obj", "");
    CHECK(run("render", {"lambert", "--size", "16x16", "--mesh", dir + "/empty.obj", "-o", dir + "/e.png"},
              &out) == 2);
    CHECK_MESSAGE(contains(out, "the file is empty"), out);  // was "text or info is NULL"
    write_text(dir + "/big.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 2147483648\n");
    CHECK(run("render", {"lambert", "--size", "16x16", "--mesh", dir + "/big.obj", "-o", dir + "/b.png"},
              &out) == 2);
    CHECK_MESSAGE(contains(out, "position index 2147483648 out of range"), out);  // was shown as 214748364
    write_text(dir + "/neg.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -99999999999999999999\n");
    CHECK(run("render", {"lambert", "--size", "16x16", "--mesh", dir + "/neg.obj", "-o", dir + "/n.png"},
              &out) == 2);
    CHECK_MESSAGE(contains(out, "position index -99999999999999999999 out of range"), out);
    CHECK(run("info", {"cornell:garnet"}, &out) == 2);
    CHECK_MESSAGE(contains(out, "unknown BRDF model 'cornell'"), out);  // was "parameter 'garnet' has no '=value'"
    CHECK_FALSE(exists(dir + "/e.png"));
}

TEST_CASE("bad input, class 9: large renders and scene bakes say so before they start") {
    const std::string dir = sepal_test::temp_dir();
    std::string out;
    // 1449 x 1449 is just over 2 Mpixels: announced on stderr (progress follows on a terminal).
    CHECK(run("render", {"lambert", "--size", "1449x1449", "--float", dir + "/big.pfm"}, &out) == 0);
    CHECK_MESSAGE(contains(out, "1449x1449 is 2.1 Mpixels"), out);
    CHECK(run("render", {"lambert", "--size", "64x64", "--float", dir + "/small.pfm"}, &out) == 0);
    CHECK_FALSE(contains(out, "Mpixels"));
    // Each material of a scene is announced before its search (which can take a minute).
    write_text(dir + "/s.json", R"({"materials":[{"name":"a","spec":"lambert","param":"gs-half","res":8,"terms":1,)"
                                R"("method":"nmf"}]})");
    CHECK(run("bake-scene", {dir + "/s.json", "-o", dir + "/out"}, &out) == 0);
    CHECK_MESSAGE(contains(out, "baking a (1 of 1)"), out);
}

TEST_CASE("bad input, class 10: PNG messages give the size or where the file is cut") {
    const std::string dir = sepal_test::temp_dir();
    std::string out;
    REQUIRE(run("render", {"lambert", "--size", "16x16", "-o", dir + "/a.png"}, &out) == 0);
    std::ifstream in(dir + "/a.png", std::ios::binary);
    const std::string png((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    write_text(dir + "/cut.png", png.substr(0, 30));
    CHECK(run("diff", {dir + "/a.png", dir + "/cut.png"}, &out) == 2);
    CHECK_MESSAGE(contains(out, "truncated PNG: chunk 'IHDR' at byte 8 needs 25 bytes, the file has 22"), out);
    // A 20000 x 20000 header (width and height at bytes 16..23, then the IHDR's CRC).
    std::string big = png;
    const unsigned char side[4] = {0x00, 0x00, 0x4e, 0x20};  // 20000
    for (int k = 0; k < 4; ++k) big[size_t(16 + k)] = char(side[k]), big[size_t(20 + k)] = char(side[k]);
    const uint32_t crc = sepal_crc32(0, big.data() + 12, 17);
    for (int k = 0; k < 4; ++k) big[size_t(29 + k)] = char(crc >> (24 - 8 * k));
    write_text(dir + "/big.png", big);
    CHECK(run("diff", {dir + "/a.png", dir + "/big.png"}, &out) == 2);
    CHECK_MESSAGE(contains(out, "PNG size 20000x20000 out of range 1..16384"), out);  // was "unknown image type"
}

TEST_CASE("bad input: --size sides are range checked before they become ints (no wraparound)") {
    const std::string dir = sepal_test::temp_dir();
    std::string out;
    // sscanf's %d took 4294967297 as 1: a 1x1 render, exit 0.
    for (const char* v : {"4294967297x1", "1x4294967297", "8193x1", "0x5", "5x", "x5", "5x5x", " 5x5"}) {
        CAPTURE(v);
        CHECK(run("render", {"lambert", "--size", v, "-o", dir + "/s.png"}, &out) == 2);
        CHECK(contains(out, "sides 1..8192"));
    }
    CHECK_FALSE(exists(dir + "/s.png"));
    CHECK(run("render", {"lambert", "--size", "8x4", "-o", dir + "/s.png"}, &out) == 0);
}

TEST_CASE("bad input, class 10: bake-scene names the member, its value and range, on stderr") {
    const std::string dir = sepal_test::temp_dir();
    write_text(dir + "/s.json", R"({"materials":[{"name":"a","spec":"lambert","res":[0]}]})");
    std::FILE* out = std::tmpfile();
    std::FILE* err = std::tmpfile();
    REQUIRE((out && err));
    CHECK(sepal::run_command("bake-scene", {dir + "/s.json", "-o", dir + "/out"}, sepal::CommandIO{out, err}) == 1);
    auto text = [](std::FILE* f) {
        std::string s(size_t(std::ftell(f)), '\0');
        std::rewind(f);
        s.resize(std::fread(&s[0], 1, s.size(), f));
        std::fclose(f);
        return s;
    };
    const std::string o = text(out), e = text(err);
    CHECK_MESSAGE(contains(e, "materials[0].res[0]: 0 is outside 1..1048576"), e);
    CHECK_MESSAGE(contains(o, "FAILED (see stderr)"), o);
    CHECK_FALSE(contains(o, "outside"));
}

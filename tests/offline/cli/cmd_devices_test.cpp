// The device profiles on the command line: sepal info --devices, sepal bake --target
// gles1:PROFILE (a bad one refused naming the accepted profiles), and sepal render's
// warning when the context is weaker than the asset's profile.
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "bake/devices.h"
#include "test_util.h"

namespace {

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

}  // namespace

TEST_CASE("sepal info --devices lists every profile; a bad --target names the accepted ones") {
    std::string out;
    REQUIRE(sepal_test::run_cmd("info", {"--devices"}, &out) == 0);
    INFO(out);
    for (const sepal::DeviceProfile& p : sepal::device_profiles()) {
        CHECK(contains(out, std::string("\n") + p.name + " "));
        CHECK(contains(out, p.family));
    }
    CHECK(sepal_test::run_cmd("info", {"--devices", "blinn"}, &out) == 2);
    CHECK(contains(out, "--devices: takes no SPEC and no --models"));
    const std::string dir = sepal_test::temp_dir();
    for (const char* target : {"gles1:nope", "cpu:mali400", "gles3", "gles1:"}) {
        CAPTURE(target);
        CHECK(sepal_test::run_cmd("bake", {"blinn", "--target", target, "-o", dir + "/x.sepal"}, &out) == 2);
        CHECK(contains(out, std::string("--target ") + target));
        if (std::string(target).find(':') != std::string::npos)
            CHECK(contains(out, sepal::device_profile_names()));
    }
    CHECK_FALSE(sepal_test::run("test -e " + dir + "/x.sepal") == 0);
}

TEST_CASE("sepal render warns when the context is weaker than the asset's profile") {
    const std::string dir = sepal_test::temp_dir();
    std::string out;
    REQUIRE(sepal_test::run_cmd("bake", {"blinn", "--param", "gs-half", "--res", "8", "--terms", "1", "-o",
                                         dir + "/b.sepal"},
                                &out) == 0);
    for (const char* backend : {"gles1", "gles1-model"}) {
        CAPTURE(backend);
        REQUIRE(sepal_test::run_cmd("render", {dir + "/b.sepal", "--backend", backend, "--size", "32x32",
                                               "--framebuffer", "565", "-o", dir + "/r.png"},
                                    &out) == 0);
        CHECK(contains(out, "warning: the context is weaker than the device profile 'default' the asset was judged "
                            "for: framebuffer 5/6/5 bits (the profile's 8/8/8)"));
        REQUIRE(sepal_test::run_cmd("render", {dir + "/b.sepal", "--backend", backend, "--size", "32x32", "-o",
                                               dir + "/r.png"},
                                    &out) == 0);
        CHECK_FALSE(contains(out, "weaker"));
    }
    // Baked for a 565 profile: inspect names it, and the 565 pbuffer draws it without a warning.
    REQUIRE(sepal_test::run_cmd("bake", {"blinn", "--param", "gs-half", "--res", "8", "--terms", "1", "--target",
                                         "gles1:gles1-minimum", "-o", dir + "/m.sepal"},
                                &out) == 0);
    // gles1-minimum: framebuffer objects unknown, so every pass is judged rounded to 5/6/5.
    CHECK(contains(out, "device profile gles1-minimum: judged at 5/6/5 framebuffer bits (every pass rounded to them), "
                        "textures at or under 64"));
    REQUIRE(sepal_test::run_cmd("inspect", {dir + "/m.sepal"}, &out) == 0);
    CHECK(contains(out, "format 2.5"));  // the profile (2.4) and blinn's 16-bit diffuse profile (2.5)
    CHECK(contains(out, "device      judged for profile gles1-minimum: framebuffer 5/6/5 bits, textures at or under 64"));
    REQUIRE(sepal_test::run_cmd("render", {dir + "/m.sepal", "--backend", "gles1", "--size", "32x32", "--framebuffer",
                                           "565", "-o", dir + "/r.png"},
                                &out) == 0);
    CHECK_FALSE(contains(out, "weaker"));
}

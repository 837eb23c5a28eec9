// Regression tests for eleven command-line defects, one TEST_CASE each (named "cli defect
// N: ..."); each failed before its fix.
#include <doctest/doctest.h>

#include <fstream>
#include <string>

#include "brdf/brdf.h"
#include "spec/spec.h"
#include "cli/cli.h"
#include "util/image.h"
#include "util/io.h"
#include "util/json.h"
#include "sepal/sepal_format.h"
#include "sepal/sepal_version.h"
#include "test_util.h"

namespace {

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

int run(const char* command, const std::vector<std::string>& args, std::string* out) {
    const int code = sepal_test::run_cmd(command, args, out);
    INFO(*out);
    return code;
}

// A number printed after `label` in `text` (-1 when absent).
double number_after(const std::string& text, const std::string& label) {
    const size_t at = text.find(label);
    return at == std::string::npos ? -1 : std::atof(text.c_str() + at + label.size());
}

// The bit depth a PNG's IHDR declares.
int png_bit_depth(const std::string& path) {
    std::vector<uint8_t> b;
    REQUIRE(sepal::read_file(path, &b, nullptr));
    REQUIRE(b.size() > 25);
    return b[24];
}

}  // namespace

TEST_CASE("cli defect 1: bake --help lists every flag, --backend and --timings included") {
    std::string out;
    REQUIRE(run("bake", {"--help"}, &out) == 0);
    for (const char* flag : {"--backend", "--timings", "--supersample", "--max-memory", "--no-mips", "--cap",
                             "--param", "--bits", "--max-error", "--export", "--report", "--threads"})
        CHECK_MESSAGE(contains(out, flag), flag);
}

TEST_CASE("cli defect 2: sepal --version") {
    std::string out;
    REQUIRE(sepal_test::run(sepal_test::bin("sepal") + " --version", &out) == 0);
    CHECK(out == "sepal " SEPAL_VERSION_STRING " (asset format " + std::to_string(SEPAL_FMT_VERSION_MAJOR) + "." +
                     std::to_string(SEPAL_FMT_VERSION_MINOR) + ")\n");
    REQUIRE(sepal_test::run(sepal_test::bin("sepal-view") + " --version", &out) == 0);
    CHECK(contains(out, SEPAL_VERSION_STRING));
}

TEST_CASE("cli defect 3: bake names the weighted SVD wsvd; svd is the paper's plain SVD") {
    const std::string dir = sepal_test::temp_dir();
    std::string out;
    // Factors of f itself (--fit brdf): the radiance fit would take Lambert's whole value
    // into its untextured diffuse part and leave both SVDs nothing to fit.
    REQUIRE(run("bake", {"lambert", "--param", "gs-half", "--res", "16", "--terms", "1", "--method",
                                  "svd,wsvd", "--fit", "brdf", "--report", dir + "/r.json", "-o", dir + "/l.sepal"},
                &out) == 0);
    // Two distinct candidates; the plain SVD spends its rank on the horizon's edge.
    sepal::Json report;
    std::string err;
    REQUIRE_MESSAGE(sepal::read_json_file(dir + "/r.json", &report, &err), err);
    double svd = -1, wsvd = -1;
    for (const sepal::Json& c : report["candidates"])
        (c["method"] == "svd" ? svd : wsvd) = c["error_quantized_relative"].get<double>();
    CHECK(svd > 0);
    CHECK(wsvd > 0);
    CHECK(svd > 5 * wsvd);
    // The default search names its methods (acls and homomorphic on GL ES, acls, wsvd and
    // homomorphic on cpu).
    REQUIRE(run("bake", {"--help"}, &out) == 0);
    CHECK(contains(out, "acls, wsvd and homomorphic on cpu"));
    // factor: --method wsvd is svd --svd-weighted.
    REQUIRE(run("factor", {"lambert", "--res", "16", "--terms", "1", "--method", "wsvd"}, &out) == 0);
    CHECK(contains(out, "wsvd"));
}

TEST_CASE("cli defect 4: factor accepts --cap like bake") {
    const std::string dir = sepal_test::temp_dir();
    std::string out;
    REQUIRE(run("factor", {"ward:rho_d=0.4,rho_s=0.5,ax=0.4,ay=0.15", "--res", "16", "--terms", "1", "--cap",
                                    "2", "--report", dir + "/r.json"},
                &out) == 0);
    const double share = number_after(out, "cap: f clamped at 2 in ");
    CHECK(share > 0);
    CHECK(share < 100);
    sepal::Json r;
    std::string err;
    REQUIRE_MESSAGE(sepal::read_json_file(dir + "/r.json", &r, &err), err);
    CHECK(r["options"]["cap"] == 2.0);
    CHECK(r["capped_share"].get<double>() > 0);
    CHECK(run("factor", {"lambert", "--cap", "0"}, &out) == 2);
}

TEST_CASE("cli defect 5: bake --param rusinkiewicz for GL ES 1.1 is refused before any factoring") {
    const std::string dir = sepal_test::temp_dir();
    std::string out;
    CHECK(run("bake", {"blinn:n=20", "--param", "gs-half,rusinkiewicz", "-o", dir + "/r.sepal"}, &out) == 2);
    CHECK(contains(out, "--param rusinkiewicz needs per-pixel coordinates: --target cpu"));
    CHECK_FALSE(contains(out, "candidate"));  // nothing was factored
    CHECK_FALSE(sepal_test::run("test -e " + dir + "/r.sepal") == 0);
    CHECK(run("bake", {"blinn:n=20", "--param", "elev-azim", "--target", "gles2", "-o", dir + "/e.sepal"},
              &out) == 2);
    // For the CPU backend it bakes, and its asset says per-pixel on inspection.
    REQUIRE(run("bake", {"blinn:n=20", "--param", "rusinkiewicz", "--res", "8", "--terms", "1", "--method",
                                  "nmf", "--target", "cpu", "-o", dir + "/c.sepal"},
                &out) == 0);
}

TEST_CASE("cli defect 6: render x.sepal without --backend renders the asset") {
    const std::string dir = sepal_test::temp_dir();
    std::string out;
    REQUIRE(run("bake", {"lambert", "--param", "gs-half", "--res", "8", "--terms", "1", "--method", "nmf",
                                  "-o", dir + "/l.sepal"},
                &out) == 0);
    REQUIRE(run("render", {dir + "/l.sepal", "--size", "32x32", "-o", dir + "/l.png"}, &out) == 0);
    CHECK(contains(out, "backend    gles1: the default for an asset"));
    sepal::Image img;
    REQUIRE(sepal::read_image(dir + "/l.png", &img, nullptr));
    double sum = 0;
    for (float v : img.data) sum += v;
    CHECK(sum > 10);  // the sphere was drawn
    // A per-pixel-only asset goes to the CPU backend, which draws it.
    REQUIRE(run("bake", {"lambert", "--param", "rusinkiewicz", "--res", "8", "--terms", "1", "--method", "nmf",
                                  "--target", "cpu", "-o", dir + "/r.sepal"},
                &out) == 0);
    REQUIRE(run("render", {dir + "/r.sepal", "--size", "32x32", "-o", dir + "/r.png"}, &out) == 0);
    CHECK(contains(out, "backend    cpu: its parameterization needs per-pixel evaluation"));
    // A missing asset is named as a file, not as a model.
    CHECK(run("render", {dir + "/nope.sepal", "-o", dir + "/n.png"}, &out) == 2);
    CHECK(contains(out, "nope.sepal"));
    CHECK_FALSE(contains(out, "model"));
    CHECK(run("render", {dir + "/l.sepal", "--backend", "exact", "-o", dir + "/n.png"}, &out) == 2);
    CHECK(contains(out, "is a baked asset"));
}

TEST_CASE("cli defect 7: a BRDF Explorer .brdf (GLSL) is refused, not read as Cornell data") {
    const std::string dir = sepal_test::temp_dir(), path = dir + "/blinn.brdf";
    std::ofstream(path) << "analytic\n\n::begin parameters\nfloat n 1 1000 100\n::end parameters\n\n"
                           "::begin shader\nvec3 BRDF( vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y )\n"
                           "{\n    return vec3(1.0);\n}\n::end shader\n";
    std::string err;
    CHECK(sepal::make_brdf(path, &err) == nullptr);
    CHECK_MESSAGE(contains(err, path + ": a BRDF Explorer file (GLSL shader text"), err);
    CHECK_MESSAGE(contains(err, "Cornell .brdf, MERL .binary"), err);
    std::string out;
    CHECK(run("info", {path}, &out) == 2);
    CHECK(contains(out, "BRDF Explorer"));
    // The Cornell files still read.
    REQUIRE_MESSAGE(sepal::make_brdf(sepal_test::source_path("fixtures/cornell/cayman.brdf"), &err), err);
}

TEST_CASE("cli defect 8: sepal diff states its tolerance and judges only against it") {
    const std::string dir = sepal_test::temp_dir();
    sepal::Image img(8, 8, 3);
    for (size_t i = 0; i < img.data.size(); ++i) img.data[i] = float(i % 50) / 255.0f;
    REQUIRE(sepal::write_png(dir + "/a.png", img, nullptr));
    std::string out;
    REQUIRE(run("diff", {dir + "/a.png", dir + "/a.png"}, &out) == 0);
    CHECK(contains(out, "tolerance  none given: no PASS or FAIL"));
    CHECK_FALSE(contains(out, "\nPASS"));
    REQUIRE(run("diff", {dir + "/a.png", dir + "/a.png", "--max-diff", "2", "--max-share", "0.001",
                                  "--min-psnr", "40"},
                &out) == 0);
    CHECK(contains(out, "tolerance  at most 0.1% of pixels over 2 (8-bit units); PSNR >= 40 dB\nPASS"));
    REQUIRE(run("diff", {dir + "/a.png", dir + "/a.png", "--max-diff", "0"}, &out) == 0);
    CHECK(contains(out, "tolerance  no pixel over 0 (8-bit units)\nPASS"));
}

TEST_CASE("cli defect 9: an OBJ mesh is framed from its bounds") {
    // A cube of side 40 centred far from the origin: the default camera (at 0,-3.2,1.4, far
    // plane 20) saw none of it.
    const std::string dir = sepal_test::temp_dir(), obj = dir + "/cube.obj";
    {
        std::ofstream f(obj);
        for (int i = 0; i < 8; ++i)
            f << "v " << 100 + ((i & 1) ? 20 : -20) << " " << 50 + ((i & 2) ? 20 : -20) << " "
              << -30 + ((i & 4) ? 20 : -20) << "\n";
        // Faces wound outwards (counter-clockwise seen from outside).
        const int faces[6][4] = {{1, 3, 4, 2}, {5, 6, 8, 7}, {1, 2, 6, 5}, {3, 7, 8, 4}, {1, 5, 7, 3}, {2, 4, 8, 6}};
        for (const auto& q : faces) f << "f " << q[0] << " " << q[1] << " " << q[2] << " " << q[3] << "\n";
    }
    std::string out;
    REQUIRE(run("render", {"lambert", "--mesh", obj, "--size", "64x64", "-o", dir + "/c.png"}, &out) == 0);
    const double covered = number_after(out, "pixels     ");
    CHECK(covered > 0.1 * 64 * 64);  // framed: the cube fills a good part of the view
    CHECK(covered < 0.9 * 64 * 64);  // and all of it is in view
    sepal::Image img;
    REQUIRE(sepal::read_image(dir + "/c.png", &img, nullptr));
    double lit = 0;
    for (float v : img.data) lit += v;
    CHECK(lit > 0.05 * img.data.size() * 0.1);  // the light was moved with the frame
    // Built-in meshes keep the default scene (the goldens depend on it).
    REQUIRE(run("render", {"lambert", "--size", "64x64", "-o", dir + "/s.png"}, &out) == 0);
}

TEST_CASE("cli defect 10: gen-merl refuses an anisotropic BRDF unless --force, saying how it is reduced") {
    const std::string dir = sepal_test::temp_dir();
    const std::string ward = "ward:rho_d=0.1,rho_s=0.5,ax=0.4,ay=0.05";
    std::string out;
    CHECK(run("gen-merl", {ward, "-o", dir + "/w.binary"}, &out) == 2);
    CHECK(contains(out, "is anisotropic"));
    CHECK(contains(out, "directional albedo"));
    CHECK(contains(out, "--force"));
    CHECK_FALSE(sepal_test::run("test -e " + dir + "/w.binary") == 0);
    REQUIRE(run("gen-merl", {ward, "-o", dir + "/w.binary", "--force"}, &out) == 0);
    CHECK(contains(out, "reduced: MERL tables are isotropic"));
    CHECK(contains(out, "wrote " + dir + "/w.binary"));
}

TEST_CASE("cli defect 11: factor and bake export one layout: a PNG per texture per MIP level, 16-bit for --bits 16") {
    const std::string dir = sepal_test::temp_dir();
    std::string out, err;
    REQUIRE(run("bake", {"blinn:n=20", "--param", "gs-half", "--res", "8", "--terms", "1", "--method", "nmf",
                                  "--bits", "16", "--mips", "-o", dir + "/b.sepal", "--export", dir + "/bake"},
                &out) == 0);
    REQUIRE(run("factor", {"blinn:n=20", "--res", "8", "--terms", "1", "--method", "nmf", "--export",
                                    dir + "/factor"},
                &out) == 0);
    for (const char* role : {"G", "H"}) {
        const std::string t = std::string("term0_") + role;
        for (int l = 0; l < 4; ++l) {  // 8x8 -> 8, 4, 2, 1
            const std::string png = dir + "/bake/" + t + "_mip" + std::to_string(l) + ".png";
            CHECK_MESSAGE(png_bit_depth(png) == 16, png);
        }
        sepal::Image pfm;
        CHECK_MESSAGE(sepal::read_image(dir + "/bake/" + t + ".pfm", &pfm, &err), err);
        CHECK(png_bit_depth(dir + "/factor/" + t + "_mip0.png") == 16);
        CHECK_MESSAGE(sepal::read_image(dir + "/factor/" + t + ".pfm", &pfm, &err), err);
    }
    // The same manifest in both: what each file is, and how to turn codes into values.
    sepal::Json b, f;
    REQUIRE_MESSAGE(sepal::read_json_file(dir + "/bake/manifest.json", &b, &err), err);
    REQUIRE_MESSAGE(sepal::read_json_file(dir + "/factor/manifest.json", &f, &err), err);
    for (const sepal::Json* m : {&b, &f}) {
        for (const char* key : {"source", "param", "map", "colour", "method", "terms", "ratio", "layout", "textures"})
            CHECK_MESSAGE(m->contains(key), key);
        REQUIRE((*m)["textures"].size() == 2u);
        for (const char* key : {"term", "role", "size", "levels", "channels", "bits", "scale", "bias", "files"})
            CHECK_MESSAGE((*m)["textures"][0].contains(key), key);
    }
    CHECK(b["textures"][0]["levels"] == 4);
    CHECK(b["textures"][0]["files"][0] == "term0_G_mip0.png");
    CHECK(f["textures"][0]["files"][0] == "term0_G_mip0.png");
    CHECK(b["method"] == "nmf");
}

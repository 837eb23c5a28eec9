// The SVBRDF sample folder format (svbrdf/samples.h): reader, writer, refusals.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "ist/generate.h"
#include "svbrdf/samples.h"
#include "spec/spec.h"
#include "util/image.h"
#include "util/io.h"
#include "test_util.h"

using namespace sepal;

namespace {

SvbrdfSamples tiny() {
    GenerateOptions g;
    g.width = 6;
    g.height = 5;
    g.views = 2;
    g.lights = 5;
    g.lobe_lights = 4;
    g.preset = "analytic";
    SvbrdfSamples s;
    std::string err;
    REQUIRE_MESSAGE(generate_svbrdf(g, &s, nullptr, &err), err);
    return s;
}

void write_text(const std::string& path, const std::string& text) {
    std::string err;
    REQUIRE(write_file_atomic(path, text.data(), text.size(), &err));
}

}  // namespace

TEST_CASE("svbrdf samples: folder round trip keeps directions, values and confidences") {
    SvbrdfSamples s = tiny();
    drop_samples(&s, 0.3, 5);
    const std::string dir = sepal_test::temp_dir() + "/card";
    std::string err;
    REQUIRE_MESSAGE(write_svbrdf(dir, s, &err), err);
    SvbrdfSamples r;
    SvbrdfCounts counts;
    REQUIRE_MESSAGE(read_svbrdf(dir, &r, &err, &counts), err);
    REQUIRE(r.width == s.width);
    REQUIRE(r.height == s.height);
    REQUIRE(r.pair_count() == s.pair_count());
    CHECK(counts.missing == count_samples(s).missing);
    CHECK(counts.missing > 0);
    for (int p = 0; p < s.pair_count(); ++p) {
        CHECK(r.pairs[size_t(p)].view == s.pairs[size_t(p)].view);
        CHECK(r.pairs[size_t(p)].albedo_weight == doctest::Approx(s.pairs[size_t(p)].albedo_weight).epsilon(1e-8));
        CHECK(r.pairs[size_t(p)].wi.z == doctest::Approx(s.pairs[size_t(p)].wi.z).epsilon(1e-8));
    }
    for (int t = 0; t < s.texels(); ++t)
        for (int p = 0; p < s.pair_count(); ++p) {
            CHECK(r.confidence(t, p) == s.confidence(t, p));  // 0 or 1: exact in 8 bits
            if (s.confidence(t, p) > 0) CHECK(r.value(t, p).y == float(s.value(t, p).y));  // PFM is float
        }
    // Writing is deterministic.
    const std::string dir2 = sepal_test::temp_dir() + "/card";
    REQUIRE(write_svbrdf(dir2, s, &err));
    std::vector<uint8_t> a, b;
    REQUIRE(read_file(dir + "/svbrdf.json", &a, &err));
    REQUIRE(read_file(dir2 + "/svbrdf.json", &b, &err));
    CHECK(a == b);
}

TEST_CASE("svbrdf samples: bad folders are refused with what and where") {
    const SvbrdfSamples s = tiny();
    const std::string dir = sepal_test::temp_dir() + "/card";
    std::string err;
    REQUIRE(write_svbrdf(dir, s, &err));
    SvbrdfSamples r;
    CHECK_FALSE(read_svbrdf(sepal_test::temp_dir() + "/nothing", &r, &err));
    CHECK(err.find("svbrdf.json") != std::string::npos);

    auto refused = [&](const std::string& json, const char* needle) {
        write_text(dir + "/svbrdf.json", json);
        CHECK_FALSE(read_svbrdf(dir, &r, &err));
        CAPTURE(err);
        CHECK(err.find(needle) != std::string::npos);
    };
    refused("{", "svbrdf.json");
    refused("{\"format\":\"other\",\"version\":1}", "format");
    refused("{\"format\":\"sepal-svbrdf\",\"version\":2}", "version");
    refused("{\"format\":\"sepal-svbrdf\",\"version\":1,\"width\":0,\"height\":5,\"pairs\":[]}", "width");
    refused("{\"format\":\"sepal-svbrdf\",\"version\":1,\"width\":6,\"height\":5,\"pairs\":[]}", "pairs");
    refused("{\"format\":\"sepal-svbrdf\",\"version\":1,\"width\":6,\"height\":5,\"pairs\":[{\"wi\":[0,0,-1],"
            "\"wo\":[0,0,1],\"image\":\"pairs/p0000.pfm\"}]}",
            "pairs[0]");
    refused("{\"format\":\"sepal-svbrdf\",\"version\":1,\"width\":6,\"height\":5,\"pairs\":[{\"wi\":[0,0,1],"
            "\"wo\":[0,0,1]}]}",
            "image");
    // An image of the wrong size names the file.
    refused("{\"format\":\"sepal-svbrdf\",\"version\":1,\"width\":7,\"height\":5,\"pairs\":[{\"wi\":[0,0,1],"
            "\"wo\":[0,0,1],\"image\":\"pairs/p0000.pfm\"}]}",
            "p0000.pfm");
    // An absurd size is refused before anything is allocated.
    SvbrdfReadOptions small;
    small.max_memory_mb = 1e-4;
    write_text(dir + "/svbrdf.json",
               "{\"format\":\"sepal-svbrdf\",\"version\":1,\"width\":6,\"height\":5,\"pairs\":[{\"wi\":[0,0,1],"
               "\"wo\":[0,0,1],\"image\":\"pairs/p0000.pfm\"}]}");
    CHECK_FALSE(read_svbrdf(dir, &r, &err, nullptr, small));
    CHECK(err.find("MB") != std::string::npos);

    // Negative values are not refused: they become missing samples, counted.
    Image img(6, 5, 3);
    for (float& v : img.data) v = 0.25f;
    img.at(2, 1, 1) = -1.0f;
    REQUIRE(write_pfm(dir + "/pairs/p0000.pfm", img, &err));
    SvbrdfCounts c;
    REQUIRE_MESSAGE(read_svbrdf(dir, &r, &err, &c), err);
    CHECK(c.negative == 1);
    CHECK(c.missing == 1);
    CHECK(r.confidence(1 * 6 + 2, 0) == 0.0f);
}

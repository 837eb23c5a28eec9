// The SVBRDF folder format (reader, writer, refusals) and the test-SVBRDF generator.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "ist/generate.h"
#include "ist/svbrdf.h"
#include "spec/spec.h"
#include "util/image.h"
#include "util/io.h"
#include "test_util.h"

using namespace sepal;

namespace {

Svbrdf tiny() {
    GenerateOptions g;
    g.width = 6;
    g.height = 5;
    g.views = 2;
    g.lights = 5;
    g.lobe_lights = 4;
    g.preset = "analytic";
    Svbrdf s;
    std::string err;
    REQUIRE_MESSAGE(generate_svbrdf(g, &s, nullptr, &err), err);
    return s;
}

void write_text(const std::string& path, const std::string& text) {
    std::string err;
    REQUIRE(write_file_atomic(path, text.data(), text.size(), &err));
}

}  // namespace

TEST_CASE("ist svbrdf: folder round trip keeps directions, values and confidences") {
    Svbrdf s = tiny();
    drop_samples(&s, 0.3, 5);
    const std::string dir = sepal_test::temp_dir() + "/card";
    std::string err;
    REQUIRE_MESSAGE(write_svbrdf(dir, s, &err), err);
    Svbrdf r;
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

TEST_CASE("ist svbrdf: bad folders are refused with what and where") {
    const Svbrdf s = tiny();
    const std::string dir = sepal_test::temp_dir() + "/card";
    std::string err;
    REQUIRE(write_svbrdf(dir, s, &err));
    Svbrdf r;
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

TEST_CASE("ist generate: true weights are a partition of unity with real blends, bases conserve energy") {
    GenerateOptions g;
    g.width = g.height = 32;
    g.materials = 6;
    g.preset = "analytic";
    Svbrdf s;
    SvbrdfTruth t;
    std::string err;
    REQUIRE_MESSAGE(generate_svbrdf(g, &s, &t, &err), err);
    REQUIRE(t.blend.count == 6);
    int blended = 0;
    std::vector<double> area(6, 0.0);
    for (int i = 0; i < s.texels(); ++i) {
        double sum = 0, top = 0;
        for (int j = 0; j < 6; ++j) {
            const double w = t.blend.at(i, j);
            CHECK(w >= 0);
            sum += w;
            top = std::max(top, w);
            area[size_t(j)] += w;
        }
        CHECK(sum == doctest::Approx(1.0).epsilon(1e-6));
        blended += top < 0.95;
    }
    for (double a : area) CHECK(a > 0.02 * s.texels());  // every material is present
    CHECK(blended > s.texels() / 10);                    // soft transitions and halftones
    // Albedo weights: a partition of each view's hemisphere; the quadrature albedo of
    // every true basis stays at or below 1 (what the energy constraint asks of the fit).
    std::vector<double> per_view(size_t(g.views), 0.0);
    for (const DirPair& p : s.pairs) {
        CHECK(p.wi.z > 0);
        CHECK(p.wo.z > 0);
        per_view[size_t(p.view)] += p.albedo_weight;
    }
    for (double w : per_view) CHECK(w == doctest::Approx(2 * M_PI).epsilon(1e-9));
    for (const std::string& spec : t.bases) {
        std::unique_ptr<Brdf> b = make_brdf(spec, &err);
        REQUIRE(b);
        for (int v = 0; v < g.views; ++v) {
            glm::dvec3 a(0);
            for (const DirPair& p : s.pairs)
                if (p.view == v) a += p.albedo_weight * b->eval(p.wi, p.wo) * p.wi.z;
            CAPTURE(spec);
            CHECK(std::max({a.x, a.y, a.z}) <= 1.0);
        }
    }
}

TEST_CASE("ist generate: deterministic, with the requested share of missing samples and bad options refused") {
    GenerateOptions g;
    g.width = g.height = 8;
    g.views = 3;
    g.lights = 8;
    g.missing = 0.4;
    g.preset = "analytic";
    Svbrdf a, b;
    std::string err;
    REQUIRE(generate_svbrdf(g, &a, nullptr, &err));
    REQUIRE(generate_svbrdf(g, &b, nullptr, &err));
    CHECK(a.values == b.values);
    CHECK(a.conf == b.conf);
    const double share = double(count_samples(a).missing) / double(count_samples(a).samples);
    CHECK(share == doctest::Approx(0.4).epsilon(0.1));
    g.seed = 2;
    REQUIRE(generate_svbrdf(g, &b, nullptr, &err));
    CHECK(a.values != b.values);

    GenerateOptions bad = g;
    bad.materials = 7;
    CHECK_FALSE(generate_svbrdf(bad, &a, nullptr, &err));
    bad = g;
    bad.preset = "nope";
    CHECK_FALSE(generate_svbrdf(bad, &a, nullptr, &err));
    CHECK(err.find("preset") != std::string::npos);
    bad = g;
    bad.bases = {"lambert", "no-such-model"};
    CHECK_FALSE(generate_svbrdf(bad, &a, nullptr, &err));
    CHECK(err.find("basis 1") != std::string::npos);
    bad = g;
    bad.missing = 1.0;
    CHECK_FALSE(generate_svbrdf(bad, &a, nullptr, &err));
    for (double h : {-0.1, 1.5, std::nan("")}) {
        bad = g;
        bad.halftone = h;
        err.clear();
        CHECK_FALSE(generate_svbrdf(bad, &a, nullptr, &err));
        CHECK(err.find("halftone") != std::string::npos);
    }
}

TEST_CASE("ist generate: an opaque halftone mixes materials only along edges") {
    // Texels whose largest true weight is under 0.95, on the default (45%) and opaque prints.
    auto blended_share = [](double halftone) {
        GenerateOptions g;
        g.width = g.height = 64;
        g.views = 1;
        g.lights = 4;
        g.lobe_lights = 0;
        g.preset = "analytic";
        g.halftone = halftone;
        Svbrdf s;
        SvbrdfTruth t;
        std::string err;
        REQUIRE_MESSAGE(generate_svbrdf(g, &s, &t, &err), err);
        int blended = 0;
        for (int i = 0; i < s.texels(); ++i) {
            double top = 0;
            for (int j = 0; j < t.blend.count; ++j) top = std::max(top, double(t.blend.at(i, j)));
            blended += top < 0.95;
        }
        return double(blended) / s.texels();
    };
    const double half = blended_share(0.45), opaque = blended_share(1.0);
    CAPTURE(half);
    CAPTURE(opaque);
    CHECK(opaque < 0.7 * half);
    CHECK(opaque > 0.02);  // the edges stay soft
}

TEST_CASE("ist generate: truth files round trip and render like the SVBRDF they describe") {
    GenerateOptions g;
    g.width = g.height = 8;
    g.views = 2;
    g.lights = 6;
    g.noise = 0;
    g.misregistration = 0;
    g.preset = "analytic";
    Svbrdf s;
    SvbrdfTruth t;
    std::string err;
    REQUIRE(generate_svbrdf(g, &s, &t, &err));
    const std::string dir = sepal_test::temp_dir();
    REQUIRE(write_truth(dir, t, &err));
    SvbrdfTruth r;
    REQUIRE_MESSAGE(read_truth(dir, &r, &err), err);
    CHECK(r.bases == t.bases);
    CHECK(r.names == t.names);
    CHECK(r.blend.w == t.blend.w);
    // The truth evaluated at a texel centre is the noiseless sample there.
    std::unique_ptr<BlendedSvbrdf> b = make_truth_svbrdf(r, &err);
    REQUIRE(b);
    for (int texel : {0, 9, 27, 63})
        for (int p = 0; p < s.pair_count(); p += 3) {
            const glm::dvec2 uv(((texel % 8) + 0.5) / 8, ((texel / 8) + 0.5) / 8);
            const glm::dvec3 f = b->eval(uv, s.pairs[size_t(p)].wi, s.pairs[size_t(p)].wo), v = s.value(texel, p);
            CHECK(f.y == doctest::Approx(v.y).epsilon(1e-5));
        }
}

// The sampler file reader and the C sampling API (runtime/include/sepal/sepal_sampler.h):
// corrupt or absurd files are refused with a message, sample() and pdf() agree exactly for
// every kind, eval() reconstructs f cos, and degenerate views fall back to cosine sampling.
#include <doctest/doctest.h>

#include <cmath>
#include <cstddef>
#include <cstring>
#include <vector>

#include "brdf/brdf.h"
#include "spec/spec.h"
#include "brdf/brdf_util.h"
#include "sampling/alternatives.h"
#include "sampling/factored_fit.h"
#include "sampling/sampler_file.h"
#include "util/parallel.h"

using namespace sepal;

namespace {

SamplerData small_factored(const std::string& spec = "cook-torrance", bool colour = true,
                           SampleAxis axis = SampleAxis::Normal, SampleParam param = SampleParam::Half) {
    std::string err;
    auto b = make_brdf(spec, &err);
    REQUIRE(b);
    FactoredOptions o;
    o.n_theta_o = 8, o.n_phi_o = 8, o.n_theta_p = 16, o.n_phi_p = 8, o.J = 2, o.K = 1, o.colour = colour;
    o.param = param;
    o.axis = axis;
    SamplerData d;
    REQUIRE_MESSAGE(fit_factored(*b, o, &d, nullptr, &err), err);
    return d;
}

std::vector<uint8_t> encode(const SamplerData& d) {
    std::vector<uint8_t> bytes;
    std::string err;
    REQUIRE_MESSAGE(encode_sampler(d, &bytes, &err), err);
    return bytes;
}

// Recomputes both checksums after an edit, so the reader's other checks are reached.
void reseal(std::vector<uint8_t>* b) {
    sepal_smp_header h;
    std::memcpy(&h, b->data(), sizeof h);
    h.payload_crc = sepal_crc32(0, b->data() + sizeof h, b->size() - sizeof h);
    h.header_crc = 0;
    h.header_crc = sepal_crc32(0, &h, sizeof h);
    std::memcpy(b->data(), &h, sizeof h);
}

std::string parse_error(const std::vector<uint8_t>& b) {
    std::vector<uint64_t> aligned((b.size() + 7) / 8 + 1);
    std::memcpy(aligned.data(), b.data(), b.size());
    sepal_sampler s;
    sepal_error e{};
    if (sepal_sampler_parse(aligned.data(), b.size(), &s, &e) == SEPAL_OK) return "";
    CHECK(std::strlen(e.message) > 0);
    return e.message;
}

}  // namespace

TEST_CASE("sampler format: round trip, determinism, and every corruption refused with a reason") {
    const SamplerData d = small_factored();
    const std::vector<uint8_t> good = encode(d);
    CHECK(good == encode(d));  // byte-identical
    CHECK(parse_error(good).empty());
    CHECK(good.size() < 64 * 1024);

    auto with = [&](auto edit) {
        std::vector<uint8_t> b = good;
        edit(&b);
        return parse_error(b);
    };
    CHECK(with([](std::vector<uint8_t>* b) { (*b)[0] = 'X'; }).find("magic") != std::string::npos);
    CHECK(with([](std::vector<uint8_t>* b) { (*b)[8] = 9; reseal(b); }).find("version") != std::string::npos);
    CHECK(with([](std::vector<uint8_t>* b) { (*b)[20] ^= 1; }).find("checksum") != std::string::npos);
    CHECK(with([](std::vector<uint8_t>* b) { b->back() ^= 0x40; }).find("checksum") != std::string::npos);
    CHECK(with([](std::vector<uint8_t>* b) { b->resize(b->size() - 8); }).find("bytes") != std::string::npos);
    CHECK(with([](std::vector<uint8_t>* b) { b->resize(40); }).find("too short") != std::string::npos);
    // Absurd counts: a huge term count, a huge grid.
    CHECK(with([](std::vector<uint8_t>* b) {
              sepal_smp_desc* desc = reinterpret_cast<sepal_smp_desc*>(b->data() + sizeof(sepal_smp_header));
              desc->terms = 100000;
              reseal(b);
          }).find("out of range") != std::string::npos);
    CHECK(with([](std::vector<uint8_t>* b) {
              sepal_smp_desc* desc = reinterpret_cast<sepal_smp_desc*>(b->data() + sizeof(sepal_smp_header));
              desc->n_theta_p = 0xFFFFFFFFu;
              reseal(b);
          }).find("out of range") != std::string::npos);
    // A NaN weight, a falling CDF, a defensive share of 2.
    uint64_t off[SEPAL_SMP_ARRAY_COUNT];
    sepal_sampler_layout(d.kind, &d.desc, off, nullptr);
    CHECK(with([&](std::vector<uint8_t>* b) {
              const float nan = std::nanf("");
              std::memcpy(b->data() + off[SEPAL_SMP_ARRAY_F], &nan, 4);
              reseal(b);
          }).find("not finite") != std::string::npos);
    CHECK(with([&](std::vector<uint8_t>* b) {
              const float x = 0.9f;
              std::memcpy(b->data() + off[SEPAL_SMP_ARRAY_U_CDF] + 8, &x, 4);
              std::memcpy(b->data() + off[SEPAL_SMP_ARRAY_U_CDF] + 12, &x, 4);
              const float y = 0.5f;
              std::memcpy(b->data() + off[SEPAL_SMP_ARRAY_U_CDF] + 16, &y, 4);
              reseal(b);
          }).find("CDF") != std::string::npos);
    CHECK(with([](std::vector<uint8_t>* b) {
              sepal_smp_desc* desc = reinterpret_cast<sepal_smp_desc*>(b->data() + sizeof(sepal_smp_header));
              desc->defensive = 2.0f;
              reseal(b);
          }).find("defensive") != std::string::npos);
    // Format 1.1's diffuse part: negative, absurd, or in a 1.0 file, refused.
    const SamplerData paint = small_factored("cook-torrance:d=0.7,Rd=0.8/0.15/0.1,s=0.3,F0=0.04,m=0.2");
    REQUIRE(paint.desc.diffuse[0] > 0.1f);
    const std::vector<uint8_t> p11 = encode(paint);
    CHECK(reinterpret_cast<const sepal_smp_header*>(p11.data())->version_minor == 1);
    CHECK(reinterpret_cast<const sepal_smp_header*>(good.data())->version_minor == (d.desc.diffuse[0] > 0 ? 1 : 0));
    CHECK(parse_error(p11).empty());
    // The parse error of a file after an edit of its header and desc (checksums resealed).
    auto edited = [](std::vector<uint8_t> b, auto edit) {
        sepal_smp_desc* desc = reinterpret_cast<sepal_smp_desc*>(b.data() + sizeof(sepal_smp_header));
        edit(reinterpret_cast<sepal_smp_header*>(b.data()), desc);
        reseal(&b);
        return parse_error(b);
    };
    auto with11 = [&](auto edit) { return edited(p11, edit); };
    CHECK(with11([](sepal_smp_header*, sepal_smp_desc* x) { x->diffuse[1] = -0.1f; }).find("diffuse") != std::string::npos);
    CHECK(with11([](sepal_smp_header*, sepal_smp_desc* x) { x->diffuse[2] = 1e30f; }).find("diffuse") != std::string::npos);
    CHECK(with11([](sepal_smp_header*, sepal_smp_desc* x) { x->diffuse[0] = std::nanf(""); }).find("diffuse") != std::string::npos);
    CHECK(with11([](sepal_smp_header* h, sepal_smp_desc*) { h->version_minor = 0; }).find("1.0") != std::string::npos);
    // A small factored sampler about an axis, encoded: edges down to -1, the lowest version
    // that holds the axis, parsed without complaint.
    auto axis_file = [&](SampleAxis axis, uint32_t value, uint16_t minor) {
        const SamplerData d = small_factored("ward:rho_d=0.1,rho_s=0.8,ax=0.2,ay=0.05", true, axis);
        REQUIRE(d.desc.axis == value);
        REQUIRE(d.z_edges.back() == -1.0f);
        const std::vector<uint8_t> bytes = encode(d);
        CHECK(reinterpret_cast<const sepal_smp_header*>(bytes.data())->version_minor == minor);
        CHECK(parse_error(bytes).empty());
        return bytes;
    };
    // Format 1.2's axis: only in a 1.2 factored file with absolute phi.
    const std::vector<uint8_t> p12 = axis_file(SampleAxis::Tangent, SEPAL_SMP_AXIS_T, 2);
    auto with12 = [&](auto edit) { return edited(p12, edit); };
    CHECK(with12([](sepal_smp_header* h, sepal_smp_desc*) { h->version_minor = 1; }).find("axis") != std::string::npos);
    CHECK(with12([](sepal_smp_header*, sepal_smp_desc* x) { x->axis = SEPAL_SMP_AXIS_COUNT; }).find("axis") != std::string::npos);
    // A view axis (format 1.3) in a 1.2 file is refused: a 1.2 reader would bin it as T.
    CHECK(with12([](sepal_smp_header*, sepal_smp_desc* x) { x->axis = SEPAL_SMP_AXIS_T_VIEW; }).find("axis") != std::string::npos);
    // Format 1.3's view axes: only in a 1.3 factored file of the half vector.
    const std::vector<uint8_t> p13 = axis_file(SampleAxis::TangentView, SEPAL_SMP_AXIS_T_VIEW, 3);
    auto with13 = [&](auto edit) { return edited(p13, edit); };
    CHECK(with13([](sepal_smp_header* h, sepal_smp_desc*) { h->version_minor = 2; }).find("axis") != std::string::npos);
    CHECK(with13([](sepal_smp_header*, sepal_smp_desc* x) { x->param = SEPAL_SMP_PARAM_INCIDENT; }).find("axis") != std::string::npos);
    CHECK(with13([](sepal_smp_header*, sepal_smp_desc* x) { x->axis = SEPAL_SMP_AXIS_S_VIEW; }).empty());
    // The mirror axes: 1.3, the incident direction only.
    CHECK(with13([](sepal_smp_header*, sepal_smp_desc* x) { x->axis = SEPAL_SMP_AXIS_T_MIRROR; }).find("axis") != std::string::npos);
    CHECK(with13([](sepal_smp_header*, sepal_smp_desc* x) {
              x->axis = SEPAL_SMP_AXIS_S_MIRROR, x->param = SEPAL_SMP_PARAM_INCIDENT;
          }).empty());
    CHECK(with12([](sepal_smp_header*, sepal_smp_desc* x) {
              x->axis = SEPAL_SMP_AXIS_T_MIRROR, x->param = SEPAL_SMP_PARAM_INCIDENT;
          }).find("axis") != std::string::npos);
    CHECK(with12([](sepal_smp_header*, sepal_smp_desc* x) { x->axis = SEPAL_SMP_AXIS_N; }).find("edges") != std::string::npos);
    CHECK(with([](std::vector<uint8_t>* b) {
              sepal_smp_desc* desc = reinterpret_cast<sepal_smp_desc*>(b->data() + sizeof(sepal_smp_header));
              desc->axis = SEPAL_SMP_AXIS_S;
              reseal(b);
          }).find("axis") != std::string::npos);
    // eval() adds D cos(theta_i): at a view and direction far from the lobe, about D cos.
    {
        Sampler ps;
        std::string e2;
        REQUIRE_MESSAGE(ps.build(paint, &e2), e2);
        sepal_sampler_view v;
        const float wo[3] = {0.0f, 0.0f, 1.0f}, wi[3] = {0.8f, 0.0f, 0.6f};
        sepal_sampler_set_view(&ps.get(), wo, &v);
        float rgb[3];
        REQUIRE(sepal_sampler_eval(&v, wi, rgb) == 1);
        CHECK(rgb[0] >= paint.desc.diffuse[0] * 0.6f * 0.999f);
        CHECK(rgb[0] < paint.desc.diffuse[0] * 0.6f * 1.5f);
        // The cosine share at this view is at least the diffuse part's share of the albedo.
        CHECK(v.defensive > 0.3f);
    }
    // Unaligned buffers and NULL are refused, not read.
    std::vector<uint64_t> aligned(good.size() / 8 + 2);
    uint8_t* odd = reinterpret_cast<uint8_t*>(aligned.data()) + 1;
    std::memcpy(odd, good.data(), good.size());
    sepal_sampler s;
    sepal_error e{};
    CHECK(sepal_sampler_parse(odd, good.size(), &s, &e) == SEPAL_ERR_INVALID_ARGUMENT);
    CHECK(sepal_sampler_parse(nullptr, good.size(), &s, &e) == SEPAL_ERR_INVALID_ARGUMENT);
    // The writer refuses what the reader would refuse.
    SamplerData bad = d;
    bad.F[0] = -1.0f;
    std::string err;
    std::vector<uint8_t> out;
    CHECK_FALSE(encode_sampler(bad, &out, &err));
    CHECK(err.find("negative") != std::string::npos);
    bad = d;
    bad.F.pop_back();
    CHECK_FALSE(encode_sampler(bad, &out, &err));
}

TEST_CASE("sampler API: sample() and pdf() agree exactly, for every kind, at many views") {
    std::string err;
    auto ct = make_brdf("cook-torrance", &err);
    auto ward = make_brdf("ward:rho_d=0.1,rho_s=0.8,ax=0.2,ay=0.05", &err);
    const std::string aniso = "ward:rho_d=0.1,rho_s=0.8,ax=0.2,ay=0.05";
    std::vector<SamplerData> kinds = {small_factored(), small_factored(aniso),
                                      small_factored(aniso, true, SampleAxis::Tangent),
                                      small_factored(aniso, true, SampleAxis::Bitangent),
                                      small_factored(aniso, true, SampleAxis::TangentView),
                                      small_factored(aniso, true, SampleAxis::BitangentMirror, SampleParam::Incident),
                                      make_cosine_sampler()};
    SamplerData d;
    REQUIRE(make_analytic_sampler(*ct, &d, &err));
    kinds.push_back(d);
    REQUIRE(make_analytic_sampler(*ward, &d, &err));
    kinds.push_back(d);
    REQUIRE(make_analytic_sampler(*make_brdf("phong", &err), &d, &err));  // a Phong-axis lobe
    kinds.push_back(d);
    TabulatedOptions to;
    to.n_theta_o = 8, to.n_phi_o = 4, to.n_theta_i = 16, to.n_phi_i = 16;
    REQUIRE(make_tabulated_sampler(*ward, to, &d, &err));
    kinds.push_back(d);
    for (const SamplerData& k : kinds) {
        Sampler s;
        REQUIRE_MESSAGE(s.build(k, &err), err);
        SplitMix64 rng(k.kind * 31 + 7);
        int mismatches = 0, used = 0;
        for (int view = 0; view < 20; ++view) {
            const double t = view < 19 ? 89.9 * view / 18.0 : 0.0;
            const glm::dvec3 wo = dir_from_degrees(t, 360.0 * rng.uniform());
            const float w[3] = {float(wo.x), float(wo.y), float(wo.z)};
            sepal_sampler_view v;
            sepal_sampler_set_view(&s.get(), w, &v);
            for (int i = 0; i < 500; ++i) {
                const float u[2] = {float(rng.uniform()), float(rng.uniform())};
                float wi[3], pdf;
                const int r = sepal_sampler_sample(&v, u, wi, &pdf);
                if (r < 0) continue;
                ++used;
                CHECK(std::fabs(std::sqrt(wi[0] * wi[0] + wi[1] * wi[1] + wi[2] * wi[2]) - 1.0f) < 1e-5f);
                CHECK((r == 1) == (wi[2] > 0.0f));
                if (sepal_sampler_pdf(&v, wi) != pdf) ++mismatches;
            }
        }
        INFO("kind " << k.kind);
        CHECK(mismatches == 0);
        CHECK(used > 9000);
        // u at the edges of [0,1): no NaN, no crash.
        sepal_sampler_view v;
        const float w[3] = {0.3f, 0.1f, 0.9f};
        sepal_sampler_set_view(&s.get(), w, &v);
        for (float a : {0.0f, 0x1.fffffep-1f, 1.0f})
            for (float b : {0.0f, 0x1.fffffep-1f, 1.0f}) {
                const float u[2] = {a, b};
                float wi[3], pdf;
                if (sepal_sampler_sample(&v, u, wi, &pdf) >= 0) CHECK(std::isfinite(pdf));
            }
    }
}

TEST_CASE("sampler API: eval reconstructs f cos; degenerate views fall back to cosine sampling") {
    std::string err;
    auto ct = make_brdf("cook-torrance", &err);
    Sampler s;
    REQUIRE(s.build(small_factored(), &err));
    // The colour reconstruction follows the BRDF's colour (Rd blue > red) near the peak.
    const glm::dvec3 wo = dir_from_degrees(30, 0), wi = dir_from_degrees(30, 180);
    const float w[3] = {float(wo.x), float(wo.y), float(wo.z)}, i[3] = {float(wi.x), float(wi.y), float(wi.z)};
    sepal_sampler_view v;
    sepal_sampler_set_view(&s.get(), w, &v);
    float rgb[3];
    REQUIRE(sepal_sampler_eval(&v, i, rgb) == 1);
    const glm::dvec3 f = ct->eval(wi, wo) * wi.z;
    for (int c = 0; c < 3; ++c) CHECK(rgb[c] == doctest::Approx(f[c]).epsilon(0.35));
    CHECK(rgb[2] > rgb[0]);
    const float below[3] = {0.1f, 0.0f, -0.5f};
    CHECK(sepal_sampler_eval(&v, below, rgb) == 0);
    // wo below the horizon, or a NaN wo: cosine samples, never NaN.
    for (const float* bad : {below, (const float*)nullptr}) {
        const float nanw[3] = {std::nanf(""), 0.0f, 1.0f};
        sepal_sampler_set_view(&s.get(), bad ? bad : nanw, &v);
        CHECK(v.fallback == 1);
        const float u[2] = {0.3f, 0.6f};
        float wi2[3], pdf;
        CHECK(sepal_sampler_sample(&v, u, wi2, &pdf) == 1);
        CHECK(pdf == doctest::Approx(wi2[2] / 3.14159265f));
    }
    // Cosine kind: no reconstruction.
    Sampler c;
    REQUIRE(c.build(make_cosine_sampler(), &err));
    sepal_sampler_set_view(&c.get(), w, &v);
    CHECK(sepal_sampler_eval(&v, i, rgb) == 0);
}

TEST_CASE("sampler: a LOBES file whose cosine share is NaN or inf is refused (CRC valid)") {
    std::string err;
    auto b = make_brdf("ward:rho_d=0.2,rho_s=0.3,ax=0.2,ay=0.2", &err);
    REQUIRE(b);
    SamplerData d;
    LobeFitReport rep;
    REQUIRE_MESSAGE(fit_as_sampler(*b, &d, &rep, &err), err);
    REQUIRE(d.kind == SEPAL_SAMPLER_LOBES);
    const std::vector<uint8_t> good = encode(d);
    CHECK(parse_error(good).empty());
    for (float bad : {NAN, INFINITY, -0.5f, 1.5f}) {
        std::vector<uint8_t> bytes = good;
        std::memcpy(bytes.data() + sizeof(sepal_smp_header) + offsetof(sepal_smp_desc, defensive), &bad, sizeof bad);
        reseal(&bytes);
        const std::string why = parse_error(bytes);
        CHECK_MESSAGE(why.find("defensive share") != std::string::npos, why);
    }
}

TEST_CASE("sampler API: NULL arguments are answered, not dereferenced") {
    sepal_sampler_view v;
    const float wo[3] = {0, 0, 1};
    sepal_sampler_set_view(nullptr, wo, &v);  // a cosine-only view
    CHECK(v.fallback == 1);
    CHECK(v.defensive == 1.0f);
    sepal_sampler_set_view(nullptr, wo, nullptr);
    const float u[2] = {0.3f, 0.6f};
    float wi[3], pdf = -1;
    CHECK(sepal_sampler_sample(&v, u, wi, &pdf) == 1);
    CHECK(pdf == doctest::Approx(wi[2] / 3.14159265f).epsilon(1e-4));
    CHECK(sepal_sampler_pdf(&v, wi) == doctest::Approx(pdf));
    float rgb[3] = {1, 1, 1};
    CHECK(sepal_sampler_eval(&v, wi, rgb) == 0);
    CHECK(rgb[0] == 0.0f);
    CHECK(sepal_sampler_sample(nullptr, u, wi, &pdf) == -1);
    CHECK(pdf == 0.0f);
    CHECK(sepal_sampler_pdf(nullptr, wi) == 0.0f);
}

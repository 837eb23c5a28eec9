// merl-nbrdf reader (measured/nbrdf.h): the MLP matches the reference evaluator
// nbrdf_eval.py, the spec "nbrdf:NAME" works through make_brdf, physics sanity of the fits,
// the data-path rule, and what the reader says about broken files.
//
// The reference values below were produced by data/merl-nbrdf/nbrdf_eval.py (numpy, float64;
// printed with %.17g). When python3 with numpy is on this machine, a second test runs the
// script itself at a few pairs, so a change on either side is caught.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "brdf/brdf.h"
#include "spec/spec.h"
#include "measured/nbrdf.h"
#include "util/parallel.h"
#include "test_util.h"

namespace {

constexpr double kPi = 3.14159265358979323846;

glm::dvec3 sph(double theta_deg, double phi_deg) {
    const double t = theta_deg * kPi / 180, p = phi_deg * kPi / 180;
    return glm::dvec3(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
}

struct RefValue {
    const char* material;
    double ti, pi, to, po;  // degrees, as nbrdf_eval.py's arguments
    double rgb[3];
};

// /usr/bin/python3 gen_ref.py: nbrdf_eval.evaluate(db[m], sph(ti, pi), sph(to, po)).
const RefValue kRef[] = {
    {"gold-paint", 30, 0, 30, 180, {0.33670290515698609, 0.24034312794791113, 0.13479879135152828}},
    {"gold-paint", 0, 0, 0, 0, {0.35079941643512136, 0.24677067026982669, 0.13445275508103061}},
    {"gold-paint", 10, 0, 10, 180, {0.34739605749497948, 0.24472958097490194, 0.13351120495225999}},
    {"gold-paint", 45, 0, 45, 180, {0.36595323108897193, 0.27115780679386359, 0.16512460559508635}},
    {"gold-paint", 45, 0, 44.5, 179.5, {0.36807793128752686, 0.27604896091957398, 0.17200128415411808}},
    {"gold-paint", 60, 20, 30, 200, {0.13125733529557548, 0.09235020900394364, 0.041510981268837233}},
    {"gold-paint", 75, 0, 75, 180, {2.611658659038627, 2.5279820629605632, 2.4652612010940782}},
    {"gold-paint", 85, 0, 80, 170, {0.236073807777329, 0.19885009210574278, 0.18472078164123307}},
    {"gold-paint", 20, 40, 70, 300, {0.052752692897051645, 0.030350966927533474, 0.012459996639896609}},
    {"gold-paint", 50, 0, 50, 0, {0.044316488561254808, 0.024057789411867203, 0.0092425028732447956}},
    {"gold-paint", 5, 90, 65, 10, {0.050529348535273577, 0.02909627633862355, 0.012176658987030464}},
    {"gold-paint", 89, 10, 89, 190, {18.632461352347597, 17.228339481990332, 17.792362032317403}},
    {"gold-paint", 30, 0, 31, 181, {0.33075106795311826, 0.23798067076523544, 0.13629272328124453}},
    {"dark-red-paint", 30, 0, 30, 180, {0.093913383890418922, 0.017831668657104283, 0.01113202275862557}},
    {"dark-red-paint", 0, 0, 0, 0, {0.092185638150880322, 0.015733182787498468, 0.0086029274812184919}},
    {"dark-red-paint", 10, 0, 10, 180, {0.092386504971921468, 0.015779368460100196, 0.0086539391829725254}},
    {"dark-red-paint", 45, 0, 45, 180, {0.10018753286447613, 0.024773729855616544, 0.019051776332432047}},
    {"dark-red-paint", 45, 0, 44.5, 179.5, {0.10010192139865381, 0.024023535251295858, 0.018753112754991141}},
    {"dark-red-paint", 60, 20, 30, 200, {0.090535692253218558, 0.019255318805510457, 0.013299718390743287}},
    {"dark-red-paint", 75, 0, 75, 180, {0.87489648372834972, 0.71136550488076922, 0.63132995226362598}},
    {"dark-red-paint", 85, 0, 80, 170, {0.33882227424640932, 0.28347924723358031, 0.25629489118733395}},
    {"dark-red-paint", 20, 40, 70, 300, {0.081996297229057102, 0.0126143918508963, 0.0058847058279343223}},
    {"dark-red-paint", 50, 0, 50, 0, {0.079732330392915385, 0.01136870014394753, 0.0031007485229812559}},
    {"dark-red-paint", 5, 90, 65, 10, {0.081427049647726513, 0.012230154383160219, 0.005409698872532287}},
    {"dark-red-paint", 89, 10, 89, 190, {11.955281319773919, 10.016604094139058, 8.2658360702564551}},
    {"dark-red-paint", 30, 0, 31, 181, {0.09358760301480773, 0.018349172115938117, 0.011649500984024508}},
    {"alum-bronze", 30, 0, 30, 180, {5.8685128015882455, 2.6751214724328554, 1.1569697294645613}},
    {"alum-bronze", 0, 0, 0, 0, {3.2208887263414363, 1.3394905847475438, 0.5060852736728696}},
    {"alum-bronze", 10, 0, 10, 180, {3.4369605536524945, 1.4525050419058387, 0.56508043109961292}},
    {"alum-bronze", 45, 0, 45, 180, {12.320498405630447, 6.7674324237996677, 3.8684940980451925}},
    {"alum-bronze", 45, 0, 44.5, 179.5, {6.7611177425137114, 3.8801461879752681, 2.126900850751944}},
    {"alum-bronze", 60, 20, 30, 200, {0.057121611464951316, 0.043663155391178154, 0.031596134000892784}},
    {"alum-bronze", 75, 0, 75, 180, {233.03630412172083, 192.63243386334725, 205.91545297303091}},
    {"alum-bronze", 85, 0, 80, 170, {0.073899300576848903, 0.0657558124638431, 0.057810770920084131}},
    {"alum-bronze", 20, 40, 70, 300, {0.011948527540327936, 0.0094778770171866089, 0.0060716729762773092}},
    {"alum-bronze", 50, 0, 50, 0, {0.0088390934691080503, 0.0062783042721703541, 0.0043943175110829902}},
    {"alum-bronze", 5, 90, 65, 10, {0.013078178113804073, 0.010254701402689248, 0.0067295544213337166}},
    {"alum-bronze", 89, 10, 89, 190, {1085.4755433830396, 944.31433984242381, 1250.860283705762}},
    {"alum-bronze", 30, 0, 31, 181, {2.0363772020370443, 1.134195769623668, 0.62065074847980539}},
    {"specular-orange-phenolic", 30, 0, 30, 180, {9.2311049318202265, 8.0238115974038902, 8.1408340959439354}},
    {"specular-orange-phenolic", 0, 0, 0, 0, {4.1749303931289878, 3.6073633566182597, 3.6278194285204206}},
    {"specular-orange-phenolic", 10, 0, 10, 180, {4.5867810249590937, 3.9672598188935311, 3.9936325050978869}},
    {"specular-orange-phenolic", 45, 0, 45, 180, {22.018584433956693, 19.097174320947357, 19.569340634342588}},
    {"specular-orange-phenolic", 45, 0, 44.5, 179.5, {9.0194325873271506, 7.870573338052905, 7.9863865152233977}},
    {"specular-orange-phenolic", 60, 20, 30, 200, {0.10682356196851406, 0.019593826505544865, 0.0049845700286919037}},
    {"specular-orange-phenolic", 75, 0, 75, 180, {214.82527999802858, 182.05786285593948, 192.01744703725612}},
    {"specular-orange-phenolic", 85, 0, 80, 170, {0.077912288683628317, 0.01616139979382436, 0.0040199325166001554}},
    {"specular-orange-phenolic", 20, 40, 70, 300, {0.099667153315729617, 0.017014838608691241, 0.0026111460733500014}},
    {"specular-orange-phenolic", 50, 0, 50, 0, {0.10552826827172712, 0.017655582494561894, 0.0020784945953278289}},
    {"specular-orange-phenolic", 5, 90, 65, 10, {0.10444912360384673, 0.017954479147370694, 0.0029757140573272167}},
    {"specular-orange-phenolic", 89, 10, 89, 190, {644.00690681130914, 524.55480646545652, 561.33939073014835}},
    {"specular-orange-phenolic", 30, 0, 31, 181, {1.4224144223491444, 1.1941688525584184, 1.1842904699393682}},
    {"white-diffuse-bball", 30, 0, 30, 180, {0.16103215692661821, 0.14341605030919991, 0.11666266235990608}},
    {"white-diffuse-bball", 0, 0, 0, 0, {0.14378812563478349, 0.12772396876344438, 0.10138146948061078}},
    {"white-diffuse-bball", 10, 0, 10, 180, {0.14613068246325711, 0.12973223241278475, 0.10371072941635284}},
    {"white-diffuse-bball", 45, 0, 45, 180, {0.23921445531094654, 0.2220257571397779, 0.19754687339333765}},
    {"white-diffuse-bball", 45, 0, 44.5, 179.5, {0.20517354556786938, 0.18634567675146441, 0.1632534009868476}},
    {"white-diffuse-bball", 60, 20, 30, 200, {0.11171360779434325, 0.096609711798333997, 0.066474636667631204}},
    {"white-diffuse-bball", 75, 0, 75, 180, {3.7558220384719183, 3.5959300512216181, 3.4298615208911807}},
    {"white-diffuse-bball", 85, 0, 80, 170, {0.10872034732247493, 0.097155240533836507, 0.084461423137340397}},
    {"white-diffuse-bball", 20, 40, 70, 300, {0.098667869360833382, 0.083136537649332043, 0.056277852249116966}},
    {"white-diffuse-bball", 50, 0, 50, 0, {0.10108461142915615, 0.085055292261559057, 0.05596222972515319}},
    {"white-diffuse-bball", 5, 90, 65, 10, {0.10148098482072121, 0.085817234892748173, 0.057330083378627661}},
    {"white-diffuse-bball", 89, 10, 89, 190, {71.777495882164402, 62.636091244327694, 56.112246052110223}},
    {"white-diffuse-bball", 30, 0, 31, 181, {0.15568671156776714, 0.14040257772612552, 0.10931778242242185}},
    {"chrome", 30, 0, 30, 180, {569.11771770102303, 600.24971943366324, 593.17425847546008}},
    {"chrome", 0, 0, 0, 0, {460.71475143126287, 484.04288382851104, 480.4362059434971}},
    {"chrome", 10, 0, 10, 180, {473.60361917862377, 496.25603009956518, 491.90891742568647}},
    {"chrome", 45, 0, 45, 180, {723.01036219431421, 780.57223738795778, 771.55085627767301}},
    {"chrome", 45, 0, 44.5, 179.5, {100.6592608288897, 94.270370408456017, 90.045480741118325}},
    {"chrome", 60, 20, 30, 200, {0.0026469562662272406, 0.002397654005705574, 0.002534491806592154}},
    {"chrome", 75, 0, 75, 180, {1391.1339190949527, 1900.3744148888957, 2178.6479738482935}},
    {"chrome", 85, 0, 80, 170, {0.029810206040256526, 0.02836681386715445, 0.037895008321215062}},
    {"chrome", 20, 40, 70, 300, {0.00070606719266153029, 0.00055048327575324407, 0.00053556549657551855}},
    {"chrome", 50, 0, 50, 0, {0.0002073631622168115, 8.6349525257434223e-05, 0.00012970448236737653}},
    {"chrome", 5, 90, 65, 10, {0.00073997071526887837, 0.00059613379421041834, 0.00060273013486700222}},
    {"chrome", 89, 10, 89, 190, {1580.9034003027236, 1807.3037293185821, 2482.9654535700706}},
    {"chrome", 30, 0, 31, 181, {22.459702634091713, 16.53889468738716, 14.948037513486851}},
};

bool close_rel(double a, double b, double rel) {
    return std::fabs(a - b) <= rel * std::max(std::fabs(b), 1e-12);
}

std::shared_ptr<const sepal::NbrdfSet> data_set() {
    std::string err;
    auto s = sepal::load_nbrdf_set(sepal_test::source_path("data/merl-nbrdf/merl-nbrdf.json"), &err);
    REQUIRE_MESSAGE(bool(s), err);
    return s;
}

std::string parse_error(const std::string& text) {
    std::string err;
    auto s = sepal::NbrdfSet::parse(text, "t.json", &err);
    CHECK(!s);
    return err;
}

// A one-material file with the given weights text (layers 6-1-1-3).
std::string tiny(const std::string& weights) {
    return R"({"format":"nbrdf-mlp-v1","layers":[6,1,1,3],"materials":{"m":{)" + weights + "}}}";
}
const char* kTinyOk =
    R"("w1":[[1],[0],[0],[0],[0],[0]],"b1":[0],"w2":[[1]],"b2":[0],"w3":[[1,0.5,0.25]],"b3":[0,0,0])";

}  // namespace

TEST_CASE("nbrdf: matches nbrdf_eval.py to 1e-5 relative (stored reference values)") {
    auto s = data_set();
    CHECK(s->size() == 100);
    double worst = 0.0;
    for (const RefValue& r : kRef) {
        const int i = s->find(r.material);
        REQUIRE_MESSAGE(i >= 0, r.material);
        const glm::dvec3 f = s->materials()[size_t(i)].eval(sph(r.ti, r.pi), sph(r.to, r.po));
        for (int c = 0; c < 3; ++c) {
            INFO(r.material << " " << r.ti << " " << r.pi << " " << r.to << " " << r.po << " c" << c);
            CHECK(close_rel(f[c], r.rgb[c], 1e-5));
            worst = std::max(worst, std::fabs(f[c] - r.rgb[c]) / std::max(std::fabs(r.rgb[c]), 1e-12));
        }
    }
    // The same arithmetic in double: far tighter than the 1e-5 the issue asks.
    CHECK(worst < 1e-10);
}

TEST_CASE("nbrdf: matches nbrdf_eval.py run live (when python3 with numpy is present)") {
    std::string py;
    for (const char* cand : {"python3", "/usr/bin/python3"}) {
        if (sepal_test::run(std::string(cand) + " -c 'import numpy' > /dev/null 2>&1") == 0) {
            py = cand;
            break;
        }
    }
    if (py.empty()) {
        MESSAGE("python3 with numpy not found: the stored reference values stand in");
        return;
    }
    auto s = data_set();
    const std::string script = sepal_test::source_path("data/merl-nbrdf/nbrdf_eval.py");
    const std::string json = sepal_test::source_path("data/merl-nbrdf/merl-nbrdf.json");
    struct Q { const char* m; double ti, pi, to, po; };
    const Q qs[] = {{"gold-paint", 30, 0, 30, 180}, {"blue-metallic-paint", 40, 10, 35, 200},
                    {"nickel", 20, 0, 21, 181}, {"white-fabric", 70, 0, 10, 90},
                    {"two-layer-silver", 60, 30, 62, 205}};
    for (const Q& q : qs) {
        char cmd[1024];
        std::snprintf(cmd, sizeof cmd, "%s '%s' '%s' %s %g %g %g %g", py.c_str(), script.c_str(),
                      json.c_str(), q.m, q.ti, q.pi, q.to, q.po);
        std::string out;
        REQUIRE(sepal_test::run(cmd, &out) == 0);
        double v[3];
        REQUIRE(std::sscanf(out.c_str(), "%lf %lf %lf", &v[0], &v[1], &v[2]) == 3);
        const glm::dvec3 f = s->materials()[size_t(s->find(q.m))].eval(sph(q.ti, q.pi), sph(q.to, q.po));
        // The script prints 6 significant digits: 5e-6 relative rounding at most.
        for (int c = 0; c < 3; ++c) {
            INFO(q.m << " c" << c << " script " << v[c] << " ours " << f[c]);
            CHECK(close_rel(f[c], v[c], 1e-5));
        }
    }
}

TEST_CASE("nbrdf: spec nbrdf:NAME through make_brdf; unknown and empty names") {
    std::string err;
    auto f = sepal::make_brdf("nbrdf:gold-paint", &err);
    REQUIRE_MESSAGE(bool(f), err);
    CHECK(f->spec() == "nbrdf:gold-paint");
    CHECK(f->model() == "nbrdf");
    CHECK(f->isotropic());
    CHECK(f->info().find("gold-paint") != std::string::npos);
    const glm::dvec3 v = f->eval(sph(30, 0), sph(30, 180));
    CHECK(close_rel(v.x, 0.33670290515698609, 1e-9));
    auto g = sepal::make_brdf(f->spec(), &err);  // canonical spec round trip
    REQUIRE(bool(g));
    CHECK(g->eval(sph(40, 10), sph(20, 250)) == f->eval(sph(40, 10), sph(20, 250)));

    CHECK(!sepal::make_brdf("nbrdf:gold-pant", &err));
    CHECK(err.find("unknown material 'gold-pant'") != std::string::npos);
    CHECK(err.find("gold-paint") != std::string::npos);  // suggested
    CHECK(!sepal::make_brdf("nbrdf:", &err));
    CHECK(err.find("alum-bronze") != std::string::npos);  // the whole list
    CHECK(err.find("yellow-plastic") != std::string::npos);
}

TEST_CASE("nbrdf: physics of the fits: finite, non-negative, zero below the horizon, near-reciprocal") {
    auto s = data_set();
    sepal::SplitMix64 rng(7);  // the same numbers on every standard library
    auto u = [&](sepal::SplitMix64&) { return rng.uniform(); };
    double worst_recip = 0.0, gap2 = 0.0, mean2 = 0.0;
    size_t n = 0;
    for (const sepal::NbrdfMaterial& m : s->materials()) {
        for (int k = 0; k < 40; ++k) {
            const glm::dvec3 wi = sph(89.0 * u(rng), 360.0 * u(rng));
            const glm::dvec3 wo = sph(89.0 * u(rng), 360.0 * u(rng));
            const glm::dvec3 a = m.eval(wi, wo), b = m.eval(wo, wi);
            for (int c = 0; c < 3; ++c) {
                REQUIRE(std::isfinite(a[c]));
                CHECK(a[c] >= 0.0);
                const double r = std::fabs(a[c] - b[c]) / std::max(0.5 * (a[c] + b[c]), 1e-3);
                worst_recip = std::max(worst_recip, r);
                gap2 += (a[c] - b[c]) * (a[c] - b[c]);
                mean2 += 0.25 * (a[c] + b[c]) * (a[c] + b[c]);
            }
            ++n;
            const glm::dvec3 below(wi.x, wi.y, -wi.z);
            CHECK(m.eval(below, wo) == glm::dvec3(0.0));
            CHECK(m.eval(wo, below) == glm::dvec3(0.0));
        }
    }
    // Reciprocity is learned, not built in: a few grazing pairs are far apart (the worst is
    // reported), the energy of the gap is small.
    const double rel_rms = std::sqrt(gap2 / mean2);
    MESSAGE("reciprocity over " << n << " random pairs: relative RMS gap " << rel_rms
                                << ", worst single pair " << worst_recip);
    CHECK(rel_rms < 0.1);
}

TEST_CASE("nbrdf: the data-path rule (SEPAL_DATA_DIR, else data/ above the executable)") {
    std::string err;
    const char* old = std::getenv("SEPAL_DATA_DIR");
    const std::string saved = old ? old : "";
    unsetenv("SEPAL_DATA_DIR");
    const std::string found = sepal::nbrdf_data_path(&err);
    CHECK_MESSAGE(found.find("data/merl-nbrdf/merl-nbrdf.json") != std::string::npos, err);
    const std::string empty = sepal_test::temp_dir();
    setenv("SEPAL_DATA_DIR", empty.c_str(), 1);
    CHECK(sepal::nbrdf_data_path(&err).empty());
    CHECK(err.find("SEPAL_DATA_DIR is set but") != std::string::npos);
    CHECK(!sepal::make_brdf("nbrdf:gold-paint", &err));
    setenv("SEPAL_DATA_DIR", sepal_test::source_path("data").c_str(), 1);
    CHECK(bool(sepal::make_brdf("nbrdf:gold-paint", &err)));
    if (old) setenv("SEPAL_DATA_DIR", saved.c_str(), 1); else unsetenv("SEPAL_DATA_DIR");
}

TEST_CASE("nbrdf: broken files are refused with what and where") {
    {
        std::string err;
        auto s = sepal::NbrdfSet::parse(tiny(kTinyOk), "t.json", &err);
        REQUIRE_MESSAGE(bool(s), err);
        // x[0] = sin(theta_h) = 0 at normal incidence: every unit is 0, f = exp(0) - 1 = 0.
        CHECK(s->materials()[0].eval(sph(0, 0), sph(0, 0)) == glm::dvec3(0.0));
        const double x[6] = {0.5, 0, 0, 0, 0, 0};
        CHECK(close_rel(s->materials()[0].eval_input(x).y, std::exp(0.25) - 1.0, 1e-15));
    }
    CHECK(parse_error("{\"format\":").find("t.json: not valid JSON at line 1") == 0);
    CHECK(parse_error("[1,2]").find("top level") != std::string::npos);
    CHECK(parse_error(R"({"format":"x","layers":[6,1,1,3],"materials":{}})").find("format") != std::string::npos);
    CHECK(parse_error(R"({"format":"nbrdf-mlp-v1","layers":[6,1,3],"materials":{}})").find("layers") != std::string::npos);
    CHECK(parse_error(R"({"format":"nbrdf-mlp-v1","layers":[6,1000,1,3],"materials":{}})").find("hidden sizes") != std::string::npos);
    CHECK(parse_error(R"({"format":"nbrdf-mlp-v1","layers":[6,1,1,3],"materials":{}})").find("materials: none") != std::string::npos);
    const std::string no_w2 = parse_error(tiny(R"("w1":[[1],[0],[0],[0],[0],[0]],"b1":[0],"b2":[0],"w3":[[1,1,1]],"b3":[0,0,0])"));
    CHECK(no_w2 == "t.json: materials.m.w2: missing");
    const std::string short_w1 = parse_error(tiny(R"("w1":[[1],[0],[0],[0],[0]],"b1":[0],"w2":[[1]],"b2":[0],"w3":[[1,1,1]],"b3":[0,0,0])"));
    CHECK(short_w1.find("materials.m.w1: expected 6 x 1 numbers, found 5 rows") != std::string::npos);
    const std::string str_num = parse_error(tiny(R"("w1":[[1],[0],[0],[0],[0],["x"]],"b1":[0],"w2":[[1]],"b2":[0],"w3":[[1,1,1]],"b3":[0,0,0])"));
    CHECK(str_num.find("materials.m.w1[5][0]: expected a number, found string") != std::string::npos);
    const std::string huge = parse_error(tiny(R"("w1":[[1],[0],[0],[0],[0],[1e999]],"b1":[0],"w2":[[1]],"b2":[0],"w3":[[1,1,1]],"b3":[0,0,0])"));
    CHECK(huge == "t.json: not valid JSON: number overflow parsing '1e999'");
    const std::string big(17u << 20, ' ');
    CHECK(parse_error(big).find("over the limit") != std::string::npos);
    std::string err;
    CHECK(!sepal::load_nbrdf_set("/nonexistent/merl-nbrdf.json", &err));
    CHECK(err.find("/nonexistent/merl-nbrdf.json") != std::string::npos);
}

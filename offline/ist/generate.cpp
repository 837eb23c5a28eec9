#include "ist/generate.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>

#include "ist/ist_util.h"
#include "spec/spec.h"
#include "util/image.h"
#include "util/io.h"
#include "util/json.h"
#include "util/json.h"
#include "util/parallel.h"

namespace sepal {

using ist_detail::fail;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kGolden = 2.39996322972865332;  // golden angle, radians

double smoothstep(double e0, double e1, double x) {
    const double t = std::min(1.0, std::max(0.0, (x - e0) / (e1 - e0)));
    return t * t * (3 - 2 * t);
}

// Coverage of a shape whose signed distance (negative inside) is d, edge width e.
double cover(double d, double e) { return 1.0 - smoothstep(-0.5 * e, 0.5 * e, d); }

glm::dvec3 spherical(double theta, double phi) {
    return glm::dvec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
}

// Rotates `axis` by `angle` toward a direction at azimuth `around` about it.
glm::dvec3 cone_direction(const glm::dvec3& axis, double angle, double around) {
    const glm::dvec3 a = glm::normalize(axis);
    const glm::dvec3 helper = std::fabs(a.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0);
    const glm::dvec3 t = glm::normalize(glm::cross(helper, a)), s = glm::cross(a, t);
    return glm::normalize(std::cos(angle) * a + std::sin(angle) * (std::cos(around) * t + std::sin(around) * s));
}

double gaussian(uint64_t seed, uint64_t i) {
    const double u1 = counter_uniform(seed, 2 * i), u2 = counter_uniform(seed, 2 * i + 1);
    return std::sqrt(-2.0 * std::log(1.0 - u1)) * std::cos(2 * kPi * u2);
}

// Albedo weights of one view's lights: the solid angle of each light's cell in the
// nearest-light partition of the hemisphere, measured on a fixed 256 x 64 grid of equal
// solid-angle cells (uniform in cos(theta) and phi). Dense rings around a lobe get small
// cells, so the quadrature resolves the peak the lights were placed to catch.
void voronoi_weights(std::vector<DirPair>* pairs, size_t first) {
    const int nphi = 256, nz = 64;
    const double cell = 2 * kPi / (double(nphi) * nz);
    for (size_t p = first; p < pairs->size(); ++p) (*pairs)[p].albedo_weight = 0;
    for (int iz = 0; iz < nz; ++iz)
        for (int ip = 0; ip < nphi; ++ip) {
            const double z = (iz + 0.5) / nz, phi = 2 * kPi * (ip + 0.5) / nphi;
            const double r = std::sqrt(1 - z * z);
            const glm::dvec3 d(r * std::cos(phi), r * std::sin(phi), z);
            size_t best = first;
            double best_dot = -2;
            for (size_t p = first; p < pairs->size(); ++p) {
                const double c = glm::dot(d, (*pairs)[p].wi);
                if (c > best_dot) best_dot = c, best = p;
            }
            (*pairs)[best].albedo_weight += cell;
        }
}

}  // namespace

const std::vector<NamedBasis>& default_bases(const std::string& preset) {
    // Energy conserving (brdf_models.h's conditions; the MERL fits have albedos <= 0.36),
    // isotropic: the second level tabulates isotropic bases (tree.h).
    static const std::vector<NamedBasis> analytic = {
        {"blue paper", "oren-nayar:rho=0.1/0.2/0.55,sigma=0.35"},
        {"white paper", "oren-nayar:rho=0.82/0.8/0.74,sigma=0.25"},
        {"gold foil", "cook-torrance:d=0.1,Rd=0.8/0.55/0.15,s=0.75,F0=0.95/0.7/0.3,m=0.18"},
        {"silver foil", "ward:rho_d=0.04,rho_s=0.56/0.57/0.6,ax=0.12,ay=0.12"},
        {"green satin", "ashikhmin-shirley:Rd=0.1/0.4/0.15,Rs=0.06,nu=40,nv=40"},
        {"red velvet", "velvet:rho_d=0.25/0.03/0.04,rho_s=0.5/0.12/0.12,sigma=0.45"},
    };
    static const std::vector<NamedBasis> measured = {
        {"dark blue paint", "nbrdf:dark-blue-paint"},
        {"white paint", "nbrdf:white-paint"},
        {"gold metallic paint", "nbrdf:gold-metallic-paint"},
        {"silver metallic paint", "nbrdf:silver-metallic-paint"},
        {"green plastic", "nbrdf:green-plastic"},
        {"red fabric", "nbrdf:red-fabric"},
    };
    static const std::vector<NamedBasis> mixed = {analytic[0], measured[1], analytic[2],
                                                  measured[3], analytic[4], measured[5]};
    static const std::vector<NamedBasis> none;
    return preset == "analytic" ? analytic : preset == "measured" ? measured : preset == "mixed" ? mixed : none;
}

std::vector<DirPair> gantry_pairs(int views, int lights, int lobe_lights) {
    std::vector<DirPair> out;
    for (int v = 0; v < views; ++v) {
        const size_t first = out.size();
        const double theta_o = (10.0 + 50.0 * (v + 0.5) / views) * kPi / 180;
        const double phi_o = std::fmod(v * kGolden, 2 * kPi);
        const glm::dvec3 wo = spherical(theta_o, phi_o);
        // Uniform over the hemisphere's solid angle: z uniform in (0, 1].
        for (int i = 0; i < lights; ++i) {
            const double z = 1.0 - (i + 0.5) / lights;
            const double phi = i * kGolden + v * 0.7;
            const double r = std::sqrt(std::max(0.0, 1 - z * z));
            DirPair p;
            p.wi = glm::dvec3(r * std::cos(phi), r * std::sin(phi), z);
            p.wo = wo;
            p.view = v;
            out.push_back(p);
        }
        const glm::dvec3 mirror(-wo.x, -wo.y, wo.z);
        const int retro = lobe_lights / 4, lobe = lobe_lights - retro;
        static const double kRingsDeg[4] = {2, 5, 10, 18};
        for (int i = 0; i < lobe + retro; ++i) {
            const bool is_lobe = i < lobe;
            const int idx = is_lobe ? i : i - lobe, count = is_lobe ? lobe : retro;
            const int ring = count >= 4 ? idx % 4 : idx % std::max(1, count);
            const double angle = (is_lobe ? kRingsDeg[ring] : 4.0 + 6.0 * ring) * kPi / 180;
            const glm::dvec3 wi = cone_direction(is_lobe ? mirror : wo, angle, idx * kGolden + 0.3 * v);
            if (wi.z < 0.05) continue;
            DirPair p;
            p.wi = wi;
            p.wo = wo;
            p.view = v;
            out.push_back(p);
        }
        voronoi_weights(&out, first);
    }
    return out;
}

void card_weights(int materials, double u, double v, double e, double halftone, double* w) {
    const int k = materials;
    std::fill(w, w + k, 0.0);
    // Papers: a wavy boundary.
    const double boundary = 0.55 + 0.08 * std::sin(2 * kPi * 1.5 * u + 0.4);
    const double white = smoothstep(-0.5 * e, 0.5 * e, v - boundary);
    w[0] = 1 - white;
    w[1] = white;
    auto over = [&](int j, double alpha) {
        if (j >= k || alpha <= 0) return;
        for (int i = 0; i < k; ++i) w[i] *= 1 - alpha;
        w[j] += alpha;
    };
    // Gold: a border frame, halftone stripes on the white paper, a wide soft-edged plaque.
    const double edge = std::min({u, v, 1 - u, 1 - v});
    over(2, cover(edge - 0.07, e));
    const double stripe = std::fabs(std::fmod((u + v) * 7.0, 1.0) - 0.5) - 0.22;
    over(2, halftone * cover(stripe / 7.0, e) * white);
    const double plaque = std::max(std::fabs(u - 0.38) - 0.2, std::fabs(v - 0.3) - 0.08);
    over(2, cover(plaque, 3 * e));
    // Silver: disks, one of them overlapping the plaque.
    static const double kDisks[3][3] = {{0.72, 0.3, 0.11}, {0.25, 0.74, 0.08}, {0.58, 0.4, 0.05}};
    for (const auto& d : kDisks) over(3, cover(std::hypot(u - d[0], v - d[1]) - d[2], e));
    // Satin: a band across the lower right; velvet: a ring.
    over(4, 0.85 * cover(std::fabs(u - v + 0.35) - 0.06, 2 * e) * (u > 0.45 ? 1.0 : 0.0));
    over(5, cover(std::fabs(std::hypot(u - 0.7, v - 0.75) - 0.12) - 0.03, e));
}

bool generate_svbrdf(const GenerateOptions& o, SvbrdfSamples* out, BlendSvbrdf* truth, std::string* err) {
    if (o.width < 4 || o.height < 4 || o.width > SvbrdfSamples::kMaxSide || o.height > SvbrdfSamples::kMaxSide)
        return fail(err, "generate: size outside 4.." + std::to_string(SvbrdfSamples::kMaxSide));
    const std::vector<NamedBasis>& preset = default_bases(o.preset);
    if (o.bases.empty() && preset.empty())
        return fail(err, "generate: unknown preset '" + o.preset + "' (analytic, measured, mixed)");
    const int k = o.bases.empty() ? o.materials : int(o.bases.size());
    if (k < 2 || k > 6) return fail(err, "generate: 2..6 materials (got " + std::to_string(k) + ")");
    if (o.views < 1 || o.views > 64 || o.lights < 1 || o.lights > 512 || o.lobe_lights < 0 || o.lobe_lights > 256)
        return fail(err, "generate: views 1..64, lights 1..512, lobe lights 0..256");
    if (!(o.noise >= 0 && o.noise <= 1) || !(o.missing >= 0 && o.missing <= 0.95) ||
        !(o.misregistration >= 0 && o.misregistration <= 4) || !(o.halftone >= 0 && o.halftone <= 1))
        return fail(err, "generate: noise 0..1, missing 0..0.95, misregistration 0..4 texels, halftone 0..1");
    BlendSvbrdf t;
    for (int j = 0; j < k; ++j) {
        const std::string spec = o.bases.empty() ? preset[size_t(j)].spec : o.bases[size_t(j)];
        std::string why;
        std::unique_ptr<Brdf> b = make_brdf(spec, &why);
        if (!b) return fail(err, "generate: basis " + std::to_string(j) + ": " + why);
        t.names.push_back(o.bases.empty() ? preset[size_t(j)].name : b->model());
        t.specs.push_back(b->spec());
        t.basis.push_back(std::move(b));
    }
    const std::vector<DirPair> pairs = gantry_pairs(o.views, o.lights, o.lobe_lights);
    if (pairs.empty() || pairs.size() > size_t(SvbrdfSamples::kMaxPairs))
        return fail(err, "generate: " + std::to_string(pairs.size()) + " direction pairs, outside 1.." +
                             std::to_string(SvbrdfSamples::kMaxPairs));
    const int np = int(pairs.size()), w = o.width, h = o.height;
    // f_j at every pair, once.
    std::vector<glm::dvec3> f(size_t(k) * np);
    for (int j = 0; j < k; ++j)
        for (int p = 0; p < np; ++p) f[size_t(j) * np + p] = t.basis[size_t(j)]->eval(pairs[size_t(p)].wi, pairs[size_t(p)].wo);
    std::vector<glm::dvec2> shift(static_cast<size_t>(np));
    for (int p = 0; p < np; ++p)
        shift[size_t(p)] = o.misregistration *
                           glm::dvec2(2 * counter_uniform(o.seed ^ 0x5151, 2 * p) - 1, 2 * counter_uniform(o.seed ^ 0x5151, 2 * p + 1) - 1);
    const double edge = std::max(1.5 / std::min(w, h), 0.004);
    t.maps.width = w;
    t.maps.height = h;
    t.maps.count = k;
    t.maps.w.assign(size_t(w) * h * k, 0.0f);
    SvbrdfSamples s;
    s.resize(w, h, pairs);
    parallel_for(size_t(h), o.threads, [&](size_t row) {
        const int y = int(row);
        std::vector<double> wt(static_cast<size_t>(k));
        for (int x = 0; x < w; ++x) {
            const int texel = y * w + x;
            card_weights(k, (x + 0.5) / w, (y + 0.5) / h, edge, o.halftone, wt.data());
            for (int j = 0; j < k; ++j) t.maps.w[size_t(texel) * k + size_t(j)] = float(wt[size_t(j)]);
            for (int p = 0; p < np; ++p) {
                const glm::dvec2 sh = shift[size_t(p)];
                card_weights(k, (x + 0.5 + sh.x) / w, (y + 0.5 + sh.y) / h, edge, o.halftone, wt.data());
                glm::dvec3 v(0);
                for (int j = 0; j < k; ++j) v += wt[size_t(j)] * f[size_t(j) * np + p];
                const uint64_t id = (uint64_t(texel) * np + uint64_t(p)) * 3;
                for (int c = 0; c < 3; ++c) v[c] = std::max(0.0, v[c] * (1 + o.noise * gaussian(o.seed, id + c)));
                s.set(texel, p, v, 1.0f);
            }
        }
    });
    if (o.missing > 0) drop_samples(&s, o.missing, o.seed ^ 0x3a3a3a3aULL);
    *out = std::move(s);
    if (truth) *truth = std::move(t);
    return true;
}

bool write_truth(const std::string& dir, const BlendSvbrdf& t, std::string* err) {
    if (!make_dirs(dir + "/truth", err)) return false;
    Json j = Json::object();
    j["format"] = "sepal-svbrdf-truth";
    j["version"] = 1;
    Json& mats = j["materials"] = Json::array();
    for (int m = 0; m < t.maps.count; ++m) {
        Image img(t.maps.width, t.maps.height, 1);
        for (int i = 0; i < t.maps.width * t.maps.height; ++i) img.data[size_t(i)] = t.maps.at(i, m);
        const std::string name = "truth/blend" + std::to_string(m) + ".pfm";
        if (!write_pfm(dir + "/" + name, img, err)) return false;
        Json mat = Json::object();
        mat["name"] = t.names[size_t(m)];
        mat["spec"] = t.specs[size_t(m)];
        mat["blend"] = name;
        mats.push_back(std::move(mat));
    }
    return write_json_file(dir + "/truth.json", j, err);
}

bool read_truth(const std::string& dir, BlendSvbrdf* out, std::string* err) {
    const std::string path = dir + "/truth.json";
    Json root;
    if (!read_json_file(path, &root, err, 1u << 20)) return false;
    std::string fmt;
    int version = 0;
    std::string why;
    if (!json_string({root, path}, "format", &fmt, &why, true) || fmt != "sepal-svbrdf-truth" ||
        !json_int({root, path}, "version", 1, 1, &version, &why, true))
        return fail(err, path + ": not a sepal-svbrdf-truth file of version 1");
    const Json* mats = nullptr;
    if (!json_array({root, path}, "materials", 1, 16, &mats, err, true)) return false;
    BlendMaps blend;
    blend.count = int(mats->size());
    std::vector<std::string> names, specs;
    std::vector<Image> maps;
    for (size_t m = 0; m < mats->size(); ++m) {
        const JsonField e{(*mats)[m], path + ": materials[" + std::to_string(m) + "]"};
        std::string name, spec, blend;
        if (!json_string(e, "name", &name, err, true) || !json_string(e, "spec", &spec, err, true) ||
            !json_string(e, "blend", &blend, err, true))
            return false;
        Image img;
        if (!read_image(dir + "/" + blend, &img, err)) return false;
        if (!maps.empty() && (img.width != maps[0].width || img.height != maps[0].height))
            return fail(err, dir + "/" + blend + ": blend maps differ in size");
        names.push_back(name);
        specs.push_back(spec);
        maps.push_back(std::move(img));
    }
    blend.width = maps[0].width;
    blend.height = maps[0].height;
    blend.w.resize(size_t(blend.width) * blend.height * blend.count);
    for (int m = 0; m < blend.count; ++m)
        for (int i = 0; i < blend.width * blend.height; ++i)
            blend.w[size_t(i) * blend.count + m] = maps[size_t(m)].data[size_t(i) * maps[size_t(m)].channels];
    BlendSvbrdf t;
    if (!make_blend_svbrdf(std::move(blend), specs, &t, &why)) return fail(err, path + ": " + why);
    t.names = std::move(names);
    *out = std::move(t);
    return true;
}

}  // namespace sepal

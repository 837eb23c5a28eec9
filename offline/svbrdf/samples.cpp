#include "svbrdf/samples.h"

#include <cmath>
#include <cstdio>

#include "util/image.h"
#include "util/io.h"
#include "util/json.h"
#include "util/parallel.h"

namespace sepal {


namespace {

bool fail(std::string* err, const std::string& msg) {
    if (err) *err = msg;
    return false;
}

bool json_vec3(const JsonField& f, const char* key, glm::dvec3* out, std::string* err) {
    double v[3];
    if (!json_numbers(f, key, 3, v, err, true)) return false;
    *out = glm::dvec3(v[0], v[1], v[2]);
    return true;
}

bool unit_above(const glm::dvec3& w) {
    const double n = std::sqrt(w.x * w.x + w.y * w.y + w.z * w.z);
    return std::isfinite(n) && std::fabs(n - 1) < 1e-3 && w.z > 0;
}

std::string pair_file(const char* prefix, int p, const char* ext) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "pairs/%s%04d.%s", prefix, p, ext);
    return buf;
}

}  // namespace

void SvbrdfSamples::resize(int w, int h, const std::vector<DirPair>& p) {
    width = w;
    height = h;
    pairs = p;
    values.assign(size_t(w) * h * p.size() * 3, 0.0f);
    conf.assign(size_t(w) * h * p.size(), 1.0f);
}

bool validate_svbrdf(const SvbrdfSamples& s, std::string* err) {
    if (s.width < 1 || s.height < 1 || s.width > SvbrdfSamples::kMaxSide || s.height > SvbrdfSamples::kMaxSide)
        return fail(err, "svbrdf: size " + std::to_string(s.width) + "x" + std::to_string(s.height) +
                             " outside 1.." + std::to_string(SvbrdfSamples::kMaxSide));
    if (s.pairs.empty() || s.pair_count() > SvbrdfSamples::kMaxPairs)
        return fail(err, "svbrdf: " + std::to_string(s.pairs.size()) + " direction pairs, outside 1.." +
                             std::to_string(SvbrdfSamples::kMaxPairs));
    const size_t n = size_t(s.texels()) * s.pairs.size();
    if (s.values.size() != 3 * n || s.conf.size() != n)
        return fail(err, "svbrdf: value or confidence arrays do not match texels x pairs");
    for (int p = 0; p < s.pair_count(); ++p) {
        const DirPair& d = s.pairs[size_t(p)];
        if (!unit_above(d.wi) || !unit_above(d.wo))
            return fail(err, "svbrdf: pair " + std::to_string(p) +
                                 ": wi and wo must be unit vectors above the horizon (z > 0)");
        if (!(d.albedo_weight >= 0) || !std::isfinite(d.albedo_weight) || d.view < -1)
            return fail(err, "svbrdf: pair " + std::to_string(p) + ": bad view or albedo weight");
    }
    for (size_t i = 0; i < n; ++i) {
        const float c = s.conf[i];
        if (!(c >= 0 && c <= 1))
            return fail(err, "svbrdf: sample " + std::to_string(i) + ": confidence outside [0, 1]");
        if (c > 0)
            for (int k = 0; k < 3; ++k) {
                const float v = s.values[3 * i + size_t(k)];
                if (!(v >= 0) || !std::isfinite(v))
                    return fail(err, "svbrdf: texel " + std::to_string(i / s.pairs.size()) + ", pair " +
                                         std::to_string(i % s.pairs.size()) +
                                         ": value negative or not finite where the confidence is > 0");
            }
    }
    return true;
}

SvbrdfCounts count_samples(const SvbrdfSamples& s) {
    SvbrdfCounts c;
    c.samples = int64_t(s.conf.size());
    for (float x : s.conf) c.missing += x <= 0;
    return c;
}

bool read_svbrdf(const std::string& dir, SvbrdfSamples* out, std::string* err, SvbrdfCounts* counts,
                 const SvbrdfReadOptions& o) {
    const std::string json_path = dir + "/svbrdf.json";
    Json root;
    if (!read_json_file(json_path, &root, err, 1u << 20)) return false;
    const JsonField top{root, json_path};
    std::string fmt;
    int64_t version = 0;
    if (!json_string(top, "format", &fmt, err, true)) return false;
    if (fmt != "sepal-svbrdf") return fail(err, json_path + ": \"format\" must be \"sepal-svbrdf\", not \"" + fmt + "\"");
    if (!json_int(top, "version", 1, 1, &version, err, true)) return false;
    int w = 0, h = 0;
    if (!json_int(top, "width", 1, SvbrdfSamples::kMaxSide, &w, err, true) ||
        !json_int(top, "height", 1, SvbrdfSamples::kMaxSide, &h, err, true))
        return false;
    const Json* pairs = nullptr;
    if (!json_array(top, "pairs", 1, size_t(SvbrdfSamples::kMaxPairs), &pairs, err, true)) return false;
    const size_t np = pairs->size();
    const double mb = double(w) * h * double(np) * 16 / (1 << 20);
    if (mb > o.max_memory_mb) {
        char buf[256];
        std::snprintf(buf, sizeof buf, "%s: %dx%d texels x %zu pairs need %.0f MB, over the limit of %.0f MB",
                      json_path.c_str(), w, h, np, mb, o.max_memory_mb);
        return fail(err, buf);
    }
    std::vector<DirPair> dp(np);
    std::vector<std::string> images(np), confs(np);
    for (size_t p = 0; p < np; ++p) {
        const JsonField e{(*pairs)[p], json_path + ": pairs[" + std::to_string(p) + "]"};
        if (!json_vec3(e, "wi", &dp[p].wi, err) || !json_vec3(e, "wo", &dp[p].wo, err)) return false;
        if (!unit_above(dp[p].wi) || !unit_above(dp[p].wo))
            return fail(err, e.where + ": wi and wo must be unit vectors above the horizon (z > 0)");
        if (!json_string(e, "image", &images[p], err, true)) return false;
        if (images[p].empty()) return fail(err, e.where + ".image: empty (a PFM path is expected)");
        if (!json_string(e, "confidence", &confs[p], err)) return false;
        if (!json_int(e, "view", -1, 1 << 20, &dp[p].view, err)) return false;
        if (!json_number(e, "albedo_weight", 0, HUGE_VAL, &dp[p].albedo_weight, err)) return false;
    }
    SvbrdfSamples s;
    s.resize(w, h, dp);
    SvbrdfCounts cnt;
    cnt.samples = int64_t(s.conf.size());
    for (size_t p = 0; p < np; ++p) {
        Image img;
        const std::string path = dir + "/" + images[p];
        if (!read_image(path, &img, err)) return false;
        if (img.width != w || img.height != h || img.channels != 3)
            return fail(err, path + ": expected a " + std::to_string(w) + "x" + std::to_string(h) +
                                 " RGB float image (PFM), got " + std::to_string(img.width) + "x" +
                                 std::to_string(img.height) + "x" + std::to_string(img.channels));
        Image conf;
        if (!confs[p].empty()) {
            const std::string cpath = dir + "/" + confs[p];
            if (!read_image(cpath, &conf, err)) return false;
            if (conf.width != w || conf.height != h)
                return fail(err, cpath + ": confidence image size differs from " + std::to_string(w) + "x" +
                                     std::to_string(h));
        }
        for (int t = 0; t < w * h; ++t) {
            const int x = t % w, y = t / w;
            float c = conf.empty() ? 1.0f : conf.at(x, y, 0);
            glm::dvec3 v(img.at(x, y, 0), img.at(x, y, 1), img.at(x, y, 2));
            if (c > 0 && (v.x < 0 || v.y < 0 || v.z < 0)) {
                ++cnt.negative;
                c = 0;
            }
            if (c <= 0) v = glm::dvec3(0);
            s.set(t, int(p), v, std::min(1.0f, std::max(0.0f, c)));
        }
    }
    for (float c : s.conf) cnt.missing += c <= 0;
    if (counts) *counts = cnt;
    *out = std::move(s);
    return true;
}

bool write_svbrdf(const std::string& dir, const SvbrdfSamples& s, std::string* err) {
    if (!validate_svbrdf(s, err)) return false;
    if (!make_dirs(dir + "/pairs", err)) return false;
    Json j = Json::object();
    j["format"] = "sepal-svbrdf";
    j["version"] = 1;
    j["width"] = s.width;
    j["height"] = s.height;
    j["units"] = "BRDF values per steradian, linear RGB; cosine not included";
    Json& pairs = j["pairs"] = Json::array();
    const int np = s.pair_count();
    for (int p = 0; p < np; ++p) {
        const DirPair& d = s.pairs[size_t(p)];
        Image img(s.width, s.height, 3), conf(s.width, s.height, 1);
        bool partial = false;
        for (int t = 0; t < s.texels(); ++t) {
            const glm::dvec3 v = s.value(t, p);
            const float c = s.confidence(t, p);
            for (int k = 0; k < 3; ++k) img.data[size_t(t) * 3 + size_t(k)] = c > 0 ? float(v[k]) : 0.0f;
            conf.data[size_t(t)] = c;
            partial = partial || c < 1;
        }
        const std::string name = pair_file("p", p, "pfm");
        if (!write_pfm(dir + "/" + name, img, err)) return false;
        Json pj = Json::object();
        pj["wi"] = Json::array({d.wi.x, d.wi.y, d.wi.z});
        pj["wo"] = Json::array({d.wo.x, d.wo.y, d.wo.z});
        pj["image"] = name;
        if (partial) {
            const std::string cname = pair_file("c", p, "png");
            if (!write_png(dir + "/" + cname, conf, err)) return false;
            pj["confidence"] = cname;
        }
        if (d.view >= 0) pj["view"] = d.view;
        if (d.albedo_weight > 0) pj["albedo_weight"] = d.albedo_weight;
        pairs.push_back(std::move(pj));
    }
    return write_json_file(dir + "/svbrdf.json", j, err);
}

int64_t drop_samples(SvbrdfSamples* s, double share, uint64_t seed) {
    int64_t dropped = 0;
    for (size_t i = 0; i < s->conf.size(); ++i)
        if (s->conf[i] > 0 && counter_uniform(seed, i) < share) {
            s->conf[i] = 0;
            s->values[3 * i] = s->values[3 * i + 1] = s->values[3 * i + 2] = 0;
            ++dropped;
        }
    return dropped;
}

}  // namespace sepal

#include "sampling/environment.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "brdf/brdf_spec.h"
#include "brdf/brdf_util.h"
#include "util/image.h"
#include "util/io.h"

namespace sepal {
namespace {

using glm::dvec3;

class Constant final : public Environment {
  public:
    explicit Constant(const dvec3& v) : v_(v) {}
    dvec3 radiance(const dvec3&) const override { return v_; }
    std::string describe() const override { return "constant " + format_colour(v_); }
    bool constant(dvec3* value) const override {
        if (value) *value = v_;
        return true;
    }

  private:
    dvec3 v_;
};

class Sky final : public Environment {
  public:
    Sky(double elevation, double azimuth, double radius, double sun)
        : sun_dir_(dir_from_degrees(90.0 - elevation, azimuth)),
          cos_radius_(std::cos(deg2rad(radius))),
          sun_(sun),
          text_("sky: sun " + format_number(sun) + " at elevation " + format_number(elevation) + ", azimuth " +
                format_number(azimuth) + ", radius " + format_number(radius) + " degrees") {}
    dvec3 radiance(const dvec3& d) const override {
        if (glm::dot(d, sun_dir_) >= cos_radius_) return sun_ * dvec3(1.0, 0.95, 0.85);
        if (d.z < 0) return dvec3(0.15, 0.13, 0.11);
        const double t = std::sqrt(std::min(1.0, d.z));
        return (1 - t) * dvec3(1.0, 0.95, 0.9) + t * dvec3(0.3, 0.5, 1.0);
    }
    std::string describe() const override { return text_; }

  private:
    dvec3 sun_dir_;
    double cos_radius_, sun_;
    std::string text_;
};

class LatLong final : public Environment {
  public:
    LatLong(Image img, std::string path) : img_(std::move(img)), path_(std::move(path)) {}
    dvec3 radiance(const dvec3& d) const override {
        const double u = 0.5 + std::atan2(d.y, d.x) / (2 * kPi);
        const double v = std::acos(std::max(-1.0, std::min(1.0, d.z))) / kPi;
        const int x = std::min(img_.width - 1, std::max(0, int(u * img_.width)));
        const int y = std::min(img_.height - 1, std::max(0, int(v * img_.height)));
        return dvec3(img_.at(x, y, 0), img_.at(x, y, 1), img_.at(x, y, 2));
    }
    std::string describe() const override {
        return path_ + " (" + std::to_string(img_.width) + "x" + std::to_string(img_.height) + " lat-long)";
    }

  private:
    Image img_;
    std::string path_;
};

bool parse_colour_list(const std::string& s, dvec3* out) {
    std::vector<double> v;
    size_t start = 0;
    for (;;) {
        const size_t comma = s.find(',', start);
        double x = 0;
        if (!parse_finite(s.substr(start, comma - start), &x) || x < 0 || x > 1e6) return false;
        v.push_back(x);
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    if (v.size() == 1) *out = dvec3(v[0]);
    else if (v.size() == 3) *out = dvec3(v[0], v[1], v[2]);
    else return false;
    return true;
}

}  // namespace

std::unique_ptr<Environment> make_environment(const std::string& spec, std::string* err) {
    auto fail = [&](const std::string& m) {
        if (err) *err = m;
        return nullptr;
    };
    if (spec == "constant") return std::make_unique<Constant>(dvec3(1.0));
    if (spec.rfind("constant:", 0) == 0) {
        dvec3 c;
        if (!parse_colour_list(spec.substr(9), &c))
            return fail("environment '" + spec + "': constant takes V or R,G,B, each in [0, 1e6]");
        return std::make_unique<Constant>(c);
    }
    if (spec == "sky" || spec.rfind("sky:", 0) == 0) {
        double elevation = 35, azimuth = -60, radius = 4, sun = 100;
        if (spec.size() > 4) {
            std::string model;
            std::vector<SpecItem> items;
            if (!split_spec(spec, &model, &items, err)) return nullptr;
            for (const SpecItem& it : items) {
                double v = 0;
                if (!parse_finite(it.value, &v)) return fail("environment '" + spec + "': bad number for " + it.key);
                if (it.key == "elevation" && v >= -90 && v <= 90) elevation = v;
                else if (it.key == "azimuth" && v >= -360 && v <= 360) azimuth = v;
                else if (it.key == "radius" && v > 0 && v <= 90) radius = v;
                else if (it.key == "sun" && v >= 0 && v <= 1e7) sun = v;
                else
                    return fail("environment '" + spec + "': " + it.key +
                                " unknown or out of range (elevation -90..90, azimuth -360..360, radius (0, 90], "
                                "sun 0..1e7)");
            }
        }
        return std::make_unique<Sky>(elevation, azimuth, radius, sun);
    }
    if (file_extension(spec) == "hdr") {
        Image img;
        if (!read_hdr(spec, &img, err)) return nullptr;
        return std::make_unique<LatLong>(std::move(img), spec);
    }
    return fail("environment '" + spec + "': use constant[:V|:R,G,B], sky[:elevation=,azimuth=,radius=,sun=] or FILE.hdr");
}

namespace {
// The first index i with cdf[i + 1] > x (cdf non-decreasing from 0 to 1, n + 1 entries),
// skipping empty bins; x rescaled to [0,1) within the bin.
int pick_bin(const double* cdf, int n, double* x) {
    const double* it = std::upper_bound(cdf + 1, cdf + n + 1, *x);
    int i = std::min(n - 1, int(it - cdf) - 1);
    while (i > 0 && !(cdf[i + 1] > cdf[i])) --i;
    const double w = cdf[i + 1] - cdf[i];
    *x = w > 0 ? std::min(std::max((*x - cdf[i]) / w, 0.0), 1.0 - 1e-12) : 0.5;
    return i;
}
double luminance_of(const dvec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }
}  // namespace

bool EnvironmentSampler::build(const Environment& env, int width, int height, std::string* err) {
    if (width < 4 || width > 4096 || height < 2 || height > 2048) {
        if (err) *err = "environment sampler: grid " + std::to_string(width) + "x" + std::to_string(height) +
                        " outside 4..4096 x 2..2048";
        return false;
    }
    w_ = width, h_ = height;
    value_.assign(size_t(w_) * h_, 0.0);
    row_cdf_.assign(size_t(h_) + 1, 0.0);
    col_cdf_.assign(size_t(h_) * (w_ + 1), 0.0);
    constexpr int kSub = 4;
    const double dphi = 2 * kPi / w_;
    for (int r = 0; r < h_; ++r) {
        const double z0 = std::cos(kPi * r / h_), z1 = std::cos(kPi * (r + 1) / h_);
        double* cdf = &col_cdf_[size_t(r) * (w_ + 1)];
        for (int c = 0; c < w_; ++c) {
            double sum = 0;
            for (int a = 0; a < kSub; ++a)
                for (int b = 0; b < kSub; ++b) {
                    const double z = z0 + (a + 0.5) / kSub * (z1 - z0);
                    const double phi = -kPi + (c + (b + 0.5) / kSub) * dphi;
                    const double s = std::sqrt(std::max(0.0, 1 - z * z));
                    const double l = luminance_of(env.radiance(dvec3(s * std::cos(phi), s * std::sin(phi), z)));
                    sum += std::isfinite(l) && l > 0 ? l : 0.0;
                }
            const double v = sum / (kSub * kSub);
            value_[size_t(r) * w_ + c] = v;
            cdf[c + 1] = cdf[c] + v * dphi * (z0 - z1);
        }
        row_cdf_[size_t(r) + 1] = row_cdf_[size_t(r)] + cdf[w_];
        if (cdf[w_] > 0)
            for (int c = 1; c <= w_; ++c) cdf[c] /= cdf[w_];
    }
    norm_ = row_cdf_[size_t(h_)];
    if (!(norm_ > 0) || !std::isfinite(norm_)) {
        if (err) *err = "environment sampler: the environment is black (or not finite) everywhere";
        return false;
    }
    for (double& x : row_cdf_) x /= norm_;
    row_cdf_[size_t(h_)] = 1.0;
    return true;
}

dvec3 EnvironmentSampler::sample(double u0, double u1, double* pdf) const {
    const int r = pick_bin(row_cdf_.data(), h_, &u0);
    const int c = pick_bin(&col_cdf_[size_t(r) * (w_ + 1)], w_, &u1);
    const double z0 = std::cos(kPi * r / h_), z1 = std::cos(kPi * (r + 1) / h_);
    const double z = z0 + u0 * (z1 - z0);
    const double phi = -kPi + (c + u1) * 2 * kPi / w_;
    const double s = std::sqrt(std::max(0.0, 1 - z * z));
    if (pdf) *pdf = value_[size_t(r) * w_ + c] / norm_;
    return dvec3(s * std::cos(phi), s * std::sin(phi), z);
}

double EnvironmentSampler::pdf(const dvec3& d) const {
    if (w_ == 0) return 0;
    const double z = std::max(-1.0, std::min(1.0, d.z));
    const int r = std::min(h_ - 1, std::max(0, int(std::acos(z) / kPi * h_)));
    const int c = std::min(w_ - 1, std::max(0, int((std::atan2(d.y, d.x) + kPi) / (2 * kPi) * w_)));
    return value_[size_t(r) * w_ + c] / norm_;
}

}  // namespace sepal

#include "measured/cornell.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include <glm/geometric.hpp>

#include "brdf/cie.h"
#include "factor/factored.h"  // luminance
#include "fit/lafortune_fit.h"
#include "util/io.h"

namespace sepal {

namespace {

constexpr double kPi = 3.14159265358979323846;
// Angles at the limits are allowed a hair of rounding slack (files print 6 decimals).
constexpr double kAngleSlack = 1e-5;

glm::dvec3 spherical(double theta, double phi) {
    const double s = std::sin(theta);
    return glm::dvec3(s * std::cos(phi), s * std::sin(phi), std::cos(theta));
}

// Whitespace-separated tokens of one line, comment ('#' to the end) removed.
void tokenize(const std::string& line, std::vector<std::string>* tokens) {
    tokens->clear();
    const size_t hash = line.find('#');
    const size_t end = hash == std::string::npos ? line.size() : hash;
    size_t i = 0;
    while (i < end) {
        while (i < end && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
        size_t j = i;
        while (j < end && !std::isspace(static_cast<unsigned char>(line[j]))) ++j;
        if (j > i) tokens->push_back(line.substr(i, j - i));
        i = j;
    }
}

// Shortened and made printable for messages (a garbage line can be long or binary).
std::string quoted(const std::string& t) {
    std::string s = t.size() > 24 ? t.substr(0, 24) + "..." : t;
    for (char& c : s)
        if (!std::isprint(static_cast<unsigned char>(c))) c = '?';
    return "'" + s + "'";
}

// Tokens of the whole text that parse completely as numbers but not finite ones.
size_t count_nonfinite(const std::string& text) {
    size_t count = 0, pos = 0;
    std::vector<std::string> tok;
    while (pos < text.size()) {
        size_t nl = text.find('\n', pos);
        if (nl == std::string::npos) nl = text.size();
        tokenize(text.substr(pos, nl - pos), &tok);
        pos = nl + 1;
        for (const std::string& t : tok) {
            char* end = nullptr;
            const double v = std::strtod(t.c_str(), &end);
            if (end == t.c_str() + t.size() && !std::isfinite(v)) ++count;
        }
    }
    return count;
}

class CornellBrdf : public Brdf {
  public:
    CornellBrdf(std::string path, CornellData data)
        : path_(std::move(path)), data_(std::move(data)) {
        tabulate_cornell(data_.samples, &table_, CornellTabulation(), &base_);
        figures_ = cornell_figures(data_, table_);
    }
    glm::dvec3 eval(const glm::dvec3& wi, const glm::dvec3& wo) const override {
        return table_.eval(wi, wo);
    }
    std::string spec() const override { return path_; }
    std::string model() const override { return "cornell"; }
    InputCounts input_counts() const override {
        InputCounts c;
        c.values = int64_t(data_.lines * data_.wavelengths.size());
        c.negative = int64_t(data_.missing - data_.huge);  // lines with a negative value
        c.huge = int64_t(data_.huge) + int64_t(table_.rejected());  // the table's: 0 by now
        c.missing = int64_t(data_.missing);
        c.filled = int64_t(figures_.filled);
        c.clamped = int64_t(data_.clamped + data_.angles_clamped);
        return c;
    }
    bool isotropic() const override { return true; }
    bool scattered_samples(std::vector<BrdfSample>* out) const override {
        out->clear();
        out->reserve(data_.samples.size());
        for (const CornellSample& s : data_.samples) out->push_back({s.wi(), s.wo(), s.rgb, 1.0});
        return true;
    }
    std::string info() const override {
        const CornellFigures& f = figures_;
        char buf[512];
        std::string s;
        std::snprintf(buf, sizeof buf,
                      "file       %s\n"
                      "format     Cornell .brdf: %zu wavelengths %g..%g nm -> linear sRGB "
                      "(CIE 1931 2-degree, D65, flat 1 -> (1,1,1))\n",
                      path_.c_str(), data_.wavelengths.size(), data_.wavelengths.front(),
                      data_.wavelengths.back());
        s += buf;
        std::snprintf(buf, sizeof buf,
                      "samples    %zu lines, %zu used as scattered data\n"
                      "missing    %zu samples (a negative spectral value, or %zu beyond "
                      "1e30)\n"
                      "clamped    %zu negative RGB channel values (colours outside sRGB) set "
                      "to 0: %.2f%% of the summed |RGB|; %zu angles within rounding of [0, "
                      "pi/2] set to it\n",
                      data_.lines, data_.samples.size(), data_.missing, data_.huge, data_.clamped,
                      100.0 * data_.clamped_share, data_.angles_clamped);
        s += buf;
        std::snprintf(buf, sizeof buf,
                      "table      %d x %d x %d, MERL layout (theta_h sqrt-spaced, theta_d, "
                      "phi_d over [0, pi)) = %zu cells",
                      table_.n_theta_h(), table_.n_theta_d(), table_.n_phi_d(), f.cells);
        s += buf;
        if (base_.lobes == 0) {
            std::snprintf(buf, sizeof buf,
                          ", push-pull on log(1 + f)\n"
                          "coverage   %.2f%% of cells hold direct data (%zu: a sample or its phi_d "
                          "mirror); %zu filled by push-pull\n",
                          100.0 * f.measured / f.cells, f.measured, f.filled);
            s += buf;
        } else {
            s += ": a " + std::to_string(base_.lobes) + "-lobe Lafortune base times exp(residual)\nbase       " +
                 base_.spec + "\n";
            std::snprintf(buf, sizeof buf,
                          "residual   log(1 + f) - log(1 + base) over %d x %d x %d cells (theta_h, theta_d%s), "
                          "%.2f%% hold a sample (%zu), the rest filled by push-pull\n"
                          "coverage   %.2f%% of the table's cells hold a sample or its phi_d mirror (%zu)\n",
                          base_.residual_res[0], base_.residual_res[1], base_.residual_res[2],
                          base_.residual_res[2] == 1 ? "; phi_d from the base" : ", phi_d",
                          100.0 * base_.residual_measured /
                              (size_t(base_.residual_res[0]) * base_.residual_res[1] * base_.residual_res[2]),
                          base_.residual_measured, 100.0 * f.measured / f.cells, f.measured);
            s += buf;
        }
        std::snprintf(buf, sizeof buf,
                      "fit        relative RMS %.2f%% at the %zu sample positions (trilinear "
                      "lookup)\n"
                      "held out   relative RMS %.2f%% at %zu held-out samples (every 10th, "
                      "table rebuilt without them)\n",
                      100.0 * f.fit_rms, data_.samples.size(), 100.0 * f.holdout_rms,
                      f.holdout_count);
        s += buf;
        return s;
    }

  private:
    std::string path_;
    CornellData data_;
    Tabulated table_;
    CornellBase base_;
    CornellFigures figures_;
};

}  // namespace

glm::dvec3 CornellSample::wi() const { return spherical(theta_i, phi_i); }
glm::dvec3 CornellSample::wo() const { return spherical(theta_s, phi_s); }

bool parse_cornell(const std::string& text, const std::string& name, CornellData* out,
                   std::string* err) {
    *out = CornellData();
    size_t line_no = 0;
    auto fail = [&](const std::string& why) {
        if (err) *err = name + ":" + std::to_string(line_no) + ": " + why;
        return false;
    };
    if (text.empty()) {
        if (err) *err = name + ": empty file";
        return false;
    }
    enum { kCount, kWavelengths, kSamples } stage = kCount;
    size_t n_wl = 0;
    SpectrumToRgb conv;
    std::vector<std::string> tok;
    std::vector<double> num;
    double abs_total = 0.0, clamped_total = 0.0;
    size_t pos = 0;
    while (pos < text.size()) {
        size_t nl = text.find('\n', pos);
        if (nl == std::string::npos) nl = text.size();
        ++line_no;
        tokenize(text.substr(pos, nl - pos), &tok);
        pos = nl + 1;
        if (tok.empty()) continue;
        num.resize(tok.size());
        for (size_t k = 0; k < tok.size(); ++k) {
            char* end = nullptr;
            errno = 0;
            num[k] = std::strtod(tok[k].c_str(), &end);
            if (end != tok[k].c_str() + tok[k].size() || tok[k].empty())
                return fail(quoted(tok[k]) + " is not a number");
            if (!std::isfinite(num[k])) {
                // Refused, not treated as missing: the format marks missing samples with
                // negative values and has no other convention; NaN or inf means a broken
                // export. The message says how many there are, so one fix covers them all.
                const size_t n = count_nonfinite(text);
                return fail(quoted(tok[k]) + " is not a finite number (" + std::to_string(n) +
                            (n == 1 ? " NaN or inf value" : " NaN or inf values") +
                            " in the file, the first here)");
            }
        }
        if (stage == kCount) {
            if (tok.size() != 1)
                return fail("expected the number of wavelengths (one integer), found " +
                            std::to_string(tok.size()) + " values: is the header missing?");
            const double v = num[0];
            if (v != std::floor(v) || v < 1 || v > kCornellMaxWavelengths)
                return fail("number of wavelengths " + quoted(tok[0]) +
                            " is not an integer in 1.." +
                            std::to_string(kCornellMaxWavelengths));
            n_wl = size_t(v);
            stage = kWavelengths;
            continue;
        }
        if (stage == kWavelengths) {
            if (out->wavelengths.size() + num.size() > n_wl)
                return fail("more wavelength values than the " + std::to_string(n_wl) +
                            " announced (the list is short, or a sample line came early)");
            out->wavelengths.insert(out->wavelengths.end(), num.begin(), num.end());
            if (out->wavelengths.size() == n_wl) {
                std::string why;
                if (!conv.init(out->wavelengths, &why)) return fail(why);
                stage = kSamples;
            }
            continue;
        }
        if (tok.size() != 4 + n_wl)
            return fail("sample line has " + std::to_string(tok.size()) + " values, expected " +
                        std::to_string(4 + n_wl) + " (4 angles + " + std::to_string(n_wl) +
                        " spectral values)");
        if (out->lines >= kCornellMaxSamples)
            return fail("more than " + std::to_string(kCornellMaxSamples) + " samples");
        const char* names[4] = {"theta_i", "phi_i", "theta_s", "phi_s"};
        for (int k = 0; k < 4; ++k) {
            const bool theta = k % 2 == 0;
            const double lo = theta ? 0.0 : -2 * kPi, hi = theta ? kPi / 2 : 2 * kPi;
            if (num[k] < lo - kAngleSlack || num[k] > hi + kAngleSlack)
                return fail(std::string(names[k]) + " " + quoted(tok[k]) + " is outside " +
                            (theta ? "[0, pi/2]" : "[-2 pi, 2 pi]") + " (radians)");
        }
        ++out->lines;
        bool negative = false, huge = false;
        for (size_t k = 4; k < num.size(); ++k) {
            negative = negative || num[k] < 0.0;
            huge = huge || num[k] > kCornellHugeValue;
        }
        if (negative || huge) {
            ++out->missing;
            out->huge += huge && !negative ? 1 : 0;
            continue;
        }
        CornellSample s;
        // Inside the slack only (checked above): rounding of printed angles, counted.
        s.theta_i = std::max(0.0, std::min(kPi / 2, num[0]));
        s.phi_i = num[1];
        s.theta_s = std::max(0.0, std::min(kPi / 2, num[2]));
        s.phi_s = num[3];
        out->angles_clamped += size_t(s.theta_i != num[0]) + size_t(s.theta_s != num[2]);
        s.rgb = conv.convert(&num[4]);
        for (int c = 0; c < 3; ++c) {
            abs_total += std::fabs(s.rgb[c]);
            if (s.rgb[c] < 0.0) {
                clamped_total -= s.rgb[c];
                s.rgb[c] = 0.0;
                ++out->clamped;
            }
        }
        out->samples.push_back(s);
    }
    if (stage == kCount) return fail("no number of wavelengths: empty or comment-only file");
    if (stage == kWavelengths)
        return fail("the file ends inside the wavelength list (" +
                    std::to_string(out->wavelengths.size()) + " of " + std::to_string(n_wl) +
                    ")");
    if (out->lines == 0) return fail("no samples");
    if (out->samples.empty())
        return fail("every sample has a negative spectral value" +
                    std::string(out->huge ? " or one beyond 1e30" : ""));
    out->clamped_share = abs_total > 0.0 ? clamped_total / abs_total : 0.0;
    return true;
}

namespace {

// The base model of CornellTabulation::base_lobes: the most lobes up to `lobes` whose fit
// succeeds and stays plausible (no created energy where no sample constrains it).
bool fit_cornell_base(const std::vector<CornellSample>& samples, int lobes, LafortuneModel* model) {
    std::vector<BrdfSample> bs;
    bs.reserve(samples.size());
    // 1 / (1 + f): about relative error over the highlight, absolute below 1 /sr, as the
    // log(1 + f) residual the table then holds.
    for (const CornellSample& s : samples) bs.push_back({s.wi(), s.wo(), s.rgb, 1.0 / (1.0 + luminance(s.rgb))});
    for (int k = std::min(lobes, 4); k >= 1; --k) {
        LafortuneFitOptions o;
        o.lobes = k;
        o.forward = true;
        LafortuneFit fit;
        std::string err;
        if (!fit_lafortune(bs, o, &fit, &err)) continue;
        LafortuneModel m = fit.model;
        tint_lafortune_lobes(bs, &m);
        if (!lafortune_plausible(m)) continue;
        *model = m;
        return true;
    }
    return false;
}

glm::dvec3 log1p_of(const glm::dvec3& v) {
    return glm::dvec3(std::log1p(std::max(0.0, v.x)), std::log1p(std::max(0.0, v.y)), std::log1p(std::max(0.0, v.z)));
}

// The base at a cell's centre; a centre below the horizon (its cell is only blended into
// lookups at the horizon) is evaluated just above it.
glm::dvec3 base_at(const LafortuneModel& m, const HalfDiff& a) {
    glm::dvec3 wi, wo;
    from_half_diff(a, &wi, &wo);
    wi.z = std::max(wi.z, 1e-3);
    wo.z = std::max(wo.z, 1e-3);
    return m.eval(glm::normalize(wi), glm::normalize(wo));
}

}  // namespace

void tabulate_cornell(const std::vector<CornellSample>& samples, Tabulated* table,
                      const CornellTabulation& how, CornellBase* base) {
    if (!table->init(how.res[0], how.res[1], how.res[2], ThetaHMapping::kSqrt, nullptr))
        *table = Tabulated::merl();  // out-of-range settings: the default layout
    LafortuneModel model;
    const bool has_base = how.base_lobes > 0 && fit_cornell_base(samples, how.base_lobes, &model);
    // The residual's own table where its shape differs from the result's (an out-of-range
    // shape: the result's own cells).
    Tabulated coarse;
    const int shape[3] = {table->n_theta_h(), table->n_theta_d(), table->n_phi_d()};
    int rres[3];
    for (int k = 0; k < 3; ++k) rres[k] = how.residual_res[k] > 0 ? how.residual_res[k] : shape[k];
    const bool separate = has_base && !std::equal(rres, rres + 3, shape) &&
                          coarse.init(rres[0], rres[1], rres[2], table->mapping(), nullptr);
    Tabulated* resid = separate ? &coarse : table;
    // With a separate residual, the result's cells that hold a sample (or its mirror): they
    // count as measured, as the splats would have made them.
    std::vector<uint8_t> hit(separate ? table->size() : 0, 0);
    for (const CornellSample& s : samples) {
        HalfDiff a = to_half_diff(s.wi(), s.wo());
        const glm::dvec3 v = has_base ? log1p_of(s.rgb) - log1p_of(model.eval(s.wi(), s.wo())) : s.rgb;
        for (int copy = 0; copy < (how.mirror ? 2 : 1); ++copy) {
            if (copy == 1) a.phi_d = -a.phi_d;  // isotropy: the mirror configuration has the same value
            resid->splat(a, v, 1.0, Tabulated::Kernel::kNearest);
            if (separate) hit[table->cell_index(a)] = 1;
        }
    }
    resid->finish_splats();
    // The residual is a log already and may be negative: push-pull on it as it is.
    resid->fill_missing(has_base ? Tabulated::FillDomain::kLinear : how.domain);
    if (base) {
        *base = CornellBase{};
        if (has_base) {
            const Tabulated::Counts c = resid->counts();
            *base = CornellBase{int(model.lobes.size()), model.spec(), {resid->n_theta_h(), resid->n_theta_d(), resid->n_phi_d()},
                                c.measured};
        }
    }
    if (!has_base) return;
    for (size_t i = 0; i < table->size(); ++i) {
        const HalfDiff c = table->cell_center(i);
        glm::dvec3 r;
        float confidence;
        Tabulated::State state;
        if (separate) {
            if (!coarse.trilinear(c, &r)) continue;
            confidence = hit[i] ? 1.0f : 0.0f;
            state = hit[i] ? Tabulated::State::kMeasured : Tabulated::State::kFilled;
        } else {
            if (!table->usable(i)) continue;
            r = table->value(i), confidence = table->confidence(i), state = table->state(i);
        }
        const glm::dvec3 l = log1p_of(base_at(model, c)) + r;
        const glm::dvec3 f(std::max(0.0, std::expm1(l.x)), std::max(0.0, std::expm1(l.y)), std::max(0.0, std::expm1(l.z)));
        table->set(i, f, confidence, state);
    }
}

namespace {

// The table's squared errors at the samples and the samples' squared values, of f and of
// log(1 + f), added to the running sums: relative_rms's, pooled over folds.
struct ErrorSums {
    double num = 0, den = 0, log_num = 0, log_den = 0;
    void add(const Tabulated& table, const std::vector<CornellSample>& samples) {
        for (const CornellSample& s : samples) {
            const glm::dvec3 f = table.eval(s.wi(), s.wo()), d = f - s.rgb, ls = log1p_of(s.rgb), l = log1p_of(f) - ls;
            num += glm::dot(d, d);
            den += glm::dot(s.rgb, s.rgb);
            log_num += glm::dot(l, l);
            log_den += glm::dot(ls, ls);
        }
    }
    static double ratio(double n, double d) { return d > 0.0 ? std::sqrt(n / d) : 0.0; }
};

}  // namespace

double relative_rms(const Tabulated& table, const std::vector<CornellSample>& samples) {
    ErrorSums e;
    e.add(table, samples);
    return ErrorSums::ratio(e.num, e.den);
}

CornellCrossValidation cornell_cross_validation(const std::vector<CornellSample>& samples,
                                                const CornellTabulation& how, int folds) {
    CornellCrossValidation cv;
    if (folds < 2 || samples.size() < size_t(folds)) return cv;
    cv.folds = folds;
    ErrorSums e;
    for (int k = 0; k < folds; ++k) {
        std::vector<CornellSample> train, test;
        for (size_t i = 0; i < samples.size(); ++i) (int(i % size_t(folds)) == k ? test : train).push_back(samples[i]);
        Tabulated t;
        tabulate_cornell(train, &t, how);
        e.add(t, test);
    }
    cv.rms = ErrorSums::ratio(e.num, e.den);
    cv.log_rms = ErrorSums::ratio(e.log_num, e.log_den);
    return cv;
}

CornellFigures cornell_figures(const CornellData& data, const Tabulated& table,
                               const CornellTabulation& how) {
    CornellFigures f;
    const Tabulated::Counts c = table.counts();
    f.cells = table.size();
    f.occupied = c.occupied;
    f.measured = c.measured;
    f.filled = c.filled;
    f.fit_rms = relative_rms(table, data.samples);
    std::vector<CornellSample> train, test;
    for (size_t i = 0; i < data.samples.size(); ++i)
        (i % 10 == 9 ? test : train).push_back(data.samples[i]);
    if (!test.empty() && !train.empty()) {
        Tabulated t;
        tabulate_cornell(train, &t, how);
        f.holdout_rms = relative_rms(t, test);
        f.holdout_count = test.size();
    }
    return f;
}

std::unique_ptr<Brdf> make_cornell_brdf(const std::string& text, const std::string& path,
                                        std::string* err) {
    CornellData data;
    if (!parse_cornell(text, path, &data, err)) return nullptr;
    return std::make_unique<CornellBrdf>(path, std::move(data));
}

std::unique_ptr<Brdf> load_cornell_brdf(const std::string& path, std::string* err) {
    std::vector<uint8_t> bytes;
    if (!read_file(path, &bytes, err, 64u << 20)) return nullptr;
    return make_cornell_brdf(std::string(bytes.begin(), bytes.end()), path, err);
}

}  // namespace sepal

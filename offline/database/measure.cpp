#include "database/measure.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "brdf/brdf_spec.h"
#include "measured/merl.h"
#include "util/io.h"
#include "util/parallel.h"

namespace sepal {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kRadToDeg = 180.0 / kPi;

double azimuth_deg(const glm::dvec3& w) {
    double phi = std::atan2(w.y, w.x) * kRadToDeg;
    if (phi < 0.0) phi += 360.0;
    return phi;
}

// One standard normal per sample (Box-Muller on two counter-based uniforms).
double normal(uint64_t seed, uint64_t i) {
    const double u1 = 1.0 - counter_uniform(seed, 2 * i);  // (0, 1]
    const double u2 = counter_uniform(seed, 2 * i + 1);
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2);
}

}  // namespace

bool simulate_samples(const BrdfDatabase& db, const MeasurementPlan& plan, const Brdf& f,
                      double noise, uint64_t seed, std::vector<double>* values, std::string* err) {
    if (!(noise >= 0.0) || noise > 1.0) {
        if (err) *err = "simulate: noise " + std::to_string(noise) + " is outside 0..1";
        return false;
    }
    values->clear();
    for (size_t i = 0; i < plan.rows.size(); ++i) {
        glm::dvec3 wi, wo;
        plan_row_directions(db, plan.rows[i], &wi, &wo);
        const double v = f.eval(wi, wo)[int(plan.rows[i] % 3)];
        if (!std::isfinite(v)) {
            if (err) *err = "simulate: " + f.spec() + " is not finite at sample " + std::to_string(i);
            return false;
        }
        values->push_back(v);
    }
    add_noise(values, noise, seed);
    return true;
}

void add_noise(std::vector<double>* values, double noise, uint64_t seed) {
    if (noise == 0.0) return;
    for (size_t i = 0; i < values->size(); ++i)
        (*values)[i] = std::max(0.0, (*values)[i] * (1.0 + noise * normal(seed, i)));
}

bool write_samples_csv(const std::string& path, const BrdfDatabase& db, const MeasurementPlan& plan,
                       const std::vector<double>& values, const std::string& comment,
                       std::string* err) {
    if (values.size() != plan.rows.size()) {
        if (err) *err = path + ": " + std::to_string(values.size()) + " values for a plan of " +
                        std::to_string(plan.rows.size());
        return false;
    }
    std::string text = "# sepal measure samples: " + comment + "\n";
    text += "sample,cell,channel,theta_i,phi_i,theta_o,phi_o,value\n";
    char line[256];
    for (size_t i = 0; i < values.size(); ++i) {
        glm::dvec3 wi, wo;
        plan_row_directions(db, plan.rows[i], &wi, &wo);
        std::snprintf(line, sizeof line, "%zu,%u,%zu,%.6f,%.6f,%.6f,%.6f,%.9g\n", i,
                      db.grid_cell(plan.rows[i] / 3), plan.rows[i] % 3,
                      std::acos(std::min(1.0, wi.z)) * kRadToDeg, azimuth_deg(wi),
                      std::acos(std::min(1.0, wo.z)) * kRadToDeg, azimuth_deg(wo), values[i]);
        text += line;
    }
    return write_file_atomic(path, text.data(), text.size(), err);
}

bool read_samples_csv(const std::string& path, const BrdfDatabase& db, const MeasurementPlan& plan,
                      std::vector<double>* values, std::string* err) {
    std::vector<uint8_t> bytes;
    if (!read_file(path, &bytes, err, 64u << 20)) return false;
    const std::string text(bytes.begin(), bytes.end());
    values->clear();
    size_t pos = 0, line_no = 0;
    bool header = false;
    auto fail = [&](const std::string& why) {
        if (err) *err = path + ": line " + std::to_string(line_no) + ": " + why;
        return false;
    };
    while (pos < text.size()) {
        size_t end = text.find('\n', pos);
        if (end == std::string::npos) end = text.size();
        std::string line = text.substr(pos, end - pos);
        pos = end + 1;
        ++line_no;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (line.empty() || line[0] == '#') continue;
        if (!header) {
            if (line.compare(0, 14, "sample,cell,ch") != 0)
                return fail("expected the header 'sample,cell,channel,theta_i,phi_i,theta_o,phi_o,value'");
            header = true;
            continue;
        }
        double f[8];
        const char* p = line.c_str();
        for (int k = 0; k < 8; ++k) {
            char* e = nullptr;
            f[k] = std::strtod(p, &e);
            if (e == p || (k < 7 && *e != ',') || (k == 7 && *e != '\0'))
                return fail("expected 8 comma-separated numbers");
            p = e + (k < 7 ? 1 : 0);
        }
        const size_t i = values->size();
        if (i >= plan.rows.size())
            return fail("more samples than the plan's " + std::to_string(plan.rows.size()));
        const size_t row = plan.rows[i];
        if (f[0] != double(i) || f[1] != double(db.grid_cell(row / 3)) || f[2] != double(row % 3))
            return fail("sample " + std::to_string(i) + " is not the plan's (cell " +
                        std::to_string(db.grid_cell(row / 3)) + ", channel " +
                        std::to_string(row % 3) + "): samples and plan do not belong together");
        if (!std::isfinite(f[7])) return fail("value is not a finite number");
        if (std::fabs(f[7]) > kMaxSampleValue)
            return fail("value " + format_number(f[7]) + " is beyond +-" + format_number(kMaxSampleValue) +
                        " (1/sr): not a BRDF measurement");
        values->push_back(f[7]);
    }
    if (!header) {
        if (err) *err = path + ": no header line (not a sepal samples file)";
        return false;
    }
    if (values->size() != plan.rows.size()) {
        if (err) *err = path + ": " + std::to_string(values->size()) + " samples; the plan has " +
                        std::to_string(plan.rows.size());
        return false;
    }
    return true;
}

bool reconstruct(const BrdfDatabase& db, const MeasurementPlan& plan,
                 const std::vector<double>& values, const std::vector<uint8_t>& use,
                 const FitOptions& opt, DatabaseReconstruction* r, std::string* err) {
    *r = DatabaseReconstruction();
    if (!fit_combination(db, plan.rows, values, use, opt, &r->fit, err)) return false;
    r->values = fit_values(db, r->fit, &r->clamped);
    for (float& v : r->values) {
        if (!std::isfinite(v)) {
            if (err) *err = "reconstruct: the fitted combination is not finite (samples beyond the database's range)";
            return false;
        }
        v = std::max(v, 0.0f);
    }
    return true;
}

namespace {

Tabulated rows_table(const BrdfDatabase& db, const std::vector<float>& values) {
    Tabulated t = Tabulated::merl();
    for (size_t v = 0; v < db.valid_cells(); ++v)
        t.set(db.grid_cell(v), glm::dvec3(values[3 * v], values[3 * v + 1], values[3 * v + 2]));
    return t;
}

}  // namespace

bool write_reconstruction_merl(const std::string& path, const BrdfDatabase& db,
                               const DatabaseReconstruction& r, std::string* err) {
    if (!db.grid().is_merl()) {
        if (err) *err = path + ": a MERL file needs the database on MERL's 90 x 90 x 180 grid";
        return false;
    }
    return write_merl_table(path, rows_table(db, r.values), err);
}

std::unique_ptr<Brdf> rows_brdf(const BrdfDatabase& db, const std::vector<float>& values,
                                const std::string& name, std::string* err) {
    if (!db.grid().is_merl() || values.size() != db.rows()) {
        if (err) *err = name + ": a table needs the database on MERL's grid and 3 values per valid cell";
        return nullptr;
    }
    std::vector<uint8_t> bytes;
    if (!encode_merl_table(rows_table(db, values), &bytes, err)) return nullptr;
    return make_merl_brdf(bytes, name, err);
}

bool tabulate_rows(const BrdfDatabase& db, const Brdf& f, std::vector<float>* values,
                   std::string* err, int threads) {
    const size_t V = db.valid_cells();
    values->assign(3 * V, 0.0f);
    constexpr size_t kChunk = 4096;
    const size_t chunks = (V + kChunk - 1) / kChunk;
    std::vector<size_t> bad(chunks, size_t(-1));  // first bad cell per chunk
    parallel_for(chunks, threads, [&](size_t ch) {
        for (size_t v = ch * kChunk; v < std::min(V, (ch + 1) * kChunk); ++v) {
            glm::dvec3 wi, wo;
            from_half_diff(db.cell_center(db.grid_cell(v)), &wi, &wo);
            const glm::dvec3 x = f.eval(wi, wo);
            for (int c = 0; c < 3; ++c) {
                if ((!std::isfinite(x[c]) || x[c] < 0.0) && bad[ch] == size_t(-1)) bad[ch] = v;
                (*values)[3 * v + size_t(c)] = float(x[c]);
            }
        }
    });
    for (size_t b : bad) {
        if (b == size_t(-1)) continue;
        if (err) *err = f.spec() + ": a negative or non-finite value at database cell " +
                        std::to_string(db.grid_cell(b));
        return false;
    }
    return true;
}

bool exclude_mask(const BrdfDatabase& db, const std::vector<std::string>& names,
                  std::vector<uint8_t>* use, std::string* err) {
    use->assign(size_t(db.size()), 1);
    for (const std::string& n : names) {
        const int k = db.find(n);
        if (k < 0) {
            if (err) *err = "--exclude " + n + ": not a database material ('sepal info nbrdf:' lists them)";
            return false;
        }
        (*use)[size_t(k)] = 0;
    }
    return true;
}

}  // namespace sepal

#include "bake/cost_model.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "util/io.h"
#include "util/json.h"

namespace sepal {

double CostModel::predict(int passes, int terms, int64_t bytes) const {
    return base_ms + per_pass_ms * passes + per_term_ms * terms + per_kib_ms * (double(bytes) / 1024.0);
}

bool fit_cost_model(const std::vector<CostSample>& samples, CostModel* out, std::string* err) {
    std::vector<CostSample> s;
    for (const CostSample& c : samples)
        if (std::isfinite(c.ms) && c.ms > 0) s.push_back(c);
    if (s.size() < 2) {
        if (err) *err = "cost model: " + std::to_string(s.size()) + " usable measurements; at least 2 needed";
        return false;
    }
    const int n = int(s.size());
    Eigen::MatrixXd X(n, 4);
    Eigen::VectorXd y(n);
    for (int i = 0; i < n; ++i) {
        X(i, 0) = 1;
        X(i, 1) = s[size_t(i)].passes;
        X(i, 2) = s[size_t(i)].terms;
        X(i, 3) = double(s[size_t(i)].bytes) / 1024.0;
        y(i) = s[size_t(i)].ms;
    }
    // Every subset of the slopes: a non-negative least squares small enough to enumerate,
    // and deterministic (no iteration order or tolerance to tune).
    double best_sse = INFINITY;
    Eigen::Vector4d best = Eigen::Vector4d::Zero();
    for (int mask = 0; mask < 8; ++mask) {
        std::vector<int> cols = {0};
        for (int j = 0; j < 3; ++j)
            if (mask & (1 << j)) cols.push_back(j + 1);
        Eigen::MatrixXd A(n, int(cols.size()));
        for (size_t c = 0; c < cols.size(); ++c) A.col(int(c)) = X.col(cols[c]);
        const Eigen::VectorXd b = A.colPivHouseholderQr().solve(y);
        if (!b.allFinite() || b.minCoeff() < 0) continue;
        const double sse = (A * b - y).squaredNorm();
        if (sse < best_sse * (1 - 1e-12)) {
            best_sse = sse;
            best.setZero();
            for (size_t c = 0; c < cols.size(); ++c) best(cols[c]) = b(int(c));
        }
    }
    if (!std::isfinite(best_sse)) {
        if (err) *err = "cost model: no fit with non-negative coefficients";
        return false;
    }
    CostModel m = *out;
    m.base_ms = best(0), m.per_pass_ms = best(1), m.per_term_ms = best(2), m.per_kib_ms = best(3);
    std::vector<double> rel;
    for (const CostSample& c : s) rel.push_back(std::fabs(m.predict(c.passes, c.terms, c.bytes) - c.ms) / c.ms);
    std::nth_element(rel.begin(), rel.begin() + long(rel.size() / 2), rel.end());
    m.fit_error = rel[rel.size() / 2];
    m.rows = n;
    *out = m;
    return true;
}

const char* cost_model_backends() { return "gles1, gles2-fused, cpu"; }

bool default_cost_model(const std::string& backend, CostModel* out, std::string* err) {
    // From `make bench` (build/bench/tradeoff.json, "cost_models"; 280 frames per backend):
    // Mesa 22.3.6 llvmpipe on 2 cores, 512x512 frames of the default scene (sphere, one point
    // light), default bakes (radiance fit: a depth pre-pass and a diffuse pass in every frame);
    // docs/reference.md (the speed-accuracy trade) dates them and says why they are kept.
    // Re-measure on the target and pass the file to `sepal bake --timings`.
    struct Row {
        const char* backend;
        double base, pass, term, kib, fit;
        int rows;
    } static const kRows[] = {
        {"gles1", 4.35015, 2.75816, 1.15295, 0.00719515, 0.0513183, 280},
        {"gles2-fused", 10.5491, 0.0291996, 4.26548, 0.00400098, 0.0431036, 280},
        {"cpu", 28.5935, 0, 6.8691, 0.0839003, 0.164678, 280},
    };
    for (const Row& r : kRows)
        if (backend == r.backend) {
            CostModel m;
            m.backend = r.backend;
            m.device = "Mesa llvmpipe, 2 cores (built in)";
            m.width = m.height = 512;
            m.base_ms = r.base, m.per_pass_ms = r.pass, m.per_term_ms = r.term, m.per_kib_ms = r.kib;
            m.fit_error = r.fit;
            m.rows = r.rows;
            *out = m;
            return true;
        }
    if (err) *err = "cost model: no built-in model for backend '" + backend + "' (" + cost_model_backends() + ")";
    return false;
}

bool read_cost_model(const std::string& path, const std::string& backend, CostModel* out, std::string* err) {
    std::vector<uint8_t> bytes;
    return read_file(path, &bytes, err, kMaxJsonBytes) &&
           parse_cost_model(std::string(bytes.begin(), bytes.end()), path, backend, out, err);
}

bool parse_cost_model(const std::string& text, const std::string& path, const std::string& backend, CostModel* out,
                      std::string* err) {
    Json v;
    if (!parse_json(text, path, &v, err)) return false;
    const JsonField top{v, path + ":"};
    if (!v.is_object() || !v.contains("cost_models") || !v["cost_models"].is_array()) {
        if (err) *err = path + ": no \"cost_models\" array (write one with `make bench`)";
        return false;
    }
    const Json& models = v["cost_models"];
    for (size_t i = 0; i < models.size(); ++i) {
        const Json& m = models[i];
        if (!m.is_object() || !m.contains("backend") || m["backend"] != backend) continue;
        CostModel c;
        c.backend = backend;
        c.device = path;
        const JsonField f{m, path + ": cost_models[" + std::to_string(i) + "] ('" + backend + "')"};
        const std::pair<const char*, double*> fields[] = {{"base_ms", &c.base_ms},
                                                          {"per_pass_ms", &c.per_pass_ms},
                                                          {"per_term_ms", &c.per_term_ms},
                                                          {"per_kib_ms", &c.per_kib_ms},
                                                          {"fit_error", &c.fit_error}};
        for (const auto& field : fields)
            if (!json_number(f, field.first, 0.0, 1e9, field.second, err, /*required=*/true)) return false;
        if (!json_int(f, "rows", 0, 1 << 30, &c.rows, err) || !json_string(top, "device", &c.device, err))
            return false;
        if (v.contains("size")) {
            const Json& size = v["size"];
            int64_t w = 0, h = 0;
            if (!size.is_array() || size.size() != 2) {
                if (err) *err = path + ": \"size\" must be [width, height]";
                return false;
            }
            if (!json_to_int(size[0], path + ": size[0]", 1, 16384, &w, err) ||
                !json_to_int(size[1], path + ": size[1]", 1, 16384, &h, err))
                return false;
            c.width = int(w), c.height = int(h);
        }
        *out = c;
        return true;
    }
    if (err) *err = path + ": no cost model for backend '" + backend + "'";
    return false;
}

}  // namespace sepal

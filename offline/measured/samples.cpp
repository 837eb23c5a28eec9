#include "measured/samples.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "brdf/brdf_spec.h"
#include "measured/cornell.h"
#include "util/io.h"

namespace sepal {
namespace {
constexpr double kPi = 3.14159265358979323846;

std::vector<std::string> split_fields(const std::string& line) {
    std::vector<std::string> f;
    size_t pos = 0;
    while (true) {
        const size_t comma = line.find(',', pos);
        std::string item = line.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
        const size_t a = item.find_first_not_of(" \t\r"), b = item.find_last_not_of(" \t\r");
        f.push_back(a == std::string::npos ? "" : item.substr(a, b - a + 1));
        if (comma == std::string::npos) break;
        pos = comma + 1;
    }
    return f;
}
}  // namespace

glm::dvec3 direction_from_degrees(double theta, double phi) {
    const double t = theta * kPi / 180, p = phi * kPi / 180;
    return glm::dvec3(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
}

void degrees_from_direction(const glm::dvec3& w, double* theta, double* phi) {
    *theta = std::acos(std::max(-1.0, std::min(1.0, w.z))) * 180 / kPi;
    *phi = std::atan2(w.y, w.x) * 180 / kPi;
}

bool parse_brdf_samples(const std::string& text, const std::string& name, std::vector<BrdfSample>* out,
                        std::string* err) {
    std::istringstream in(text);
    std::string line;
    int line_no = 0;
    std::vector<std::string> header;
    int col[9];  // theta_i phi_i theta_o phi_o r g b value weight
    const char* names[9] = {"theta_i", "phi_i", "theta_o", "phi_o", "r", "g", "b", "value", "weight"};
    std::vector<BrdfSample> s;
    auto fail = [&](const std::string& why) {
        if (err) *err = name + ":" + std::to_string(line_no) + ": " + why;
        return false;
    };
    while (std::getline(in, line)) {
        ++line_no;
        const size_t first = line.find_first_not_of(" \t\r");
        if (first == std::string::npos || line[first] == '#') continue;
        const std::vector<std::string> f = split_fields(line);
        if (header.empty()) {
            header = f;
            for (int k = 0; k < 9; ++k) {
                col[k] = -1;
                for (size_t i = 0; i < f.size(); ++i)
                    if (f[i] == names[k]) col[k] = int(i);
            }
            for (int k = 0; k < 4; ++k)
                if (col[k] < 0) return fail(std::string("the header has no '") + names[k] + "' column");
            const bool rgb = col[4] >= 0 && col[5] >= 0 && col[6] >= 0;
            if (!rgb && col[7] < 0) return fail("the header needs r, g, b or value columns");
            if (col[7] >= 0 && std::find(f.begin(), f.end(), std::string("channel")) != f.end())
                return fail("one channel per line (the database's samples.csv) is not a BRDF sample: fit needs r, g, b or grey values");
            continue;
        }
        if (f.size() != header.size())
            return fail(std::to_string(f.size()) + " fields, the header has " + std::to_string(header.size()));
        if (s.size() >= kMaxBrdfSamples) return fail("more than " + std::to_string(kMaxBrdfSamples) + " samples");
        double v[9] = {0, 0, 0, 0, 0, 0, 0, 0, 1};
        for (int k = 0; k < 9; ++k) {
            if (col[k] < 0) continue;
            if (!parse_finite(f[size_t(col[k])], &v[k]))
                return fail(std::string("'") + names[k] + "' is not a finite number: '" + f[size_t(col[k])] + "'");
        }
        if (v[0] < 0 || v[0] > 90 || v[2] < 0 || v[2] > 90) return fail("theta outside [0, 90] degrees");
        if (v[8] < 0) return fail("negative weight");
        BrdfSample x;
        x.wi = direction_from_degrees(v[0], v[1]);
        x.wo = direction_from_degrees(v[2], v[3]);
        x.value = col[4] >= 0 && col[5] >= 0 && col[6] >= 0 ? glm::dvec3(v[4], v[5], v[6]) : glm::dvec3(v[7]);
        x.weight = v[8];
        s.push_back(x);
    }
    if (header.empty()) return fail("no header line");
    if (s.empty()) return fail("no samples");
    *out = std::move(s);
    return true;
}

bool read_brdf_samples(const std::string& path, std::vector<BrdfSample>* out, std::string* err) {
    std::vector<uint8_t> bytes;
    if (!read_file(path, &bytes, err, uint64_t(256) << 20)) return false;
    const std::string text(bytes.begin(), bytes.end());
    if (file_extension(path) == "brdf") {
        CornellData d;
        if (!parse_cornell(text, path, &d, err)) return false;
        out->clear();
        for (const CornellSample& c : d.samples) {
            BrdfSample x;
            x.wi = c.wi();
            x.wo = c.wo();
            x.value = c.rgb;
            out->push_back(x);
        }
        return true;
    }
    return parse_brdf_samples(text, path, out, err);
}

bool write_brdf_samples(const std::string& path, const std::vector<BrdfSample>& samples, const std::string& comment,
                        std::string* err, const std::vector<std::string>& extra_names,
                        const std::vector<std::vector<double>>& extra_values) {
    std::string text = "# " + comment + "\n";
    for (const std::string& n : extra_names) text += n + ",";
    text += "theta_i,phi_i,theta_o,phi_o,r,g,b,weight\n";
    char buf[256];
    for (size_t i = 0; i < samples.size(); ++i) {
        for (size_t k = 0; k < extra_names.size(); ++k) {
            std::snprintf(buf, sizeof buf, "%.9g,", extra_values[k][i]);
            text += buf;
        }
        double ti, pi, to, po;
        degrees_from_direction(samples[i].wi, &ti, &pi);
        degrees_from_direction(samples[i].wo, &to, &po);
        const glm::dvec3& v = samples[i].value;
        std::snprintf(buf, sizeof buf, "%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", ti, pi, to, po, v.x, v.y, v.z,
                      samples[i].weight);
        text += buf;
    }
    return write_file_atomic(path, text.data(), text.size(), err);
}

}  // namespace sepal

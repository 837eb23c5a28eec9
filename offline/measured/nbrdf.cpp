#include "measured/nbrdf.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <mutex>

#include <nlohmann/json.hpp>

#include "util/io.h"

namespace sepal {

namespace {

constexpr uint64_t kMaxFileBytes = 16u << 20;
constexpr int kMaxHidden = 256;
const char* const kSpecPrefix = "nbrdf:";

// Rodrigues rotation of v about a unit axis by angle a: nbrdf_eval.py's rot(), term by term.
glm::dvec3 rodrigues(const glm::dvec3& v, const glm::dvec3& axis, double a) {
    const double c = std::cos(a), s = std::sin(a);
    const double ad = axis.x * v.x + axis.y * v.y + axis.z * v.z;
    const glm::dvec3 cr(axis.y * v.z - axis.z * v.y, axis.z * v.x - axis.x * v.z,
                        axis.x * v.y - axis.y * v.x);
    return v * c + axis * ad * (1.0 - c) + cr * s;
}

uint64_t fnv1a64(const std::string& s) {
    uint64_t h = 1469598103934665603ULL;
    for (unsigned char c : s) {
        h ^= c;
        h *= 1099511628211ULL;
    }
    return h;
}

// "line L, column C" of a byte offset (nlohmann reports bytes).
std::string text_position(const std::string& text, size_t byte) {
    size_t line = 1, col = 1;
    for (size_t i = 0; i < byte && i < text.size(); ++i) {
        if (text[i] == '\n') {
            ++line;
            col = 1;
        } else {
            ++col;
        }
    }
    return "line " + std::to_string(line) + ", column " + std::to_string(col);
}

// Reads a rows x cols matrix (cols == 0: a vector of rows numbers) into out, row-major.
bool read_array(const nlohmann::ordered_json& m, const std::string& where, const char* key, int rows,
                int cols, std::vector<double>* out, std::string* err) {
    const std::string at = where + "." + key;
    auto fail = [&](const std::string& why) {
        *err = at + ": " + why;
        return false;
    };
    auto it = m.find(key);
    if (it == m.end()) return fail("missing");
    const nlohmann::ordered_json& a = *it;
    const std::string shape =
        cols ? std::to_string(rows) + " x " + std::to_string(cols) : std::to_string(rows);
    if (!a.is_array() || a.size() != size_t(rows))
        return fail("expected " + shape + " numbers, found " +
                    (a.is_array() ? std::to_string(a.size()) + " rows" : std::string(a.type_name())));
    out->clear();
    out->reserve(size_t(rows) * (cols ? cols : 1));
    auto number = [&](const nlohmann::ordered_json& v, const std::string& vat) {
        if (!v.is_number()) {
            *err = vat + ": expected a number, found " + v.type_name();
            return false;
        }
        const double d = v.get<double>();
        if (!std::isfinite(d)) {
            *err = vat + ": not a finite number";
            return false;
        }
        out->push_back(d);
        return true;
    };
    for (int r = 0; r < rows; ++r) {
        const std::string rat = at + "[" + std::to_string(r) + "]";
        if (!cols) {
            if (!number(a[size_t(r)], rat)) return false;
            continue;
        }
        const nlohmann::ordered_json& row = a[size_t(r)];
        if (!row.is_array() || row.size() != size_t(cols))
            return fail("expected " + shape + " numbers; row " + std::to_string(r) + " has " +
                        (row.is_array() ? std::to_string(row.size()) : std::string(row.type_name())));
        for (int c = 0; c < cols; ++c)
            if (!number(row[size_t(c)], rat + "[" + std::to_string(c) + "]")) return false;
    }
    return true;
}

bool file_exists(const std::string& p) {
    FILE* f = std::fopen(p.c_str(), "rb");
    if (!f) return false;
    std::fclose(f);
    return true;
}

class NbrdfBrdf : public Brdf {
  public:
    NbrdfBrdf(std::shared_ptr<const NbrdfSet> set, int index)
        : set_(std::move(set)), m_(&set_->materials()[size_t(index)]) {}
    glm::dvec3 eval(const glm::dvec3& wi, const glm::dvec3& wo) const override {
        return m_->eval(wi, wo);
    }
    std::string spec() const override { return kSpecPrefix + m_->name(); }
    std::string model() const override { return "nbrdf"; }
    bool isotropic() const override { return true; }
    std::string info() const override {
        return "material   " + m_->name() +
               " (MERL database, Matusik et al. 2003)\n"
               "model      neural fit 6-21-21-3 MLP (Sztrajman et al. 2021), evaluated in double\n"
               "file       " + set_->path() + "\nsource     " + set_->source() + "\n";
    }

  private:
    std::shared_ptr<const NbrdfSet> set_;  // keeps m_ alive
    const NbrdfMaterial* m_;
};

}  // namespace

void nbrdf_input(const glm::dvec3& wi, const glm::dvec3& wo, double x[6]) {
    glm::dvec3 h = wi + wo;
    const double len = std::sqrt(h.x * h.x + h.y * h.y + h.z * h.z);
    h = len > 0.0 ? h / len : glm::dvec3(0, 0, 1);
    const double th = std::atan2(std::hypot(h.x, h.y), h.z);
    const double ph = std::atan2(h.y, h.x);
    const glm::dvec3 d =
        rodrigues(rodrigues(wi, glm::dvec3(0, 0, 1), -ph), glm::dvec3(0, 1, 0), -th);
    x[0] = std::sin(th);
    x[1] = 0.0;
    x[2] = std::cos(th);
    x[3] = d.x;
    x[4] = d.y;
    x[5] = d.z;
}

glm::dvec3 NbrdfMaterial::eval_input(const double x[6]) const {
    double a1[kMaxHidden], a2[kMaxHidden];
    for (int j = 0; j < h1_; ++j) a1[j] = 0.0;
    for (int i = 0; i < 6; ++i) {
        const double* w = &w1_[size_t(i) * h1_];
        for (int j = 0; j < h1_; ++j) a1[j] += x[i] * w[j];
    }
    for (int j = 0; j < h1_; ++j) a1[j] = std::max(a1[j] + b1_[size_t(j)], 0.0);
    for (int j = 0; j < h2_; ++j) a2[j] = 0.0;
    for (int i = 0; i < h1_; ++i) {
        if (a1[i] == 0.0) continue;  // relu zeros: a sum of exact zeros either way
        const double* w = &w2_[size_t(i) * h2_];
        for (int j = 0; j < h2_; ++j) a2[j] += a1[i] * w[j];
    }
    for (int j = 0; j < h2_; ++j) a2[j] = std::max(a2[j] + b2_[size_t(j)], 0.0);
    double z[3] = {0.0, 0.0, 0.0};
    for (int i = 0; i < h2_; ++i)
        for (int c = 0; c < 3; ++c) z[c] += a2[i] * w3_[size_t(i) * 3 + c];
    glm::dvec3 f;
    // exp(z) - 1, not expm1: the reference evaluator's formula, bit for bit where it matters.
    for (int c = 0; c < 3; ++c) f[c] = std::max(std::exp(z[c] + b3_[size_t(c)]) - 1.0, 0.0);
    return f;
}

glm::dvec3 NbrdfMaterial::eval(const glm::dvec3& wi, const glm::dvec3& wo) const {
    if (!(wi.z > 0.0) || !(wo.z > 0.0)) return glm::dvec3(0.0);
    double x[6];
    nbrdf_input(wi, wo, x);
    return eval_input(x);
}

std::shared_ptr<const NbrdfSet> NbrdfSet::parse(const std::string& text, const std::string& name,
                                                std::string* err) {
    std::string e;
    auto fail = [&](const std::string& why) -> std::shared_ptr<const NbrdfSet> {
        if (err) *err = name + ": " + why;
        return nullptr;
    };
    if (text.size() > kMaxFileBytes)
        return fail("file of " + std::to_string(text.size()) + " bytes is over the limit of " +
                    std::to_string(kMaxFileBytes));
    nlohmann::ordered_json j;
    try {
        j = nlohmann::ordered_json::parse(text);
    } catch (const nlohmann::json::parse_error& ex) {
        // ex.what() is "[json.exception.parse_error.101] parse error at line ..": keep the
        // part after the library's prefix.
        std::string what = ex.what();
        const size_t colon = what.find(": ");
        if (colon != std::string::npos) what = what.substr(colon + 2);
        return fail("not valid JSON at " + text_position(text, ex.byte ? ex.byte - 1 : 0) +
                    " (byte " + std::to_string(ex.byte) + "): " + what);
    } catch (const nlohmann::json::exception& ex) {
        std::string what = ex.what();  // "[json.exception.out_of_range.406] number overflow .."
        const size_t bracket = what.find("] ");
        if (bracket != std::string::npos) what = what.substr(bracket + 2);
        return fail("not valid JSON: " + what);
    }
    if (!j.is_object()) return fail("expected a JSON object at the top level");
    auto fmt = j.find("format");
    if (fmt == j.end() || !fmt->is_string() || fmt->get<std::string>() != "nbrdf-mlp-v1")
        return fail("format: expected \"nbrdf-mlp-v1\"" +
                    (fmt == j.end() ? std::string(" (missing)") : ", found " + fmt->dump()));
    auto layers = j.find("layers");
    if (layers == j.end() || !layers->is_array() || layers->size() != 4)
        return fail("layers: expected [6, H1, H2, 3]");
    int l[4];
    for (int k = 0; k < 4; ++k) {
        const nlohmann::ordered_json& v = (*layers)[size_t(k)];
        if (!v.is_number_integer()) return fail("layers: expected 4 integers");
        const int64_t n = v.get<int64_t>();
        l[k] = int(std::max<int64_t>(-1, std::min<int64_t>(n, 1 << 20)));
    }
    if (l[0] != 6 || l[3] != 3 || l[1] < 1 || l[1] > kMaxHidden || l[2] < 1 || l[2] > kMaxHidden)
        return fail("layers: [" + std::to_string(l[0]) + ", " + std::to_string(l[1]) + ", " +
                    std::to_string(l[2]) + ", " + std::to_string(l[3]) +
                    "] is not [6, H1, H2, 3] with hidden sizes 1.." + std::to_string(kMaxHidden));
    auto mats = j.find("materials");
    if (mats == j.end() || !mats->is_object()) return fail("materials: expected an object");
    if (mats->empty()) return fail("materials: none");
    auto set = std::make_shared<NbrdfSet>();
    set->path_ = name;
    set->hash_ = fnv1a64(text);
    auto src = j.find("source");
    if (src != j.end() && src->is_string()) set->source_ = src->get<std::string>();
    for (auto it = mats->begin(); it != mats->end(); ++it) {
        const std::string where = "materials." + it.key();
        if (it.key().empty() || it.key().find_first_of(" :,\t\n") != std::string::npos)
            return fail(where + ": a material name must be non-empty, without spaces, ':' or ','");
        if (!it->is_object()) return fail(where + ": expected an object of weights");
        NbrdfMaterial m;
        m.name_ = it.key();
        m.h1_ = l[1];
        m.h2_ = l[2];
        if (!read_array(*it, where, "w1", 6, l[1], &m.w1_, &e) ||
            !read_array(*it, where, "b1", l[1], 0, &m.b1_, &e) ||
            !read_array(*it, where, "w2", l[1], l[2], &m.w2_, &e) ||
            !read_array(*it, where, "b2", l[2], 0, &m.b2_, &e) ||
            !read_array(*it, where, "w3", l[2], 3, &m.w3_, &e) ||
            !read_array(*it, where, "b3", 3, 0, &m.b3_, &e))
            return fail(e);
        set->materials_.push_back(std::move(m));
    }
    return set;
}

int NbrdfSet::find(const std::string& name) const {
    for (size_t i = 0; i < materials_.size(); ++i)
        if (materials_[i].name() == name) return int(i);
    return -1;
}

std::vector<std::string> NbrdfSet::names() const {
    std::vector<std::string> n;
    for (const NbrdfMaterial& m : materials_) n.push_back(m.name());
    return n;
}

std::string nbrdf_data_path(std::string* err) {
    const std::string rel = "merl-nbrdf/merl-nbrdf.json";
    if (const char* env = std::getenv("SEPAL_DATA_DIR")) {
        if (*env) {
            const std::string p = std::string(env) + "/" + rel;
            if (file_exists(p)) return p;
            if (err) *err = "SEPAL_DATA_DIR is set but " + p + " does not exist";
            return "";
        }
    }
    // A checkout's data/ (build/bin/sepal), or an installed tree's share/sepal/
    // (PREFIX/bin/sepal with make install's PREFIX/share/sepal/merl-nbrdf).
    std::string dir = executable_dir(), tried;
    for (int up = 0; up < 8 && !dir.empty(); ++up) {
        for (const char* sub : {"/data/", "/share/sepal/"}) {
            const std::string p = dir + sub + rel;
            if (file_exists(p)) return p;
            tried += (tried.empty() ? "" : ", ") + dir + sub;
        }
        const size_t slash = dir.rfind('/');
        if (slash == std::string::npos) break;
        dir = dir.substr(0, slash);
    }
    if (err)
        *err = "cannot find " + rel + ": set SEPAL_DATA_DIR to the folder holding merl-nbrdf/ "
               "(a sepal checkout's data/, or an installed PREFIX/share/sepal/); looked in " + (tried.empty() ? "(no executable path)" : tried);
    return "";
}

std::shared_ptr<const NbrdfSet> load_nbrdf_set(const std::string& path, std::string* err) {
    static std::mutex mu;
    static std::map<std::string, std::shared_ptr<const NbrdfSet>> cache;
    std::lock_guard<std::mutex> lock(mu);
    auto it = cache.find(path);
    if (it != cache.end()) return it->second;
    std::vector<uint8_t> bytes;
    if (!read_file(path, &bytes, err, kMaxFileBytes)) return nullptr;
    std::shared_ptr<const NbrdfSet> s =
        NbrdfSet::parse(std::string(bytes.begin(), bytes.end()), path, err);
    if (s) cache[path] = s;
    return s;
}

std::shared_ptr<const NbrdfSet> load_default_nbrdf_set(std::string* err) {
    const std::string path = nbrdf_data_path(err);
    if (path.empty()) return nullptr;
    return load_nbrdf_set(path, err);
}

std::unique_ptr<Brdf> make_nbrdf_brdf(const std::string& spec, std::string* err) {
    const std::string prefix = kSpecPrefix;
    if (spec.compare(0, prefix.size(), prefix) != 0) {
        if (err) *err = "'" + spec + "' is not an nbrdf spec (nbrdf:NAME)";
        return nullptr;
    }
    const std::string name = spec.substr(prefix.size());
    std::shared_ptr<const NbrdfSet> set = load_default_nbrdf_set(err);
    if (!set) return nullptr;
    if (name.empty()) {
        std::string all;
        for (const std::string& n : set->names()) all += (all.empty() ? "" : " ") + n;
        if (err) *err = "nbrdf: name a material, nbrdf:NAME; the " + std::to_string(set->size()) +
                        " in " + set->path() + ": " + all;
        return nullptr;
    }
    const int i = set->find(name);
    if (i >= 0) return std::make_unique<NbrdfBrdf>(set, i);
    // Near matches: names sharing the first word, or containing the given name.
    const std::string word = name.substr(0, name.find('-'));
    std::string near;
    int shown = 0;
    for (const std::string& n : set->names()) {
        const bool same_word = !word.empty() && n.compare(0, word.size() + 1, word + "-") == 0;
        if ((same_word || (!name.empty() && n.find(name) != std::string::npos)) && shown < 8) {
            near += (shown++ ? ", " : "") + n;
        }
    }
    if (err)
        *err = "nbrdf: unknown material '" + name + "' (" + std::to_string(set->size()) +
               " in " + set->path() + ")" + (near.empty() ? "" : "; did you mean " + near + "?") +
               " ('sepal info nbrdf:' lists them all)";
    return nullptr;
}

}  // namespace sepal

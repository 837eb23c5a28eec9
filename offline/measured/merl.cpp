#include "measured/merl.h"

#include <cmath>
#include <cstdio>
#include <cstring>

#include "util/io.h"

namespace sepal {

const double kMerlScale[3] = {1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0};

namespace {

// Values beyond this (after scaling) would overflow the float table: counted as missing.
constexpr double kHugeValue = 1e30;

uint32_t load_u32le(const uint8_t* p) {
    return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}
uint32_t bswap32(uint32_t v) {
    return (v >> 24) | ((v >> 8) & 0xff00u) | ((v << 8) & 0xff0000u) | (v << 24);
}
int32_t as_i32(uint32_t v) {
    int32_t i;
    std::memcpy(&i, &v, 4);
    return i;
}
double load_f64(const uint8_t* p, bool swapped) {
    uint64_t u = 0;
    for (int k = 0; k < 8; ++k) u |= uint64_t(p[swapped ? 7 - k : k]) << (8 * k);
    double d;
    std::memcpy(&d, &u, 8);
    return d;
}
void store_f64le(double d, uint8_t* p) {
    uint64_t u;
    std::memcpy(&u, &d, 8);
    for (int k = 0; k < 8; ++k) p[k] = uint8_t(u >> (8 * k));
}
void store_i32le(int32_t i, uint8_t* p) {
    uint32_t u;
    std::memcpy(&u, &i, 4);
    for (int k = 0; k < 4; ++k) p[k] = uint8_t(u >> (8 * k));
}

// A value a real or generated MERL file can hold: 0, the -1 marker, or a BRDF times ~1500.
// Byte-swapped doubles almost never look like that.
bool plausible(double v) {
    const double a = std::fabs(v);
    return std::isfinite(v) && (a == 0.0 || (a >= 1e-30 && a <= 1e12));
}

std::string dims_text(int64_t a, int64_t b, int64_t c) {
    return std::to_string(a) + " x " + std::to_string(b) + " x " + std::to_string(c);
}

HalfDiff merl_center(size_t i) {
    return table_cell_center(kMerlThetaH, kMerlThetaD, kMerlPhiD, ThetaHMapping::kSqrt, i);
}

class MerlBrdf : public Brdf {
  public:
    MerlBrdf(std::string path, Tabulated table, const MerlStats& stats)
        : path_(std::move(path)), table_(std::move(table)), stats_(stats) {
        filled_ = table_.fill_missing();
    }
    glm::dvec3 eval(const glm::dvec3& wi, const glm::dvec3& wo) const override {
        return table_.eval(wi, wo);
    }
    std::string spec() const override { return path_; }
    std::string model() const override { return "merl"; }
    InputCounts input_counts() const override {
        InputCounts c;
        c.values = int64_t(3 * stats_.cells);
        c.nonfinite = int64_t(stats_.nan + stats_.inf);
        c.negative = int64_t(stats_.negative - 3 * stats_.horizon_cells);
        c.huge = int64_t(stats_.huge);
        c.missing = int64_t(stats_.missing_cells - stats_.horizon_cells);
        c.horizon = int64_t(stats_.horizon_cells);
        c.filled = int64_t(filled_);
        return c;
    }
    bool isotropic() const override { return true; }
    std::string info() const override {
        char buf[512];
        std::string s;
        std::snprintf(buf, sizeof buf,
                      "file       %s\n"
                      "format     MERL .binary: %d x %d x %d (theta_h sqrt-spaced, theta_d, "
                      "phi_d over [0, pi)), float64 RGB, scales 1/1500 1.15/1500 1.66/1500\n",
                      path_.c_str(), kMerlThetaH, kMerlThetaD, kMerlPhiD);
        s += buf;
        const size_t valid = stats_.cells - stats_.missing_cells;
        const size_t missing = stats_.missing_cells - stats_.horizon_cells;
        std::snprintf(buf, sizeof buf, "samples    %zu cells, %zu valid, %zu below the horizon (marked -1: no data by geometry)\n",
                      stats_.cells, valid, stats_.horizon_cells);
        s += buf;
        std::snprintf(buf, sizeof buf,
                      "missing    %zu cells above the horizon (%.2f%%): %zu negative, %zu NaN, %zu inf, %zu "
                      "beyond float range (values over the 3 channels)\n",
                      missing, 100.0 * missing / stats_.cells, stats_.negative - 3 * stats_.horizon_cells,
                      stats_.nan, stats_.inf, stats_.huge);
        s += buf;
        std::snprintf(buf, sizeof buf,
                      "coverage   %.2f%% of cells hold valid data; %zu missing cells get "
                      "push-pull values for lookups\n",
                      100.0 * valid / stats_.cells, filled_);
        s += buf;
        s += "lookup     trilinear between bin centres (sqrt(theta_h), theta_d, phi_d)\n";
        return s;
    }

  private:
    std::string path_;
    Tabulated table_;
    MerlStats stats_;
    size_t filled_ = 0;
};

}  // namespace

void merl_bin_center_dirs(size_t i, glm::dvec3* wi, glm::dvec3* wo) {
    from_half_diff(merl_center(i), wi, wo);
}

bool parse_merl(const std::vector<uint8_t>& bytes, const std::string& name, Tabulated* table,
                MerlStats* stats, std::string* err) {
    auto fail = [&](const std::string& why) {
        if (err) *err = name + ": " + why;
        return false;
    };
    if (bytes.empty()) return fail("empty file (a MERL .binary file is 34992012 bytes)");
    if (bytes.size() < 12)
        return fail("file of " + std::to_string(bytes.size()) +
                    " bytes is too short for the 12-byte MERL header");
    int64_t le[3], be[3];
    for (int k = 0; k < 3; ++k) {
        const uint32_t u = load_u32le(&bytes[4 * k]);
        le[k] = as_i32(u);
        be[k] = as_i32(bswap32(u));
    }
    const bool le_ok = le[0] == kMerlThetaH && le[1] == kMerlThetaD && le[2] == kMerlPhiD;
    if (!le_ok) {
        if (be[0] == kMerlThetaH && be[1] == kMerlThetaD && be[2] == kMerlPhiD)
            return fail("wrong byte order: the header reads 90 x 90 x 180 only when "
                        "byte-swapped (big-endian); MERL files are little-endian");
        const bool positive = le[0] > 0 && le[1] > 0 && le[2] > 0;
        // In double: three dims below 2^31 multiply past int64 (signed overflow); a double
        // is exact up to 2^53 and only approximate (never undefined) beyond.
        const double product = double(le[0]) * double(le[1]) * double(le[2]);
        char product_text[40];
        std::snprintf(product_text, sizeof product_text, product < 9007199254740992.0 ? "%.0f" : "about %.3g", product);
        if (positive && product == double(kMerlCells))
            return fail("header dims " + dims_text(le[0], le[1], le[2]) +
                        " multiply to 1458000 but are not MERL's layout 90 x 90 x 180");
        return fail("header dims " + dims_text(le[0], le[1], le[2]) +
                    (positive ? std::string(" (product ") + product_text + ")" : "") +
                    " do not match MERL's 90 x 90 x 180 = 1458000 samples");
    }
    if (bytes.size() != kMerlFileBytes)
        return fail("file is " + std::to_string(bytes.size()) + " bytes; a MERL file is " +
                    std::to_string(kMerlFileBytes) +
                    " (12-byte header + 3 x 1458000 float64): " +
                    (bytes.size() < kMerlFileBytes ? "truncated" : "extra bytes at the end"));

    *table = Tabulated::merl();
    std::string why;
    if (!decode_merl_planes(
            &bytes[12], kMerlCells,
            [&](size_t i, const glm::dvec3& rgb, bool missing) {
                if (missing)
                    table->set_missing(i);  // none of its channels is used
                else
                    table->set(i, rgb);
            },
            stats, &why))
        return fail(why);
    if (stats) {
        // Cells whose bin centre lies below the horizon hold no measurement by geometry; MERL
        // (and write_merl) mark them -1 in every channel. Told apart from missing data.
        for (size_t i = 0; i < kMerlCells; ++i) {
            if (table->state(i) != Tabulated::State::kMissing) continue;
            glm::dvec3 wi, wo;
            merl_bin_center_dirs(i, &wi, &wo);
            if (wi.z > 0.0 && wo.z > 0.0) continue;
            bool marker = true;
            for (int c = 0; c < 3; ++c) marker = marker && load_f64(&bytes[12 + 8 * (c * kMerlCells + i)], false) < 0.0;
            stats->horizon_cells += marker;
        }
    }
    return true;
}

bool decode_merl_planes(const uint8_t* planes, size_t n,
                        const std::function<void(size_t, const glm::dvec3&, bool)>& cell,
                        MerlStats* stats, std::string* why) {
    // Sample data in the other byte order: most values read as NaN, inf or absurd
    // magnitudes, and swapping makes them sane.
    size_t bad_le = 0, bad_be = 0;
    for (size_t v = 0; v < 3 * n; ++v) {
        bad_le += !plausible(load_f64(planes + 8 * v, false));
        bad_be += !plausible(load_f64(planes + 8 * v, true));
    }
    if (n > 0 && bad_le > 3 * n / 4 && bad_be < 3 * n / 100) {
        char buf[160];
        std::snprintf(buf, sizeof buf,
                      "sample data looks byte-swapped (big-endian): %.1f%% of values are NaN, "
                      "inf or absurd as little-endian, %.2f%% when swapped",
                      100.0 * bad_le / (3 * n), 100.0 * bad_be / (3 * n));
        if (why) *why = buf;
        return false;
    }
    MerlStats st;
    st.cells = n;
    for (size_t i = 0; i < n; ++i) {
        double rgb[3];
        bool missing = false;
        for (int c = 0; c < 3; ++c) {
            const double v = load_f64(planes + 8 * (c * n + i), false);
            if (std::isnan(v)) {
                ++st.nan;
                missing = true;
            } else if (std::isinf(v)) {
                ++st.inf;
                missing = true;
            } else if (v < 0.0) {
                ++st.negative;
                missing = true;
            } else if (v * kMerlScale[c] > kHugeValue) {
                ++st.huge;
                missing = true;
            }
            rgb[c] = v * kMerlScale[c];
        }
        if (missing) ++st.missing_cells;
        cell(i, missing ? glm::dvec3(0.0) : glm::dvec3(rgb[0], rgb[1], rgb[2]), missing);
    }
    if (stats) *stats = st;
    return true;
}

bool read_merl(const std::string& path, Tabulated* table, MerlStats* stats, std::string* err) {
    std::vector<uint8_t> bytes;
    // Bound: well over a real MERL file, far under anything that would strain memory.
    if (!read_file(path, &bytes, err, 64u << 20)) return false;
    return parse_merl(bytes, path, table, stats, err);
}

namespace {
// Writes the header and every cell's values: value(i, rgb) fills a cell's BRDF (1/sr) and
// returns true, or returns false for a cell without data (written as MERL's -1 marker).
// Refuses (clearing *bytes) a negative or non-finite value, naming the cell.
template <class CellValue>
bool encode_cells(CellValue value, std::vector<uint8_t>* bytes, std::string* err) {
    const size_t n = kMerlCells;
    bytes->assign(kMerlFileBytes, 0);
    uint8_t* out = bytes->data();
    store_i32le(kMerlThetaH, out);
    store_i32le(kMerlThetaD, out + 4);
    store_i32le(kMerlPhiD, out + 8);
    for (size_t i = 0; i < n; ++i) {
        double rgb[3];
        double v[3] = {-1.0, -1.0, -1.0};  // MERL's marker: no data (below the horizon)
        if (value(i, rgb)) {
            for (int c = 0; c < 3; ++c) {
                if (!std::isfinite(rgb[c]) || rgb[c] < 0.0) {
                    const HalfDiff a = merl_center(i);
                    char buf[200];
                    std::snprintf(buf, sizeof buf,
                                  "the BRDF returned %g (channel %d) at theta_h %.4f, theta_d "
                                  "%.4f, phi_d %.4f rad: not a finite non-negative value",
                                  rgb[c], c, a.theta_h, a.theta_d, a.phi_d);
                    if (err) *err = buf;
                    bytes->clear();
                    return false;
                }
                v[c] = rgb[c] / kMerlScale[c];
            }
        }
        for (int c = 0; c < 3; ++c) store_f64le(v[c], out + 12 + 8 * (c * n + i));
    }
    return true;
}
}  // namespace

bool encode_merl(const Brdf& f, std::vector<uint8_t>* bytes, std::string* err) {
    return encode_cells(
        [&](size_t i, double rgb[3]) {
            glm::dvec3 wi, wo;
            from_half_diff(merl_center(i), &wi, &wo);
            if (!(wi.z > 0.0 && wo.z > 0.0)) return false;
            const glm::dvec3 v = f.eval(wi, wo);
            for (int c = 0; c < 3; ++c) rgb[c] = v[c];
            return true;
        },
        bytes, err);
}

bool encode_merl_table(const Tabulated& t, std::vector<uint8_t>* bytes, std::string* err) {
    if (t.n_theta_h() != kMerlThetaH || t.n_theta_d() != kMerlThetaD || t.n_phi_d() != kMerlPhiD ||
        t.mapping() != ThetaHMapping::kSqrt) {
        if (err) *err = "a MERL file holds a 90 x 90 x 180 table with sqrt-spaced theta_h";
        return false;
    }
    return encode_cells(
        [&](size_t i, double rgb[3]) {
            if (!t.usable(i)) return false;
            const glm::dvec3 v = t.value(i);
            for (int c = 0; c < 3; ++c) rgb[c] = v[c];
            return true;
        },
        bytes, err);
}

bool write_merl_table(const std::string& path, const Tabulated& t, std::string* err) {
    std::vector<uint8_t> bytes;
    if (!encode_merl_table(t, &bytes, err)) return false;
    return write_file_atomic(path, bytes.data(), bytes.size(), err);
}

bool write_merl(const std::string& path, const Brdf& f, std::string* err) {
    std::vector<uint8_t> bytes;
    if (!encode_merl(f, &bytes, err)) return false;
    return write_file_atomic(path, bytes.data(), bytes.size(), err);
}

std::unique_ptr<Brdf> make_merl_brdf(const std::vector<uint8_t>& bytes, const std::string& path,
                                     std::string* err) {
    Tabulated table;
    MerlStats stats;
    if (!parse_merl(bytes, path, &table, &stats, err)) return nullptr;
    if (stats.missing_cells == stats.cells) {
        if (err)
            *err = path + ": every cell has a missing value (" + std::to_string(stats.negative) + " negative, " +
                   std::to_string(stats.nan) + " NaN, " + std::to_string(stats.inf) + " inf, " +
                   std::to_string(stats.huge) + " over 1e30 after MERL's scale)";
        return nullptr;
    }
    return std::make_unique<MerlBrdf>(path, std::move(table), stats);
}

std::unique_ptr<Brdf> load_merl_brdf(const std::string& path, std::string* err) {
    std::vector<uint8_t> bytes;
    if (!read_file(path, &bytes, err, 64u << 20)) return nullptr;
    return make_merl_brdf(bytes, path, err);
}

}  // namespace sepal

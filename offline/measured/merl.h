// MERL .binary BRDF files (Matusik et al. 2003): reader, writer and the Brdf they load as.
//
// Usage:
//   std::unique_ptr<sepal::Brdf> f = sepal::load_merl_brdf("blue-metallic-paint.binary", &err);
//   sepal::write_merl("out.binary", *analytic, &err);     // tabulate any BRDF
//
// Format (NOTES.md section 6): three little-endian int32 dims 90 90 180, then 3 planes (red,
// green, blue) of 1,458,000 little-endian float64 each, 34,992,012 bytes in all; a stored
// value times its channel's scale (1/1500, 1.15/1500, 1.66/1500) is the BRDF. The table is
// the MERL instance of sepal::Tabulated (see tabulated.h for the index formulas).
// The reader refuses: an empty or short file, a header other than 90 x 90 x 180 (with
// separate messages for a big-endian header and for a dims product other than 1,458,000),
// a file size other than 34,992,012 bytes, and sample data that reads as garbage unless
// byte-swapped. Negative, NaN and infinite values (and values beyond float range) are
// counted per kind and treated as missing: a cell with any missing channel is missing, its
// values are never used; fill_missing then gives it a push-pull value for lookups only.
// The writer evaluates f at each bin centre (tabulated.h), with phi_h = 0, and writes -1 (the
// MERL marker for missing / below the horizon) where either direction is at or below the
// horizon there. It is deterministic: the same BRDF gives the same bytes.
// Limits: the whole file is held in memory (35 MB plus a 1,458,000-cell float table).
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "brdf/brdf.h"
#include "measured/tabulated.h"

namespace sepal {

constexpr int kMerlThetaH = 90, kMerlThetaD = 90, kMerlPhiD = 180;
constexpr size_t kMerlCells = size_t(kMerlThetaH) * kMerlThetaD * kMerlPhiD;  // 1,458,000
constexpr uint64_t kMerlFileBytes = 12 + 3 * 8 * uint64_t(kMerlCells);         // 34,992,012
extern const double kMerlScale[3];  // red 1/1500, green 1.15/1500, blue 1.66/1500

struct MerlStats {
    size_t cells = 0;          // table cells (1,458,000)
    size_t missing_cells = 0;  // cells with at least one missing channel
    size_t negative = 0, nan = 0, inf = 0, huge = 0;  // missing values, per kind
    // Of the missing cells, those whose bin centre is below the horizon and whose three
    // channels hold MERL's -1 marker: no data by geometry, not a gap in the measurement
    // (parse_merl only; decode_merl_planes does not know the grid).
    size_t horizon_cells = 0;
};

// Decodes a whole file's bytes into a MERL-layout table (BRDF units, scales applied).
// `name` prefixes the messages.
bool parse_merl(const std::vector<uint8_t>& bytes, const std::string& name, Tabulated* table,
                MerlStats* stats, std::string* err);
bool read_merl(const std::string& path, Tabulated* table, MerlStats* stats, std::string* err);
// parse_merl's sample decoding on its own, for n cells (three planes of n float64 at
// `planes`): the byte-order check, then cell(i, rgb, missing) for each cell in order (rgb in
// BRDF units, zero when missing). Any n, so the fuzz harness drives it with small tables
// (a whole file takes seconds under ASan). Fails, with *why, on byte-swapped data.
bool decode_merl_planes(const uint8_t* planes, size_t n,
                        const std::function<void(size_t, const glm::dvec3&, bool)>& cell,
                        MerlStats* stats, std::string* why);

// Tabulates f into MERL bytes / an atomically written file. Fails (never writes) when f
// returns a negative or non-finite value at a bin centre.
bool encode_merl(const Brdf& f, std::vector<uint8_t>* bytes, std::string* err);
bool write_merl(const std::string& path, const Brdf& f, std::string* err);

// Writes a MERL-layout table as it is: usable cells with their values, missing cells as -1.
// Refuses another layout and (never writing) negative or non-finite values.
bool encode_merl_table(const Tabulated& t, std::vector<uint8_t>* bytes, std::string* err);
bool write_merl_table(const std::string& path, const Tabulated& t, std::string* err);

// The bin-centre direction pair the writer evaluates for cell i (phi_h = 0).
void merl_bin_center_dirs(size_t i, glm::dvec3* wi, glm::dvec3* wo);

std::unique_ptr<Brdf> load_merl_brdf(const std::string& path, std::string* err);
// The same from bytes already read (used by load_measured_brdf's content sniffing).
std::unique_ptr<Brdf> make_merl_brdf(const std::vector<uint8_t>& bytes, const std::string& path,
                                     std::string* err);

}  // namespace sepal

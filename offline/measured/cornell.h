// Cornell measured BRDFs (.brdf text files from the Cornell Program of Computer Graphics, as
// redistributed with pbrt-v2): parser, dense tabulation and the Brdf they load as.
//
// Usage:
//   std::unique_ptr<sepal::Brdf> f = sepal::load_cornell_brdf("fixtures/cornell/cayman.brdf", &err);
//   // or, step by step:
//   sepal::CornellData d;  sepal::parse_cornell(text, "name", &d, &err);
//   sepal::Tabulated t;    sepal::tabulate_cornell(d.samples, &t);
//
// Format (NOTES.md section 6): '#' starts a comment (to the end of the line); then the number
// of wavelengths, the wavelengths in nm (over one or more lines), then one sample per line:
// "theta_i phi_i theta_s phi_s v_1 .. v_n" (radians; spectral BRDF values per steradian).
// The parser refuses, naming the line: a missing or non-integer count (1..1000), wavelengths
// that are not strictly increasing within 300..1000 nm or too few or too many of them, a
// sample line with the wrong number of values, a token that is not a number, a non-finite
// number (the message counts every NaN and inf token in the file), theta outside [0, pi/2]
// (beyond 1e-5 of rounding slack; inside it the angle is clamped and counted) or phi outside
// [-2 pi, 2 pi], more than kMaxSamples
// samples, or no sample at all. A sample with a negative spectral value, or one above 1e30
// (beyond the float table), is counted as missing and not used.
// Colour: each spectrum becomes linear sRGB through the CIE 1931 matching functions under
// D65, normalized so a flat spectrum of 1 gives (1, 1, 1) (cie.h); negative RGB channels
// (colours outside the sRGB gamut; tiny in the Cornell files) are clamped to 0 and counted.
// Dense form: the samples stay as scattered data (CornellData::samples) and are also
// tabulated into the MERL layout, 90 x 90 x 180 with sqrt-spaced theta_h so the specular
// peak gets the finest cells (tabulated.h). A two-lobe Lafortune model fitted to the samples
// is the base; the residual log(1 + f) - log(1 + base) goes to a 20 x 20 table over
// (theta_h, theta_d): each sample to the cell containing it (and, because an isotropic BRDF
// is symmetric under phi_d -> -phi_d, its mirror), push-pull fills every other cell; each
// cell of the result is the base times that residual at its centre (CornellTabulation).
// The choices (layout, kernel, mirror, log1p, base, residual) were measured on the three
// Cornell files: docs/reference.md, "Measured data".
// Limits: isotropic data only (phi_i is used, not assumed 0); at most 64 MiB of text.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "brdf/brdf.h"
#include "measured/tabulated.h"

namespace sepal {

struct CornellSample {
    double theta_i = 0, phi_i = 0, theta_s = 0, phi_s = 0;  // radians
    glm::dvec3 rgb{0.0};                                    // linear sRGB per steradian
    glm::dvec3 wi() const;  // incident direction (the light), local frame
    glm::dvec3 wo() const;  // scattered direction (the viewer)
};

struct CornellData {
    std::vector<double> wavelengths;      // nm
    std::vector<CornellSample> samples;   // usable samples
    size_t missing = 0;                   // sample lines with a negative or huge value
    size_t huge = 0;                      // of those, lines with a value beyond 1e30 (none negative)
    size_t lines = 0;                     // sample lines read
    size_t clamped = 0;                   // negative RGB channel values set to 0
    size_t angles_clamped = 0;            // thetas within kAngleSlack outside [0, pi/2], clamped
    double clamped_share = 0;             // their |sum| over the sum of all |RGB| values
};

constexpr size_t kCornellMaxSamples = 1000000;
// Spectral values above this are treated as missing, as MERL's reader does (merl.cpp): they
// would not survive the float table.
constexpr double kCornellHugeValue = 1e30;
constexpr int kCornellMaxWavelengths = 1000;
bool parse_cornell(const std::string& text, const std::string& name, CornellData* out,
                   std::string* err);

// How the samples become a dense table; the defaults are the choices described above (the
// other settings exist to measure those choices).
struct CornellTabulation {
    int res[3] = {90, 90, 180};  // theta_h (sqrt-spaced), theta_d, phi_d
    bool mirror = true;          // also splat each sample at -phi_d
    Tabulated::FillDomain domain = Tabulated::FillDomain::kLog1p;
    // A base model under the table (0: none, push-pull in `domain` on f itself). With 1..4 (more
    // counts as 4), a Lafortune model of that many forward lobes (fit/lafortune_fit.h; fewer when the fit
    // fails or creates energy) is fitted to the samples in a log-like measure (weights
    // 1 / (1 + luminance)); push-pull then fills the residual log(1 + f) - log(1 + base) at the
    // samples, and each cell becomes exp(log(1 + base) + residual) - 1 at its centre.
    int base_lobes = 2;
    // Cells of the residual's own table (theta_h sqrt-spaced, theta_d, phi_d; 0 takes the
    // table's count). The default, 20 x 20 x 1, makes the residual a smooth function of
    // (theta_h, theta_d) alone: the base carries the phi_d dependence. The Cornell files
    // sample phi_d on a few dozen azimuths; a residual over phi_d spreads their pattern into
    // rays around the highlight (a star at normal incidence, a fan where the view grazes
    // beyond the samples' 80 degrees), and one over the table's 90 x 90 into rings around it.
    // Measured in docs/reference.md, "Measured data".
    int residual_res[3] = {20, 20, 1};
};
// What tabulate_cornell put under the table: lobes 0 when there is no base (base_lobes 0, or
// no fit that succeeded and stayed plausible).
struct CornellBase {
    int lobes = 0;
    std::string spec;  // the base's `lafortune` spec (brdf_models.h), empty without one
    // The residual's table (with a base): its shape, and its cells holding a sample.
    int residual_res[3] = {0, 0, 0};
    size_t residual_measured = 0;
};
// Tabulates the samples into *table (re-initialized); *base (optional) says what base the
// table holds its residual over.
void tabulate_cornell(const std::vector<CornellSample>& samples, Tabulated* table,
                      const CornellTabulation& how = CornellTabulation(), CornellBase* base = nullptr);

// sqrt(sum over samples and channels of (f_table - f_sample)^2 / sum of f_sample^2), with
// f_table read by trilinear lookup at each sample's own (wi, wo). 0 when there are no samples.
double relative_rms(const Tabulated& table, const std::vector<CornellSample>& samples);

struct CornellFigures {
    size_t cells = 0, occupied = 0, measured = 0, filled = 0;
    double fit_rms = 0;      // relative RMS at every sample of `table`
    double holdout_rms = 0;  // relative RMS at every 10th sample, table built without them
    size_t holdout_count = 0;
};
// `table` is tabulate_cornell(data.samples, how); the holdout builds a second table.
CornellFigures cornell_figures(const CornellData& data, const Tabulated& table,
                               const CornellTabulation& how = CornellTabulation());

// k-fold cross-validation of a tabulation: sample i is held out in fold i % folds, the table
// built from the others; every sample is predicted once and the errors are pooled:
// relative_rms's measure, and the same of log(1 + f) (less ruled by the few highlight samples).
struct CornellCrossValidation {
    double rms = 0, log_rms = 0;
    int folds = 0;
};
CornellCrossValidation cornell_cross_validation(const std::vector<CornellSample>& samples,
                                                const CornellTabulation& how, int folds);

std::unique_ptr<Brdf> load_cornell_brdf(const std::string& path, std::string* err);
std::unique_ptr<Brdf> make_cornell_brdf(const std::string& text, const std::string& path,
                                        std::string* err);

}  // namespace sepal

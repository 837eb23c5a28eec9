#include "brdf/cie.h"

#include <cmath>

namespace sepal {

namespace {

// CIE 1931 2-degree standard colorimetric observer, 380..780 nm every 10 nm, and CIE
// standard illuminant D65 (relative spectral power, 100 at 560 nm) on the same grid.
// Source: CIE 015:2004 "Colorimetry", 3rd ed., tables T.1 (D65) and T.4 (x_bar, y_bar,
// z_bar), the same values as the CVRL tables (cvrl.org, "CIE 1931 2-deg, XYZ CMFs", 5 nm
// file sampled every other row) and CIE's data sets DOI 10.25039/CIE.DS.xvudnb9b
// (observer) and 10.25039/CIE.DS.hjfjmt59 (D65).
constexpr double kFirstNm = 380.0, kStepNm = 10.0;
constexpr int kCount = 41;
// clang-format off
constexpr double kCmf[kCount][3] = {
    {0.001368, 0.000039, 0.006450}, {0.004243, 0.000120, 0.020050},  // 380, 390
    {0.014310, 0.000396, 0.067850}, {0.043510, 0.001210, 0.207400},  // 400, 410
    {0.134380, 0.004000, 0.645600}, {0.283900, 0.011600, 1.385600},  // 420, 430
    {0.348280, 0.023000, 1.747060}, {0.336200, 0.038000, 1.772110},  // 440, 450
    {0.290800, 0.060000, 1.669200}, {0.195360, 0.090980, 1.287640},  // 460, 470
    {0.095640, 0.139020, 0.812950}, {0.032010, 0.208020, 0.465180},  // 480, 490
    {0.004900, 0.323000, 0.272000}, {0.009300, 0.503000, 0.158200},  // 500, 510
    {0.063270, 0.710000, 0.078250}, {0.165500, 0.862000, 0.042160},  // 520, 530
    {0.290400, 0.954000, 0.020300}, {0.433450, 0.994950, 0.008750},  // 540, 550
    {0.594500, 0.995000, 0.003900}, {0.762100, 0.952000, 0.002100},  // 560, 570
    {0.916300, 0.870000, 0.001650}, {1.026300, 0.757000, 0.001100},  // 580, 590
    {1.062200, 0.631000, 0.000800}, {1.002600, 0.503000, 0.000340},  // 600, 610
    {0.854450, 0.381000, 0.000190}, {0.642400, 0.265000, 0.000050},  // 620, 630
    {0.447900, 0.175000, 0.000020}, {0.283500, 0.107000, 0.000000},  // 640, 650
    {0.164900, 0.061000, 0.000000}, {0.087400, 0.032000, 0.000000},  // 660, 670
    {0.046770, 0.017000, 0.000000}, {0.022700, 0.008210, 0.000000},  // 680, 690
    {0.011359, 0.004102, 0.000000}, {0.005790, 0.002091, 0.000000},  // 700, 710
    {0.002899, 0.001047, 0.000000}, {0.001440, 0.000520, 0.000000},  // 720, 730
    {0.000690, 0.000249, 0.000000}, {0.000332, 0.000120, 0.000000},  // 740, 750
    {0.000166, 0.000060, 0.000000}, {0.000083, 0.000030, 0.000000},  // 760, 770
    {0.000042, 0.000015, 0.000000},                                  // 780
};
constexpr double kD65[kCount] = {
    49.9755, 54.6482, 82.7549, 91.4860, 93.4318, 86.6823, 104.865, 117.008,   // 380..450
    117.812, 114.861, 115.923, 108.811, 109.354, 107.802, 104.790, 107.689,   // 460..530
    104.405, 104.046, 100.000, 96.3342, 95.7880, 88.6856, 90.0062, 89.5991,   // 540..610
    87.6987, 83.2886, 83.6992, 80.0268, 80.2146, 82.2778, 78.2842, 69.7213,   // 620..690
    71.6091, 74.3490, 61.6040, 69.8856, 75.0870, 63.5927, 46.4182, 66.8054,   // 700..770
    63.3828,                                                                  // 780
};
// clang-format on

// Position in the table: index i and fraction t, or false outside 380..780 nm.
bool table_pos(double nm, int* i, double* t) {
    if (!(nm >= kFirstNm && nm <= kFirstNm + kStepNm * (kCount - 1))) return false;
    const double u = (nm - kFirstNm) / kStepNm;
    int k = int(std::floor(u));
    if (k >= kCount - 1) k = kCount - 2;
    *i = k;
    *t = u - k;
    return true;
}

}  // namespace

glm::dvec3 cie1931_cmf(double nm) {
    int i;
    double t;
    if (!table_pos(nm, &i, &t)) return glm::dvec3(0.0);
    const double* a = kCmf[i];
    const double* b = kCmf[i + 1];
    return glm::dvec3(a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]),
                      a[2] + t * (b[2] - a[2]));
}

double cie_d65(double nm) {
    int i;
    double t;
    if (!table_pos(nm, &i, &t)) return 0.0;
    return kD65[i] + t * (kD65[i + 1] - kD65[i]);
}

glm::dvec3 xyz_to_linear_srgb(const glm::dvec3& c) {
    // IEC 61966-2-1:1999, the inverse of the sRGB primaries' matrix (D65 white).
    return glm::dvec3(3.2406 * c.x - 1.5372 * c.y - 0.4986 * c.z,
                      -0.9689 * c.x + 1.8758 * c.y + 0.0415 * c.z,
                      0.0557 * c.x - 0.2040 * c.y + 1.0570 * c.z);
}

bool SpectrumToRgb::init(const std::vector<double>& nm, std::string* err) {
    weights_.clear();
    if (nm.empty()) {
        if (err) *err = "no wavelengths";
        return false;
    }
    for (size_t i = 0; i < nm.size(); ++i) {
        if (!std::isfinite(nm[i]) || nm[i] < 300.0 || nm[i] > 1000.0) {
            if (err) *err = "wavelength " + std::to_string(nm[i]) + " nm is outside 300..1000 nm";
            return false;
        }
        if (i > 0 && !(nm[i] > nm[i - 1])) {
            if (err) *err = "wavelengths are not strictly increasing";
            return false;
        }
    }
    // Each sample stands for the interval halfway to its neighbours; at the ends the full
    // spacing to the one neighbour, so a uniform list gets equal weights (CIE 015's sum).
    const size_t n = nm.size();
    std::vector<double> dl(n, 1.0);
    for (size_t i = 0; i < n && n > 1; ++i) {
        if (i == 0)
            dl[i] = nm[1] - nm[0];
        else if (i == n - 1)
            dl[i] = nm[n - 1] - nm[n - 2];
        else
            dl[i] = 0.5 * (nm[i + 1] - nm[i - 1]);
    }
    double y_norm = 0.0;
    for (size_t i = 0; i < n; ++i) y_norm += dl[i] * cie_d65(nm[i]) * cie1931_cmf(nm[i]).y;
    if (!(y_norm > 0.0)) {
        if (err) *err = "no wavelength falls inside the visible range 380..780 nm";
        return false;
    }
    glm::dvec3 white(0.0);
    weights_.resize(n);
    for (size_t i = 0; i < n; ++i) {
        const glm::dvec3 xyz = cie1931_cmf(nm[i]) * (dl[i] * cie_d65(nm[i]) / y_norm);
        weights_[i] = xyz_to_linear_srgb(xyz);
        white += weights_[i];
    }
    // A list covering too little of the spectrum cannot represent white in all channels.
    if (!(white.x > 0.05 && white.y > 0.05 && white.z > 0.05)) {
        weights_.clear();
        if (err) *err = "the wavelengths cover too little of the visible range for RGB";
        return false;
    }
    for (glm::dvec3& w : weights_) w /= white;
    return true;
}

glm::dvec3 SpectrumToRgb::convert(const double* values) const {
    glm::dvec3 rgb(0.0);
    for (size_t i = 0; i < weights_.size(); ++i) rgb += weights_[i] * values[i];
    return rgb;
}

}  // namespace sepal

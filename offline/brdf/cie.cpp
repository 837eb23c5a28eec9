#include "brdf/cie.h"

#include <algorithm>
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

glm::dvec3 linear_srgb_to_xyz(const glm::dvec3& c) {
    // IEC 61966-2-1:1999's primaries matrix (the forward of the one above).
    return glm::dvec3(0.4124 * c.x + 0.3576 * c.y + 0.1805 * c.z,
                      0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z,
                      0.0193 * c.x + 0.1192 * c.y + 0.9505 * c.z);
}

glm::dvec3 srgb_display_to_lab(const glm::dvec3& srgb) {
    glm::dvec3 lin;
    for (int c = 0; c < 3; ++c) {
        const double v = std::min(1.0, std::max(0.0, srgb[c]));
        lin[c] = v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
    }
    const glm::dvec3 xyz = linear_srgb_to_xyz(lin);
    // CIE 15: the cube root above (6/29)^3, its tangent line below.
    auto f = [](double t) {
        constexpr double d = 6.0 / 29.0;
        return t > d * d * d ? std::cbrt(t) : t / (3.0 * d * d) + 4.0 / 29.0;
    };
    const double fx = f(xyz.x / 0.95047), fy = f(xyz.y), fz = f(xyz.z / 1.08883);
    return glm::dvec3(116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz));
}

double ciede2000(const glm::dvec3& l1, const glm::dvec3& l2) {
    constexpr double kDeg = 3.14159265358979323846 / 180.0;
    const double pow25_7 = 6103515625.0;  // 25^7
    const double c1 = std::hypot(l1.y, l1.z), c2 = std::hypot(l2.y, l2.z);
    const double cbar7 = std::pow(0.5 * (c1 + c2), 7.0);
    const double g = 0.5 * (1.0 - std::sqrt(cbar7 / (cbar7 + pow25_7)));
    const double a1 = (1.0 + g) * l1.y, a2 = (1.0 + g) * l2.y;
    const double c1p = std::hypot(a1, l1.z), c2p = std::hypot(a2, l2.z);
    auto hue = [&](double b, double a) {
        if (a == 0.0 && b == 0.0) return 0.0;
        const double h = std::atan2(b, a) / kDeg;
        return h < 0.0 ? h + 360.0 : h;
    };
    const double h1 = hue(l1.z, a1), h2 = hue(l2.z, a2);
    const bool achromatic = c1p * c2p == 0.0;
    double dh = 0.0;
    if (!achromatic) {
        dh = h2 - h1;
        if (dh > 180.0) dh -= 360.0;
        else if (dh < -180.0) dh += 360.0;
    }
    const double dL = l2.x - l1.x, dC = c2p - c1p;
    const double dH = 2.0 * std::sqrt(c1p * c2p) * std::sin(0.5 * dh * kDeg);
    const double lbar = 0.5 * (l1.x + l2.x), cbarp = 0.5 * (c1p + c2p);
    double hbar = h1 + h2;
    if (!achromatic) {
        if (std::fabs(h1 - h2) <= 180.0) hbar = 0.5 * (h1 + h2);
        else if (h1 + h2 < 360.0) hbar = 0.5 * (h1 + h2 + 360.0);
        else hbar = 0.5 * (h1 + h2 - 360.0);
    }
    const double t = 1.0 - 0.17 * std::cos((hbar - 30.0) * kDeg) + 0.24 * std::cos(2.0 * hbar * kDeg) +
                     0.32 * std::cos((3.0 * hbar + 6.0) * kDeg) - 0.20 * std::cos((4.0 * hbar - 63.0) * kDeg);
    const double dtheta = 30.0 * std::exp(-((hbar - 275.0) / 25.0) * ((hbar - 275.0) / 25.0));
    const double cbarp7 = std::pow(cbarp, 7.0);
    const double rc = 2.0 * std::sqrt(cbarp7 / (cbarp7 + pow25_7));
    const double l50 = (lbar - 50.0) * (lbar - 50.0);
    const double sl = 1.0 + 0.015 * l50 / std::sqrt(20.0 + l50);
    const double sc = 1.0 + 0.045 * cbarp, sh = 1.0 + 0.015 * cbarp * t;
    const double rt = -std::sin(2.0 * dtheta * kDeg) * rc;
    const double x = dL / sl, y = dC / sc, z = dH / sh;
    return std::sqrt(std::max(0.0, x * x + y * y + z * z + rt * y * z));
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

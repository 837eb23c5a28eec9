// Spectral to linear sRGB conversion through the CIE 1931 colour-matching functions.
//
// Usage:
//   sepal::SpectrumToRgb conv;
//   if (!conv.init(wavelengths_nm, &err)) ...;     // once per wavelength list
//   glm::dvec3 rgb = conv.convert(values.data());  // one spectrum, same length
//
// Colorimetry: the spectrum is read as a spectral reflectance (or BRDF) lit by CIE standard
// illuminant D65, so X = sum R S x_bar dl / sum S y_bar dl (likewise Y, Z), then the IEC
// 61966-2-1 XYZ -> linear sRGB matrix (whose white is D65). Normalization: a spectrally
// flat value of 1 maps to RGB exactly (1, 1, 1): each channel is divided by the RGB of the
// flat spectrum over the same wavelengths. Without that step a flat spectrum sampled at
// 400..700 nm every 10 nm gives (0.9974, 1.0010, 0.9979): the per-channel division only
// removes the small error of the truncated, coarsely sampled sums.
// Colour differences: srgb_display_to_lab reads a display value (an 8-bit image's pixel / 255,
// in sRGB's transfer encoding, as a monitor shows it) as CIE L*a*b* under D65, and ciede2000
// is the CIEDE2000 difference of two such colours (kL = kC = kH = 1; Sharma, Wu and Dalal
// 2005, whose test pairs the tests check). About 1 is a just-noticeable difference side by
// side; 2 is what the measurement tools hold a reconstruction's mean to.
// Limits: wavelengths must be strictly increasing within 300..1000 nm; outside the
// tabulated 380..780 nm the matching functions are taken as 0. At least part of the list
// must fall inside the visible table. Output RGB may be negative for saturated spectra
// (outside the sRGB gamut); callers decide whether to clamp.
#pragma once
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace sepal {

// CIE 1931 2-degree x_bar, y_bar, z_bar and D65 at `nm` (linear interpolation in the 10 nm
// table, 0 outside 380..780 nm).
glm::dvec3 cie1931_cmf(double nm);
double cie_d65(double nm);
// IEC 61966-2-1 (sRGB) matrix, D65 white.
glm::dvec3 xyz_to_linear_srgb(const glm::dvec3& xyz);
glm::dvec3 linear_srgb_to_xyz(const glm::dvec3& rgb);

// Display value (each channel clamped to [0, 1], sRGB-encoded) to CIE L*a*b* (D65 white, Y = 1).
glm::dvec3 srgb_display_to_lab(const glm::dvec3& srgb);
// CIEDE2000 Delta E between two L*a*b* colours.
double ciede2000(const glm::dvec3& lab1, const glm::dvec3& lab2);

class SpectrumToRgb {
  public:
    bool init(const std::vector<double>& wavelengths_nm, std::string* err);
    glm::dvec3 convert(const double* values) const;
    size_t size() const { return weights_.size(); }

  private:
    std::vector<glm::dvec3> weights_;  // per wavelength: RGB contribution of value 1
};

}  // namespace sepal

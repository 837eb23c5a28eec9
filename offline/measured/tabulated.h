// A dense isotropic BRDF table in Rusinkiewicz half/difference angles (theta_h, theta_d,
// phi_d): the common dense form of measured data. The MERL layout (90 x 90 x 180, non-linear
// theta_h index) is one instance; any resolution works.
//
// Usage:
//   sepal::Tabulated t;
//   if (!t.init(32, 32, 64, sepal::ThetaHMapping::kSqrt, &err)) ...;   // or Tabulated::merl()
//   t.set(t.index(ih, id, ip), rgb);                 // dense data, or scattered data:
//   t.splat(sepal::to_half_diff(wi, wo), rgb);  ...;  t.finish_splats();  t.fill_missing();
//   glm::dvec3 f = t.eval(wi, wo);                   // trilinear, 0 below the horizon
//
// Layout and indexing (NOTES.md section 6): cell (ih, id, ip) is at ip + n_pd*(id + n_td*ih).
//   theta_h index: linear int(theta_h/(pi/2)*n) or, as MERL, int(sqrt(theta_h/(pi/2))*n);
//   theta_d index: int(theta_d/(pi/2)*n); phi_d index: int(phi_d/pi*n) after adding pi to a
//   negative phi_d (reciprocity: swapping wi and wo maps phi_d to phi_d + pi, so the table
//   holds [0, pi)); every index clamped to its range.
// A cell's value stands for the centre of its bin in index space (index + 0.5): for MERL
// theta_h = ((ih + 0.5)/90)^2 * pi/2. Trilinear lookup interpolates between those centres in
// index space (so in sqrt(theta_h) for MERL), clamps theta_h and theta_d at the table's
// edges and wraps phi_d around the pi period.
//
// Missing data: each cell is measured (direct data), filled (a value reconstructed by
// fill_missing) or missing (no value). Lookups never read a missing cell: trilinear
// renormalizes the weights of the usable corners, nearest takes the closest usable cell of
// the surrounding 2x2x2 block; with none usable, both report false and eval returns 0.
// Each cell also keeps a confidence in [0, 1]: 1 for dense measured data, the clamped sum of
// splat weights for scattered data (as in Lawrence et al. 2006), 0 for filled cells.
// Limits: at most kMaxCells cells; values are stored as float (lookups return doubles).
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace sepal {

struct HalfDiff {
    double theta_h = 0, theta_d = 0, phi_d = 0;  // radians; phi_d in [-pi, pi]
};

// Exactly NOTES.md section 6: h = norm(wi + wo), theta_h = acos(h.z), phi_h = atan2(h.y, h.x),
// d = rotate_y(rotate_z(wi, -phi_h), -theta_h), theta_d = acos(d.z), phi_d = atan2(d.y, d.x).
HalfDiff to_half_diff(const glm::dvec3& wi, const glm::dvec3& wo);
// The inverse with phi_h = 0: wi = rotate_y(d, theta_h), wo = the mirror of wi about h.
void from_half_diff(const HalfDiff& a, glm::dvec3* wi, glm::dvec3* wo);

enum class ThetaHMapping { kLinear, kSqrt };

// The angles at the centre of cell i of an n_theta_h x n_theta_d x n_phi_d table (the layout
// and index formulas above); Tabulated::cell_center of a table of that shape.
HalfDiff table_cell_center(int n_theta_h, int n_theta_d, int n_phi_d, ThetaHMapping mapping,
                           size_t i);

// The cell of an n_theta_h x n_theta_d x n_phi_d table containing these angles (the index
// formulas above); Tabulated::cell_index of a table of that shape, without allocating one.
size_t table_cell_index(int n_theta_h, int n_theta_d, int n_phi_d, ThetaHMapping mapping, const HalfDiff& a);

class Tabulated {
  public:
    enum class State : uint8_t { kMissing = 0, kMeasured = 1, kFilled = 2 };
    static constexpr size_t kMaxCells = size_t(1) << 24;
    static constexpr int kMaxDim = 4096;

    // Allocates an all-missing table; false (with *err) on sizes out of range.
    bool init(int n_theta_h, int n_theta_d, int n_phi_d, ThetaHMapping mapping,
              std::string* err);
    // 90 x 90 x 180, sqrt theta_h: MERL's layout.
    static Tabulated merl();

    int n_theta_h() const { return n_[0]; }
    int n_theta_d() const { return n_[1]; }
    int n_phi_d() const { return n_[2]; }
    ThetaHMapping mapping() const { return mapping_; }
    size_t size() const { return state_.size(); }
    size_t index(int ih, int id, int ip) const {
        return size_t(ip) + size_t(n_[2]) * (size_t(id) + size_t(n_[1]) * size_t(ih));
    }
    // The cell containing these angles (the MERL index formulas for the MERL layout).
    size_t cell_index(const HalfDiff& a) const;
    // The angles at a cell's centre.
    HalfDiff cell_center(size_t index) const;

    // A value that is NaN, inf or beyond float range leaves the cell missing and is counted
    // in rejected() (so does splat with such a value: the sample is dropped).
    void set(size_t i, const glm::dvec3& v, float confidence = 1.0f,
             State s = State::kMeasured);
    size_t rejected() const { return rejected_; }
    void set_missing(size_t i);
    glm::dvec3 value(size_t i) const {
        return glm::dvec3(val_[3 * i], val_[3 * i + 1], val_[3 * i + 2]);
    }
    float confidence(size_t i) const { return conf_[i]; }
    State state(size_t i) const { return state_[i]; }
    bool usable(size_t i) const { return state_[i] != State::kMissing; }

    bool nearest(const HalfDiff& a, glm::dvec3* out) const;
    bool trilinear(const HalfDiff& a, glm::dvec3* out) const;
    // Trilinear at (wi, wo); exactly 0 when either is at or below the horizon or no cell is
    // usable nearby.
    glm::dvec3 eval(const glm::dvec3& wi, const glm::dvec3& wo) const;

    // Scattered data: kNearest adds each sample to the cell containing it; kTent spreads it
    // over the 8 cells around it with trilinear weights (the adjoint of trilinear lookup).
    // finish_splats turns the sums into cell values (weighted means), marks every cell with
    // weight as measured with confidence min(1, sum of weights) (Lawrence et al. 2006), and
    // counts the cells that contain a sample.
    enum class Kernel { kNearest, kTent };
    void splat(const HalfDiff& a, const glm::dvec3& v, double weight = 1.0,
               Kernel kernel = Kernel::kTent);
    void finish_splats();
    // Push-pull (Gortler et al. 1996, as used by Matusik et al. 2003 and Lawrence et al.
    // 2006): every missing cell gets a value from a pyramid of box-filtered coarser levels,
    // blended down by trilinear interpolation; measured cells keep their values where their
    // confidence is 1 (below 1 they are blended with the coarser level, as Gortler's push).
    // kLog1p runs the pyramid on log(1 + f) (f clamped at 0) and maps back with exp(x) - 1:
    // about linear over diffuse values (f << 1 per steradian) and logarithmic over
    // highlights, so one narrow, bright peak (a few hundred per steradian in measured paint)
    // does not flood the coarse levels and with them every empty cell. Returns the number of
    // cells filled (0 when nothing is measured).
    enum class FillDomain { kLinear, kLog1p };
    size_t fill_missing(FillDomain domain = FillDomain::kLog1p);

    struct Counts {
        size_t measured = 0, filled = 0, missing = 0;
        size_t occupied = 0;  // cells containing at least one splatted sample
    };
    Counts counts() const;

  private:
    // Continuous index-space coordinates (cell centres at integers) of angles.
    void coords(const HalfDiff& a, double c[3]) const;
    double theta_h_unit(double theta_h) const;  // 0..1 along the theta_h axis
    // The 8 cells around a point and their trilinear weights (summing to 1), shared by
    // lookup (trilinear, nearest) and its adjoint (splat).
    void corners(const HalfDiff& a, size_t cells[8], double weights[8]) const;

    int n_[3] = {0, 0, 0};
    ThetaHMapping mapping_ = ThetaHMapping::kLinear;
    std::vector<float> val_;    // 3 per cell, RGB
    std::vector<float> conf_;   // per cell
    std::vector<State> state_;  // per cell
    std::vector<double> acc_;   // while splatting: 4 per cell (weight, weighted RGB)
    std::vector<uint8_t> hit_;  // while splatting: cell contains a sample
    size_t occupied_ = 0;
    size_t rejected_ = 0;  // values refused by set() and splat() (not finite as floats)
};

}  // namespace sepal

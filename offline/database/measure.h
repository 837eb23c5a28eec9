// Measuring a new material from a plan (measure_plan.h): the virtual gonioreflectometer, the
// samples file, and the reconstruction as a linear combination of the database (Matusik et
// al. 2003, section 7) written as a MERL .binary.
//
// Usage:
//   std::vector<double> v;
//   sepal::simulate_samples(*db, plan, *brdf, 0.01, 1, &v, &err);     // 1% noise, seed 1
//   sepal::write_samples_csv("samples.csv", *db, plan, v, "nbrdf:gold-paint, noise 0.01", &err);
//   sepal::read_samples_csv("samples.csv", *db, plan, &v, &err);
//   sepal::DatabaseReconstruction r;
//   sepal::reconstruct(*db, plan, v, use, sepal::FitOptions{}, &r, &err);
//   sepal::write_reconstruction_merl("new.binary", *db, r, &err);
//
// The instrument: a sample is the BRDF at its cell's bin-centre direction pair (phi_h = 0) in
// one channel, times (1 + noise * n) with n standard normal (seeded, counter-based: sample i's
// noise does not depend on the others), clamped at 0.
// samples.csv: '#' comment lines, then the header
//   sample,cell,channel,theta_i,phi_i,theta_o,phi_o,value
// and one line per plan sample in plan order (angles in degrees, as plan.json; value in 1/sr,
// 9 significant digits). The reader checks that the lines match the plan (count, cell and
// channel of each), that every value is a finite number within +-kMaxSampleValue (1/sr),
// and that the file is under 64 MiB.
// The reconstruction: fit_combination's model (log space by default, linear_model.h) over every
// valid cell; values below 0 (linear least squares can produce them; the log model just below
// its floor) are set to 0 and counted: the BRDF is never negative, and the clamp only moves a
// value towards any non-negative truth.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "brdf/brdf.h"
#include "database/linear_model.h"
#include "database/measure_plan.h"

namespace sepal {

constexpr double kMaxSampleValue = 1e6;

bool simulate_samples(const BrdfDatabase& db, const MeasurementPlan& plan, const Brdf& f,
                      double noise, uint64_t seed, std::vector<double>* values, std::string* err);

// The instrument's noise alone: v_i *= 1 + noise * n_i (n_i standard normal, counter-based on
// (seed, i)), clamped at 0. simulate_samples applies it.
void add_noise(std::vector<double>* values, double noise, uint64_t seed);

bool write_samples_csv(const std::string& path, const BrdfDatabase& db, const MeasurementPlan& plan,
                       const std::vector<double>& values, const std::string& comment,
                       std::string* err);
bool read_samples_csv(const std::string& path, const BrdfDatabase& db, const MeasurementPlan& plan,
                      std::vector<double>* values, std::string* err);

struct DatabaseReconstruction {
    CombinationFit fit;
    std::vector<float> values;  // 3 per valid cell of the database grid, >= 0
    size_t clamped = 0;         // values of P c below 0, set to 0
};

bool reconstruct(const BrdfDatabase& db, const MeasurementPlan& plan,
                 const std::vector<double>& values, const std::vector<uint8_t>& use,
                 const FitOptions& opt, DatabaseReconstruction* r, std::string* err);

// Writes the reconstruction as a MERL .binary (cells below the horizon as -1). The database
// grid must be MERL's.
bool write_reconstruction_merl(const std::string& path, const BrdfDatabase& db,
                               const DatabaseReconstruction& r, std::string* err);

// The rows (3 per valid cell, as DatabaseReconstruction::values or a database column) as a BRDF
// with the MERL reader's lookup, as `write_reconstruction_merl` then `make_brdf(path)` gives
// it, without the file: to render a reconstruction and a database material the same way.
// The database grid must be MERL's.
std::unique_ptr<Brdf> rows_brdf(const BrdfDatabase& db, const std::vector<float>& values,
                                const std::string& name, std::string* err);

// A BRDF's values at the database rows (bin centres; 3 per valid cell), for errors against
// materials outside the database. Fails on a negative or non-finite value.
bool tabulate_rows(const BrdfDatabase& db, const Brdf& f, std::vector<float>* values,
                   std::string* err, int threads = 0);

// The material mask of "all but these names" (empty names: all); false on an unknown name.
bool exclude_mask(const BrdfDatabase& db, const std::vector<std::string>& names,
                  std::vector<uint8_t>* use, std::string* err);

}  // namespace sepal

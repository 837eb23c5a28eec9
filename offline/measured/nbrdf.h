// merl-nbrdf: the 100 MERL materials (Matusik et al. 2003) as small neural fits (Sztrajman et
// al. 2021), read from merl-nbrdf.json and evaluated exactly as its reference evaluator
// nbrdf_eval.py does.
//
// Usage:
//   std::unique_ptr<sepal::Brdf> f = sepal::make_brdf("nbrdf:gold-paint", &err);   // any spec
//   std::shared_ptr<const sepal::NbrdfSet> db = sepal::load_default_nbrdf_set(&err);
//   for (const sepal::NbrdfMaterial& m : db->materials()) m.eval(wi, wo);
//
// Where the data is (one rule): $SEPAL_DATA_DIR/merl-nbrdf/merl-nbrdf.json when SEPAL_DATA_DIR
// is set, else the first data/merl-nbrdf/merl-nbrdf.json or share/sepal/merl-nbrdf/merl-nbrdf.json
// found walking up from the directory of the running executable (build/bin/sepal and
// build/asan/bin/sepal-tests find the checkout's data/; PREFIX/bin/sepal finds what
// make install put in PREFIX/share/sepal/). data/merl-nbrdf/LICENSE is the fits' licence (MIT).
//
// Each material is an MLP 6 -> H1 -> H2 -> 3 (21, 21 in the file): input the Rusinkiewicz
// half/difference vectors with phi_h = 0, x = [sin theta_h, 0, cos theta_h, d.x, d.y, d.z];
// a1 = relu(x W1 + b1), a2 = relu(a1 W2 + b2), f = max(exp(a2 W3 + b3) - 1, 0): RGB in 1/sr
// (MERL's colour scales already applied); exactly 0 when either direction is at or below the
// horizon. Everything is double, so the values match nbrdf_eval.py to ~1e-12 relative.
// The fits are not exactly reciprocal (the network sees wi through d, not symmetrically).
//
// The reader refuses, with what and where: a file over 16 MiB, malformed JSON (line, column),
// a format other than "nbrdf-mlp-v1", layers other than [6, H1, H2, 3] with 1 <= H <= 256, a
// material missing a weight array or with one of the wrong shape, non-finite numbers, and no
// materials at all. Loaded sets are cached per path for the life of the process (parsing the
// 850 KB file takes ~20 ms; specs naming many materials parse it once).
#pragma once
#include <memory>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "brdf/brdf.h"

namespace sepal {

class NbrdfMaterial {
  public:
    const std::string& name() const { return name_; }
    // The BRDF (1/sr, RGB) at a direction pair; 0 below the horizon.
    glm::dvec3 eval(const glm::dvec3& wi, const glm::dvec3& wo) const;
    // The network on a prepared input (nbrdf_input), for tabulating many materials over
    // one grid without recomputing the directions.
    glm::dvec3 eval_input(const double x[6]) const;

  private:
    friend class NbrdfSet;
    std::string name_;
    int h1_ = 0, h2_ = 0;
    std::vector<double> w1_, b1_, w2_, b2_, w3_, b3_;  // row-major, row = input
};

// The network input of nbrdf_eval.py's inputs(wi, wo).
void nbrdf_input(const glm::dvec3& wi, const glm::dvec3& wo, double x[6]);

class NbrdfSet {
  public:
    // Parses the file's text; `name` (the path) prefixes every message.
    static std::shared_ptr<const NbrdfSet> parse(const std::string& text, const std::string& name,
                                                 std::string* err);
    const std::vector<NbrdfMaterial>& materials() const { return materials_; }
    size_t size() const { return materials_.size(); }
    // Index of a material by exact name, or -1.
    int find(const std::string& name) const;
    std::vector<std::string> names() const;
    const std::string& path() const { return path_; }
    const std::string& source() const { return source_; }
    // FNV-1a 64 of the file's bytes: keys caches built from this set.
    uint64_t content_hash() const { return hash_; }

  private:
    std::string path_, source_;
    uint64_t hash_ = 0;
    std::vector<NbrdfMaterial> materials_;
};

// The data file this process uses (see the rule above), or "" with *err saying where it
// looked.
std::string nbrdf_data_path(std::string* err);
// Loads (once per path per process) and returns the set.
std::shared_ptr<const NbrdfSet> load_nbrdf_set(const std::string& path, std::string* err);
std::shared_ptr<const NbrdfSet> load_default_nbrdf_set(std::string* err);

// The Brdf of "nbrdf:NAME" (make_brdf calls this for specs starting with "nbrdf:"). An
// unknown name lists the names that share its first word.
std::unique_ptr<Brdf> make_nbrdf_brdf(const std::string& spec, std::string* err);

}  // namespace sepal

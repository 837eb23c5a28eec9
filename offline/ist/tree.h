// An inverse shade tree: blend maps x basis BRDFs (the top level, decompose.h), each basis a
// sum of terms, each term a product of 1D curves (Lawrence et al. 2006, Trees 1 and 2):
//   S(uv, wi, wo) ~= sum_j w_j(uv) sum_k gt_jk(theta_x) gp_jk(phi_x) ht_jk(theta_y) hp_jk(phi_y)
// where x and y are the points of the factor parameterization (param.h): for the default
// gs-half x = h (theta_h, phi_h in the tangent frame) and y = wi in the frame (t', s', h)
// (theta_y = theta_d exactly; phi_y differs from Rusinkiewicz's phi_d by a rotation about
// h); for rusinkiewicz (the paper's choice; per-pixel backends only) x = h and y = d.
// Every curve holds RGB samples; colour may live in any curve. After a fit the phi curves
// have mean 1 per channel and the G theta curve peaks at 1, so the H theta curve (theta_d)
// carries each term's colour and magnitude, as in the paper's Fig. 15.
//
// Usage:
//   sepal::TreeOptions t;  sepal::ShadeTree tree;  std::string err;
//   sepal::build_tree(decomposition, t, &tree, &err);     // the second and third levels
//   sepal::write_tree("card.tree", tree, &err);  sepal::read_tree("card.tree", &tree, &err);
//   tree.swap_basis(1, "nbrdf:gold-paint", t, &err);        // or set_curve, set_blend
//   sepal::TreeSvbrdf exact(tree);                            // render_exact_spatial
//   sepal::Factored f = tree.textures(j);                     // basis j as factor textures
//
// Second level (per basis): the basis BRDF's values at the SVBRDF's direction pairs are
// tabulated as an isotropic table in (theta_h, theta_d, phi_d) with the scattered-data
// tabulation of measured/cornell.h (tent splats, mirrored in phi_d, push-pull on log(1+f)),
// and that table is factored by the factor engine (factor.h) with confidence-weighted ACLS
// (each cell weighted by its splat confidence above a floor, eq. 7): `terms` terms at
// `res` x `res`, the first held constant in the half vector (a diffuse-like lobe) and the
// others non-increasing in theta_h (section 4.3.2). A swapped basis (a BRDF spec or
// measured file) is factored the same way straight from its BRDF.
// Third level: each 2D factor, resampled on a polar grid (theta x phi, weighted by solid
// angle), is fitted by one product of two curves with the same solver (non-negative
// ACLS, rank 1 per channel). Theta curves have `curve_samples` knots on [0, 90] degrees
// (sqrt-spaced for the half-angle factor, where highlights are narrow), phi curves
// `curve_samples` knots on [0, 360) degrees, periodic; evaluation is linear between knots.
// Textures: a basis's factor textures are rasterized from its curves (texel centre ->
// point -> angles -> product; texels outside the map's disk take the disk's rim), so a
// curve edit changes what every backend draws.
// Tree format (a folder; docs/ist.md): tree.json, blend/J.pfm (grey float maps) and
// curves/bJ_tK_{g_theta,g_phi,h_theta,h_phi}.csv ("degrees,r,g,b" lines after a comment
// header). Curve id "j.i" names basis j, curve i = 4 k + {0 g_theta, 1 g_phi, 2 h_theta,
// 3 h_phi} of term k.
// Limits: isotropic bases (an anisotropic basis is represented by its average over phi_h
// at the second level); 1..8 bases, 1..4 terms per basis, 2..1024 knots per curve,
// parameterizations iv, gs-half, vh, rusinkiewicz with res 4..128.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "factor/factored.h"
#include "ist/decompose.h"
#include "ist/generate.h"
#include "reference/render_exact.h"

namespace sepal {

struct Curve {
    std::vector<double> x;       // radians, strictly increasing
    std::vector<glm::dvec3> y;   // RGB
    bool periodic = false;       // phi curves: x in [0, 2 pi), wraps
    glm::dvec3 at(double angle) const;
};

struct TreeTerm {
    Curve g_theta, g_phi, h_theta, h_phi;
    Curve& curve(int i) { return i == 0 ? g_theta : i == 1 ? g_phi : i == 2 ? h_theta : h_phi; }
    const Curve& curve(int i) const { return i == 0 ? g_theta : i == 1 ? g_phi : i == 2 ? h_theta : h_phi; }
};

struct TreeBasis {
    std::string name;
    std::string source = "decomposed";  // or the spec it was swapped for
    std::vector<TreeTerm> terms;
};

struct TreeOptions {
    Param param = Param::GsHalf;
    HemiMap map = HemiMap::XY;
    int res = 32;
    int terms = 2;
    bool constant_term = true;   // term 1 constant in the half vector
    bool monotonic = false;      // the others non-increasing in theta_h (hurts rough diffuse bases)
    int curve_samples = 64;
    int table_res[3] = {45, 45, 90};  // theta_h (sqrt), theta_d, phi_d of the basis tables
    // Weight of a table cell in the second-level fit: floor + (1 - floor) x its confidence
    // (push-pull filled cells: the floor).
    double confidence_floor = 1;
    // Then the factors are refitted to the samples themselves (factor/scattered.h): outer
    // iterations (0: off) and the Laplacian's relative weight.
    int refine_iterations = 40;
    double smoothness = 0.1;
    int threads = 0;
};

// Per basis: cosine-weighted RMS at the SVBRDF's pairs of each level against the basis
// values the top level found (Fig. 19: tabular, 2D factors, 1D curves).
struct LevelErrors {
    double tabular = 0, factors = 0, curves = 0;
};

class ShadeTree {
  public:
    Param param = Param::GsHalf;
    HemiMap map = HemiMap::XY;
    int res = 32;
    BlendMaps blend;
    std::vector<TreeBasis> bases;
    std::vector<LevelErrors> level_errors;  // from build_tree; empty after read_tree
    std::string provenance;                 // one line: how the tree was made

    int basis_count() const { return int(bases.size()); }
    // Basis j from its curves, exactly (no textures).
    glm::dvec3 eval_basis(int j, const glm::dvec3& wi, const glm::dvec3& wo) const;
    // Basis j as factor textures (res x res, RGB) rasterized from its curves.
    Factored textures(int j) const;

    // Edits (docs/ist.md): false with the reason, the tree unchanged.
    bool set_curve(int basis, int curve, const Curve& c, std::string* err);
    bool set_blend(int j, const Image& img, std::string* err);  // grey, or channel 0; resampled to the map size
    bool swap_basis(int j, const std::string& spec, const TreeOptions& o, std::string* err);
};

bool validate_tree(const ShadeTree& t, std::string* err);
bool build_tree(const Decomposition& d, const TreeOptions& o, ShadeTree* out, std::string* err);
// The curves of a factored BRDF (levels 2 -> 3 for one basis); used by build_tree and
// swap_basis.
bool curves_from_factors(const Factored& f, int curve_samples, int threads, TreeBasis* out, std::string* err);

bool write_tree(const std::string& dir, const ShadeTree& t, std::string* err);
bool read_tree(const std::string& dir, ShadeTree* t, std::string* err);
// A curve file: "degrees,r,g,b" per line, '#' comments; theta curves on [0, 90],
// phi curves on [0, 360) (periodic). Refuses unsorted, out-of-range or non-finite values.
bool read_curve_csv(const std::string& path, bool periodic, Curve* c, std::string* err);
bool write_curve_csv(const std::string& path, const Curve& c, const std::string& what, std::string* err);

// Basis j of a tree as a BRDF, evaluated exactly from its curves (the tree must outlive it).
std::unique_ptr<Brdf> tree_basis_brdf(const ShadeTree& t, int j);

// The tree evaluated per pixel from its curves: the exact render of a tree.
class TreeSvbrdf : public SpatialBrdf {
  public:
    explicit TreeSvbrdf(const ShadeTree& t) : t_(t) {}
    glm::dvec3 eval(const glm::dvec2& uv, const glm::dvec3& wi, const glm::dvec3& wo) const override;

  private:
    const ShadeTree& t_;
};

}  // namespace sepal

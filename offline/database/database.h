// The BRDF database of Matusik et al. 2003: the merl-nbrdf materials tabulated on the MERL grid
// (90 x 90 x 180, theta_h sqrt-spaced) or a coarser one, with the Gram matrices every linear
// model here is built from, cached on disk and memory-mapped.
//
// Usage:
//   auto set = sepal::load_default_nbrdf_set(&err);
//   sepal::DatabaseOptions o;  o.progress = stderr;          // MERL grid, all 100 materials
//   std::unique_ptr<sepal::BrdfDatabase> db = sepal::BrdfDatabase::open(*set, o, &err);
//   float f = db->value(k, row);            // material k at row = 3 * valid cell + channel
//   const double* G = db->gram();           // K x K, sum over all rows of P^T P
//
// Rows and columns: the database is a matrix P with one column per material and one row per
// (valid cell, channel); a valid cell is one whose bin-centre direction pair (tabulated.h,
// phi_h = 0) has both directions above the horizon: 1,096,216 of MERL's 1,458,000 cells.
// Values are the nbrdf network at the bin centre (exactly what `sepal gen-merl nbrdf:NAME`
// writes), in 1/sr, stored as float32.
//
// The cache: one file per (set contents, material list, grid) in cache_dir, default
// default_database_cache_dir(): $SEPAL_CACHE_DIR/database; for an installed tool,
// $XDG_CACHE_HOME/sepal/database (~/.cache/sepal/database); in a build tree
// build/cache/database. Layout: a header (magic, version, dims, counts, hashes of the JSON and
// the names, checksum of everything but the table), names, valid cells, the two Gram
// matrices, the planning pool, then the table (material-major, 4096-aligned). Building it
// (MERL grid, 100 materials: ~1.3 GB, about a minute on 2 cores) prints progress; the bytes
// do not depend on the thread count; it is written to a temporary and renamed. Opening checks
// the header, size and checksum and rebuilds a stale or corrupt file; the table itself is
// not checksummed on open (1.3 GB): `verify_table` does that on demand.
// Memory: the table is mmap'ed read-only, so it lives in the page cache (shared, evictable),
// not in the process; readers touch only the columns and rows they use.
//
// Gram matrices (double, summed per chunk of cells in chunk order): linear, G = P^T P, and in
// the log mapping y = log(f + kDatabaseLogEps), G_log = Y^T Y. With them the PCA of the
// database (linear_model.h) and the full-grid error of any linear combination of its
// columns, ||P c - P e_k||^2 = (c - e_k)^T G (c - e_k), cost O(K^2), no pass over the grid.
// The planning pool: a stratified random subset of valid cells (all of them on small grids),
// stored row-major (one row = K floats) so planning reads a few tens of MB, not the table.
// Limits: 1..256 materials; grid dims 1..512 each and at most 2^24 cells.
#pragma once
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "measured/nbrdf.h"
#include "measured/tabulated.h"

namespace sepal {

constexpr double kDatabaseLogEps = 1e-3;  // 1/sr: below the darkest diffuse albedo/pi in MERL

struct DatabaseGrid {
    int n_theta_h = 90, n_theta_d = 90, n_phi_d = 180;  // MERL's layout (theta_h sqrt-spaced)
    size_t cells() const { return size_t(n_theta_h) * n_theta_d * n_phi_d; }
    bool is_merl() const { return n_theta_h == 90 && n_theta_d == 90 && n_phi_d == 180; }
};

struct DatabaseOptions {
    DatabaseGrid grid;
    std::vector<std::string> materials;  // empty: every material of the set, in file order
    std::string cache_dir;               // empty: default_database_cache_dir()
    int threads = 0;                     // 0: all cores; the result does not depend on it
    FILE* progress = nullptr;            // progress lines while building, or nullptr
    size_t pool_cells = 32768;           // planning pool size in cells (capped at all valid)
};

class BrdfDatabase {
  public:
    static std::unique_ptr<BrdfDatabase> open(const NbrdfSet& set, const DatabaseOptions& o,
                                              std::string* err);
    ~BrdfDatabase();
    BrdfDatabase(const BrdfDatabase&) = delete;
    BrdfDatabase& operator=(const BrdfDatabase&) = delete;

    int size() const { return int(names_.size()); }  // K materials
    const std::string& name(int k) const { return names_[size_t(k)]; }
    const std::vector<std::string>& names() const { return names_; }
    int find(const std::string& name) const;
    const DatabaseGrid& grid() const { return grid_; }
    size_t valid_cells() const { return valid_.size(); }
    size_t rows() const { return 3 * valid_.size(); }
    // The full-grid index (Tabulated layout) of valid cell v.
    uint32_t grid_cell(size_t v) const { return valid_[v]; }
    // Valid cell of a full-grid index, or -1 when that cell is below the horizon.
    int64_t valid_index(size_t grid_cell) const;
    HalfDiff cell_center(size_t grid_cell) const;

    const float* column(int k) const { return table_ + size_t(k) * rows(); }
    float value(int k, size_t row) const { return column(k)[row]; }
    const double* gram() const { return gram_.data(); }      // K x K row-major
    const double* gram_log() const { return gram_log_.data(); }

    size_t pool_rows() const { return pool_cells_.size() * 3; }
    size_t pool_row_index(size_t i) const { return 3 * size_t(pool_cells_[i / 3]) + i % 3; }
    const float* pool_row(size_t i) const { return pool_ + i * size_t(size()); }

    const std::string& cache_path() const { return path_; }
    bool built_now() const { return built_now_; }  // false: read from the cache
    // Recomputes the table's checksum (reads the whole table).
    bool verify_table(std::string* err) const;

  private:
    BrdfDatabase() = default;
    bool map_file(const std::string& path, std::string* err);

    DatabaseGrid grid_;
    std::vector<std::string> names_;
    std::vector<uint32_t> valid_;        // full-grid index per valid cell
    std::vector<int32_t> valid_of_cell_;  // -1 or the valid index, per grid cell
    std::vector<uint32_t> pool_cells_;   // valid-cell indices of the pool
    std::vector<double> gram_, gram_log_;
    const float* table_ = nullptr;
    const float* pool_ = nullptr;
    uint64_t table_checksum_ = 0;
    void* map_ = nullptr;
    size_t map_bytes_ = 0;
    std::string path_;
    bool built_now_ = false;
};

// $SEPAL_CACHE_DIR/database when SEPAL_CACHE_DIR is set; else, for an installed tool (the
// executable's ../share/sepal holds the data), $XDG_CACHE_HOME/sepal/database or
// $HOME/.cache/sepal/database; else <executable dir>/../cache/database (a build tree).
std::string default_database_cache_dir();

// Bin centre of a grid cell (Tabulated's layout and index formulas, theta_h sqrt-spaced).
HalfDiff database_cell_center(const DatabaseGrid& g, size_t cell);

}  // namespace sepal

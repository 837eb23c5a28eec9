#include "database/database.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <mutex>

#include <Eigen/Core>

#include "util/io.h"
#include "util/parallel.h"

namespace sepal {

namespace {

constexpr char kMagic[8] = {'S', 'E', 'P', 'A', 'L', 'D', 'B', '1'};
constexpr uint32_t kVersion = 1;
constexpr size_t kChunkCells = 8192;  // cells per tabulation chunk (fixed: determinism)
constexpr size_t kNameBytes = 64;
constexpr size_t kAlign = 4096;

struct Header {
    char magic[8];
    uint32_t version, k, nh, nd, np, reserved;
    uint64_t valid, pool, json_hash, names_hash, table_checksum, meta_checksum;
    uint64_t off_names, off_valid, off_gram, off_pool_cells, off_pool, off_table, total;
};
static_assert(sizeof(Header) == 136, "header layout");

// A 64-bit FNV-style hash over 8-byte words (the tail byte-wise): fast enough for 1.3 GB.
uint64_t hash_bytes(const void* data, size_t n, uint64_t h = 1469598103934665603ULL) {
    const uint8_t* p = static_cast<const uint8_t*>(data);
    size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        uint64_t w;
        std::memcpy(&w, p + i, 8);
        h = (h ^ w) * 1099511628211ULL;
        h ^= h >> 29;
    }
    for (; i < n; ++i) h = (h ^ p[i]) * 1099511628211ULL;
    return h;
}

size_t align_up(size_t v) { return (v + kAlign - 1) / kAlign * kAlign; }

struct Layout {
    size_t names, valid, gram, pool_cells, pool, table, total;
};

Layout layout(size_t k, size_t v, size_t p) {
    Layout l;
    l.names = sizeof(Header);
    l.valid = l.names + k * kNameBytes;
    l.gram = l.valid + v * 4;
    l.gram = (l.gram + 7) / 8 * 8;
    l.pool_cells = l.gram + 2 * k * k * 8;
    l.pool = l.pool_cells + p * 4;
    l.pool = (l.pool + 7) / 8 * 8;
    l.table = align_up(l.pool + 3 * p * k * 4);
    l.total = l.table + 3 * v * k * 4;
    return l;
}

std::string hex64(uint64_t v) {
    char b[17];
    std::snprintf(b, sizeof b, "%016llx", (unsigned long long)v);
    return b;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Sums the chunks' Gram matrices (linear, log) in chunk order (thread-count independent),
// then mirrors the lower halves.
void sum_grams(const std::vector<double>& part, size_t chunks, size_t K, std::vector<double>* gram,
               std::vector<double>* gram_log) {
    gram->assign(K * K, 0.0);
    gram_log->assign(K * K, 0.0);
    for (size_t ch = 0; ch < chunks; ++ch)
        for (size_t i = 0; i < K * K; ++i) {
            (*gram)[i] += part[ch * 2 * K * K + i];
            (*gram_log)[i] += part[ch * 2 * K * K + K * K + i];
        }
    // rankUpdate filled the column-major lower triangle: (row b, col a) at a * K + b, b > a.
    for (size_t a = 0; a < K; ++a)
        for (size_t b = a + 1; b < K; ++b) {
            (*gram)[b * K + a] = (*gram)[a * K + b];
            (*gram_log)[b * K + a] = (*gram_log)[a * K + b];
        }
}

// Planning pool: stratified random over the V valid cells (in grid order, so spread over
// theta_h, which the sqrt spacing already makes dense near the specular peak).
std::vector<uint32_t> planning_pool(size_t V, size_t pool_cells) {
    std::vector<uint32_t> pool;
    const size_t P = std::min(std::max<size_t>(pool_cells, 1), V);
    for (size_t i = 0; i < P; ++i) {
        const double u = P == V ? 0.0 : counter_uniform(0x5eba1db, i);
        pool.push_back(uint32_t(std::min(V - 1, size_t((double(i) + u) * double(V) / double(P)))));
    }
    return pool;
}

// Everything but the table, which the workers wrote: header, names, valid cells, Gram
// matrices, the planning pool's cells and rows; checksums last.
void write_tables(const NbrdfSet& set, const std::vector<int>& idx, const DatabaseGrid& g, const Layout& l,
                  uint64_t names_hash, const std::vector<uint32_t>& valid, const std::vector<uint32_t>& pool,
                  const std::vector<double>& gram, const std::vector<double>& gram_log, uint8_t* base) {
    const size_t K = idx.size(), V = valid.size(), P = pool.size(), R = 3 * V;
    const float* table = reinterpret_cast<const float*>(base + l.table);
    Header h;
    std::memset(&h, 0, sizeof h);
    std::memcpy(h.magic, kMagic, 8);
    h.version = kVersion;
    h.k = uint32_t(K);
    h.nh = uint32_t(g.n_theta_h);
    h.nd = uint32_t(g.n_theta_d);
    h.np = uint32_t(g.n_phi_d);
    h.valid = V;
    h.pool = P;
    h.json_hash = set.content_hash();
    h.names_hash = names_hash;
    h.off_names = l.names;
    h.off_valid = l.valid;
    h.off_gram = l.gram;
    h.off_pool_cells = l.pool_cells;
    h.off_pool = l.pool;
    h.off_table = l.table;
    h.total = l.total;
    for (size_t k = 0; k < K; ++k) {
        const std::string& n = set.materials()[size_t(idx[k])].name();
        std::memcpy(base + l.names + k * kNameBytes, n.data(), n.size());
    }
    std::memcpy(base + l.valid, valid.data(), V * 4);
    std::memcpy(base + l.gram, gram.data(), K * K * 8);
    std::memcpy(base + l.gram + K * K * 8, gram_log.data(), K * K * 8);
    std::memcpy(base + l.pool_cells, pool.data(), P * 4);
    float* pool_rows = reinterpret_cast<float*>(base + l.pool);
    for (size_t i = 0; i < 3 * P; ++i)
        for (size_t k = 0; k < K; ++k)
            pool_rows[i * K + k] = table[k * R + 3 * size_t(pool[i / 3]) + i % 3];
    h.table_checksum = hash_bytes(table, R * K * sizeof(float));
    h.meta_checksum = hash_bytes(base + sizeof(Header), l.table - sizeof(Header),
                                 hash_bytes(&h, sizeof h));
    std::memcpy(base, &h, sizeof h);
}

// The materials, by index into the set (all when `names` is empty), and the hash of their
// names; false with the reason for an unknown, repeated or over-long name.
bool select_materials(const NbrdfSet& set, const std::vector<std::string>& names, std::vector<int>* out,
                      uint64_t* names_hash, std::string* why) {
    std::vector<int>& idx = *out;
    if (names.empty()) {
        for (size_t k = 0; k < set.size(); ++k) idx.push_back(int(k));
    } else {
        for (const std::string& n : names) {
            const int i = set.find(n);
            if (i < 0) return *why = "unknown material '" + n + "' (not in " + set.path() + ")", false;
            for (int j : idx)
                if (j == i) return *why = "material '" + n + "' is listed twice", false;
            idx.push_back(i);
        }
    }
    if (idx.empty() || idx.size() > 256) return *why = "1..256 materials, not " + std::to_string(idx.size()), false;
    std::string names_blob;
    for (int i : idx) {
        const std::string& n = set.materials()[size_t(i)].name();
        if (n.size() >= kNameBytes) return *why = "material name '" + n + "' is over 63 bytes", false;
        names_blob += n + '\n';
    }
    *names_hash = hash_bytes(names_blob.data(), names_blob.size());
    return true;
}

}  // namespace

std::string default_database_cache_dir() {
    if (const char* env = std::getenv("SEPAL_CACHE_DIR"))
        if (*env) return std::string(env) + "/database";
    const std::string exe = executable_dir();
    const size_t slash = exe.rfind('/');
    const std::string parent = slash == std::string::npos ? std::string("build") : exe.substr(0, slash);
    // An installed tool (PREFIX/bin next to PREFIX/share/sepal) may not write under PREFIX:
    // its cache is the user's (XDG). A build tree's stays in it (make clean removes it).
    struct stat installed;
    if (stat((parent + "/share/sepal/merl-nbrdf/merl-nbrdf.json").c_str(), &installed) == 0) {
        if (const char* xdg = std::getenv("XDG_CACHE_HOME"))
            if (*xdg == '/') return std::string(xdg) + "/sepal/database";
        if (const char* home = std::getenv("HOME"))
            if (*home) return std::string(home) + "/.cache/sepal/database";
    }
    return parent + "/cache/database";
}

HalfDiff database_cell_center(const DatabaseGrid& g, size_t cell) {
    return table_cell_center(g.n_theta_h, g.n_theta_d, g.n_phi_d, ThetaHMapping::kSqrt, cell);
}

BrdfDatabase::~BrdfDatabase() {
    if (map_) munmap(map_, map_bytes_);
}

int BrdfDatabase::find(const std::string& name) const {
    for (size_t k = 0; k < names_.size(); ++k)
        if (names_[k] == name) return int(k);
    return -1;
}

int64_t BrdfDatabase::valid_index(size_t cell) const {
    return cell < valid_of_cell_.size() ? valid_of_cell_[cell] : -1;
}

HalfDiff BrdfDatabase::cell_center(size_t cell) const { return database_cell_center(grid_, cell); }

bool BrdfDatabase::verify_table(std::string* err) const {
    const uint64_t h = hash_bytes(table_, rows() * size_t(size()) * sizeof(float));
    if (h == table_checksum_) return true;
    if (err) *err = path_ + ": the table's checksum does not match (a corrupt cache: delete it)";
    return false;
}

bool BrdfDatabase::map_file(const std::string& path, std::string* err) {
    auto fail = [&](const std::string& why) {
        if (err) *err = path + ": " + why;
        return false;
    };
    const int fd = ::open(path.c_str(), O_RDONLY);
    if (fd < 0) return fail(std::strerror(errno));
    struct stat st;
    if (fstat(fd, &st) != 0 || size_t(st.st_size) < sizeof(Header)) {
        ::close(fd);
        return fail("too short for a database header");
    }
    void* m = mmap(nullptr, size_t(st.st_size), PROT_READ, MAP_SHARED, fd, 0);
    ::close(fd);
    if (m == MAP_FAILED) return fail(std::string("mmap: ") + std::strerror(errno));
    map_ = m;
    map_bytes_ = size_t(st.st_size);
    const uint8_t* base = static_cast<const uint8_t*>(m);
    Header h;
    std::memcpy(&h, base, sizeof h);
    if (std::memcmp(h.magic, kMagic, 8) != 0 || h.version != kVersion)
        return fail("not a sepal database cache of version " + std::to_string(kVersion));
    const Layout l = layout(h.k, h.valid, h.pool);
    if (h.total != l.total || map_bytes_ != l.total || h.off_table != l.table)
        return fail("size " + std::to_string(map_bytes_) + " does not match its header");
    Header hz = h;
    hz.meta_checksum = 0;
    const uint64_t meta = hash_bytes(base + sizeof(Header), l.table - sizeof(Header),
                                     hash_bytes(&hz, sizeof hz));
    if (meta != h.meta_checksum) return fail("header checksum mismatch");
    grid_.n_theta_h = int(h.nh);
    grid_.n_theta_d = int(h.nd);
    grid_.n_phi_d = int(h.np);
    names_.clear();
    for (uint32_t k = 0; k < h.k; ++k) {
        const char* s = reinterpret_cast<const char*>(base + l.names + k * kNameBytes);
        names_.emplace_back(s, strnlen(s, kNameBytes));
    }
    valid_.resize(h.valid);
    std::memcpy(valid_.data(), base + l.valid, h.valid * 4);
    valid_of_cell_.assign(grid_.cells(), -1);
    for (size_t v = 0; v < valid_.size(); ++v) {
        if (valid_[v] >= valid_of_cell_.size()) return fail("valid cell index out of range");
        valid_of_cell_[valid_[v]] = int32_t(v);
    }
    gram_.resize(size_t(h.k) * h.k);
    gram_log_.resize(size_t(h.k) * h.k);
    std::memcpy(gram_.data(), base + l.gram, gram_.size() * 8);
    std::memcpy(gram_log_.data(), base + l.gram + gram_.size() * 8, gram_log_.size() * 8);
    pool_cells_.resize(h.pool);
    std::memcpy(pool_cells_.data(), base + l.pool_cells, h.pool * 4);
    for (uint32_t p : pool_cells_)
        if (p >= h.valid) return fail("pool cell index out of range");
    pool_ = reinterpret_cast<const float*>(base + l.pool);
    table_ = reinterpret_cast<const float*>(base + l.table);
    table_checksum_ = h.table_checksum;
    path_ = path;
    return true;
}

std::unique_ptr<BrdfDatabase> BrdfDatabase::open(const NbrdfSet& set, const DatabaseOptions& o,
                                                 std::string* err) {
    auto fail = [&](const std::string& why) -> std::unique_ptr<BrdfDatabase> {
        if (err) *err = "database: " + why;
        return nullptr;
    };
    const DatabaseGrid& g = o.grid;
    if (g.n_theta_h < 1 || g.n_theta_d < 1 || g.n_phi_d < 1 || g.n_theta_h > 512 ||
        g.n_theta_d > 512 || g.n_phi_d > 512 || g.cells() > (size_t(1) << 24))
        return fail("grid " + std::to_string(g.n_theta_h) + " x " + std::to_string(g.n_theta_d) +
                    " x " + std::to_string(g.n_phi_d) + " is outside 1..512 per axis, 2^24 cells");
    std::vector<int> idx;
    uint64_t names_hash = 0;
    std::string why;
    if (!select_materials(set, o.materials, &idx, &names_hash, &why)) return fail(why);
    uint64_t key = hash_bytes(&kVersion, sizeof kVersion, set.content_hash() ^ names_hash);
    const int dims[4] = {g.n_theta_h, g.n_theta_d, g.n_phi_d, int(o.pool_cells)};
    key = hash_bytes(dims, sizeof dims, key);
    const std::string dir = o.cache_dir.empty() ? default_database_cache_dir() : o.cache_dir;
    const std::string path = dir + "/nbrdf-" + std::to_string(g.n_theta_h) + "x" +
                             std::to_string(g.n_theta_d) + "x" + std::to_string(g.n_phi_d) + "-" +
                             std::to_string(idx.size()) + "m-" + hex64(key) + ".db";

    std::unique_ptr<BrdfDatabase> db(new BrdfDatabase());
    {
        struct stat st;
        std::string why;
        if (stat(path.c_str(), &st) == 0) {
            // The table is checked too: a cache overwritten in place would otherwise give
            // reconstructions and plans of garbage.
            if (db->map_file(path, &why) && db->names_.size() == idx.size() && db->verify_table(&why)) return db;
            if (o.progress) std::fprintf(o.progress, "database: rebuilding %s (%s)\n", path.c_str(), why.c_str());
            db.reset(new BrdfDatabase());
        }
    }

    // ---- build ----
    const auto t0 = std::chrono::steady_clock::now();
    const size_t K = idx.size(), cells = g.cells();
    std::vector<uint32_t> valid;
    for (size_t i = 0; i < cells; ++i) {
        glm::dvec3 wi, wo;
        from_half_diff(database_cell_center(g, i), &wi, &wo);
        if (wi.z > 0.0 && wo.z > 0.0) valid.push_back(uint32_t(i));
    }
    const size_t V = valid.size();
    if (V == 0) return fail("the grid has no cell with both directions above the horizon");
    const std::vector<uint32_t> pool = planning_pool(V, o.pool_cells);
    const size_t P = pool.size();
    const Layout l = layout(K, V, P);
    if (!make_dirs(dir, err)) return nullptr;
    // The space is said and reserved before the work: the table is written through a mapping,
    // where a full disk is SIGBUS rather than an error.
    char need[200];
    const int64_t avail = free_bytes(dir);
    std::snprintf(need, sizeof need, "the cache needs %.0f MB in %s (%.0f MB free there; SEPAL_CACHE_DIR moves it)",
                  double(l.total) / 1e6, dir.c_str(), double(avail) / 1e6);
    if (o.progress) std::fprintf(o.progress, "database: %s\n", need);
    if (avail >= 0 && uint64_t(avail) < l.total) return fail(path + ": " + need);
    const std::string tmp = path + ".tmp." + std::to_string(getpid());
    register_temporary(tmp);  // removed on SIGINT/SIGTERM too
    auto fail_tmp = [&](const std::string& why) {
        std::remove(tmp.c_str());
        unregister_temporary(tmp);
        return fail(why);
    };
    const int fd = ::open(tmp.c_str(), O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) return fail_tmp(tmp + ": " + std::strerror(errno));
    const int rc = reserve_file(fd, l.total);
    if (rc != 0) {
        ::close(fd);
        return fail_tmp(tmp + ": cannot reserve " + std::to_string(l.total) + " bytes: " + std::strerror(rc) + "; " +
                        need);
    }
    void* m = mmap(nullptr, l.total, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
    ::close(fd);
    if (m == MAP_FAILED) return fail_tmp(tmp + ": mmap: " + std::strerror(errno));
    uint8_t* base = static_cast<uint8_t*>(m);
    float* table = reinterpret_cast<float*>(base + l.table);
    const size_t R = 3 * V;
    if (o.progress)
        std::fprintf(o.progress,
                     "database: tabulating %zu materials on %d x %d x %d (%zu cells above the "
                     "horizon) into %s (%.0f MB)\n",
                     K, g.n_theta_h, g.n_theta_d, g.n_phi_d, V, path.c_str(), l.total / 1e6);

    const size_t chunks = (V + kChunkCells - 1) / kChunkCells;
    std::vector<double> part(chunks * 2 * K * K, 0.0);  // per chunk: G, G_log (lower halves)
    const int nw = workers(chunks, o.threads);
    std::vector<Eigen::MatrixXd> dlin{size_t(nw)}, dlog{size_t(nw)};
    std::atomic<size_t> done{0};
    std::mutex mu;
    int reported = 0;
    parallel_for_workers(chunks, o.threads, [&](size_t ch, int w) {
        const size_t v0 = ch * kChunkCells, v1 = std::min(V, v0 + kChunkCells);
        const size_t n = v1 - v0;
        Eigen::MatrixXd& D = dlin[size_t(w)];
        Eigen::MatrixXd& L = dlog[size_t(w)];
        D.resize(Eigen::Index(3 * n), Eigen::Index(K));
        L.resize(Eigen::Index(3 * n), Eigen::Index(K));
        for (size_t v = v0; v < v1; ++v) {
            glm::dvec3 wi, wo;
            from_half_diff(database_cell_center(g, valid[v]), &wi, &wo);
            double x[6];
            nbrdf_input(wi, wo, x);
            for (size_t k = 0; k < K; ++k) {
                const glm::dvec3 f = set.materials()[size_t(idx[k])].eval_input(x);
                for (int c = 0; c < 3; ++c) {
                    const float fv = float(f[c]);
                    table[k * R + 3 * v + size_t(c)] = fv;
                    const Eigen::Index r = Eigen::Index(3 * (v - v0) + size_t(c));
                    D(r, Eigen::Index(k)) = fv;  // the Gram of the stored (float) values
                    L(r, Eigen::Index(k)) = std::log(double(fv) + kDatabaseLogEps);
                }
            }
        }
        Eigen::Map<Eigen::MatrixXd> G(&part[ch * 2 * K * K], Eigen::Index(K), Eigen::Index(K));
        Eigen::Map<Eigen::MatrixXd> GL(&part[ch * 2 * K * K + K * K], Eigen::Index(K), Eigen::Index(K));
        G.selfadjointView<Eigen::Lower>().rankUpdate(D.transpose());
        GL.selfadjointView<Eigen::Lower>().rankUpdate(L.transpose());
        const size_t d = ++done;
        if (o.progress) {
            std::lock_guard<std::mutex> lock(mu);
            const int pct = int(100 * d / chunks);
            if (pct >= reported + 10 || d == chunks) {
                reported = pct - pct % 10;
                std::fprintf(o.progress, "database:   %3d%%  %.1f s\n", pct, seconds_since(t0));
                std::fflush(o.progress);
            }
        }
    });
    std::vector<double> gram, gram_log;
    sum_grams(part, chunks, K, &gram, &gram_log);

    write_tables(set, idx, g, l, names_hash, valid, pool, gram, gram_log, base);
    const bool synced = msync(m, l.total, MS_SYNC) == 0;
    const std::string sync_why = synced ? "" : std::strerror(errno);
    munmap(m, l.total);
    if (!synced) return fail_tmp(tmp + ": cannot write the cache: " + sync_why);
    if (std::rename(tmp.c_str(), path.c_str()) != 0)
        return fail_tmp(path + ": cannot rename the finished cache: " + std::strerror(errno));
    unregister_temporary(tmp);
    if (!db->map_file(path, err)) return nullptr;
    db->built_now_ = true;
    if (o.progress)
        std::fprintf(o.progress, "database: built in %.1f s\n", seconds_since(t0));
    return db;
}

}  // namespace sepal

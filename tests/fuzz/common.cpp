// Helpers shared by the fuzz harnesses (fuzz.h).
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>

#include "database/database.h"
#include "database/measure_plan.h"
#include "fuzz/fuzz.h"
#include "measured/nbrdf.h"
#include "sepal/sepal_asset.h"

namespace sepal_fuzz {

void check(bool ok, const char* harness, const char* what) {
    if (ok) return;
    std::fprintf(stderr, "fuzz %s: %s\n", harness, what);
    std::abort();
}

void fix_asset_checksums(std::vector<uint8_t>* bytes) {
    std::vector<uint8_t>& b = *bytes;
    if (b.size() < sizeof(sepal_fmt_header)) return;
    sepal_fmt_header h;
    std::memcpy(&h, b.data(), sizeof h);
    h.file_bytes = b.size();
    const size_t room = (b.size() - sizeof h) / sizeof(sepal_fmt_chunk);
    const size_t count = h.chunk_count < room ? h.chunk_count : room;
    for (size_t i = 0; i < count; ++i) {
        uint8_t* entry = b.data() + sizeof h + i * sizeof(sepal_fmt_chunk);
        sepal_fmt_chunk c;
        std::memcpy(&c, entry, sizeof c);
        if (c.offset > b.size() || c.size > b.size() - c.offset) continue;
        c.crc = sepal_crc32(0, b.data() + c.offset, size_t(c.size));
        std::memcpy(entry, &c, sizeof c);
    }
    h.header_crc = 0;
    std::memcpy(b.data(), &h, sizeof h);
    const size_t table = h.chunk_count <= room ? size_t(h.chunk_count) * sizeof(sepal_fmt_chunk) : 0;
    uint32_t crc = sepal_crc32(0, b.data(), sizeof h);
    crc = sepal_crc32(crc, b.data() + sizeof h, table);
    h.header_crc = crc;
    std::memcpy(b.data(), &h, sizeof h);
}

const std::string& scratch_dir() {
    static const std::string dir = [] {
        struct stat st;
        const std::string root = stat("/dev/shm", &st) == 0 && S_ISDIR(st.st_mode) ? "/dev/shm" : "/tmp";
        const std::string d = root + "/sepal-fuzz-" + std::to_string(getpid());
        mkdir(d.c_str(), 0700);
        return d;
    }();
    return dir;
}

std::string write_scratch(const std::string& name, const uint8_t* data, size_t size) {
    const std::string path = scratch_dir() + "/" + name;
    FILE* f = std::fopen(path.c_str(), "wb");
    check(f != nullptr, "scratch", "cannot write the scratch folder");
    if (size) check(std::fwrite(data, 1, size, f) == size, "scratch", "cannot write the scratch folder");
    std::fclose(f);
    return path;
}

const sepal::BrdfDatabase& database() {
    static const std::unique_ptr<sepal::BrdfDatabase> db = [] {
        std::string err;
        auto set = sepal::load_nbrdf_set(std::string(SEPAL_SOURCE_DIR) + "/data/merl-nbrdf/merl-nbrdf.json", &err);
        check(bool(set), "database", err.c_str());
        sepal::DatabaseOptions o;
        o.grid.n_theta_h = 16;
        o.grid.n_theta_d = 16;
        o.grid.n_phi_d = 32;
        o.materials = {"gold-paint", "blue-acrylic", "red-plastic", "silver-paint", "black-phenolic", "white-paint"};
        o.cache_dir = scratch_dir() + "/database";
        o.threads = 1;
        auto d = sepal::BrdfDatabase::open(*set, o, &err);
        check(bool(d), "database", err.c_str());
        return d;
    }();
    return *db;
}

const sepal::MeasurementPlan& samples_plan() {
    static const sepal::MeasurementPlan plan = [] {
        sepal::PlanOptions o;
        o.samples = 40;
        o.method = sepal::PlanMethod::kUniform;
        sepal::MeasurementPlan p;
        std::string err;
        check(sepal::plan_measurement(database(), o, &p, &err), "samples", err.c_str());
        return p;
    }();
    return plan;
}

}  // namespace sepal_fuzz

#include "util/io.h"

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <sys/stat.h>
#include <unistd.h>

namespace sepal {

bool read_file(const std::string& path, std::vector<uint8_t>* out, std::string* err,
               uint64_t max_bytes) {
    FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) {
        if (err) *err = path + ": " + std::strerror(errno);
        return false;
    }
    struct stat st;
    if (fstat(fileno(f), &st) != 0 || !S_ISREG(st.st_mode)) {
        if (err) *err = path + ": not a regular file";
        std::fclose(f);
        return false;
    }
    if (uint64_t(st.st_size) > max_bytes) {
        if (err)
            *err = path + ": " + std::to_string(st.st_size) + " bytes is over the limit of " +
                   std::to_string(max_bytes);
        std::fclose(f);
        return false;
    }
    out->resize(size_t(st.st_size));
    const size_t got = out->empty() ? 0 : std::fread(out->data(), 1, out->size(), f);
    const bool ok = got == out->size() && !std::ferror(f);
    std::fclose(f);
    if (!ok && err) *err = path + ": read error";
    return ok;
}

namespace {
std::atomic<int64_t> g_write_fault{-1};
}  // namespace

void inject_write_failure(int64_t bytes) { g_write_fault = bytes < 0 ? -1 : bytes; }

bool write_file_atomic(const std::string& path, const void* data, size_t size,
                       std::string* err) {
    const std::string tmp = path + ".tmp." + std::to_string(getpid());
    FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f) {
        if (err) *err = path + ": cannot write: " + std::strerror(errno);
        return false;
    }
    const int64_t fault = g_write_fault;
    const bool short_write = fault >= 0 && uint64_t(fault) < size;
    const size_t n = short_write ? size_t(fault) : size;
    bool ok = n == 0 || std::fwrite(data, 1, n, f) == n;
    ok = (std::fflush(f) == 0) && ok;
    ok = (std::fclose(f) == 0) && ok;
    if (short_write) ok = false, errno = ENOSPC;  // what a full disk reports
    if (ok && std::rename(tmp.c_str(), path.c_str()) != 0) ok = false;
    if (!ok) {
        if (err) *err = path + ": write failed: " + std::strerror(errno);
        std::remove(tmp.c_str());
    }
    return ok;
}

bool make_dirs(const std::string& path, std::string* err) {
    std::string partial;
    size_t pos = 0;
    while (pos != std::string::npos) {
        pos = path.find('/', pos + 1);
        partial = path.substr(0, pos);
        if (partial.empty()) continue;
        if (mkdir(partial.c_str(), 0755) != 0 && errno != EEXIST) {
            if (err) *err = partial + ": " + std::strerror(errno);
            return false;
        }
    }
    return true;
}

double physical_memory_mb() {
    const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
    return pages > 0 && page > 0 ? double(pages) * double(page) / (1024.0 * 1024.0) : 0.0;
}

std::string executable_dir() {
    char buf[4096];
    const ssize_t n = readlink("/proc/self/exe", buf, sizeof buf - 1);
    if (n <= 0) return "";
    const std::string p(buf, size_t(n));
    const size_t slash = p.rfind('/');
    return slash == std::string::npos ? std::string() : p.substr(0, slash);
}

std::string file_extension(const std::string& path) {
    const size_t slash = path.find_last_of('/');
    const size_t dot = path.find_last_of('.');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
    std::string e = path.substr(dot + 1);
    for (char& c : e) c = char(std::tolower(static_cast<unsigned char>(c)));
    return e;
}

OutputGuard::~OutputGuard() {
    for (const std::string& p : paths_) std::remove(p.c_str());
}

}  // namespace sepal

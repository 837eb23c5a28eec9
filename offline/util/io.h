// File helpers for offline tools: whole-file reads and atomic writes.
//
// Every output file of sepal is written through write_file_atomic: the bytes go to a
// temporary file beside the target, which is renamed over it only when complete, so a
// failure never leaves a half-written output.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace sepal {

// Reads a whole file; refuses files larger than max_bytes (a bound on every input).
bool read_file(const std::string& path, std::vector<uint8_t>* out, std::string* err,
               uint64_t max_bytes = uint64_t(1) << 31);
bool write_file_atomic(const std::string& path, const void* data, size_t size,
                       std::string* err);
// Fault injection for tests: every later write_file_atomic stores at most `bytes` bytes of
// its file and then fails as a full disk does (ENOSPC); a negative value turns it off.
void inject_write_failure(int64_t bytes);
// The files one command has written: unless commit() is called, the destructor removes them,
// so a command that fails part-way (the second of two outputs cannot be written) leaves none
// of its outputs behind.
//   OutputGuard written;
//   if (!write_png(a, ...) || !written.add(a) || !write_pfm(b, ...)) return fail;  // a removed
//   written.commit();
class OutputGuard {
  public:
    OutputGuard() = default;
    OutputGuard(const OutputGuard&) = delete;
    OutputGuard& operator=(const OutputGuard&) = delete;
    ~OutputGuard();
    bool add(const std::string& path) {  // true, to chain after a successful write
        paths_.push_back(path);
        return true;
    }
    void commit() { paths_.clear(); }

  private:
    std::vector<std::string> paths_;
};
// Creates a directory and its parents (like mkdir -p).
bool make_dirs(const std::string& path, std::string* err);
// The folder of the running executable (Linux: /proc/self/exe), or "" when unknown. Run-time
// data (data/) and caches (build/cache) are found relative to it.
std::string executable_dir();
// Physical memory in MB (0 when unknown): what a command's memory estimate is held to
// before it allocates.
double physical_memory_mb();
// Lower-cased extension without the dot ("png"), or "" when there is none.
std::string file_extension(const std::string& path);

}  // namespace sepal

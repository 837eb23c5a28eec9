// File helpers for offline tools: whole-file reads and atomic writes.
//
// Every output file of sepal is written through write_file_atomic, which writes what the
// path names: a regular file (or a new one) gets a temporary beside it that is renamed over it
// only when complete, so a failure never leaves a half-written output; a symlink is followed
// and its target written the same way (the link stays a link); a FIFO or a device (/dev/null,
// /dev/stdout) is written directly; a folder, socket or other special file is refused.
// Temporaries and the folders make_dirs creates are removed on failure and on SIGINT/SIGTERM.
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
// All-or-nothing outputs of one command. While an OutputGuard is open, write_file_atomic
// and make_dirs stage: files go to temporaries (writes to FIFOs and devices are held in
// memory) and nothing the user had is touched; commit() then writes the FIFOs and devices
// and renames every temporary over its path. Without commit (an error return, an exception,
// SIGINT/SIGTERM) the temporaries and the folders made are removed, so every path holds
// what it held before. A staged file cannot be read back before commit.
//   OutputGuard written;
//   if (!write_png(a, ...) || !write_pfm(b, ...) || !written.commit(&err)) return fail(err);
// Guards nest (the innermost stages); one command's writes happen on one thread at a time.
class OutputGuard {
  public:
    OutputGuard();
    OutputGuard(const OutputGuard&) = delete;
    OutputGuard& operator=(const OutputGuard&) = delete;
    ~OutputGuard();
    bool commit(std::string* err);

    struct Staged {
        std::string path, tmp;       // tmp empty: write `bytes` to path directly (FIFO, device)
        std::vector<uint8_t> bytes;
    };

  private:
    friend bool write_file_atomic(const std::string&, const void*, size_t, std::string*);
    friend bool make_dirs(const std::string&, std::string*);
    std::vector<Staged> staged_;
    std::vector<std::string> dirs_;  // made while open, parents first
    OutputGuard* outer_ = nullptr;
    bool done_ = false;
};
// Checks before a command's work that each path can be written (flag names the option, as
// "-o" or "--report", and starts the message): an existing path must be a writable regular
// file (through symlinks), FIFO or device, a new one's folder must exist and take a new file.
// Empty paths are skipped.
bool check_output(const std::string& flag, const std::string& path, std::string* err);
// The same for an output folder (--export DIR): an existing folder that takes new files, or
// one make_dirs can create.
bool check_output_dir(const std::string& flag, const std::string& dir, std::string* err);
// A temporary that SIGINT and SIGTERM remove (sepal's handler, installed where the signal
// still has its default action, then re-raises it): register while it exists, unregister
// after it is renamed or removed.
void register_temporary(const std::string& path);
void unregister_temporary(const std::string& path);
// Gives a file its size with every block allocated (posix_fallocate), so writes through a
// mapping of it cannot fail later (a full disk there is SIGBUS). Returns 0 or the errno;
// honours inject_write_failure (ENOSPC past its byte count).
int reserve_file(int fd, uint64_t bytes);
// Bytes free to this user in the folder's file system (statvfs), or -1 when unknown.
int64_t free_bytes(const std::string& folder);
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

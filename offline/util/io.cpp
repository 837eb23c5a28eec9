#include "util/io.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <atomic>
#include <climits>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>

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

// Temporaries and made folders that SIGINT/SIGTERM remove: fixed slots of heap strings, so the
// handler only loads pointers and calls unlink/rmdir (async-signal-safe). 'f' files, 'd' folders.
constexpr int kSlots = 4096;
std::atomic<char*> g_slots[kSlots];

void cleanup_registered() {
    for (int i = 0; i < kSlots; ++i) {
        const char* p = g_slots[i].load();
        if (p && p[0] == 'f') unlink(p + 1);
    }
    for (int i = kSlots - 1; i >= 0; --i) {  // children were registered after their parents
        const char* p = g_slots[i].load();
        if (p && p[0] == 'd') rmdir(p + 1);
    }
}

void on_signal(int sig) {
    cleanup_registered();
    signal(sig, SIG_DFL);
    raise(sig);
}

// Checked at every registration, not once: a signal whose handler is someone else's (a test
// harness, an embedding program) is left alone, and one reset to the default since gets ours.
void install_handlers() {
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
        struct sigaction old;
        if (sigaction(sig, nullptr, &old) != 0 || old.sa_handler != SIG_DFL) continue;
        struct sigaction sa;
        std::memset(&sa, 0, sizeof sa);
        sa.sa_handler = on_signal;
        sigemptyset(&sa.sa_mask);
        sigaction(sig, &sa, nullptr);
    }
}

void register_slot(char kind, const std::string& path) {
    install_handlers();
    char* p = static_cast<char*>(std::malloc(path.size() + 2));
    if (!p) return;
    p[0] = kind;
    std::memcpy(p + 1, path.c_str(), path.size() + 1);
    for (int i = 0; i < kSlots; ++i) {
        char* expected = nullptr;
        if (g_slots[i].compare_exchange_strong(expected, p)) return;
    }
    std::free(p);  // all slots taken: this one is cleaned on failure, not on a signal
}

void unregister_slot(char kind, const std::string& path) {
    for (int i = 0; i < kSlots; ++i) {
        char* p = g_slots[i].load();
        if (p && p[0] == kind && path == p + 1 && g_slots[i].compare_exchange_strong(p, nullptr)) {
            std::free(p);
            return;
        }
    }
}

std::mutex g_guard_mu;
OutputGuard* g_guard = nullptr;  // the innermost open guard

std::string parent_dir(const std::string& path) {
    const size_t slash = path.find_last_of('/');
    if (slash == std::string::npos) return ".";
    return slash == 0 ? "/" : path.substr(0, slash);
}

// Follows symlinks to the path a write lands on. *exists false: nothing is there yet (a new
// file, or the missing target of a dangling link, which the write creates as `>` does).
bool resolve_output(const std::string& path, std::string* target, struct stat* st, bool* exists,
                    std::string* err) {
    std::string p = path;
    for (int hops = 0; hops < 40; ++hops) {
        if (lstat(p.c_str(), st) != 0) {
            if (errno == ENOENT) {
                *target = p;
                *exists = false;
                return true;
            }
            if (err) *err = path + ": " + std::strerror(errno);
            return false;
        }
        if (!S_ISLNK(st->st_mode)) {
            *target = p;
            *exists = true;
            return true;
        }
        char buf[4096];
        const ssize_t n = readlink(p.c_str(), buf, sizeof buf - 1);
        if (n <= 0) {
            if (err) *err = path + ": cannot read the symlink " + p + ": " + std::strerror(errno);
            return false;
        }
        const std::string link(buf, size_t(n));
        p = link[0] == '/' ? link : parent_dir(p) + "/" + link;
    }
    if (err) *err = path + ": too many levels of symlinks";
    return false;
}

bool direct_kind(const struct stat& st) {
    return S_ISFIFO(st.st_mode) || S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode);
}

// Why a write to an existing path of this kind is refused ("" when it is not).
std::string refuse_kind(const struct stat& st) {
    if (S_ISREG(st.st_mode) || direct_kind(st)) return "";
    if (S_ISDIR(st.st_mode)) return "is a folder, not a file";
    if (S_ISSOCK(st.st_mode)) return "is a socket: sepal writes regular files, FIFOs and devices";
    return "is a special file: sepal writes regular files, FIFOs and devices";
}

// Stores at most the injected fault's bytes; false with errno ENOSPC past it.
bool write_all(int fd, const void* data, size_t size) {
    const int64_t fault = g_write_fault;
    const bool short_write = fault >= 0 && uint64_t(fault) < size;
    size_t n = short_write ? size_t(fault) : size;
    const char* p = static_cast<const char*>(data);
    while (n > 0) {
        const ssize_t w = ::write(fd, p, n);
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) {
            if (w == 0) errno = ENOSPC;
            return false;
        }
        p += w;
        n -= size_t(w);
    }
    if (short_write) errno = ENOSPC;  // what a full disk reports
    return !short_write;
}

bool write_direct(const std::string& shown, const std::string& target, const void* data, size_t size,
                  std::string* err) {
    const int fd = ::open(target.c_str(), O_WRONLY | O_CLOEXEC);
    if (fd < 0) {
        if (err) *err = shown + ": cannot write: " + std::strerror(errno);
        return false;
    }
    bool ok = write_all(fd, data, size);
    int saved = errno;
    if (::close(fd) != 0 && ok) ok = false, saved = errno;
    if (!ok && err) *err = shown + ": write failed: " + std::strerror(saved);
    return ok;
}

// Creates the file's temporary (its old file's permissions, else 0666 less the umask).
int open_temporary(const std::string& tmp, const struct stat* old) {
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
    if (fd >= 0 && old) (void)fchmod(fd, old->st_mode & 07777);
    return fd;
}

bool probe_folder(const std::string& shown, const std::string& folder, const std::string& probe,
                  std::string* err) {
    const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
    if (fd < 0) {
        if (err) *err = shown + ": cannot create a file in " + folder + ": " + std::strerror(errno);
        return false;
    }
    ::close(fd);
    unlink(probe.c_str());
    return true;
}
}  // namespace

void inject_write_failure(int64_t bytes) { g_write_fault = bytes < 0 ? -1 : bytes; }

int reserve_file(int fd, uint64_t bytes) {
    const int64_t fault = g_write_fault;
    if (fault >= 0 && uint64_t(fault) < bytes) return ENOSPC;
    if (bytes > uint64_t(INT64_MAX)) return EFBIG;
    return posix_fallocate(fd, 0, off_t(bytes));
}

int64_t free_bytes(const std::string& folder) {
    struct statvfs v;
    if (statvfs(folder.c_str(), &v) != 0) return -1;
    return int64_t(v.f_bavail) * int64_t(v.f_frsize);
}

void register_temporary(const std::string& path) { register_slot('f', path); }
void unregister_temporary(const std::string& path) { unregister_slot('f', path); }

bool write_file_atomic(const std::string& path, const void* data, size_t size,
                       std::string* err) {
    std::string target;
    struct stat st;
    bool exists = false;
    if (!resolve_output(path, &target, &st, &exists, err)) return false;
    if (exists) {
        const std::string why = refuse_kind(st);
        if (!why.empty()) {
            if (err) *err = path + (target == path ? "" : " (" + target + ")") + ": " + why;
            return false;
        }
    }
    std::unique_lock<std::mutex> lock(g_guard_mu);
    OutputGuard* guard = g_guard;
    lock.unlock();
    if (exists && direct_kind(st)) {
        if (!guard) return write_direct(path, target, data, size, err);
        const uint8_t* b = static_cast<const uint8_t*>(data);
        lock.lock();
        guard->staged_.push_back({target, "", std::vector<uint8_t>(b, b + size)});
        return true;
    }
    const std::string tmp = target + ".tmp." + std::to_string(getpid());
    register_temporary(tmp);
    const int fd = open_temporary(tmp, exists ? &st : nullptr);
    if (fd < 0) {
        if (err) *err = path + ": cannot write: " + std::strerror(errno);
        unregister_temporary(tmp);
        return false;
    }
    bool ok = write_all(fd, data, size);
    int saved = errno;
    if (::close(fd) != 0 && ok) ok = false, saved = errno;
    if (ok && !guard && std::rename(tmp.c_str(), target.c_str()) != 0) ok = false, saved = errno;
    if (!ok) {
        if (err) *err = path + ": write failed: " + std::strerror(saved);
        std::remove(tmp.c_str());
        unregister_temporary(tmp);
        return false;
    }
    if (!guard) {
        unregister_temporary(tmp);
        return true;
    }
    lock.lock();
    for (const OutputGuard::Staged& s : guard->staged_)
        if (s.tmp == tmp) {
            unregister_temporary(tmp);  // written twice: the last bytes win, registered once
            return true;
        }
    guard->staged_.push_back({target, tmp, {}});
    return true;
}

OutputGuard::OutputGuard() {
    std::lock_guard<std::mutex> lock(g_guard_mu);
    outer_ = g_guard;
    g_guard = this;
}

OutputGuard::~OutputGuard() {
    if (!done_) {
        for (const Staged& s : staged_)
            if (!s.tmp.empty()) {
                std::remove(s.tmp.c_str());
                unregister_temporary(s.tmp);
            }
        for (size_t i = dirs_.size(); i-- > 0;) {
            rmdir(dirs_[i].c_str());
            unregister_slot('d', dirs_[i]);
        }
    }
    std::lock_guard<std::mutex> lock(g_guard_mu);
    if (g_guard == this) g_guard = outer_;
}

bool OutputGuard::commit(std::string* err) {
    {
        std::lock_guard<std::mutex> lock(g_guard_mu);
        if (g_guard == this) g_guard = outer_;
    }
    // FIFOs and devices first: they may block or fail (a full device); the renames after
    // them do neither, so a failure here still leaves every regular file as it was.
    for (const Staged& s : staged_)
        if (s.tmp.empty() && !write_direct(s.path, s.path, s.bytes.data(), s.bytes.size(), err))
            return false;  // the destructor removes the temporaries and folders
    bool ok = true;
    for (const Staged& s : staged_) {
        if (s.tmp.empty()) continue;
        if (ok && std::rename(s.tmp.c_str(), s.path.c_str()) != 0) {
            if (err) *err = s.path + ": cannot rename its finished temporary: " + std::strerror(errno);
            ok = false;
        }
        if (!ok) std::remove(s.tmp.c_str());
        unregister_temporary(s.tmp);
    }
    for (const std::string& d : dirs_) unregister_slot('d', d);
    done_ = true;
    return ok;
}

bool check_output(const std::string& flag, const std::string& path, std::string* err) {
    if (path.empty()) return true;
    const std::string shown = flag.empty() ? path : flag + " " + path;
    std::string target, why;
    struct stat st;
    bool exists = false;
    if (!resolve_output(path, &target, &st, &exists, &why)) {
        if (err) *err = flag.empty() ? why : flag + " " + why;
        return false;
    }
    if (exists) {
        why = refuse_kind(st);
        if (!why.empty()) {
            if (err) *err = shown + ": " + why;
            return false;
        }
        if (direct_kind(st)) {
            if (access(target.c_str(), W_OK) == 0) return true;
            if (err) *err = shown + ": cannot write: " + std::strerror(errno);
            return false;
        }
    }
    return probe_folder(shown, parent_dir(target), target + ".tmp." + std::to_string(getpid()), err);
}

bool check_output_dir(const std::string& flag, const std::string& dir, std::string* err) {
    if (dir.empty()) return true;
    const std::string shown = flag.empty() ? dir : flag + " " + dir;
    std::string d = dir;
    while (d.size() > 1 && d.back() == '/') d.pop_back();
    struct stat st;
    for (;;) {
        if (stat(d.c_str(), &st) == 0) break;
        const std::string up = parent_dir(d);
        if (errno != ENOENT || up == d) {
            if (err) *err = shown + ": " + d + ": " + std::strerror(errno);
            return false;
        }
        d = up;
    }
    if (!S_ISDIR(st.st_mode)) {
        if (err) *err = shown + ": " + d + " is not a folder";
        return false;
    }
    return probe_folder(shown, d, d + "/.sepal-probe." + std::to_string(getpid()), err);
}

bool make_dirs(const std::string& path, std::string* err) {
    std::unique_lock<std::mutex> lock(g_guard_mu);
    OutputGuard* guard = g_guard;
    lock.unlock();
    std::string partial;
    size_t pos = 0;
    while (pos != std::string::npos) {
        pos = path.find('/', pos + 1);
        partial = path.substr(0, pos);
        if (partial.empty()) continue;
        if (mkdir(partial.c_str(), 0755) != 0) {
            if (errno == EEXIST) continue;
            if (err) *err = partial + ": " + std::strerror(errno);
            return false;
        }
        if (guard) {
            register_slot('d', partial);
            lock.lock();
            guard->dirs_.push_back(partial);
            lock.unlock();
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

}  // namespace sepal

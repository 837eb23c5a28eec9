// Outputs write what the path names and are all-or-nothing (util/io.h): a symlink's target is
// written and the link stays a link, a FIFO or a device is written directly, other special
// files are refused; a command that fails leaves every path as it was, and checks its outputs
// before the work; SIGINT during a write removes what it had begun; a full stdout is an error.
#include <doctest/doctest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include "cli/cli.h"
#include "test_util.h"
#include "util/io.h"

namespace {

std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void put(const std::string& path, const std::string& text) {
    std::string err;
    REQUIRE_MESSAGE(sepal::write_file_atomic(path, text.data(), text.size(), &err), err);
}

std::vector<std::string> listing(const std::string& dir) {
    std::vector<std::string> out;
    for (const auto& e : std::filesystem::directory_iterator(dir)) out.push_back(e.path().filename().string());
    std::sort(out.begin(), out.end());
    return out;
}

bool is_link(const std::string& p) {
    struct stat st;
    return lstat(p.c_str(), &st) == 0 && S_ISLNK(st.st_mode);
}

bool is_fifo(const std::string& p) {
    struct stat st;
    return lstat(p.c_str(), &st) == 0 && S_ISFIFO(st.st_mode);
}

}  // namespace

TEST_CASE("outputs: a symlink's target is written and the link stays a link") {
    const std::string dir = sepal_test::temp_dir();
    put(dir + "/target.txt", "old");
    REQUIRE(symlink("target.txt", (dir + "/link.txt").c_str()) == 0);
    put(dir + "/link.txt", "new");
    CHECK(is_link(dir + "/link.txt"));
    CHECK(slurp(dir + "/target.txt") == "new");
    // A dangling link: its target is created, as a shell's > does.
    REQUIRE(symlink("made.txt", (dir + "/dangling.txt").c_str()) == 0);
    put(dir + "/dangling.txt", "x");
    CHECK(is_link(dir + "/dangling.txt"));
    CHECK(slurp(dir + "/made.txt") == "x");
    // Through a command: render -o a link.
    std::string out;
    REQUIRE(symlink("real.png", (dir + "/shown.png").c_str()) == 0);
    CHECK(sepal_test::run_cmd("render", {"lambert", "--size", "16x16", "-o", dir + "/shown.png"}, &out) == 0);
    CHECK(is_link(dir + "/shown.png"));
    CHECK(slurp(dir + "/real.png").compare(1, 3, "PNG") == 0);
}

TEST_CASE("outputs: a FIFO is written directly, a device too, a socket and a folder are refused") {
    const std::string dir = sepal_test::temp_dir();
    const std::string fifo = dir + "/pipe";
    REQUIRE(mkfifo(fifo.c_str(), 0600) == 0);
    std::string got;
    std::thread reader([&] { got = slurp(fifo); });
    std::string err;
    CHECK_MESSAGE(sepal::write_file_atomic(fifo, "through the pipe", 16, &err), err);
    reader.join();
    CHECK(got == "through the pipe");
    CHECK(is_fifo(fifo));
    CHECK(listing(dir) == std::vector<std::string>{"pipe"});  // no temporary beside it
    // A device: /dev/null takes it, /dev/full fails as a full disk, and both stay devices.
    CHECK(sepal::write_file_atomic("/dev/null", "x", 1, &err));
    CHECK_FALSE(sepal::write_file_atomic("/dev/full", "x", 1, &err));
    CHECK(err.find("/dev/full") == 0);
    CHECK(err.find("No space left on device") != std::string::npos);
    struct stat st;
    REQUIRE(stat("/dev/full", &st) == 0);
    CHECK(S_ISCHR(st.st_mode));
    std::string out;
    CHECK(sepal_test::run_cmd("render", {"lambert", "--size", "16x16", "-o", "/dev/full"}, &out) == 2);
    CHECK(out.find("/dev/full") != std::string::npos);
    REQUIRE(stat("/dev/full", &st) == 0);
    CHECK(S_ISCHR(st.st_mode));
    // A socket is refused with its kind named; so is a folder.
    const std::string sock = dir + "/sock";
    const int fd = socket(AF_UNIX, SOCK_STREAM, 0);
    REQUIRE(fd >= 0);
    sockaddr_un addr = {};
    addr.sun_family = AF_UNIX;
    std::snprintf(addr.sun_path, sizeof addr.sun_path, "%s", sock.c_str());
    REQUIRE(bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0);
    CHECK_FALSE(sepal::write_file_atomic(sock, "x", 1, &err));
    CHECK(err.find("is a socket") != std::string::npos);
    CHECK_FALSE(sepal::write_file_atomic(dir, "x", 1, &err));
    CHECK(err.find("is a folder") != std::string::npos);
    close(fd);
    CHECK(sepal_test::run_cmd("render", {"lambert", "--size", "16x16", "-o", sock}, &out) == 2);
    CHECK(out.find("is a socket") != std::string::npos);
    struct stat ss;
    REQUIRE(lstat(sock.c_str(), &ss) == 0);
    CHECK(S_ISSOCK(ss.st_mode));
}

TEST_CASE("outputs: a failed sibling output leaves the older good file as it was") {
    const std::string dir = sepal_test::temp_dir();
    std::string out;
    put(dir + "/keep.sepal", "good asset");
    put(dir + "/keep.png", "good png");
    put(dir + "/keep.smp", "good sampler");
    put(dir + "/keep.csv", "good samples");
    // bake: the export folder cannot be made; refused before the search, the asset kept.
    CHECK(sepal_test::run_cmd("bake", {"lambert", "--param", "gs-half", "--res", "8", "--terms", "1", "--method",
                                       "acls", "-o", dir + "/keep.sepal", "--export", "/proc/nope"},
                              &out) == 2);
    CHECK(out.find("--export /proc/nope") != std::string::npos);
    CHECK(out.find("candidate") == std::string::npos);  // no search ran
    CHECK(slurp(dir + "/keep.sepal") == "good asset");
    CHECK(sepal_test::run_cmd("render", {"lambert", "--size", "16x16", "-o", dir + "/keep.png", "--float",
                                         "/nonexistent/x.pfm"},
                              &out) == 2);
    CHECK(out.find("--float /nonexistent/x.pfm") != std::string::npos);
    CHECK(slurp(dir + "/keep.png") == "good png");
    CHECK(sepal_test::run_cmd("sampler", {"lambert", "-o", dir + "/keep.smp", "--report", "/nonexistent/r.json"},
                              &out) == 2);
    CHECK(slurp(dir + "/keep.smp") == "good sampler");
    CHECK(sepal_test::run_cmd("measure", {"capture", "--samples", dir + "/keep.csv", "-o", "/nonexistent/p.png"},
                              &out) == 2);
    CHECK(slurp(dir + "/keep.csv") == "good samples");
    // diff: both pictures or neither.
    REQUIRE(sepal_test::run_cmd("render", {"lambert", "--size", "16x16", "-o", dir + "/a.png"}, &out) == 0);
    put(dir + "/h.png", "old heatmap");
    CHECK(sepal_test::run_cmd("diff", {dir + "/a.png", dir + "/a.png", "--heatmap", dir + "/h.png", "--sheet",
                                       "/nonexistent/s.png"},
                              &out) == 2);
    CHECK(slurp(dir + "/h.png") == "old heatmap");
    // A failure at the last write (a full disk there) undoes nothing it had not done: the
    // first output, already staged, is not put in place either.
    {
        sepal::inject_write_failure(-1);
        std::string err;
        sepal::OutputGuard g;
        CHECK(sepal::write_file_atomic(dir + "/keep.png", "new png", 7, &err));
        CHECK(slurp(dir + "/keep.png") == "good png");  // staged, not yet in place
    }
    CHECK(slurp(dir + "/keep.png") == "good png");
    const std::vector<std::string> left = listing(dir);
    for (const std::string& f : left) CHECK_MESSAGE(f.find(".tmp.") == std::string::npos, f);
    // And a commit puts every staged file in place.
    {
        std::string err;
        sepal::OutputGuard g;
        CHECK(sepal::write_file_atomic(dir + "/keep.png", "new png", 7, &err));
        CHECK(sepal::make_dirs(dir + "/made/deeper", &err));
        CHECK(sepal::write_file_atomic(dir + "/made/deeper/f.txt", "f", 1, &err));
        CHECK(g.commit(&err));
    }
    CHECK(slurp(dir + "/keep.png") == "new png");
    CHECK(slurp(dir + "/made/deeper/f.txt") == "f");
    // Without it, the folders made for the outputs go too.
    {
        std::string err;
        sepal::OutputGuard g;
        CHECK(sepal::make_dirs(dir + "/gone/deeper", &err));
        CHECK(sepal::write_file_atomic(dir + "/gone/deeper/f.txt", "f", 1, &err));
    }
    CHECK_FALSE(std::filesystem::exists(dir + "/gone"));
}

TEST_CASE("outputs: SIGINT while bake --export writes leaves neither the asset nor the export") {
    // The export's manifest is a FIFO nobody reads, so the bake blocks on it after staging
    // everything else: the moment a long export would be interrupted. SIGINT then must leave
    // the old asset, no temporaries, and no files in the export folder but the FIFO.
    const std::string dir = sepal_test::temp_dir();
    put(dir + "/x.sepal", "old asset");
    REQUIRE(mkdir((dir + "/export").c_str(), 0755) == 0);
    REQUIRE(mkfifo((dir + "/export/manifest.json").c_str(), 0600) == 0);
    const pid_t pid = fork();
    REQUIRE(pid >= 0);
    if (pid == 0) {
        const std::string sepal = sepal_test::bin("sepal");
        const int devnull = open("/dev/null", O_WRONLY);
        dup2(devnull, 1), dup2(devnull, 2);
        execl(sepal.c_str(), "sepal", "bake", "lambert", "--param", "gs-half", "--res", "8", "--terms", "1",
              "--method", "acls", "-o", (dir + "/x.sepal").c_str(), "--export", (dir + "/export").c_str(),
              static_cast<char*>(nullptr));
        _exit(127);
    }
    // Wait until the staged temporaries exist (the bake is done and the commit has begun).
    bool staged = false;
    for (int i = 0; i < 600 && !staged; ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        for (const std::string& f : listing(dir)) staged = staged || f.find("x.sepal.tmp.") == 0;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    kill(pid, SIGINT);
    int status = 0;
    waitpid(pid, &status, 0);
    CHECK(staged);
    CHECK(WIFSIGNALED(status));
    CHECK(slurp(dir + "/x.sepal") == "old asset");
    CHECK(listing(dir) == std::vector<std::string>{"export", "x.sepal"});
    CHECK(listing(dir + "/export") == std::vector<std::string>{"manifest.json"});
}

TEST_CASE("outputs: a write error on stdout is an error") {
    FILE* full = std::fopen("/dev/full", "w");
    REQUIRE(full);
    FILE* err = std::tmpfile();
    REQUIRE(err);
    sepal::CommandIO io;
    io.out = full;
    io.err = err;
    CHECK(sepal::run_command("info", {"lambert"}, io) == 2);
    std::fclose(full);
    std::rewind(err);
    char buf[512] = {};
    CHECK(std::fread(buf, 1, sizeof buf - 1, err) > 0);
    std::fclose(err);
    CHECK(std::string(buf).find("sepal info: cannot write its output: No space left on device") != std::string::npos);
    std::string out;
    CHECK(sepal_test::run(sepal_test::bin("sepal") + " info lambert > /dev/full", &out) == 2);
}

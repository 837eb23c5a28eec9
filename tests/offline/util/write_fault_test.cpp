// A fault: a write that fails part-way (a full disk) leaves no partial output: not
// the file, not its temporary, not the command's other outputs; an existing file keeps its
// old bytes. Through the fault hook (util/io.h, inject_write_failure) everywhere, and on a
// real 64 KiB tmpfs where this process may mount one (root).
#include <doctest/doctest.h>

#include <sys/mount.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "cli/cli.h"
#include "test_util.h"
#include "util/io.h"

namespace {

std::vector<std::string> listing(const std::string& dir) {
    std::vector<std::string> out;
    for (const auto& e : std::filesystem::directory_iterator(dir)) out.push_back(e.path().filename().string());
    return out;
}

std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

struct FaultScope {
    explicit FaultScope(int64_t bytes) { sepal::inject_write_failure(bytes); }
    ~FaultScope() { sepal::inject_write_failure(-1); }
};

}  // namespace

TEST_CASE("write failure: a full disk part-way leaves no partial file, and an existing file intact") {
    const std::string dir = sepal_test::temp_dir();
    const std::string data(100000, 'x');
    std::string err;
    {
        FaultScope fault(4096);
        CHECK_FALSE(sepal::write_file_atomic(dir + "/new.bin", data.data(), data.size(), &err));
        CHECK(err.find("No space left on device") != std::string::npos);
        CHECK(err.find(dir + "/new.bin") == 0);
    }
    CHECK(listing(dir).empty());  // neither the file nor its temporary
    REQUIRE(sepal::write_file_atomic(dir + "/old.bin", "old", 3, &err));
    {
        FaultScope fault(10);
        CHECK_FALSE(sepal::write_file_atomic(dir + "/old.bin", data.data(), data.size(), &err));
    }
    CHECK(slurp(dir + "/old.bin") == "old");
    CHECK(listing(dir) == std::vector<std::string>{"old.bin"});
}

TEST_CASE("write failure: commands that fail on a full disk leave none of their outputs") {
    const std::string dir = sepal_test::temp_dir();
    std::string out;
    {
        // render: the PNG fits, the PFM does not.
        FaultScope fault(20000);
        CHECK(sepal_test::run_cmd("render", {"lambert", "--size", "64x64", "-o", dir + "/r.png", "--float",
                                                      dir + "/r.pfm"},
                                  &out) == 2);
        CHECK(out.find("No space left on device") != std::string::npos);
    }
    {
        // bake: the asset does not fit.
        FaultScope fault(100);
        CHECK(sepal_test::run_cmd("bake", {"lambert", "--param", "gs-half", "--res", "8", "--terms", "1", "-o",
                                                    dir + "/b.sepal"},
                                  &out) == 2);
        CHECK(out.find("No space left on device") != std::string::npos);
    }
    CHECK(listing(dir).empty());
    // The same commands write their outputs once the disk has room.
    CHECK(sepal_test::run_cmd("render", {"lambert", "--size", "64x64", "-o", dir + "/r.png", "--float",
                                                  dir + "/r.pfm"},
                              &out) == 0);
    CHECK(listing(dir).size() == 2);
}

TEST_CASE("write failure: a real full disk (a 64 KiB tmpfs) leaves no partial output") {
    const std::string dir = sepal_test::temp_dir();
    if (geteuid() != 0 || mount("tmpfs", dir.c_str(), "tmpfs", 0, "size=64k") != 0) {
        MESSAGE("not root or tmpfs not mountable here: the fault-hook tests above cover this");
        return;
    }
    std::string out;
    // 256x256 RGB floats are 786,449 bytes of PFM: the disk fills part-way through.
    const int code = sepal_test::run_cmd(
        "render", {"lambert", "--size", "256x256", "-o", dir + "/r.png", "--float", dir + "/r.pfm"}, &out);
    const std::vector<std::string> left = listing(dir);
    umount(dir.c_str());
    CHECK(code == 2);
    CHECK(out.find("No space left on device") != std::string::npos);
    CHECK(left.empty());
}

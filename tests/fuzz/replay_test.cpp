// Replays the fuzz harnesses' regression inputs (fixtures/fuzz/<harness>/: inputs that once
// crashed or broke a promise, kept after the fix) and seeds (fixtures/fuzz-seeds/<harness>/)
// through the same functions libFuzzer calls (tests/fuzz/fuzz.h). Under `make test-asan` this
// is the sanitizer run of every one of them.
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "fuzz/fuzz.h"
#include "test_util.h"

namespace {

struct Harness {
    const char* name;
    int (*fn)(const uint8_t*, size_t);
};

#define SEPAL_FUZZ_ROW(name) {#name, sepal_fuzz_##name},
const Harness kHarnesses[] = {SEPAL_FUZZ_HARNESSES(SEPAL_FUZZ_ROW)};
#undef SEPAL_FUZZ_ROW

std::vector<std::string> files_in(const std::string& dir) {
    std::vector<std::string> out;
    std::error_code ec;
    for (const auto& e : std::filesystem::directory_iterator(dir, ec))
        if (e.is_regular_file()) out.push_back(e.path().string());
    std::sort(out.begin(), out.end());
    return out;
}

std::vector<uint8_t> bytes_of(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace

TEST_CASE("fuzz: every harness file is in the list make fuzz and this suite share") {
    std::vector<std::string> names;
    for (const std::string& f : files_in(sepal_test::source_path("tests/fuzz"))) {
        const std::string base = std::filesystem::path(f).filename().string();
        if (base.compare(0, 5, "fuzz_") == 0 && base.size() > 9 && base.substr(base.size() - 4) == ".cpp")
            names.push_back(base.substr(5, base.size() - 9));
    }
    std::vector<std::string> listed;
    for (const Harness& h : kHarnesses) listed.push_back(h.name);
    std::sort(listed.begin(), listed.end());
    CHECK(names == listed);
    CHECK(listed.size() >= 9);
}

TEST_CASE("fuzz: regression inputs and seeds replay cleanly through every harness") {
    int replayed = 0;
    for (const Harness& h : kHarnesses) {
        for (const char* root : {"fixtures/fuzz/", "fixtures/fuzz-seeds/"}) {
            for (const std::string& path : files_in(sepal_test::source_path(root + std::string(h.name)))) {
                CAPTURE(path);
                const std::vector<uint8_t> b = bytes_of(path);
                CHECK(h.fn(b.data(), b.size()) == 0);  // a broken promise aborts (check() in fuzz.h)
                ++replayed;
            }
        }
        // The empty input, every time.
        CHECK(h.fn(nullptr, 0) == 0);
    }
    MESSAGE("replayed " << replayed << " fuzz inputs");
    CHECK(replayed > 0);
}

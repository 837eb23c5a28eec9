// Fuzz harnesses: one plain function per reader, int sepal_fuzz_<name>(data, size),
// in tests/fuzz/fuzz_<name>.cpp. Two callers share them:
//   - `make fuzz` links each with tests/fuzz/entry/libfuzzer.cpp (clang, -fsanitize=fuzzer,
//     address, undefined, float-cast-overflow) into build/fuzz/bin/fuzz-<name> and runs it
//     on a corpus seeded from fixtures/ (tests/fuzz/seed.sh);
//   - the replay suite (tests/fuzz/replay_test.cpp, in sepal-tests, g++) feeds every file
//     under fixtures/fuzz/<name>/ (crashers found so far, kept as regression inputs) and
//     fixtures/fuzz-seeds/<name>/ through the same functions, so `make test` and
//     `make test-asan` replay them.
// A harness returns 0. Input a reader refuses is fine (that is the point); what is not:
// a crash, a sanitizer report, an exception escaping, a refusal without a message, or a
// result that breaks the reader's promises (check() aborts, so libFuzzer keeps the input).
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace sepal {
class BrdfDatabase;
struct MeasurementPlan;
}  // namespace sepal

// X(name): every harness, in the order the replay suite runs them.
#define SEPAL_FUZZ_HARNESSES(X) \
    X(asset)                    \
    X(runtime)                  \
    X(scene_json)               \
    X(cost_model)               \
    X(merl)                     \
    X(cornell)                  \
    X(obj)                      \
    X(png)                      \
    X(pfm)                      \
    X(spec)                     \
    X(cli_flags)                \
    X(smp)                      \
    X(tree)                     \
    X(plan)                     \
    X(samples)

#define SEPAL_FUZZ_DECLARE(name) extern "C" int sepal_fuzz_##name(const uint8_t* data, size_t size);
SEPAL_FUZZ_HARNESSES(SEPAL_FUZZ_DECLARE)
#undef SEPAL_FUZZ_DECLARE

namespace sepal_fuzz {

// Aborts with "fuzz <harness>: <what>" on stderr when ok is false.
void check(bool ok, const char* harness, const char* what);
// The asset parser's checksum fix-up: sets the header's file size to the buffer's, recomputes
// every chunk's CRC-32 whose range lies inside the buffer, then the header CRC, so mutated
// bytes reach the field checks behind the checksums.
void fix_asset_checksums(std::vector<uint8_t>* bytes);
// Readers that take a path get the input as a file: a folder of this process (created once,
// under /dev/shm where it exists), and `name` written there with the input's bytes.
const std::string& scratch_dir();
std::string write_scratch(const std::string& name, const uint8_t* data, size_t size);
// The measurement harnesses' database: 6 MERL-fitted materials on a coarse 16 x 16 x 32 grid,
// built once per process into scratch_dir() (about 0.1 s), and a uniform 40-sample plan on it
// (what the samples harness reads its CSVs against). Seeds: fixtures/fuzz-seeds/{plan,samples}.
const sepal::BrdfDatabase& database();
const sepal::MeasurementPlan& samples_plan();

}  // namespace sepal_fuzz

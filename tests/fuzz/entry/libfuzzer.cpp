// libFuzzer's entry for one harness: `make fuzz` compiles this file once per harness with
// -DSEPAL_FUZZ_TARGET=sepal_fuzz_<name> (tests/fuzz/fuzz.h). Not part of sepal-tests.
#include "fuzz/fuzz.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) { return SEPAL_FUZZ_TARGET(data, size); }

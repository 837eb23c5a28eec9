// GL ES call counting for tests and benchmarks: this file defines the GL ES 1.1 entry
// points the runtime's fixed-function executor calls, counts them while counting is on,
// and forwards each to the driver's (dlsym RTLD_NEXT). The runtime is linked statically
// into the test and bench programs, so its calls bind here; the driver's own do not pass
// through. Single-threaded use (GL contexts are per thread).
//
//   sepal_test::gl_counts_reset(); sepal_test::gl_counting(true);
//   sepal_draw(...);
//   sepal_test::gl_counting(false);
//   long n = sepal_test::gl_calls("glTexEnvi"), all = sepal_test::gl_calls_total();
#pragma once
#include <string>

namespace sepal_test {

void gl_counting(bool on);
void gl_counts_reset();
long gl_calls(const char* name);  // 0 for an entry point not called (or not counted)
long gl_calls_total();
std::string gl_calls_by_name();   // "glTexEnvi 21 glEnable 10 ...", most first

}  // namespace sepal_test

// One-line progress on stderr for long runs ("sepal render: 42%"); silent when disabled.
//
// Usage:
//   sepal::Progress p(show, "sepal render:", rows);   // label, then the percentage
//   parallel_for(rows, 0, [&](size_t r) { ...; p.advance(); });
// advance() is thread-safe; the line is rewritten only when the percentage changes and is
// erased when the object goes away.
#pragma once
#include <cstddef>
#include <string>

namespace sepal {

class Progress {
  public:
    Progress(bool enabled, const std::string& label, size_t total);
    ~Progress();
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;
    void advance();

  private:
    struct State;
    State* state_;
};

}  // namespace sepal

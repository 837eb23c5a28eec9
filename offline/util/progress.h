// Progress of long runs, reported through one process-wide sink: by default a rewritten
// line on stderr ("sepal render: 42%") and whole lines for notes; a program that shows
// progress its own way (a GUI, a log, a test) sets its sink once. Library code never writes
// to stderr itself.
//
// Usage:
//   sepal::Progress p(show, "sepal render:", rows);   // label, then the percentage
//   parallel_for(rows, 0, [&](size_t r) { ...; p.advance(); });
//   sepal::progress_note("sepal ist: K=3 RMS 0.012");   // a whole line
//   sepal::set_progress_sink(my_sink);                   // nullptr: the default again
// advance() is thread-safe; the sink is called only when the percentage changes, and with
// percent -1 when the object goes away (the default sink erases its line). Notes and
// percentages reach the sink under one lock, so a sink need not be thread-safe.
#pragma once
#include <cstddef>
#include <string>

namespace sepal {

// percent: 0..100 for a Progress's line, -1 when it ends, -2 for a note (label is the line).
using ProgressSink = void (*)(const std::string& label, int percent);
void set_progress_sink(ProgressSink sink);
void progress_note(const std::string& line);

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

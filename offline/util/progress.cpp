#include "util/progress.h"

#include <atomic>
#include <cstdio>
#include <mutex>

namespace sepal {
namespace {

void stderr_sink(const std::string& label, int percent) {
    if (percent == -2)
        std::fprintf(stderr, "%s\n", label.c_str());
    else if (percent < 0)
        std::fprintf(stderr, "\r%-70s\r", "");
    else
        std::fprintf(stderr, "\r%s %3d%%", label.c_str(), percent);
    std::fflush(stderr);
}

std::mutex& sink_mutex() {
    static std::mutex m;
    return m;
}
ProgressSink g_sink = stderr_sink;  // guarded by sink_mutex()

void report(const std::string& label, int percent) {
    std::lock_guard<std::mutex> lock(sink_mutex());
    g_sink(label, percent);
}

}  // namespace

void set_progress_sink(ProgressSink sink) {
    std::lock_guard<std::mutex> lock(sink_mutex());
    g_sink = sink ? sink : stderr_sink;
}

void progress_note(const std::string& line) { report(line, -2); }

struct Progress::State {
    std::string label;
    size_t total = 0;
    std::atomic<size_t> done{0};
    std::mutex mutex;
    int shown = -1;
};

Progress::Progress(bool enabled, const std::string& label, size_t total) : state_(nullptr) {
    if (!enabled || total == 0) return;
    state_ = new State;
    state_->label = label;
    state_->total = total;
}

Progress::~Progress() {
    if (!state_) return;
    report(state_->label, -1);
    delete state_;
}

void Progress::advance() {
    if (!state_) return;
    const size_t d = ++state_->done;
    const int pct = int(100.0 * double(d) / double(state_->total));
    std::lock_guard<std::mutex> lock(state_->mutex);
    if (pct != state_->shown) {
        state_->shown = pct;
        report(state_->label, pct);
    }
}

}  // namespace sepal

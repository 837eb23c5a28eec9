#include "util/progress.h"

#include <atomic>
#include <cstdio>
#include <mutex>

namespace sepal {

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
    std::fprintf(stderr, "\r%-70s\r", "");
    delete state_;
}

void Progress::advance() {
    if (!state_) return;
    const size_t d = ++state_->done;
    const int pct = int(100.0 * double(d) / double(state_->total));
    std::lock_guard<std::mutex> lock(state_->mutex);
    if (pct != state_->shown) {
        state_->shown = pct;
        std::fprintf(stderr, "\r%s %3d%%", state_->label.c_str(), pct);
        std::fflush(stderr);
    }
}

}  // namespace sepal

// Progress reaches the sink a program sets: percentages as they change, the end, notes.
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "util/progress.h"

namespace {
std::vector<std::pair<std::string, int>> g_seen;
void collect(const std::string& label, int percent) { g_seen.emplace_back(label, percent); }
}  // namespace

TEST_CASE("progress: a set sink receives every change, the end and notes; nullptr restores the default") {
    g_seen.clear();
    sepal::set_progress_sink(collect);
    {
        sepal::Progress p(true, "work:", 4);
        for (int i = 0; i < 4; ++i) p.advance();
        sepal::Progress off(false, "quiet:", 4);
        off.advance();
    }
    sepal::progress_note("a whole line");
    sepal::set_progress_sink(nullptr);
    REQUIRE(g_seen.size() == 6u);
    const int want[] = {25, 50, 75, 100, -1, -2};
    for (size_t i = 0; i < 6; ++i) CHECK(g_seen[i].second == want[i]);
    CHECK(g_seen[0].first == "work:");
    CHECK(g_seen[5].first == "a whole line");
    sepal::progress_note("");  // the default sink again: nothing reaches collect
    CHECK(g_seen.size() == 6u);
}

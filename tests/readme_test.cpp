// The README as a newcomer reads it: short, its links resolve, and every measured figure it
// quotes is quoted by reference from a document that a benchmark regenerates (issue 19).
#include <doctest/doctest.h>

#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "test_util.h"

namespace {

std::string read_text(const std::string& relative) {
    std::ifstream in(sepal_test::source_path(relative), std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string l; std::getline(in, l);) out.push_back(l);
    return out;
}

// The lines of the section whose "## " heading starts with `title`, up to the next heading.
std::string section(const std::string& text, const std::string& title) {
    std::string out;
    bool in = false;
    for (const std::string& l : lines_of(text)) {
        if (l.rfind("## ", 0) == 0) in = l.rfind("## " + title, 0) == 0;
        else if (in) out += l + "\n";
    }
    return out;
}

// Relative link targets of markdown links [text](target), anchors dropped.
std::vector<std::string> relative_links(const std::string& text) {
    std::vector<std::string> out;
    static const std::regex link(R"(\]\(([^)\s#]+)(#[^)]*)?\))");
    for (auto it = std::sregex_iterator(text.begin(), text.end(), link); it != std::sregex_iterator(); ++it) {
        const std::string target = (*it)[1];
        if (target.find("://") == std::string::npos) out.push_back(target);
    }
    return out;
}

}  // namespace

TEST_CASE("README: at most 250 lines, and every relative link names a file in the repository") {
    const std::string readme = read_text("README.md");
    REQUIRE(!readme.empty());
    CHECK(lines_of(readme).size() <= 250);
    const std::vector<std::string> links = relative_links(readme);
    CHECK(links.size() >= 5);
    for (const std::string& l : links) CHECK_MESSAGE(!read_text(l).empty(), "README links to " << l << ", which is missing or empty");
}

TEST_CASE("README: each measured figure in 'Research results at a glance' is in a document it links") {
    const std::string readme = read_text("README.md");
    const std::string s = section(readme, "Research results at a glance");
    REQUIRE(!s.empty());
    std::string docs;
    for (const std::string& l : relative_links(s)) docs += read_text(l);
    REQUIRE(!docs.empty());
    // Percentages and decimals (dB, ratios); small integers (view counts) are not figures.
    static const std::regex figure(R"((\d+\.\d+%?|\d+%))");
    std::set<std::string> seen;
    for (auto it = std::sregex_iterator(s.begin(), s.end(), figure); it != std::sregex_iterator(); ++it) {
        const std::string f = (*it)[1];
        if (!seen.insert(f).second) continue;
        CHECK_MESSAGE(docs.find(f) != std::string::npos,
                      "README quotes " << f << " but no linked document holds it: copy figures from the documents "
                                          "(which their benchmarks regenerate), never by hand");
    }
    CHECK(seen.size() >= 10);
}

// The README as a newcomer reads it: short, its links resolve, and every measured figure it
// quotes is quoted by reference from a document that a benchmark regenerates.
#include <doctest/doctest.h>

#include <cctype>
#include <fstream>
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

// Relative link targets of markdown links [text](target), anchors dropped. (Scanned by
// hand: <regex> trips GCC 12's -Wmaybe-uninitialized under the sanitizers' -O levels.)
std::vector<std::string> relative_links(const std::string& text) {
    std::vector<std::string> out;
    for (size_t at = text.find("]("); at != std::string::npos; at = text.find("](", at + 2)) {
        const size_t end = text.find(')', at + 2);
        if (end == std::string::npos) break;
        std::string target = text.substr(at + 2, end - at - 2);
        target = target.substr(0, target.find('#'));
        if (target.empty() || target.find("://") != std::string::npos ||
            target.find_first_of(" \t\n") != std::string::npos)
            continue;
        out.push_back(target);
    }
    return out;
}

// Decimals (dB, ratios) and percentages in reading order; plain integers (view counts) are
// not figures.
std::vector<std::string> figures(const std::string& text) {
    std::vector<std::string> out;
    auto digit = [&](size_t i) { return i < text.size() && std::isdigit(static_cast<unsigned char>(text[i])); };
    for (size_t i = 0; i < text.size();) {
        if (!digit(i)) {
            ++i;
            continue;
        }
        size_t j = i;
        while (digit(j)) ++j;
        bool figure = false;
        if (j + 1 < text.size() && text[j] == '.' && digit(j + 1)) {
            for (++j; digit(j);) ++j;
            figure = true;
        }
        if (j < text.size() && text[j] == '%') ++j, figure = true;
        if (figure) out.push_back(text.substr(i, j - i));
        i = j;
    }
    return out;
}

}  // namespace

TEST_CASE("README: every relative link names a file in the repository") {
    const std::string readme = read_text("README.md");
    REQUIRE(!readme.empty());
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
    std::set<std::string> seen;
    for (const std::string& f : figures(s)) {
        if (!seen.insert(f).second) continue;
        CHECK_MESSAGE(docs.find(f) != std::string::npos,
                      "README quotes " << f << " but no linked document holds it: copy figures from the documents "
                                          "(which their benchmarks regenerate), never by hand");
    }
    CHECK(seen.size() >= 10);
}

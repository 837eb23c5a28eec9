// Tree folders (ist/tree.h: read_tree): tree.json, the blend maps and the curve CSVs it names.
// The input is the folder packed as text: tree.json's bytes, then for each other file a line
// "@@ NAME" and its bytes (NAME of letters, digits, '_', '-', '.' and at most one '/', no "..";
// the last newline before "@@" belongs to the separator). An accepted tree passes
// validate_tree: finite blend weights >= 0, finite curves, one blend map per basis.
#include <sys/stat.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "fuzz/fuzz.h"
#include "ist/tree.h"

namespace {

bool safe_name(const std::string& n) {
    if (n.empty() || n.size() > 64 || n[0] == '/' || n[0] == '.' || n.find("..") != std::string::npos) return false;
    int slashes = 0;
    for (char c : n) {
        const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
                        c == '-' || c == '.' || c == '/';
        if (!ok) return false;
        slashes += c == '/';
    }
    return slashes <= 1 && n.back() != '/';
}

}  // namespace

extern "C" int sepal_fuzz_tree(const uint8_t* data, size_t size) {
    const char* h = "tree";
    const std::string dir = sepal_fuzz::scratch_dir() + "/tree";
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
    mkdir(dir.c_str(), 0700);
    const std::string text(reinterpret_cast<const char*>(data), size);
    std::string name = "tree.json";
    size_t pos = 0;
    for (int files = 0; files < 64; ++files) {
        const size_t sep = text.find("\n@@ ", pos);
        const size_t end = sep == std::string::npos ? text.size() : sep;
        if (safe_name(name)) {
            // A name whose folder is already a file (or the reverse) is skipped, as a packer
            // could not have made it.
            const size_t slash = name.find('/');
            if (slash != std::string::npos) mkdir((dir + "/" + name.substr(0, slash)).c_str(), 0700);
            if (FILE* f = std::fopen((dir + "/" + name).c_str(), "wb")) {
                if (end > pos) std::fwrite(data + pos, 1, end - pos, f);
                std::fclose(f);
            }
        }
        if (sep == std::string::npos) break;
        const size_t eol = text.find('\n', sep + 4);
        name = text.substr(sep + 4, (eol == std::string::npos ? text.size() : eol) - (sep + 4));
        if (eol == std::string::npos) break;
        pos = eol + 1;
    }
    sepal::ShadeTree t;
    std::string err;
    if (!sepal::read_tree(dir, &t, &err)) {
        sepal_fuzz::check(!err.empty(), h, "a refusal without a message");
        return 0;
    }
    sepal_fuzz::check(sepal::validate_tree(t, &err), h, "an accepted tree fails validate_tree");
    for (float w : t.blend.w) sepal_fuzz::check(std::isfinite(w) && w >= 0, h, "a blend weight not finite or < 0");
    return 0;
}

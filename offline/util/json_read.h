// A minimal JSON reader for scene files (sepal bake-scene).
//
// Usage:
//   sepal::JsonValue v; std::string err;
//   if (!sepal::parse_json(text, &v, &err)) ...        // err: "line 3, column 7: ..."
//   const sepal::JsonValue* m = v.find("materials");   // NULL when absent
//
// Hand-written: no JSON library is among sepal's dependencies, and scene files are small
// and flat. Accepts RFC 8259 JSON (no comments, no trailing commas); \u escapes are
// decoded to UTF-8 (surrogate pairs included). Limits: 1 MB of text, nesting depth 32.
#pragma once
#include <map>
#include <string>
#include <vector>

namespace sepal {

struct JsonValue {
    enum Kind { Null, Bool, Number, String, Array, Object } kind = Null;
    bool boolean = false;
    double number = 0;
    std::string string;
    std::vector<JsonValue> array;
    std::vector<std::pair<std::string, JsonValue>> object;  // in file order

    const JsonValue* find(const std::string& key) const;
};

bool parse_json(const std::string& text, JsonValue* out, std::string* err);

}  // namespace sepal

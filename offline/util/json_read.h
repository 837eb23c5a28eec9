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

// Typed members of an object, each false with "KEY: what was expected" in *err:
// a finite number in [lo, hi]; an integer in [lo, hi]; a string; an array of exactly
// `count` finite numbers.
bool json_number(const JsonValue& obj, const std::string& key, double lo, double hi, double* out,
                 std::string* err);
bool json_int(const JsonValue& obj, const std::string& key, int lo, int hi, int* out, std::string* err);
bool json_string(const JsonValue& obj, const std::string& key, std::string* out, std::string* err);
bool json_numbers(const JsonValue& obj, const std::string& key, int count, double* out, std::string* err);

}  // namespace sepal

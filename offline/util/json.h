// JSON for sepal's reports, manifests and input files: nlohmann-json (Debian
// nlohmann-json3-dev) with the project's conventions on top.
//
// Usage:
//   sepal::Json j;                                   // members keep insertion order
//   j["res"] = 32;
//   j["errors"] = sepal::Json::array({0.5, 0.25});
//   std::string err;
//   sepal::write_json_file("r.json", j, &err);       // atomic
//
//   sepal::Json v;
//   if (!sepal::parse_json(text, "scene.json", &v, &err)) ...  // err says where
//   int passes = 0;
//   if (!sepal::json_int(v, "max_passes", 1, 64, &passes, &err)) ...
//
// Writing (dump_json): two-space indent, one member or element per line, a final newline.
// Doubles are rounded to 9 significant digits first (a float's round-trip precision: a
// float widened to double prints 0.100000001, not 0.10000000149011612; the digits the
// hand-written writer before it printed), NaN and inf become null
// (JSON has neither), and bytes that are not UTF-8 are replaced (U+FFFD) instead of failing.
// The same value always gives the same bytes. dump_json_compact: the same rounding, no
// whitespace and no final newline (an asset's META, where every byte is shipped).
// Reading (parse_json): RFC 8259 JSON, stricter than nlohmann's default: a key repeated in
// one object is refused (naming the key and its path, e.g. materials[1].name), nesting
// deeper than 64 and texts over 16 MiB are refused, numbers beyond the double range are
// refused; a UTF-8 byte-order mark at the start is skipped. Messages read
// "scene.json: line 2, column 5: syntax error while parsing value ...".
// The typed readers check kind and range before converting (an out-of-range double is never
// cast to int) and name the member: "scene.json: materials[0].max_passes: 1e+12 is outside 1..64".
#pragma once
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

namespace sepal {

using Json = nlohmann::ordered_json;

std::string dump_json(const Json& value);
std::string dump_json_compact(const Json& value);
bool write_json_file(const std::string& path, const Json& value, std::string* err);

constexpr size_t kMaxJsonBytes = size_t(16) << 20;
// `source` names the text in messages (a path, or "asset META").
bool parse_json(const std::string& text, const std::string& source, Json* out, std::string* err);
// Reads and parses a file of at most max_bytes (and kMaxJsonBytes).
bool read_json_file(const std::string& path, Json* out, std::string* err, size_t max_bytes = kMaxJsonBytes);

// Typed members of an object. `where` prefixes messages (e.g. "scene.json: materials[0]");
// absent members leave *out unchanged and return true when `required` is false.
struct JsonField {
    const Json& object;
    std::string where;
};
bool json_int(const JsonField& f, const char* key, int64_t lo, int64_t hi, int64_t* out, std::string* err,
              bool required = false);
bool json_int(const JsonField& f, const char* key, int lo, int hi, int* out, std::string* err,
              bool required = false);
bool json_number(const JsonField& f, const char* key, double lo, double hi, double* out, std::string* err,
                 bool required = false);
bool json_string(const JsonField& f, const char* key, std::string* out, std::string* err, bool required = false);
// An array member of lo..hi elements; *out points into f.object (nullptr when absent and not required).
bool json_array(const JsonField& f, const char* key, size_t lo, size_t hi, const Json** out, std::string* err,
                bool required = false);
// An array member of exactly `count` finite numbers.
bool json_numbers(const JsonField& f, const char* key, size_t count, double* out, std::string* err,
                  bool required = false);
// The same checks on a value (an array element, or the value itself).
bool json_to_int(const Json& v, const std::string& where, int64_t lo, int64_t hi, int64_t* out, std::string* err);
bool json_to_number(const Json& v, const std::string& where, double lo, double hi, double* out, std::string* err);
// "string", "number", ...: for messages.
const char* json_kind(const Json& v);

}  // namespace sepal

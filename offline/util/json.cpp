#include "util/json.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <stdexcept>
#include <vector>

#include "util/io.h"

namespace sepal {
namespace {

void round_doubles(Json* v) {
    if (v->is_number_float()) {
        const double d = v->get<double>();
        if (!std::isfinite(d)) {
            *v = nullptr;
            return;
        }
        char buf[40];
        std::snprintf(buf, sizeof buf, "%.9g", d);
        *v = std::strtod(buf, nullptr);
    } else if (v->is_structured()) {
        for (Json& child : *v) round_doubles(&child);
    }
}

// A refusal raised from inside the parser's callback (a duplicate key, too deep).
struct Refusal : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// Where the parser is, for messages: materials[1].name.
struct Frame {
    bool object = false;
    std::set<std::string> keys;
    std::string key;
    int64_t index = -1;
};

std::string path_of(const std::vector<Frame>& frames) {
    std::string p;
    for (const Frame& f : frames) {
        if (f.object && !f.key.empty()) p += (p.empty() ? "" : ".") + f.key;
        if (!f.object && f.index >= 0) p += "[" + std::to_string(f.index) + "]";
    }
    return p;
}

// nlohmann's messages start with "[json.exception.parse_error.101] parse error at "; the
// rest says where and what.
std::string strip_prefix(const std::string& what) {
    std::string m = what;
    const size_t close = m.find("] ");
    if (m.rfind("[json.exception.", 0) == 0 && close != std::string::npos) m = m.substr(close + 2);
    if (m.rfind("parse error at ", 0) == 0) m = m.substr(15);
    return m;
}

bool fail(std::string* err, const std::string& msg) {
    if (err) *err = msg;
    return false;
}

}  // namespace

std::string dump_json(const Json& value) {
    Json copy = value;
    round_doubles(&copy);
    return copy.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
}

std::string dump_json_compact(const Json& value) {
    Json copy = value;
    round_doubles(&copy);
    return copy.dump(-1, ' ', false, Json::error_handler_t::replace);
}

bool write_json_file(const std::string& path, const Json& value, std::string* err) {
    const std::string text = dump_json(value);
    return write_file_atomic(path, text.data(), text.size(), err);
}

bool parse_json(const std::string& text, const std::string& source, Json* out, std::string* err) {
    if (text.size() > kMaxJsonBytes)
        return fail(err, source + ": " + std::to_string(text.size()) + " bytes of JSON; the limit is " +
                             std::to_string(kMaxJsonBytes));
    std::vector<Frame> frames;
    auto enter = [&](bool object) {
        if (frames.size() >= 64) throw Refusal(path_of(frames) + ": nesting deeper than 64");
        if (!frames.empty() && !frames.back().object) ++frames.back().index;
        frames.push_back(Frame{object, {}, {}, -1});
    };
    const Json::parser_callback_t callback = [&](int, Json::parse_event_t event, Json& parsed) {
        switch (event) {
            case Json::parse_event_t::object_start: enter(true); break;
            case Json::parse_event_t::array_start: enter(false); break;
            case Json::parse_event_t::object_end:
            case Json::parse_event_t::array_end: frames.pop_back(); break;
            case Json::parse_event_t::key: {
                Frame& f = frames.back();
                f.key = parsed.get<std::string>();
                if (!f.keys.insert(f.key).second)
                    throw Refusal("duplicate key \"" + f.key + "\" at " + path_of(frames) +
                                  " (each key may appear once per object)");
                break;
            }
            case Json::parse_event_t::value:
                if (!frames.empty() && !frames.back().object) ++frames.back().index;
                break;
        }
        return true;
    };
    try {
        *out = Json::parse(text, callback, /*allow_exceptions=*/true, /*ignore_comments=*/false);
    } catch (const Refusal& e) {
        return fail(err, source + ": " + e.what());
    } catch (const Json::exception& e) {
        return fail(err, source + ": " + strip_prefix(e.what()));
    }
    return true;
}

bool read_json_file(const std::string& path, Json* out, std::string* err, size_t max_bytes) {
    std::vector<uint8_t> bytes;
    if (!read_file(path, &bytes, err, std::min(max_bytes, kMaxJsonBytes))) return false;
    return parse_json(std::string(bytes.begin(), bytes.end()), path, out, err);
}

const char* json_kind(const Json& v) {
    switch (v.type()) {
        case Json::value_t::null: return "null";
        case Json::value_t::object: return "an object";
        case Json::value_t::array: return "an array";
        case Json::value_t::string: return "a string";
        case Json::value_t::boolean: return "a boolean";
        case Json::value_t::binary: return "binary";
        case Json::value_t::discarded: return "nothing";
        default: return "a number";
    }
}

bool json_to_number(const Json& v, const std::string& where, double lo, double hi, double* out, std::string* err) {
    char range[64];
    std::snprintf(range, sizeof range, "%.9g..%.9g", lo, hi);
    if (!v.is_number()) return fail(err, where + ": expected a number in " + range + ", got " + json_kind(v));
    const double d = v.get<double>();
    if (!std::isfinite(d) || d < lo || d > hi) return fail(err, where + ": " + v.dump() + " is outside " + range);
    *out = d;
    return true;
}

bool json_to_int(const Json& v, const std::string& where, int64_t lo, int64_t hi, int64_t* out, std::string* err) {
    const std::string range = std::to_string(lo) + ".." + std::to_string(hi);
    if (!v.is_number()) return fail(err, where + ": expected an integer in " + range + ", got " + json_kind(v));
    bool in_range = false;
    int64_t x = 0;
    if (v.is_number_unsigned()) {
        const uint64_t u = v.get<uint64_t>();
        in_range = hi >= 0 && u <= uint64_t(hi) && (lo <= 0 || u >= uint64_t(lo));
        x = in_range ? int64_t(u) : 0;
    } else if (v.is_number_integer()) {
        x = v.get<int64_t>();
        in_range = x >= lo && x <= hi;
    } else {
        const double d = v.get<double>();
        if (std::isfinite(d) && d != std::floor(d))
            return fail(err, where + ": " + v.dump() + " is not an integer (expected " + range + ")");
        // Compared as doubles before any conversion: 1e300 never reaches an int64_t.
        // (double(INT64_MAX) rounds up to 2^63, which no int64_t holds: the last test.)
        in_range = std::isfinite(d) && d >= double(lo) && d <= double(hi) && std::fabs(d) < 9223372036854775808.0;
        x = in_range ? int64_t(d) : 0;
    }
    if (!in_range) return fail(err, where + ": " + v.dump() + " is outside " + range);
    *out = x;
    return true;
}

namespace {
const Json* member(const JsonField& f, const char* key, bool required, std::string* err, bool* ok) {
    *ok = true;
    if (!f.object.is_object()) {
        *ok = fail(err, f.where + ": expected an object, got " + json_kind(f.object));
        return nullptr;
    }
    const auto it = f.object.find(key);
    if (it == f.object.end()) {
        if (required) *ok = fail(err, f.where + ": missing \"" + key + "\"");
        return nullptr;
    }
    return &*it;
}
std::string member_where(const JsonField& f, const char* key) {
    return f.where + (f.where.empty() || f.where.back() == ' ' ? "" : ".") + key;
}
}  // namespace

bool json_int(const JsonField& f, const char* key, int64_t lo, int64_t hi, int64_t* out, std::string* err,
              bool required) {
    bool ok = true;
    const Json* v = member(f, key, required, err, &ok);
    return v ? json_to_int(*v, member_where(f, key), lo, hi, out, err) : ok;
}

bool json_int(const JsonField& f, const char* key, int lo, int hi, int* out, std::string* err, bool required) {
    int64_t x = 0;
    bool ok = true;
    const Json* v = member(f, key, required, err, &ok);
    if (!v) return ok;
    if (!json_to_int(*v, member_where(f, key), lo, hi, &x, err)) return false;
    *out = int(x);
    return true;
}

bool json_number(const JsonField& f, const char* key, double lo, double hi, double* out, std::string* err,
                 bool required) {
    bool ok = true;
    const Json* v = member(f, key, required, err, &ok);
    return v ? json_to_number(*v, member_where(f, key), lo, hi, out, err) : ok;
}

bool json_string(const JsonField& f, const char* key, std::string* out, std::string* err, bool required) {
    bool ok = true;
    const Json* v = member(f, key, required, err, &ok);
    if (!v) return ok;
    if (!v->is_string()) return fail(err, member_where(f, key) + ": expected a string, got " + json_kind(*v));
    *out = v->get<std::string>();
    return true;
}

bool json_array(const JsonField& f, const char* key, size_t lo, size_t hi, const Json** out, std::string* err,
                bool required) {
    bool ok = true;
    const Json* v = member(f, key, required, err, &ok);
    if (!v) return ok;
    const std::string range = std::to_string(lo) + ".." + std::to_string(hi);
    if (!v->is_array())
        return fail(err, member_where(f, key) + ": expected an array of " + range + " elements, got " + json_kind(*v));
    if (v->size() < lo || v->size() > hi)
        return fail(err, member_where(f, key) + ": " + std::to_string(v->size()) + " elements, expected " + range);
    *out = v;
    return true;
}

bool json_numbers(const JsonField& f, const char* key, size_t count, double* out, std::string* err, bool required) {
    const Json* a = nullptr;
    if (!json_array(f, key, count, count, &a, err, required)) return false;
    if (!a) return true;
    const std::string where = member_where(f, key);
    for (size_t i = 0; i < count; ++i)
        if (!json_to_number((*a)[i], where + "[" + std::to_string(i) + "]", -HUGE_VAL, HUGE_VAL, &out[i], err))
            return false;
    return true;
}

}  // namespace sepal

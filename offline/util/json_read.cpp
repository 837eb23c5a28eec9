#include "util/json_read.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace sepal {
namespace {

struct Parser {
    const std::string& s;
    size_t i = 0;
    std::string* err;

    bool fail(const std::string& what) {
        int line = 1, col = 1;
        for (size_t k = 0; k < i && k < s.size(); ++k) {
            if (s[k] == '\n') ++line, col = 1;
            else ++col;
        }
        if (err) *err = "line " + std::to_string(line) + ", column " + std::to_string(col) + ": " + what;
        return false;
    }
    void space() {
        while (i < s.size() && (s[i] == ' ' || s[i] == '\t' || s[i] == '\n' || s[i] == '\r')) ++i;
    }
    bool literal(const char* word) {
        const size_t n = std::strlen(word);
        if (s.compare(i, n, word) != 0) return false;
        i += n;
        return true;
    }
    static void utf8(uint32_t c, std::string* out) {
        if (c < 0x80) {
            out->push_back(char(c));
        } else if (c < 0x800) {
            out->push_back(char(0xC0 | (c >> 6)));
            out->push_back(char(0x80 | (c & 0x3F)));
        } else if (c < 0x10000) {
            out->push_back(char(0xE0 | (c >> 12)));
            out->push_back(char(0x80 | ((c >> 6) & 0x3F)));
            out->push_back(char(0x80 | (c & 0x3F)));
        } else {
            out->push_back(char(0xF0 | (c >> 18)));
            out->push_back(char(0x80 | ((c >> 12) & 0x3F)));
            out->push_back(char(0x80 | ((c >> 6) & 0x3F)));
            out->push_back(char(0x80 | (c & 0x3F)));
        }
    }
    bool hex4(uint32_t* v) {
        if (i + 4 > s.size()) return fail("truncated \\u escape");
        *v = 0;
        for (int k = 0; k < 4; ++k) {
            const char c = s[i++];
            *v <<= 4;
            if (c >= '0' && c <= '9') *v |= uint32_t(c - '0');
            else if (c >= 'a' && c <= 'f') *v |= uint32_t(c - 'a' + 10);
            else if (c >= 'A' && c <= 'F') *v |= uint32_t(c - 'A' + 10);
            else return fail("bad \\u escape");
        }
        return true;
    }
    bool string(std::string* out) {
        ++i;  // opening quote
        while (true) {
            if (i >= s.size()) return fail("unterminated string");
            const char c = s[i++];
            if (c == '"') return true;
            if (static_cast<unsigned char>(c) < 0x20) return fail("control character in a string");
            if (c != '\\') {
                out->push_back(c);
                continue;
            }
            if (i >= s.size()) return fail("unterminated escape");
            const char e = s[i++];
            switch (e) {
                case '"': out->push_back('"'); break;
                case '\\': out->push_back('\\'); break;
                case '/': out->push_back('/'); break;
                case 'b': out->push_back('\b'); break;
                case 'f': out->push_back('\f'); break;
                case 'n': out->push_back('\n'); break;
                case 'r': out->push_back('\r'); break;
                case 't': out->push_back('\t'); break;
                case 'u': {
                    uint32_t c1 = 0;
                    if (!hex4(&c1)) return false;
                    if (c1 >= 0xD800 && c1 < 0xDC00) {
                        uint32_t c2 = 0;
                        if (!literal("\\u") || !hex4(&c2) || c2 < 0xDC00 || c2 >= 0xE000)
                            return fail("unpaired surrogate in \\u escape");
                        c1 = 0x10000 + ((c1 - 0xD800) << 10) + (c2 - 0xDC00);
                    }
                    utf8(c1, out);
                    break;
                }
                default: return fail(std::string("unknown escape \\") + e);
            }
        }
    }
    bool number(double* out) {
        const size_t start = i;
        if (i < s.size() && s[i] == '-') ++i;
        if (i >= s.size() || !std::isdigit(static_cast<unsigned char>(s[i]))) return fail("malformed number");
        if (s[i] == '0') ++i;
        else while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) ++i;
        if (i < s.size() && s[i] == '.') {
            ++i;
            if (i >= s.size() || !std::isdigit(static_cast<unsigned char>(s[i]))) return fail("malformed number");
            while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) ++i;
        }
        if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
            ++i;
            if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
            if (i >= s.size() || !std::isdigit(static_cast<unsigned char>(s[i]))) return fail("malformed number");
            while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) ++i;
        }
        // The grammar above guarantees a plain decimal; convert it without the locale.
        const std::string text = s.substr(start, i - start);
        double mantissa = 0;
        int exp10 = 0;
        size_t k = 0;
        const bool neg = text[0] == '-';
        if (neg) ++k;
        for (; k < text.size() && std::isdigit(static_cast<unsigned char>(text[k])); ++k) mantissa = mantissa * 10 + (text[k] - '0');
        if (k < text.size() && text[k] == '.')
            for (++k; k < text.size() && std::isdigit(static_cast<unsigned char>(text[k])); ++k)
                mantissa = mantissa * 10 + (text[k] - '0'), --exp10;
        if (k < text.size()) exp10 += std::atoi(text.c_str() + k + 1);
        *out = (neg ? -1 : 1) * mantissa * std::pow(10.0, exp10);
        if (!std::isfinite(*out)) return fail("number out of range");
        return true;
    }
    bool value(JsonValue* v, int depth) {
        if (depth > 32) return fail("nesting deeper than 32");
        space();
        if (i >= s.size()) return fail("unexpected end of text");
        const char c = s[i];
        if (c == '{') {
            v->kind = JsonValue::Object;
            ++i;
            space();
            if (i < s.size() && s[i] == '}') return ++i, true;
            while (true) {
                space();
                if (i >= s.size() || s[i] != '"') return fail("expected a quoted key");
                std::string key;
                if (!string(&key)) return false;
                space();
                if (i >= s.size() || s[i] != ':') return fail("expected ':' after a key");
                ++i;
                JsonValue member;
                if (!value(&member, depth + 1)) return false;
                v->object.emplace_back(std::move(key), std::move(member));
                space();
                if (i < s.size() && s[i] == ',') { ++i; continue; }
                if (i < s.size() && s[i] == '}') return ++i, true;
                return fail("expected ',' or '}' in an object");
            }
        }
        if (c == '[') {
            v->kind = JsonValue::Array;
            ++i;
            space();
            if (i < s.size() && s[i] == ']') return ++i, true;
            while (true) {
                JsonValue element;
                if (!value(&element, depth + 1)) return false;
                v->array.push_back(std::move(element));
                space();
                if (i < s.size() && s[i] == ',') { ++i; continue; }
                if (i < s.size() && s[i] == ']') return ++i, true;
                return fail("expected ',' or ']' in an array");
            }
        }
        if (c == '"') {
            v->kind = JsonValue::String;
            return string(&v->string);
        }
        if (literal("true")) return v->kind = JsonValue::Bool, v->boolean = true, true;
        if (literal("false")) return v->kind = JsonValue::Bool, v->boolean = false, true;
        if (literal("null")) return v->kind = JsonValue::Null, true;
        v->kind = JsonValue::Number;
        return number(&v->number);
    }
};

}  // namespace

const JsonValue* JsonValue::find(const std::string& key) const {
    for (const auto& m : object)
        if (m.first == key) return &m.second;
    return nullptr;
}

bool parse_json(const std::string& text, JsonValue* out, std::string* err) {
    if (text.size() > (1u << 20)) {
        if (err) *err = "JSON text over 1 MB";
        return false;
    }
    Parser p{text, 0, err};
    *out = JsonValue{};
    if (!p.value(out, 0)) return false;
    p.space();
    if (p.i != text.size()) return p.fail("trailing characters after the JSON value");
    return true;
}

bool json_number(const JsonValue& obj, const std::string& key, double lo, double hi, double* out,
                 std::string* err) {
    const JsonValue* v = obj.find(key);
    if (!v || v->kind != JsonValue::Number || !(v->number >= lo && v->number <= hi)) {
        if (err) {
            char buf[128];
            std::snprintf(buf, sizeof buf, ": a number in [%g, %g] is expected", lo, hi);
            *err = "\"" + key + "\"" + buf;
        }
        return false;
    }
    *out = v->number;
    return true;
}

bool json_int(const JsonValue& obj, const std::string& key, int lo, int hi, int* out, std::string* err) {
    double d = 0;
    if (!json_number(obj, key, lo, hi, &d, err)) return false;
    if (d != std::floor(d)) {
        if (err) *err = "\"" + key + "\": an integer is expected";
        return false;
    }
    *out = int(d);
    return true;
}

bool json_string(const JsonValue& obj, const std::string& key, std::string* out, std::string* err) {
    const JsonValue* v = obj.find(key);
    if (!v || v->kind != JsonValue::String) {
        if (err) *err = "\"" + key + "\": a string is expected";
        return false;
    }
    *out = v->string;
    return true;
}

bool json_numbers(const JsonValue& obj, const std::string& key, int count, double* out, std::string* err) {
    const JsonValue* v = obj.find(key);
    bool ok = v && v->kind == JsonValue::Array && v->array.size() == size_t(count);
    for (int i = 0; ok && i < count; ++i) {
        const JsonValue& x = v->array[size_t(i)];
        ok = x.kind == JsonValue::Number && std::isfinite(x.number);
        if (ok) out[i] = x.number;
    }
    if (!ok && err) *err = "\"" + key + "\": an array of " + std::to_string(count) + " numbers is expected";
    return ok;
}

}  // namespace sepal

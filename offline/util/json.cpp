#include "util/json.h"

#include <cmath>
#include <cstdio>

namespace sepal {

std::string JsonWriter::escape(const std::string& s) {
    std::string o = "\"";
    for (unsigned char c : s) {
        switch (c) {
            case '"': o += "\\\""; break;
            case '\\': o += "\\\\"; break;
            case '\n': o += "\\n"; break;
            case '\r': o += "\\r"; break;
            case '\t': o += "\\t"; break;
            default:
                if (c < 0x20) {
                    char buf[8];
                    std::snprintf(buf, sizeof buf, "\\u%04x", c);
                    o += buf;
                } else {
                    o += char(c);
                }
        }
    }
    return o + "\"";
}

void JsonWriter::before_value() {
    if (after_key_) {
        after_key_ = false;
        return;
    }
    if (!empty_.empty()) {
        out_ += empty_.back() ? "\n" : ",\n";
        empty_.back() = false;
        out_.append(2 * empty_.size(), ' ');
    }
}

void JsonWriter::open(char c) {
    before_value();
    out_ += c;
    empty_.push_back(true);
}

void JsonWriter::close(char c) {
    const bool was_empty = empty_.empty() || empty_.back();
    if (!empty_.empty()) empty_.pop_back();
    if (!was_empty) {
        out_ += "\n";
        out_.append(2 * empty_.size(), ' ');
    }
    out_ += c;
    if (empty_.empty()) out_ += "\n";
}

JsonWriter& JsonWriter::begin_object() { return open('{'), *this; }
JsonWriter& JsonWriter::end_object() { return close('}'), *this; }
JsonWriter& JsonWriter::begin_array() { return open('['), *this; }
JsonWriter& JsonWriter::end_array() { return close(']'), *this; }

JsonWriter& JsonWriter::key(const std::string& k) {
    before_value();
    out_ += escape(k) + ": ";
    after_key_ = true;
    return *this;
}

JsonWriter& JsonWriter::value(double v) {
    before_value();
    if (!std::isfinite(v)) {
        out_ += "null";
    } else {
        char buf[40];
        std::snprintf(buf, sizeof buf, "%.9g", v);
        out_ += buf;
    }
    return *this;
}

JsonWriter& JsonWriter::value(int64_t v) {
    before_value();
    out_ += std::to_string(v);
    return *this;
}

JsonWriter& JsonWriter::value(bool v) {
    before_value();
    out_ += v ? "true" : "false";
    return *this;
}

JsonWriter& JsonWriter::value(const std::string& v) {
    before_value();
    out_ += escape(v);
    return *this;
}

JsonWriter& JsonWriter::null() {
    before_value();
    out_ += "null";
    return *this;
}

}  // namespace sepal

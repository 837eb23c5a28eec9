// A minimal JSON writer for reports (no reader: sepal only writes JSON).
//
// Usage:
//   sepal::JsonWriter j;
//   j.begin_object().key("res").value(32).key("errors").begin_array();
//   j.value(0.5).end_array().end_object();
//   write_file_atomic(path, j.str().data(), j.str().size(), &err);
//
// Output is indented by two spaces, one member or element per line. Numbers are written
// with 9 significant digits ("%.9g", "C" locale behaviour of snprintf), NaN and inf as
// null (JSON has neither). Strings are escaped (quote, backslash, control characters);
// other bytes pass through, so give it UTF-8. Misuse (a value without a key inside an
// object, unbalanced ends) is not diagnosed: the writer trusts its caller.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace sepal {

class JsonWriter {
  public:
    JsonWriter& begin_object();
    JsonWriter& end_object();
    JsonWriter& begin_array();
    JsonWriter& end_array();
    JsonWriter& key(const std::string& k);
    JsonWriter& value(double v);
    JsonWriter& value(int v) { return value(int64_t(v)); }
    JsonWriter& value(int64_t v);
    JsonWriter& value(bool v);
    JsonWriter& value(const std::string& v);
    JsonWriter& value(const char* v) { return value(std::string(v)); }
    JsonWriter& null();
    // The document so far, with a final newline once the outermost value is closed.
    const std::string& str() const { return out_; }

    static std::string escape(const std::string& s);

  private:
    void before_value();
    void open(char c);
    void close(char c);
    std::string out_;
    std::vector<bool> empty_;  // per open container: nothing written into it yet
    bool after_key_ = false;
};

}  // namespace sepal

// A streaming front end over nlohmann (sepal::Json) for the benches' long reports: nested
// objects and arrays written in order with begin/key/value/end, dumped by sepal::dump_json
// (the project's one JSON printer: byte-stable numbers, NaN/inf as null).
//
//   JsonBuilder j;
//   j.begin_object().key("bench").value("foo").key("rows").begin_array();
//   for (...) j.begin_object().key("ms").value(ms).end_object();
//   j.end_array().end_object();
//   write_text(path, j.str());
#pragma once
#include <string>
#include <vector>

#include "util/json.h"

class JsonBuilder {
  public:
    JsonBuilder& begin_object() { return open(sepal::Json::object()); }
    JsonBuilder& begin_array() { return open(sepal::Json::array()); }
    JsonBuilder& end_object() { return close(); }
    JsonBuilder& end_array() { return close(); }
    JsonBuilder& key(const std::string& k) {
        key_ = k;
        return *this;
    }
    template <typename T>
    JsonBuilder& value(const T& v) {
        put(sepal::Json(v));
        return *this;
    }
    JsonBuilder& value(const char* v) { return value(std::string(v)); }
    std::string str() const { return sepal::dump_json(root_); }
    const sepal::Json& json() const { return root_; }

  private:
    JsonBuilder& open(sepal::Json v) {
        stack_.push_back(put(std::move(v)));
        return *this;
    }
    JsonBuilder& close() {
        if (!stack_.empty()) stack_.pop_back();
        return *this;
    }
    // Where the next value goes: the root, the open array, or the open object under key_.
    // The pointers on the stack stay valid: a container only grows while it is the innermost
    // open one, so no open container is ever moved by its parent growing.
    sepal::Json* put(sepal::Json v) {
        if (stack_.empty()) {
            root_ = std::move(v);
            return &root_;
        }
        sepal::Json& top = *stack_.back();
        if (top.is_array()) {
            top.push_back(std::move(v));
            return &top.back();
        }
        sepal::Json& slot = top[key_];
        slot = std::move(v);
        return &slot;
    }
    sepal::Json root_;
    std::string key_;
    std::vector<sepal::Json*> stack_;
};

// Enum <-> name tables: one table per enum, so that its printed names and its parser
// cannot disagree.
//
// Usage:
//   constexpr EnumName<Method> kMethods[] = {{Method::SVD, "svd"}, {Method::NMF, "nmf"}};
//   const char* method_name(Method m) { return enum_name(kMethods, m); }      // "?" if absent
//   bool parse_method(const std::string& s, Method* m) { return parse_enum(kMethods, s, m); }
#pragma once
#include <cstddef>
#include <string>

namespace sepal {

template <typename E>
struct EnumName {
    E value;
    const char* name;
};

template <typename E, size_t N>
const char* enum_name(const EnumName<E> (&table)[N], E value) {
    for (const EnumName<E>& e : table)
        if (e.value == value) return e.name;
    return "?";
}

// False (and *out unchanged) when `text` names no entry.
template <typename E, size_t N>
bool parse_enum(const EnumName<E> (&table)[N], const std::string& text, E* out) {
    for (const EnumName<E>& e : table)
        if (text == e.name) {
            *out = e.value;
            return true;
        }
    return false;
}

}  // namespace sepal

// JSON conventions over nlohmann-json (offline/util/json.h): output format, strict reading,
// range-checked typed reads.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include "util/json.h"

using sepal::Json;

namespace {
bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }
}  // namespace

TEST_CASE("json: output is indented, ordered, escaped, with floats at 9 digits and NaN as null") {
    Json j;
    j["b"] = 1;
    j["a"] = "q\"\\\n\x01";
    j["n"] = std::nan("");
    j["f"] = double(0.1f);  // a float widened: 9 significant digits, not 17
    j["v"] = {0.5, true};
    j["e"] = Json::object();
    CHECK(sepal::dump_json(j) ==
          "{\n  \"b\": 1,\n  \"a\": \"q\\\"\\\\\\n\\u0001\",\n  \"n\": null,\n  \"f\": 0.100000001,\n  \"v\": [\n    0.5,\n"
          "    true\n  ],\n  \"e\": {}\n}\n");
    // Bytes that are not UTF-8 (a Latin-1 file name) are replaced, not thrown at the caller.
    CHECK(contains(sepal::dump_json(Json("caf\xe9")), "caf\xef\xbf\xbd"));
}

TEST_CASE("json: the reader refuses duplicate keys, deep nesting and huge numbers, naming where") {
    Json v;
    std::string err;
    CHECK(sepal::parse_json("{\"materials\": [{\"name\": \"a\"}, {\"name\": \"b\", \"name\": \"c\"}]}", "s.json", &v,
                            &err) == false);
    CHECK_MESSAGE(contains(err, "s.json: duplicate key \"name\" at materials[1].name"), err);
    // The same key in different objects is fine.
    REQUIRE_MESSAGE(sepal::parse_json("{\"a\": {\"x\": 1}, \"b\": {\"x\": 2}, \"c\": [1, {\"x\": 3}]}", "s", &v, &err),
                    err);
    CHECK(v["c"][1]["x"] == 3);
    CHECK_FALSE(sepal::parse_json(std::string(100, '[') + std::string(100, ']'), "deep.json", &v, &err));
    CHECK_MESSAGE(contains(err, "nesting deeper than 64"), err);
    CHECK_FALSE(sepal::parse_json("{\"a\": 1e400}", "big.json", &v, &err));
    CHECK_MESSAGE(contains(err, "big.json: number overflow"), err);
    CHECK_FALSE(sepal::parse_json("{\"a\":\n tru}", "t.json", &v, &err));
    CHECK_MESSAGE(contains(err, "t.json: line 2, column"), err);
    CHECK_MESSAGE(!contains(err, "json.exception"), err);
    CHECK_FALSE(sepal::parse_json("{\"a\": 1} x", "t.json", &v, &err));
    CHECK_FALSE(sepal::parse_json("{\"a\": 1, /* no */ }", "t.json", &v, &err));
    // A UTF-8 byte-order mark (some Windows editors write one) is skipped.
    REQUIRE_MESSAGE(sepal::parse_json("\xEF\xBB\xBF{\"a\": 2}", "bom.json", &v, &err), err);
    CHECK(v["a"] == 2);
}

TEST_CASE("json: typed reads check the kind and the range before converting") {
    Json v;
    std::string err;
    REQUIRE(sepal::parse_json("{\"i\": 3, \"f\": 2.0, \"h\": 1e12, \"x\": 2.5, \"s\": \"t\", \"neg\": -4, "
                              "\"u\": 18446744073709551615, \"inf\": -1e308}",
                              "m.json", &v, &err));
    const sepal::JsonField f{v, "m.json: materials[0]"};
    int i = 0;
    CHECK(sepal::json_int(f, "i", 1, 64, &i, &err));
    CHECK(i == 3);
    CHECK(sepal::json_int(f, "f", 1, 64, &i, &err));  // an integral double is an integer
    CHECK(i == 2);
    i = 7;
    CHECK_FALSE(sepal::json_int(f, "h", 1, 64, &i, &err));
    CHECK_MESSAGE(err == "m.json: materials[0].h: 1000000000000.0 is outside 1..64", err);
    CHECK(i == 7);  // untouched on failure
    CHECK_FALSE(sepal::json_int(f, "x", 1, 64, &i, &err));
    CHECK_MESSAGE(contains(err, "2.5 is not an integer"), err);
    CHECK_FALSE(sepal::json_int(f, "s", 1, 64, &i, &err));
    CHECK_MESSAGE(contains(err, "expected an integer in 1..64, got a string"), err);
    CHECK_FALSE(sepal::json_int(f, "neg", 0, 10, &i, &err));
    CHECK_FALSE(sepal::json_int(f, "u", 0, std::numeric_limits<int>::max(), &i, &err));
    int64_t big = 0;
    CHECK_FALSE(sepal::json_int(f, "u", int64_t(0), std::numeric_limits<int64_t>::max(), &big, &err));
    CHECK(sepal::json_int(f, "absent", 1, 64, &i, &err));  // optional: untouched
    CHECK(i == 7);
    CHECK_FALSE(sepal::json_int(f, "absent", 1, 64, &i, &err, /*required=*/true));
    CHECK_MESSAGE(contains(err, "m.json: materials[0]: missing \"absent\""), err);
    double d = 0;
    CHECK(sepal::json_number(f, "x", 0.0, 10.0, &d, &err));
    CHECK(d == 2.5);
    CHECK_FALSE(sepal::json_number(f, "inf", 0.0, 10.0, &d, &err));
    std::string s;
    CHECK(sepal::json_string(f, "s", &s, &err));
    CHECK(s == "t");
    CHECK_FALSE(sepal::json_string(f, "i", &s, &err));
    CHECK_MESSAGE(contains(err, "materials[0].i: expected a string, got a number"), err);
}

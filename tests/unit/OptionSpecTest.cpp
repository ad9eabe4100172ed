// SPDX-License-Identifier: Apache-2.0
#include <catch2/catch.hpp>

#include "vdbmap/Error.h"
#include "vdbmap/core/OptionSpec.h"

using namespace vdbmap;

namespace {
struct Members {
    bool flag = false;
    int count = 0;
    std::int64_t big = 0;
    double size_m = 0.0;
    std::string name;
    std::vector<double> xs;
    std::vector<int> ids;
    std::vector<std::string> names;
    void declare(OptionSpec& spec) {
        spec.add("flag", "a bool", flag, true);
        spec.add("count", "an int", count, 3);
        spec.add("big", "an int64", big, std::int64_t{1} << 40);
        spec.add("size_m", "a double", size_m, 0.25, "m");
        spec.add("name", "a string", name, std::string("abc"));
        spec.add("xs", "doubles", xs, std::vector<double>{1.5});
        spec.add("ids", "ints", ids, std::vector<int>{1, 2});
        spec.addRequired("names", "strings", names);
    }
};
}  // namespace

TEST_CASE("defaults are written into the members at declaration", "[options]") {
    Members m;
    OptionSpec spec;
    m.declare(spec);
    CHECK(m.flag);
    CHECK(m.count == 3);
    CHECK(m.big == (std::int64_t{1} << 40));
    CHECK(m.size_m == 0.25);
    CHECK(m.name == "abc");
    CHECK(m.xs == std::vector<double>{1.5});
    CHECK(m.ids == std::vector<int>{1, 2});
    CHECK(spec.find("names")->required);
    CHECK_FALSE(spec.find("count")->required);
    CHECK(spec.find("size_m")->unit == "m");
    CHECK(spec.find("nope") == nullptr);
    CHECK(spec.keyList() == "flag, count, big, size_m, name, xs, ids, names");
}

TEST_CASE("set assigns matching types and converts int to double", "[options]") {
    Members m;
    OptionSpec spec;
    m.declare(spec);
    spec.set("flag", false);
    spec.set("count", std::int64_t{-7});
    spec.set("size_m", std::int64_t{2});  // int -> double
    spec.set("name", std::string("xyz"));
    spec.set("xs", std::vector<std::int64_t>{1, 2, 3});  // list<int> -> list<double>
    spec.set("ids", std::vector<std::int64_t>{});
    spec.set("names", std::vector<std::string>{"a", "b"});
    CHECK_FALSE(m.flag);
    CHECK(m.count == -7);
    CHECK(m.size_m == 2.0);
    CHECK(m.name == "xyz");
    CHECK(m.xs == std::vector<double>{1.0, 2.0, 3.0});
    CHECK(m.ids.empty());
    CHECK(m.names == std::vector<std::string>{"a", "b"});
    CHECK(std::get<double>(spec.value("size_m")) == 2.0);
    CHECK(std::get<std::vector<std::int64_t>>(spec.value("ids")).empty());
    // An empty list of another element type is still an empty list.
    spec.set("names", std::vector<double>{});
    CHECK(m.names.empty());
}

TEST_CASE("set rejects wrong types naming key, expected and found", "[options]") {
    Members m;
    OptionSpec spec;
    m.declare(spec);
    try {
        spec.set("count", 1.5);
        FAIL("no exception");
    } catch (const ConfigError& e) {
        const std::string what = e.what();
        CHECK(what.find("'count'") != std::string::npos);
        CHECK(what.find("expected int") != std::string::npos);
        CHECK(what.find("found double 1.5") != std::string::npos);
    }
    CHECK(m.count == 3);  // untouched
    CHECK_THROWS_AS(spec.set("flag", std::int64_t{1}), ConfigError);
    CHECK_THROWS_AS(spec.set("name", std::int64_t{1}), ConfigError);
    CHECK_THROWS_AS(spec.set("xs", std::vector<std::string>{"a"}), ConfigError);
    CHECK_THROWS_WITH(spec.set("count", std::int64_t{1} << 40),
                      Catch::Contains("does not fit in a 32-bit int"));
    CHECK_THROWS_WITH(spec.set("ids", std::vector<std::int64_t>{std::int64_t{1} << 40}),
                      Catch::Contains("does not fit"));
    CHECK_THROWS_WITH(spec.set("nope", true), Catch::Contains("valid keys: flag, count"));
}

TEST_CASE("duplicate and empty keys are rejected", "[options]") {
    OptionSpec spec;
    int a = 0;
    spec.add("a", "first", a, 1);
    CHECK_THROWS_AS(spec.add("a", "again", a, 2), InvalidInput);
    CHECK_THROWS_AS(spec.add("", "empty", a, 2), InvalidInput);
}

TEST_CASE("values format for describe and reports", "[options]") {
    CHECK(formatOptionValue(true) == "true");
    CHECK(formatOptionValue(std::int64_t{-3}) == "-3");
    CHECK(formatOptionValue(2.0) == "2.0");
    CHECK(formatOptionValue(0.1) == "0.1");
    CHECK(formatOptionValue(std::string("a\"b")) == "\"a\\\"b\"");
    CHECK(formatOptionValue(std::vector<double>{1.0, 0.5}) == "[1.0, 0.5]");
    CHECK(formatOptionValue(std::vector<std::int64_t>{}) == "[]");
    CHECK(formatOptionValue(std::vector<std::string>{"x"}) == "[\"x\"]");
    CHECK(std::string(optionTypeName(OptionType::DoubleList)) == "list<double>");
}

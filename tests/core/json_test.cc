#include "core/json.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/errors.h"
#include "core/limits.h"
#include "core/rng.h"

namespace hribench::core {
namespace {

TEST(JsonTest, CanonicalTextSortsKeysWithoutSpaces) {
  Json j;
  j["b"] = 1;
  j["a"] = Json::array({1.5, "x"});
  EXPECT_EQ(canonical_json(j), R"({"a":[1.5,"x"],"b":1})");
}

// Random doubles over many magnitudes read back bit for bit.
TEST(JsonTest, DoublesRoundTripExactly) {
  Rng rng(7);
  for (int i = 0; i < 2000; ++i) {
    const double x = rng.normal(0.0, 1.0) * std::pow(10.0, rng.uniform_int(-12, 12));
    const Json back = parse_json(canonical_json(Json(x)), "test");
    EXPECT_EQ(back.get<double>(), x) << canonical_json(Json(x));
  }
  const double tiny = std::numeric_limits<double>::denorm_min();
  EXPECT_EQ(parse_json(canonical_json(Json(tiny)), "t").get<double>(), tiny);
  EXPECT_EQ(parse_json(canonical_json(Json(0.1)), "t").get<double>(), 0.1);
}

TEST(JsonTest, RefusesNaNWithItsPath) {
  Json j;
  j["acts"] = Json::array({Json::object({{"t", std::nan("")}})});
  try {
    canonical_json(j);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), "acts[0].t");
    EXPECT_EQ(e.expected(), "a finite number");
  }
}

TEST(JsonTest, ParseErrorsCarryLineAndColumn) {
  try {
    parse_json("{\n  \"a\": 1,\n  \"b\": ]\n}", "spec.json");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), "spec.json:3:8");
    EXPECT_NE(std::string(e.what()).find("invalid JSON"), std::string::npos);
  }
}

// Nesting deeper than kMaxNestingDepth is refused where it starts (200,000 levels used to
// overflow the stack in the DOM and its readers), and a number beyond a double's range is an
// InputError with its location, not nlohmann's out_of_range.
TEST(JsonTest, DeepNestingAndHugeNumbersAreInputErrors) {
  const std::string ok = std::string(kMaxNestingDepth, '[') + std::string(kMaxNestingDepth, ']');
  EXPECT_EQ(parse_json(ok, "ok.json").size(), 1U);
  for (const size_t n : {size_t{kMaxNestingDepth} + 1, size_t{200000}}) {
    try {
      parse_json("\n " + std::string(n, '[') + std::string(n, ']'), "deep.json");
      FAIL() << "no error";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()), "deep.json:2:34: expected nesting at most 32 deep, got deeper nesting");
    }
  }
  try {
    parse_json(R"({"a": {"x": 1}, "b": "[[[[", "fps": 1e400})", "clip.json");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), "clip.json:1:37");
    EXPECT_EQ(e.expected(), "a number within the range of a double");
    EXPECT_EQ(e.got(), "'1e400'");
  }
}

TEST(JsonTest, TypedAccessNamesThePath) {
  const Json j = parse_json(R"({"x": "s", "n": 2, "f": true})", "t");
  EXPECT_EQ(json_number(json_member(j, "n", "spec"), "spec.n"), 2.0);
  EXPECT_EQ(json_string(json_member(j, "x", "spec"), "spec.x"), "s");
  EXPECT_TRUE(json_bool(json_member(j, "f", "spec"), "spec.f"));
  EXPECT_THROW(json_member(j, "missing", "spec"), InputError);
  try {
    json_number(j["x"], "spec.x");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "spec.x: expected a number, got string");
  }
  EXPECT_THROW(read_json_file("/nonexistent/file.json"), InputError);
}

}  // namespace
}  // namespace hribench::core

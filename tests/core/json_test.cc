#include "core/json.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/errors.h"
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

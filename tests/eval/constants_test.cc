#include "eval/constants.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace hribench::eval {
namespace {

// The Wilson z follows `confidence`: the two-sided standard normal quantile, the 0.95 value
// as before to the last bit.
TEST(ConstantsTest, WilsonZFollowsTheConfidence) {
  MetricConstants c;
  EXPECT_EQ(c.wilson_z(), 1.959963984540054);
  c.confidence = 0.90;
  EXPECT_NEAR(c.wilson_z(), 1.6448536269514722, 1e-14);
  c.confidence = 0.99;
  EXPECT_NEAR(c.wilson_z(), 2.5758293035489004, 1e-14);
  c.confidence = 0.5;
  EXPECT_NEAR(c.wilson_z(), 0.6744897501960817, 1e-14);
}

TEST(ConstantsTest, NormalQuantileInvertsTheDistribution) {
  for (const double p : {1e-12, 0.001, 0.1, 0.3, 0.5, 0.7, 0.9, 0.999, 1 - 1e-12}) {
    const double z = normal_quantile(p);
    EXPECT_NEAR(0.5 * std::erfc(-z / std::sqrt(2.0)), p, 1e-15 + 1e-12 * p) << p;
  }
  EXPECT_EQ(normal_quantile(0.5), 0.0);
  EXPECT_DEATH(normal_quantile(1.0), "normal_quantile");
}

// The results file records what is set (confidence), not what is derived from it.
TEST(ConstantsTest, TheTableHoldsNoDerivedValue) {
  const std::vector<NamedConstant> table = constant_table(MetricConstants{});
  EXPECT_TRUE(std::any_of(table.begin(), table.end(), [](const NamedConstant& c) { return c.name == "confidence"; }));
  EXPECT_TRUE(std::none_of(table.begin(), table.end(), [](const NamedConstant& c) { return c.name == "wilson_z"; }));
}

}  // namespace
}  // namespace hribench::eval

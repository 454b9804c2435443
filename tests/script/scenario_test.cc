#include "script/scenario.h"

#include <gtest/gtest.h>

namespace hribench::script {
namespace {

TEST(ScenarioTest, ResolvedValuesAndLocationBlindEquality) {
  Num n(2.5);
  EXPECT_EQ(n.value(), 2.5);
  Text t("cup");
  EXPECT_EQ(t.value(), "cup");
  Num m(2.5);
  m.where.text = "a.yaml:3:4 (x)";
  EXPECT_EQ(n, m);  // where a value was written does not make it different
  m.expr = Expr::Number(2.75);
  EXPECT_NE(n, m);
}

TEST(ScenarioTest, UnresolvedValueIsAProgrammerError) {
  Num n;
  n.expr = parse_expr("U(0, 1)");
  EXPECT_DEATH(n.value(), "unresolved number U\\(0, 1\\)");
}

}  // namespace
}  // namespace hribench::script

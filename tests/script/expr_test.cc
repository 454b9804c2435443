#include "script/expr.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

namespace hribench::script {
namespace {

ExprError error_of(const std::string& text) {
  try {
    parse_expr(text);
  } catch (const ExprError& e) {
    return e;
  }
  return {"(no error)", ""};
}

TEST(ExprTest, ParsesLiteralsVarsAndTemplates) {
  EXPECT_EQ(parse_expr("1.25"), Expr::Number(1.25));
  EXPECT_EQ(parse_expr("-3e-2"), Expr::Number(-0.03));
  EXPECT_EQ(parse_expr("light blue"), Expr::String("light blue"));
  EXPECT_EQ(parse_expr("Take the cup (red)."), Expr::String("Take the cup (red)."));
  const Expr var = parse_expr("$hand");
  EXPECT_EQ(var.kind, Expr::Kind::kVar);
  EXPECT_EQ(var.text, "hand");
  const Expr tpl = parse_expr("human.$hand");
  EXPECT_EQ(tpl.kind, Expr::Kind::kTemplate);
  EXPECT_EQ(var_refs(tpl), std::vector<std::string>{"hand"});
  EXPECT_EQ(template_refs("$hand.wrist and $x"), (std::vector<std::string>{"hand", "x"}));
}

TEST(ExprTest, ParsesDistributionsAndPrintsThemBack) {
  for (const char* text : {"U(0.5, 3)", "Uint(0, 2)", "N(180, 5)", "N(180, 5, clip=[170, 190])",
                           "choice([right, left])", "choice([1, 2.5], [3, 1])", "choice([$a, 'two words'])"}) {
    const Expr e = parse_expr(text);
    EXPECT_EQ(to_source(e), text);
    EXPECT_EQ(parse_expr(to_source(e)), e);
  }
  EXPECT_EQ(parse_expr("U (1,2)").kind, Expr::Kind::kUniform);
}

TEST(ExprTest, RefusesMalformedDistributions) {
  EXPECT_EQ(error_of("U(2, 1)").expected, "U(a, b) with a < b");
  EXPECT_EQ(error_of("U(1, 1)").got, "U(1, 1)");
  EXPECT_EQ(error_of("Uint(0.5, 2)").expected, "Uint(a, b) with integer bounds");
  EXPECT_EQ(error_of("N(0, 0)").expected, "N(mu, sigma) with sigma > 0");
  EXPECT_EQ(error_of("N(0, 1, clip=[2, 1])").expected, "clip=[lo, hi] with lo < hi");
  EXPECT_EQ(error_of("choice([])").expected, "at least one choice");
  EXPECT_EQ(error_of("choice([a, b], [1])").expected, "one weight per choice (2)");
  EXPECT_EQ(error_of("choice([a, b], [0, 0])").expected, "weights with a positive sum");
  EXPECT_EQ(error_of("choice([a, b], [-1, 2])").expected, "weights >= 0");
  EXPECT_EQ(error_of("U(1e400, 2)").expected, "a number within +-1e6");
  EXPECT_EQ(error_of("U(0.3").got, "the end");
  EXPECT_NE(error_of("U(0.3").expected.find("quote the expression"), std::string::npos);
  EXPECT_EQ(error_of("U(1, 2) extra").expected, "the end of the expression");
  EXPECT_EQ(error_of("$").expected, "a var name after '$'");
  EXPECT_THROW(parse_expr("2000000"), ExprError);
}

// Calls nested deeper than core::kMaxNestingDepth are refused by the parser (5,000 nested
// choice(...) used to overflow the stack in `hribench check`).
TEST(ExprTest, DeeplyNestedCallsAreRefused) {
  const auto nested = [](int n) {
    std::string text;
    for (int i = 0; i < n; ++i) text += "choice([";
    text += "1";
    for (int i = 0; i < n; ++i) text += "])";
    return text;
  };
  EXPECT_EQ(parse_expr(nested(32)).kind, Expr::Kind::kChoice);
  for (const int n : {33, 5000}) {
    const ExprError e = error_of(nested(n));
    EXPECT_EQ(e.expected, "calls nested at most 32 deep");
    EXPECT_EQ(e.got, "deeper nesting");
  }
}

TEST(ExprTest, DrawsWithinSupportAndFollowsWeights) {
  core::Rng rng(11);
  VarTable vars;
  const Expr u = parse_expr("U(0.5, 3)"), i = parse_expr("Uint(0, 2)"),
             n = parse_expr("N(180, 5, clip=[178, 182])"), c = parse_expr("choice([a, b], [3, 1])");
  std::map<std::string, int> counts;
  std::map<double, int> ints;
  for (int k = 0; k < 4000; ++k) {
    const double x = std::get<double>(draw(u, rng, vars));
    EXPECT_TRUE(x >= 0.5 && x < 3);
    ints[std::get<double>(draw(i, rng, vars))]++;
    const double y = std::get<double>(draw(n, rng, vars));
    EXPECT_TRUE(y >= 178 && y <= 182);
    counts[std::get<std::string>(draw(c, rng, vars))]++;
  }
  EXPECT_EQ(ints.size(), 3U);
  EXPECT_NEAR(counts["a"] / 4000.0, 0.75, 0.03);
}

TEST(ExprTest, VarsAndTemplatesUseTheDrawnValues) {
  core::Rng rng(1);
  VarTable vars;
  vars.names = {"hand", "n"};
  vars.values = {std::string("left"), 0.1};
  EXPECT_EQ(std::get<std::string>(draw(parse_expr("human.$hand"), rng, vars)), "human.left");
  EXPECT_EQ(std::get<double>(draw(parse_expr("$n"), rng, vars)), 0.1);
  EXPECT_EQ(substitute("near(robot, $hand, $n)", vars), "near(robot, left, 0.1)");
  EXPECT_THROW(draw(parse_expr("$missing"), rng, vars), ExprError);
}

TEST(ExprTest, RangesTypesAndWordSets) {
  const std::vector<std::string> names = {"side", "d"};
  const std::vector<Expr> defs = {parse_expr("choice([left, right])"), parse_expr("U(1, 2)")};
  const Range r = value_range(parse_expr("choice([$d, 5])"), names, defs);
  EXPECT_EQ(r.lo, 1);
  EXPECT_EQ(r.hi, 5);
  EXPECT_TRUE(std::isinf(value_range(parse_expr("N(0, 1)"), names, defs).hi));
  EXPECT_EQ(expr_type(parse_expr("$side"), names, defs), "string");
  EXPECT_EQ(expr_type(parse_expr("choice([1, a])"), names, defs), "mixed");
  EXPECT_EQ(expr_type(parse_expr("$nope"), names, defs), "unknown");
  const StringSet s = string_values(parse_expr("human.$side"), names, defs);
  EXPECT_TRUE(s.complete);
  EXPECT_EQ(s.values, (std::vector<std::string>{"human.left", "human.right"}));
  EXPECT_FALSE(string_values(parse_expr("U(0, 1)"), names, defs).complete);
}

TEST(ExprTest, FormatsShortestExactNumbers) {
  EXPECT_EQ(format_number(0.1), "0.1");
  EXPECT_EQ(format_number(1.0), "1");
  const double x = 0.1 + 0.2;
  EXPECT_EQ(std::stod(format_number(x)), x);
}

}  // namespace
}  // namespace hribench::script

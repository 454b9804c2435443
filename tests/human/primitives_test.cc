#include "human/primitives.h"

#include <gtest/gtest.h>

#include <set>
#include <string>

namespace hribench::human {
namespace {

TEST(PrimitivesTest, CatalogListsEveryPrimitiveOnce) {
  const std::vector<std::string> expected = {
      "idle",   "walk_to", "reach",   "retract", "point",       "go",    "stop",  "give_me",
      "cancel", "your_turn", "offer", "receive", "pick",        "place", "move_object",
      "hold_lid", "lift",  "carry",   "lower",   "intrude",     "withdraw", "release_retract"};
  const auto& catalog = primitive_catalog();
  ASSERT_EQ(catalog.size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(catalog[i].name, expected[i]);
    EXPECT_EQ(find_primitive(expected[i]), &catalog[i]);
  }
  EXPECT_EQ(find_primitive("dance"), nullptr);
}

TEST(PrimitivesTest, PhasesFollowTheLiterature) {
  const PrimitiveInfo* point = find_primitive("point");
  ASSERT_NE(point, nullptr);
  std::vector<std::string> names;
  for (const PhaseInfo& p : point->phases) names.emplace_back(p.name);
  EXPECT_EQ(names, (std::vector<std::string>{"prep", "stroke", "hold", "retract"}));
  const PrimitiveInfo* offer = find_primitive("offer");
  names.clear();
  for (const PhaseInfo& p : offer->phases) names.emplace_back(p.name);
  EXPECT_EQ(names, (std::vector<std::string>{"reach", "hold", "hold_stable", "release", "retract"}));
  ASSERT_NE(offer->phase("hold_stable"), nullptr);
  EXPECT_TRUE(offer->phase("hold_stable")->waits);
  EXPECT_FALSE(offer->phase("reach")->waits);
  EXPECT_TRUE(find_primitive("receive")->phase("open")->waits);
  EXPECT_TRUE(find_primitive("hold_lid")->phase("hold")->waits);
  EXPECT_EQ(offer->phase("grasp"), nullptr);
}

TEST(PrimitivesTest, ParametersAreWellFormed) {
  for (const PrimitiveInfo& prim : primitive_catalog()) {
    SCOPED_TRACE(std::string(prim.name));
    EXPECT_FALSE(prim.phases.empty());
    EXPECT_FALSE(prim.summary.empty());
    std::set<std::string_view> seen;
    for (const ParamInfo& p : prim.params) {
      EXPECT_TRUE(seen.insert(p.name).second) << "duplicate " << p.name;
      EXPECT_FALSE(p.doc.empty()) << p.name;
      if (p.kind == ParamKind::kNumber) {
        EXPECT_LE(p.min, p.max) << p.name;
        EXPECT_FALSE(p.unit.empty()) << p.name;
        if (p.has_default) {
          EXPECT_GE(p.default_value, p.min) << p.name;
          EXPECT_LE(p.default_value, p.max) << p.name;
        }
      }
      if (p.kind == ParamKind::kSide || p.kind == ParamKind::kChoice) {
        ASSERT_TRUE(p.has_default) << p.name;
        bool found = false;
        for (std::string_view c : p.choices) found = found || c == p.default_choice;
        EXPECT_TRUE(found) << p.name;
      }
      if (p.required) {
        EXPECT_FALSE(p.has_default) << p.name;
      }
    }
    EXPECT_NE(prim.param("onset"), nullptr);
    EXPECT_EQ(prim.param("hand") != nullptr, prim.uses_hand);
    std::set<std::string_view> phase_names;
    for (const PhaseInfo& ph : prim.phases) EXPECT_TRUE(phase_names.insert(ph.name).second);
  }
  const ParamInfo* target = find_primitive("point")->param("target");
  ASSERT_NE(target, nullptr);
  EXPECT_EQ(target->kind, ParamKind::kPoint);
  EXPECT_TRUE(target->required);
  const ParamInfo* hold = find_primitive("point")->param("hold");
  EXPECT_EQ(hold->unit, "s");
  EXPECT_EQ(to_string(ParamKind::kZone), "zone");
}

}  // namespace
}  // namespace hribench::human

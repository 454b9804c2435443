#include "script/phases.h"

#include <gtest/gtest.h>

#include "core/errors.h"

namespace hribench::script {
namespace {

Motion motion(const std::string& primitive, const std::vector<std::pair<std::string, double>>& params) {
  Motion m;
  m.primitive = Text(primitive.c_str());
  for (const auto& [name, value] : params) {
    ValueTree v;
    v.scalar.expr = Expr::Number(value);
    m.params.push_back({name, {}, v});
  }
  return m;
}

TEST(PhasesTest, PhaseDurationsComeFromTheirParameters) {
  const auto t = phase_timing(motion("point", {{"prep", 0.3}, {"stroke", 0.5}, {"hold", 2.0}}), core::Vec3::Zero());
  ASSERT_EQ(t.size(), 4U);
  EXPECT_EQ(t[0].name, "prep");
  EXPECT_EQ(t[0].duration, 0.3);
  EXPECT_EQ(t[1].duration, 0.5);
  EXPECT_EQ(t[2].name, "hold");
  EXPECT_TRUE(t[2].waits);
  EXPECT_EQ(t[2].duration, 2.0);
  // retract not given: the catalog default.
  EXPECT_EQ(t[3].duration, human::find_primitive("point")->param("retract")->default_value);
}

TEST(PhasesTest, OfferMapsSettleAndHold) {
  const auto t = phase_timing(motion("offer", {{"duration", 1.2}, {"settle", 0.25}, {"hold", 0.5}}), core::Vec3::Zero());
  ASSERT_EQ(t.size(), 5U);
  EXPECT_EQ(t[0].name, "reach");
  EXPECT_EQ(t[0].duration, 1.2);
  EXPECT_EQ(t[1].name, "hold");
  EXPECT_EQ(t[1].duration, 0.25);
  EXPECT_EQ(t[2].name, "hold_stable");
  EXPECT_EQ(t[2].duration, 0.5);
  EXPECT_TRUE(t[2].waits);
}

TEST(PhasesTest, WalkLastsTheDistanceOverSpeed) {
  Motion m = motion("walk_to", {{"speed", 1.0}, {"turn", 0.5}});
  ValueTree to;
  to.kind = ValueTree::Kind::kList;
  for (double x : {1.5, 3.0, 0.0}) {
    ValueTree c;
    c.scalar.expr = Expr::Number(x);
    to.items.push_back(c);
  }
  m.params.push_back({"to", {}, to});
  const auto t = phase_timing(m, core::Vec3(1.5, 0.0, 0.0));
  ASSERT_EQ(t.size(), 3U);
  EXPECT_EQ(t[0].duration, 0.5);
  EXPECT_DOUBLE_EQ(t[1].duration, 3.0 / 0.75);
  EXPECT_EQ(t[2].duration, 0.5);
}

TEST(PhasesTest, ClipsPlayAndOnsetIsSeparate) {
  Motion clip;
  clip.clip = Text("walk.bvh");
  ValueTree d;
  d.scalar.expr = Expr::Number(4.0);
  clip.params.push_back({"duration", {}, d});
  const auto t = phase_timing(clip, core::Vec3::Zero());
  ASSERT_EQ(t.size(), 1U);
  EXPECT_EQ(t[0].name, "play");
  EXPECT_EQ(t[0].duration, 4.0);
  EXPECT_EQ(motion_onset(motion("go", {{"onset", 0.7}})), 0.7);
  EXPECT_EQ(motion_onset(motion("go", {})), 0.0);
  EXPECT_THROW(phase_timing(motion("wave", {}), core::Vec3::Zero()), core::InputError);
}

TEST(PhasesTest, EveryCatalogPhaseHasATiming) {
  for (const human::PrimitiveInfo& p : human::primitive_catalog()) {
    for (size_t i = 0; i < p.phases.size(); ++i) {
      if (std::string(p.name) == "walk_to" && std::string(p.phases[i].name) == "walk") continue;
      EXPECT_FALSE(phase_parameter(p, i).empty()) << p.name << "." << p.phases[i].name;
    }
  }
  EXPECT_NE(primitive_reference_markdown().find("| `offer` | reach (duration), hold (settle), hold_stable* (hold)"),
            std::string::npos);
}

}  // namespace
}  // namespace hribench::script

#include "script/sample.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <set>

#include "core/errors.h"
#include "core/json.h"
#include "script/check.h"
#include "script/schema_io.h"

namespace hribench::script {
namespace {

const char* kHandover = "tests/data/scripts/good/handover_h2r.yaml";

const Num& stand_x(const EpisodeSpec& s) { return s.human.stand.x; }

TEST(SampleTest, SameSeedGivesTheSameSpecAndHash) {
  const Scenario scenario = load_scenario(kHandover);
  const EpisodeSpec a = sample(scenario, 42);
  const EpisodeSpec b = sample(scenario, 42);
  EXPECT_EQ(a, b);
  EXPECT_EQ(spec_hash(a), spec_hash(b));
  EXPECT_EQ(spec_to_text(a), spec_to_text(b));
  EXPECT_EQ(spec_hash(a).size(), 64U);
}

// The robot is part of the spec, and so of its hash, but no draw depends on it.
TEST(SampleTest, TheRobotIsRecordedAndChangesOnlyTheHash) {
  const Scenario scenario = load_scenario(kHandover);
  const EpisodeSpec panda = sample(scenario, 42);
  EpisodeSpec other = sample(scenario, 42, "other_arm");
  EXPECT_EQ(panda.robot, "panda");
  EXPECT_EQ(other.robot, "other_arm");
  EXPECT_NE(spec_hash(panda), spec_hash(other));
  EXPECT_NE(spec_to_text(other).find("\"robot\": \"other_arm\""), std::string::npos);
  EXPECT_EQ(spec_from_text(spec_to_text(other), "spec"), other);
  other.robot = panda.robot;
  EXPECT_EQ(other, panda);
}

// Pinned across processes, builds and machines: a change here means the released episode pool
// changes (every spec drawn from the scenarios changes), so the pool's version must be bumped.
TEST(SampleTest, TheHandoverAtSeed42HasItsPinnedHash) {
  EXPECT_EQ(spec_hash(sample(load_scenario(kHandover), 42)),
            "8c6f98592583884f59081344912ca7be80f438804459cfa563de9197bd6bce4c");
}

// Distractors keep their footprint circles 2 cm clear of every other object's (the bin's
// circle is 0.15 m: the old 0.12 m centre spacing let them overlap it); those without room
// are left out and the names stay contiguous.
TEST(SampleTest, DistractorsKeepClearOfOtherObjectsByFootprint) {
  Scenario scenario = load_scenario("tasks/I1_point_pick.yaml");
  scenario.scene.distractors.count = Num(20.0);  // more than fit
  const auto radius = [](const std::string& kind) {
    if (kind == "bin") return std::hypot(0.12, 0.09);
    if (kind == "cube") return std::hypot(0.025, 0.025);
    if (kind == "cup") return 0.035;
    ADD_FAILURE() << "unexpected kind " << kind;
    return 0.0;
  };
  size_t placed = 0, left_out = 0;
  for (uint64_t seed = 0; seed < 40; ++seed) {
    const EpisodeSpec spec = sample(scenario, seed);
    size_t distractors = 0;
    for (size_t i = 0; i < spec.scene.objects.size(); ++i) {
      const Entry<SceneObject>& a = spec.scene.objects[i];
      if (a.name.rfind("distractor_", 0) != 0) continue;
      EXPECT_EQ(a.name, "distractor_" + std::to_string(++distractors));
      for (size_t j = 0; j < spec.scene.objects.size(); ++j) {
        const Entry<SceneObject>& b = spec.scene.objects[j];
        if (j == i || !b.value.pose) continue;
        const double d = std::hypot(a.value.pose->xy[0].value() - b.value.pose->xy[0].value(),
                                    a.value.pose->xy[1].value() - b.value.pose->xy[1].value());
        EXPECT_GE(d, radius(a.value.kind.value()) + radius(b.value.kind.value()) + 0.02 - 1e-12)
            << "seed " << seed << ": " << a.name << " and " << b.name;
      }
    }
    placed += distractors;
    left_out += 20 - distractors;
  }
  EXPECT_GT(placed, 40u);
  EXPECT_GT(left_out, 0u);
}

TEST(SampleTest, DifferentSeedsGiveDifferentSpecs) {
  const Scenario scenario = load_scenario(kHandover);
  std::set<std::string> hashes;
  std::set<double> heights;
  for (uint64_t seed = 0; seed < 20; ++seed) {
    const EpisodeSpec spec = sample(scenario, seed);
    hashes.insert(spec_hash(spec));
    heights.insert(spec.human.height.value());
    // Every value is resolved and inside its distribution's support.
    EXPECT_GE(spec.human.height.value(), 1.55);
    EXPECT_LT(spec.human.height.value(), 1.95);
    EXPECT_GE(spec.human.stand.yaw_deg.value(), 170.0);
    EXPECT_LE(spec.human.stand.yaw_deg.value(), 190.0);
  }
  EXPECT_EQ(hashes.size(), 20U);
  EXPECT_EQ(heights.size(), 20U);
}

TEST(SampleTest, VarsAreDrawnOnceAndShared) {
  const Scenario scenario = load_scenario(kHandover);
  std::set<std::string> hands;
  for (uint64_t seed = 0; seed < 16; ++seed) {
    const EpisodeSpec spec = sample(scenario, seed);
    ASSERT_EQ(spec.vars[0].name, "hand");
    const std::string hand = spec.vars[0].value.expr.text;
    hands.insert(hand);
    const SceneObject& item = spec.scene.objects[0].value;
    EXPECT_EQ(item.held_by->value(), "human." + hand);
    EXPECT_EQ(item.kind.value(), spec.vars[1].value.expr.text);
    EXPECT_EQ(spec.safety.contact_permitted[0].human.value(), hand + ".hand");
    // The instruction names the drawn colour and kind.
    EXPECT_EQ(spec.instruction, "Take the " + item.color->value() + " " + item.kind.value() +
                                    " from the person and put it in the bin.");
    // Distractors are drawn into the scene.
    EXPECT_LE(spec.scene.objects.size(), 4U);
    EXPECT_EQ(spec.scene.distractors.count.value(), 0.0);
  }
  EXPECT_EQ(hands.size(), 2U);
}

// Streams are split per section: the human's draws do not depend on the acts.
TEST(SampleTest, SectionsDrawFromIndependentStreams) {
  Scenario scenario = load_scenario(kHandover);
  const EpisodeSpec before = sample(scenario, 7);
  scenario.acts[0].value.onset->expr = parse_expr("U(0.1, 0.2)");
  const EpisodeSpec after = sample(scenario, 7);
  EXPECT_EQ(stand_x(before).value(), stand_x(after).value());
  EXPECT_EQ(before.human, after.human);
  EXPECT_EQ(before.scene, after.scene);
  EXPECT_NE(before.acts[0].value.onset->value(), after.acts[0].value.onset->value());
}

TEST(SampleTest, JsonRoundTripIsExact) {
  const Scenario scenario = load_scenario(kHandover);
  for (uint64_t seed = 100; seed < 110; ++seed) {
    const EpisodeSpec spec = sample(scenario, seed);
    const std::string text = spec_to_text(spec);
    const EpisodeSpec back = spec_from_text(text, "spec.json");
    EXPECT_EQ(back, spec);
    EXPECT_EQ(spec_hash(back), spec_hash(spec));
    EXPECT_EQ(spec_to_text(back), text);
    // Doubles bit for bit.
    const double a = spec.human.height.value(), b = back.human.height.value();
    EXPECT_EQ(std::memcmp(&a, &b, sizeof a), 0);
  }
}

TEST(SampleTest, HashChangesWithAnyValue) {
  const EpisodeSpec spec = sample(load_scenario(kHandover), 3);
  EpisodeSpec changed = spec;
  changed.human.height = Num(std::nextafter(spec.human.height.value(), 3.0));
  EXPECT_NE(spec_hash(changed), spec_hash(spec));
}

TEST(SampleTest, MalformedSpecJsonNamesThePath) {
  const EpisodeSpec spec = sample(load_scenario(kHandover), 3);
  core::Json j = to_json(spec);
  j["human"]["height"] = "tall";
  try {
    episode_from_json(j, "spec.json");
    FAIL() << "no error";
  } catch (const core::InputError& e) {
    EXPECT_EQ(e.where(), "spec.json (human.height)");
  }
  j = to_json(spec);
  j["acts"][0]["colour"] = 1;
  EXPECT_THROW(episode_from_json(j, "spec.json"), core::InputError);
  j = to_json(spec);
  j.erase("seed");
  EXPECT_THROW(episode_from_json(j, "spec.json"), core::InputError);
}

}  // namespace
}  // namespace hribench::script

#include "eval/script_driver.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "core/errors.h"
#include "eval/runner.h"
#include "model/model.h"
#include "policy/builtin.h"
#include "script/check.h"
#include "script/sample.h"
#include "sim/data.h"
#include "support/mujoco_fixture.h"

namespace hribench::eval {
namespace {

class ScriptDriverTest : public hribench::testing::MujocoTest {
 protected:
  static script::EpisodeSpec stop_go_spec() {
    return script::sample(script::load_scenario("tests/data/scripts/good/stop_go.yaml"), 1);
  }
  EpisodeLog run(const script::EpisodeSpec& spec, const model::Model& model, double horizon = 4.0) {
    sim::Data data = sim::make_data(model);
    ScriptDriver driver(spec);
    policy::NoopPolicy noop;
    RunOptions options;
    options.horizon = horizon;
    EpisodeSetup setup;
    setup.task = spec.task;
    setup.role = spec.role;
    setup.seed = spec.seed;
    setup.policy = "noop";
    EpisodeLog log = run_episode(model, data, noop, driver, setup, options);
    ExpectNoWarnings(data.mj.get());
    return log;
  }
  // Samples a script at seed 1, builds its model and runs a noop episode.
  EpisodeLog run_script(const std::string& path, double horizon) {
    const script::EpisodeSpec spec = script::sample(script::load_scenario(path), 1);
    const model::Model model = model::build(scene_spec_from_episode(spec));
    return run(spec, model, horizon);
  }
};

TEST_F(ScriptDriverTest, SceneSpecCarriesObjectsAndHuman) {
  const script::EpisodeSpec spec = stop_go_spec();
  const model::SceneSpec scene = scene_spec_from_episode(spec);
  ASSERT_EQ(scene.objects.size(), spec.scene.objects.size());
  EXPECT_EQ(scene.objects[0].name, "cube");
  EXPECT_EQ(scene.objects[0].kind, "cube");
  EXPECT_DOUBLE_EQ(scene.objects[0].x, spec.scene.objects[0].value.pose->xy[0].value());
  EXPECT_DOUBLE_EQ(scene.human.height, spec.human.height.value());
  EXPECT_NEAR(scene.human.yaw, spec.human.stand.yaw_deg.value() * core::kPi / 180, 1e-12);
}

TEST_F(ScriptDriverTest, GrayBecomesGreyAndPlatformsAreRefused) {
  script::EpisodeSpec spec = stop_go_spec();
  spec.scene.objects[1].value.color = script::Text("gray");
  EXPECT_EQ(scene_spec_from_episode(spec).objects[1].colour, "grey");
  spec.scene.objects[0].value.kind = script::Text("platform");
  try {
    scene_spec_from_episode(spec);
    FAIL() << "a platform object was accepted";
  } catch (const core::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("scene.objects.cube"), std::string::npos) << e.what();
  }
}

TEST_F(ScriptDriverTest, NoopEpisodeMovesTheHumanOnScheduleDeterministically) {
  const script::EpisodeSpec spec = stop_go_spec();
  const model::Model model = model::build(scene_spec_from_episode(spec));
  const EpisodeLog log = run(spec, model);
  ASSERT_EQ(log.status, core::EpisodeStatus::kOk) << log.status_reason;
  ASSERT_FALSE(log.steps.empty());

  // The first act starts at its sampled onset.
  const double onset = spec.acts[0].value.onset->value();
  ASSERT_LT(onset, 3.0);
  const std::optional<double> start = log.event_time("go.start");
  ASSERT_TRUE(start.has_value());
  EXPECT_NEAR(*start, onset, log.control_dt);
  bool logged_as_act_start = false;
  for (const Event& e : log.events) {
    if (e.name == "go.start") logged_as_act_start = e.kind == EventKind::kActStart && e.actor == Actor::kHuman;
  }
  EXPECT_TRUE(logged_as_act_start);

  // The gesturing wrist moved after the onset, not before.
  const size_t wrist = static_cast<size_t>(spec.human.handedness.value() == "left"
                                               ? human::Joint::kLeftWrist
                                               : human::Joint::kRightWrist);
  const core::Vec3 first = log.steps.front().human_joints_W[wrist];
  double moved_before = 0, moved_after = 0;
  for (const StepRecord& s : log.steps) {
    const double d = (s.human_joints_W[wrist] - first).norm();
    if (s.time < onset - 1e-9) moved_before = std::max(moved_before, d);
    else moved_after = std::max(moved_after, d);
  }
  EXPECT_LT(moved_before, 1e-9);
  EXPECT_GT(moved_after, 0.10);

  // Deterministic: a second run gives the same log.
  const EpisodeLog again = run(spec, model);
  EXPECT_EQ(again.events, log.events);
  ASSERT_EQ(again.steps.size(), log.steps.size());
  for (size_t i = 0; i < log.steps.size(); ++i) {
    EXPECT_EQ(again.steps[i].time, log.steps[i].time);
    EXPECT_EQ(again.steps[i].human_joints_W, log.steps[i].human_joints_W) << i;
    EXPECT_EQ(again.steps[i].predicates, log.steps[i].predicates) << i;
    ASSERT_EQ(again.steps[i].object_poses.size(), log.steps[i].object_poses.size());
    for (size_t o = 0; o < log.steps[i].object_poses.size(); ++o) {
      EXPECT_EQ(again.steps[i].object_poses[o].translation, log.steps[i].object_poses[o].translation);
    }
  }
}

// The demonstrator's motion labels grasp and release a real object: the human's demo act
// puts inst_a into cont_1 by hand (hold springs, not teleporting).
TEST_F(ScriptDriverTest, HumanDemoPlacesTheObjectThroughHandHolds) {
  const EpisodeLog log = run_script("tasks/I3_demo_imitate.yaml", 7.0);
  ASSERT_EQ(log.status, core::EpisodeStatus::kOk) << log.status_reason;
  const std::optional<double> release = log.event_time("demo.release");
  ASSERT_TRUE(release.has_value());
  bool placed = false;
  for (const Event& e : log.events) {
    if (e.kind == EventKind::kPredicateChange && e.name == "in(inst_a, cont_1)" && e.detail == "true") {
      placed = true;
      EXPECT_GE(e.time, *release);
    }
  }
  EXPECT_TRUE(placed);
}

// A superseding act (give_up after an unanswered offer) keeps the offered item in the hand.
TEST_F(ScriptDriverTest, GivingUpKeepsTheOfferedItem) {
  const EpisodeLog log = run_script("tests/data/scripts/good/handover_h2r.yaml", 10.0);
  ASSERT_EQ(log.status, core::EpisodeStatus::kOk) << log.status_reason;
  ASSERT_TRUE(log.event_time("give_up.end").has_value());
  for (const Event& e : log.events) {
    EXPECT_FALSE(e.kind == EventKind::kPredicateChange && e.name == "not dropped(item)" &&
                 e.detail == "false")
        << "dropped at " << e.time;
  }
}

}  // namespace
}  // namespace hribench::eval

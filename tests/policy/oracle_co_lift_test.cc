// The co-carry skill (policy/oracle_co_lift.cc) without physics: C4's robot acts become
// co-carry steps, and on hand-built observations the expert grips the robot's end of the plank,
// waits for the lift cue, keeps its end level with the person's, lets go with the person, while
// blind lifts on its own.

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "human/skeleton.h"
#include "policy/oracle.h"
#include "policy/oracle_plan.h"
#include "script/check.h"
#include "script/sample.h"

namespace hribench::policy {
namespace {

using core::Pose;
using core::Vec3;

constexpr const char* kTask = "tasks/C4_co_lift.yaml";

std::shared_ptr<script::EpisodeSpec> c4_episode() {
  return std::make_shared<script::EpisodeSpec>(script::sample(script::load_scenario(kTask), 0));
}

TEST(CoCarryPlan, EveryRobotActOnTheLiftedPlankIsACoCarryStepOntoThePlatform) {
  const auto spec = c4_episode();
  const std::vector<std::string> acts = {"hold_end", "lift_end", "follow", "lower_end"};
  const std::vector<std::string> afters = {"", "hlift.prep", "carry.start", "put_down.start"};
  for (Competence c : {Competence::kOracle, Competence::kReactive, Competence::kBlind}) {
    const std::vector<PlanStep> plan = make_plan(*spec, c);
    ASSERT_EQ(plan.size(), acts.size()) << to_string(c);
    for (size_t i = 0; i < plan.size(); ++i) {
      EXPECT_EQ(plan[i].act, acts[i]);
      EXPECT_EQ(plan[i].kind, StepKind::kCoCarry) << acts[i];
      EXPECT_EQ(plan[i].object, "plank");
      EXPECT_EQ(plan[i].target, "platform") << acts[i];
      EXPECT_EQ(plan[i].after, c == Competence::kBlind ? "" : afters[i]) << to_string(c) << " " << acts[i];
    }
  }
  EXPECT_EQ(to_string(StepKind::kCoCarry), "co_carry");
}

TEST(CoCarryPlan, AnObjectThePersonDoesNotLiftIsPickedAndPlacedAsUsual) {
  const script::EpisodeSpec spec = script::sample(script::load_scenario("tasks/I1_point_pick.yaml"), 0);
  for (const PlanStep& step : make_plan(spec, Competence::kOracle)) EXPECT_NE(step.kind, StepKind::kCoCarry);
}

// A hand-built C4 world: the plank lying on its support (or its person's end raised by `raise`
// metres, pivoting about the robot's grip), the person standing at the far end, the TCP at the
// robot's grip point with the given gripper width.
struct Scene {
  const script::EpisodeSpec& spec;
  std::vector<ScriptEvent> events;

  double plank_y() const {
    for (const auto& e : spec.scene.objects) {
      if (e.name == "plank") return e.value.pose->xy[1].value();
    }
    return 0;
  }
  // The robot's grip: 2.5 cm in from the plank's robot end, at its mid-height.
  Vec3 grip() const { return Vec3(0.62 - 0.275, plank_y(), 0.83 + 0.02); }

  Observation observe(double time, const Vec3& tcp, double width, double raise) const {
    Observation obs;
    obs.time = time;
    obs.events = events;
    obs.proprio.gripper_width = width;
    obs.proprio.X_WT.translation = tcp;
    obs.proprio.X_WT.rotation = core::axis_angle(Vec3::UnitX(), core::kPi);
    StateObservation state;
    const double pitch = std::asin(raise / 0.545);
    for (const auto& entry : spec.scene.objects) {
      ObjectPose pose{entry.name, Pose::Identity()};
      const Vec3 xy(entry.value.pose->xy[0].value(), entry.value.pose->xy[1].value(), 0.75);
      pose.X_WO.translation = xy;
      if (entry.name == "plank") {
        // Rotating about -y raises the +x (person's) end; the robot's grip stays where it is.
        pose.X_WO.rotation = core::axis_angle(-Vec3::UnitY(), pitch);
        pose.X_WO.translation = grip() - pose.X_WO.rotation * Vec3(-0.275, 0, 0.02);
      }
      if (entry.value.kind.value() == "platform") continue;  // fixed: the expert knows them
      state.objects.push_back(pose);
    }
    for (size_t j = 0; j < state.human_joints_W.size(); ++j) state.human_joints_W[j] = Vec3(1.1, plank_y(), 1.2);
    state.human_joints_W[static_cast<size_t>(human::index(human::Joint::kPelvis))] = Vec3(1.25, plank_y(), 1.0);
    obs.state = state;
    return obs;
  }
  void add(const std::string& kind, const std::string& name, double time) { events.push_back({time, kind, name, ""}); }
};

Vec3 translation(const ActionChunk& chunk) {
  return Vec3(chunk.actions.at(0)[0], chunk.actions.at(0)[1], chunk.actions.at(0)[2]);
}

// Runs the grasp of the robot's end with the TCP put where the expert asks (above the grip,
// then at it) and the fingers closing on the 6 cm plank; returns the time reached.
double grasp_end(ExpertPolicy& policy, Scene& scene) {
  double t = 0.05;
  const Vec3 above = scene.grip() + Vec3(0, 0, 0.05);
  policy.act(scene.observe(t, above, 0.08, 0));
  t += 0.05;
  policy.act(scene.observe(t, scene.grip(), 0.08, 0));
  scene.add("act_end", "hold_end.end", t + 0.5);
  for (int k = 0; k < 70; ++k) {
    t += 0.05;
    const ActionChunk chunk = policy.act(scene.observe(t, scene.grip(), 0.058, 0));
    validate_chunk(chunk, ActionSpace::kEeDelta, ActionLimits{});
  }
  return t;
}

// The expert of a competence, reset on the C4 episode of seed 0, and its hand-built scene.
struct CoLift {
  explicit CoLift(Competence competence) : spec(c4_episode()), policy(competence), scene{*spec, {}} {
    EpisodeInfo info;
    info.episode = spec;
    policy.reset(info);
  }
  std::shared_ptr<script::EpisodeSpec> spec;
  ExpertPolicy policy;
  Scene scene;
};

TEST(CoCarrySkill, GripsTheRobotsEndAndWaitsStillForTheLiftCue) {
  CoLift c4(Competence::kOracle);
  ExpertPolicy& oracle = c4.policy;
  Scene& scene = c4.scene;
  // From home: toward the point above the robot's end (x 0.345), not the plank's centre.
  const ActionChunk first = oracle.act(scene.observe(0.0, Vec3(0.55, 0, 1.27), 0.08, 0));
  EXPECT_LT(translation(first).x(), -1e-3);
  double t = grasp_end(oracle, scene);
  // Gripped, the person's end already rising a little (no cue yet): the oracle holds still.
  const ActionChunk waiting = oracle.act(scene.observe(t + 0.05, scene.grip(), 0.058, 0.02));
  EXPECT_LT(translation(waiting).norm(), 1e-6);
  EXPECT_DOUBLE_EQ(waiting.actions[0][6], 0.0);  // full grip
  EXPECT_EQ(oracle.current_step(), 0u);
}

TEST(CoCarrySkill, AfterTheCueKeepsItsEndLevelWithThePersonsAndLetsGoWithThem) {
  CoLift c4(Competence::kOracle);
  ExpertPolicy& oracle = c4.policy;
  Scene& scene = c4.scene;
  double t = grasp_end(oracle, scene);
  scene.add("cue", "hlift.prep", t);
  scene.add("phase", "hlift.prep", t);
  // Level: stays. The person's end 2 cm up: the robot's end rises 2 cm in this control step.
  t += 0.05;
  EXPECT_LT(translation(oracle.act(scene.observe(t, scene.grip(), 0.058, 0))).norm(), 1e-3);
  t += 0.05;
  const Vec3 up = translation(oracle.act(scene.observe(t, scene.grip(), 0.058, 0.02)));
  EXPECT_NEAR(up.z(), 0.02, 0.002);
  EXPECT_NEAR(up.head<2>().norm(), 0.0, 0.002);
  EXPECT_EQ(oracle.current_step(), 1u);  // lift_end
  // The person lowers it onto the platform and opens the hands: the robot opens too.
  for (const char* e : {"lift_end.end", "follow.end"}) scene.add("act_end", e, t);
  for (const char* e : {"carry.start", "put_down.start"}) scene.add("act_start", e, t);
  for (int k = 0; k < 3; ++k) {  // one step ends per control step
    t += 0.05;
    EXPECT_DOUBLE_EQ(oracle.act(scene.observe(t, scene.grip(), 0.058, 0)).actions[0][6], 0.0);
  }
  EXPECT_EQ(oracle.current_step(), 3u);  // lower_end
  scene.add("phase", "put_down.release", t);
  t += 0.05;
  EXPECT_DOUBLE_EQ(oracle.act(scene.observe(t, scene.grip(), 0.058, 0)).actions[0][6], 1.0);
}

TEST(CoCarrySkill, BlindLiftsRightAfterGrippingWhateverThePersonDoes) {
  CoLift c4(Competence::kBlind);
  ExpertPolicy& blind = c4.policy;
  Scene& scene = c4.scene;
  const double t = grasp_end(blind, scene);
  const Vec3 up = translation(blind.act(scene.observe(t + 0.05, scene.grip(), 0.058, 0)));
  EXPECT_GT(up.z(), 1e-3);
  EXPECT_EQ(blind.current_step(), 1u);
}

}  // namespace
}  // namespace hribench::policy

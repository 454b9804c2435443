// The expert's handover skills without physics (oracle_handover.cc): taking an object a person
// holds out (C1), on hand-built observations whose TCP follows the commanded deltas exactly.

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "human/skeleton.h"
#include "policy/oracle.h"
#include "script/check.h"
#include "script/sample.h"

namespace hribench::policy {
namespace {

using core::Vec3;

// C1 seed 0, the offered object held still at `object` (its body frame: bottom centre), the
// person's joints at the far edge, the offering wrist beside the object, the head at `head`.
struct TakeScene {
  std::shared_ptr<script::EpisodeSpec> spec;
  Vec3 object = Vec3(0.62, -0.05, 1.00);
  Vec3 head = Vec3(1.25, 0, 1.65);
  Vec3 tcp = Vec3(0.55, 0, 1.27);
  // Both wrists here (elbows 0.2 m further from the robot) instead of beside the object.
  std::optional<Vec3> wrists;
  // The offered object's yaw (rad); with `turn`, the gripper turns as commanded (else it stays
  // at its start rotation).
  double object_yaw = 0;
  bool turn = false;
  core::Quat rotation = core::axis_angle(Vec3::UnitX(), core::kPi);
  std::vector<ScriptEvent> events;

  explicit TakeScene(uint64_t seed = 0) {
    spec = std::make_shared<script::EpisodeSpec>(
        script::sample(script::load_scenario("tasks/C1_handover_h2r.yaml"), seed));
  }
  EpisodeInfo info() const {
    EpisodeInfo i;
    i.task = spec->task;
    i.episode = spec;
    i.horizon = spec->horizon;
    return i;
  }
  Observation observation(double time) const {
    Observation obs;
    obs.time = time;
    obs.proprio.gripper_width = 0.08;
    obs.proprio.X_WT.translation = tcp;
    obs.proprio.X_WT.rotation = rotation;
    StateObservation state;
    for (const auto& entry : spec->scene.objects) {
      ObjectPose pose{entry.name, core::Pose::Identity()};
      pose.X_WO.translation = entry.name == "item" ? object : Vec3(0.35, 0.30, 0.75);
      if (entry.name == "item") pose.X_WO.rotation = core::axis_angle(Vec3::UnitZ(), object_yaw);
      state.objects.push_back(pose);
    }
    for (size_t j = 0; j < state.human_joints_W.size(); ++j) state.human_joints_W[j] = Vec3(1.3, 0, 1.0);
    // The offering forearm reaches toward the object from the person's side.
    for (const human::Joint wrist : {human::Joint::kLeftWrist, human::Joint::kRightWrist}) {
      state.human_joints_W[static_cast<size_t>(human::index(wrist))] = object + Vec3(0.05, 0.07, 0.05);
    }
    if (wrists) {
      for (const human::Side side : {human::Side::kLeft, human::Side::kRight}) {
        state.human_joints_W[static_cast<size_t>(human::index(human::wrist(side)))] = *wrists;
        state.human_joints_W[static_cast<size_t>(human::index(human::elbow(side)))] = *wrists + Vec3(0.2, 0, 0);
      }
    }
    state.human_joints_W[static_cast<size_t>(human::index(human::Joint::kHead))] = head;
    obs.state = state;
    obs.events = events;
    return obs;
  }
  // Runs `steps` control steps from `time`, moving the TCP by each commanded delta; returns the
  // last action.
  Action run(ExpertPolicy& policy, double& time, int steps) {
    Action last;
    for (int k = 0; k < steps; ++k) {
      time += 0.05;
      const ActionChunk chunk = policy.act(observation(time));
      validate_chunk(chunk, ActionSpace::kEeDelta, ActionLimits{});
      last = chunk.actions[0];
      tcp += Vec3(last[0], last[1], last[2]);
      const Vec3 turned(last[3], last[4], last[5]);
      if (turn && turned.norm() > 1e-9) rotation = (core::axis_angle(turned.normalized(), turned.norm()) * rotation).normalized();
    }
    return last;
  }
};

double horizontal(const Vec3& v) { return v.head<2>().norm(); }

// The centre of the zone of `spec`'s offer act (where the person holds the object out).
Vec3 offer_zone(const script::EpisodeSpec& spec) {
  for (const auto& act : spec.acts) {
    if (act.name != "offer" || !act.value.motion) continue;
    for (const auto& param : act.value.motion->params) {
      if (param.name != "zone") continue;
      for (size_t i = 0; i < param.value.keys.size(); ++i) {
        const script::ValueTree& c = param.value.items[i];
        if (param.value.keys[i] == "center" && c.items.size() == 3) {
          return Vec3(c.items[0].scalar.expr.number, c.items[1].scalar.expr.number, c.items[2].scalar.expr.number);
        }
      }
    }
  }
  ADD_FAILURE() << "no offer zone";
  return Vec3::Zero();
}

TEST(HandoverTake, WaitsShortOfTheObjectWhileThePersonReachesThenComesInAndCloses) {
  TakeScene scene;
  ExpertPolicy oracle(Competence::kOracle);
  oracle.reset(scene.info());
  double time = 0;
  scene.events.push_back({0.5, "act_start", "offer.start", ""});
  Action last = scene.run(oracle, time, 80);
  // Short of where the object will be held (the offer's zone: the object on its way there may
  // pass under a head leaning in) on the robot's side, open, not moving any more.
  const Vec3 zone = offer_zone(*scene.spec);
  EXPECT_NEAR(horizontal(zone - scene.tcp), 0.30, 0.03);
  EXPECT_LT(scene.tcp.x(), zone.x());
  EXPECT_DOUBLE_EQ(last[6], 1.0);
  EXPECT_LT(Vec3(last[0], last[1], last[2]).norm(), 1e-3);

  // Held still: over the grasp point, down to it, then the fingers close.
  scene.events.push_back({time, "phase", "offer.hold", ""});
  last = scene.run(oracle, time, 120);
  EXPECT_LT(horizontal(scene.object - scene.tcp), 0.01);
  EXPECT_GT(scene.tcp.z(), scene.object.z());
  EXPECT_LT(scene.tcp.z(), scene.object.z() + 0.20);
  EXPECT_LT(last[6], 0.95);
}

TEST(HandoverTake, BacksOffFromAHeadLeaningInOverTheObject) {
  TakeScene scene;
  ExpertPolicy oracle(Competence::kOracle);
  oracle.reset(scene.info());
  double time = 0;
  scene.events.push_back({0.5, "act_start", "offer.start", ""});
  scene.events.push_back({0.6, "phase", "offer.hold", ""});
  scene.run(oracle, time, 15);
  // The head comes down right in front of the hand.
  scene.head = scene.tcp + Vec3(0.12, 0, 0.10);
  const double before = (scene.tcp - scene.head).norm();
  scene.run(oracle, time, 10);
  EXPECT_GT((scene.tcp - scene.head).norm(), before + 0.03);
}

TEST(HandoverTake, OnceThePersonLetsGoBacksTowardItsBaseBeforePlacingThoughThePersonStaysClose) {
  TakeScene scene;
  ExpertPolicy oracle(Competence::kOracle);
  oracle.reset(scene.info());
  double time = 0;
  scene.events.push_back({0.5, "act_start", "offer.start", ""});
  scene.events.push_back({0.6, "phase", "offer.hold", ""});
  scene.run(oracle, time, 200);  // taken: closed on it
  ASSERT_LT(horizontal(scene.object - scene.tcp), 0.01);
  // The person lets go and keeps the hand 0.38 m in front of the TCP (inside the
  // speed-and-separation stop band, outside its back-off distance).
  scene.wrists = scene.tcp + Vec3(0.46, 0, 0);
  scene.events.push_back({time, "phase", "offer.release", ""});
  const Vec3 before = scene.tcp;
  const Action last = scene.run(oracle, time, 30);
  EXPECT_LT(horizontal(scene.tcp), horizontal(before) - 0.05);  // back toward the base
  EXPECT_LT(scene.tcp.z(), before.z());                          // and a little lower
  EXPECT_LT(last[6], 0.5);                                      // still gripping
}

TEST(HandoverTake, BlindComesStraightInWithoutWaitingForTheHold) {
  TakeScene scene;
  ExpertPolicy blind(Competence::kBlind);
  blind.reset(scene.info());
  double time = 0;
  scene.run(blind, time, 120);  // no events at all
  EXPECT_LT(horizontal(scene.object - scene.tcp), 0.01);
}

TEST(HandoverTake, ReactiveWaitsShortOfTheObjectItselfNotOfTheZone) {
  TakeScene scene;
  ExpertPolicy reactive(Competence::kReactive);
  reactive.reset(scene.info());
  double time = 0;
  scene.events.push_back({0.5, "act_start", "offer.start", ""});
  scene.run(reactive, time, 80);
  EXPECT_NEAR(horizontal(scene.object - scene.tcp), 0.30, 0.03);
  EXPECT_GT(horizontal(offer_zone(*scene.spec) - scene.tcp), 0.30 + 0.01);
}

TEST(HandoverTake, ClosesTheFingersAlongTheHandHoldingTheObject) {
  TakeScene scene(48194801322540);  // a cup
  for (const auto& entry : scene.spec->scene.objects) {
    if (entry.name == "item") {
      ASSERT_EQ(entry.value.kind.value(), "cup");
    }
  }
  // The object as a hand holds it from the start: its x axis along the hand (here turned 30
  // degrees from the robot's -x), its centre 0.09 m beyond the wrist along it and 0.074 m
  // beside it.
  const Vec3 along(-std::cos(0.5), -std::sin(0.5), 0);
  const Vec3 beside(-along.y(), along.x(), 0);
  scene.object_yaw = std::atan2(along.y(), along.x());
  scene.turn = true;
  scene.wrists = scene.object + Vec3(0, 0, 0.045) - 0.09 * along - 0.074 * beside;
  ExpertPolicy oracle(Competence::kOracle);
  oracle.reset(scene.info());
  double time = 0;
  scene.events.push_back({0.5, "act_start", "offer.start", ""});
  scene.events.push_back({0.6, "phase", "offer.hold", ""});
  scene.run(oracle, time, 120);
  const Vec3 fingers = scene.rotation * Vec3::UnitY();
  EXPECT_GT(std::abs(fingers.dot(along)), 0.98);
}

}  // namespace
}  // namespace hribench::policy

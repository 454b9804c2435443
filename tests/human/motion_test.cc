#include "human/motion.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <fmt/format.h>

#include <array>
#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "core/errors.h"
#include "core/rng.h"
#include "human/arm_ik.h"
#include "human/labels.h"

namespace hribench::human {
namespace {

using core::Vec3;

// Scene convention (docs/tasks.md): the person stands at the far edge of the table (x = 1.5) facing
// the robot (-x); the table top is at 0.75 m.
constexpr double kStandX = 1.5;
const Vec3 kObject(1.05, 0.12, 0.82);

SkeletonPose standing(const Skeleton& k) { return SkeletonPose::Standing(k, kStandX, 0, core::kPi); }

// Parameters that make every primitive well-defined in the scene above.
PrimitiveParams example(const std::string& name, const std::string& hand = "right") {
  PrimitiveParams p;
  p.primitive = name;
  const PrimitiveInfo* info = find_primitive(name);
  if (info != nullptr && info->uses_hand) p.choices["hand"] = hand;
  if (name == "walk_to") p.points["to"] = Vec3(1.5, 0.8, 0);
  if (name == "reach" || name == "pick" || name == "place") p.points["target"] = kObject;
  if (name == "point") p.points["target"] = Vec3(0.5, -0.3, 0.8);
  if (name == "offer" || name == "receive") p.zones["zone"] = {Vec3(1.05, 0.05, 1.05), 0.05};
  if (name == "move_object") {
    p.points["from"] = kObject;
    p.points["to"] = Vec3(1.0, -0.2, 0.8);
  }
  if (name == "hold_lid") {
    p.points["handle"] = Vec3(1.15, 0, 0.95);
    p.points["hinge"] = Vec3(0.9, 0, 0.95);
  }
  if (name == "intrude") p.points["target"] = Vec3(0.9, 0.0, 0.95);
  if (name == "lift") p.points["target"] = Vec3(1.15, 0, 0.80);
  if (name == "carry") p.points["to"] = Vec3(1.6, 0.6, 0.95);
  if (name == "offer" || name == "receive" || name == "pick" || name == "place" ||
      name == "move_object" || name == "lift" || name == "carry" || name == "lower") {
    p.objects["object"] = "item";
  }
  return p;
}

// The catalog parameter that sets a phase's duration (empty: derived, e.g. walk).
std::string timing_param(const std::string& prim, const std::string& phase) {
  if (prim == "walk_to") return phase == "walk" ? "" : "turn";
  if (prim == "offer" && phase == "hold") return "settle";
  if (prim == "offer" && phase == "hold_stable") return "hold";
  if (prim == "reach" && phase == "hold") return "dwell";
  const PrimitiveInfo* info = find_primitive(prim);
  if (info->param(phase) != nullptr && info->param(phase)->kind == ParamKind::kNumber) return phase;
  return "duration";
}

Vec3 palm_of(const Clip& clip, size_t frame, Side side) {
  return hand_point(clip.skeleton, clip.frames[frame], side, HandPoint::kPalm);
}

TEST(MotionTest, EveryPrimitiveHasItsPhasesWithTheRequestedTiming) {
  core::Rng rng(7);
  const Skeleton k = Skeleton::FromHeight(1.72);
  for (const PrimitiveInfo& prim : primitive_catalog()) {
    SCOPED_TRACE(std::string(prim.name));
    PrimitiveParams p = example(std::string(prim.name));
    p.numbers["onset"] = 0.7;
    std::map<std::string, double> requested;
    for (const PhaseInfo& phase : prim.phases) {
      const std::string param = timing_param(std::string(prim.name), std::string(phase.name));
      if (param.empty()) continue;
      const ParamInfo* info = prim.param(param);
      ASSERT_NE(info, nullptr) << param;
      const double lo = std::max(info->min, 0.1);
      const double value = p.numbers.count(param) ? p.numbers[param]
                                                  : std::round(rng.uniform(lo, std::min(info->max, 2.5)) * 100) / 100;
      p.numbers[param] = value;
      requested[std::string(phase.name)] = value;
    }
    const LabelledClip lc = generate_clip(k, standing(k), p, 30);
    ASSERT_EQ(lc.clip.phases.size(), prim.phases.size());
    double t = 0.7;
    for (size_t i = 0; i < prim.phases.size(); ++i) {
      const Phase& ph = lc.clip.phases[i];
      EXPECT_EQ(ph.name, prim.phases[i].name);
      EXPECT_NEAR(ph.start, t, 1e-9) << ph.name;
      if (requested.count(ph.name)) {
        EXPECT_NEAR(ph.end - ph.start, requested[ph.name], 1e-9) << ph.name;
      }
      t = ph.end;
    }
    EXPECT_GE(lc.clip.duration(), t - 1e-9);
    EXPECT_LT(lc.clip.duration(), t + 1.0 / 30);
    EXPECT_EQ(lc.labels.size(), lc.clip.frames.size());
    EXPECT_EQ(lc.clip.active_hand.has_value(), prim.uses_hand);
  }
}

TEST(MotionTest, EveryPrimitiveKeepsBonesLimitsAndBodyIntactForBothHandsAndAllHeights) {
  for (const double height : {1.55, 1.75, 1.95}) {
    const Skeleton k = Skeleton::FromHeight(height);
    for (const PrimitiveInfo& prim : primitive_catalog()) {
      for (const std::string hand : {"left", "right"}) {
        SCOPED_TRACE(std::string(prim.name) + " " + hand + " " + std::to_string(height));
        const LabelledClip lc = generate_clip(k, standing(k), example(std::string(prim.name), hand), 20);
        const CheckResult bones = check_bone_lengths(lc.clip, 1e-9);
        EXPECT_TRUE(bones.ok) << bones.message;
        const CheckResult limits = check_clip_joint_limits(lc.clip);
        EXPECT_TRUE(limits.ok) << limits.message;
        const CheckResult body = check_self_penetration(lc.clip);
        EXPECT_TRUE(body.ok) << body.message;
        // One foot stays on the floor; the ankle of a swinging leg rises less than 15 cm.
        for (const SkeletonPose& pose : lc.clip.frames) {
          const auto X = forward_kinematics(k, pose);
          const double l = X[index(Joint::kLeftAnkle)].translation.z() - 0.06 * k.scale;
          const double r = X[index(Joint::kRightAnkle)].translation.z() - 0.06 * k.scale;
          EXPECT_NEAR(std::min(l, r), 0, 0.01);
          EXPECT_LT(std::max(l, r), 0.15);
        }
      }
    }
  }
}

TEST(MotionTest, ReachFollowsABellShapedMinJerkSpeedProfile) {
  const Skeleton k = Skeleton::FromHeight(1.75);
  // Start with the hand already raised, so the reach is one straight min-jerk segment.
  PrimitiveParams first = example("reach");
  first.points["target"] = Vec3(1.15, -0.05, 1.05);
  const MotionPlan raise = plan_motion(k, standing(k), first);
  const SkeletonPose start = raise.pose_at(raise.nominal_duration());
  PrimitiveParams p = example("reach");
  p.points["target"] = Vec3(1.0, 0.2, 0.95);
  p.numbers["duration"] = 0.8;
  const double fps = 200;
  const LabelledClip lc = generate_clip(k, start, p, fps);
  const Phase* reach = lc.clip.phase("reach");
  ASSERT_NE(reach, nullptr);
  const auto f0 = static_cast<size_t>(std::round(reach->start * fps));
  const auto f1 = static_cast<size_t>(std::round(reach->end * fps));
  const double amplitude = (palm_of(lc.clip, f1, Side::kRight) - palm_of(lc.clip, f0, Side::kRight)).norm();
  EXPECT_GT(amplitude, 0.2);
  std::vector<double> speed;
  for (size_t f = f0; f < f1; ++f) {
    speed.push_back((palm_of(lc.clip, f + 1, Side::kRight) - palm_of(lc.clip, f, Side::kRight)).norm() * fps);
  }
  const auto peak = static_cast<size_t>(std::max_element(speed.begin(), speed.end()) - speed.begin());
  // Peak 1.875 A / T at mid-time; single-peaked (rises, then falls).
  EXPECT_NEAR(speed[peak], 1.875 * amplitude / 0.8, 0.02 * 1.875 * amplitude / 0.8);
  EXPECT_NEAR((static_cast<double>(peak) + 0.5) / fps, 0.4, 1.0 / fps);
  for (size_t i = 1; i <= peak; ++i) EXPECT_GE(speed[i], speed[i - 1] - 1e-9) << i;
  for (size_t i = peak + 1; i < speed.size(); ++i) EXPECT_LE(speed[i], speed[i - 1] + 1e-9) << i;
  EXPECT_LT(speed.front(), 0.01);
  EXPECT_LT(speed.back(), 0.01);
}

TEST(MotionTest, PointingStrokeHasALongerDecelerationTail) {
  const Skeleton k = Skeleton::FromHeight(1.75);
  PrimitiveParams p = example("point");
  p.numbers["stroke"] = 1.0;
  p.numbers["decel"] = 0.7;
  const double fps = 200;
  const LabelledClip lc = generate_clip(k, standing(k), p, fps);
  const Phase* stroke = lc.clip.phase("stroke");
  const auto f0 = static_cast<size_t>(std::round(stroke->start * fps));
  const auto f1 = static_cast<size_t>(std::round(stroke->end * fps));
  double best = 0;
  size_t peak = f0;
  for (size_t f = f0; f < f1; ++f) {
    const double v = (palm_of(lc.clip, f + 1, Side::kRight) - palm_of(lc.clip, f, Side::kRight)).norm();
    if (v > best) {
      best = v;
      peak = f;
    }
  }
  // Peak at 1 - decel = 30 % of the stroke.
  EXPECT_NEAR((static_cast<double>(peak - f0) + 0.5) / fps, 0.3, 2.0 / fps);
}

TEST(MotionTest, PointingRayPassesThroughTheTargetDuringTheHold) {
  for (const double height : {1.55, 1.95}) {
    const Skeleton k = Skeleton::FromHeight(height);
    for (const std::string hand : {"left", "right"}) {
      for (const Vec3& target : {Vec3(0.5, -0.3, 0.8), Vec3(0.7, 0.35, 0.76), Vec3(0.2, 0.0, 1.2)}) {
        PrimitiveParams p = example("point", hand);
        p.points["target"] = target;
        p.numbers["swivel"] = 45;
        const LabelledClip lc = generate_clip(k, standing(k), p, 30);
        const Side side = hand == "left" ? Side::kLeft : Side::kRight;
        const CheckResult hold = check_pointing(lc.clip, side, target, 0.01, "hold");
        EXPECT_TRUE(hold.ok) << hold.message;
        // The stroke ends on the ray too, and the arm is extended as asked.
        const double ext = arm_extension(k, lc.clip.frames.back(), side);
        EXPECT_LT(ext, 0.99);
        const Phase* h = lc.clip.phase("hold");
        EXPECT_NEAR(arm_extension(k, lc.clip.pose_at(0.5 * (h->start + h->end)), side), 0.85, 1e-6);
        // Before the stroke the ray does not point at it yet.
        EXPECT_FALSE(check_pointing(lc.clip, side, target, 0.05, "prep").ok);
      }
    }
  }
}

// The hand shape follows the keys (docs/motion.md "Hands"): the pointing hand points from the
// preparation through the hold and opens again as it retracts; a holding hand is closed; the
// other hand stays open.
TEST(MotionTest, HandShapesPointAndGripAsTheKeysSay) {
  const Skeleton k = Skeleton::FromHeight(1.75);
  const MotionPlan point = plan_motion(k, standing(k), example("point"));
  const auto timeline = point.timeline({});
  // 0.1 s into a phase (a waiting phase without its signal never ends).
  const auto at = [](const std::vector<Phase>& phases, const std::string& name) {
    const auto it = std::find_if(phases.begin(), phases.end(), [&](const Phase& p) { return p.name == name; });
    return it->start + 0.1;
  };
  EXPECT_EQ(point.pose_at(0).hands[1], (HandShape{0, 0}));
  EXPECT_EQ(point.pose_at(at(timeline, "hold")).hands[1], (HandShape{0, 1}));
  EXPECT_EQ(point.pose_at(at(timeline, "hold")).hands[0], (HandShape{0, 0}));
  const double prep = point.pose_at(at(timeline, "prep")).hands[1].point;
  EXPECT_GT(prep, 0);
  EXPECT_LT(prep, 1);
  EXPECT_EQ(point.pose_at(point.nominal_duration(), {{"hold", 0}}).hands[1], (HandShape{0, 0}));

  const MotionPlan offer = plan_motion(k, standing(k), example("offer", "left"));
  const auto offered = offer.timeline({});
  EXPECT_EQ(offer.pose_at(at(offered, "hold_stable")).hands[0], (HandShape{1, 0}));
  EXPECT_EQ(offer.pose_at(at(offered, "hold_stable")).hands[1], (HandShape{0, 0}));
  // A clip keeps the shapes, interpolated between frames.
  const LabelledClip lc = offer.to_clip(30);
  EXPECT_EQ(lc.clip.pose_at(at(offered, "hold_stable")).hands[0], (HandShape{1, 0}));
}

TEST(MotionTest, TheHeadLooksAtThePointedTarget) {
  const Skeleton k = Skeleton::FromHeight(1.75);
  const Vec3 target(0.9, 0.3, 1.0);
  PrimitiveParams p = example("point");
  p.points["target"] = target;
  const MotionPlan plan = plan_motion(k, standing(k), p);
  const double t = plan.timeline({})[2].start + 0.1;  // in the hold
  const auto X = forward_kinematics(k, plan.pose_at(t));
  const core::Pose& head = X[index(Joint::kHead)];
  const Vec3 look = head.rotation * Vec3::UnitX();
  const Vec3 want = (target - X[index(Joint::kNeck)].translation).normalized();
  EXPECT_GT(look.dot(want), std::cos(5 * core::kPi / 180));
  // After the retraction the head is straight again.
  const auto end = forward_kinematics(k, plan.pose_at(plan.nominal_duration(), {{"hold", 0}}));
  EXPECT_LT(end[index(Joint::kHead)].rotation.angularDistance(end[index(Joint::kSpine3)].rotation), 1e-9);
}

TEST(MotionTest, OfferHoldsStableInTheZoneAndLabelsTheHeldObject) {
  const Skeleton k = Skeleton::FromHeight(1.68);
  PrimitiveParams p = example("offer", "left");
  const Zone zone = p.zones["zone"];
  p.numbers["hold"] = 1.2;
  const LabelledClip lc = generate_clip(k, standing(k), p, 30);
  const CheckResult stable = check_stable_in_zone(lc.clip, Side::kLeft, HandPoint::kPalm, zone, "hold_stable");
  EXPECT_TRUE(stable.ok) << stable.message;
  EXPECT_LT(stable.worst, 1e-6);
  EXPECT_TRUE(check_stable_in_zone(lc.clip, Side::kLeft, HandPoint::kPalm, zone, "hold", 0.2).ok);
  const CheckResult moving = check_stable_in_zone(lc.clip, Side::kLeft, HandPoint::kPalm, zone, "reach");
  EXPECT_FALSE(moving.ok);
  EXPECT_NE(moving.message.find("reach"), std::string::npos);
  // Held from the start until the middle of the release, then empty; the right hand is free.
  const Phase* release = lc.clip.phase("release");
  for (size_t f = 0; f < lc.labels.size(); ++f) {
    const double t = static_cast<double>(f) / 30;
    const FrameLabel& l = lc.labels[f];
    EXPECT_EQ(l.active_hand, Side::kLeft);
    EXPECT_EQ(l.hands[1].holding, "");
    if (t < release->start) {
      EXPECT_EQ(l.hands[0].holding, "item") << t;
      EXPECT_DOUBLE_EQ(l.hands[0].grip, 1);
    }
    if (t > release->end) {
      EXPECT_EQ(l.hands[0].holding, "") << t;
      EXPECT_DOUBLE_EQ(l.hands[0].grip, 0);
    }
    const Phase* ph = lc.clip.phase_at(t);
    if (ph != nullptr && t > ph->start + 1e-9 && t < ph->end - 1e-9) {
      EXPECT_EQ(l.phase, ph->name) << t;
    }
  }
}

TEST(MotionTest, ReactivePhasesWaitForTheirSignal) {
  const Skeleton k = Skeleton::FromHeight(1.75);
  const MotionPlan plan = plan_motion(k, standing(k), example("offer"));
  const auto timeline = plan.timeline({});
  ASSERT_EQ(timeline.size(), 5u);
  EXPECT_EQ(timeline[2].name, "hold_stable");
  EXPECT_TRUE(std::isinf(timeline[2].end));
  EXPECT_TRUE(std::isinf(plan.end_time({})));
  const double t_stable = timeline[2].start;
  // Still waiting long after: the pose does not move, the object is still held.
  const SkeletonPose a = plan.pose_at(t_stable + 0.6);
  const SkeletonPose b = plan.pose_at(t_stable + 30);
  EXPECT_TRUE(a.local == b.local);
  EXPECT_EQ(plan.label_at(t_stable + 30).phase, "hold_stable");
  EXPECT_EQ(plan.label_at(t_stable + 30).hands[1].holding, "item");
  // The signal ends the wait; the rest of the plan follows it.
  const Signals go{{"hold_stable", t_stable + 4.0}};
  const auto after = plan.timeline(go);
  EXPECT_DOUBLE_EQ(after[2].end, t_stable + 4.0);
  EXPECT_DOUBLE_EQ(after[3].start, t_stable + 4.0);
  EXPECT_DOUBLE_EQ(plan.end_time(go), t_stable + 4.0 + 0.3 + 0.8);
  EXPECT_EQ(plan.label_at(t_stable + 4.2, go).phase, "release");
  EXPECT_EQ(plan.label_at(t_stable + 4.5, go).hands[1].holding, "");
  // A signal before the minimum hold does not shorten it.
  const Signals early{{"hold_stable", 0.1}};
  EXPECT_DOUBLE_EQ(plan.timeline(early)[2].end, t_stable + 0.5);
  // to_clip with the signal covers the whole plan; without, the minimum.
  EXPECT_NEAR(plan.to_clip(30, go).clip.duration(), plan.end_time(go), 1.0 / 30);
  EXPECT_NEAR(plan.to_clip(30).clip.duration(), plan.nominal_duration(), 1.0 / 30);
  // Receive closes only on its signal.
  const MotionPlan receive = plan_motion(k, standing(k), example("receive"));
  const double open = receive.timeline({})[3].start;
  ASSERT_EQ(receive.timeline({})[3].name, "open");
  EXPECT_EQ(receive.label_at(open + 10).hands[1].grip, 0);
  const Signals in_palm{{"open", open + 2}};
  EXPECT_EQ(receive.label_at(open + 2 + 0.3 + 0.01, in_palm).hands[1].holding, "item");
}

TEST(MotionTest, AReceivingHandWithShiftByIsHeldOutShortOfTheZoneThenMovesIntoIt) {
  const Skeleton k = Skeleton::FromHeight(1.75);
  PrimitiveParams p = example("receive");
  const Vec3 zone = p.zones["zone"].center;
  const Vec3 shift_by(0.02, -0.12, 0.0);
  p.points["shift_by"] = shift_by;
  p.numbers["present"] = 0.5;
  p.numbers["shift"] = 0.7;
  const MotionPlan plan = plan_motion(k, standing(k), p);
  const auto phases = plan.timeline({});
  ASSERT_EQ(phases[1].name, "present");
  ASSERT_EQ(phases[2].name, "shift");
  ASSERT_EQ(phases[3].name, "open");
  EXPECT_NEAR(phases[1].end - phases[1].start, 0.5, 1e-12);
  EXPECT_NEAR(phases[2].end - phases[2].start, 0.7, 1e-12);
  const auto palm = [&](double t) { return hand_point(k, plan.pose_at(t), Side::kRight, HandPoint::kPalm); };
  // Held still short of the zone while presented, then in the zone once it opens to wait.
  EXPECT_LT((palm(phases[1].start) - (zone - shift_by)).norm(), 0.01);
  EXPECT_LT((palm(phases[1].end) - (zone - shift_by)).norm(), 0.01);
  EXPECT_LT((palm(phases[3].start + 1.0) - zone).norm(), 0.01);
  // Moving during the shift.
  EXPECT_GT((palm(phases[2].start + 0.35) - palm(phases[2].start)).norm(), 0.03);
  // A shift too short to move the hand in is refused with the parameter's name.
  p.numbers["shift"] = 0.1;
  try {
    plan_motion(k, standing(k), p);
    FAIL() << "expected an InputError";
  } catch (const core::InputError& e) {
    EXPECT_THAT(std::string(e.what()), ::testing::HasSubstr("motion.shift"));
    EXPECT_THAT(std::string(e.what()), ::testing::HasSubstr("at least 0.2 s"));
  }
}

TEST(MotionTest, RetargetingBendsTheReachSmoothlyToTheNewPlace) {
  const Skeleton k = Skeleton::FromHeight(1.75);
  const MotionPlan plan = plan_motion(k, standing(k), example("receive"));
  const double t = 0.5;  // mid-reach
  const Vec3 moved = example("receive").zones["zone"].center + Vec3(0.05, -0.1, 0.05);
  const MotionPlan next = plan.retarget(t, {}, Side::kRight, moved, 0.6);
  const auto palm = [&](const MotionPlan& m, double tt) {
    return hand_point(k, m.pose_at(tt), Side::kRight, HandPoint::kPalm);
  };
  // Position and velocity continue across the switch.
  EXPECT_LT((palm(plan, t) - palm(next, 0)).norm(), 1e-9);
  const Vec3 v_old = (palm(plan, t) - palm(plan, t - 1e-3)) / 1e-3;
  const Vec3 v_new = (palm(next, 1e-3) - palm(next, 0)) / 1e-3;
  EXPECT_LT((v_old - v_new).norm(), 0.02 * v_old.norm() + 1e-3);
  // It arrives at the new place, waits there open, and closes there on the signal.
  EXPECT_LT((palm(next, 0.6) - moved).norm(), 1e-6);
  EXPECT_LT((palm(next, 5.0) - moved).norm(), 1e-6);
  EXPECT_EQ(next.label_at(5.0).phase, "open");
  const Signals in_palm{{"open", 6.0}};
  EXPECT_LT((hand_point(k, next.pose_at(6.2, in_palm), Side::kRight, HandPoint::kPalm) - moved).norm(), 1e-6);
  EXPECT_EQ(next.label_at(6.4, in_palm).hands[1].holding, "item");
  const LabelledClip lc = next.to_clip(30, in_palm);
  EXPECT_TRUE(check_self_penetration(lc.clip).ok);
  EXPECT_TRUE(check_clip_joint_limits(lc.clip).ok);
}

TEST(MotionTest, IntruderHandEntersTheWorkspace) {
  const Skeleton k = Skeleton::FromHeight(1.80);
  const LabelledClip lc = generate_clip(k, standing(k), example("intrude"), 30);
  const Box workspace{Vec3(0.3, -0.4, 0.75), Vec3(0.95, 0.4, 1.3)};
  const CheckResult enters = check_enters_box(lc.clip, Side::kRight, HandPoint::kPalm, workspace, "reach");
  EXPECT_TRUE(enters.ok) << enters.message;
  EXPECT_GT(enters.worst, 0.0);
  EXPECT_LE(enters.worst, lc.clip.phase("reach")->end + 1e-9);
  // It stays there during the dwell and leaves in the retraction.
  const Phase* dwell = lc.clip.phase("dwell");
  EXPECT_TRUE(workspace.contains(palm_of(lc.clip, static_cast<size_t>(std::ceil(dwell->start * 30)), Side::kRight)));
  EXPECT_FALSE(workspace.contains(palm_of(lc.clip, lc.clip.frames.size() - 1, Side::kRight)));
  const Box elsewhere{Vec3(0.0, 0.5, 0.75), Vec3(0.3, 0.9, 1.0)};
  const CheckResult never = check_enters_box(lc.clip, Side::kRight, HandPoint::kPalm, elsewhere);
  EXPECT_FALSE(never.ok);
  EXPECT_NE(never.message.find("never enters"), std::string::npos);
}

TEST(MotionTest, HandsReachTheirTargets) {
  const Skeleton k = Skeleton::FromHeight(1.75);
  for (const std::string name : {"reach", "pick", "place", "intrude"}) {
    SCOPED_TRACE(name);
    const PrimitiveParams p = example(name, "right");
    const MotionPlan plan = plan_motion(k, standing(k), p);
    const Phase main = plan.timeline({{"hold", 0}})[0];  // a copy: the timeline is a temporary
    const Vec3 palm = hand_point(k, plan.pose_at(main.end, {{"hold", 0}}), Side::kRight, HandPoint::kPalm);
    EXPECT_LT((palm - p.points.at("target")).norm(), 1e-6);
  }
  // A via-point bends the path through it.
  PrimitiveParams via = example("reach");
  via.paths["via"] = {Vec3(1.1, -0.05, 1.15)};
  const LabelledClip curved = generate_clip(k, standing(k), via, 100);
  double closest = 1;
  for (size_t f = 0; f < curved.clip.frames.size(); ++f) {
    closest = std::min(closest, (palm_of(curved.clip, f, Side::kRight) - via.paths["via"][0]).norm());
  }
  EXPECT_LT(closest, 0.01);
  // The body key of a generated pose gives back the plan's hand targets.
  // (Start with both arms at the plan's hanging pose: the rest pose's straight arms are
  // bent to 99.5 % of their reach by the IK.)
  PrimitiveParams crossed = example("cancel");
  const MotionPlan settle = plan_motion(k, standing(k), crossed);
  const MotionPlan reach = plan_motion(k, settle.pose_at(settle.nominal_duration()), example("reach"));
  for (const double t : {0.2, 0.5, 0.8}) {
    const BodyKey planned = reach.key_at(t);
    const BodyKey measured = body_key(k, reach.pose_at(t));
    // The reaching (right) hand; the hanging left one follows its shoulder when the torso leans.
    EXPECT_LT((planned.hands[1].palm - measured.hands[1].palm).norm(), 1e-6) << t;
    EXPECT_NEAR(planned.hands[1].swivel, measured.hands[1].swivel, 1e-6) << t;
  }
  // A lid handle follows the hinge arc: at the end of "open" it is open_deg up.
  const PrimitiveParams lid = example("hold_lid");
  const MotionPlan plan = plan_motion(k, standing(k), lid);
  const auto tl = plan.timeline({{"hold", 0}});
  const Vec3 palm = hand_point(k, plan.pose_at(tl[2].end, {{"hold", 0}}), Side::kRight, HandPoint::kPalm);
  const Vec3 hinge = lid.points.at("hinge");
  const Vec3 handle = lid.points.at("handle");
  EXPECT_NEAR((palm - hinge).norm(), (handle - hinge).norm(), 2e-3);
  EXPECT_NEAR(std::acos((palm - hinge).normalized().dot((handle - hinge).normalized())), 100 * core::kPi / 180, 0.02);
}

TEST(MotionTest, GesturesOrientThePalm) {
  const Skeleton k = Skeleton::FromHeight(1.75);
  // The person faces world -x: the robot is in front (-x), up is +z.
  const auto palm_at = [&](const std::string& name, const std::string& phase) {
    const MotionPlan plan = plan_motion(k, standing(k), example(name, "left"));
    const auto tl = plan.timeline({{phase, 0}});
    double t = 0;
    for (const Phase& ph : tl) {
      if (ph.name == phase) t = ph.start + 0.01;
    }
    const auto X = forward_kinematics(k, plan.pose_at(t, {{phase, 0}}));
    return palm_normal(Side::kLeft, X[index(Joint::kLeftWrist)]);
  };
  EXPECT_GT(palm_at("stop", "hold").dot(-Vec3::UnitX()), 0.7);   // palm toward the robot
  EXPECT_GT(palm_at("give_me", "gesture").dot(Vec3::UnitZ()), 0.7);  // palm up
  EXPECT_GT(palm_at("receive", "open").dot(Vec3::UnitZ()), 0.7);
  // Side grasp: the left palm faces the midline, which is world +y for a person facing -x.
  EXPECT_GT(palm_at("pick", "grasp").dot(Vec3::UnitY()), 0.5);
}

TEST(MotionTest, WalkToArrivesAndFacesTheRequestedHeading) {
  const Skeleton k = Skeleton::FromHeight(1.75);
  PrimitiveParams p = example("walk_to");
  p.numbers["yaw_deg"] = 90;
  p.numbers["speed"] = 1.4;
  const LabelledClip lc = generate_clip(k, standing(k), p, 30);
  const SkeletonPose& end = lc.clip.frames.back();
  EXPECT_NEAR(end.X_WP.translation.x(), 1.5, 1e-9);
  EXPECT_NEAR(end.X_WP.translation.y(), 0.8, 1e-9);
  const Vec3 fwd = end.X_WP.rotation * Vec3::UnitX();
  EXPECT_NEAR(std::atan2(fwd.y(), fwd.x()), core::kPi / 2, 1e-9);
  // Walk duration: 1.875 * distance / peak speed; the legs move while walking.
  const Phase* walk = lc.clip.phase("walk");
  EXPECT_NEAR(walk->end - walk->start, 1.875 * 0.8 / 1.4, 1e-9);
  EXPECT_DOUBLE_EQ(walk_duration(0.8, 1.4), 1.875 * 0.8 / 1.4);
  EXPECT_DOUBLE_EQ(walk_duration(0, 1.4), 0.2);
  const SkeletonPose mid = lc.clip.pose_at(0.5 * (walk->start + walk->end));
  EXPECT_GT(core::Quat(mid.local[index(Joint::kLeftHip)]).angularDistance(core::Quat::Identity()), 0.05);
}

TEST(MotionTest, ChainedActsStartWhereThePreviousEnded) {
  const Skeleton k = Skeleton::FromHeight(1.75);
  SkeletonPose pose = standing(k);
  for (const std::string name : {"lift", "carry", "lower"}) {
    SCOPED_TRACE(name);
    const LabelledClip lc = generate_clip(k, pose, example(name), 30);
    // The first frame is the previous last frame (hands within 1 mm; 3 mm from the rest pose,
    // whose straight arm is bent to 99.5 % of its reach).
    for (const Side side : {Side::kLeft, Side::kRight}) {
      const Vec3 before = hand_point(k, pose, side, HandPoint::kPalm);
      const Vec3 after = hand_point(k, lc.clip.frames.front(), side, HandPoint::kPalm);
      EXPECT_LT((before - after).norm(), name == std::string("lift") ? 3e-3 : 1e-3);
    }
    EXPECT_TRUE(check_self_penetration(lc.clip).ok);
    EXPECT_TRUE(check_clip_joint_limits(lc.clip).ok);
    pose = lc.clip.frames.back();
  }
  // After the carry the body stood elsewhere; after lower the hands are empty.
  EXPECT_GT(std::hypot(pose.X_WP.translation.x() - kStandX, pose.X_WP.translation.y()), 0.3);
}

TEST(MotionTest, SameParametersGiveIdenticalMotionAndTremorIsSeeded) {
  const Skeleton k = Skeleton::FromHeight(1.75);
  PrimitiveParams p = example("offer");
  p.numbers["tremor"] = 0.002;
  p.seed = 11;
  const LabelledClip a = generate_clip(k, standing(k), p, 30);
  const LabelledClip b = generate_clip(k, standing(k), p, 30);
  ASSERT_EQ(a.clip.frames.size(), b.clip.frames.size());
  for (size_t f = 0; f < a.clip.frames.size(); ++f) {
    EXPECT_TRUE(a.clip.frames[f].local == b.clip.frames[f].local);
    EXPECT_EQ(a.clip.frames[f].X_WP.translation, b.clip.frames[f].X_WP.translation);
  }
  p.seed = 12;
  const LabelledClip c = generate_clip(k, standing(k), p, 30);
  const size_t mid = a.clip.frames.size() / 2;
  const double diff = (palm_of(a.clip, mid, Side::kRight) - palm_of(c.clip, mid, Side::kRight)).norm();
  EXPECT_GT(diff, 1e-5);
  EXPECT_LT(diff, 2 * std::sqrt(3.0) * 0.002 + 1e-6);
  // With tremor the hold is no longer perfectly still, but stays in the zone.
  const CheckResult stable = check_stable_in_zone(a.clip, Side::kRight, HandPoint::kPalm,
                                                  p.zones["zone"], "hold_stable", 0.5);
  EXPECT_TRUE(stable.ok) << stable.message;
  EXPECT_GT(stable.worst, 0.01);
}

TEST(MotionTest, RandomValidParametersGiveFiniteHumanPoses) {
  for (const PrimitiveInfo& prim : primitive_catalog()) {
    // One stream per primitive: a parameter added to one primitive leaves the others' draws.
    core::Rng rng = core::Rng(2024).split(std::string(prim.name));
    for (int draw = 0; draw < 6; ++draw) {
      const Skeleton k = Skeleton::FromHeight(rng.uniform(1.55, 1.95));
      PrimitiveParams p = example(std::string(prim.name), rng.uniform() < 0.5 ? "left" : "right");
      p.seed = rng.next_u64();
      for (const ParamInfo& info : prim.params) {
        if (info.kind == ParamKind::kNumber && info.name != "onset") {
          p.numbers[std::string(info.name)] = rng.uniform(info.min, std::min(info.max, std::max(info.min, 3.0)));
        }
      }
      // Targets anywhere on the near half of the table, 0.78-1.3 m high.
      for (auto& [name, point] : p.points) {
        if (name != "to" && name != "hinge") point = Vec3(rng.uniform(0.9, 1.25), rng.uniform(-0.4, 0.4), rng.uniform(0.78, 1.3));
      }
      SCOPED_TRACE(std::string(prim.name) + " draw " + std::to_string(draw));
      const LabelledClip lc = generate_clip(k, standing(k), p, 15);
      for (const SkeletonPose& pose : lc.clip.frames) {
        ASSERT_TRUE(pose.X_WP.translation.allFinite());
        for (const core::Quat& q : pose.local) ASSERT_TRUE(q.coeffs().allFinite());
      }
      const CheckResult limits = check_clip_joint_limits(lc.clip);
      EXPECT_TRUE(limits.ok) << limits.message;
    }
  }
}

TEST(MotionTest, BadParametersAreClearErrors) {
  const Skeleton k = Skeleton::FromHeight(1.75);
  const auto message = [&](const PrimitiveParams& p) {
    try {
      plan_motion(k, standing(k), p);
    } catch (const core::InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  PrimitiveParams p = example("dance");
  EXPECT_NE(message(p).find("motion.primitive: expected one of idle, walk_to"), std::string::npos) << message(p);
  p = example("point");
  p.numbers["hold"] = 100;
  EXPECT_EQ(message(p), "motion.hold: expected a number in [0, 60] s, got 100");
  p = example("point");
  p.numbers["hold"] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(message(p).find("motion.hold: expected a number in [0, 60] s"), std::string::npos);
  p = example("point");
  p.numbers["speed"] = 1;
  EXPECT_NE(message(p).find("motion.speed: expected a parameter of point (onset, hand, target"), std::string::npos);
  p = example("point");
  p.points.erase("target");
  EXPECT_EQ(message(p), "motion.target: expected a point (required by point), got nothing");
  p = example("go");
  p.choices["style"] = "salute";
  EXPECT_EQ(message(p), "motion.style: expected wave | beckon, got 'salute'");
  p = example("offer");
  p.zones["zone"].radius = 2;
  EXPECT_EQ(message(p), "motion.zone.radius: expected a radius in [0.005, 0.5] m, got 2");
  p = example("offer");
  p.numbers["zone"] = 1;
  EXPECT_EQ(message(p), "motion.zone: expected a zone, got a value of another kind");
  EXPECT_EQ(message(example("offer")), "no error");
}


TEST(MotionTest, AHangingArmDoesNotSinkWithAForwardLean) {
  // A low, far reach with the right hand leans the trunk; the left arm hangs. Carried down
  // with its shoulder it would sink into whatever the person leans over (a table edge).
  const Skeleton k = Skeleton::FromHeight(1.60);
  PrimitiveParams p = example("reach");
  p.points["target"] = Vec3(kStandX - 0.62, -0.10, 0.80);
  const LabelledClip lc = generate_clip(k, standing(k), p, 30);
  const auto shoulder_z = [&](size_t f) {
    return forward_kinematics(k, lc.clip.frames[f])[static_cast<size_t>(index(Joint::kLeftShoulder))].translation.z();
  };
  double lowest_palm = 1e9, lowest_shoulder = 1e9;
  for (size_t f = 0; f < lc.clip.frames.size(); ++f) {
    lowest_palm = std::min(lowest_palm, palm_of(lc.clip, f, Side::kLeft).z());
    lowest_shoulder = std::min(lowest_shoulder, shoulder_z(f));
  }
  EXPECT_LT(lowest_shoulder, shoulder_z(0) - 0.03);  // the trunk did lean
  EXPECT_GT(lowest_palm, palm_of(lc.clip, 0, Side::kLeft).z() - 0.005);
}


// Largest wrist speed (m/s, world) of a plan sampled every 5 ms over its nominal duration; the
// time of it in `at`.
double max_wrist_speed(const MotionPlan& plan, double& at) {
  constexpr double dt = 0.005;
  const Skeleton& k = plan.skeleton();
  std::array<Vec3, 2> prev{};
  double worst = 0;
  const auto n = static_cast<int>(plan.nominal_duration() / dt) + 1;
  for (int i = 0; i <= n; ++i) {
    const double t = i * dt;
    const auto X = forward_kinematics(k, plan.pose_at(t));
    for (const Side side : {Side::kLeft, Side::kRight}) {
      const size_t h = side == Side::kLeft ? 0 : 1;
      const Vec3 w = X[static_cast<size_t>(index(wrist(side)))].translation;
      if (i > 0 && (w - prev[h]).norm() / dt > worst) {
        worst = (w - prev[h]).norm() / dt;
        at = t;
      }
      prev[h] = w;
    }
  }
  return worst;
}

TEST(MotionTest, RandomValidPlansMoveTheWristsContinuously) {
  // Phases of human pace (>= 0.8 s each): a wrist never moves faster than ~3 m/s. A switch in
  // how the arms are solved (a lean coming in at once, an arm counted as hanging or not, the
  // elbow jumping on its circle) moves a wrist by centimetres within one 5 ms step.
  for (const PrimitiveInfo& prim : primitive_catalog()) {
    const std::string name(prim.name);
    const bool plank = name == "lift" || name == "carry" || name == "lower";
    const bool handling = plank || name == "offer" || name == "receive";
    core::Rng rng = core::Rng(77).split(name);
    double worst = 0;
    std::string worst_draw;
    for (int draw = 0; draw < (handling ? 24 : 6); ++draw) {
      const Skeleton k = Skeleton::FromHeight(rng.uniform(1.55, 1.95));
      PrimitiveParams p = example(name, rng.uniform() < 0.5 ? "left" : "right");
      p.seed = rng.next_u64();
      for (const ParamInfo& info : prim.params) {
        if (info.kind != ParamKind::kNumber || info.name == "onset") continue;
        const double lo = info.unit == "s" ? std::max(info.min, 0.8) : info.min;
        const double hi = info.unit == "s" ? std::min(info.max, 3.0) : std::min(info.max, std::max(info.min, 3.0));
        p.numbers[std::string(info.name)] = rng.uniform(lo, std::max(lo, hi));
      }
      if (name == "walk_to") p.numbers["speed"] = rng.uniform(0.3, 1.2);
      for (auto& [pname, point] : p.points) {
        if (pname == "to" || pname == "hinge") continue;
        // A plank end 0.3-0.45 m in front at 0.8-0.95 m (C4), other targets anywhere on the
        // near half of the table, 0.78-1.3 m high.
        point = plank ? Vec3(kStandX - rng.uniform(0.3, 0.45), rng.uniform(-0.1, 0.1), rng.uniform(0.8, 0.95))
                      : Vec3(rng.uniform(0.9, 1.25), rng.uniform(-0.4, 0.4), rng.uniform(0.78, 1.3));
      }
      for (auto& [zname, zone] : p.zones) {
        zone.center = Vec3(rng.uniform(0.9, 1.2), rng.uniform(-0.3, 0.3), rng.uniform(0.85, 1.3));
      }
      const SkeletonPose start = SkeletonPose::Standing(k, kStandX, rng.uniform(-0.1, 0.1),
                                                        core::kPi + rng.uniform(-0.1, 0.1));
      double at = 0;
      const double v = max_wrist_speed(plan_motion(k, start, p), at);
      if (v > worst) {
        worst = v;
        worst_draw = fmt::format("draw {} ({} hand, height {:.2f} m) at t = {:.3f} s", draw,
                                 p.choices.count("hand") ? p.choices["hand"] : "-", k.height, at);
      }
    }
    EXPECT_LT(worst, 3.0) << name << ": " << worst_draw;
  }
}

TEST(MotionTest, ATwoHandedPlankLiftReachesWithoutAJump) {
  // C4 co_lift, generation candidate 89 (episode seed 2389382841100): a tall person reaching
  // both hands to a low plank end. The trunk's lean came in at once when the right hand's target
  // left the hanging zone, and the left hand, still counted as hanging, went with its shoulder
  // until its target left the zone too: the left wrist jumped 0.36 m within 5 ms.
  const Skeleton k = Skeleton::FromHeight(1.9185);
  const SkeletonPose start = SkeletonPose::Standing(k, 1.2473, 0.0478, 175.474 * core::kPi / 180);
  PrimitiveParams p = example("lift");
  p.points["target"] = Vec3(0.89, -0.0273, 0.85);
  p.numbers = {{"duration", 0.8622}, {"grasp", 0.5877}, {"grip_width", 0.1383}, {"height", 0.18},
               {"lift", 1.5268}, {"prep", 0.4552}, {"swivel", 0.5825}, {"tremor", 0.0009}};
  double at = 0;
  EXPECT_LT(max_wrist_speed(plan_motion(k, start, p), at), 1.5) << "at t = " << at << " s";
}


TEST(MotionTest, RetargetingInTheMiddleOfALeaningReachKeepsThePose) {
  // A far, low reach leans the trunk gradually; the retargeted plan starts from the lean the body
  // has at that instant, not from the lean its new start key would ask for.
  const Skeleton k = Skeleton::FromHeight(1.60);
  PrimitiveParams p = example("receive");
  p.zones["zone"] = {Vec3(kStandX - 0.65, 0.05, 0.85), 0.05};
  const MotionPlan plan = plan_motion(k, standing(k), p);
  const Phase reach = plan.timeline({})[0];
  const double t = 0.5 * (reach.start + reach.end);
  const MotionPlan moved = plan.retarget(t, {}, Side::kRight, Vec3(kStandX - 0.6, -0.1, 0.9), 0.6);
  for (const Joint j : {Joint::kSpine3, Joint::kRightWrist, Joint::kLeftWrist}) {
    const auto i = static_cast<size_t>(index(j));
    EXPECT_LT((forward_kinematics(k, plan.pose_at(t))[i].translation -
               forward_kinematics(k, moved.pose_at(0))[i].translation).norm(), 1e-3)
        << joint_name(j);
  }
}


TEST(MotionTest, ALowReachBendsTheKneesAndKeepsTheHeadNearTheFeet) {
  // C4 co_lift's grip (0.35-0.40 m in front of the pelvis at 0.85 m) once drove a tall person's
  // head, hinged straight-legged at the hips, into the robot's hand at home (docs/motion.md,
  // "Leaning"). Here: a low reach and a far one at chest height, for every body height.
  for (const double height : {1.55, 1.75, 1.95}) {
    const Skeleton k = Skeleton::FromHeight(height);
    const SkeletonPose start = standing(k);
    for (const Vec3& target : {Vec3(kStandX - 0.38, 0, 0.85), Vec3(kStandX - 0.72, 0.05, 1.0)}) {
      SCOPED_TRACE(fmt::format("height {} target x {}", height, target.x()));
      PrimitiveParams p = example("reach");
      p.points["target"] = target;
      const LabelledClip lc = generate_clip(k, start, p, 30);
      double knee = 0;
      double head_ahead = 0;
      for (const SkeletonPose& pose : lc.clip.frames) {
        const auto X = forward_kinematics(k, pose);
        const Vec3 feet = 0.5 * (X[index(Joint::kLeftAnkle)].translation + X[index(Joint::kRightAnkle)].translation);
        const Vec3 head = X[index(Joint::kNeck)] * Vec3(0.01 * k.scale, 0, 0.10 * k.scale);
        // The person faces -x.
        head_ahead = std::max(head_ahead, feet.x() - head.x());
        const core::Quat q = pose.local[static_cast<size_t>(index(Joint::kLeftKnee))];
        knee = std::max(knee, 2 * std::acos(std::min(1.0, std::abs(q.w()))));
      }
      // The palm gets there (within tasks_test's 5 cm), the knees bend for the low target, the head
      // stays within 0.45 m of the ankles or 0.15 m behind the wrist (0.06 m behind the palm
      // target), whichever is further.
      double closest = 1;
      for (size_t f = 0; f < lc.clip.frames.size(); ++f) {
        closest = std::min(closest, (palm_of(lc.clip, f, Side::kRight) - target).norm());
      }
      EXPECT_LT(closest, 0.05);
      if (target.z() < 0.9) {
        EXPECT_GT(knee, 10 * core::kPi / 180);
      }
      EXPECT_LT(head_ahead, std::max(0.45, kStandX - target.x() - 0.06) + 1e-3);
    }
  }
}

// Whole poses compared to the bit: the root and every joint's local rotation.
bool same_pose(const SkeletonPose& a, const SkeletonPose& b) {
  if (a.X_WP.translation != b.X_WP.translation || a.X_WP.rotation.coeffs() != b.X_WP.rotation.coeffs()) return false;
  for (size_t j = 0; j < a.local.size(); ++j) {
    if (a.local[j].coeffs() != b.local[j].coeffs()) return false;
  }
  return true;
}

// A plan's first waiting phase and its nominal end (the phase empty where none waits).
std::pair<std::string, double> first_waiting_phase(const MotionPlan& plan) {
  double end = 0;
  for (const Segment& seg : plan.segments()) {
    end += seg.duration;
    if (seg.waits) return {seg.phase, end};
  }
  return {"", end};
}

TEST(MotionTest, TheLeansKeptAtTheKnotsOnlySaveWork) {
  // A reaching hand's lean is solved at the knots of plan time (every kLeanPeriod) and
  // interpolated between them; an episode keeps the knots it solved (MotionPlan::Knots). Posed
  // every physics step with the knots kept, each pose is the one computed afresh, to the bit,
  // also where a signal moves the knots.
  const Skeleton k = Skeleton::FromHeight(1.60);
  PrimitiveParams p = example("hold_lid");
  p.points["handle"] = Vec3(kStandX - 0.62, 0, 0.9);  // beyond reach: the trunk leans
  p.points["hinge"] = Vec3(kStandX - 0.87, 0, 0.9);
  const MotionPlan plan = plan_motion(k, standing(k), p);
  // Posed until 0.2 s after the waiting phase's (hold's) nominal end with no signal (the person
  // holds the lid open), then with the signal dated at that nominal end: closing the lid is
  // under way already, and the knots kept for the holding person no longer hold.
  const auto [waiting, nominal_end] = first_waiting_phase(plan);
  const double signal_at = nominal_end + 0.2;
  ASSERT_FALSE(waiting.empty());
  MotionPlan::Knots knots;
  Signals signals;
  int leaning = 0;
  const auto upright_spine = SkeletonPose::Standing(k, kStandX, 0, core::kPi).local[static_cast<size_t>(index(Joint::kSpine1))];
  for (double t = 0; t < plan.nominal_duration() + 1; t += 0.0025) {
    if (signals.empty() && t >= signal_at) signals[waiting] = nominal_end;
    const SkeletonPose kept = plan.pose_at(t, signals, &knots);
    ASSERT_TRUE(same_pose(kept, plan.pose_at(t, signals))) << "t = " << t;
    if (kept.local[static_cast<size_t>(index(Joint::kSpine1))].angularDistance(upright_spine) > 0.05) ++leaning;
  }
  EXPECT_GT(leaning, 100);  // the trunk leaned in this plan
}

TEST(MotionTest, AFrameIsThePoseTheLabelsAndTheKeyAtOnce) {
  // frame_at gives, from one interpolation, what pose_at, label_at and key_at give apart, to the
  // bit: for every primitive, through a waiting phase and after its signal.
  const Skeleton k = Skeleton::FromHeight(1.70);
  int holding = 0;
  int waited = 0;
  for (const PrimitiveInfo& prim : primitive_catalog()) {
    const MotionPlan plan = plan_motion(k, standing(k), example(std::string(prim.name)));
    Signals signals;
    const auto [waiting, nominal_end] = first_waiting_phase(plan);
    MotionPlan::Knots knots;
    for (double t = 0; t < plan.nominal_duration() + 1.5; t += 0.0125) {
      if (!waiting.empty() && signals.empty() && t >= nominal_end + 0.5) {
        signals[waiting] = nominal_end + 0.5;
        ++waited;
      }
      const MotionPlan::Frame frame = plan.frame_at(t, signals, &knots);
      ASSERT_TRUE(same_pose(frame.pose, plan.pose_at(t, signals))) << prim.name << " t = " << t;
      const FrameLabel label = plan.label_at(t, signals);
      ASSERT_EQ(frame.label.phase, label.phase) << prim.name << " t = " << t;
      ASSERT_EQ(frame.label.active_hand, label.active_hand) << prim.name;
      const BodyKey key = plan.key_at(t, signals);
      ASSERT_TRUE(frame.key.X_WF.translation == key.X_WF.translation) << prim.name << " t = " << t;
      for (size_t h = 0; h < 2; ++h) {
        ASSERT_EQ(frame.label.hands[h].grip, label.hands[h].grip) << prim.name << " t = " << t;
        ASSERT_EQ(frame.label.hands[h].holding, label.hands[h].holding) << prim.name << " t = " << t;
        ASSERT_EQ(frame.key.hands[h].swivel, key.hands[h].swivel) << prim.name << " t = " << t;
        ASSERT_TRUE(frame.key.hands[h].palm == key.hands[h].palm) << prim.name << " t = " << t;
        holding += !label.hands[h].holding.empty();
      }
    }
  }
  EXPECT_GT(holding, 100);  // labels that say something
  EXPECT_GT(waited, 2);     // plans that waited for a signal and got it
}

TEST(MotionTest, AReachingHandsLeanIsInterpolatedBetweenKnots) {
  // A person holding a lid open beyond reach with a tremor (8-12 Hz): the lean the hand asks
  // for changes within every 50 ms. Solved at the knots and interpolated, the trunk's lean (the
  // pelvis pitches by 40 % of it) is linear in time inside each knot interval; solved at every
  // instant it bends with the tremor (second differences of 3-4e-3 rad over 12.5 ms).
  const Skeleton k = Skeleton::FromHeight(1.60);
  PrimitiveParams p = example("hold_lid");
  p.points["handle"] = Vec3(kStandX - 0.45, 0, 0.95);
  p.points["hinge"] = Vec3(kStandX - 0.70, 0, 0.95);
  p.numbers["tremor"] = 0.004;
  const MotionPlan plan = plan_motion(k, standing(k), p);
  double hold_start = 0;
  for (const Segment& seg : plan.segments()) {
    if (seg.waits) break;
    hold_start += seg.duration;
  }
  const core::Quat upright = standing(k).X_WP.rotation;
  const auto pitch = [&](double t) { return plan.pose_at(t).X_WP.rotation.angularDistance(upright); };
  const auto first = static_cast<int>(std::ceil(hold_start / kLeanPeriod)) + 2;
  std::vector<std::array<double, 3>> thirds;  // pitch at 1/4, 1/2 and 3/4 of each knot interval
  double keys = 1e9;                          // the keys' lean's pitch: the least seen
  for (int knot = first; knot < first + 160; ++knot) {
    const double t0 = knot * kLeanPeriod;
    thirds.push_back({pitch(t0 + 0.0125), pitch(t0 + 0.025), pitch(t0 + 0.0375)});
    for (const double v : thirds.back()) keys = std::min(keys, v);
  }
  // Where the hand's lean exceeds the keys' at all three instants, the trunk follows it alone.
  int checked = 0;
  for (size_t i = 0; i < thirds.size(); ++i) {
    const auto& [a, b, c] = thirds[i];
    if (std::min({a, b, c}) < keys + 1e-6) continue;
    ++checked;
    EXPECT_LT(std::abs(a - 2 * b + c), 1e-6) << "knot interval " << i;
  }
  EXPECT_GT(checked, 5);  // the hand's lean, not the keys' constant one, leaned the trunk
}

}  // namespace
}  // namespace hribench::human

// The drawn hand: part frames and capsules from a HandShape (docs/motion.md "Hands").

#include "human/hand.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "human/arm_ik.h"


namespace hribench::human {
namespace {

using core::Pose;
using core::Vec3;

// The far ends of a part's capsules, in the wrist frame.
std::vector<Vec3> tips(const Skeleton& k, Side side, const HandShape& shape, HandPart part) {
  const auto X = hand_part_frames(k, side, shape);
  std::vector<Vec3> out;
  for (const HandCapsule& c : hand_capsules(k)) {
    if (c.part == part) out.push_back(X[static_cast<size_t>(part)] * c.to);
  }
  return out;
}

Vec3 index_tip(const Skeleton& k, Side side, const HandShape& shape) {
  return tips(k, side, shape, HandPart::kIndexDistal).at(0);
}

// The palm normal in the wrist frame.
Vec3 palm_side(Side side) { return palm_normal(side, Pose::Identity()); }

TEST(Hand, EveryPartHasCapsulesAndANameAndTheStraightIndexReachesTheHandLength) {
  for (const double height : {1.5, 1.75, 1.95}) {
    const Skeleton k = Skeleton::FromHeight(height);
    const std::vector<HandCapsule> capsules = hand_capsules(k);
    for (int p = 0; p < kNumHandParts; ++p) {
      const auto part = static_cast<HandPart>(p);
      EXPECT_NE(to_string(part), "?");
      EXPECT_TRUE(std::any_of(capsules.begin(), capsules.end(),
                              [&](const HandCapsule& c) { return c.part == part; }))
          << to_string(part);
    }
    const Vec3 tip = index_tip(k, Side::kRight, {0, 1});
    EXPECT_NEAR(-tip.z(), k.hand_length, 1e-12) << height;
    EXPECT_NEAR(tip.y(), 0, 1e-12);
  }
}

TEST(Hand, PointingStraightensTheIndexAndFoldsTheOtherFingers) {
  const Skeleton k = Skeleton::FromHeight(1.75);
  for (const Side side : {Side::kLeft, Side::kRight}) {
    const Vec3 index = index_tip(k, side, {0, 1});
    for (const Vec3& tip : tips(k, side, {0, 1}, HandPart::kFingersDistal)) {
      // A fist: the fingertips come back toward the wrist, in front of the palm.
      EXPECT_LT(tip.norm(), 0.6 * index.norm()) << to_string(side);
      EXPECT_GT(tip.dot(palm_side(side)), 0.01) << to_string(side);
    }
    // Open, the fingers reach about as far as the index.
    for (const Vec3& tip : tips(k, side, {0, 0}, HandPart::kFingersDistal))
      EXPECT_GT(tip.norm(), 0.8 * index.norm()) << to_string(side);
  }
}

TEST(Hand, GripClosesEveryFingerTowardThePalmAndIsClamped) {
  const Skeleton k = Skeleton::FromHeight(1.75);
  for (const Side side : {Side::kLeft, Side::kRight}) {
    // The fingertips come back toward the wrist as the grip closes.
    double previous = 1;
    for (const double grip : {0.0, 0.25, 0.5, 0.75, 1.0}) {
      const double reach = -index_tip(k, side, {grip, 0}).z();
      EXPECT_LT(reach, previous) << grip;
      previous = reach;
    }
    EXPECT_GT(-index_tip(k, side, {0, 0}).z(), 0.98 * k.hand_length);  // open: nearly straight
    EXPECT_LT(index_tip(k, side, {0, 0}).dot(palm_side(side)), 0.025);
    EXPECT_GT(index_tip(k, side, {1, 0}).dot(palm_side(side)), 0.05);  // closed: wrapped
    // The thumb swings from spread to the palm side.
    const Vec3 spread = tips(k, side, {0, 0}, HandPart::kThumbDistal).at(0);
    const Vec3 across = tips(k, side, {1, 0}, HandPart::kThumbDistal).at(0);
    EXPECT_GT(spread.x(), across.x() + 0.03);
    EXPECT_GT(across.dot(palm_side(side)), spread.dot(palm_side(side)) + 0.02);
    // Out-of-range shapes are clamped.
    const auto clamped = hand_part_frames(k, side, {1, 1});
    const auto beyond = hand_part_frames(k, side, {3, 2});
    for (size_t p = 0; p < clamped.size(); ++p) {
      EXPECT_LT((clamped[p].translation - beyond[p].translation).norm(), 1e-15);
      EXPECT_TRUE(clamped[p].rotation.isApprox(beyond[p].rotation, 1e-15));
    }
  }
}

TEST(Hand, LeftIsTheMirrorImageOfRight) {
  const Skeleton k = Skeleton::FromHeight(1.75);
  for (const HandShape shape : {HandShape{0, 0}, HandShape{1, 0}, HandShape{0.3, 1}}) {
    const auto L = hand_part_frames(k, Side::kLeft, shape);
    const auto R = hand_part_frames(k, Side::kRight, shape);
    for (const HandCapsule& c : hand_capsules(k)) {
      const size_t p = static_cast<size_t>(c.part);
      for (const Vec3& q : {c.from, c.to}) {
        const Vec3 l = L[p] * q;
        const Vec3 r = R[p] * q;
        EXPECT_LT((l - Vec3(r.x(), -r.y(), r.z())).norm(), 1e-12) << to_string(c.part);
      }
    }
  }
}

// The drawn hand is what a camera sees; contact uses the hand's capsule (body_capsules). The
// drawn hand reaches at most 5.5 cm beyond it, with its fingers wrapped round a held object
// (docs/motion.md "Hands").
TEST(Hand, TheDrawnHandStaysCloseToItsContactCapsule) {
  const Skeleton k = Skeleton::FromHeight(1.75);
  const auto capsules = body_capsules(k);
  const auto contact = std::find_if(capsules.begin(), capsules.end(),
                                    [](const BodyCapsule& c) { return c.name == "right_hand"; });
  ASSERT_NE(contact, capsules.end());
  const auto outside = [&](const Vec3& p, double radius) {
    const Vec3 d = contact->to - contact->from;
    const double t = std::clamp((p - contact->from).dot(d) / d.squaredNorm(), 0.0, 1.0);
    return (p - (contact->from + t * d)).norm() + radius - contact->radius;
  };
  double worst = 0;
  for (const double grip : {0.0, 0.5, 1.0}) {
    for (const double point : {0.0, 0.5, 1.0}) {
      const auto X = hand_part_frames(k, Side::kRight, {grip, point});
      for (const HandCapsule& c : hand_capsules(k)) {
        const Pose& P = X[static_cast<size_t>(c.part)];
        worst = std::max({worst, outside(P * c.from, c.radius), outside(P * c.to, c.radius)});
      }
    }
  }
  EXPECT_LT(worst, 0.055);
  EXPECT_GT(worst, 0.0);
}

TEST(Hand, PartPosesFollowTheWristOfEachSide) {
  const Skeleton k = Skeleton::FromHeight(1.75);
  SkeletonPose pose = SkeletonPose::Standing(k, 1.2, 0.1, 3.0);
  pose.hands[0] = {1, 0};
  pose.hands[1] = {0, 1};
  const auto X_WJ = forward_kinematics(k, pose);
  const auto X_W = hand_part_poses(k, pose, X_WJ);
  for (const Side side : {Side::kLeft, Side::kRight}) {
    const size_t h = static_cast<size_t>(side);
    const auto X_wrist = hand_part_frames(k, side, pose.hands[h]);
    for (size_t p = 0; p < X_wrist.size(); ++p) {
      const Pose expected = X_WJ[static_cast<size_t>(index(wrist(side)))] * X_wrist[p];
      EXPECT_LT((X_W[h][p].translation - expected.translation).norm(), 1e-12);
    }
  }
}

}  // namespace
}  // namespace hribench::human

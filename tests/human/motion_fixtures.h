#pragma once
// Test fixtures shared by the importer tests: a synthetic clip of our skeleton that moves every
// joint, and the largest joint-position difference between two clips.

#include <algorithm>
#include <cmath>

#include "human/clip.h"

namespace hribench::human::testing {

// 40 frames at 30 fps of a 1.8 m skeleton: the root walks and turns, every joint rotates about
// its own axis by up to ~0.6 rad.
inline Clip synthetic_clip(double height = 1.8) {
  Clip clip;
  clip.skeleton = Skeleton::FromHeight(height);
  clip.fps = 30;
  clip.phases = {{"all", 0, 39.0 / 30}, {"middle", 0.4, 0.8}};
  clip.active_hand = Side::kRight;
  for (int f = 0; f < 40; ++f) {
    const double t = f / 30.0;
    SkeletonPose pose = SkeletonPose::Standing(clip.skeleton, 0.5 * t, 0.2 * t, 0.3 * t);
    pose.X_WP.translation.z() += 0.02 * std::sin(6 * t);
    pose.X_WP.rotation = pose.X_WP.rotation * core::axis_angle(core::Vec3(0.2, 1, 0.1), 0.1 * std::sin(3 * t));
    for (int j = 1; j < kNumJoints; ++j) {
      const core::Vec3 axis(std::sin(1.3 * j), std::cos(0.7 * j), std::sin(0.4 * j + 1));
      pose.local[static_cast<size_t>(j)] = core::axis_angle(axis, 0.6 * std::sin(2.0 * t + j));
    }
    clip.frames.push_back(pose);
  }
  return clip;
}

// Largest distance between corresponding joints over all frames (clips of equal length).
inline double max_joint_error(const Clip& a, const Clip& b) {
  double worst = 0;
  for (size_t f = 0; f < std::min(a.frames.size(), b.frames.size()); ++f) {
    const auto Xa = forward_kinematics(a.skeleton, a.frames[f]);
    const auto Xb = forward_kinematics(b.skeleton, b.frames[f]);
    for (size_t j = 0; j < Xa.size(); ++j) worst = std::max(worst, (Xa[j].translation - Xb[j].translation).norm());
  }
  return worst;
}

}  // namespace hribench::human::testing

#include "human/minjerk.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hribench::human {
namespace {

using core::Vec3;

TEST(MinJerkTest, SymmetricProfileHasTheTextbookShape) {
  EXPECT_DOUBLE_EQ(min_jerk(0), 0);
  EXPECT_DOUBLE_EQ(min_jerk(1), 1);
  EXPECT_DOUBLE_EQ(min_jerk(0.5), 0.5);
  EXPECT_DOUBLE_EQ(min_jerk(-1), 0);
  EXPECT_DOUBLE_EQ(min_jerk(2), 1);
  EXPECT_DOUBLE_EQ(min_jerk_rate(0.5), 1.875);
  EXPECT_DOUBLE_EQ(min_jerk_rate(0), 0);
  EXPECT_DOUBLE_EQ(min_jerk_rate(1), 0);
  EXPECT_DOUBLE_EQ(min_jerk_rate2(0.5), 0);
  // Peak acceleration about 5.77 A / T^2 at tau = 0.5 - sqrt(3)/6.
  EXPECT_NEAR(min_jerk_rate2(0.5 - std::sqrt(3.0) / 6), 5.7735, 1e-3);
  // The rate is the derivative of the position (central difference).
  for (double t = 0.05; t < 1; t += 0.1) {
    EXPECT_NEAR((min_jerk(t + 1e-6) - min_jerk(t - 1e-6)) / 2e-6, min_jerk_rate(t), 1e-6);
  }
}

TEST(MinJerkTest, AsymmetricProfileHasALongerDecelerationTail) {
  const MinJerkProfile sym{0.5};
  const MinJerkProfile prec{0.65};
  for (double t = 0; t <= 1.0001; t += 0.05) EXPECT_NEAR(sym.progress(t), min_jerk(t), 1e-12);
  EXPECT_DOUBLE_EQ(prec.progress(0), 0);
  EXPECT_DOUBLE_EQ(prec.progress(1), 1);
  EXPECT_NEAR(prec.rate(0.35), 1.875, 1e-12);
  // Single peak at 1 - decel; monotone rise before it, fall after it.
  double previous = -1;
  for (int i = 0; i <= 100; ++i) {
    const double t = 0.01 * i;
    if (i < 35) {
      EXPECT_GE(prec.rate(t), previous) << t;
    } else if (i > 36) {
      EXPECT_LE(prec.rate(t), previous + 1e-12) << t;
    }
    EXPECT_LE(prec.rate(t), 1.875 + 1e-12);
    previous = prec.rate(t);
  }
  // Continuous rate and derivative consistent with the progress.
  for (double t = 0.02; t < 1; t += 0.04) {
    EXPECT_NEAR((prec.progress(t + 1e-6) - prec.progress(t - 1e-6)) / 2e-6, prec.rate(t), 1e-5);
  }
  // More of the distance is covered in the first half of the time than symmetric.
  EXPECT_GT(prec.progress(0.5), 0.5);
}

TEST(MinJerkTest, QuinticRestToRestIsMinJerk) {
  const Vec3 a(0.1, 0.2, 0.9);
  const Vec3 b(0.5, -0.1, 1.1);
  const Quintic q = Quintic::RestToRest(a, b, 0.8);
  for (double t = 0; t <= 0.8; t += 0.1) {
    EXPECT_NEAR((q.position(t) - (a + (b - a) * min_jerk(t / 0.8))).norm(), 0, 1e-12);
  }
  // A 0.40 m reach in 0.8 s peaks at 0.94 m/s (docs/motion.md).
  const Quintic r = Quintic::RestToRest(Vec3::Zero(), Vec3(0.4, 0, 0), 0.8);
  EXPECT_NEAR(r.velocity(0.4).norm(), 0.9375, 1e-9);
  EXPECT_NEAR(r.velocity(0.8).norm(), 0, 1e-9);
  EXPECT_NEAR(r.acceleration(0.8).norm(), 0, 1e-9);
}

TEST(MinJerkTest, RetargetingIsContinuousAndReachesTheNewTarget) {
  const Quintic q = Quintic::RestToRest(Vec3::Zero(), Vec3(0.4, 0, 0), 1.0);
  const Vec3 target(0.3, 0.2, 0.1);
  const Quintic r = q.retarget(0.4, target, 0.7);
  EXPECT_NEAR((r.position(0) - q.position(0.4)).norm(), 0, 1e-12);
  EXPECT_NEAR((r.velocity(0) - q.velocity(0.4)).norm(), 0, 1e-12);
  EXPECT_NEAR((r.acceleration(0) - q.acceleration(0.4)).norm(), 0, 1e-9);
  EXPECT_NEAR((r.position(0.7) - target).norm(), 0, 1e-12);
  EXPECT_NEAR(r.velocity(0.7).norm(), 0, 1e-9);
  EXPECT_NEAR(r.acceleration(0.7).norm(), 0, 1e-9);
  EXPECT_DOUBLE_EQ(r.duration(), 0.7);
}

TEST(MinJerkTest, ViaPathPassesThroughEveryPoint) {
  const std::vector<Vec3> pts = {Vec3(0, 0, 0), Vec3(0.2, 0.1, 0.1), Vec3(0.2, 0.1, 0.1),
                                 Vec3(0.4, 0, 0.3)};
  const ViaPath path(pts);
  EXPECT_NEAR((path.at(0) - pts[0]).norm(), 0, 1e-12);
  EXPECT_NEAR((path.at(1) - pts[3]).norm(), 0, 1e-12);
  const double knot = (pts[1] - pts[0]).norm() / path.chord_length();
  EXPECT_NEAR((path.at(knot) - pts[1]).norm(), 0, 1e-12);
  // Smooth: no jumps between nearby samples.
  for (double s = 0; s < 1; s += 0.01) EXPECT_LT((path.at(s + 0.01) - path.at(s)).norm(), 0.02);
  const ViaPath line({Vec3(0, 0, 0), Vec3(1, 0, 0)});
  EXPECT_NEAR((line.at(0.25) - Vec3(0.25, 0, 0)).norm(), 0, 1e-12);
  const ViaPath single({Vec3(1, 2, 3)});
  EXPECT_EQ(single.at(0.5), Vec3(1, 2, 3));
}

}  // namespace
}  // namespace hribench::human

#include "core/math.h"

#include <gtest/gtest.h>

namespace hribench::core {
namespace {

TEST(PoseTest, ComposeAndInverse) {
  const Pose X_AB{axis_angle(Vec3::UnitZ(), kPi / 2), Vec3(1, 0, 0)};
  const Pose X_BC{Quat::Identity(), Vec3(1, 0, 0)};
  const Pose X_AC = X_AB * X_BC;
  EXPECT_TRUE(X_AC.translation.isApprox(Vec3(1, 1, 0), 1e-12));
  const Pose I = X_AC * X_AC.inverse();
  EXPECT_NEAR(I.translation.norm(), 0, 1e-12);
  EXPECT_NEAR(I.rotation.angularDistance(Quat::Identity()), 0, 1e-12);
  EXPECT_NEAR((X_AB * Vec3(0, 1, 0)).norm(), 0, 1e-12);
}

TEST(PoseTest, MujocoQuaternionOrder) {
  const double wxyz[4] = {0.5, 0.5, 0.5, 0.5};
  const Quat q = quat_from_wxyz(wxyz);
  double back[4];
  quat_to_wxyz(q, back);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(back[i], wxyz[i]);
  EXPECT_EQ(q.w(), 0.5);
}

TEST(AnglesTest, DegreesRadians) {
  EXPECT_DOUBLE_EQ(deg_to_rad(180), kPi);
  EXPECT_DOUBLE_EQ(rad_to_deg(kPi / 2), 90);
}

}  // namespace
}  // namespace hribench::core

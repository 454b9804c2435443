#include "model/mjcf.h"

#include <gtest/gtest.h>

namespace hribench::model::mjcf {
namespace {

using core::Vec3;

TEST(MjcfTest, NumbersAreCompactAndNeverNegativeZero) {
  EXPECT_EQ(num(0.75), "0.75");
  EXPECT_EQ(num(-0.0), "0");
  EXPECT_EQ(num(1.0 / 3.0), "0.333333333");
  EXPECT_EQ(vec(Vec3(1, -2, 0.5)), "1 -2 0.5");
  EXPECT_EQ(quat(core::Quat::Identity()), "1 0 0 0");
  EXPECT_EQ(rgba(Rgba{1, 0, 0.5f, 1}), "1 0 0.5 1");
}

TEST(MjcfTest, CameraAxesLookAtTheTargetWithALevelImageX) {
  const Vec3 pos(0.5, -1.5, 1.5);
  const Vec3 target(0.5, 0, 1.0);
  double a[6];
  ASSERT_EQ(std::sscanf(camera_xyaxes(pos, target).c_str(), "%lf %lf %lf %lf %lf %lf", &a[0],
                        &a[1], &a[2], &a[3], &a[4], &a[5]),
            6);
  const Vec3 x(a[0], a[1], a[2]);
  const Vec3 y(a[3], a[4], a[5]);
  const Vec3 forward = -x.cross(y);  // cameras look along -z
  EXPECT_LT((forward - (target - pos).normalized()).norm(), 1e-6);
  EXPECT_NEAR(x.z(), 0.0, 1e-9);  // level horizon
  EXPECT_GT(y.z(), 0.0);          // image up is world up
  EXPECT_NEAR(x.dot(y), 0.0, 1e-9);
}

TEST(MjcfTest, ShapeVolumes) {
  EXPECT_NEAR(box(Vec3::Zero(), Vec3(0.1, 0.2, 0.3)).volume(), 0.048, 1e-12);
  EXPECT_NEAR(cylinder(Vec3::Zero(), Vec3(0, 0, 2), 1).volume(), 2 * core::kPi, 1e-12);
  EXPECT_NEAR(capsule(Vec3::Zero(), Vec3(0, 0, 0), 1).volume(), 4.0 / 3.0 * core::kPi, 1e-12);
}

}  // namespace
}  // namespace hribench::model::mjcf

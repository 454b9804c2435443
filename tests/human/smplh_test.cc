#include "human/smplh.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/errors.h"
#include "human/motion_fixtures.h"

namespace hribench::human {
namespace {

using core::Vec3;

size_t u(Joint j) { return static_cast<size_t>(index(j)); }

// Joint positions in the body (pelvis) frame.
std::array<Vec3, kNumJoints> body_positions(const Clip& clip, size_t frame) {
  const auto X = forward_kinematics(clip.skeleton, clip.frames[frame]);
  std::array<Vec3, kNumJoints> p;
  for (size_t j = 0; j < p.size(); ++j) p[j] = X[0].inverse() * X[j].translation;
  return p;
}

TEST(SmplhTest, RestSkeletonIsATPoseWithTheReferenceBoneLengths) {
  const RestTree t = smpl_rest_tree();
  // docs/motion.md, SMPL-neutral column (PHC): within 5 mm.
  EXPECT_NEAR(t.offset[u(Joint::kLeftKnee)].norm(), 0.377, 0.005);
  EXPECT_NEAR(t.offset[u(Joint::kLeftAnkle)].norm(), 0.401, 0.005);
  EXPECT_NEAR(t.offset[u(Joint::kLeftElbow)].norm(), 0.261, 0.005);
  EXPECT_NEAR(t.offset[u(Joint::kNeck)].norm(), 0.218, 0.005);
  // T-pose in SMPL's frame (x left, y up): the left arm points +x, the right arm -x.
  EXPECT_GT(t.offset[u(Joint::kLeftElbow)].normalized().x(), 0.99);
  EXPECT_LT(t.offset[u(Joint::kRightWrist)].normalized().x(), -0.99);
  EXPECT_LT(t.offset[u(Joint::kLeftKnee)].normalized().y(), -0.99);
}

TEST(SmplhTest, UpAxisConversionIsAProperRotation) {
  EXPECT_NEAR(y_up_to_z_up().determinant(), 1.0, 1e-15);
  EXPECT_TRUE((y_up_to_z_up() * y_up_to_z_up().transpose()).isIdentity(1e-15));
  // SMPL's left (+x), up (+y), forward (+z) become ours: +y, +z, +x.
  EXPECT_EQ(y_up_to_z_up() * Vec3::UnitX(), Vec3::UnitY());
  EXPECT_EQ(y_up_to_z_up() * Vec3::UnitY(), Vec3::UnitZ());
  EXPECT_EQ(y_up_to_z_up() * Vec3::UnitZ(), Vec3::UnitX());
}

TEST(SmplhTest, HyMotionArchiveImportsWithLeftOnTheLeft) {
  // y-up, DEFLATE members with zip64 local headers, a string member: as HY-Motion writes.
  const Clip clip = read_smplh("tests/data/motion/hy_motion_like.npz", {});
  ASSERT_EQ(clip.frames.size(), 3u);
  EXPECT_EQ(clip.fps, 30.0);  // HY-Motion's output rate (no mocap_framerate key)
  // Frame 0, zero pose: a T-pose facing +x, arms out at shoulder height.
  EXPECT_NEAR(facing_yaw(clip.frames[0]), 0.0, 0.05);
  auto p = body_positions(clip, 0);
  EXPECT_GT(p[u(Joint::kLeftWrist)].y(), p[u(Joint::kLeftShoulder)].y() + 0.4);
  EXPECT_LT(p[u(Joint::kRightWrist)].y(), p[u(Joint::kRightShoulder)].y() - 0.4);
  EXPECT_NEAR(p[u(Joint::kLeftWrist)].z(), p[u(Joint::kLeftShoulder)].z(), 0.06);
  // Frames 1-2: the left arm raised overhead, still on the left; the right arm unchanged.
  p = body_positions(clip, 1);
  EXPECT_GT(p[u(Joint::kLeftWrist)].z(), p[u(Joint::kHead)].z());
  EXPECT_GT(p[u(Joint::kLeftWrist)].y(), 0.1);
  EXPECT_LT(p[u(Joint::kRightWrist)].y(), p[u(Joint::kRightShoulder)].y() - 0.4);
  // trans moves 0.1 m per frame along file +z = forward = our +x.
  const Vec3 d = clip.frames[2].X_WP.translation - clip.frames[0].X_WP.translation;
  EXPECT_GT(d.x() / d.norm(), 0.99);
  // Grounded by default: the lowest ankle at our rest ankle height.
  const auto X = forward_kinematics(clip.skeleton, clip.frames[0]);
  const Skeleton& k = clip.skeleton;
  const double ankle_rest = k.pelvis_height + k.offset[u(Joint::kLeftHip)].z() +
                            k.offset[u(Joint::kLeftKnee)].z() + k.offset[u(Joint::kLeftAnkle)].z();
  EXPECT_NEAR(std::min(X[u(Joint::kLeftAnkle)].translation.z(), X[u(Joint::kRightAnkle)].translation.z()),
              ankle_rest, 1e-9);
}

TEST(SmplhTest, AmassArchiveIsZUpWithItsFrameRate) {
  // z-up (root_orient +90 deg about x), stored members, a pickled member that is never decoded.
  const Clip clip = read_smplh("tests/data/motion/amass_like.npz", {});
  EXPECT_EQ(clip.fps, 60.0);
  ASSERT_EQ(clip.frames.size(), 3u);
  // Upright: head above pelvis; facing world -y (SMPL +z turned by Rx(90)).
  const auto X = forward_kinematics(clip.skeleton, clip.frames[0]);
  EXPECT_GT(X[u(Joint::kHead)].translation.z(), X[0].translation.z() + 0.4);
  EXPECT_NEAR(facing_yaw(clip.frames[0]), -core::kPi / 2, 0.05);
  const auto p = body_positions(clip, 0);
  EXPECT_GT(p[u(Joint::kLeftWrist)].y(), 0.4);  // left stays left
}

TEST(SmplhTest, RoundTripReproducesJointPositions) {
  const Clip clip = testing::synthetic_clip(1.65);
  const std::string bytes = format_smplh(clip);
  const NpzArchive archive(bytes, "ours.npz");
  EXPECT_EQ(archive.array("poses").shape, (std::vector<size_t>{40, 156}));
  RetargetOptions options;
  options.height = clip.skeleton.height;
  options.ground = false;
  const Clip back = clip_from_smplh(archive, options, "ours.npz");
  EXPECT_EQ(back.fps, 30.0);
  const double err = testing::max_joint_error(clip, back);
  EXPECT_LT(err, 1e-3);
  std::printf("npz round trip: max joint error %.3g m\n", err);
}

}  // namespace
}  // namespace hribench::human

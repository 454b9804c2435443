#include "human/retarget.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "core/errors.h"
#include "human/motion_fixtures.h"

namespace hribench::human {
namespace {

using core::Vec3;

size_t u(Joint j) { return static_cast<size_t>(index(j)); }

JointTargets targets_of(const Clip& clip, size_t frame) {
  const auto X = forward_kinematics(clip.skeleton, clip.frames[frame]);
  JointTargets t;
  for (size_t j = 0; j < X.size(); ++j) t.joint[j] = X[j].translation;
  return t;
}

TEST(RetargetTest, PositionsOfOurOwnSkeletonComeBackExactly) {
  const Clip clip = testing::synthetic_clip(1.7);
  std::vector<JointTargets> frames;
  for (size_t f = 0; f < clip.frames.size(); ++f) frames.push_back(targets_of(clip, f));
  const Clip back = clip_from_targets(frames, 30, {}, "synthetic");
  EXPECT_NEAR(back.skeleton.height, 1.7, 1e-9);  // from the leg length
  EXPECT_LT(testing::max_joint_error(clip, back), 1e-9);
  // The pelvis and spine3 (several children) get their full rotation back.
  for (size_t f = 0; f < clip.frames.size(); ++f) {
    EXPECT_TRUE(back.frames[f].X_WP.rotation.isApprox(clip.frames[f].X_WP.rotation, 1e-9) ||
                back.frames[f].X_WP.rotation.isApprox(Eigen::Quaterniond(-clip.frames[f].X_WP.rotation.coeffs()), 1e-9));
  }
}

TEST(RetargetTest, ScalesTheRootByLegLengthAndKeepsOurBones) {
  // A source twice our size: directions kept, root halved, our bone lengths.
  const Clip clip = testing::synthetic_clip(1.7);
  std::vector<JointTargets> frames;
  for (size_t f = 0; f < clip.frames.size(); ++f) {
    JointTargets t = targets_of(clip, f);
    for (Vec3& p : t.joint) p *= 2.0;
    frames.push_back(t);
  }
  RetargetOptions options;
  options.height = 1.7;
  const Clip back = clip_from_targets(frames, 30, options, "big");
  EXPECT_LT(testing::max_joint_error(clip, back), 1e-9);
  EXPECT_THROW(clip_from_targets({}, 30, {}, "empty"), core::InputError);
  EXPECT_THROW(clip_from_targets(frames, 0, {}, "no fps"), core::InputError);
  EXPECT_THROW(clip_from_targets(frames, 5000, {}, "fast"), core::InputError);
}

TEST(RetargetTest, GroundPutsTheLowestAnkleAtItsRestHeight) {
  const Clip clip = testing::synthetic_clip(1.7);
  std::vector<JointTargets> frames;
  for (size_t f = 0; f < clip.frames.size(); ++f) {
    JointTargets t = targets_of(clip, f);
    for (Vec3& p : t.joint) p.z() += 0.5;  // floating
    frames.push_back(t);
  }
  RetargetOptions options;
  options.ground = true;
  const Clip back = clip_from_targets(frames, 30, options, "float");
  const Skeleton& k = back.skeleton;
  const double ankle_rest = k.pelvis_height + k.offset[u(Joint::kLeftHip)].z() + k.offset[u(Joint::kLeftKnee)].z() +
                            k.offset[u(Joint::kLeftAnkle)].z();
  double lowest = 1e9;
  for (const SkeletonPose& pose : back.frames) {
    const auto X = forward_kinematics(k, pose);
    lowest = std::min({lowest, X[u(Joint::kLeftAnkle)].translation.z(), X[u(Joint::kRightAnkle)].translation.z()});
  }
  EXPECT_NEAR(lowest, ankle_rest, 1e-9);
}

TEST(RetargetTest, RecognisesNamingConventions) {
  const auto names = [](std::initializer_list<const char*> list) {
    return std::vector<std::string>(list.begin(), list.end());
  };
  const auto mixamo = names({"mixamorig:Hips", "mixamorig:Spine", "mixamorig:Spine1", "mixamorig:Spine2",
                             "mixamorig:Neck", "mixamorig:Head", "mixamorig:LeftShoulder", "mixamorig:LeftArm",
                             "mixamorig:LeftForeArm", "mixamorig:LeftHand", "mixamorig:RightShoulder",
                             "mixamorig:RightArm", "mixamorig:RightForeArm", "mixamorig:RightHand",
                             "mixamorig:LeftUpLeg", "mixamorig:LeftLeg", "mixamorig:LeftFoot",
                             "mixamorig:LeftToeBase", "mixamorig:RightUpLeg", "mixamorig:RightLeg",
                             "mixamorig:RightFoot", "mixamorig:RightToeBase"});
  EXPECT_EQ(match_convention(mixamo, "m").name, "mixamo");
  const auto cmu_mb = names({"Hips", "LHipJoint", "LeftUpLeg", "LeftLeg", "LeftFoot", "LeftToeBase", "RHipJoint",
                             "RightUpLeg", "RightLeg", "RightFoot", "RightToeBase", "LowerBack", "Spine", "Spine1",
                             "Neck", "Neck1", "Head", "LeftShoulder", "LeftArm", "LeftForeArm", "LeftHand",
                             "RightShoulder", "RightArm", "RightForeArm", "RightHand"});
  EXPECT_EQ(match_convention(cmu_mb, "c").name, "cmu_motionbuilder");
  std::vector<std::string> smpl_short = {"Pelvis", "L_Hip", "R_Hip", "Spine1", "L_Knee", "R_Knee", "Spine2",
                                         "L_Ankle", "R_Ankle", "Spine3", "L_Foot", "R_Foot", "Neck", "L_Collar",
                                         "R_Collar", "Head", "L_Shoulder", "R_Shoulder", "L_Elbow", "R_Elbow",
                                         "L_Wrist", "R_Wrist"};
  EXPECT_EQ(match_convention(smpl_short, "s").name, "smpl_short");
  std::vector<std::string> ours;
  for (int j = 0; j < kNumJoints; ++j) ours.emplace_back(joint_name(static_cast<Joint>(j)));
  EXPECT_EQ(match_convention(ours, "o").name, "smpl");
  EXPECT_EQ(normalize_joint_name("mixamorig:Left_Fore-Arm"), "leftforearm");
  try {
    match_convention(names({"root", "tail"}), "x.bvh");
    FAIL() << "no error";
  } catch (const core::InputError& e) {
    EXPECT_EQ(e.where(), "x.bvh");
    EXPECT_THAT(e.got(), ::testing::HasSubstr("2 joints; closest is"));
  }
}

TEST(RetargetTest, MixedMarkersAverageSourceJoints) {
  const NameConvention& cmu = name_conventions().back();
  ASSERT_EQ(cmu.name, "cmu");
  ASSERT_EQ(cmu.joint[u(Joint::kSpine2)].size(), 2u);
  double total = 0;
  for (const auto& [name, w] : cmu.joint[u(Joint::kSpine2)]) total += w;
  EXPECT_DOUBLE_EQ(total, 1.0);
}

TEST(RetargetTest, TimeScaleStretchesFramesAndPhases) {
  const Clip clip = testing::synthetic_clip();
  const Clip slow = time_scale(clip, 2.0);
  EXPECT_EQ(slow.fps, clip.fps);
  EXPECT_NEAR(slow.duration(), 2 * clip.duration(), 1e-12);
  EXPECT_EQ(slow.frames.size(), 79u);
  EXPECT_NEAR(slow.phase("middle")->start, 0.8, 1e-12);
  EXPECT_NEAR(slow.phase("middle")->end, 1.6, 1e-12);
  // Slow frame 2i is the original frame i.
  for (size_t i = 0; i < clip.frames.size(); ++i) {
    EXPECT_TRUE(slow.frames[2 * i].X_WP.translation.isApprox(clip.frames[i].X_WP.translation, 1e-12));
  }
  const Clip fast = time_scale(clip, 0.5);
  EXPECT_NEAR(fast.duration(), 0.65, 1.0 / 30);
  EXPECT_THROW(time_scale(clip, 0), core::InputError);
  EXPECT_THROW(time_scale(clip, std::nan("")), core::InputError);
}

TEST(RetargetTest, PlaceMovesAndTurnsTheClipRigidly) {
  const Clip clip = testing::synthetic_clip();
  const Clip placed = place(clip, 2.0, -1.0, core::kPi / 2);
  const Vec3 p0 = placed.frames[0].X_WP.translation;
  EXPECT_NEAR(p0.x(), 2.0, 1e-12);
  EXPECT_NEAR(p0.y(), -1.0, 1e-12);
  EXPECT_NEAR(p0.z(), clip.frames[0].X_WP.translation.z(), 1e-12);  // heights kept
  EXPECT_NEAR(facing_yaw(placed.frames[0]), core::kPi / 2, 1e-9);
  // Rigid: distances between frames' pelvises and every bone are unchanged.
  const double d0 = (clip.frames[30].X_WP.translation - clip.frames[0].X_WP.translation).norm();
  const double d1 = (placed.frames[30].X_WP.translation - placed.frames[0].X_WP.translation).norm();
  EXPECT_NEAR(d0, d1, 1e-12);
  for (size_t f = 0; f < clip.frames.size(); f += 7) {
    EXPECT_EQ(placed.frames[f].local, clip.frames[f].local);
  }
  // The original walks +x then turns left: after a quarter turn it walks +y.
  const Vec3 step = placed.frames[5].X_WP.translation - placed.frames[0].X_WP.translation;
  EXPECT_GT(step.y(), 0);
}

}  // namespace
}  // namespace hribench::human

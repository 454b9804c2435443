#include "human/bvh.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <map>

#include "core/errors.h"
#include "human/motion_fixtures.h"

namespace hribench::human {
namespace {

using core::Vec3;

const char* kCmu = "tests/data/motion/cmu_131_01.bvh";

size_t u(Joint j) { return static_cast<size_t>(index(j)); }

TEST(BvhTest, ParsesTheCmuClip) {
  const BvhMotion m = read_bvh(kCmu);
  EXPECT_EQ(m.joints.size(), 31u);
  EXPECT_EQ(m.joints[0].name, "Hips");
  EXPECT_EQ(m.joints[0].parent, -1);
  EXPECT_EQ(m.num_channels, 6u + 30u * 3u);
  EXPECT_EQ(m.frames.size(), 994u);
  EXPECT_DOUBLE_EQ(bvh_fps(m.frame_time), 120.0);
  ASSERT_EQ(m.joints[0].channels.size(), 6u);
  EXPECT_EQ(m.joints[0].channels[3], BvhChannel::kZrotation);
  // LeftHip's OFFSET as written.
  EXPECT_EQ(m.joints[2].name, "LeftHip");
  EXPECT_NEAR(m.joints[2].offset.x(), 1.24777, 1e-12);
  EXPECT_TRUE(m.joints[5].has_end_site);  // LeftToe
  EXPECT_NEAR(m.frames[0][1], 16.9002, 1e-12);  // root Yposition of frame 1
}

TEST(BvhTest, ImportsTheCmuWalkOntoOurSkeleton) {
  const Clip clip = clip_from_bvh(read_bvh(kCmu), {}, kCmu);
  ASSERT_EQ(clip.frames.size(), 994u);
  EXPECT_DOUBLE_EQ(clip.fps, 120.0);
  const Skeleton& k = clip.skeleton;
  EXPECT_GT(k.height, 1.5);
  EXPECT_LT(k.height, 1.95);
  const double ankle_rest = k.pelvis_height + k.offset[u(Joint::kLeftHip)].z() +
                            k.offset[u(Joint::kLeftKnee)].z() + k.offset[u(Joint::kLeftAnkle)].z();
  // The source's joint directions, frame by frame, for comparison.
  const BvhMotion m = read_bvh(kCmu);
  std::vector<std::string> names;
  for (const BvhJoint& j : m.joints) names.push_back(j.name);
  for (const BvhJoint& j : m.joints) {
    if (j.has_end_site) names.push_back(j.name + "_end");
  }
  const NameConvention& convention = match_convention(names, kCmu);
  EXPECT_EQ(convention.name, "cmu");
  double lowest = 1e9;
  int low_frames = 0;
  for (size_t f = 0; f < clip.frames.size(); ++f) {
    const auto X = forward_kinematics(k, clip.frames[f]);
    // Bone lengths are ours, every frame.
    for (int j = 1; j < kNumJoints; ++j) {
      const auto p = u(*parent(static_cast<Joint>(j)));
      ASSERT_NEAR((X[static_cast<size_t>(j)].translation - X[p].translation).norm(),
                  k.bone_length(static_cast<Joint>(j)), 1e-9) << "frame " << f << " joint " << j;
    }
    // Limb bones point where the source's do.
    const auto W = bvh_forward_kinematics(m, f);
    std::vector<Vec3> p;
    for (const core::Pose& w : W) p.push_back(y_up_to_z_up() * w.translation);
    for (size_t i = 0; i < m.joints.size(); ++i) {
      if (m.joints[i].has_end_site) p.push_back(y_up_to_z_up() * (W[i] * m.joints[i].end_site));
    }
    const JointTargets t = targets_from_named(convention, names, p);
    for (const auto& [a, b] : {std::pair{Joint::kLeftHip, Joint::kLeftKnee}, {Joint::kLeftKnee, Joint::kLeftAnkle},
                               {Joint::kRightKnee, Joint::kRightAnkle}, {Joint::kLeftShoulder, Joint::kLeftElbow},
                               {Joint::kRightElbow, Joint::kRightWrist}, {Joint::kSpine3, Joint::kNeck}}) {
      const Vec3 ours = (X[u(b)].translation - X[u(a)].translation).normalized();
      const Vec3 theirs = (t.joint[u(b)] - t.joint[u(a)]).normalized();
      ASSERT_GT(ours.dot(theirs), 1 - 1e-9) << "frame " << f << " bone to " << joint_name(b);
    }
    const double low = std::min(X[u(Joint::kLeftAnkle)].translation.z(), X[u(Joint::kRightAnkle)].translation.z());
    if (low < ankle_rest + 0.08) ++low_frames;
    lowest = std::min(lowest, low);
    // Head above pelvis.
    EXPECT_GT(X[u(Joint::kHead)].translation.z(), X[0].translation.z() + 0.3);
  }
  // Feet near the floor: never below it, and most frames have a foot down (the source's
  // ankles sit 3-4 cm higher than ours at rest).
  EXPECT_GT(lowest, ankle_rest - 0.01);
  EXPECT_LT(lowest, ankle_rest + 0.06);
  EXPECT_GT(low_frames, static_cast<int>(clip.frames.size() * 6 / 10));
  // Walks forward: more than 2 m of floor displacement, along the way the person faces
  // during the walk (frames 560-720).
  const Vec3 d = clip.frames.back().X_WP.translation - clip.frames.front().X_WP.translation;
  const Vec3 flat(d.x(), d.y(), 0);
  EXPECT_GT(flat.norm(), 2.0);
  for (size_t f = 560; f <= 720; f += 40) {
    const double yaw = facing_yaw(clip.frames[f]);
    EXPECT_GT((std::cos(yaw) * flat.x() + std::sin(yaw) * flat.y()) / flat.norm(), 0.85) << "frame " << f;
  }
  // Frame 1 (not a T-pose in this file, whatever the cgspeed notes say): arms hang at the
  // sides, the left arm on the person's left.
  const auto X0 = forward_kinematics(k, clip.frames[0]);
  const core::Pose& P = X0[0];
  for (const Side side : {Side::kLeft, Side::kRight}) {
    const Vec3 s = P.inverse() * X0[u(shoulder(side))].translation;
    const Vec3 w = P.inverse() * X0[u(wrist(side))].translation;
    EXPECT_LT(w.z(), s.z() - 0.2) << to_string(side);
    EXPECT_GT(side == Side::kLeft ? w.y() : -w.y(), 0.05) << to_string(side);
  }
  std::printf("height %.3f lowest %.3f ankle_rest %.3f displacement %.3f m over %.2f s\n", k.height,
              lowest, ankle_rest, flat.norm(), clip.duration());
}


// A small two-root file: a chain with a position channel on a child, End Sites, odd spacing.
constexpr const char* kSmall =
    "hierarchy\n"
    "ROOT Hips\n{\n  offset 1 2 3\n  CHANNELS 6 Xposition Yposition Zposition Xrotation Yrotation Zrotation\n"
    "  JOINT Upper Arm\n  {\n    OFFSET 0 1 0\n    CHANNELS 4 Zrotation Yposition Xrotation Yrotation\n"
    "    End Site forearm\n    {\n      OFFSET 0 2 0\n    }\n  }\n}\n"
    "ROOT Prop\n{\n  OFFSET 5 0 0\n  CHANNELS 3 Xposition Yposition Zposition\n}\n"
    "Motion\nFRAMES: 2\nframe time: 0.04\n"
    "0 0 0 0 0 0 0 0 0 0 0 0 0\n"
    "1 2 3 90 0 0 90 0.5 0 0 7 8 9\n";

std::string with_line_ends(std::string text, const std::string& end) {
  std::string out;
  for (const char c : text) {
    if (c == '\n') out += end;
    else out += c;
  }
  return out;
}

TEST(BvhTest, ParsesAnyLineEndingAndKeywordCase) {
  for (const std::string end : {"\n", "\r\n", "\r"}) {
    const BvhMotion m = parse_bvh(with_line_ends(kSmall, end), "small.bvh");
    ASSERT_EQ(m.joints.size(), 3u);
    EXPECT_EQ(m.joints[1].name, "Upper_Arm");  // several words joined with '_'
    EXPECT_EQ(m.joints[1].parent, 0);
    EXPECT_EQ(m.joints[2].parent, -1);  // a second ROOT
    EXPECT_TRUE(m.joints[1].has_end_site);
    EXPECT_EQ(m.num_channels, 13u);
    EXPECT_EQ(m.joints[2].first_channel, 10u);
    ASSERT_EQ(m.frames.size(), 2u);
    EXPECT_DOUBLE_EQ(bvh_fps(m.frame_time), 25.0);
  }
  // Errors count lines the same way whatever the line ends.
  for (const std::string end : {"\n", "\r\n", "\r"}) {
    std::string text = with_line_ends(kSmall, end);
    text.replace(text.find("OFFSET 0 2 0"), 12, "OFFSET 0 x 0");
    try {
      parse_bvh(text, "small.bvh");
      FAIL() << "no error";
    } catch (const core::InputError& e) {
      EXPECT_EQ(e.where(), "small.bvh:12");
      EXPECT_EQ(e.expected(), "a number (OFFSET y)");
    }
  }
}

TEST(BvhTest, RotationIsTheProductOfChannelsInListedOrder) {
  const BvhMotion m = parse_bvh(kSmall, "small.bvh");
  // Hips at frame 2: Xrotation 90 then Y 0 then Z 0 -> Rx(90).
  const core::Quat hips = bvh_local_rotation(m, 0, 1);
  EXPECT_TRUE(hips.isApprox(core::axis_angle(Vec3::UnitX(), core::kPi / 2), 1e-12));
  // Upper arm: Zrotation 90, Xrotation 0, Yrotation 0 -> Rz(90); its Yposition adds to OFFSET.
  const auto X = bvh_forward_kinematics(m, 1);
  EXPECT_TRUE(X[0].translation.isApprox(Vec3(2, 4, 6), 1e-12));       // OFFSET + position
  // Arm origin: hips origin + Rx(90) * (0, 1 + 0.5, 0).
  EXPECT_TRUE(X[1].translation.isApprox(Vec3(2, 4, 6 + 1.5), 1e-12));
  // End site: arm frame rotated Rx(90) Rz(90): (0, 2, 0) -> Rx(Rz (0,2,0)) = Rx(-2, 0, 0).
  EXPECT_TRUE((X[1] * m.joints[1].end_site).isApprox(Vec3(0, 4, 7.5), 1e-12));
  // A second root with only position channels.
  EXPECT_TRUE(X[2].translation.isApprox(Vec3(12, 8, 9), 1e-12));
  // Order matters: Z then X differs from X then Z.
  BvhMotion zx = m;
  zx.frames[1] = {0, 0, 0, 30, 40, 0, 0, 0, 0, 0, 0, 0, 0};
  const core::Quat q = bvh_local_rotation(zx, 0, 1);
  EXPECT_TRUE(q.isApprox(core::axis_angle(Vec3::UnitX(), core::deg_to_rad(30)) *
                         core::axis_angle(Vec3::UnitY(), core::deg_to_rad(40)), 1e-12));
}

TEST(BvhTest, FormatThenParseKeepsEverything) {
  const BvhMotion m = parse_bvh(kSmall, "small.bvh");
  const BvhMotion again = parse_bvh(format_bvh(m), "formatted.bvh");
  ASSERT_EQ(again.joints.size(), m.joints.size());
  for (size_t i = 0; i < m.joints.size(); ++i) {
    EXPECT_EQ(again.joints[i].name, m.joints[i].name);
    EXPECT_EQ(again.joints[i].parent, m.joints[i].parent);
    EXPECT_EQ(again.joints[i].channels, m.joints[i].channels);
    EXPECT_TRUE(again.joints[i].offset.isApprox(m.joints[i].offset));
  }
  EXPECT_EQ(again.frames, m.frames);
}

TEST(BvhTest, RoundTripOfOurSkeletonReproducesJointPositions) {
  const Clip clip = testing::synthetic_clip();
  for (const BvhRotationOrder order : {BvhRotationOrder::kZYX, BvhRotationOrder::kXYZ}) {
    const std::string text = format_bvh(bvh_from_clip(clip, order));
    const Clip back = clip_from_bvh(parse_bvh(text, "ours.bvh"), {}, "ours.bvh");
    ASSERT_EQ(back.frames.size(), clip.frames.size());
    EXPECT_DOUBLE_EQ(back.fps, 30.0);
    EXPECT_NEAR(back.skeleton.height, 1.8, 1e-6);
    const double err = testing::max_joint_error(clip, back);
    EXPECT_LT(err, 1e-3);
    std::printf("BVH %s round trip: max joint error %.3g m\n", order == BvhRotationOrder::kZYX ? "ZYX" : "XYZ", err);
  }
}

TEST(BvhTest, MixamoNamesImportTheSameMotion) {
  // Our BVH with every joint renamed the Mixamo way (with the "mixamorig:" prefix).
  const Clip clip = testing::synthetic_clip();
  BvhMotion m = bvh_from_clip(clip, BvhRotationOrder::kZYX);
  const std::map<std::string, std::string> rename = {
      {"pelvis", "Hips"}, {"spine1", "Spine"}, {"spine2", "Spine1"}, {"spine3", "Spine2"}, {"neck", "Neck"},
      {"head", "Head"}, {"left_collar", "LeftShoulder"}, {"left_shoulder", "LeftArm"},
      {"left_elbow", "LeftForeArm"}, {"left_wrist", "LeftHand"}, {"right_collar", "RightShoulder"},
      {"right_shoulder", "RightArm"}, {"right_elbow", "RightForeArm"}, {"right_wrist", "RightHand"},
      {"left_hip", "LeftUpLeg"}, {"left_knee", "LeftLeg"}, {"left_ankle", "LeftFoot"}, {"left_foot", "LeftToeBase"},
      {"right_hip", "RightUpLeg"}, {"right_knee", "RightLeg"}, {"right_ankle", "RightFoot"},
      {"right_foot", "RightToeBase"}};
  for (BvhJoint& j : m.joints) j.name = "mixamorig:" + rename.at(j.name);
  const Clip back = clip_from_bvh(parse_bvh(format_bvh(m), "mixamo.bvh"), {}, "mixamo.bvh");
  EXPECT_LT(testing::max_joint_error(clip, back), 1e-3);
}

// A hierarchy of `depth` nested joints (or `width` siblings under the root), one channel each.
std::string nested_bvh(int depth, int width) {
  std::string text = "HIERARCHY\nROOT r\n{\nOFFSET 0 0 0\nCHANNELS 1 Xposition\n";
  for (int i = 0; i < depth; ++i) text += "JOINT n" + std::to_string(i) + "\n{\nOFFSET 0 1 0\n";
  for (int i = 0; i < width; ++i) text += "JOINT w" + std::to_string(i) + "\n{\nOFFSET 0 1 0\n}\n";
  for (int i = 0; i < depth; ++i) text += "}\n";
  return text + "}\nMOTION\nFrames: 1\nFrame Time: 0.033\n0\n";
}

// Joints nested deeper than core::kMaxNestingDepth are refused where the parser recurses
// (100,000 nested joints used to overflow the stack).
TEST(BvhTest, DeeplyNestedJointsAreRefused) {
  EXPECT_EQ(parse_bvh(nested_bvh(31, 0), "ok.bvh").joints.size(), 32U);
  for (const int depth : {32, 100000}) {
    try {
      parse_bvh(nested_bvh(depth, 0), "deep.bvh");
      FAIL() << "no error";
    } catch (const core::InputError& e) {
      // The 33rd joint's JOINT keyword: 5 header lines, 3 lines per joint.
      EXPECT_EQ(std::string(e.what()), "deep.bvh:99: expected joints nested at most 32 deep, got deeper nesting");
    }
  }
}

// 60,000 sibling joints parse in linear time (the duplicate-name check was quadratic: 100 s),
// and a repeated name is still refused.
TEST(BvhTest, ManySiblingJointsParseQuicklyAndNamesStayUnique) {
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(parse_bvh(nested_bvh(0, 60000), "wide.bvh").joints.size(), 60001U);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 10.0);
  try {
    parse_bvh("HIERARCHY\nROOT r\n{\nOFFSET 0 0 0\nCHANNELS 1 Xposition\nJOINT r\n{\nOFFSET 0 0 0\n}\n}\n"
              "MOTION\nFrames: 1\nFrame Time: 0.033\n0\n", "twice.bvh");
    FAIL() << "no error";
  } catch (const core::InputError& e) {
    EXPECT_EQ(std::string(e.what()), "twice.bvh:6: expected unique joint names, got a second joint 'r'");
  }
}

TEST(BvhTest, UnknownSkeletonIsAClearError) {
  try {
    clip_from_bvh(parse_bvh(kSmall, "small.bvh"), {}, "small.bvh");
    FAIL() << "no error";
  } catch (const core::InputError& e) {
    EXPECT_EQ(e.where(), "small.bvh");
    EXPECT_THAT(e.got(), ::testing::HasSubstr("missing"));
  }
}

}  // namespace
}  // namespace hribench::human

#include "human/clip_io.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "core/errors.h"
#include "human/bvh.h"
#include "human/npy.h"
#include "human/smplh.h"
#include "human/motion_fixtures.h"

namespace hribench::human {
namespace {

namespace fs = std::filesystem;
using core::Vec3;

// A directory of this test and process alone, so parallel runs (other build dirs) never share one.
fs::path temp_dir() {
  const std::string test = ::testing::UnitTest::GetInstance()->current_test_info()->name();
  const fs::path dir =
      fs::path(::testing::TempDir()) / ("hribench_clip_io_test_" + test + "_" + std::to_string(getpid()));
  fs::create_directories(dir);
  return dir;
}

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The malformed-input corpus: every file gives one clear InputError naming the file and the
// position (line, byte offset or key).
struct BadFile {
  const char* file;
  const char* message;  // what(), after "tests/data/motion/bad/"
};
constexpr BadFile kCorpus[] = {
    {"bvh_absurd_frame_rate.bvh",
     "bvh_absurd_frame_rate.bvh:18: expected a frame time giving 1 to 1000 frames per second, got 0.000001 s (1e+06 fps)"},
    {"bvh_bad_channel_name.bvh",
     "bvh_bad_channel_name.bvh:9: expected channel 2 of 3: Xposition, Yposition, Zposition, Xrotation, Yrotation or Zrotation, got 'Wrotation'"},
    {"bvh_channel_count_too_big.bvh",
     "bvh_channel_count_too_big.bvh:9: expected a channel count from 0 to 6, got '7'"},
    {"bvh_crlf_short_frame.bvh",
     "bvh_crlf_short_frame.bvh:19: expected 9 values in frame 1 (one per channel), got 4"},
    {"bvh_duplicate_joint.bvh",
     "bvh_duplicate_joint.bvh:6: expected unique joint names, got a second joint 'Hips'"},
    {"bvh_empty.bvh",
     "bvh_empty.bvh:1: expected HIERARCHY, got end of file"},
    {"bvh_extra_frames.bvh",
     "bvh_extra_frames.bvh:20: expected 1 frames (Frames: at line 17), got more frame lines"},
    {"bvh_inf_offset.bvh",
     "bvh_inf_offset.bvh:8: expected a finite number (OFFSET x), got 'inf'"},
    {"bvh_missing_brace.bvh",
     "bvh_missing_brace.bvh:7: expected '{', got 'OFFSET'"},
    {"bvh_missing_frame_time.bvh",
     "bvh_missing_frame_time.bvh:18: expected 'Frame Time:', got '0'"},
    {"bvh_missing_frames.bvh",
     "bvh_missing_frames.bvh:17: expected 'Frames:', got 'Frame'"},
    {"bvh_nan_value.bvh",
     "bvh_nan_value.bvh:20: expected a finite number (value 4 of frame 2), got 'nan'"},
    {"bvh_negative_frames.bvh",
     "bvh_negative_frames.bvh:17: expected a frame count from 1 to 10000000 after 'Frames:', got '-3'"},
    {"bvh_no_hierarchy.bvh",
     "bvh_no_hierarchy.bvh:1: expected HIERARCHY, got 'ROOT'"},
    {"bvh_overflow_value.bvh",
     "bvh_overflow_value.bvh:19: expected a finite number (value 9 of frame 1), got '1e999'"},
    {"bvh_truncated_hierarchy.bvh",
     "bvh_truncated_hierarchy.bvh:9: expected JOINT, End Site or '}', got end of file"},
    {"bvh_truncated_motion.bvh",
     "bvh_truncated_motion.bvh:20: expected 5 frames (Frames: at line 17), got 2 (the file ends)"},
    {"bvh_unknown_skeleton.bvh",
     "bvh_unknown_skeleton.bvh: expected joint names of a known skeleton (smpl, smpl_short, mixamo, cmu_motionbuilder, cmu), got 3 joints; closest is cmu_motionbuilder, missing leftupleg, rightupleg, leftleg, rightleg, spine1, leftfoot, ..."},
    {"bvh_wrong_channel_count.bvh",
     "bvh_wrong_channel_count.bvh:20: expected 9 values in frame 2 (one per channel), got 8"},
    {"bvh_zero_frame_time.bvh",
     "bvh_zero_frame_time.bvh:18: expected a positive frame time in seconds, got '0'"},
    {"clip_truncated.json",
     "clip_truncated.json:3:1: invalid JSON ([json.exception.parse_error.101] parse error at line 3, column 1: syntax error while parsing object key - unexpected end of input; expected string literal)"},
    {"clip_wrong_joints.json",
     "clip_wrong_joints.json: joints: expected an array of 22 entries, got []"},
    {"npy_bad_header.npy",
     "npy_bad_header.npy: byte 60: expected a shape tuple '(...)', got '['"},
    {"npy_bad_magic.npy",
     "npy_bad_magic.npy: byte 0: expected the .npy magic \\x93NUMPY, got other bytes"},
    {"npy_complex_dtype.npy",
     "npy_complex_dtype.npy: byte 10: expected dtype float32, float64, int32 or int64 ('<f4', '<f8', '<i4', '<i8'), got '<c16'"},
    {"npy_fortran_order.npy",
     "npy_fortran_order.npy: byte 10: expected C order (fortran_order False), got fortran_order True"},
    {"npy_nan_value.npy",
     "npy_nan_value.npy: byte 408: expected finite joint positions, got nan (frame 1, joint 1, axis 1)"},
    {"npy_pickled_objects.npy",
     "npy_pickled_objects.npy: byte 10: expected a numeric array, got dtype 'O' (pickled Python objects, refused)"},
    {"npy_truncated_data.npy",
     "npy_truncated_data.npy: byte 128: expected 528 bytes of data (132 values), got 518 bytes (truncated)"},
    {"npy_truncated_header.npy",
     "npy_truncated_header.npy: byte 10: expected a header of 118 bytes, got 30 bytes (truncated)"},
    {"npy_unsupported_dtype.npy",
     "npy_unsupported_dtype.npy: byte 10: expected dtype float32, float64, int32 or int64 ('<f4', '<f8', '<i4', '<i8'), got '<i2'"},
    {"npy_wrong_joint_count.npy",
     "npy_wrong_joint_count.npy: byte 0 (header): expected shape (frames, 22, 3), got (2, 21, 3)"},
    {"npz_bad_crc.npz",
     "npz_bad_crc.npz[poses.npy]: expected an intact zip member, got CRC error"},
    {"npz_corrupt_deflate.npz",
     "npz_corrupt_deflate.npz[poses.npy]: expected an intact zip member, got Zlib error: data error"},
    {"npz_inf_trans.npz",
     "npz_inf_trans.npz[trans.npy]: byte 136: expected finite values, got inf at index 1"},
    {"npz_missing_poses.npz",
     "npz_missing_poses.npz[poses]: expected an array 'poses', got keys trans"},
    {"npz_not_a_zip.npz",
     "npz_not_a_zip.npz: expected a zip archive (npz), got Not a zip archive"},
    {"npz_pickled_poses.npz",
     "npz_pickled_poses.npz[poses.npy]: byte 10: expected a numeric array, got dtype 'O' (pickled Python objects, refused)"},
    {"npz_poses_wrong_shape.npz",
     "npz_poses_wrong_shape.npz[poses.npy]: expected shape (frames, 3 x joints) with at least 22 joints (156 for SMPL-H), got (3, 10)"},
    {"npz_truncated.npz",
     "npz_truncated.npz: expected a zip archive (npz), got Not a zip archive"},
};

TEST(ClipIoTest, MalformedCorpusGivesTheExpectedErrors) {
  size_t files = 0;
  for (const auto& entry : fs::directory_iterator("tests/data/motion/bad")) {
    (void)entry;
    ++files;
  }
  EXPECT_EQ(files, std::size(kCorpus)) << "every corpus file has a row in the table";
  EXPECT_GE(std::size(kCorpus), 20u);
  for (const BadFile& bad : kCorpus) {
    const std::string path = std::string("tests/data/motion/bad/") + bad.file;
    try {
      read_clip(path);
      ADD_FAILURE() << path << ": no error";
    } catch (const core::InputError& e) {
      EXPECT_EQ(std::string(e.what()), "tests/data/motion/bad/" + std::string(bad.message)) << path;
    }
  }
}

TEST(ClipIoTest, JsonRoundTripIsExact) {
  Clip clip = testing::synthetic_clip();
  clip.frames[3].hands[0] = {0.75, 1.0 / 3.0};
  const Clip back = parse_clip_json(format_clip_json(clip), "clip.json");
  EXPECT_EQ(back.skeleton.height, clip.skeleton.height);
  EXPECT_EQ(back.fps, clip.fps);
  EXPECT_EQ(back.active_hand, clip.active_hand);
  ASSERT_EQ(back.phases.size(), 2u);
  EXPECT_EQ(back.phases[1].name, "middle");
  EXPECT_EQ(back.phases[1].start, 0.4);
  ASSERT_EQ(back.frames.size(), clip.frames.size());
  for (size_t f = 0; f < clip.frames.size(); ++f) {
    EXPECT_EQ(back.frames[f].X_WP.translation, clip.frames[f].X_WP.translation);
    for (size_t j = 1; j < clip.frames[f].local.size(); ++j) {
      EXPECT_TRUE(back.frames[f].local[j].isApprox(clip.frames[f].local[j], 1e-15));
    }
    EXPECT_EQ(back.frames[f].hands, clip.frames[f].hands);
  }
  EXPECT_LT(testing::max_joint_error(clip, back), 1e-12);
}

TEST(ClipIoTest, JsonErrorsNameTheKeyPath) {
  std::string text = format_clip_json(testing::synthetic_clip());
  text.replace(text.find("\"fps\":30.0"), 10, "\"fps\":\"x\"");
  try {
    parse_clip_json(text, "c.json");
    FAIL() << "no error";
  } catch (const core::InputError& e) {
    EXPECT_EQ(e.where(), "c.json: fps");
    EXPECT_EQ(e.expected(), "a number");
  }
}

// Hand shapes are optional (a converted motion-capture clip has none) and within [0, 1].
TEST(ClipIoTest, HandShapesAreOptionalAndChecked) {
  Clip clip = testing::synthetic_clip();
  clip.frames[0].hands[1] = {0, 1};
  std::string text = format_clip_json(clip);
  const std::string shape = R"({"grip":0.0,"point":1.0})";
  ASSERT_NE(text.find(shape), std::string::npos);
  std::string wrong = text;
  wrong.replace(wrong.find(shape), shape.size(), R"({"grip":0.0,"point":1.5})");
  try {
    parse_clip_json(wrong, "c.json");
    FAIL() << "no error";
  } catch (const core::InputError& e) {
    EXPECT_STREQ(e.what(), "c.json: frames[0].hands[1].point: expected a number in [0, 1], got 1.5");
  }
  // Without "hands", frames have open hands.
  std::string none = text;
  // Keys are written in order ("hands", "local", "root"): drop each `"hands":[...],`.
  for (size_t at = none.find(R"("hands":)"); at != std::string::npos; at = none.find(R"("hands":)")) {
    none.erase(at, none.find("]", at) + 2 - at);
  }
  const Clip back = parse_clip_json(none, "c.json");
  EXPECT_EQ(back.frames[0].hands[1], (HandShape{}));
  EXPECT_LT(testing::max_joint_error(clip, back), 1e-12);
}

TEST(ClipIoTest, HumanMl3dRoundTripReproducesJointPositions) {
  const Clip clip = testing::synthetic_clip();
  const fs::path path = temp_dir() / "walk.npy";
  write_clip(clip, path);
  // HumanML3D layout: float32 (F, 22, 3), y-up: the pelvis height is the y column.
  const NpyArray a = read_npy(path);
  EXPECT_EQ(a.descr, "<f4");
  EXPECT_EQ(a.shape, (std::vector<size_t>{40, 22, 3}));
  EXPECT_NEAR(a.values[1], clip.frames[0].X_WP.translation.z(), 1e-6);
  const Clip back = read_clip(path);
  EXPECT_EQ(back.fps, 30.0);  // from the sidecar
  EXPECT_NEAR(back.skeleton.height, clip.skeleton.height, 1e-5);
  const double err = testing::max_joint_error(clip, back);
  EXPECT_LT(err, 1e-3);
  std::printf("npy round trip: max joint error %.3g m\n", err);
  // Without the sidecar: HumanML3D's 20 fps.
  fs::remove(fs::path(path.string() + ".json"));
  EXPECT_EQ(read_clip(path).fps, 20.0);
}

TEST(ClipIoTest, HumanMl3dConventionFacesForwardWithLeftOnTheLeft) {
  // A HumanML3D-style file written independently of our writer: the SMPL T-pose in its own
  // y-up frame (x = the body's left, z = forward), pelvis 0.9 m up, two frames.
  std::array<Vec3, kNumJoints> zero_pose;
  zero_pose.fill(Vec3::Zero());
  const JointTargets t = smpl_forward_kinematics(zero_pose, Vec3(0, 0.9 + 0.2233, 0));
  std::vector<double> values;
  for (int f = 0; f < 2; ++f) {
    for (const Vec3& p : t.joint) values.insert(values.end(), {p.x(), p.y(), p.z() + 0.1 * f});
  }
  const Clip clip = parse_humanml3d(format_npy({2, 22, 3}, values, NpyType::kFloat32), 20, {}, "h.npy");
  EXPECT_EQ(clip.fps, 20.0);
  EXPECT_NEAR(facing_yaw(clip.frames[0]), 0.0, 0.05);  // file +z = our +x
  const auto X = forward_kinematics(clip.skeleton, clip.frames[0]);
  EXPECT_GT(X[static_cast<size_t>(index(Joint::kLeftWrist))].translation.y(), 0.5);   // T-pose, left arm +y
  EXPECT_LT(X[static_cast<size_t>(index(Joint::kRightWrist))].translation.y(), -0.5);
  EXPECT_GT(clip.frames[1].X_WP.translation.x(), clip.frames[0].X_WP.translation.x());  // moves forward
}

TEST(ClipIoTest, BvhAndNpzThroughWriteAndRead) {
  const Clip clip = testing::synthetic_clip();
  for (const char* name : {"walk.bvh", "walk.npz", "walk.json"}) {
    const fs::path path = temp_dir() / name;
    write_clip(clip, path);
    RetargetOptions options;
    options.height = clip.skeleton.height;
    options.ground = false;
    const Clip back = read_clip(path, options);
    EXPECT_EQ(back.frames.size(), clip.frames.size()) << name;
    const double err = testing::max_joint_error(clip, back);
    EXPECT_LT(err, 1e-3) << name;
    std::printf("%s round trip: max joint error %.3g m\n", name, err);
  }
  // BVH text is deterministic.
  write_clip(clip, temp_dir() / "again.bvh");
  EXPECT_EQ(slurp(temp_dir() / "walk.bvh"), slurp(temp_dir() / "again.bvh"));
}

TEST(ClipIoTest, UnknownExtensionsAndUnwritablePathsAreInputErrors) {
  const Clip clip = testing::synthetic_clip();
  EXPECT_THROW(write_clip(clip, temp_dir() / "walk.fbx"), core::InputError);
  EXPECT_THROW(write_clip(clip, "/nonexistent-dir/x/walk.json"), core::InputError);
  EXPECT_THROW(read_clip(temp_dir() / "missing.bvh"), core::InputError);
  EXPECT_THROW(read_clip("tests/data/motion/make_fixtures.py"), core::InputError);
}

// Every prefix and every single-byte corruption of valid files is either read or refused with
// an InputError: never a crash, never another exception.
TEST(ClipIoTest, TruncatedOrCorruptedFilesNeverCrash) {
  const std::string npz = slurp("tests/data/motion/hy_motion_like.npz");
  const std::string npy = format_humanml3d(testing::synthetic_clip());
  const std::string bvh = format_bvh(bvh_from_clip(testing::synthetic_clip(), BvhRotationOrder::kZYX)).substr(0, 4000);
  int refused = 0, read = 0;
  const auto attempt = [&](const std::string& bytes, const char* name) {
    const std::string_view ext = std::string_view(name).substr(std::string_view(name).size() - 3);
    try {
      if (ext == "npz") clip_from_smplh(NpzArchive(bytes, name), {}, name);
      else if (ext == "npy") parse_humanml3d(bytes, 20, {}, name);
      else clip_from_bvh(parse_bvh(bytes, name), {}, name);
      ++read;
    } catch (const core::InputError&) {
      ++refused;
    }
  };
  for (size_t n = 0; n < npz.size(); n += 3) attempt(npz.substr(0, n), "cut.npz");
  for (size_t i = 0; i < npz.size(); ++i) {
    std::string bad = npz;
    bad[i] = static_cast<char>(bad[i] ^ 0x5a);
    attempt(bad, "flip.npz");
  }
  for (size_t n = 0; n < 400; n += 7) attempt(npy.substr(0, n), "cut.npy");
  for (size_t i = 0; i < 200; ++i) {
    std::string bad = npy;
    bad[i] = static_cast<char>(bad[i] ^ 0x5a);
    attempt(bad, "flip.npy");
  }
  const size_t motion = bvh.find("MOTION");
  for (size_t n = 0; n < motion + 40; n += 11) attempt(bvh.substr(0, n), "cut.bvh");
  // BVH flips, in a whole file (three frames) so that a harmless flip still reads: 0x5a turns
  // digits and spaces into letters, 0x01 turns digits into other digits (channel counts, the
  // frame count, the frame time, offsets and angles change value).
  const int refused_before_bvh_flips = refused, read_before_bvh_flips = read;
  Clip short_clip = testing::synthetic_clip();
  short_clip.frames.resize(3);
  short_clip.phases.clear();
  const std::string whole_bvh = format_bvh(bvh_from_clip(short_clip, BvhRotationOrder::kZYX));
  for (const char mask : {'\x5a', '\x01'}) {
    for (size_t i = 0; i < whole_bvh.size(); ++i) {
      std::string bad = whole_bvh;
      bad[i] = static_cast<char>(bad[i] ^ mask);
      attempt(bad, "flip.bvh");
    }
  }
  EXPECT_GT(refused, refused_before_bvh_flips);  // letters where numbers belong, bad names
  EXPECT_GT(read, read_before_bvh_flips);        // changed angles and offsets still read
  EXPECT_GT(refused, 500);
  EXPECT_GT(read, 0);  // flips in unused bytes (names, padding) still read
}

}  // namespace
}  // namespace hribench::human

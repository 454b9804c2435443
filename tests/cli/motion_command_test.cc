// Tests of `hribench motion`: primitives and files in, clips and pictures out; bad input is one
// line and exit 2.

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <string>

#include "human/clip_io.h"
#include "render/png.h"
#include "support/run_command.h"

namespace hribench::cli {
namespace {

using ::hribench::testing::count_lines;
using ::hribench::testing::run_hribench;
namespace fs = std::filesystem;

// A directory of this test and process alone, so parallel runs (other build dirs) never share one.
fs::path out_dir() {
  const std::string test = ::testing::UnitTest::GetInstance()->current_test_info()->name();
  const fs::path dir = fs::path(::testing::TempDir()) /
                       ("hribench_motion_command_test_" + test + "_" + std::to_string(getpid()));
  fs::create_directories(dir);
  return dir;
}

TEST(MotionCommandTest, GeneratesAPrimitiveAndRendersAStrip) {
  const fs::path clip = out_dir() / "point.json";
  const fs::path png = out_dir() / "point.png";
  const auto r = run_hribench("motion point --param hand=left --param target=1.0,0.5,1.3 --out " + clip.string() +
                              " --render " + png.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("phases prep["), std::string::npos) << r.output;
  const human::Clip c = human::read_clip(clip);
  EXPECT_EQ(c.active_hand, human::Side::kLeft);
  EXPECT_NE(c.phase("stroke"), nullptr);
  const render::Image image = render::read_png(png.string());
  EXPECT_EQ(image.width, 6 * 240);
  EXPECT_EQ(image.height, 420);
}

TEST(MotionCommandTest, ImportsTheCmuClipPlacedAndSlowed) {
  const fs::path out = out_dir() / "cmu.bvh";
  const auto r = run_hribench("motion tests/data/motion/cmu_131_01.bvh --place 1,2,90 --time-scale 2 --out " +
                              out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const human::Clip c = human::read_clip(out);
  EXPECT_EQ(c.fps, 120.0);
  EXPECT_EQ(c.frames.size(), 2u * 993u + 1u);
  EXPECT_NEAR(c.frames[0].X_WP.translation.x(), 1.0, 1e-4);
  EXPECT_NEAR(c.frames[0].X_WP.translation.y(), 2.0, 1e-4);
}

TEST(MotionCommandTest, UnknownPrimitiveIsOneLine) {
  const auto r = run_hribench("motion frobnicate --out " + (out_dir() / "x.json").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_NE(r.output.find("expected a primitive (idle, walk_to, reach"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("got 'frobnicate'"), std::string::npos) << r.output;
}

TEST(MotionCommandTest, MissingOutIsOneLine) {
  const auto r = run_hribench("motion point");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_NE(r.output.find("--out"), std::string::npos) << r.output;
}

TEST(MotionCommandTest, UnwritablePathIsOneLine) {
  const auto r = run_hribench("motion point --out /nonexistent-dir/sub/point.json");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_NE(r.output.find("/nonexistent-dir/sub/point.json: cannot write"), std::string::npos) << r.output;
}

TEST(MotionCommandTest, BadParametersAndFilesAreOneLine) {
  const std::string out = " --out " + (out_dir() / "x.json").string();
  auto r = run_hribench("motion point --param target=1,2" + out);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_NE(r.output.find("--param target: expected 3 comma-separated numbers, got '1,2'"), std::string::npos) << r.output;
  r = run_hribench("motion point --param wingspan=2" + out);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--param wingspan: expected a parameter of point ("), std::string::npos) << r.output;
  r = run_hribench("motion point --param hand=middle" + out);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  r = run_hribench("motion tests/data/motion/bad/bvh_nan_value.bvh" + out);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_NE(r.output.find("bvh_nan_value.bvh:20: expected a finite number"), std::string::npos) << r.output;
  r = run_hribench("motion point --out " + (out_dir() / "x.fbx").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("expected an output file ending in .json, .bvh, .npy or .npz"), std::string::npos) << r.output;
}

// Out-of-range flags are one line naming the flag, the range and the value: never an internal
// check failure (fps <= 0) or an unbounded allocation (huge fps or time scale).
TEST(MotionCommandTest, OutOfRangeFlagsAreOneLine) {
  const std::string out = " --out " + (out_dir() / "x.json").string();
  const struct {
    const char* flags;
    const char* message;
  } cases[] = {
      {"--fps 0", "--fps: expected a frame rate in (0, 1000] fps, got 0"},
      {"--fps=-5", "--fps: expected a frame rate in (0, 1000] fps, got -5"},
      {"--fps 1e9", "--fps: expected a frame rate in (0, 1000] fps, got 1000000000"},
      {"--time-scale 0", "--time-scale: expected a factor in (0, 100], got 0"},
      {"--time-scale=-2", "--time-scale: expected a factor in (0, 100], got -2"},
      {"--time-scale 1e12", "--time-scale: expected a factor in (0, 100], got 1000000000000"},
      {"--height 0.5", "--height: expected a standing height in [1.0, 2.5] m, got 0.5"},
      {"--height 3", "--height: expected a standing height in [1.0, 2.5] m, got 3"},
      {"--unit 0", "--unit: expected a positive number of metres per file unit (e.g. 0.01), got 0"},
      {"--unit=-0.01", "--unit: expected a positive number of metres per file unit (e.g. 0.01), got -0.01"},
  };
  for (const auto& c : cases) {
    for (const char* source : {"point", "tests/data/motion/cmu_131_01.bvh"}) {
      const auto r = run_hribench(std::string("motion ") + source + " " + c.flags + out);
      EXPECT_EQ(r.exit_code, 2) << c.flags << " " << source << ": " << r.output;
      EXPECT_EQ(count_lines(r.output), 1) << c.flags << " " << source << ": " << r.output;
      EXPECT_NE(r.output.find(c.message), std::string::npos) << c.flags << " " << source << ": " << r.output;
    }
  }
}

// The edges of the ranges are accepted.
TEST(MotionCommandTest, FlagsAtTheirLimitsAreAccepted) {
  const auto r = run_hribench("motion idle --param duration=0.1 --fps 1000 --time-scale 0.5 --height 2.5 --out " +
                              (out_dir() / "edge.json").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const human::Clip c = human::read_clip(out_dir() / "edge.json");
  EXPECT_EQ(c.fps, 1000.0);
  EXPECT_DOUBLE_EQ(c.skeleton.height, 2.5);
}

}  // namespace
}  // namespace hribench::cli

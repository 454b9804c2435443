// Tests of `hribench render`: a small still is written and readable; every kind of bad input
// (unknown flag, impossible size, unknown camera, unwritable path, unknown or none back end,
// no usable GL context) is one clear line and exit code 2.

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "render/png.h"
#include "support/run_command.h"

namespace hribench::cli {
namespace {

using ::hribench::testing::count_lines;
using ::hribench::testing::run_hribench;

// A temporary PNG path unique to this process (test programs may run in parallel).
std::string temp_png(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          (std::to_string(getpid()) + "_" + name))
      .string();
}

// Runs `args` and expects exit 2 with exactly the one line "hribench: error: <message>".
void expect_one_line_error(const std::string& args, const std::string& message) {
  const auto r = run_hribench(args);
  EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.output;
  EXPECT_EQ(count_lines(r.output), 1) << args << "\n" << r.output;
  EXPECT_EQ(r.output, "hribench: error: " + message + "\n") << args;
}

TEST(RenderCommandTest, WritesAReadablePng) {
  const std::string out = temp_png("hribench_render_command_test.png");
  std::remove(out.c_str());
  const auto r = run_hribench("render --out " + out + " --width 64 --height 48 --camera wrist");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("wrote " + out + " (64x48, camera wrist, osmesa: "), std::string::npos)
      << r.output;
  const render::Image image = render::read_png(out);
  EXPECT_EQ(image.width, 64);
  EXPECT_EQ(image.height, 48);
  std::remove(out.c_str());
}

TEST(RenderCommandTest, UnknownFlagIsOneLine) {
  const auto r = run_hribench("render --out x.png --shadows");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_NE(r.output.find("--shadows"), std::string::npos) << r.output;
}

TEST(RenderCommandTest, ImpossibleSizesAreOneLine) {
  const std::string out = temp_png("hribench_render_command_size.png");
  expect_one_line_error("render --out " + out + " --width 0",
                        "--width: expected an image side in [1, 4096] pixels, got 0");
  expect_one_line_error("render --out " + out + " --height -5",
                        "--height: expected an image side in [1, 4096] pixels, got -5");
  expect_one_line_error("render --out " + out + " --width 5000",
                        "--width: expected an image side in [1, 4096] pixels, got 5000");
  EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(RenderCommandTest, UnknownCameraNamesTheCameras) {
  expect_one_line_error("render --out " + temp_png("hribench_render_command_cam.png") +
                            " --width 8 --height 8 --camera ceiling",
                        "--camera: expected one of agentview, wrist, got 'ceiling'");
}

TEST(RenderCommandTest, UnwritablePathIsOneLine) {
  expect_one_line_error("render --out /nonexistent-dir/scene.png",
                        "--out: cannot write '/nonexistent-dir/scene.png' (No such file or "
                        "directory)");
  expect_one_line_error("render --out " + std::filesystem::temp_directory_path().string(),
                        "--out: expected a file path, got the directory '" +
                            std::filesystem::temp_directory_path().string() + "'");
}

TEST(RenderCommandTest, BadBackendsAreOneLine) {
  const std::string out = temp_png("hribench_render_command_backend.png");
  expect_one_line_error("render --out " + out + " --backend vulkan",
                        "--backend: expected one of osmesa, egl, none, got 'vulkan'");
  expect_one_line_error("render --out " + out + " --backend none",
                        "--backend: expected osmesa or egl (render writes an image), got 'none'");
}

TEST(RenderCommandTest, NoUsableGlContextIsOneLine) {
  // Point the OSMesa loader at a library that does not exist.
  setenv("HRIBENCH_OSMESA_LIBRARY", "libhribench-no-such-osmesa.so", 1);
  const auto r = run_hribench("render --out " + temp_png("hribench_render_command_gl.png") +
                              " --width 8 --height 8");
  unsetenv("HRIBENCH_OSMESA_LIBRARY");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_EQ(r.output.rfind("hribench: error: osmesa: no usable GL context: cannot load the "
                           "platform library (libhribench-no-such-osmesa.so: ",
                           0),
            0u)
      << r.output;
}

TEST(RenderCommandTest, EglRendersOrSaysWhyNot) {
  // Machines without an EGL device must still give one clear line; where EGL works (Mesa's
  // software device, or a GPU), the still is written.
  const std::string out = temp_png("hribench_render_command_egl.png");
  std::remove(out.c_str());
  const auto r = run_hribench("render --backend egl --out " + out + " --width 32 --height 24");
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  if (r.exit_code == 0) {
    EXPECT_NE(r.output.find("wrote " + out + " (32x24, camera agentview, egl: "),
              std::string::npos)
        << r.output;
    EXPECT_EQ(render::read_png(out).width, 32);
  } else {
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_EQ(r.output.rfind("hribench: error: egl: no usable GL context: ", 0), 0u) << r.output;
  }
  std::remove(out.c_str());
}

}  // namespace
}  // namespace hribench::cli

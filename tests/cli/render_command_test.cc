// Tests of `hribench render`: a small still is written and readable; every kind of bad input
// (unknown flag, impossible size, unknown camera, unwritable path, unknown or none back end,
// no usable GL context) is one clear line and exit code 2; --mujoco-shapes changes only edge
// pixels. Task moments (--task/--at): a still of an event moment is written, is not blank and
// differs from the episode's start; bad --at, unknown events, bad task files and misplaced
// options are one line and exit code 2.

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
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

// Runs `args`, expects exit 2 and one line of output, and returns that output.
std::string one_line_error_output(const std::string& args) {
  const auto r = run_hribench(args);
  EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.output;
  EXPECT_EQ(count_lines(r.output), 1) << args << "\n" << r.output;
  return r.output;
}

// Runs `args` and expects exit 2 with exactly the one line "hribench: error: <message>".
void expect_one_line_error(const std::string& args, const std::string& message) {
  EXPECT_EQ(one_line_error_output(args), "hribench: error: " + message + "\n") << args;
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

// --mujoco-shapes draws capsules, spheres and cylinders as MuJoCo does: the same view with other
// edge pixels (docs/rendering.md "Shapes"); the rest of the image is ours.
TEST(RenderCommandTest, MujocoShapesChangeOnlyTheShapesEdges) {
  const std::string ours = temp_png("hribench_render_ours.png");
  const std::string mujoco = temp_png("hribench_render_mujoco_shapes.png");
  const std::string args = " --width 224 --height 224 --camera agentview";
  ASSERT_EQ(run_hribench("render --out " + ours + args).exit_code, 0);
  const auto r = run_hribench("render --mujoco-shapes --out " + mujoco + args);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const render::Image a = render::read_png(ours);
  const render::Image b = render::read_png(mujoco);
  ASSERT_EQ(a.rgb.size(), b.rgb.size());
  size_t differ = 0;
  for (size_t i = 0; i < a.rgb.size(); i += 3) {
    differ += std::equal(a.rgb.begin() + static_cast<long>(i), a.rgb.begin() + static_cast<long>(i + 3),
                         b.rgb.begin() + static_cast<long>(i)) ? 0 : 1;
  }
  EXPECT_GT(differ, 0U);
  EXPECT_LT(differ, a.rgb.size() / 3 / 10);
  std::remove(ours.c_str());
  std::remove(mujoco.c_str());
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
                        "--camera: expected one of agentview, wrist, free, got 'ceiling'");
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

// Distinct pixel colours of an image (a blank or one-colour image has 1).
size_t distinct_colours(const render::Image& image) {
  std::set<uint32_t> colours;
  for (size_t i = 0; i + 2 < image.rgb.size(); i += 3) {
    colours.insert(static_cast<uint32_t>(image.rgb[i]) << 16 |
                   static_cast<uint32_t>(image.rgb[i + 1]) << 8 | image.rgb[i + 2]);
  }
  return colours.size();
}

constexpr const char* kPointPick = "tasks/I1_point_pick.yaml";

// I1 with an 8 s horizon (its pointing ends by then), in a temporary file: for the moments
// that need the whole episode run (an unknown event, a moment past the horizon).
std::string short_point_pick() {
  std::ifstream in(kPointPick);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const size_t at = text.find("\nhorizon: 30\n");
  EXPECT_NE(at, std::string::npos);
  const std::string path = temp_png("I1_short.yaml");
  std::ofstream(path) << text.substr(0, at) << "\nhorizon: 8\n"
                      << text.substr(at + std::string("\nhorizon: 30\n").size());
  return path;
}

TEST(RenderCommandTest, TaskEventMomentIsRenderedAndDiffersFromTheStart) {
  const std::string start = temp_png("hribench_render_task_start.png");
  const std::string stroke = temp_png("hribench_render_task_stroke.png");
  const std::string common = std::string(" --task ") + kPointPick +
                             " --seed 3 --camera free --width 96 --height 72";
  const auto r0 = run_hribench("render --out " + start + common + " --at 0");
  ASSERT_EQ(r0.exit_code, 0) << r0.output;
  EXPECT_NE(r0.output.find("; I1_point_pick seed 3, noop, t = 0 s -> t = 0.00 s"),
            std::string::npos)
      << r0.output;
  const auto r1 = run_hribench("render --out " + stroke + common + " --at point.hold+0.2");
  ASSERT_EQ(r1.exit_code, 0) << r1.output;
  EXPECT_EQ(count_lines(r1.output), 1) << r1.output;
  EXPECT_NE(r1.output.find("wrote " + stroke + " (96x72, camera free, osmesa: "),
            std::string::npos)
      << r1.output;
  EXPECT_NE(r1.output.find("noop, point.hold at "), std::string::npos) << r1.output;

  const render::Image a = render::read_png(start);
  const render::Image b = render::read_png(stroke);
  ASSERT_EQ(b.width, 96);
  ASSERT_EQ(b.height, 72);
  // Not blank: the table, robot, objects and person give many colours.
  EXPECT_GT(distinct_colours(b), 50u);
  // The person has moved (the pointing arm is up): many pixels changed since the start.
  size_t changed = 0;
  ASSERT_EQ(a.rgb.size(), b.rgb.size());
  for (size_t i = 0; i < a.rgb.size(); ++i) changed += a.rgb[i] != b.rgb[i] ? 1 : 0;
  EXPECT_GT(changed, 30u);
  std::remove(start.c_str());
  std::remove(stroke.c_str());
}

TEST(RenderCommandTest, TaskMomentIsDeterministic) {
  const std::string a = temp_png("hribench_render_task_det_a.png");
  const std::string b = temp_png("hribench_render_task_det_b.png");
  const std::string args = std::string(" --task ") + kPointPick +
                           " --seed 2 --policy random?seed=4 --width 48 --height 36 --at 1.5";
  ASSERT_EQ(run_hribench("render --out " + a + args).exit_code, 0);
  const auto r = run_hribench("render --out " + b + args);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("random?seed=4, t = 1.5 s -> t = 1.50 s"), std::string::npos)
      << r.output;
  EXPECT_EQ(render::read_png(a).rgb, render::read_png(b).rgb);
  std::remove(a.c_str());
  std::remove(b.c_str());
}

TEST(RenderCommandTest, BadMomentsAreOneLine) {
  const std::string out = temp_png("hribench_render_task_bad_at.png");
  const std::string task = std::string(" --task ") + kPointPick + " --width 8 --height 8";
  const std::string expected = "a time in seconds or an event of the episode, optionally +S";
  expect_one_line_error("render --out " + out + task + " --at -1",
                        "--at: expected " + expected + ", got '-1'");
  expect_one_line_error("render --out " + out + task + " --at 2s",
                        "--at: expected " + expected + ", got '2s'");
  expect_one_line_error("render --out " + out + task + " --at point.stroke+x",
                        "--at: expected " + expected + ", got 'point.stroke+x'");
  expect_one_line_error("render --out " + out + task + " --at 31",
                        "--at: expected a time within the episode's horizon [0, 30] s, got 31");
  // An event that happens, with an offset past the horizon.
  const std::string short_task = short_point_pick();
  const std::string past = one_line_error_output("render --out " + out + " --task " + short_task +
                                                 " --width 8 --height 8 --at point.end+5");
  EXPECT_EQ(past.rfind("hribench: error: --at: point.end at ", 0), 0u) << past;
  EXPECT_NE(past.find(" s + 5 s: past the episode's horizon (8 s)\n"), std::string::npos) << past;
  EXPECT_FALSE(std::filesystem::exists(out));
  std::remove(short_task.c_str());
}

TEST(RenderCommandTest, UnknownEventNamesTheEpisodesEvents) {
  const std::string out = temp_png("hribench_render_task_event.png");
  const std::string short_task = short_point_pick();
  const std::string output = one_line_error_output(
      "render --out " + out + " --task " + short_task +
      " --seed 0 --width 8 --height 8 --at point.nosuch");
  // The task is named by its file's stem; the events the episode has are listed.
  const std::string stem = std::filesystem::path(short_task).stem().string();
  EXPECT_EQ(output.rfind("hribench: error: --at: expected an event of " + stem +
                             " seed 0 with noop (point.start, point.prep, point.stroke, ",
                         0),
            0u)
      << output;
  EXPECT_NE(output.find("), got 'point.nosuch'\n"), std::string::npos) << output;
  // Every event the script can give, reached or not: the robot act and the watched goal.
  EXPECT_NE(output.find(", put.start, put.end, "), std::string::npos) << output;
  EXPECT_NE(output.find(", cue), got"), std::string::npos) << output;
  EXPECT_FALSE(std::filesystem::exists(out));
  std::remove(short_task.c_str());
}

TEST(RenderCommandTest, OutMustBeAPng) {
  expect_one_line_error("render --out " + temp_png("hribench_render_z") + ".jpg",
                        "--out: expected a .png file (render writes PNG images), got '" +
                            temp_png("hribench_render_z") + ".jpg'");
}

// A watched predicate, as the script writes it (blanks optional), is a moment.
TEST(RenderCommandTest, PredicateMomentIsRendered) {
  const std::string out = temp_png("hribench_render_predicate.png");
  const std::string task = std::string(" --task ") + kPointPick + " --seed 0 --policy oracle --width 8 --height 8";
  for (const std::string at : {"'in(obj_b, bin)'", "'in(obj_b,bin)'"}) {
    const auto r = run_hribench("render --out " + out + task + " --at " + at);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("oracle, in(obj_b, bin) at "), std::string::npos) << r.output;
    EXPECT_TRUE(std::filesystem::exists(out));
    std::remove(out.c_str());
  }
}

TEST(RenderCommandTest, BadTaskFilesAreOneLine) {
  const std::string out = temp_png("hribench_render_task_file.png");
  expect_one_line_error("render --out " + out + " --task no/such/task.yaml --at cue",
                        "--task: expected a scenario script file, got 'no/such/task.yaml'");
  // A script with a schema problem: its first problem, with file and line.
  const std::string bad = temp_png("hribench_render_bad_task.yaml");
  std::ofstream(bad) << "hribench: 1\ntask: broken\n";
  const std::string output =
      one_line_error_output("render --out " + out + " --task " + bad + " --at cue");
  EXPECT_EQ(output.rfind("hribench: error: " + bad + ":", 0), 0u) << output;
  EXPECT_FALSE(std::filesystem::exists(out));
  std::remove(bad.c_str());
}

TEST(RenderCommandTest, MisplacedTaskAndViewOptionsAreOneLine) {
  const std::string out = temp_png("hribench_render_task_misplaced.png");
  expect_one_line_error("render --out " + out + " --at cue",
                        "--task: --seed, --at and --policy need --task FILE");
  expect_one_line_error("render --out " + out + " --azimuth 30",
                        "--camera: --azimuth, --elevation and --distance need --camera free");
  expect_one_line_error("render --out " + out + " --camera free --elevation 95",
                        "--elevation: expected an angle in [-90, 90] degrees, got 95");
  expect_one_line_error("render --out " + out + " --camera free --distance 0",
                        "--distance: expected a distance in (0, 20] m, got 0");
  EXPECT_EQ(one_line_error_output("render --out " + out + " --task " + kPointPick +
                                  " --policy nosuch")
                .rfind("hribench: error: policy: expected one of ", 0),
            0u);
  EXPECT_FALSE(std::filesystem::exists(out));
}

}  // namespace
}  // namespace hribench::cli

// Tests of PNG writing and reading: an exact round trip, and clear errors for unwritable paths
// and files that are not PNGs.

#include "render/png.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "core/errors.h"

namespace hribench::render {
namespace {

// A temporary path unique to this process (test programs may run in parallel).
std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() / (std::to_string(getpid()) + "_" + name))
      .string();
}

TEST(PngTest, RoundTripIsExact) {
  Image image;
  image.resize(5, 3);
  for (size_t i = 0; i < image.rgb.size(); ++i) image.rgb[i] = static_cast<uint8_t>(i * 37 % 256);
  const std::string path = temp_path("hribench_png_test_roundtrip.png");
  write_png(path, image);
  const Image back = read_png(path);
  std::remove(path.c_str());
  EXPECT_EQ(back.width, 5);
  EXPECT_EQ(back.height, 3);
  EXPECT_EQ(back.rgb, image.rgb);
  // Row 0 is the top row in both.
  EXPECT_EQ(back.at(0, 1, 2), image.rgb[5]);
}

TEST(PngTest, UnwritablePathIsAnInputError) {
  Image image;
  image.resize(2, 2);
  try {
    write_png("/nonexistent-dir/x.png", image);
    FAIL() << "no error";
  } catch (const core::InputError& e) {
    EXPECT_STREQ(e.what(),
                 "/nonexistent-dir/x.png: cannot open for writing (No such file or directory)");
  }
}

TEST(PngTest, ReadingANonPngIsAnInputError) {
  const std::string path = temp_path("hribench_png_test_not_a_png.png");
  std::ofstream(path) << "hello";
  try {
    read_png(path);
    FAIL() << "no error";
  } catch (const core::InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(path + ": cannot read PNG (", 0), 0u) << e.what();
  }
  std::remove(path.c_str());
}

}  // namespace
}  // namespace hribench::render

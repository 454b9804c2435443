#pragma once
// Caller-owned image buffers the renderer writes into. Row 0 is the TOP row of the picture
// (image convention, as policies and PNG expect; GL's bottom-up rows are flipped on read).
// resize() reallocates only when the buffer grows, so a reused image costs no allocation.

#include <cstdint>
#include <vector>

namespace hribench::render {

// 8-bit RGB, height x width x 3 (HWC), row-major.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;

  void resize(int w, int h) {
    width = w;
    height = h;
    rgb.resize(static_cast<size_t>(w) * static_cast<size_t>(h) * 3);
  }
  // Pixel (row, col) channel c; row 0 is the top row.
  std::uint8_t at(int row, int col, int c) const {
    return rgb[(static_cast<size_t>(row) * static_cast<size_t>(width) +
                static_cast<size_t>(col)) * 3 + static_cast<size_t>(c)];
  }
};

// Per-pixel MuJoCo geom id (mjModel index), -1 where no geom is seen (background, sites,
// decorations). height x width, row 0 is the top row.
struct SegmentationImage {
  int width = 0;
  int height = 0;
  std::vector<int> geom;

  void resize(int w, int h) {
    width = w;
    height = h;
    geom.resize(static_cast<size_t>(w) * static_cast<size_t>(h));
  }
  int at(int row, int col) const {
    return geom[static_cast<size_t>(row) * static_cast<size_t>(width) + static_cast<size_t>(col)];
  }
};

}  // namespace hribench::render

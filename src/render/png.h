#pragma once
// PNG files of RGB images (libpng), for `hribench render`, docs and tests.

#include <string>

#include "render/image.h"

namespace hribench::render {

// Writes `image` (8-bit RGB) to `path`. Throws core::InputError("PATH", ...) when the file
// cannot be opened for writing or written; a partly written file is removed.
void write_png(const std::string& path, const Image& image);

// Reads an 8-bit or 16-bit PNG of any colour type into RGB (alpha dropped, grey expanded,
// 16-bit reduced). Throws core::InputError("PATH", ...) when missing or not a PNG.
Image read_png(const std::string& path);

}  // namespace hribench::render

#include "render/png.h"

#include <png.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "core/errors.h"

namespace hribench::render {

void write_png(const std::string& path, const Image& image) {
  HRIB_CHECK(image.width > 0 && image.height > 0 &&
             image.rgb.size() == static_cast<size_t>(image.width) *
                                     static_cast<size_t>(image.height) * 3)
      << "write_png of an empty or inconsistent image " << image.width << "x" << image.height;
  // Open the file ourselves so the error names the OS reason (libpng's simplified API does not).
  FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) {
    throw core::InputError::Message(path, std::string("cannot open for writing (") +
                                              std::strerror(errno) + ")");
  }
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  png.width = static_cast<png_uint_32>(image.width);
  png.height = static_cast<png_uint_32>(image.height);
  png.format = PNG_FORMAT_RGB;
  const int ok = png_image_write_to_stdio(&png, file, 0, image.rgb.data(), 0, nullptr);
  const bool closed = std::fclose(file) == 0;
  if (ok == 0 || !closed) {
    std::remove(path.c_str());
    throw core::InputError::Message(
        path, std::string("cannot write PNG (") + (ok == 0 ? png.message : "close failed") + ")");
  }
}

Image read_png(const std::string& path) {
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  if (png_image_begin_read_from_file(&png, path.c_str()) == 0) {
    throw core::InputError::Message(path, std::string("cannot read PNG (") + png.message + ")");
  }
  png.format = PNG_FORMAT_RGB;
  Image image;
  image.resize(static_cast<int>(png.width), static_cast<int>(png.height));
  const png_color black{0, 0, 0};
  if (png_image_finish_read(&png, &black, image.rgb.data(), 0, nullptr) == 0) {
    png_image_free(&png);
    throw core::InputError::Message(path, std::string("cannot read PNG (") + png.message + ")");
  }
  return image;
}

}  // namespace hribench::render

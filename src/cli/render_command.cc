// `hribench render --out scene.png [--camera NAME --width W --height H --backend B]`: a still
// of the default scene (robot at home, objects on the table, the human standing across it), so
// a person can look at it.

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>

#include "cli/command.h"
#include "core/errors.h"
#include "model/model.h"
#include "render/png.h"
#include "render/renderer.h"
#include "sim/data.h"

namespace hribench::cli {
namespace {

struct RenderOptions {
  std::string out;
  std::string camera = "agentview";
  int width = 640;
  int height = 480;
  std::string backend = "osmesa";
};

// Fails early (before any simulation or GL work) when `path` cannot be written.
void check_writable(const std::string& path) {
  const std::filesystem::path p(path);
  if (std::filesystem::is_directory(p)) {
    throw core::InputError("--out", "a file path", "the directory '" + path + "'");
  }
  const std::string dir = p.has_parent_path() ? p.parent_path().string() : ".";
  const bool exists = access(path.c_str(), F_OK) == 0;
  if (access(exists ? path.c_str() : dir.c_str(), W_OK) != 0) {
    throw core::InputError::Message(
        "--out", "cannot write '" + path + "' (" + std::strerror(errno) + ")");
  }
}

int run_render(const RenderOptions& o) {
  // Validate everything the user typed before building anything.
  const render::Backend backend = render::parse_backend(o.backend);
  if (backend == render::Backend::kNone) {
    throw core::InputError("--backend", "osmesa or egl (render writes an image)", "'none'");
  }
  render::check_image_size(o.width, o.height, "--width", "--height");
  check_writable(o.out);

  const model::Model model = model::build(model::SceneSpec::Default());
  const int camera = render::camera_id(*model.m(), o.camera, "--camera");
  sim::Data data = sim::make_data(model);

  auto renderer = render::make_renderer(backend, *model.m(), o.width, o.height);
  render::Image image;
  renderer->render(*model.m(), *data.mj, camera, image);
  render::write_png(o.out, image);
  std::printf("wrote %s (%dx%d, camera %s, %s: %s)\n", o.out.c_str(), o.width, o.height,
              o.camera.c_str(), std::string(render::to_string(backend)).c_str(),
              renderer->gl_renderer().c_str());
  return 0;
}

HRIB_REGISTER_COMMAND(
    "render", "Render a still of the default scene to a PNG file",
    [](CLI::App& app) -> std::function<int()> {
      auto options = std::make_shared<RenderOptions>();
      app.add_option("--out", options->out, "PNG file to write")->required();
      app.add_option("--camera", options->camera, "camera name (agentview, wrist)")
          ->capture_default_str();
      app.add_option("--width", options->width, "image width in pixels")->capture_default_str();
      app.add_option("--height", options->height, "image height in pixels")
          ->capture_default_str();
      app.add_option("--backend", options->backend, "osmesa (CPU) or egl (GPU)")
          ->capture_default_str();
      return [options] { return run_render(*options); };
    });

}  // namespace
}  // namespace hribench::cli

#pragma once
// Camera images of a MuJoCo scene, behind one interface with three back ends:
//   osmesa — CPU (Mesa llvmpipe through libOSMesa); the default, works everywhere.
//   egl    — headless GPU through EGL (or Mesa's software EGL device where there is no GPU).
//   none   — never touches GL; render() returns false and leaves images empty.
// Images only when asked: nothing is rendered unless render() is called.
//
// A Renderer owns one mjrContext (offscreen buffer of exactly width x height) and one mjvScene,
// in the GL context of the thread that makes it (thread_gl_context: one per thread, shared by
// the renderers made on it, kept for the thread's life). It renders any mjModel/mjData pair
// whose mjModel is the one it was made with (textures and meshes are uploaded once at
// creation). A Renderer is used on the thread that made it. A process uses one GL back end
// (see gl_context.h). Not copyable.
//
// Settings are chosen for speed on llvmpipe (docs/rendering.md has the measurements): no
// shadows, no reflections, no skybox, no multisampling, and capsules, spheres and cylinders
// drawn with fewer triangles. RenderSettings::mujoco_defaults() gives MuJoCo's own defaults for
// comparison.

#include <mujoco/mujoco.h>

#include <array>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "model/model.h"
#include "render/gl_context.h"
#include "render/image.h"
#include "sim/data.h"

namespace hribench::render {

// One cell of the text band under a frame's camera panels (render_panels; docs/videos.md):
// `text` centred in white on a flat `background` (RGB in [0, 1]).
struct BandCell {
  std::string text;
  std::array<float, 3> background{0.12F, 0.12F, 0.12F};
};
// Cells of one band row share its width equally.
using BandRow = std::vector<BandCell>;

// Largest image side we accept (pixels); every GL we target supports this offscreen size.
inline constexpr int kMaxImageSide = 4096;

struct RenderSettings {
  bool shadows = false;      // mjRND_SHADOW and a shadow map (the big cost on llvmpipe)
  bool reflections = false;  // mjRND_REFLECTION (reflective materials re-render the scene)
  bool skybox = false;       // mjRND_SKYBOX; without it the background is the clear colour
  int multisamples = 0;      // MSAA samples of the offscreen buffer (MuJoCo's default is 4)
  int shadow_map_size = 0;   // shadow map side when shadows are on; 0: the model's value
  int font_scale = 50;       // mjtFontScale of the text render_panels draws (50, 100, 150, ...)
  // Tessellation of MuJoCo's built-in shapes (vis.quality.numslices / numstacks): slices around
  // a capsule, sphere or cylinder, stacks from pole to pole. 0: the model's value (MuJoCo's
  // default, as the scene does not set it). Ours is about half the vertices' cost per frame.
  int shape_slices = 16;
  int shape_stacks = 8;
  // Leave out of the draw the geoms wholly outside the camera's view (changes no pixel; skipped
  // while shadows or reflections are on, since a geom out of view can cast or show in them).
  bool cull_outside_view = true;

  // MuJoCo 2.2.2's defaults (shadows, reflections, skybox, 4x MSAA, its tessellation).
  static RenderSettings mujoco_defaults();
};

class Renderer {
 public:
  // Throws core::InputError for width/height outside [1, kMaxImageSide] (where "width"/"height")
  // and "no usable GL context" (see make_gl_context) for osmesa/egl. `m` must outlive nothing:
  // it is read during construction only.
  Renderer(Backend backend, const mjModel& m, int width, int height,
           RenderSettings settings = {});
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  Backend backend() const { return backend_; }
  int width() const { return width_; }
  int height() const { return height_; }
  const RenderSettings& settings() const { return settings_; }
  // Geoms the last image drew: the scene's, the drawn hands', less those out of view.
  int drawn_geoms() const { return scene_.ngeom; }
  // GL_RENDERER of the context ("none" for the none back end).
  const std::string& gl_renderer() const { return gl_renderer_; }

  // Renders fixed camera `camera_id` (0 <= id < m.ncam) of state `d` into `out`, resized to
  // width x height (no allocation when `out` already has that size). Returns false (and
  // leaves `out` 0x0) for the none back end. `d` is not modified except mjv_updateScene's
  // bookkeeping of d->warning (never triggered: the scene has room for every geom).
  bool render(const mjModel& m, const mjData& d, int camera_id, Image& out);
  // The same for a built Model and its simulation Data (camera: e.g. model.agentview_camera).
  bool render(const model::Model& model, const sim::Data& data, int camera_id, Image& out) {
    return render(*model.m(), *data.mj, camera_id, out);
  }
  // Same with any MuJoCo camera (e.g. a free camera placed for a documentation picture).
  bool render(const mjModel& m, const mjData& d, const mjvCamera& camera, Image& out);
  // A video frame: fixed cameras `camera_ids` side by side, each width/n x (height - band
  // height) pixels and the same picture a renderer of that size gives, above `band` rows of
  // `row_height` pixels each (top row first). Needs width divisible by n and a band shorter
  // than the image (HRIB_CHECK). False (and `out` 0x0) for the none back end.
  bool render_panels(const mjModel& m, const mjData& d, const std::vector<int>& camera_ids,
                     const std::vector<BandRow>& band, int row_height, Image& out);
  // Segmentation: each pixel's mjModel geom id, -1 for background and non-geom objects.
  bool render_segmentation(const mjModel& m, const mjData& d, int camera_id,
                           SegmentationImage& out);

  // Raw MuJoCo objects, for benchmarks that time raw mjv_updateScene + mjr_render +
  // mjr_readPixels on the very same context. Null/unusable for the none back end.
  mjvScene& scene() { return scene_; }
  mjrContext& context() { return context_; }
  mjvOption& option() { return option_; }
  void make_current();

 private:
  void draw(const mjModel& m, const mjData& d, const mjvCamera& camera);

  Backend backend_;
  int width_;
  int height_;
  RenderSettings settings_;
  std::string gl_renderer_;
  std::shared_ptr<GlContext> gl_;  // the thread's (thread_gl_context); null for kNone
  mjvScene scene_{};
  mjrContext context_{};
  mjvOption option_{};
  mjvCamera camera_{};
  std::vector<unsigned char> segment_rgb_;  // scratch for segmentation colours
};

std::unique_ptr<Renderer> make_renderer(Backend backend, const mjModel& m, int width, int height,
                                        RenderSettings settings = {});

// The id of camera `name` in `m`. Throws core::InputError(where, "one of A, B", "'name'").
int camera_id(const mjModel& m, std::string_view name, std::string_view where = "camera");

// Throws core::InputError(width_name or height_name, ...) unless both sides are in
// [1, kMaxImageSide] pixels.
void check_image_size(int width, int height, std::string_view width_name = "width",
                      std::string_view height_name = "height");

}  // namespace hribench::render

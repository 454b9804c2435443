#include "render/renderer.h"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/errors.h"
#include "human/hand.h"

namespace hribench::render {

RenderSettings RenderSettings::mujoco_defaults() {
  RenderSettings s;
  s.shadows = true;
  s.reflections = true;
  s.skybox = true;
  s.multisamples = 4;
  s.shape_slices = 0;
  s.shape_stacks = 0;
  s.cull_outside_view = false;
  return s;
}

namespace {

// MuJoCo reports fatal errors through mju_user_error; its default prints and exits the
// process. While a GL context is being made we turn them into exceptions (one clear line).
class ThrowingMujocoErrors {
 public:
  ThrowingMujocoErrors() : previous_(mju_user_error) { mju_user_error = &raise; }
  ~ThrowingMujocoErrors() { mju_user_error = previous_; }
  ThrowingMujocoErrors(const ThrowingMujocoErrors&) = delete;
  ThrowingMujocoErrors& operator=(const ThrowingMujocoErrors&) = delete;

 private:
  static void raise(const char* message) { throw std::runtime_error(message); }
  void (*previous_)(const char*);
};

// Every renderer's GL work (making and freeing its context, drawing, reading pixels) holds this
// process-wide lock. Mesa 22's llvmpipe (osmesa, and EGL without a GPU) crashed when two
// threads drew through their own contexts at once: a core dump of `eval --video failures` on
// two threads has one worker inside mjr_label and the other inside mjr_render
// (docs/rendering.md, "Threads"). llvmpipe spreads each draw over its own rasterizer threads,
// so serialising draws costs little; simulation, encoding and everything else stay parallel.
// MuJoCo's GL loading (mjr_makeContext) and its global mju_user_error need the same lock.
std::mutex& gl_work_mutex() {
  static std::mutex mutex;
  return mutex;
}

// The person's skeleton, from the model's numeric kHumanHeightNumeric; none without a person.
std::optional<human::Skeleton> drawn_skeleton(const mjModel& m) {
  const int id = mj_name2id(&m, mjOBJ_NUMERIC, model::kHumanHeightNumeric);
  if (id < 0 || m.nuserdata < model::kHandShapeValues) return std::nullopt;
  return human::Skeleton::FromHeight(m.numeric_data[m.numeric_adr[id]]);
}

// Room for everything mjv_updateScene may add with default options (geoms, sites, tendon
// segments, lights' decor), and for the drawn hands, so it never raises mjWARN_VGEOMFULL into
// the caller's mjData.
int scene_capacity(const mjModel& m) {
  const std::optional<human::Skeleton> skeleton = drawn_skeleton(m);
  const int hands = skeleton ? 2 * static_cast<int>(human::hand_capsules(*skeleton).size()) : 0;
  return m.ngeom + m.nsite + 16 * m.ntendon + m.nbody + m.nlight + 100 + hands;
}

// The person's hands (human/hand.h), drawn in place of their contact capsules, which the model
// does not draw (group 3): capsules added to the scene after mjv_updateScene, posed from the
// wrist bodies and the shapes in d.userdata (model::kHandShapeValues), in the capsule's colour.
// Each carries its hand capsule's geom id, so segmentation names it as that hand.
void add_drawn_hands(const mjModel& m, const mjData& d, mjvScene& scene) {
  const std::optional<human::Skeleton> skeleton = drawn_skeleton(m);
  if (!skeleton) return;
  const std::vector<human::HandCapsule> parts = human::hand_capsules(*skeleton);
  for (const human::BodyCapsule& hand : human::body_capsules(*skeleton)) {
    if (hand.region != human::BodyRegion::kHand) continue;
    const human::Side side = hand.joint == human::wrist(human::Side::kLeft) ? human::Side::kLeft : human::Side::kRight;
    const int wrist = mj_name2id(&m, mjOBJ_BODY, ("human_" + std::string(human::joint_name(hand.joint))).c_str());
    const int capsule = mj_name2id(&m, mjOBJ_GEOM, ("human_" + std::string(hand.name)).c_str());
    if (wrist < 0 || capsule < 0) continue;
    const core::Pose X_W_wrist{core::quat_from_wxyz(d.xquat + 4 * wrist),
                               core::Vec3(d.xpos[3 * wrist], d.xpos[3 * wrist + 1], d.xpos[3 * wrist + 2])};
    const mjtNum* shape = d.userdata + 2 * static_cast<size_t>(side);
    const auto X = human::hand_part_frames(*skeleton, side, {shape[0], shape[1]});
    for (const human::HandCapsule& c : parts) {
      if (scene.ngeom >= scene.maxgeom) return;
      const core::Pose X_W_part = X_W_wrist * X[static_cast<size_t>(c.part)];
      const core::Vec3 a = X_W_part * c.from;
      const core::Vec3 b = X_W_part * c.to;
      mjvGeom* g = scene.geoms + scene.ngeom;
      const mjtNum size[3] = {c.radius, c.radius, c.radius};
      mjv_initGeom(g, mjGEOM_CAPSULE, size, nullptr, nullptr, m.geom_rgba + 4 * capsule);
      mjv_makeConnector(g, mjGEOM_CAPSULE, c.radius, a.x(), a.y(), a.z(), b.x(), b.y(), b.z());
      g->objtype = mjOBJ_GEOM;
      g->objid = capsule;
      g->category = mjCAT_DYNAMIC;
      g->segid = scene.ngeom;
      ++scene.ngeom;
    }
  }
}

// Radius of a sphere around a scene geom's centre that holds it, or a negative value for kinds
// that are never culled (planes, meshes, lines, labels, ...).
double bounding_radius(const mjvGeom& g) {
  const double a = g.size[0], b = g.size[1], c = g.size[2];
  switch (g.type) {
    case mjGEOM_SPHERE: return a;
    case mjGEOM_CAPSULE: return a + c;
    case mjGEOM_ELLIPSOID: return std::max({a, b, c});
    case mjGEOM_CYLINDER: return std::hypot(a, c);
    case mjGEOM_BOX: return std::sqrt(a * a + b * b + c * c);
    default: return -1;
  }
}

// Drops the scene's geoms that lie wholly outside the view frustum of its camera for an image of
// `aspect` (width / height), keeping the others in order. mjr_render would draw them for
// nothing: every vertex costs on llvmpipe, and the wrist camera sees little of the scene. A
// geom is dropped only when its centre lies farther than its bounding radius (and a millimetre)
// outside one of the frustum's planes, so no pixel changes (renderer_test). Segment ids follow
// the geoms' new places (render_segmentation maps them back through the scene).
void cull_outside_view(mjvScene& scene, double aspect) {
  // Without stereo, mjr_render draws from the average of the scene's two eyes (camera[0] and [1]
  // sit half the inter-pupillary distance to each side, 3.4 cm by default).
  const mjvGLCamera c = mjv_averageCamera(&scene.camera[0], &scene.camera[1]);
  const auto vec = [](const float* v) { return Eigen::Vector3d(v[0], v[1], v[2]); };
  const Eigen::Vector3d eye = vec(c.pos);
  const Eigen::Vector3d forward = vec(c.forward).normalized();
  const Eigen::Vector3d up = vec(c.up).normalized();
  const Eigen::Vector3d right = forward.cross(up);
  const double near = c.frustum_near, far = c.frustum_far;
  const double bottom = c.frustum_bottom, top = c.frustum_top, center = c.frustum_center;
  // MuJoCo sets the horizontal extent from the aspect: center ± aspect · (top − bottom) / 2.
  const double half_width = 0.5 * aspect * (top - bottom);
  // Each side plane passes through the eye; a point (x, y, z) in the camera's (right, up,
  // forward) frame is outside it when x < s·z (left), x > s·z (right), ... with s the plane's
  // slope at the near plane. `beyond(s, u, z)` is the distance outside the plane u = s·z.
  const auto beyond = [](double slope, double u, double z) { return (slope * z - u) / std::hypot(1.0, slope); };
  const double kMargin = 1e-3;  // m
  int kept = 0;
  for (int i = 0; i < scene.ngeom; ++i) {
    const mjvGeom& g = scene.geoms[i];
    const double r = bounding_radius(g);
    if (r >= 0) {
      const Eigen::Vector3d p = vec(g.pos) - eye;
      const double x = p.dot(right), y = p.dot(up), z = p.dot(forward);
      const double reach = r + kMargin;
      if (z + reach < near || z - reach > far || beyond((center - half_width) / near, x, z) > reach ||
          -beyond((center + half_width) / near, x, z) > reach || beyond(bottom / near, y, z) > reach ||
          -beyond(top / near, y, z) > reach) {
        continue;
      }
    }
    if (kept != i) scene.geoms[kept] = g;
    scene.geoms[kept].segid = kept;
    ++kept;
  }
  scene.ngeom = kept;
}

// The model's fixed camera `camera_id` as an mjvCamera.
mjvCamera fixed_camera(const mjModel& m, int camera_id) {
  HRIB_CHECK(camera_id >= 0 && camera_id < m.ncam) << "camera id " << camera_id << " of "
                                                   << m.ncam;
  mjvCamera camera;
  mjv_defaultCamera(&camera);
  camera.type = mjCAMERA_FIXED;
  camera.fixedcamid = camera_id;
  return camera;
}

// GL rows run bottom-up; images run top-down.
template <typename T>
void flip_rows(T* data, int width, int height, int channels) {
  const size_t row = static_cast<size_t>(width) * static_cast<size_t>(channels);
  for (int top = 0, bottom = height - 1; top < bottom; ++top, --bottom) {
    std::swap_ranges(data + static_cast<size_t>(top) * row,
                     data + static_cast<size_t>(top + 1) * row,
                     data + static_cast<size_t>(bottom) * row);
  }
}

}  // namespace

Renderer::Renderer(Backend backend, const mjModel& m, int width, int height,
                   RenderSettings settings)
    : backend_(backend), width_(width), height_(height), settings_(settings) {
  check_image_size(width, height);
  HRIB_CHECK(settings.multisamples >= 0 && settings.shadow_map_size >= 0 &&
             settings.shape_slices >= 0 && settings.shape_stacks >= 0 &&
             settings.font_scale >= 50 && settings.font_scale <= 300 &&
             settings.font_scale % 50 == 0)
      << "multisamples " << settings.multisamples << ", shadow map " << settings.shadow_map_size
      << ", shapes " << settings.shape_slices << "x" << settings.shape_stacks
      << ", font scale " << settings.font_scale;
  mjv_defaultOption(&option_);
  mjv_defaultCamera(&camera_);
  mjv_defaultScene(&scene_);
  mjr_defaultContext(&context_);
  if (backend == Backend::kNone) {
    gl_renderer_ = "none";
    return;
  }
  const std::lock_guard<std::mutex> lock(gl_work_mutex());
  gl_ = thread_gl_context(backend);
  gl_->make_current();
  gl_renderer_ = gl_->gl_renderer();

  // The context is made from a shallow copy of the model whose visual settings size the
  // offscreen buffer to exactly this image and apply our render settings.
  mjModel sized = m;
  sized.vis.global.offwidth = width;
  sized.vis.global.offheight = height;
  sized.vis.quality.offsamples = settings.multisamples;
  if (settings.shadow_map_size > 0) sized.vis.quality.shadowsize = settings.shadow_map_size;
  if (!settings.shadows) sized.vis.quality.shadowsize = 1;  // no shadow map memory or cost
  // mjr_makeContext builds the shapes' display lists from these.
  if (settings.shape_slices > 0) sized.vis.quality.numslices = settings.shape_slices;
  if (settings.shape_stacks > 0) sized.vis.quality.numstacks = settings.shape_stacks;
  // mju_user_error is process-global and MuJoCo's GL loading is not thread-safe: under the lock
  // a concurrent constructor can neither see the throwing handler as "previous" nor leave it
  // installed.
  try {
    ThrowingMujocoErrors errors;
    mjv_makeScene(&m, &scene_, scene_capacity(m));
    mjr_makeContext(&sized, &context_, settings.font_scale);
    mjr_setBuffer(mjFB_OFFSCREEN, &context_);
  } catch (const std::runtime_error& e) {
    mjr_freeContext(&context_);
    mjv_freeScene(&scene_);
    throw core::InputError::Message(std::string(to_string(backend)),
                                    std::string("no usable GL context: ") + e.what());
  }
  if (context_.offWidth < width || context_.offHeight < height) {
    const std::string got = std::to_string(context_.offWidth) + "x" +
                            std::to_string(context_.offHeight);
    mjr_freeContext(&context_);
    mjv_freeScene(&scene_);
    throw core::InputError(std::string(to_string(backend)),
                           "an offscreen buffer of " + std::to_string(width) + "x" +
                               std::to_string(height),
                           got);
  }
  scene_.flags[mjRND_SHADOW] = settings.shadows ? 1 : 0;
  scene_.flags[mjRND_REFLECTION] = settings.reflections ? 1 : 0;
  scene_.flags[mjRND_SKYBOX] = settings.skybox ? 1 : 0;
}

Renderer::~Renderer() {
  if (gl_ == nullptr) return;
  const std::lock_guard<std::mutex> lock(gl_work_mutex());
  gl_->make_current();
  mjr_freeContext(&context_);
  mjv_freeScene(&scene_);
}

void Renderer::make_current() {
  if (gl_ == nullptr) return;
  gl_->make_current();
  mjr_setBuffer(mjFB_OFFSCREEN, &context_);
}

void Renderer::draw(const mjModel& m, const mjData& d, const mjvCamera& camera) {
  gl_->make_current();
  // Other renderers of this thread's context bind their own offscreen buffers.
  mjr_setBuffer(mjFB_OFFSCREEN, &context_);
  camera_ = camera;
  // mjv_updateScene takes mjData* but only reads it (it could set a warning; see capacity).
  mjv_updateScene(&m, const_cast<mjData*>(&d), &option_, nullptr, &camera_, mjCAT_ALL, &scene_);
  add_drawn_hands(m, d, scene_);
  if (settings_.cull_outside_view && !settings_.shadows && !settings_.reflections &&
      scene_.stereo == mjSTEREO_NONE) {
    cull_outside_view(scene_, static_cast<double>(width_) / height_);
  }
  mjr_render(mjrRect{0, 0, width_, height_}, &scene_, &context_);
}

bool Renderer::render(const mjModel& m, const mjData& d, int camera_id, Image& out) {
  return render(m, d, fixed_camera(m, camera_id), out);
}

bool Renderer::render(const mjModel& m, const mjData& d, const mjvCamera& camera, Image& out) {
  if (gl_ == nullptr) {
    out.resize(0, 0);
    return false;
  }
  out.resize(width_, height_);
  {
    const std::lock_guard<std::mutex> lock(gl_work_mutex());
    draw(m, d, camera);
    mjr_readPixels(out.rgb.data(), nullptr, mjrRect{0, 0, width_, height_}, &context_);
  }
  flip_rows(out.rgb.data(), width_, height_, 3);
  return true;
}

bool Renderer::render_panels(const mjModel& m, const mjData& d,
                             const std::vector<int>& camera_ids, const std::vector<BandRow>& band,
                             int row_height, Image& out) {
  if (gl_ == nullptr) {
    out.resize(0, 0);
    return false;
  }
  const int panels = static_cast<int>(camera_ids.size());
  const int band_height = row_height * static_cast<int>(band.size());
  HRIB_CHECK(panels > 0 && width_ % panels == 0 && band_height >= 0 && band_height < height_)
      << panels << " panels and a band of " << band_height << " px in " << width_ << "x" << height_;
  const int panel_width = width_ / panels;
  out.resize(width_, height_);
  const std::lock_guard<std::mutex> lock(gl_work_mutex());
  gl_->make_current();
  mjr_setBuffer(mjFB_OFFSCREEN, &context_);
  for (int i = 0; i < panels; ++i) {
    camera_ = fixed_camera(m, camera_ids[static_cast<size_t>(i)]);
    mjv_updateScene(&m, const_cast<mjData*>(&d), &option_, nullptr, &camera_, mjCAT_ALL, &scene_);
    add_drawn_hands(m, d, scene_);
    mjr_render(mjrRect{i * panel_width, band_height, panel_width, height_ - band_height}, &scene_,
               &context_);
  }
  for (size_t row = 0; row < band.size(); ++row) {
    const int cells = static_cast<int>(band[row].size());
    const int bottom = band_height - row_height * static_cast<int>(row + 1);  // GL rows run up
    for (int c = 0; c < cells; ++c) {
      const int left = width_ * c / cells;
      const BandCell& cell = band[row][static_cast<size_t>(c)];
      mjr_label(mjrRect{left, bottom, width_ * (c + 1) / cells - left, row_height}, mjFONT_NORMAL,
                cell.text.c_str(), cell.background[0], cell.background[1], cell.background[2], 1,
                1, 1, 1, &context_);
    }
  }
  mjr_readPixels(out.rgb.data(), nullptr, mjrRect{0, 0, width_, height_}, &context_);
  flip_rows(out.rgb.data(), width_, height_, 3);
  return true;
}

bool Renderer::render_segmentation(const mjModel& m, const mjData& d, int camera_id,
                                   SegmentationImage& out) {
  if (gl_ == nullptr) {
    out.resize(0, 0);
    return false;
  }
  const mjvCamera camera = fixed_camera(m, camera_id);
  // Each scene geom is drawn in the flat colour segid + 1 (background 0).
  segment_rgb_.resize(static_cast<size_t>(width_) * static_cast<size_t>(height_) * 3);
  {
    const std::lock_guard<std::mutex> lock(gl_work_mutex());
    scene_.flags[mjRND_SEGMENT] = 1;
    scene_.flags[mjRND_IDCOLOR] = 1;
    draw(m, d, camera);
    scene_.flags[mjRND_SEGMENT] = 0;
    scene_.flags[mjRND_IDCOLOR] = 0;
    mjr_readPixels(segment_rgb_.data(), nullptr, mjrRect{0, 0, width_, height_}, &context_);
  }
  flip_rows(segment_rgb_.data(), width_, height_, 3);
  out.resize(width_, height_);
  for (size_t i = 0; i < out.geom.size(); ++i) {
    const unsigned char* c = &segment_rgb_[3 * i];
    const int segid = c[0] + (c[1] << 8) + (c[2] << 16) - 1;
    int geom = -1;
    if (segid >= 0 && segid < scene_.ngeom && scene_.geoms[segid].objtype == mjOBJ_GEOM) {
      geom = scene_.geoms[segid].objid;
    }
    out.geom[i] = geom;
  }
  return true;
}

std::unique_ptr<Renderer> make_renderer(Backend backend, const mjModel& m, int width, int height,
                                        RenderSettings settings) {
  return std::make_unique<Renderer>(backend, m, width, height, settings);
}

void check_image_size(int width, int height, std::string_view width_name,
                      std::string_view height_name) {
  for (const auto& [where, pixels] :
       {std::pair{width_name, width}, std::pair{height_name, height}}) {
    if (pixels < 1 || pixels > kMaxImageSide) {
      throw core::InputError(std::string(where),
                             "an image side in [1, " + std::to_string(kMaxImageSide) + "] pixels",
                             std::to_string(pixels));
    }
  }
}

int camera_id(const mjModel& m, std::string_view name, std::string_view where) {
  const int id = mj_name2id(&m, mjOBJ_CAMERA, std::string(name).c_str());
  if (id >= 0) return id;
  std::string names;
  for (int i = 0; i < m.ncam; ++i) {
    const char* n = mj_id2name(&m, mjOBJ_CAMERA, i);
    names += (i > 0 ? ", " : "") + std::string(n != nullptr ? n : "#" + std::to_string(i));
  }
  throw core::InputError(std::string(where),
                         m.ncam > 0 ? "one of " + names : "a camera (the model has none)",
                         "'" + std::string(name) + "'");
}

}  // namespace hribench::render

// Tests of the Renderer on a small hand-written scene: rows come out top-down, segmentation
// names the geoms seen, buffers are reused, bad sizes/cameras give clear errors, and the none
// back end never loads a GL library.

#include "render/renderer.h"

#include <gtest/gtest.h>
#include <link.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <thread>

#include "core/errors.h"
#include "model/model.h"
#include "sim/data.h"
#include "support/default_scene.h"

namespace hribench::render {
namespace {

// Seen from camera "top" (1.6 m above the origin, looking down; image up = world +y): a red box
// in the top half of the picture and a blue capsule in the bottom half, on black.
constexpr char kSceneXml[] = R"(
<mujoco>
  <worldbody>
    <light pos="0 0 4" dir="0 0 -1"/>
    <camera name="top" pos="0 0 1.6"/>
    <camera name="side" pos="0 -3 0.3" xyaxes="1 0 0 0 0 1"/>
    <body name="robot" pos="0 0.3 0">
      <geom name="robot_box" type="box" size="0.3 0.15 0.1" rgba="1 0 0 1"/>
    </body>
    <body name="human" pos="0 -0.3 0" mocap="true">
      <geom name="human_arm" type="capsule" fromto="-0.3 0 0 0.3 0 0" size="0.12" rgba="0 0 1 1"/>
    </body>
  </worldbody>
</mujoco>)";

struct MjDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
  void operator()(mjData* d) const { mj_deleteData(d); }
};

class RendererTest : public ::testing::Test {
 protected:
  void SetUp() override {
    mjVFS vfs;
    mj_defaultVFS(&vfs);
    const size_t size = std::strlen(kSceneXml);
    ASSERT_EQ(mj_makeEmptyFileVFS(&vfs, "scene.xml", static_cast<int>(size)), 0);
    std::memcpy(vfs.filedata[0], kSceneXml, size);
    char error[1000] = "";
    model_.reset(mj_loadXML("scene.xml", &vfs, error, sizeof(error)));
    mj_deleteVFS(&vfs);
    ASSERT_NE(model_, nullptr) << error;
    data_.reset(mj_makeData(model_.get()));
    mj_forward(model_.get(), data_.get());
  }
  const mjModel& m() const { return *model_; }
  const mjData& d() const { return *data_; }
  int geom(const char* name) const { return mj_name2id(model_.get(), mjOBJ_GEOM, name); }

  std::unique_ptr<mjModel, MjDeleter> model_;
  std::unique_ptr<mjData, MjDeleter> data_;
};

TEST_F(RendererTest, OsmesaRendersRowsTopDown) {
  auto renderer = make_renderer(Backend::kOsmesa, m(), 64, 48);
  EXPECT_FALSE(renderer->gl_renderer().empty());
  EXPECT_NE(renderer->gl_renderer(), "none");
  Image image;
  ASSERT_TRUE(renderer->render(m(), d(), camera_id(m(), "top"), image));
  ASSERT_EQ(image.width, 64);
  ASSERT_EQ(image.height, 48);
  ASSERT_EQ(image.rgb.size(), 64u * 48u * 3u);
  // The red box is in the top half, the blue capsule in the bottom half, corners are black.
  const int col = 32;
  EXPECT_GT(image.at(12, col, 0), image.at(12, col, 2) + 80);
  EXPECT_GT(image.at(36, col, 2), image.at(36, col, 0) + 80);
  EXPECT_EQ(image.at(0, 0, 0) + image.at(0, 0, 1) + image.at(0, 0, 2), 0);
}

TEST_F(RendererTest, ImagesAreReusedAndDeterministic) {
  auto renderer = make_renderer(Backend::kOsmesa, m(), 32, 32);
  Image first;
  ASSERT_TRUE(renderer->render(m(), d(), 0, first));
  const uint8_t* buffer = first.rgb.data();
  const Image copy = first;
  ASSERT_TRUE(renderer->render(m(), d(), 0, first));
  EXPECT_EQ(first.rgb.data(), buffer);  // no reallocation per frame
  EXPECT_EQ(first.rgb, copy.rgb);       // same state, same pixels
  // Moving the mocap body changes the picture.
  data_->mocap_pos[1] = 0.4;
  mj_forward(model_.get(), data_.get());
  ASSERT_TRUE(renderer->render(m(), d(), 0, first));
  EXPECT_NE(first.rgb, copy.rgb);
}

TEST_F(RendererTest, SegmentationNamesTheGeomsSeen) {
  auto renderer = make_renderer(Backend::kOsmesa, m(), 64, 48);
  SegmentationImage segmentation;
  ASSERT_TRUE(renderer->render_segmentation(m(), d(), camera_id(m(), "top"), segmentation));
  ASSERT_EQ(segmentation.width, 64);
  ASSERT_EQ(segmentation.height, 48);
  EXPECT_EQ(segmentation.at(12, 32), geom("robot_box"));
  EXPECT_EQ(segmentation.at(36, 32), geom("human_arm"));
  EXPECT_EQ(segmentation.at(0, 0), -1);
  int robot = 0;
  int human = 0;
  for (int g : segmentation.geom) {
    ASSERT_GE(g, -1);
    ASSERT_LT(g, m().ngeom);
    robot += g == geom("robot_box") ? 1 : 0;
    human += g == geom("human_arm") ? 1 : 0;
  }
  EXPECT_GT(robot, 100);
  EXPECT_GT(human, 100);
  // A colour render right after is not in segmentation colours.
  Image image;
  ASSERT_TRUE(renderer->render(m(), d(), camera_id(m(), "top"), image));
  EXPECT_GT(image.at(12, 32, 0), 100);
}

TEST_F(RendererTest, FreeCameraAndMujocoDefaultSettingsRender) {
  auto renderer = make_renderer(Backend::kOsmesa, m(), 32, 24, RenderSettings::mujoco_defaults());
  mjvCamera camera;
  mjv_defaultCamera(&camera);
  camera.type = mjCAMERA_FREE;
  camera.lookat[2] = 0;
  camera.distance = 3;
  camera.elevation = -89;
  Image image;
  ASSERT_TRUE(renderer->render(m(), d(), camera, image));
  int red = 0;
  int blue = 0;
  for (size_t i = 0; i < image.rgb.size(); i += 3) {
    red += image.rgb[i] > image.rgb[i + 2] + 80 ? 1 : 0;
    blue += image.rgb[i + 2] > image.rgb[i] + 80 ? 1 : 0;
  }
  EXPECT_GT(red, 10);
  EXPECT_GT(blue, 10);
}

TEST_F(RendererTest, ImpossibleSizesAreInputErrors) {
  const auto message = [&](int w, int h) {
    try {
      make_renderer(Backend::kNone, m(), w, h);
    } catch (const core::InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message(0, 10), "width: expected an image side in [1, 4096] pixels, got 0");
  EXPECT_EQ(message(10, -3), "height: expected an image side in [1, 4096] pixels, got -3");
  EXPECT_EQ(message(4097, 10), "width: expected an image side in [1, 4096] pixels, got 4097");
}

TEST_F(RendererTest, UnknownCameraNamesTheKnownOnes) {
  EXPECT_EQ(camera_id(m(), "side"), 1);
  try {
    camera_id(m(), "agentview");
    FAIL() << "no error";
  } catch (const core::InputError& e) {
    EXPECT_STREQ(e.what(), "camera: expected one of top, side, got 'agentview'");
  }
}

// True when a GL platform library (OSMesa, EGL, GLX) is loaded into this process.
bool gl_library_loaded() {
  return dl_iterate_phdr(
             [](dl_phdr_info* info, size_t, void*) {
               const std::string name = info->dlpi_name != nullptr ? info->dlpi_name : "";
               for (const char* lib : {"libOSMesa", "libEGL", "libGL.", "libGLX"}) {
                 if (name.find(lib) != std::string::npos) return 1;
               }
               return 0;
             },
             nullptr) != 0;
}

TEST_F(RendererTest, NoneBackendNeverLoadsGl) {
  // Run in a fresh process (re-executed test binary) so other tests' contexts do not count.
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(
      {
        auto renderer = make_renderer(Backend::kNone, m(), 64, 48);
        Image image;
        image.resize(2, 2);
        SegmentationImage segmentation;
        const bool rendered = renderer->render(m(), d(), 0, image) ||
                              renderer->render_segmentation(m(), d(), 0, segmentation);
        const bool ok = !rendered && image.width == 0 && image.rgb.empty() &&
                        segmentation.geom.empty() && renderer->gl_renderer() == "none" &&
                        loaded_gl_platform() == Backend::kNone && !gl_library_loaded();
        std::exit(ok ? 0 : 1);
      },
      ::testing::ExitedWithCode(0), "");
}

// The acceptance check of the foundation: the default scene's agentview shows the robot and the
// human, counted by segmentation through the Model's geom tags (not by eye).
class DefaultSceneTest : public ::hribench::testing::DefaultScene {
 protected:
  // Segmentation of `camera` at width x height, by geom owner.
  std::vector<model::GeomTag> seen_tags(int camera, int width, int height) {
    auto renderer = make_renderer(Backend::kOsmesa, *model_.m(), width, height);
    SegmentationImage segmentation;
    EXPECT_TRUE(renderer->render_segmentation(*model_.m(), *data_.mj, camera, segmentation));
    std::vector<model::GeomTag> tags;
    for (int g : segmentation.geom) {
      if (g < 0) continue;
      EXPECT_LT(g, model_.m()->ngeom);
      tags.push_back(model_.geom_tags[static_cast<size_t>(g)]);
    }
    return tags;
  }
};

TEST_F(DefaultSceneTest, AgentviewShowsRobotHumanTableAndObjects) {
  int robot = 0;
  int human = 0;
  int table = 0;
  int objects = 0;
  for (const model::GeomTag& tag : seen_tags(model_.agentview_camera, 96, 72)) {
    robot += tag.is_robot() ? 1 : 0;
    human += tag.is_human() ? 1 : 0;
    table += tag.owner == model::GeomOwner::kTable ? 1 : 0;
    objects += tag.owner == model::GeomOwner::kObject ? 1 : 0;
  }
  const int pixels = 96 * 72;
  EXPECT_GT(robot, pixels / 100) << "robot pixels";
  EXPECT_GT(human, pixels / 100) << "human pixels";
  EXPECT_GT(table, pixels / 20) << "table pixels";
  EXPECT_GT(objects, 10) << "object pixels";

  // The colour image of the same view is not blank: it has many distinct colours.
  Image image;
  ASSERT_TRUE(make_renderer(Backend::kOsmesa, *model_.m(), 96, 72)
                  ->render(model_, data_, model_.agentview_camera, image));
  std::vector<bool> seen(1 << 12, false);
  int distinct = 0;
  for (size_t i = 0; i < image.rgb.size(); i += 3) {
    const int key =
        ((image.rgb[i] >> 4) << 8) | ((image.rgb[i + 1] >> 4) << 4) | (image.rgb[i + 2] >> 4);
    distinct += seen[static_cast<size_t>(key)] ? 0 : 1;
    seen[static_cast<size_t>(key)] = true;
  }
  EXPECT_GT(distinct, 20);
}

TEST_F(DefaultSceneTest, ThreadsRenderWithTheirOwnRenderers) {
  // One Renderer per thread on a shared Model (docs/design.md): same state, same pixels.
  const model::Model& model = model_;
  const sim::Data& data = data_;
  Image reference;
  make_renderer(Backend::kOsmesa, *model.m(), 48, 32)->render(model, data, model.agentview_camera,
                                                              reference);
  // Renderers made at once must leave MuJoCo's global error handler as it was.
  void (*const error_handler)(const char*) = mju_user_error;
  std::vector<Image> images(2);
  std::vector<std::thread> threads;
  for (size_t t = 0; t < images.size(); ++t) {
    threads.emplace_back([&, t] {
      auto renderer = make_renderer(Backend::kOsmesa, *model.m(), 48, 32);
      for (int i = 0; i < 3; ++i) renderer->render(model, data, model.agentview_camera, images[t]);
    });
  }
  for (std::thread& thread : threads) thread.join();
  for (const Image& image : images) EXPECT_EQ(image.rgb, reference.rgb);
  EXPECT_EQ(mju_user_error, error_handler);
}

TEST_F(DefaultSceneTest, RenderersOfAThreadShareItsContextAndKeepTheirImages) {
  // Renderers made one after another on a thread share its GL context (thread_gl_context);
  // each binds its own offscreen buffer, so interleaved renders of two sizes give the images
  // each gives alone, and a renderer made after another was destroyed renders the same.
  Image alone_small, alone_large;
  make_renderer(Backend::kOsmesa, *model_.m(), 40, 30)->render(model_, data_, model_.agentview_camera, alone_small);
  make_renderer(Backend::kOsmesa, *model_.m(), 64, 48)->render(model_, data_, model_.wrist_camera, alone_large);
  auto small = make_renderer(Backend::kOsmesa, *model_.m(), 40, 30);
  auto large = make_renderer(Backend::kOsmesa, *model_.m(), 64, 48);
  EXPECT_EQ(thread_gl_context(Backend::kOsmesa).get(), thread_gl_context(Backend::kOsmesa).get());
  Image a, b;
  for (int i = 0; i < 2; ++i) {
    ASSERT_TRUE(small->render(model_, data_, model_.agentview_camera, a));
    ASSERT_TRUE(large->render(model_, data_, model_.wrist_camera, b));
    EXPECT_EQ(a.rgb, alone_small.rgb) << i;
    EXPECT_EQ(b.rgb, alone_large.rgb) << i;
  }
}

TEST_F(DefaultSceneTest, WristCameraSeesTheFingers) {
  int fingers = 0;
  for (const model::GeomTag& tag : seen_tags(model_.wrist_camera, 64, 48)) {
    fingers += tag.owner == model::GeomOwner::kRobotFinger ? 1 : 0;
  }
  EXPECT_GT(fingers, 0);
}

TEST_F(DefaultSceneTest, ThreadsDrawVideoFramesAtOnce) {
  // Video frames (panels and a text band) drawn by renderers on two threads at once, made and
  // freed repeatedly, are the frame drawn alone (the GL lock of docs/rendering.md, "Threads").
  const model::Model& model = model_;
  const sim::Data& data = data_;
  RenderSettings settings;
  settings.font_scale = 100;
  const std::vector<BandRow> band(2, BandRow(3, BandCell{"t 8.00 s", {0.1F, 0.2F, 0.3F}}));
  const std::vector<int> cameras = {model.agentview_camera, model.wrist_camera};
  Image reference;
  ASSERT_TRUE(Renderer(Backend::kOsmesa, *model.m(), 128, 88, settings)
                  .render_panels(*model.m(), *data.mj, cameras, band, 12, reference));
  std::vector<Image> images(2);
  std::vector<std::thread> threads;
  for (size_t t = 0; t < images.size(); ++t) {
    threads.emplace_back([&, t] {
      for (int k = 0; k < 4; ++k) {
        Renderer renderer(Backend::kOsmesa, *model.m(), 128, 88, settings);
        for (int i = 0; i < 10; ++i) renderer.render_panels(*model.m(), *data.mj, cameras, band, 12, images[t]);
      }
    });
  }
  for (std::thread& thread : threads) thread.join();
  for (const Image& image : images) EXPECT_EQ(image.rgb, reference.rgb);
}

// The drawn hands (human/hand.h, added to the scene by the renderer) at the resolution policies
// use: seen by agentview at 224², with a silhouette that changes with the hand's shape. Their
// pixels carry their hand's capsule geom in segmentation.
TEST_F(DefaultSceneTest, AgentviewSeesTheHandShapes) {
  const auto hand_pixels = [&](const human::HandShape& shape, int size) {
    human::SkeletonPose pose = model_.human_start;
    pose.hands = {shape, shape};
    sim::set_human_pose(model_, data_, pose);
    sim::forward(model_, data_);
    auto renderer = make_renderer(Backend::kOsmesa, *model_.m(), size, size);
    SegmentationImage segmentation;
    EXPECT_TRUE(renderer->render_segmentation(*model_.m(), *data_.mj, model_.agentview_camera, segmentation));
    std::vector<bool> mask;
    for (const int g : segmentation.geom) {
      // The hands' contact capsules are not drawn: their pixels are the drawn fingers and palms.
      const model::GeomTag tag = g >= 0 ? model_.geom_tags[static_cast<size_t>(g)] : model::GeomTag{};
      mask.push_back(tag.is_human() && tag.region == human::BodyRegion::kHand);
    }
    return mask;
  };
  const auto count = [](const std::vector<bool>& mask) { return std::count(mask.begin(), mask.end(), true); };
  const auto differ = [](const std::vector<bool>& a, const std::vector<bool>& b) {
    long n = 0;
    for (size_t i = 0; i < a.size(); ++i) n += a[i] != b[i] ? 1 : 0;
    return n;
  };
  EXPECT_GT(count(hand_pixels({0, 0}, 224)), 40);
  const auto open = hand_pixels({0, 0}, 448);
  const auto closed = hand_pixels({1, 0}, 448);
  const auto pointing = hand_pixels({0, 1}, 448);
  EXPECT_GT(differ(open, closed), count(open) / 5);
  EXPECT_GT(differ(open, pointing), count(open) / 5);
  EXPECT_GT(differ(closed, pointing), count(closed) / 10);
}

// Our tessellation of capsules, spheres and cylinders (RenderSettings::shape_slices/stacks)
// looks like MuJoCo's in the images policies get, 224² from agentview and the wrist: colours
// differ by less than one level of 255 on average and by more than 32 levels in under 0.5 % of
// the pixels, and under 0.5 % of the pixels show another geom (docs/rendering.md "Shapes";
// measured: agentview 0.41, 0.17 % and 0.26 %; 8 x 4 shapes give 1.9 and 1.1 %, 16 x 4 0.77 %
// of the pixels on another geom).
TEST_F(DefaultSceneTest, OurShapesLookLikeMujocosAtPolicyResolution) {
  RenderSettings mujoco_shapes;
  mujoco_shapes.shape_slices = 0;
  mujoco_shapes.shape_stacks = 0;
  const double pixels = 224.0 * 224.0;
  for (const int camera : {model_.agentview_camera, model_.wrist_camera}) {
    SCOPED_TRACE(mj_id2name(model_.m(), mjOBJ_CAMERA, camera));
    Image ours;
    Image theirs;
    ASSERT_TRUE(make_renderer(Backend::kOsmesa, *model_.m(), 224, 224)->render(model_, data_, camera, ours));
    ASSERT_TRUE(make_renderer(Backend::kOsmesa, *model_.m(), 224, 224, mujoco_shapes)
                    ->render(model_, data_, camera, theirs));
    double difference = 0;  // per pixel, the largest of its three channels' differences
    int far = 0;
    for (size_t i = 0; i < ours.rgb.size(); i += 3) {
      int pixel = 0;
      for (size_t c = 0; c < 3; ++c) pixel = std::max(pixel, std::abs(ours.rgb[i + c] - theirs.rgb[i + c]));
      difference += pixel;
      far += pixel > 32 ? 1 : 0;
    }
    EXPECT_LT(difference / pixels, 1.0);
    EXPECT_LT(far / pixels, 0.005);

    SegmentationImage our_geoms;
    SegmentationImage their_geoms;
    ASSERT_TRUE(make_renderer(Backend::kOsmesa, *model_.m(), 224, 224)
                    ->render_segmentation(*model_.m(), *data_.mj, camera, our_geoms));
    ASSERT_TRUE(make_renderer(Backend::kOsmesa, *model_.m(), 224, 224, mujoco_shapes)
                    ->render_segmentation(*model_.m(), *data_.mj, camera, their_geoms));
    int other_geom = 0;
    for (size_t i = 0; i < our_geoms.geom.size(); ++i) other_geom += our_geoms.geom[i] != their_geoms.geom[i] ? 1 : 0;
    EXPECT_LT(other_geom / pixels, 0.005);
  }
}

// Leaving the geoms wholly outside the view out of the draw (RenderSettings::cull_outside_view)
// changes no pixel and no segment, for both cameras, square and not; the wrist camera sees few
// of the scene's geoms, so it draws far fewer.
TEST_F(DefaultSceneTest, CullingWhatIsOutOfViewChangesNoPixel) {
  RenderSettings everything;
  everything.cull_outside_view = false;
  for (const auto& [width, height] : {std::pair{224, 224}, std::pair{96, 48}, std::pair{48, 96}}) {
    for (const int camera : {model_.agentview_camera, model_.wrist_camera}) {
      SCOPED_TRACE(std::string(mj_id2name(model_.m(), mjOBJ_CAMERA, camera)) + " " + std::to_string(width) + "x" +
                   std::to_string(height));
      auto culled = make_renderer(Backend::kOsmesa, *model_.m(), width, height);
      auto all = make_renderer(Backend::kOsmesa, *model_.m(), width, height, everything);
      Image a, b;
      ASSERT_TRUE(culled->render(model_, data_, camera, a));
      ASSERT_TRUE(all->render(model_, data_, camera, b));
      EXPECT_EQ(a.rgb, b.rgb);
      EXPECT_LE(culled->drawn_geoms(), all->drawn_geoms());
      if (camera == model_.wrist_camera && width == height) {
        EXPECT_LT(culled->drawn_geoms(), all->drawn_geoms() / 2) << culled->drawn_geoms() << " of " << all->drawn_geoms();
      }
      SegmentationImage sa, sb;
      ASSERT_TRUE(culled->render_segmentation(*model_.m(), *data_.mj, camera, sa));
      ASSERT_TRUE(all->render_segmentation(*model_.m(), *data_.mj, camera, sb));
      EXPECT_EQ(sa.geom, sb.geom);
    }
  }
}

}  // namespace
}  // namespace hribench::render

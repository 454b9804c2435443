#include "model/model.h"

#include <array>
#include <cstring>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "core/errors.h"
#include "support/mujoco_fixture.h"

namespace hribench::model {
namespace {

using ::testing::HasSubstr;
using ModelTest = testing::MujocoTest;

TEST_F(ModelTest, DefaultSceneBuildsWithRobotObjectsHumanAndCameras) {
  const Model model = build(SceneSpec::Default());
  const mjModel* m = model.m();
  ASSERT_NE(m, nullptr);
  EXPECT_DOUBLE_EQ(m->opt.timestep, kTimestep);
  EXPECT_EQ(m->opt.integrator, mjINT_EULER);
  EXPECT_TRUE(model.servo_damping_in_joints);
  EXPECT_EQ(m->nu, 8);
  EXPECT_EQ(m->nmocap, human::kNumJoints);
  ASSERT_EQ(model.objects.size(), 3u);
  EXPECT_EQ(model.objects[0].name, "cube");
  EXPECT_EQ(model.objects[0].kind, ObjectKind::kCube);
  EXPECT_EQ(model.object_index("bin"), 2);
  EXPECT_EQ(model.object_index("nope"), -1);
  EXPECT_STREQ(mj_id2name(m, mjOBJ_CAMERA, model.agentview_camera), "agentview");
  EXPECT_STREQ(mj_id2name(m, mjOBJ_CAMERA, model.wrist_camera), "wrist");
  EXPECT_TRUE(model.has_human);
  for (int j = 0; j < human::kNumJoints; ++j) EXPECT_GE(model.human_mocap[static_cast<size_t>(j)], 0);
  EXPECT_THAT(model.mjcf, HasSubstr("<mujoco model=\"hribench\">"));
}

TEST_F(ModelTest, EveryGeomIsTagged) {
  const Model model = build(SceneSpec::Default());
  const mjModel* m = model.m();
  ASSERT_EQ(model.geom_tags.size(), static_cast<size_t>(m->ngeom));
  std::set<int> links, fingers, objects;
  int hand = 0, human_geoms = 0;
  for (int g = 0; g < m->ngeom; ++g) {
    const GeomTag& tag = model.geom_tags[static_cast<size_t>(g)];
    EXPECT_NE(tag.owner, GeomOwner::kOther) << mj_id2name(m, mjOBJ_GEOM, g);
    if (tag.owner == GeomOwner::kRobotLink) links.insert(tag.index);
    if (tag.owner == GeomOwner::kRobotFinger) fingers.insert(tag.index);
    if (tag.owner == GeomOwner::kRobotHand) ++hand;
    if (tag.owner == GeomOwner::kObject) objects.insert(tag.index);
    if (tag.owner == GeomOwner::kHuman) {
      ++human_geoms;
      const auto& capsule = model.human_capsules[static_cast<size_t>(tag.index)];
      EXPECT_EQ(tag.region, capsule.region);
      EXPECT_EQ(tag.joint, capsule.joint);
      EXPECT_EQ(m->geom_bodyid[g], model.human_body[static_cast<size_t>(human::index(capsule.joint))]);
    }
    if (tag.is_robot()) {
      EXPECT_FALSE(tag.is_human());
    }
  }
  EXPECT_EQ(links, (std::set<int>{0, 1, 2, 3, 4, 5, 6, 7}));
  EXPECT_EQ(fingers, (std::set<int>{0, 1}));
  EXPECT_GT(hand, 0);
  EXPECT_EQ(objects, (std::set<int>{0, 1, 2}));
  EXPECT_EQ(human_geoms, static_cast<int>(model.human_capsules.size()));
  EXPECT_EQ(model.geom_tags[static_cast<size_t>(model.table_geom)].owner, GeomOwner::kTable);
  EXPECT_EQ(model.geom_tags[static_cast<size_t>(model.floor_geom)].owner, GeomOwner::kFloor);
}

TEST_F(ModelTest, HumanCollidesWithRobotAndObjectsButNotItselfTableOrFloor) {
  const Model model = build(SceneSpec::Default());
  const mjModel* m = model.m();
  const auto collide = [&](int a, int b) {
    return (m->geom_contype[a] & m->geom_conaffinity[b]) || (m->geom_contype[b] & m->geom_conaffinity[a]);
  };
  const int human_geom = model.human_capsule_geom[0];
  const int other_human = model.human_capsule_geom[1];
  const int link = mj_name2id(m, mjOBJ_GEOM, "link5_g0");
  const int cube = mj_name2id(m, mjOBJ_GEOM, "object_cube_g0");
  EXPECT_TRUE(collide(human_geom, link));
  EXPECT_TRUE(collide(human_geom, cube));
  EXPECT_FALSE(collide(human_geom, other_human));
  EXPECT_FALSE(collide(human_geom, model.table_geom));
  EXPECT_FALSE(collide(human_geom, model.floor_geom));
  EXPECT_TRUE(collide(cube, model.table_geom));
  EXPECT_TRUE(collide(link, cube));
}

TEST_F(ModelTest, EveryObjectKindBuilds) {
  SceneSpec spec;
  const char* kinds[] = {"cube", "cup", "bottle", "plate", "bin", "tray", "box", "plank"};
  const double xs[] = {0.3, 0.3, 0.3, 0.6, 0.6, 0.85, 0.88, 0.55};
  const double ys[] = {-0.35, -0.15, 0.05, -0.35, -0.05, 0.2, -0.25, 0.42};
  for (size_t i = 0; i < 8; ++i) {
    ObjectSpec o;
    o.kind = kinds[i];
    o.x = xs[i];
    o.y = ys[i];
    o.yaw = i < 4 ? 0.3 : 0.0;
    o.colour = colour_names()[i];
    spec.objects.push_back(o);
  }
  const Model model = build(spec);
  ASSERT_EQ(model.objects.size(), 8u);
  EXPECT_EQ(model.objects[0].name, "cube0");  // default names: kind + index
  EXPECT_GE(model.objects[6].lid_joint, 0);
  EXPECT_EQ(model.objects[0].lid_joint, -1);
  for (const ObjectInfo& o : model.objects) EXPECT_GT(o.mass, 0.0) << o.name;
}

TEST_F(ModelTest, NoHumanMeansNoMocap) {
  SceneSpec spec = SceneSpec::Default();
  spec.human.present = false;
  const Model model = build(spec);
  EXPECT_EQ(model.m()->nmocap, 0);
  EXPECT_FALSE(model.has_human);
  EXPECT_TRUE(model.human_capsule_geom.empty());
}

// Bad specs: one clear InputError each.
std::string build_error(const SceneSpec& spec) {
  try {
    build(spec);
  } catch (const core::InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST_F(ModelTest, RejectsUnknownKindAndColour) {
  SceneSpec spec = SceneSpec::Default();
  spec.objects[1].kind = "teapot";
  EXPECT_EQ(build_error(spec),
            "scene.objects[1].kind: expected one of cube, cup, bottle, plate, bin, tray, box, "
            "plank, got 'teapot'");
  spec = SceneSpec::Default();
  spec.objects[0].colour = "mauve";
  EXPECT_THAT(build_error(spec), HasSubstr("scene.objects[0].colour: expected one of red, green"));
  EXPECT_THAT(build_error(spec), HasSubstr("got 'mauve'"));
}

TEST_F(ModelTest, RejectsObjectsOffTheTableOnTheBaseOrOverlapping) {
  SceneSpec spec = SceneSpec::Default();
  spec.objects[0].x = 1.2;
  EXPECT_THAT(build_error(spec), HasSubstr("scene.objects[0]: expected an object footprint on the table"));
  EXPECT_THAT(build_error(spec), HasSubstr("got 'cube' off the table at x=1.200"));
  spec = SceneSpec::Default();
  spec.objects[0].y = 0.49;  // centre on the table, footprint over the edge
  EXPECT_THAT(build_error(spec), HasSubstr("off the table"));
  spec = SceneSpec::Default();
  spec.objects[0].x = 0.05;
  EXPECT_THAT(build_error(spec), HasSubstr("expected an object clear of the robot base"));
  spec = SceneSpec::Default();
  spec.objects[1].x = spec.objects[0].x + 0.03;
  spec.objects[1].y = spec.objects[0].y;
  EXPECT_EQ(build_error(spec),
            "scene.objects[1]: expected objects that do not overlap, got 'cup' overlaps 'cube'");
}

TEST_F(ModelTest, RejectsBadNamesScalesHumansAndHolds) {
  SceneSpec spec = SceneSpec::Default();
  spec.objects[1].name = "cube";
  EXPECT_EQ(build_error(spec),
            "scene.objects[1].name: expected a name not used by another object, got duplicate 'cube'");
  spec = SceneSpec::Default();
  spec.objects[1].name = "my cup";
  EXPECT_THAT(build_error(spec), HasSubstr("expected 1-40 characters of [A-Za-z0-9_], got 'my cup'"));
  spec = SceneSpec::Default();
  spec.objects[0].size_scale = 3;
  EXPECT_EQ(build_error(spec), "scene.objects[0].size_scale: expected a value in [0.5, 2], got 3");
  spec = SceneSpec::Default();
  spec.human.height = 3.1;
  EXPECT_EQ(build_error(spec), "scene.human.height: expected a height in [1.0, 2.5] m, got 3.1");
  spec = SceneSpec::Default();
  spec.light_intensity = 0;
  EXPECT_THAT(build_error(spec), HasSubstr("scene.light_intensity"));
  spec = SceneSpec::Default();
  spec.human.present = false;
  spec.objects[0].held_by = human::Side::kLeft;
  EXPECT_EQ(build_error(spec), "scene.objects[0].held_by: expected a scene with a human, got no human");
  spec = SceneSpec::Default();
  spec.objects[0].held_by = human::Side::kLeft;
  spec.objects[1].held_by = human::Side::kLeft;
  EXPECT_THAT(build_error(spec), HasSubstr("expected a free hand, got the left hand already holds 'cube'"));
}

// qpos[adr] after 1 s of passive physics from the home keyframe (the arm holds its pose).
double settled_qpos(const Model& model, int adr) {
  const mjModel* m = model.m();
  mjData* d = mj_makeData(m);
  mj_resetDataKeyframe(m, d, 0);
  for (int i = 0; i < 500; ++i) mj_step(m, d);
  const double q = d->qpos[adr];
  mj_deleteData(d);
  return q;
}

TEST_F(ModelTest, PlatformIsAStaticTaggedBoxOnTheTable) {
  SceneSpec spec = SceneSpec::Default();
  PlatformSpec platform;
  platform.name = "stand";
  platform.x = 0.75;
  platform.y = 0.3;
  platform.length = 0.5;
  platform.width = 0.2;
  platform.height = 0.1;
  spec.platforms = {platform};
  spec.objects[1].x = 0.3;  // the cup out of the platform's way
  const Model model = build(spec);
  ASSERT_EQ(model.platforms.size(), 1u);
  EXPECT_EQ(model.platform_index("stand"), 0);
  EXPECT_EQ(model.platform_index("nope"), -1);
  const int geom = model.platforms[0].geom;
  ASSERT_GE(geom, 0);
  EXPECT_EQ(model.geom_tags[static_cast<size_t>(geom)].owner, GeomOwner::kPlatform);
  EXPECT_EQ(model.geom_tags[static_cast<size_t>(geom)].index, 0);
  const mjModel* m = model.m();
  EXPECT_EQ(m->body_weldid[m->geom_bodyid[geom]], 0);  // fixed to the world
  EXPECT_NEAR(m->geom_pos[3 * geom + 2] + m->geom_size[3 * geom + 2], kTableTopZ + 0.1, 1e-9);
  EXPECT_NEAR(model.platforms[0].X_WC.translation.z() + model.platforms[0].half_extents.z(),
              kTableTopZ + 0.1, 1e-12);
  EXPECT_NEAR(model.platforms[0].half_extents.x(), 0.25, 1e-12);
  spec.objects[1].x = 0.7;
  EXPECT_EQ(build_error(spec),
            "scene.objects[1]: expected an object clear of the platforms, got 'cup' overlaps the platform 'stand'");
  spec.objects[1].x = 0.3;
  spec.platforms[0].height = 0.8;
  EXPECT_EQ(build_error(spec), "scene.platforms[0].height: expected a height in [0.02, 0.5] m, got 0.8");
  spec.platforms[0].height = 0.1;
  spec.platforms.push_back(platform);
  spec.platforms[1].y = -0.3;
  EXPECT_EQ(build_error(spec),
            "scene.platforms[1].name: expected a name not used by another platform, got duplicate 'stand'");
  spec.platforms[1].name = "";
  spec.platforms[1].y = 0.25;
  EXPECT_EQ(build_error(spec),
            "scene.platforms[1]: expected platforms that do not overlap, got 'platform1' overlaps 'stand'");
  EXPECT_TRUE(build(SceneSpec::Default()).platforms.empty());
}

TEST_F(ModelTest, ObjectOnAPlatformRestsOnItsTopAndMayOverhang) {
  SceneSpec spec = SceneSpec::Default();
  PlatformSpec support;
  support.name = "support";
  support.x = 0.62;
  support.y = 0.0;
  support.length = 0.5;
  support.width = 0.12;
  support.height = 0.08;
  spec.platforms = {support};
  ObjectSpec plank;
  plank.kind = "plank";
  plank.name = "plank";
  plank.x = 0.62;
  plank.on = "support";
  spec.objects = {plank};
  const Model model = build(spec);
  EXPECT_NEAR(model.objects[0].X_W_start.translation.z(), kTableTopZ + 0.08, 1e-12);
  // It stays there (the 0.6 m plank overhangs the 0.5 m support at both ends).
  EXPECT_NEAR(settled_qpos(model, model.objects[0].qpos_adr + 2), kTableTopZ + 0.08, 2e-3);
  spec.objects[0].on = "";
  EXPECT_EQ(build_error(spec),
            "scene.objects[0]: expected an object clear of the platforms, got 'plank' overlaps the platform 'support'");
  spec.objects[0].on = "table";
  EXPECT_EQ(build_error(spec), "scene.objects[0].on: expected the name of a platform of the scene, got 'table'");
  spec.objects[0].on = "support";
  spec.objects[0].y = 0.1;
  EXPECT_EQ(build_error(spec),
            "scene.objects[0].on: expected a footprint centre over the platform, got 'plank' at x=0.620 y=0.100 is off 'support'");
}

TEST_F(ModelTest, ObjectInsideAContainerRestsOnItsFloor) {
  SceneSpec spec = SceneSpec::Default();
  ObjectSpec box;
  box.kind = "box";
  box.name = "box";
  box.x = 0.68;
  ObjectSpec item;
  item.kind = "cup";
  item.name = "item";
  item.x = 0.68;
  item.inside = "box";
  spec.objects = {box, item};
  const Model model = build(spec);
  EXPECT_NEAR(model.objects[1].X_W_start.translation.z(),
              kTableTopZ + container_floor_height(ObjectKind::kBox, 1.0), 1e-12);
  EXPECT_GT(container_floor_height(ObjectKind::kBin, 1.0), 0);
  EXPECT_EQ(container_floor_height(ObjectKind::kCube, 1.0), 0);
  EXPECT_NEAR(settled_qpos(model, model.objects[1].qpos_adr), 0.68, 2e-3);
  EXPECT_NEAR(settled_qpos(model, model.objects[1].qpos_adr + 2),
              model.objects[1].X_W_start.translation.z(), 2e-3);
  // Refused: not fitting, not a container, the container later, held and inside.
  spec.objects[1].x = 0.76;
  EXPECT_EQ(build_error(spec),
            "scene.objects[1].inside: expected an object that fits within the container's walls, got 'item' does not fit in 'box'");
  spec.objects[1].x = 0.68;
  spec.objects[1].kind = "bottle";  // taller than the closed box
  EXPECT_EQ(build_error(spec),
            "scene.objects[1].inside: expected an object that fits within the container's walls, got 'item' does not fit in 'box'");
  spec.objects[1].kind = "cup";
  spec.objects[0].kind = "plate";
  EXPECT_EQ(build_error(spec),
            "scene.objects[1].inside: expected an earlier bin, tray or box of the scene resting on the table, got 'box'");
  spec.objects[0].kind = "box";
  std::swap(spec.objects[0], spec.objects[1]);
  spec.objects[1].x = 0.5;
  spec.objects[1].inside = "";
  spec.objects[0].inside = "box";
  EXPECT_THAT(build_error(spec), HasSubstr("expected an earlier bin, tray or box"));
  spec.objects[0].inside = "";
  spec.objects[0].x = 0.68;
  spec.objects[0].held_by = human::Side::kRight;
  spec.objects[0].inside = "box";
  EXPECT_EQ(build_error(spec), "scene.objects[0]: expected at most one of held_by, inside and on, got 'item' has more than one");
}

TEST_F(ModelTest, NamesAndColours) {
  EXPECT_EQ(object_kind_from_name("plank"), ObjectKind::kPlank);
  EXPECT_EQ(object_kind_from_name("Plank"), std::nullopt);
  EXPECT_EQ(to_string(ObjectKind::kBox), "box");
  for (int k = 0; k < kNumObjectKinds; ++k)
    EXPECT_EQ(object_kind_from_name(to_string(static_cast<ObjectKind>(k))), static_cast<ObjectKind>(k));
  ASSERT_TRUE(colour_from_name("red"));
  EXPECT_GT(colour_from_name("red")->r, 0.5f);
  EXPECT_EQ(colour_from_name("nope"), std::nullopt);
  EXPECT_EQ(to_string(GeomOwner::kRobotFinger), "robot_finger");
}

// build() compiles with an empty constraint arena and sets its sizes afterwards (model.cc, load):
// the model must be the one MuJoCo compiles from the scene's own MJCF, byte for byte (once the
// servos' damping is back in the servos), with every robot, with and without the person, with
// an object in the person's hand.
TEST_F(ModelTest, TheArenaSetAfterCompilingGivesTheSameModel) {
  std::vector<SceneSpec> specs;
  for (const std::string_view robot : robot_names()) {
    SceneSpec spec = SceneSpec::Default();
    spec.robot = std::string(robot);
    specs.push_back(spec);
  }
  SceneSpec alone = SceneSpec::Default();
  alone.human.present = false;
  specs.push_back(alone);
  SceneSpec held = SceneSpec::Default();
  held.objects[0].held_by = human::Side::kRight;
  specs.push_back(held);
  const auto bytes = [](const mjModel* m) {
    std::vector<char> out(static_cast<size_t>(mj_sizeModel(m)));
    mj_saveModel(m, nullptr, out.data(), static_cast<int>(out.size()));
    return out;
  };
  for (const SceneSpec& spec : specs) {
    Model model = build(spec);
    servo_damping_in_servos(model);  // the arm's damping as compiled
    const std::string& xml = model.mjcf;
    auto files = std::make_unique<mjVFS>();
    mj_defaultVFS(files.get());
    ASSERT_EQ(mj_makeEmptyFileVFS(files.get(), "scene.xml", static_cast<int>(xml.size())), 0);
    std::memcpy(files->filedata[mj_findFileVFS(files.get(), "scene.xml")], xml.data(), xml.size());
    std::array<char, 1024> error{};
    const std::unique_ptr<mjModel, MjModelDeleter> direct(mj_loadXML("scene.xml", files.get(), error.data(), static_cast<int>(error.size())));
    mj_deleteVFS(files.get());
    ASSERT_NE(direct, nullptr) << error.data();
    EXPECT_EQ(model.m()->njmax, kMaxConstraintRows);
    EXPECT_EQ(model.m()->nconmax, kMaxContacts);
    EXPECT_GT(model.m()->nstack, 1000);
    EXPECT_TRUE(bytes(model.m()) == bytes(direct.get())) << spec.robot << ", person " << spec.human.present;
  }
}

TEST_F(ModelTest, ToMjcfIsDeterministic) {
  EXPECT_EQ(to_mjcf(SceneSpec::Default()), to_mjcf(SceneSpec::Default()));
}

}  // namespace
}  // namespace hribench::model

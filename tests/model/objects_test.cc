// Object geometry and masses as built into the model.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include "core/errors.h"
#include "model/mjcf.h"
#include "model/model.h"
#include "script/catalogue.h"
#include "support/mujoco_fixture.h"

namespace hribench::model {
namespace {

using ObjectsTest = testing::MujocoTest;
using core::Vec3;

// Axis-aligned bounding box (centre, half extents) of geom g, in the frame F given X_FW.
struct GeomBox {
  Vec3 centre;
  Vec3 half;
};
GeomBox geom_box_in(const mjModel& m, const mjData& d, int g, const core::Pose& X_FW) {
  const auto b = static_cast<size_t>(g);
  const Vec3 p_W(d.geom_xpos[3 * b], d.geom_xpos[3 * b + 1], d.geom_xpos[3 * b + 2]);
  // Rows of geom_xmat are world axes; columns are geom axes.
  Eigen::Matrix3d R_WG;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) R_WG(r, c) = d.geom_xmat[9 * b + static_cast<size_t>(3 * r + c)];
  }
  const Eigen::Matrix3d R = X_FW.rotation.toRotationMatrix() * R_WG;
  const double* size = m.geom_size + 3 * b;
  Vec3 half;
  for (int i = 0; i < 3; ++i) {
    const double axial = std::abs(R(i, 2));  // geom z: cylinder and capsule axis
    const double radial = std::sqrt(std::max(0.0, 1.0 - axial * axial));
    switch (m.geom_type[g]) {
      case mjGEOM_BOX:
        half[i] = std::abs(R(i, 0)) * size[0] + std::abs(R(i, 1)) * size[1] + axial * size[2];
        break;
      case mjGEOM_SPHERE:
        half[i] = size[0];
        break;
      case mjGEOM_CYLINDER:
        half[i] = axial * size[1] + radial * size[0];
        break;
      case mjGEOM_CAPSULE:
        half[i] = axial * size[1] + size[0];
        break;
      case mjGEOM_ELLIPSOID:
        half[i] = std::hypot(R(i, 0) * size[0], R(i, 1) * size[1], R(i, 2) * size[2]);
        break;
      default:
        half[i] = m.geom_rbound[g];  // any other shape: its bounding sphere
        break;
    }
  }
  return {X_FW * p_W, half};
}

// The model builds every kind of the catalogue (script/catalogue.h), in ObjectKind order, at the
// catalogue's size, and colours objects by the catalogue's names.
TEST(ObjectCatalogue, TheModelsKindsAndColoursAreTheCatalogues) {
  ASSERT_EQ(script::catalogue_kinds().size(), static_cast<size_t>(kNumObjectKinds));
  for (int i = 0; i < kNumObjectKinds; ++i) {
    const auto kind = static_cast<ObjectKind>(i);
    const script::ObjectKindEntry& entry = script::catalogue_kinds()[static_cast<size_t>(i)];
    EXPECT_EQ(to_string(kind), entry.name);
    EXPECT_EQ(object_kind_from_name(entry.name), kind);
    EXPECT_EQ(mjcf::nominal_half_extents(kind), entry.half_extents) << entry.name;
  }
  EXPECT_EQ(object_kind_from_name("platform"), std::nullopt);  // sized by the script, not a kind
  ASSERT_EQ(colour_names().size(), script::catalogue_colours().size());
  for (const script::ColourEntry& c : script::catalogue_colours()) {
    const std::optional<Rgba> rgba = colour_from_name(c.name);
    ASSERT_TRUE(rgba) << c.name;
    EXPECT_EQ(rgba->r, c.rgba[0]);
    EXPECT_EQ(rgba->a, 1.0f);
  }
  // One spelling; the old one still reads as it.
  EXPECT_EQ(std::count(colour_names().begin(), colour_names().end(), "gray"), 1);
  EXPECT_EQ(std::count(colour_names().begin(), colour_names().end(), "grey"), 0);
  ASSERT_TRUE(colour_from_name("grey"));
  EXPECT_EQ(colour_from_name("grey")->g, colour_from_name("gray")->g);
}

TEST_F(ObjectsTest, UnknownKindAndColourNameTheCataloguesChoices) {
  SceneSpec spec;
  spec.human.present = false;
  ObjectSpec o;
  o.kind = "sphere";
  spec.objects = {o};
  try {
    build(spec);
    FAIL() << "built a sphere";
  } catch (const core::InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "scene.objects[0].kind: expected one of cube, cup, bottle, plate, bin, tray, box, plank, got 'sphere'");
  }
  spec.objects[0].kind = "cube";
  spec.objects[0].colour = "magenta";
  try {
    build(spec);
    FAIL() << "built a magenta cube";
  } catch (const core::InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "scene.objects[0].colour: expected one of red, green, blue, yellow, orange, purple, white, black, "
              "gray, brown, pink, cyan, got 'magenta'");
  }
}

TEST_F(ObjectsTest, SizesAndMassesScale) {
  SceneSpec spec;
  spec.human.present = false;
  ObjectSpec small, large;
  small.kind = large.kind = "cube";
  small.x = 0.4;
  large.x = 0.7;
  large.size_scale = 2;
  spec.objects = {small, large};
  const Model model = build(spec);
  EXPECT_NEAR(model.objects[0].mass, mjcf::nominal_mass(ObjectKind::kCube), 1e-9);
  EXPECT_NEAR(model.objects[1].mass, 8 * mjcf::nominal_mass(ObjectKind::kCube), 1e-9);
  EXPECT_LT((model.objects[1].half_extents - 2 * model.objects[0].half_extents).norm(), 1e-12);
}

// SceneSpec::base_feet (on as built since pool v7): one hidden, massless box inside the round
// base of each cup and bottle, level with the base's bottom; nothing else in the model changes.
TEST_F(ObjectsTest, BaseFeetAreHiddenMasslessSquaresInsideRoundBases) {
  SceneSpec spec;
  EXPECT_TRUE(spec.base_feet);
  spec.base_feet = false;
  spec.human.present = false;
  spec.objects.resize(3);
  const char* kinds[] = {"cup", "bottle", "cube"};
  for (size_t i = 0; i < 3; ++i) {
    spec.objects[i].kind = kinds[i];
    spec.objects[i].x = 0.3 + 0.2 * static_cast<double>(i);
    spec.objects[i].size_scale = 1.2;
  }
  const Model without = build(spec);
  spec.base_feet = true;
  const Model with = build(spec);
  const mjModel& a = *without.m();
  const mjModel& b = *with.m();
  ASSERT_EQ(b.ngeom, a.ngeom + 2);
  ASSERT_EQ(b.nbody, a.nbody);
  for (int i = 0; i < a.nbody; ++i) {
    EXPECT_EQ(a.body_mass[i], b.body_mass[i]) << i;
    for (int k = 0; k < 3; ++k) EXPECT_EQ(a.body_inertia[3 * i + k], b.body_inertia[3 * i + k]) << i;
  }
  mjData* d = mj_makeData(&b);
  mj_resetDataKeyframe(&b, d, 0);
  mj_kinematics(&b, d);
  for (const ObjectInfo& o : with.objects) {
    const std::string name = "object_" + o.name + "_foot_g0";
    const int g = mj_name2id(&b, mjOBJ_GEOM, name.c_str());
    if (o.kind == ObjectKind::kCube) {
      EXPECT_EQ(g, -1) << name;
      continue;
    }
    ASSERT_GE(g, 0) << name;
    EXPECT_EQ(b.geom_bodyid[g], o.body) << name;
    EXPECT_EQ(b.geom_type[g], mjGEOM_BOX) << name;
    EXPECT_EQ(b.geom_group[g], 3) << name;
    EXPECT_EQ(b.geom_condim[g], 3) << name;
    // Its bottom face level with the base's (the object's first geom), its corners inside the
    // base's circle.
    const int base = mj_name2id(&b, mjOBJ_GEOM, ("object_" + o.name + "_g0").c_str());
    ASSERT_EQ(b.geom_type[base], mjGEOM_CYLINDER) << name;
    const core::Pose X_OW = o.X_W_start.inverse();
    const GeomBox foot = geom_box_in(b, *d, g, X_OW);
    const GeomBox cylinder = geom_box_in(b, *d, base, X_OW);
    EXPECT_NEAR(foot.centre.z() - foot.half.z(), cylinder.centre.z() - cylinder.half.z(), 1e-12) << name;
    EXPECT_LT(std::hypot(b.geom_size[3 * g], b.geom_size[3 * g + 1]), b.geom_size[3 * base]) << name;
  }
  mj_deleteData(d);
}

TEST_F(ObjectsTest, GeomsLieInsideTheDeclaredBoundingBox) {
  SceneSpec spec;
  spec.human.present = false;
  for (const script::ObjectKindEntry& kind : script::catalogue_kinds()) {
    ObjectSpec o;
    o.kind = std::string(kind.name);
    o.x = 0.5;
    spec.objects = {o};
    const Model model = build(spec);
    const mjModel* m = model.m();
    mjData* d = mj_makeData(m);
    mj_resetDataKeyframe(m, d, 0);
    mj_kinematics(m, d);
    const ObjectInfo& info = model.objects[0];
    const Vec3 h = info.half_extents;
    // Each geom's axis-aligned box in the object frame lies within [-h, h] x [0, 2h] + 1 mm.
    const core::Pose X_OW = info.X_W_start.inverse();
    const Vec3 lo(-h.x(), -h.y(), 0.0);
    const Vec3 hi(h.x(), h.y(), 2 * h.z());
    int checked = 0;
    for (int g = 0; g < m->ngeom; ++g) {
      if (model.geom_tags[static_cast<size_t>(g)].owner != GeomOwner::kObject) continue;
      const GeomBox box = geom_box_in(*m, *d, g, X_OW);
      for (int i = 0; i < 3; ++i) {
        const std::string where = std::string(kind.name) + " geom " + std::to_string(g);
        EXPECT_GT(box.centre[i] - box.half[i], lo[i] - 1e-3) << where << " axis " << i;
        EXPECT_LT(box.centre[i] + box.half[i], hi[i] + 1e-3) << where << " axis " << i;
      }
      ++checked;
    }
    EXPECT_GT(checked, 0) << kind.name;
    if (info.kind == ObjectKind::kBox) {
      // The lid opens upward: at 1 rad its free edge is above the closed lid.
      const int lid = info.lid_body;
      const double closed = d->xipos[3 * lid + 2];
      d->qpos[m->jnt_qposadr[info.lid_joint]] = 1.0;
      mj_kinematics(m, d);
      EXPECT_GT(d->xipos[3 * lid + 2], closed + 0.05);
    }
    mj_deleteData(d);
  }
}

}  // namespace
}  // namespace hribench::model

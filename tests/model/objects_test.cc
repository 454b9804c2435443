// Object geometry and masses as built into the model.

#include <gtest/gtest.h>

#include "model/mjcf.h"
#include "model/model.h"
#include "support/mujoco_fixture.h"

namespace hribench::model {
namespace {

using ObjectsTest = testing::MujocoTest;
using core::Vec3;

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

TEST_F(ObjectsTest, GeomsLieInsideTheDeclaredBoundingBox) {
  SceneSpec spec;
  spec.human.present = false;
  const char* kinds[] = {"cube", "cup", "bottle", "plate", "bin", "tray", "box", "plank"};
  for (const char* kind : kinds) {
    ObjectSpec o;
    o.kind = kind;
    o.x = 0.5;
    spec.objects = {o};
    const Model model = build(spec);
    const mjModel* m = model.m();
    mjData* d = mj_makeData(m);
    mj_resetDataKeyframe(m, d, 0);
    mj_kinematics(m, d);
    const ObjectInfo& info = model.objects[0];
    const Vec3 h = info.half_extents;
    // Geom AABBs (world = body frame translated, yaw 0) within [-h, h] x [0, 2h] + 1 mm.
    for (int g = 0; g < m->ngeom; ++g) {
      if (model.geom_tags[static_cast<size_t>(g)].owner != GeomOwner::kObject) continue;
      const Vec3 c = Vec3(d->geom_xpos[3 * g], d->geom_xpos[3 * g + 1], d->geom_xpos[3 * g + 2]) -
                     info.X_W_start.translation;
      const double r = m->geom_rbound[g];
      EXPECT_GT(c.z() + r, 0.0) << kind;
      EXPECT_LT(c.z(), 2 * h.z() + 1e-3) << kind;
      EXPECT_LT(std::abs(c.x()), h.x() + 1e-3) << kind;
      EXPECT_LT(std::abs(c.y()), h.y() + 1e-3) << kind;
    }
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

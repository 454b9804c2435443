#pragma once
// Minimum human–robot separation d(t) (docs/metrics.md: the minimum distance between any robot geom
// and any human geom) with its closest points, from the geoms' world poses in mjData.
//
// Which geoms count: every geom tagged robot (link, hand, finger) or human in
// model::Model::geom_tags that can collide (contype or conaffinity non-zero). Shapes:
// sphere, capsule, cylinder and box exactly (sim/distance.h); an ellipsoid as the sphere of
// its largest semi-axis and a mesh as its bounding sphere (mjModel.geom_rbound), both of which
// can only under-estimate the distance; planes and height fields are not robot/human shapes
// and are skipped.
//
// Poses are read from mjData.geom_xpos / geom_xmat, so the caller must have run forward
// kinematics (mj_forward, mj_step or mj_kinematics) for the current qpos and mocap poses.

#include <limits>
#include <vector>

#include <mujoco/mujoco.h>

#include "core/math.h"
#include "human/skeleton.h"
#include "model/model.h"
#include "sim/data.h"
#include "sim/distance.h"

namespace hribench::sim {

struct Separation {
  // Signed distance, m: > 0 apart, <= 0 touching/penetrating (minus the penetration depth).
  // +infinity when the model has no robot geom or no human geom.
  double distance = std::numeric_limits<double>::infinity();
  core::Vec3 point_robot_W = core::Vec3::Zero();  // closest point on the robot geom's surface
  core::Vec3 point_human_W = core::Vec3::Zero();  // closest point on the human geom's surface
  int robot_geom = -1;  // MuJoCo geom ids; -1 when distance is infinite
  int human_geom = -1;
  human::BodyRegion region = human::BodyRegion::kTorso;  // region of human_geom

  bool valid() const { return robot_geom >= 0; }
};

// The robot and human geoms of one Model, with their shape types and sizes, precomputed once
// so that min_separation() does not allocate. Immutable; shareable between threads.
struct SeparationMonitor {
  struct Geom {
    int id = -1;                       // MuJoCo geom id
    ShapeType type = ShapeType::kSphere;
    core::Vec3 size = core::Vec3::Zero();  // sizes in Shape's (MuJoCo geom_size) convention
    double bound = 0;                  // bounding-sphere radius about geom_xpos (geom_rbound)
    human::BodyRegion region = human::BodyRegion::kTorso;  // human geoms only
  };
  std::vector<Geom> robot;  // in geom id order
  std::vector<Geom> human;  // in geom id order

  static SeparationMonitor FromModel(const model::Model& model);
};

// Minimum separation over all (robot geom, human geom) pairs for the poses in `d`. Exact (the
// pairs whose bounding spheres are already farther apart than the best pair are skipped).
// Ties keep the pair with the lowest (robot geom, human geom) ids. Allocation-free.
Separation min_separation(const SeparationMonitor& monitor, const mjData& d);

// The same on a running episode's Data (positions as of its last mj_step / forward()).
Separation min_separation(const SeparationMonitor& monitor, const Data& data);

// Convenience for one-off queries: builds the monitor (allocates) and queries it.
Separation min_separation(const model::Model& model, const mjData& d);
Separation min_separation(const model::Model& model, const Data& data);

// Motion of the robot's closest point (the v_r of ISO/TS 15066 speed-and-separation
// monitoring, docs/metrics.md HCS), from the velocities of the last mj_forward / mj_step.
struct RobotPointMotion {
  core::Vec3 velocity_W = core::Vec3::Zero();  // m/s, of point_robot_W fixed to its body
  // Component of velocity_W along the unit direction from the robot to the human (m/s;
  // positive = approaching). The direction is (point_human - point_robot) / distance, which
  // also holds in penetration; at distance exactly 0 it is taken toward the human geom's centre.
  double speed_toward_human = 0;
};
// Zero motion when `separation` is not valid.
RobotPointMotion robot_point_motion(const mjModel& m, const mjData& d,
                                    const Separation& separation);

// Distance between one robot geom and one human geom of the monitor (indices into
// monitor.robot / monitor.human), without any pruning. For tests and diagnostics.
Separation pair_separation(const SeparationMonitor& monitor, const mjData& d, size_t robot_index,
                           size_t human_index);

}  // namespace hribench::sim

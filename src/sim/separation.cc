#include "sim/separation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "core/errors.h"

namespace hribench::sim {
namespace {

// The monitor's description of one geom, or nullopt for shapes that are skipped.
std::optional<SeparationMonitor::Geom> describe_geom(const mjModel& m, int g) {
  SeparationMonitor::Geom geom;
  geom.id = g;
  const mjtNum* size = m.geom_size + 3 * g;
  geom.size = core::Vec3(size[0], size[1], size[2]);
  geom.bound = m.geom_rbound[g];
  switch (m.geom_type[g]) {
    case mjGEOM_SPHERE:
      geom.type = ShapeType::kSphere;
      break;
    case mjGEOM_CAPSULE:
      geom.type = ShapeType::kCapsule;
      break;
    case mjGEOM_CYLINDER:
      geom.type = ShapeType::kCylinder;
      break;
    case mjGEOM_BOX:
      geom.type = ShapeType::kBox;
      break;
    case mjGEOM_ELLIPSOID:
      // Enclosing sphere: the largest semi-axis.
      geom.type = ShapeType::kSphere;
      geom.size = core::Vec3(geom.size.maxCoeff(), 0, 0);
      break;
    case mjGEOM_MESH:
      // Enclosing sphere about the geom centre.
      geom.type = ShapeType::kSphere;
      geom.size = core::Vec3(geom.bound, 0, 0);
      break;
    default:  // planes, height fields
      return std::nullopt;
  }
  // The bounding radius must enclose the shape we use (rbound can be 0 for some geoms).
  geom.bound = std::max(geom.bound, geom.size.norm());
  return geom;
}

Shape shape_of(const SeparationMonitor::Geom& geom, const mjData& d) {
  const int g = geom.id;
  return Shape::FromMujoco(geom.type, d.geom_xpos + 3 * g, d.geom_xmat + 9 * g,
                           geom.size.data());
}

core::Vec3 centre_of(const mjData& d, int g) {
  return core::Vec3(d.geom_xpos[3 * g], d.geom_xpos[3 * g + 1], d.geom_xpos[3 * g + 2]);
}

}  // namespace

SeparationMonitor SeparationMonitor::FromModel(const model::Model& model) {
  const mjModel& m = *model.m();
  HRIB_CHECK(static_cast<int>(model.geom_tags.size()) == m.ngeom)
      << "geom_tags has " << model.geom_tags.size() << " entries for " << m.ngeom << " geoms";
  SeparationMonitor monitor;
  for (int g = 0; g < m.ngeom; ++g) {
    const model::GeomTag& tag = model.geom_tags[static_cast<size_t>(g)];
    if (!tag.is_robot() && !tag.is_human()) continue;
    if (m.geom_contype[g] == 0 && m.geom_conaffinity[g] == 0) continue;  // visual only
    std::optional<Geom> geom = describe_geom(m, g);
    if (!geom) continue;
    if (tag.is_human()) {
      geom->region = tag.region;
      monitor.human.push_back(*geom);
    } else {
      monitor.robot.push_back(*geom);
    }
  }
  return monitor;
}

Separation pair_separation(const SeparationMonitor& monitor, const mjData& d, size_t robot_index,
                           size_t human_index) {
  const SeparationMonitor::Geom& r = monitor.robot[robot_index];
  const SeparationMonitor::Geom& h = monitor.human[human_index];
  const ClosestPoints c = closest_points(shape_of(r, d), shape_of(h, d));
  return {c.distance, c.point_a_W, c.point_b_W, r.id, h.id, h.region};
}

Separation min_separation(const SeparationMonitor& monitor, const mjData& d) {
  // Lower bound of a pair's distance from the bounding spheres.
  const auto lower_bound = [&](size_t i, size_t j) {
    const SeparationMonitor::Geom& r = monitor.robot[i];
    const SeparationMonitor::Geom& h = monitor.human[j];
    return (centre_of(d, h.id) - centre_of(d, r.id)).norm() - r.bound - h.bound;
  };
  // Seed the search with the pair of smallest lower bound, so that most pairs are pruned.
  double seed_bound = std::numeric_limits<double>::infinity();
  size_t seed_i = 0;
  size_t seed_j = 0;
  for (size_t i = 0; i < monitor.robot.size(); ++i) {
    for (size_t j = 0; j < monitor.human.size(); ++j) {
      const double lower = lower_bound(i, j);
      if (lower < seed_bound) {
        seed_bound = lower;
        seed_i = i;
        seed_j = j;
      }
    }
  }
  Separation best;
  if (!std::isfinite(seed_bound)) return best;  // no robot or no human geoms
  const Separation seed = pair_separation(monitor, d, seed_i, seed_j);
  // Exact distances of the pairs whose bound can beat the best so far (ties: lowest ids).
  for (size_t i = 0; i < monitor.robot.size(); ++i) {
    for (size_t j = 0; j < monitor.human.size(); ++j) {
      if (lower_bound(i, j) > std::min(best.distance, seed.distance)) continue;
      const Separation s = (i == seed_i && j == seed_j) ? seed : pair_separation(monitor, d, i, j);
      if (s.distance < best.distance) best = s;
    }
  }
  return best;
}

RobotPointMotion robot_point_motion(const mjModel& m, const mjData& d,
                                    const Separation& separation) {
  RobotPointMotion motion;
  if (!separation.valid()) return motion;
  // 6-D velocity (angular; linear) at the geom centre, world orientation.
  mjtNum v[6];
  mj_objectVelocity(&m, &d, mjOBJ_GEOM, separation.robot_geom, v, 0);
  const core::Vec3 omega(v[0], v[1], v[2]);
  const core::Vec3 linear(v[3], v[4], v[5]);
  const core::Vec3 lever = separation.point_robot_W - centre_of(d, separation.robot_geom);
  motion.velocity_W = linear + omega.cross(lever);
  // Unit direction robot -> human: the ClosestPoints normal (point_b = point_a + distance * n).
  core::Vec3 n = separation.point_human_W - separation.point_robot_W;
  if (std::abs(separation.distance) > 1e-12) {
    n /= separation.distance;
  } else {
    n = centre_of(d, separation.human_geom) - separation.point_robot_W;
    const double norm = n.norm();
    n = norm > 0 ? core::Vec3(n / norm) : core::Vec3::Zero();
  }
  motion.speed_toward_human = motion.velocity_W.dot(n);
  return motion;
}

Separation min_separation(const SeparationMonitor& monitor, const Data& data) {
  return min_separation(monitor, *data.mj);
}

Separation min_separation(const model::Model& model, const mjData& d) {
  return min_separation(SeparationMonitor::FromModel(model), d);
}

Separation min_separation(const model::Model& model, const Data& data) {
  return min_separation(model, *data.mj);
}

}  // namespace hribench::sim

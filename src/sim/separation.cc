#include "sim/separation.h"

#include <algorithm>
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
  Separation best;
  for (size_t i = 0; i < monitor.robot.size(); ++i) {
    const SeparationMonitor::Geom& r = monitor.robot[i];
    const core::Vec3 centre_r = centre_of(d, r.id);
    for (size_t j = 0; j < monitor.human.size(); ++j) {
      const SeparationMonitor::Geom& h = monitor.human[j];
      // Bounding spheres give a lower bound; skip pairs that cannot beat the best.
      const double lower = (centre_of(d, h.id) - centre_r).norm() - r.bound - h.bound;
      if (lower >= best.distance) continue;
      const Separation s = pair_separation(monitor, d, i, j);
      if (s.distance < best.distance) best = s;
    }
  }
  return best;
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

// The graspable objects: primitives with distinct shapes, each a free body whose frame origin
// is the centre of its footprint on the bottom face (z up).

#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "model/mjcf.h"
#include "script/catalogue.h"

namespace hribench::model::mjcf {
namespace {

using core::Vec3;


// An open container: a floor and four walls.
std::vector<Shape> container(const ContainerWalls& w) {
  const double hx = w.hx, hy = w.hy, h = w.height, t = w.thickness;
  return {box(Vec3(0, 0, t / 2), Vec3(hx, hy, t / 2)),
          box(Vec3(hx - t / 2, 0, h / 2), Vec3(t / 2, hy, h / 2)),
          box(Vec3(-hx + t / 2, 0, h / 2), Vec3(t / 2, hy, h / 2)),
          box(Vec3(0, hy - t / 2, h / 2), Vec3(hx - t, t / 2, h / 2)),
          box(Vec3(0, -hy + t / 2, h / 2), Vec3(hx - t, t / 2, h / 2))};
}

// Shapes of a kind at scale s (the box's lid is separate).
std::vector<Shape> shapes(ObjectKind kind, double s) {
  switch (kind) {
    case ObjectKind::kCube:
      return {box(Vec3(0, 0, 0.025 * s), Vec3(0.025, 0.025, 0.025) * s)};
    case ObjectKind::kCup:
      return {cylinder(Vec3::Zero(), Vec3(0, 0, 0.09 * s), 0.035 * s)};
    case ObjectKind::kBottle:
      return {cylinder(Vec3::Zero(), Vec3(0, 0, 0.16 * s), 0.032 * s),
              cylinder(Vec3(0, 0, 0.16 * s), Vec3(0, 0, 0.21 * s), 0.014 * s)};
    case ObjectKind::kPlate: {
      // Collision: an octagon of two boxes (MuJoCo 2.2.2's cylinder-box contact is a single
      // point, which makes a thin disk rock); a visual-only cylinder is added by object().
      const double a = 0.1 * s / std::sqrt(2.0);
      return {box(Vec3(0, 0, 0.008 * s), Vec3(a, a, 0.008 * s)),
              {Shape::kBox, Vec3(0, 0, 0.008 * s), Vec3(a, a, 0.008 * s), 0, core::kPi / 4}};
    }
    case ObjectKind::kBin:
    case ObjectKind::kTray:
    case ObjectKind::kBox:
      return container(*container_walls(kind, s));
    case ObjectKind::kPlank:
      return {box(Vec3(0, 0, 0.02 * s), Vec3(0.3, 0.03, 0.02) * s)};
  }
  return {};
}

}  // namespace

std::optional<ContainerWalls> container_walls(ObjectKind kind, double s) {
  switch (kind) {
    case ObjectKind::kBin: return ContainerWalls{0.12 * s, 0.09 * s, 0.1 * s, 0.008};
    case ObjectKind::kTray: return ContainerWalls{0.15 * s, 0.11 * s, 0.025 * s, 0.006};
    case ObjectKind::kBox: return ContainerWalls{0.1 * s, 0.08 * s, 0.12 * s, 0.008};
    default: return std::nullopt;
  }
}

core::Vec3 nominal_half_extents(ObjectKind kind) {
  return script::catalogue_kinds()[static_cast<size_t>(kind)].half_extents;
}

double nominal_mass(ObjectKind kind) {
  switch (kind) {
    case ObjectKind::kCube: return 0.1;
    case ObjectKind::kCup: return 0.15;
    case ObjectKind::kBottle: return 0.25;
    case ObjectKind::kPlate: return 0.25;
    case ObjectKind::kBin: return 0.5;
    case ObjectKind::kTray: return 0.3;
    case ObjectKind::kBox: return 0.5;  // without the lid (0.08 kg)
    case ObjectKind::kPlank: return 0.5;
  }
  return 0;
}

void object(const ObjectSpec& spec, ObjectKind kind, const Rgba& colour, const core::Pose& X_WO,
            bool base_foot, std::string& worldbody) {
  const double s = spec.size_scale;
  const std::string body = "object_" + spec.name;
  const std::string colour_attr = "rgba=\"" + rgba(colour) + "\"";
  worldbody += fmt::format(R"(<body name="{}" pos="{}" quat="{}">)", body, vec(X_WO.translation),
                           quat(X_WO.rotation));
  worldbody += "\n<freejoint name=\"" + body + "_free\"/>\n";
  const double mass = nominal_mass(kind) * s * s * s;
  if (kind == ObjectKind::kPlate) {
    shape_geoms(shapes(kind, s), mass, body, "object", worldbody, "group=\"3\" " + colour_attr);
    worldbody += fmt::format(
        R"(<geom name="{}_visual" type="cylinder" fromto="0 0 0 0 0 {}" size="{}" contype="0" conaffinity="0" mass="0" {}/>)",
        body, num(0.016 * s), num(0.1 * s), colour_attr);
    worldbody += "\n";
  } else {
    shape_geoms(shapes(kind, s), mass, body, "object", worldbody, colour_attr);
  }
  if (base_foot && (kind == ObjectKind::kCup || kind == ObjectKind::kBottle)) {
    // A square inside the round base, as low as the base (SceneSpec::base_feet): hidden,
    // massless, with sliding friction only.
    const double half = 0.7 * shapes(kind, s).front().radius;
    const double height = 0.002 * s;
    shape_geoms({box(Vec3(0, 0, height / 2), Vec3(half, half, height / 2))}, 0, body + "_foot",
                "object", worldbody, "group=\"3\" condim=\"3\" " + colour_attr);
  }
  if (kind == ObjectKind::kBox) {
    // The lid: hinged about +y at the top of the +x wall; q = 0 closed, opening upward.
    const double hx = 0.1 * s;
    const double hy = 0.08 * s;
    const double top = 0.12 * s;
    worldbody += fmt::format(R"(<body name="{}_lid" pos="{}">)", body, vec(Vec3(hx, 0, top)));
    worldbody += fmt::format(
        "\n<joint name=\"{}_lid_hinge\" type=\"hinge\" axis=\"0 1 0\" range=\"0 1.9\" damping=\"0.02\"/>\n",
        body);
    shape_geoms({box(Vec3(-hx, 0, 0.004 * s), Vec3(hx, hy, 0.004 * s))}, 0.08 * s * s * s,
                body + "_lid", "object", worldbody, colour_attr);
    worldbody += "</body>\n";
  }
  worldbody += "</body>\n";
}

}  // namespace hribench::model::mjcf

// MJCF text helpers shared by the model generators.

#include "model/mjcf.h"

#include <cmath>

#include <fmt/format.h>

namespace hribench::model {

double Shape::volume() const {
  switch (kind) {
    case kBox:
      return 8 * b.x() * b.y() * b.z();
    case kCylinder:
      return core::kPi * radius * radius * (b - a).norm();
    case kCapsule:
      return core::kPi * radius * radius * (b - a).norm() +
             4.0 / 3.0 * core::kPi * radius * radius * radius;
  }
  return 0;
}

namespace mjcf {

std::string num(double v) {
  if (v == 0) v = 0;  // no "-0"
  return fmt::format("{:.9g}", v);
}

std::string vec(const core::Vec3& v) { return num(v.x()) + " " + num(v.y()) + " " + num(v.z()); }

std::string quat(const core::Quat& q) {
  return num(q.w()) + " " + num(q.x()) + " " + num(q.y()) + " " + num(q.z());
}

std::string rgba(const Rgba& c) {
  return fmt::format("{:.4g} {:.4g} {:.4g} {:.4g}", static_cast<double>(c.r),
                     static_cast<double>(c.g), static_cast<double>(c.b), static_cast<double>(c.a));
}

std::string camera_xyaxes(const core::Vec3& pos, const core::Vec3& target,
                          const core::Vec3& up_hint) {
  // MuJoCo cameras look along -z with y up in the image; x is image right.
  const core::Vec3 forward = (target - pos).normalized();
  core::Vec3 right = forward.cross(up_hint);
  if (right.norm() < 1e-6) right = forward.unitOrthogonal();  // looking along `up`
  right.normalize();
  const core::Vec3 up = right.cross(forward);
  return vec(right) + " " + vec(up);
}

void shape_geoms(const std::vector<Shape>& shapes, double mass, std::string_view name_prefix,
                 std::string_view cls, std::string& out, std::string_view extra) {
  double total = 0;
  for (const Shape& s : shapes) total += s.volume();
  for (size_t i = 0; i < shapes.size(); ++i) {
    const Shape& s = shapes[i];
    const double m = mass * s.volume() / total;
    if (s.kind == Shape::kBox) {
      out += fmt::format(
          R"(<geom name="{}_g{}" class="{}" type="box" pos="{}" quat="{}" size="{}" mass="{}" {}/>)",
          name_prefix, i, cls, vec(s.a), quat(core::axis_angle(core::Vec3::UnitZ(), s.yaw)),
          vec(s.b), num(m), extra);
    } else {
      out += fmt::format(
          R"(<geom name="{}_g{}" class="{}" type="{}" fromto="{} {}" size="{}" mass="{}" {}/>)",
          name_prefix, i, cls, s.kind == Shape::kCapsule ? "capsule" : "cylinder", vec(s.a),
          vec(s.b), num(s.radius), num(m), extra);
    }
    out += "\n";
  }
}

}  // namespace mjcf
}  // namespace hribench::model

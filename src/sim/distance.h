#pragma once
// Closest points between convex primitives, for human–robot clearance (docs/metrics.md d(t)).
// MuJoCo 2.2.2 has no mj_geomDistance, so these are written here; pure geometry, no MuJoCo.
//
// Units: metres. Everything is expressed in the world frame W (any common frame works).
// Conventions of every result (ClosestPoints):
//   - distance > 0: the shapes are apart; point_a_W / point_b_W are the closest points on the
//     surfaces of A and B, and |point_b_W - point_a_W| == distance.
//   - distance <= 0: the shapes touch or overlap; -distance is a penetration depth, point_a_W is
//     A's deepest point inside B and point_b_W the point of B's surface where A would leave it
//     (so again |point_b_W - point_a_W| == |distance|). For a segment against a box or a
//     cylinder the depth is that of the segment point deepest inside B (plus A's radius), which
//     is the exact signed distance of the two shapes along that point's nearest face normal.
// A "point" or "segment" is a shape of zero radius: its point_a_W lies on the point/segment.
// Degenerate inputs are allowed: a zero-length segment is a point, a zero-radius capsule a
// segment, a zero-size box a point. All functions are allocation-free.

#include "core/math.h"

namespace hribench::sim {

struct ClosestPoints {
  double distance = 0;  // signed, m (negative = penetration depth)
  core::Vec3 point_a_W = core::Vec3::Zero();
  core::Vec3 point_b_W = core::Vec3::Zero();
};

// The straight segment from p0_W to p1_W (p0_W == p1_W is a point).
struct Segment {
  core::Vec3 p0_W;
  core::Vec3 p1_W;
};

struct Sphere {
  core::Vec3 center_W;
  double radius = 0;  // m, >= 0
};

// The set of points within `radius` of `axis`.
struct Capsule {
  Segment axis;
  double radius = 0;  // m, >= 0
};

// An oriented box: centre p_WB, rotation R_WB (columns = the box axes in W), half sizes along
// the box's own x, y, z.
struct Box {
  core::Vec3 center_W;
  core::Mat3 R_WB = core::Mat3::Identity();
  core::Vec3 half_size;  // m, each >= 0

  static Box FromPose(const core::Pose& X_WB, const core::Vec3& half_size) {
    return {X_WB.translation, X_WB.rotation.toRotationMatrix(), half_size};
  }
};

// A solid circular cylinder about its own z axis (as MuJoCo's cylinder geom): centre, rotation
// R_WC (column 2 = the axis in W), radius and half length along z.
struct Cylinder {
  core::Vec3 center_W;
  core::Mat3 R_WC = core::Mat3::Identity();
  double radius = 0;       // m, >= 0
  double half_length = 0;  // m, >= 0
};

// Point–segment: a = the point, b = the closest point of the segment. distance >= 0.
ClosestPoints closest_points(const core::Vec3& point_W, const Segment& segment);
// Segment–segment (parallel, crossing and zero-length segments included). distance >= 0.
// When the closest pair is not unique (parallel overlap) one valid pair is returned.
ClosestPoints closest_points(const Segment& a, const Segment& b);
// Sphere/capsule pairs: the distance of the axes minus the radii. When the axes intersect the
// separating direction is arbitrary (perpendicular to both axes where possible).
ClosestPoints closest_points(const Capsule& a, const Capsule& b);
ClosestPoints closest_points(const Sphere& a, const Capsule& b);
ClosestPoints closest_points(const Sphere& a, const Sphere& b);

// Point–box, signed (negative inside: minus the distance to the nearest face); b lies on the
// box surface. Exact.
ClosestPoints closest_points(const core::Vec3& point_W, const Box& box);
// Segment–box, signed as above (the deepest segment point when the segment enters the box).
// Exact: the squared distance is minimised piecewise-quadratically between the slab crossings.
ClosestPoints closest_points(const Segment& segment, const Box& box);
ClosestPoints closest_points(const Capsule& capsule, const Box& box);
ClosestPoints closest_points(const Sphere& sphere, const Box& box);

// Point–cylinder, signed, exact; b lies on the cylinder surface.
ClosestPoints closest_points(const core::Vec3& point_W, const Cylinder& cylinder);
// Segment–cylinder, signed: the signed point–cylinder distance is convex along the segment and
// is minimised by golden-section search to ~1e-12 of the segment length (not closed form).
ClosestPoints closest_points(const Segment& segment, const Cylinder& cylinder);
ClosestPoints closest_points(const Capsule& capsule, const Cylinder& cylinder);
ClosestPoints closest_points(const Sphere& sphere, const Cylinder& cylinder);

// A primitive described the way MuJoCo describes a geom (mjModel.geom_type / geom_size,
// mjData.geom_xpos / geom_xmat), for dispatching over pairs of geoms.
enum class ShapeType { kSphere, kCapsule, kCylinder, kBox };
struct Shape {
  ShapeType type = ShapeType::kSphere;
  core::Vec3 center_W = core::Vec3::Zero();  // geom_xpos
  core::Mat3 R_WS = core::Mat3::Identity();  // geom_xmat (columns = local axes)
  // MuJoCo geom_size: sphere {r, -, -}; capsule/cylinder {r, half length along local z, -};
  // box {half x, half y, half z}.
  core::Vec3 size = core::Vec3::Zero();

  // From mjData.geom_xpos (3) and geom_xmat (9, row-major) of one geom.
  static Shape FromMujoco(ShapeType type, const double* xpos, const double* xmat,
                          const double* geom_size);
};

// Closest points of any two shapes; point_a_W is on `a`. Exact (up to the cylinder search)
// whenever at least one shape is a sphere or capsule. Box–box, box–cylinder and
// cylinder–cylinder pairs replace `b` by its smallest enclosing capsule along its longest axis,
// which can only under-estimate the distance (conservative for clearance).
ClosestPoints closest_points(const Shape& a, const Shape& b);

}  // namespace hribench::sim

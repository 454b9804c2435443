#include "sim/distance.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

namespace hribench::sim {
namespace {

using core::Mat3;
using core::Vec3;

// Squared lengths below this count as zero (a segment shorter than 1e-12 m is a point).
constexpr double kTinySq = 1e-24;
// sin^2 of the angle below which two segments are treated as parallel.
constexpr double kParallelSin2 = 1e-14;

// Closest points plus the unit direction n with point_b = point_a + distance * n. At
// distance == 0 n still separates the shapes (a face normal or a chosen perpendicular).
struct Witness {
  ClosestPoints points;
  Vec3 normal_W;
};

double clamp01(double x) { return std::clamp(x, 0.0, 1.0); }

// Any unit vector perpendicular to v (v need not be unit; x axis when v is zero).
Vec3 any_perpendicular(const Vec3& v) {
  if (v.squaredNorm() < kTinySq) return Vec3::UnitX();
  const Vec3 helper = std::abs(v.x()) < 0.9 * v.norm() ? Vec3::UnitX() : Vec3::UnitY();
  return v.cross(helper).normalized();
}

// Witness from two points: n from a to b, or `fallback` when they coincide.
Witness from_points(const Vec3& a, const Vec3& b, const Vec3& fallback) {
  const Vec3 ab = b - a;
  const double d = ab.norm();
  return {{d, a, b}, d > 0 ? Vec3(ab / d) : fallback};
}

// Grows A by ra and B by rb along the witness normal (sphere/capsule radii).
ClosestPoints inflate(const Witness& w, double ra, double rb) {
  return {w.points.distance - ra - rb, w.points.point_a_W + ra * w.normal_W,
          w.points.point_b_W - rb * w.normal_W};
}

Witness segment_segment(const Segment& sa, const Segment& sb) {
  // Ericson, Real-Time Collision Detection §5.1.9, with relative degeneracy tests.
  const Vec3 d1 = sa.p1_W - sa.p0_W;
  const Vec3 d2 = sb.p1_W - sb.p0_W;
  const Vec3 r = sa.p0_W - sb.p0_W;
  const double a = d1.squaredNorm();
  const double e = d2.squaredNorm();
  const double f = d2.dot(r);
  double s = 0;
  double t = 0;
  if (a <= kTinySq && e <= kTinySq) {
    // Both points.
  } else if (a <= kTinySq) {
    t = clamp01(f / e);
  } else {
    const double c = d1.dot(r);
    if (e <= kTinySq) {
      s = clamp01(-c / a);
    } else {
      const double b = d1.dot(d2);
      const double denom = a * e - b * b;
      // Non-parallel: closest points of the infinite lines, s clamped; parallel: s = 0.
      s = denom > kParallelSin2 * a * e ? clamp01((b * f - c * e) / denom) : 0.0;
      t = (b * s + f) / e;
      if (t < 0) {
        t = 0;
        s = clamp01(-c / a);
      } else if (t > 1) {
        t = 1;
        s = clamp01((b - c) / a);
      }
    }
  }
  // Fallback direction for crossing axes: perpendicular to both where defined.
  Vec3 fallback = d1.cross(d2);
  fallback = fallback.squaredNorm() > kTinySq * std::max(a * e, kTinySq)
                 ? Vec3(fallback.normalized())
                 : any_perpendicular(a > e ? d1 : d2);
  // Near-parallel segments make (s, t) ill-conditioned; the optimum is then at an end point,
  // so also try each end point against the other segment and keep the nearest pair.
  Vec3 pa = sa.p0_W + s * d1;
  Vec3 pb = sb.p0_W + t * d2;
  double best_sq = (pb - pa).squaredNorm();
  const auto try_pair = [&](const Vec3& qa, const Vec3& qb) {
    const double sq = (qb - qa).squaredNorm();
    if (sq < best_sq) {
      best_sq = sq;
      pa = qa;
      pb = qb;
    }
  };
  const auto project = [](const Vec3& p, const Vec3& origin, const Vec3& dir,
                          double len_sq) -> Vec3 {
    if (len_sq <= kTinySq) return origin;
    return Vec3(origin + clamp01((p - origin).dot(dir) / len_sq) * dir);
  };
  try_pair(sa.p0_W, project(sa.p0_W, sb.p0_W, d2, e));
  try_pair(sa.p1_W, project(sa.p1_W, sb.p0_W, d2, e));
  try_pair(project(sb.p0_W, sa.p0_W, d1, a), sb.p0_W);
  try_pair(project(sb.p1_W, sa.p0_W, d1, a), sb.p1_W);
  return from_points(pa, pb, fallback);
}

// Signed segment–box witness (see the header for the convention inside the box).
Witness segment_box(const Segment& seg, const Box& box) {
  const Mat3 R_BW = box.R_WB.transpose();
  const Vec3 p0 = R_BW * (seg.p0_W - box.center_W);
  const Vec3 u = R_BW * (seg.p1_W - seg.p0_W);
  const Vec3& h = box.half_size;
  const auto point_at = [&](double t) -> Vec3 { return p0 + t * u; };
  const auto clamp_to_box = [&](const Vec3& q) -> Vec3 { return q.cwiseMax(-h).cwiseMin(h); };

  // Breakpoints: where the segment crosses a slab plane x_i = +-h_i.
  std::array<double, 8> ts{};
  size_t n = 0;
  ts[n++] = 0.0;
  ts[n++] = 1.0;
  for (int i = 0; i < 3; ++i) {
    if (u[i] == 0.0) continue;
    for (const double side : {-1.0, 1.0}) {
      const double t = (side * h[i] - p0[i]) / u[i];
      if (t > 0.0 && t < 1.0) ts[n++] = t;
    }
  }
  // Insertion sort (at most 8 values).
  for (size_t i = 1; i < n; ++i) {
    for (size_t j = i; j > 0 && ts[j - 1] > ts[j]; --j) std::swap(ts[j - 1], ts[j]);
  }

  // Between breakpoints the squared distance is one quadratic in t: minimise it exactly.
  double best_t = 0.0;
  double best_sq = std::numeric_limits<double>::infinity();
  for (size_t k = 0; k + 1 < n; ++k) {
    const double ta = ts[k];
    const double tb = ts[k + 1];
    const Vec3 mid = point_at(0.5 * (ta + tb));
    double qa = 0.0;
    double qb = 0.0;
    for (int i = 0; i < 3; ++i) {
      if (std::abs(mid[i]) <= h[i]) continue;
      const double face = mid[i] > 0 ? h[i] : -h[i];
      qa += u[i] * u[i];
      qb += 2.0 * u[i] * (p0[i] - face);
    }
    const double t = qa > 0.0 ? std::clamp(-qb / (2.0 * qa), ta, tb) : ta;
    const Vec3 q = point_at(t);
    const double sq = (q - clamp_to_box(q)).squaredNorm();
    if (sq < best_sq) {
      best_sq = sq;
      best_t = t;
    }
  }
  // Apart by more than rounding (slab crossings are computed, not exact).
  if (best_sq > kTinySq) {
    const Vec3 q = point_at(best_t);
    return from_points(box.center_W + box.R_WB * q, box.center_W + box.R_WB * clamp_to_box(q),
                       Vec3::UnitX());
  }

  // The segment reaches the box: find its deepest point, i.e. maximise
  // g(t) = min over the six faces of (h_i - s * x_i(t)), a concave piecewise-linear function
  // whose maximum lies at t = 0, t = 1 or where two face lines cross.
  std::array<double, 6> k0{};
  std::array<double, 6> k1{};
  for (size_t j = 0; j < 6; ++j) {
    const int i = static_cast<int>(j / 2);
    const double s = (j % 2 == 0) ? 1.0 : -1.0;
    k0[j] = h[i] - s * p0[i];
    k1[j] = -s * u[i];
  }
  const auto depth_at = [&](double t, size_t* face) {
    double g = std::numeric_limits<double>::infinity();
    for (size_t j = 0; j < 6; ++j) {
      const double v = k0[j] + k1[j] * t;
      if (v < g) {
        g = v;
        *face = j;
      }
    }
    return g;
  };
  size_t face = 0;
  double best_depth = -std::numeric_limits<double>::infinity();
  const auto consider = [&](double t) {
    size_t f = 0;
    const double g = depth_at(t, &f);
    if (g > best_depth) {
      best_depth = g;
      best_t = t;
      face = f;
    }
  };
  consider(0.0);
  consider(1.0);
  for (size_t j = 0; j < 6; ++j) {
    for (size_t l = j + 1; l < 6; ++l) {
      const double dk = k1[j] - k1[l];
      if (dk == 0.0) continue;
      const double t = (k0[l] - k0[j]) / dk;
      if (t > 0.0 && t < 1.0) consider(t);
    }
  }
  best_depth = std::max(best_depth, 0.0);  // touching from outside reads as depth 0
  const int axis = static_cast<int>(face / 2);
  const double side = (face % 2 == 0) ? 1.0 : -1.0;
  const Vec3 q = point_at(best_t);
  Vec3 exit = q;
  exit[axis] = side * h[axis];
  const Vec3 outward_W = side * box.R_WB.col(axis);
  // Inside, point_b = point_a + distance * n with distance = -depth: n points into the box.
  return {{-best_depth, box.center_W + box.R_WB * q, box.center_W + box.R_WB * exit}, -outward_W};
}

// Signed point–cylinder witness (A = the point).
Witness point_cylinder(const Vec3& p_W, const Cylinder& cyl) {
  const Vec3 q = cyl.R_WC.transpose() * (p_W - cyl.center_W);
  const double rho = std::sqrt(q.x() * q.x() + q.y() * q.y());
  const Vec3 radial = rho > 1e-12 ? Vec3(q.x() / rho, q.y() / rho, 0.0) : Vec3::UnitX();
  const double dr = rho - cyl.radius;
  const double dz = std::abs(q.z()) - cyl.half_length;
  const double sz = q.z() >= 0 ? 1.0 : -1.0;
  if (dr <= 0 && dz <= 0) {
    // Inside (or on the surface): leave through the nearer of the side and the cap.
    Vec3 exit = q;
    Vec3 outward = Vec3::UnitZ() * sz;
    if (dr >= dz) {
      exit.head<2>() = cyl.radius * radial.head<2>();
      outward = radial;
    } else {
      exit.z() = sz * cyl.half_length;
    }
    return {{std::max(dr, dz), p_W, cyl.center_W + cyl.R_WC * exit}, -(cyl.R_WC * outward)};
  }
  Vec3 surface = q;
  surface.head<2>() = std::min(rho, cyl.radius) * radial.head<2>();
  surface.z() = std::clamp(q.z(), -cyl.half_length, cyl.half_length);
  return from_points(p_W, cyl.center_W + cyl.R_WC * surface, Vec3::UnitX());
}

// Segment–cylinder: golden-section search of the convex signed distance along the segment,
// on a scalar form of point_cylinder in the cylinder's frame (the witness is built once).
Witness segment_cylinder(const Segment& seg, const Cylinder& cyl) {
  const Vec3 d = seg.p1_W - seg.p0_W;
  if (d.squaredNorm() <= kTinySq) return point_cylinder(seg.p0_W, cyl);
  const Vec3 p0 = cyl.R_WC.transpose() * (seg.p0_W - cyl.center_W);
  const Vec3 u = cyl.R_WC.transpose() * d;
  const auto f = [&](double t) {
    const Vec3 q = p0 + t * u;
    const double dr = std::sqrt(q.x() * q.x() + q.y() * q.y()) - cyl.radius;
    const double dz = std::abs(q.z()) - cyl.half_length;
    if (dr <= 0 && dz <= 0) return std::max(dr, dz);
    const double er = std::max(dr, 0.0);
    const double ez = std::max(dz, 0.0);
    return std::sqrt(er * er + ez * ez);
  };
  constexpr double kInvPhi = 0.6180339887498949;
  double lo = 0.0;
  double hi = 1.0;
  double x1 = hi - kInvPhi * (hi - lo);
  double x2 = lo + kInvPhi * (hi - lo);
  double f1 = f(x1);
  double f2 = f(x2);
  // 0.618^60 ~ 3e-13 of the segment length.
  for (int it = 0; it < 60; ++it) {
    if (f1 <= f2) {
      hi = x2;
      x2 = x1;
      f2 = f1;
      x1 = hi - kInvPhi * (hi - lo);
      f1 = f(x1);
    } else {
      lo = x1;
      x1 = x2;
      f1 = f2;
      x2 = lo + kInvPhi * (hi - lo);
      f2 = f(x2);
    }
  }
  // The search never evaluates the end points themselves: compare them too.
  double best_t = 0.5 * (lo + hi);
  double best_f = f(best_t);
  for (const double t : {0.0, 1.0}) {
    const double ft = f(t);
    if (ft < best_f) {
      best_f = ft;
      best_t = t;
    }
  }
  return point_cylinder(seg.p0_W + best_t * d, cyl);
}

Segment point_segment(const Vec3& p) { return {p, p}; }

// A sphere or capsule as an axis plus radius; boxes and cylinders are not round.
bool is_round(ShapeType t) { return t == ShapeType::kSphere || t == ShapeType::kCapsule; }
Capsule as_capsule(const Shape& s) {
  const double half = s.type == ShapeType::kCapsule ? s.size[1] : 0.0;
  const Vec3 axis = s.R_WS.col(2) * half;
  return {{s.center_W - axis, s.center_W + axis}, s.size[0]};
}
// Smallest capsule along the longest axis that encloses a box or cylinder.
Capsule enclosing_capsule(const Shape& s) {
  if (s.type == ShapeType::kCylinder) {
    const Vec3 axis = s.R_WS.col(2) * s.size[1];
    return {{s.center_W - axis, s.center_W + axis}, s.size[0]};
  }
  if (s.type == ShapeType::kBox) {
    Eigen::Index longest = 0;
    s.size.maxCoeff(&longest);
    const Vec3 axis = s.R_WS.col(longest) * s.size[longest];
    double r_sq = 0;
    for (Eigen::Index i = 0; i < 3; ++i) {
      if (i != longest) r_sq += s.size[i] * s.size[i];
    }
    return {{s.center_W - axis, s.center_W + axis}, std::sqrt(r_sq)};
  }
  return as_capsule(s);
}

// A round shape (axis + radius) against any shape.
ClosestPoints round_vs(const Capsule& a, const Shape& b) {
  switch (b.type) {
    case ShapeType::kSphere:
    case ShapeType::kCapsule:
      return closest_points(a, as_capsule(b));
    case ShapeType::kBox:
      return closest_points(a, Box{b.center_W, b.R_WS, b.size});
    case ShapeType::kCylinder:
      return closest_points(a, Cylinder{b.center_W, b.R_WS, b.size[0], b.size[1]});
  }
  return {};
}

ClosestPoints swap_points(const ClosestPoints& c) { return {c.distance, c.point_b_W, c.point_a_W}; }

}  // namespace

ClosestPoints closest_points(const Vec3& point_W, const Segment& segment) {
  return segment_segment(point_segment(point_W), segment).points;
}

ClosestPoints closest_points(const Segment& a, const Segment& b) {
  return segment_segment(a, b).points;
}

ClosestPoints closest_points(const Capsule& a, const Capsule& b) {
  return inflate(segment_segment(a.axis, b.axis), a.radius, b.radius);
}

ClosestPoints closest_points(const Sphere& a, const Capsule& b) {
  return closest_points(Capsule{point_segment(a.center_W), a.radius}, b);
}

ClosestPoints closest_points(const Sphere& a, const Sphere& b) {
  return closest_points(Capsule{point_segment(a.center_W), a.radius},
                        Capsule{point_segment(b.center_W), b.radius});
}

ClosestPoints closest_points(const Vec3& point_W, const Box& box) {
  return segment_box(point_segment(point_W), box).points;
}

ClosestPoints closest_points(const Segment& segment, const Box& box) {
  return segment_box(segment, box).points;
}

ClosestPoints closest_points(const Capsule& capsule, const Box& box) {
  return inflate(segment_box(capsule.axis, box), capsule.radius, 0.0);
}

ClosestPoints closest_points(const Sphere& sphere, const Box& box) {
  return inflate(segment_box(point_segment(sphere.center_W), box), sphere.radius, 0.0);
}

ClosestPoints closest_points(const Vec3& point_W, const Cylinder& cylinder) {
  return point_cylinder(point_W, cylinder).points;
}

ClosestPoints closest_points(const Segment& segment, const Cylinder& cylinder) {
  return segment_cylinder(segment, cylinder).points;
}

ClosestPoints closest_points(const Capsule& capsule, const Cylinder& cylinder) {
  return inflate(segment_cylinder(capsule.axis, cylinder), capsule.radius, 0.0);
}

ClosestPoints closest_points(const Sphere& sphere, const Cylinder& cylinder) {
  return inflate(point_cylinder(sphere.center_W, cylinder), sphere.radius, 0.0);
}

Shape Shape::FromMujoco(ShapeType type, const double* xpos, const double* xmat,
                        const double* geom_size) {
  Shape s;
  s.type = type;
  s.center_W = Vec3(xpos[0], xpos[1], xpos[2]);
  s.R_WS = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(xmat);
  s.size = Vec3(geom_size[0], geom_size[1], geom_size[2]);
  return s;
}

ClosestPoints closest_points(const Shape& a, const Shape& b) {
  if (is_round(a.type)) return round_vs(as_capsule(a), b);
  if (is_round(b.type)) return swap_points(round_vs(as_capsule(b), a));
  return swap_points(round_vs(enclosing_capsule(b), a));
}

}  // namespace hribench::sim

#include "sim/distance.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/rng.h"

namespace hribench::sim {
namespace {

using core::Vec3;

constexpr double kTol = 1e-9;

// Every result must satisfy |b - a| == |distance|.
void ExpectConsistent(const ClosestPoints& c) {
  EXPECT_NEAR((c.point_b_W - c.point_a_W).norm(), std::abs(c.distance), 1e-9);
}

void ExpectVecNear(const Vec3& a, const Vec3& b, double tol = kTol) {
  EXPECT_NEAR((a - b).norm(), 0.0, tol) << "got " << a.transpose() << " want " << b.transpose();
}

// Distance from a point to a segment, by dense sampling (independent of the code under test).
double SampledPointSegment(const Vec3& p, const Segment& s, int n) {
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= n; ++i) {
    const double t = static_cast<double>(i) / n;
    best = std::min(best, (p - (s.p0_W + t * (s.p1_W - s.p0_W))).norm());
  }
  return best;
}

TEST(PointSegment, InteriorEndpointAndDegenerate) {
  const Segment s{Vec3(0, 0, 0), Vec3(2, 0, 0)};
  ClosestPoints c = closest_points(Vec3(1, 3, 0), s);
  EXPECT_NEAR(c.distance, 3.0, kTol);
  ExpectVecNear(c.point_b_W, Vec3(1, 0, 0));
  ExpectVecNear(c.point_a_W, Vec3(1, 3, 0));
  c = closest_points(Vec3(-3, 4, 0), s);  // beyond p0: the end point
  EXPECT_NEAR(c.distance, 5.0, kTol);
  ExpectVecNear(c.point_b_W, Vec3(0, 0, 0));
  c = closest_points(Vec3(5, 0, 4), s);  // beyond p1
  EXPECT_NEAR(c.distance, 5.0, kTol);
  ExpectVecNear(c.point_b_W, Vec3(2, 0, 0));
  c = closest_points(Vec3(1, 1, 1), Segment{Vec3(1, 1, 3), Vec3(1, 1, 3)});  // a point
  EXPECT_NEAR(c.distance, 2.0, kTol);
  c = closest_points(Vec3(0.5, 0, 0), s);  // on the segment
  EXPECT_NEAR(c.distance, 0.0, kTol);
}

TEST(SegmentSegment, SkewCrossingParallelAndDegenerate) {
  // Skew: x axis at z = 0 against y axis at z = 1, crossing above (0.5, 0).
  ClosestPoints c = closest_points(Segment{Vec3(-1, 0, 0), Vec3(1, 0, 0)},
                                   Segment{Vec3(0.5, -1, 1), Vec3(0.5, 1, 1)});
  EXPECT_NEAR(c.distance, 1.0, kTol);
  ExpectVecNear(c.point_a_W, Vec3(0.5, 0, 0));
  ExpectVecNear(c.point_b_W, Vec3(0.5, 0, 1));
  // Crossing in a plane.
  c = closest_points(Segment{Vec3(-1, -1, 0), Vec3(1, 1, 0)},
                     Segment{Vec3(-1, 1, 0), Vec3(1, -1, 0)});
  EXPECT_NEAR(c.distance, 0.0, kTol);
  ExpectVecNear(c.point_a_W, Vec3(0, 0, 0));
  // Parallel, overlapping: distance is the offset, the pair lies in the overlap.
  c = closest_points(Segment{Vec3(0, 0, 0), Vec3(2, 0, 0)},
                     Segment{Vec3(1, 0.5, 0), Vec3(3, 0.5, 0)});
  EXPECT_NEAR(c.distance, 0.5, kTol);
  EXPECT_GE(c.point_a_W.x(), 1.0 - kTol);
  EXPECT_LE(c.point_a_W.x(), 2.0 + kTol);
  ExpectConsistent(c);
  // Parallel, disjoint along the axis: end point to end point.
  c = closest_points(Segment{Vec3(0, 0, 0), Vec3(1, 0, 0)},
                     Segment{Vec3(4, 4, 0), Vec3(6, 4, 0)});
  EXPECT_NEAR(c.distance, 5.0, kTol);
  ExpectVecNear(c.point_a_W, Vec3(1, 0, 0));
  ExpectVecNear(c.point_b_W, Vec3(4, 4, 0));
  // Anti-parallel and collinear, disjoint.
  c = closest_points(Segment{Vec3(0, 0, 0), Vec3(1, 0, 0)},
                     Segment{Vec3(5, 0, 0), Vec3(3, 0, 0)});
  EXPECT_NEAR(c.distance, 2.0, kTol);
  // Non-parallel but the infinite lines' closest points lie outside both segments.
  c = closest_points(Segment{Vec3(0, 0, 0), Vec3(1, 0, 0)},
                     Segment{Vec3(3, 1, 0), Vec3(3, 3, 0)});
  EXPECT_NEAR(c.distance, std::sqrt(4.0 + 1.0), kTol);
  ExpectVecNear(c.point_a_W, Vec3(1, 0, 0));
  ExpectVecNear(c.point_b_W, Vec3(3, 1, 0));
  // Zero-length against a segment, either way round, and two points.
  c = closest_points(Segment{Vec3(1, 2, 0), Vec3(1, 2, 0)},
                     Segment{Vec3(0, 0, 0), Vec3(2, 0, 0)});
  EXPECT_NEAR(c.distance, 2.0, kTol);
  ExpectVecNear(c.point_b_W, Vec3(1, 0, 0));
  c = closest_points(Segment{Vec3(0, 0, 0), Vec3(2, 0, 0)},
                     Segment{Vec3(1, 2, 0), Vec3(1, 2, 0)});
  EXPECT_NEAR(c.distance, 2.0, kTol);
  ExpectVecNear(c.point_a_W, Vec3(1, 0, 0));
  c = closest_points(Segment{Vec3(0, 0, 0), Vec3(0, 0, 0)},
                     Segment{Vec3(0, 3, 4), Vec3(0, 3, 4)});
  EXPECT_NEAR(c.distance, 5.0, kTol);
}

TEST(SegmentSegment, MatchesDenseSamplingOnRandomAndNearParallelPairs) {
  core::Rng rng(7);
  const auto random_point = [&] {
    return Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
  };
  for (int trial = 0; trial < 200; ++trial) {
    const Segment a{random_point(), random_point()};
    Segment b{random_point(), random_point()};
    if (trial % 4 == 1) {  // nearly parallel to a
      const Vec3 off = random_point();
      const Vec3 tilt = 1e-7 * random_point();
      b = {a.p0_W + off, a.p1_W + off + tilt};
    } else if (trial % 4 == 2) {  // exactly parallel, different length
      const Vec3 off = random_point();
      b = {a.p0_W + off, a.p0_W + off + rng.uniform(-2, 2) * (a.p1_W - a.p0_W)};
    }
    const ClosestPoints c = closest_points(a, b);
    ExpectConsistent(c);
    // Sampled minimum: point of a against the exactly-sampled segment b (dense grid on a).
    double sampled = std::numeric_limits<double>::infinity();
    constexpr int kN = 400;
    for (int i = 0; i <= kN; ++i) {
      const double s = static_cast<double>(i) / kN;
      sampled = std::min(sampled, SampledPointSegment(a.p0_W + s * (a.p1_W - a.p0_W), b, kN));
    }
    EXPECT_LE(c.distance, sampled + 1e-12) << "trial " << trial;
    EXPECT_GE(c.distance, sampled - 1e-2) << "trial " << trial;
    // The returned points lie on their segments.
    EXPECT_NEAR(SampledPointSegment(c.point_a_W, a, 20000), 0.0, 2e-4);
    EXPECT_NEAR(SampledPointSegment(c.point_b_W, b, 20000), 0.0, 2e-4);
  }
}

TEST(Capsule, SeparatedTouchingAndPenetrating) {
  const Capsule a{{Vec3(0, 0, 0), Vec3(1, 0, 0)}, 0.1};
  Capsule b{{Vec3(0.5, -1, 0.5), Vec3(0.5, 1, 0.5)}, 0.2};
  ClosestPoints c = closest_points(a, b);
  EXPECT_NEAR(c.distance, 0.2, kTol);
  ExpectVecNear(c.point_a_W, Vec3(0.5, 0, 0.1));
  ExpectVecNear(c.point_b_W, Vec3(0.5, 0, 0.3));
  b.axis = {Vec3(0.5, -1, 0.3), Vec3(0.5, 1, 0.3)};  // touching
  EXPECT_NEAR(closest_points(a, b).distance, 0.0, kTol);
  b.axis = {Vec3(0.5, -1, 0.25), Vec3(0.5, 1, 0.25)};  // 5 cm deep
  c = closest_points(a, b);
  EXPECT_NEAR(c.distance, -0.05, kTol);
  ExpectConsistent(c);
  ExpectVecNear(c.point_a_W, Vec3(0.5, 0, 0.1));
  ExpectVecNear(c.point_b_W, Vec3(0.5, 0, 0.05));
  // Axes crossing: depth is the sum of the radii, the pair is still |distance| apart.
  b.axis = {Vec3(0.5, -1, 0), Vec3(0.5, 1, 0)};
  c = closest_points(a, b);
  EXPECT_NEAR(c.distance, -0.3, kTol);
  ExpectConsistent(c);
  // Spheres.
  c = closest_points(Sphere{Vec3(0, 0, 0), 0.5}, Sphere{Vec3(3, 4, 0), 1.5});
  EXPECT_NEAR(c.distance, 3.0, kTol);
  ExpectVecNear(c.point_a_W, Vec3(0.3, 0.4, 0));
  c = closest_points(Sphere{Vec3(2, 0, 0.3), 0.1}, a);
  EXPECT_NEAR(c.distance, std::sqrt(1.0 + 0.09) - 0.2, kTol);
}

// A box rotated 30 degrees about z, centred at (1, 2, 0.5), half sizes (0.3, 0.2, 0.1).
Box RotatedBox() {
  return Box::FromPose({core::axis_angle(Vec3::UnitZ(), core::deg_to_rad(30)), Vec3(1, 2, 0.5)},
                       Vec3(0.3, 0.2, 0.1));
}
// World point from box-frame coordinates.
Vec3 InBox(const Box& box, const Vec3& q_B) { return box.center_W + box.R_WB * q_B; }

TEST(PointBox, FaceEdgeCornerAndInside) {
  const Box box = RotatedBox();
  // Face region: above the top face.
  ClosestPoints c = closest_points(InBox(box, Vec3(0.1, -0.1, 0.4)), box);
  EXPECT_NEAR(c.distance, 0.3, kTol);
  ExpectVecNear(c.point_b_W, InBox(box, Vec3(0.1, -0.1, 0.1)));
  // Edge region: beyond +x and +z.
  c = closest_points(InBox(box, Vec3(0.6, 0.0, 0.5)), box);
  EXPECT_NEAR(c.distance, 0.5, kTol);
  ExpectVecNear(c.point_b_W, InBox(box, Vec3(0.3, 0.0, 0.1)));
  // Corner region.
  c = closest_points(InBox(box, Vec3(-0.5, -0.4, -0.3)), box);
  EXPECT_NEAR(c.distance, std::sqrt(0.04 + 0.04 + 0.04), kTol);
  ExpectVecNear(c.point_b_W, InBox(box, Vec3(-0.3, -0.2, -0.1)));
  // Inside, nearest to the -y face (0.05 away).
  c = closest_points(InBox(box, Vec3(0.0, -0.15, 0.0)), box);
  EXPECT_NEAR(c.distance, -0.05, kTol);
  ExpectVecNear(c.point_b_W, InBox(box, Vec3(0.0, -0.2, 0.0)));
  ExpectConsistent(c);
  // On the surface.
  EXPECT_NEAR(closest_points(InBox(box, Vec3(0.3, 0.1, 0.0)), box).distance, 0.0, kTol);
}

TEST(CapsuleBox, TouchingPenetratingEdgeAndCorner) {
  const Box box = RotatedBox();
  const double r = 0.05;
  // Lying flat 2 cm above the top face, spanning beyond the box: 2 cm.
  Capsule cap{{InBox(box, Vec3(-1, 0, 0.17)), InBox(box, Vec3(1, 0, 0.17))}, r};
  ClosestPoints c = closest_points(cap, box);
  EXPECT_NEAR(c.distance, 0.02, kTol);
  EXPECT_NEAR((c.point_b_W - box.center_W).dot(box.R_WB.col(2)), 0.1, kTol);
  ExpectConsistent(c);
  // Touching the top face.
  cap.axis = {InBox(box, Vec3(-1, 0, 0.15)), InBox(box, Vec3(1, 0, 0.15))};
  EXPECT_NEAR(closest_points(cap, box).distance, 0.0, kTol);
  // Penetrating the top face by 3 cm (axis 2 cm above it).
  cap.axis = {InBox(box, Vec3(-1, 0.05, 0.12)), InBox(box, Vec3(1, 0.05, 0.12))};
  c = closest_points(cap, box);
  EXPECT_NEAR(c.distance, -0.03, kTol);
  ExpectConsistent(c);
  // Axis through the box along x at depth 0.04 below the top face: deepest point is 0.04
  // from the top face (nearer than the +-y faces at 0.2 - 0.05 = 0.15), so depth 0.04 + r.
  cap.axis = {InBox(box, Vec3(-1, 0.05, 0.06)), InBox(box, Vec3(1, 0.05, 0.06))};
  c = closest_points(cap, box);
  EXPECT_NEAR(c.distance, -(0.04 + r), kTol);
  ExpectConsistent(c);
  // A vertical capsule whose lower end point dips 1 cm into the top face.
  cap.axis = {InBox(box, Vec3(0.1, 0.1, 0.09 + r)), InBox(box, Vec3(0.1, 0.1, 1.0))};
  EXPECT_NEAR(closest_points(cap, box).distance, -0.01, kTol);
  // Edge region: a capsule parallel to the box's y edge at (+x, +z), offset diagonally.
  cap.axis = {InBox(box, Vec3(0.4, -1, 0.2)), InBox(box, Vec3(0.4, 1, 0.2))};
  c = closest_points(cap, box);
  EXPECT_NEAR(c.distance, std::sqrt(0.01 + 0.01) - r, kTol);
  // Corner region: a capsule pointing at the corner along its diagonal.
  const Vec3 corner(0.3, 0.2, 0.1);
  const Vec3 dir = corner.normalized();
  cap.axis = {InBox(box, corner + 0.2 * dir), InBox(box, corner + 1.0 * dir)};
  c = closest_points(cap, box);
  EXPECT_NEAR(c.distance, 0.2 - r, kTol);
  ExpectVecNear(c.point_b_W, InBox(box, corner));
  // Sphere against the box face.
  c = closest_points(Sphere{InBox(box, Vec3(0.0, 0.0, -0.4)), 0.1}, box);
  EXPECT_NEAR(c.distance, 0.2, kTol);
  ExpectVecNear(c.point_a_W, InBox(box, Vec3(0.0, 0.0, -0.3)));
}

// Points on a box's surface (an n x n grid on each face), in W.
template <typename F>
void ForBoxSurface(const Box& box, int n, F&& visit) {
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3;
    const int v = (axis + 2) % 3;
    for (const double side : {-1.0, 1.0}) {
      for (int i = 0; i <= n; ++i) {
        for (int j = 0; j <= n; ++j) {
          Vec3 q;
          q[axis] = side * box.half_size[axis];
          q[u] = box.half_size[u] * (2.0 * i / n - 1.0);
          q[v] = box.half_size[v] * (2.0 * j / n - 1.0);
          visit(InBox(box, q));
        }
      }
    }
  }
}

// Points on a cylinder's surface (side and caps), in W.
template <typename F>
void ForCylinderSurface(const Cylinder& cyl, int n, F&& visit) {
  for (int i = 0; i < 4 * n; ++i) {
    const double a = 2.0 * core::kPi * i / (4 * n);
    for (int j = 0; j <= n; ++j) {
      const double z = cyl.half_length * (2.0 * j / n - 1.0);
      visit(cyl.center_W + cyl.R_WC * Vec3(cyl.radius * std::cos(a), cyl.radius * std::sin(a), z));
      const double rho = cyl.radius * j / n;
      for (const double side : {-1.0, 1.0}) {
        visit(cyl.center_W +
              cyl.R_WC * Vec3(rho * std::cos(a), rho * std::sin(a), side * cyl.half_length));
      }
    }
  }
}

core::Quat RandomRotation(core::Rng& rng) {
  core::Quat q(rng.normal(0, 1), rng.normal(0, 1), rng.normal(0, 1), rng.normal(0, 1));
  return q.normalized();
}

// Penetration: the reported (negative) distance is that of the capsule axis point deepest
// inside `shape`, found by sampling the axis with the exact signed point distance.
template <typename Solid>
void ExpectDeepestSampledPoint(const ClosestPoints& c, const Capsule& cap, const Solid& shape,
                               int trial) {
  double deepest = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= 2000; ++i) {
    const Vec3 p = cap.axis.p0_W + (i / 2000.0) * (cap.axis.p1_W - cap.axis.p0_W);
    deepest = std::min(deepest, closest_points(p, shape).distance - cap.radius);
  }
  EXPECT_LE(c.distance, deepest + 1e-9) << "trial " << trial;
  EXPECT_GE(c.distance, deepest - 1e-3) << "trial " << trial;
}

// Checks closest_points(cap, solid) against brute force and counts the case it fell in.
// Apart: sampled axis points against sampled surface points (`for_surface` visits them); the
// sampled minimum over-estimates the true distance, so the analytic value must be <= it and
// close to it, and the returned points lie on the two surfaces. Penetrating: see
// ExpectDeepestSampledPoint.
template <typename Solid, typename Surface>
void ExpectMatchesSampling(const Capsule& cap, const Solid& solid, Surface&& for_surface,
                           int trial, int* apart, int* penetrating) {
  const ClosestPoints c = closest_points(cap, solid);
  ExpectConsistent(c);
  if (c.distance <= 0) {
    ++*penetrating;
    ExpectDeepestSampledPoint(c, cap, solid, trial);
    return;
  }
  ++*apart;
  const Vec3& p0 = cap.axis.p0_W;
  const Vec3& p1 = cap.axis.p1_W;
  double sampled = std::numeric_limits<double>::infinity();
  constexpr int kSeg = 60;
  for_surface([&](const Vec3& q) {
    for (int i = 0; i <= kSeg; ++i) {
      const Vec3 p = p0 + (static_cast<double>(i) / kSeg) * (p1 - p0);
      sampled = std::min(sampled, (p - q).norm() - cap.radius);
    }
  });
  EXPECT_LE(c.distance, sampled + 1e-9) << "trial " << trial;
  EXPECT_GE(c.distance, sampled - 0.02) << "trial " << trial;
  EXPECT_NEAR(closest_points(c.point_b_W, solid).distance, 0.0, 1e-9);
  EXPECT_NEAR(closest_points(c.point_a_W, cap.axis).distance, cap.radius, 1e-9);
}

TEST(CapsuleBox, MatchesSurfaceSamplingOnRandomConfigurations) {
  core::Rng rng(11);
  int checked = 0;
  int penetrating = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const Box box = Box::FromPose(
        {RandomRotation(rng), Vec3(rng.uniform(-0.2, 0.2), rng.uniform(-0.2, 0.2), 0)},
        Vec3(rng.uniform(0.05, 0.3), rng.uniform(0.05, 0.3), rng.uniform(0.05, 0.3)));
    // Every third segment starts near the box centre, so some penetrate.
    const double reach = trial % 3 == 2 ? 0.1 : 0.8;
    const Vec3 p0 = box.center_W + Vec3(rng.uniform(-reach, reach), rng.uniform(-reach, reach),
                                        rng.uniform(-reach, reach));
    const Vec3 p1 = trial % 5 == 0 ? p0 : Vec3(p0 + 0.6 * Vec3(rng.uniform(-1, 1),
                                                              rng.uniform(-1, 1),
                                                              rng.uniform(-1, 1)));
    const Capsule cap{{p0, p1}, 0.03};
    ExpectMatchesSampling(
        cap, box, [&](auto&& visit) { ForBoxSurface(box, 24, visit); }, trial, &checked,
        &penetrating);
  }
  EXPECT_GT(checked, 30);
  EXPECT_GT(penetrating, 10);
}

TEST(Cylinder, PointSideCapRimAndInside) {
  const Cylinder cyl{Vec3(0, 0, 1), core::axis_angle(Vec3::UnitX(), core::kPi / 2)
                                        .toRotationMatrix(),  // axis along -y in W
                     0.2, 0.5};
  // Side: along W x.
  ClosestPoints c = closest_points(Vec3(1.0, 0.1, 1.0), cyl);
  EXPECT_NEAR(c.distance, 0.8, kTol);
  ExpectVecNear(c.point_b_W, Vec3(0.2, 0.1, 1.0));
  // Cap: beyond the axis end (W y = -0.5 is one cap).
  c = closest_points(Vec3(0.05, -0.9, 1.0), cyl);
  EXPECT_NEAR(c.distance, 0.4, kTol);
  ExpectVecNear(c.point_b_W, Vec3(0.05, -0.5, 1.0));
  // Rim.
  c = closest_points(Vec3(0.5, 0.9, 1.0), cyl);
  EXPECT_NEAR(c.distance, std::sqrt(0.09 + 0.16), kTol);
  ExpectVecNear(c.point_b_W, Vec3(0.2, 0.5, 1.0));
  // Inside, nearer to the side than to a cap.
  c = closest_points(Vec3(0.15, 0.0, 1.0), cyl);
  EXPECT_NEAR(c.distance, -0.05, kTol);
  ExpectVecNear(c.point_b_W, Vec3(0.2, 0.0, 1.0));
  // Inside, nearer to a cap.
  c = closest_points(Vec3(0.0, 0.45, 1.0), cyl);
  EXPECT_NEAR(c.distance, -0.05, kTol);
  // On the axis (no radial direction) and inside.
  EXPECT_NEAR(closest_points(Vec3(0.0, 0.0, 1.0), cyl).distance, -0.2, kTol);
}

TEST(Cylinder, CapsuleAnalyticCases) {
  const Cylinder cyl{Vec3(0, 0, 0), core::Mat3::Identity(), 0.1, 0.3};  // axis W z
  // Parallel to the axis, beside it.
  ClosestPoints c = closest_points(Capsule{{Vec3(0.5, 0, -1), Vec3(0.5, 0, 1)}, 0.05}, cyl);
  EXPECT_NEAR(c.distance, 0.35, 1e-9);
  ExpectConsistent(c);
  // Crossing above the cap.
  c = closest_points(Capsule{{Vec3(-1, 0.02, 0.5), Vec3(1, 0.02, 0.5)}, 0.05}, cyl);
  EXPECT_NEAR(c.distance, 0.15, 1e-9);
  // Through the side: the deepest point is on the axis, 0.1 from the side.
  c = closest_points(Capsule{{Vec3(-1, 0, 0), Vec3(1, 0, 0)}, 0.05}, cyl);
  EXPECT_NEAR(c.distance, -0.15, 1e-9);
  ExpectConsistent(c);
  // Sphere near the rim.
  c = closest_points(Sphere{Vec3(0.4, 0, 0.7), 0.1}, cyl);
  EXPECT_NEAR(c.distance, 0.4, 1e-9);
}

TEST(Cylinder, CapsuleMatchesSurfaceSampling) {
  core::Rng rng(5);
  int checked = 0;
  int penetrating = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const Cylinder cyl{Vec3(0, 0, 0), RandomRotation(rng).toRotationMatrix(),
                       rng.uniform(0.03, 0.15), rng.uniform(0.05, 0.3)};
    // Every third segment starts near the centre, so some penetrate.
    const double reach = trial % 3 == 2 ? 0.05 : 0.6;
    const Vec3 p0(rng.uniform(-reach, reach), rng.uniform(-reach, reach),
                  rng.uniform(-reach, reach));
    const Vec3 p1 =
        p0 + 0.5 * Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    const Capsule cap{{p0, p1}, 0.02};
    ExpectMatchesSampling(
        cap, cyl, [&](auto&& visit) { ForCylinderSurface(cyl, 24, visit); }, trial, &checked,
        &penetrating);
  }
  EXPECT_GT(checked, 20);
  EXPECT_GT(penetrating, 10);
}

TEST(Shape, DispatchMatchesTheTypedFunctionsAndSwapsRoles) {
  const Box box = RotatedBox();
  const Shape box_shape{ShapeType::kBox, box.center_W, box.R_WB, box.half_size};
  // A capsule along world z: MuJoCo capsule size {r, half length}.
  const Shape cap_shape{ShapeType::kCapsule, Vec3(1, 2, 1.3), core::Mat3::Identity(),
                        Vec3(0.05, 0.4, 0)};
  const Capsule cap{{Vec3(1, 2, 0.9), Vec3(1, 2, 1.7)}, 0.05};
  const ClosestPoints typed = closest_points(cap, box);
  const ClosestPoints ab = closest_points(cap_shape, box_shape);
  const ClosestPoints ba = closest_points(box_shape, cap_shape);
  EXPECT_NEAR(typed.distance, 0.9 - 0.6 - 0.05, kTol);
  EXPECT_NEAR(ab.distance, typed.distance, kTol);
  EXPECT_NEAR(ba.distance, typed.distance, kTol);
  ExpectVecNear(ab.point_a_W, typed.point_a_W);
  ExpectVecNear(ba.point_b_W, typed.point_a_W);  // roles swapped
  ExpectVecNear(ba.point_a_W, typed.point_b_W);
  // Sphere shape.
  const Shape sphere{ShapeType::kSphere, Vec3(0, 0, 0), core::Mat3::Identity(),
                     Vec3(0.1, 0, 0)};
  EXPECT_NEAR(closest_points(sphere, cap_shape).distance,
              closest_points(Sphere{Vec3(0, 0, 0), 0.1}, cap).distance, kTol);
  // Cylinder shape: size {r, half length}.
  const Shape cyl{ShapeType::kCylinder, Vec3(0, 0, 3), core::Mat3::Identity(),
                  Vec3(0.2, 0.5, 0)};
  EXPECT_NEAR(closest_points(sphere, cyl).distance, 2.5 - 0.1, 1e-9);
  // Box against a box: conservative (never above the true distance 1.0 - 0.2 - 0.2).
  const Shape b1{ShapeType::kBox, Vec3(0, 0, 0), core::Mat3::Identity(), Vec3(0.2, 0.1, 0.1)};
  const Shape b2{ShapeType::kBox, Vec3(1, 0, 0), core::Mat3::Identity(), Vec3(0.2, 0.1, 0.1)};
  const double dbb = closest_points(b1, b2).distance;
  EXPECT_LE(dbb, 0.6 + kTol);
  EXPECT_GE(dbb, 0.6 - 0.15);
}

TEST(Shape, FromMujocoReadsRowMajorRotation) {
  const double xpos[3] = {1, 2, 3};
  // Rotation of +90 degrees about z, row-major: local x -> world y.
  const double xmat[9] = {0, -1, 0, 1, 0, 0, 0, 0, 1};
  const double size[3] = {0.1, 0.2, 0.3};
  const Shape s = Shape::FromMujoco(ShapeType::kBox, xpos, xmat, size);
  ExpectVecNear(s.center_W, Vec3(1, 2, 3));
  ExpectVecNear(s.R_WS.col(0), Vec3(0, 1, 0));
  ExpectVecNear(s.size, Vec3(0.1, 0.2, 0.3));
}

}  // namespace
}  // namespace hribench::sim

#pragma once
// Minimum-jerk timing (Flash & Hogan 1985; docs/motion.md) for hand paths: the
// symmetric profile, an asymmetric variant with a longer deceleration tail for precision
// phases (pointing, placing), quintic segments with arbitrary boundary velocity and
// acceleration (for re-targeting a movement that is already under way), and a smooth path
// through via-points that the profile moves along.

#include <vector>

#include "core/math.h"

namespace hribench::human {

// Symmetric min-jerk progress s(tau) = 10 tau^3 - 15 tau^4 + 6 tau^5 for tau in [0, 1] (clamped
// outside), and its first and second derivatives with respect to tau. Peak ds/dtau = 1.875 at
// tau = 0.5, so a move of amplitude A in T seconds peaks at 1.875 A / T.
double min_jerk(double tau);
double min_jerk_rate(double tau);
double min_jerk_rate2(double tau);

// Progress profile with a deceleration fraction `decel` in [0.5, 1): the accelerating half of
// the min-jerk curve is compressed into [0, 1 - decel] and the decelerating half stretched over
// [1 - decel, 1], scaled so that position, velocity and acceleration stay continuous. The peak
// rate is 1.875 at tau = 1 - decel (the same peak as the symmetric profile); decel = 0.5 is the
// symmetric profile.
struct MinJerkProfile {
  double decel = 0.5;
  double progress(double tau) const;  // s in [0, 1]
  double rate(double tau) const;      // ds/dtau
};

// A 3-D quintic x(t), t in [0, T]: the min-jerk trajectory between two states with given
// position, velocity and acceleration (zero end velocity/acceleration gives the min-jerk
// reach). Times are clamped to [0, T].
class Quintic {
 public:
  // Requires T > 0.
  static Quintic Between(const core::Vec3& x0, const core::Vec3& v0, const core::Vec3& a0,
                         const core::Vec3& x1, const core::Vec3& v1, const core::Vec3& a1,
                         double T);
  // A rest-to-rest min-jerk move from x0 to x1 in T seconds.
  static Quintic RestToRest(const core::Vec3& x0, const core::Vec3& x1, double T);

  core::Vec3 position(double t) const;
  core::Vec3 velocity(double t) const;
  core::Vec3 acceleration(double t) const;
  double duration() const { return T_; }

  // Re-target at time t_now (of this quintic): a new quintic that starts with this one's
  // position, velocity and acceleration at t_now and comes to rest at `target` after
  // `remaining` seconds (> 0). Time 0 of the result is t_now of this one.
  Quintic retarget(double t_now, const core::Vec3& target, double remaining) const;

 private:
  std::array<core::Vec3, 6> c_{};  // x(t) = sum c_k t^k
  double T_ = 1;
};

// A smooth curve P(s), s in [0, 1], from `points.front()` to `points.back()` through every
// point in order: a Catmull-Rom (cubic Hermite) spline with chord-length knots (two points:
// the straight segment). Requires at least one point; repeated points are skipped.
class ViaPath {
 public:
  explicit ViaPath(std::vector<core::Vec3> points);
  core::Vec3 at(double s) const;
  double chord_length() const { return total_; }

 private:
  std::vector<core::Vec3> p_;
  std::vector<double> knot_;  // cumulative chord length at each point
  double total_ = 0;
};

}  // namespace hribench::human

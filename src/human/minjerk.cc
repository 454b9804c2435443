#include "human/minjerk.h"

#include <algorithm>
#include <cmath>

#include "core/errors.h"

namespace hribench::human {

using core::Vec3;

double min_jerk(double tau) {
  const double t = std::clamp(tau, 0.0, 1.0);
  return t * t * t * (10 + t * (-15 + 6 * t));
}

double min_jerk_rate(double tau) {
  const double t = std::clamp(tau, 0.0, 1.0);
  return 30 * t * t * (1 - t) * (1 - t);
}

double min_jerk_rate2(double tau) {
  const double t = std::clamp(tau, 0.0, 1.0);
  return 60 * t * (1 - t) * (1 - 2 * t);
}

// The accelerating half of min_jerk (s: 0 -> 0.5 over x: 0 -> 0.5) is mapped onto
// [0, peak] with amplitude `peak`, the decelerating half onto [peak, 1] with amplitude 1 - peak:
// the slopes match at the peak, so the rate is continuous and peaks at 1.875.
double MinJerkProfile::progress(double tau) const {
  const double t = std::clamp(tau, 0.0, 1.0);
  const double peak = 1 - decel;
  if (peak <= 0) return 1;
  if (t <= peak) return 2 * peak * min_jerk(t / (2 * peak));
  return peak + (1 - peak) * (2 * min_jerk(0.5 + (t - peak) / (2 * (1 - peak))) - 1);
}

double MinJerkProfile::rate(double tau) const {
  const double t = std::clamp(tau, 0.0, 1.0);
  const double peak = 1 - decel;
  if (peak <= 0) return 0;
  if (t <= peak) return min_jerk_rate(t / (2 * peak));
  return min_jerk_rate(0.5 + (t - peak) / (2 * (1 - peak)));
}

Quintic Quintic::Between(const Vec3& x0, const Vec3& v0, const Vec3& a0, const Vec3& x1,
                         const Vec3& v1, const Vec3& a1, double T) {
  HRIB_CHECK(T > 0) << "T=" << T;
  Quintic q;
  q.T_ = T;
  const double T2 = T * T;
  const double T3 = T2 * T;
  q.c_[0] = x0;
  q.c_[1] = v0;
  q.c_[2] = 0.5 * a0;
  q.c_[3] = (20 * (x1 - x0) - (8 * v1 + 12 * v0) * T - (3 * a0 - a1) * T2) / (2 * T3);
  q.c_[4] = (30 * (x0 - x1) + (14 * v1 + 16 * v0) * T + (3 * a0 - 2 * a1) * T2) / (2 * T3 * T);
  q.c_[5] = (12 * (x1 - x0) - 6 * (v1 + v0) * T - (a0 - a1) * T2) / (2 * T3 * T2);
  return q;
}

Quintic Quintic::RestToRest(const Vec3& x0, const Vec3& x1, double T) {
  return Between(x0, Vec3::Zero(), Vec3::Zero(), x1, Vec3::Zero(), Vec3::Zero(), T);
}

Vec3 Quintic::position(double t) const {
  const double u = std::clamp(t, 0.0, T_);
  return c_[0] + u * (c_[1] + u * (c_[2] + u * (c_[3] + u * (c_[4] + u * c_[5]))));
}

Vec3 Quintic::velocity(double t) const {
  const double u = std::clamp(t, 0.0, T_);
  return c_[1] + u * (2 * c_[2] + u * (3 * c_[3] + u * (4 * c_[4] + u * 5 * c_[5])));
}

Vec3 Quintic::acceleration(double t) const {
  const double u = std::clamp(t, 0.0, T_);
  return 2 * c_[2] + u * (6 * c_[3] + u * (12 * c_[4] + u * 20 * c_[5]));
}

Quintic Quintic::retarget(double t_now, const Vec3& target, double remaining) const {
  return Between(position(t_now), velocity(t_now), acceleration(t_now), target, Vec3::Zero(),
                 Vec3::Zero(), remaining);
}

ViaPath::ViaPath(std::vector<Vec3> points) {
  HRIB_CHECK(!points.empty());
  // Skip repeated points (zero-length chords).
  for (const Vec3& p : points) {
    if (p_.empty() || (p - p_.back()).norm() > 1e-9) p_.push_back(p);
  }
  knot_.push_back(0);
  for (size_t i = 1; i < p_.size(); ++i) knot_.push_back(knot_.back() + (p_[i] - p_[i - 1]).norm());
  total_ = knot_.back();
}

Vec3 ViaPath::at(double s) const {
  if (p_.size() == 1 || total_ <= 0) return p_.front();
  const double u = std::clamp(s, 0.0, 1.0) * total_;
  size_t i = 0;
  while (i + 2 < p_.size() && u > knot_[i + 1]) ++i;
  // Tangents (d/du) by central differences over the chord-length knots; chords at the ends.
  const auto tangent = [&](size_t k) -> Vec3 {
    const size_t lo = k == 0 ? 0 : k - 1;
    const size_t hi = std::min(k + 1, p_.size() - 1);
    return (p_[hi] - p_[lo]) / (knot_[hi] - knot_[lo]);
  };
  const double h = knot_[i + 1] - knot_[i];
  const double t = (u - knot_[i]) / h;
  const double t2 = t * t;
  const double t3 = t2 * t;
  return (2 * t3 - 3 * t2 + 1) * p_[i] + (t3 - 2 * t2 + t) * h * tangent(i) +
         (-2 * t3 + 3 * t2) * p_[i + 1] + (t3 - t2) * h * tangent(i + 1);
}

}  // namespace hribench::human

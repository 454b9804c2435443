#include "human/labels.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "human/arm_ik.h"

namespace hribench::human {

using core::Vec3;

namespace {

// The frames whose time lies in the phase (all frames for an empty name); false if the clip
// has no such phase.
bool phase_frames(const Clip& clip, const std::string& phase, size_t& first, size_t& last) {
  if (clip.frames.empty()) return false;
  double start = 0;
  double end = clip.duration();
  if (!phase.empty()) {
    const Phase* p = clip.phase(phase);
    if (p == nullptr) return false;
    start = p->start;
    end = std::min(p->end, clip.duration());
  }
  first = static_cast<size_t>(std::ceil(start * clip.fps - 1e-9));
  last = static_cast<size_t>(std::floor(end * clip.fps + 1e-9));
  last = std::min(last, clip.frames.size() - 1);
  return first <= last;
}

CheckResult missing_phase(const std::string& phase) {
  return {false, 0, 0, fmt::format("the clip has no frames in a phase '{}'", phase)};
}

double frame_time(const Clip& clip, size_t i) { return static_cast<double>(i) / clip.fps; }

// Edges between two joints in the kinematic tree.
int tree_distance(Joint a, Joint b) {
  const auto depth = [](Joint j) {
    int d = 0;
    for (auto p = parent(j); p; p = parent(*p)) ++d;
    return d;
  };
  int da = depth(a);
  int db = depth(b);
  int n = 0;
  while (da > db) { a = *parent(a); --da; ++n; }
  while (db > da) { b = *parent(b); --db; ++n; }
  while (a != b) { a = *parent(a); b = *parent(b); n += 2; }
  return n;
}

}  // namespace

std::optional<HandPoint> hand_point_from_name(std::string_view name) {
  if (name == "wrist") return HandPoint::kWrist;
  if (name == "palm" || name == "hand") return HandPoint::kPalm;
  if (name == "index") return HandPoint::kIndexTip;
  return std::nullopt;
}

Vec3 hand_point(const Skeleton& skeleton, const SkeletonPose& pose, Side side, HandPoint point) {
  const core::Pose X_W_wrist = forward_kinematics(skeleton, pose)[static_cast<size_t>(index(wrist(side)))];
  switch (point) {
    case HandPoint::kWrist: return X_W_wrist.translation;
    case HandPoint::kPalm: return palm_centre(skeleton, X_W_wrist);
    case HandPoint::kIndexTip: return index_tip(skeleton, X_W_wrist);
  }
  return X_W_wrist.translation;
}

double pointing_ray_distance(const Skeleton& skeleton, const SkeletonPose& pose, Side side,
                             const Vec3& target) {
  const auto X = forward_kinematics(skeleton, pose);
  const Vec3 S = X[static_cast<size_t>(index(shoulder(side)))].translation;
  const Vec3 tip = index_tip(skeleton, X[static_cast<size_t>(index(wrist(side)))]);
  const Vec3 dir = (tip - S).normalized();
  const double along = std::max(0.0, (target - S).dot(dir));
  return (target - (S + along * dir)).norm();
}

double arm_extension(const Skeleton& skeleton, const SkeletonPose& pose, Side side) {
  const auto X = forward_kinematics(skeleton, pose);
  return (X[static_cast<size_t>(index(wrist(side)))].translation -
          X[static_cast<size_t>(index(shoulder(side)))].translation)
             .norm() /
         arm_length(skeleton, side);
}

CheckResult check_pointing(const Clip& clip, Side side, const Vec3& target, double radius,
                           const std::string& phase) {
  size_t first = 0;
  size_t last = 0;
  if (!phase_frames(clip, phase, first, last)) return missing_phase(phase);
  CheckResult r;
  for (size_t i = first; i <= last; ++i) {
    const double d = pointing_ray_distance(clip.skeleton, clip.frames[i], side, target);
    if (d > r.worst) {
      r.worst = d;
      r.time = frame_time(clip, i);
    }
  }
  if (r.worst > radius) {
    r.ok = false;
    r.message = fmt::format("{}: the pointing ray misses the target by {:.3f} m (> {:.3f}) at t={:.2f} s",
                            phase, r.worst, radius, r.time);
  }
  return r;
}

CheckResult check_stable_in_zone(const Clip& clip, Side side, HandPoint point, const Zone& zone,
                                 const std::string& phase, double max_speed) {
  size_t first = 0;
  size_t last = 0;
  if (!phase_frames(clip, phase, first, last)) return missing_phase(phase);
  CheckResult r;
  double worst_out = 0;
  double out_time = 0;
  Vec3 previous = hand_point(clip.skeleton, clip.frames[first], side, point);
  for (size_t i = first; i <= last; ++i) {
    const Vec3 p = hand_point(clip.skeleton, clip.frames[i], side, point);
    const double outside = (p - zone.center).norm() - zone.radius;
    if (outside > worst_out) {
      worst_out = outside;
      out_time = frame_time(clip, i);
    }
    if (i > first) {
      const double speed = (p - previous).norm() * clip.fps;
      if (speed > r.worst) {
        r.worst = speed;
        r.time = frame_time(clip, i);
      }
    }
    previous = p;
  }
  if (worst_out > 0) {
    return {false, worst_out, out_time,
            fmt::format("{}: the hand leaves the zone by {:.3f} m at t={:.2f} s", phase, worst_out,
                        out_time)};
  }
  if (r.worst > max_speed) {
    r.ok = false;
    r.message = fmt::format("{}: the hand moves at {:.3f} m/s (> {:.3f}) at t={:.2f} s", phase,
                            r.worst, max_speed, r.time);
  }
  return r;
}

bool Box::contains(const Vec3& p) const {
  return (p.array() >= min.array()).all() && (p.array() <= max.array()).all();
}

CheckResult check_enters_box(const Clip& clip, Side side, HandPoint point, const Box& box,
                             const std::string& phase) {
  size_t first = 0;
  size_t last = 0;
  if (!phase_frames(clip, phase, first, last)) return missing_phase(phase);
  if (box.contains(hand_point(clip.skeleton, clip.frames.front(), side, point))) {
    return {false, 0, 0, "the hand is inside the workspace already at the start"};
  }
  double closest = std::numeric_limits<double>::infinity();
  for (size_t i = first; i <= last; ++i) {
    const Vec3 p = hand_point(clip.skeleton, clip.frames[i], side, point);
    if (box.contains(p)) return {true, frame_time(clip, i), frame_time(clip, i), ""};
    const Vec3 c = p.cwiseMax(box.min).cwiseMin(box.max);
    closest = std::min(closest, (p - c).norm());
  }
  return {false, closest, 0,
          fmt::format("{}: the hand never enters the workspace (closest {:.3f} m)",
                      phase.empty() ? "clip" : phase, closest)};
}

// Closest points of two segments (Ericson, Real-Time Collision Detection, 5.1.9).
double segment_distance(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1) {
  const Vec3 d1 = p1 - p0;
  const Vec3 d2 = q1 - q0;
  const Vec3 r = p0 - q0;
  const double a = d1.squaredNorm();
  const double e = d2.squaredNorm();
  const double f = d2.dot(r);
  double s = 0;
  double t = 0;
  constexpr double kEps = 1e-12;
  if (a <= kEps && e <= kEps) return r.norm();
  if (a <= kEps) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= kEps) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2);
      const double denom = a * e - b * b;
      s = denom > kEps ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0) {
        t = 0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1) {
        t = 1;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return ((p0 + s * d1) - (q0 + t * d2)).norm();
}

CheckResult check_self_penetration(const Clip& clip, double tolerance) {
  const auto capsules = body_capsules(clip.skeleton);
  CheckResult r;
  std::string worst_pair;
  for (size_t f = 0; f < clip.frames.size(); ++f) {
    const auto X = forward_kinematics(clip.skeleton, clip.frames[f]);
    std::vector<std::pair<Vec3, Vec3>> seg;
    for (const BodyCapsule& c : capsules) {
      const core::Pose& X_WJ = X[static_cast<size_t>(index(c.joint))];
      seg.emplace_back(X_WJ * c.from, X_WJ * c.to);
    }
    for (size_t i = 0; i < capsules.size(); ++i) {
      for (size_t j = i + 1; j < capsules.size(); ++j) {
        if (tree_distance(capsules[i].joint, capsules[j].joint) <= 2) continue;
        const double depth = capsules[i].radius + capsules[j].radius -
                             segment_distance(seg[i].first, seg[i].second, seg[j].first, seg[j].second);
        if (depth > r.worst) {
          r.worst = depth;
          r.time = frame_time(clip, f);
          worst_pair = std::string(capsules[i].name) + " and " + std::string(capsules[j].name);
        }
      }
    }
  }
  if (r.worst > tolerance) {
    r.ok = false;
    r.message = fmt::format("self-penetration: {} overlap by {:.3f} m (> {:.3f}) at t={:.2f} s",
                            worst_pair, r.worst, tolerance, r.time);
  }
  return r;
}

CheckResult check_clip_joint_limits(const Clip& clip) {
  CheckResult r;
  for (size_t f = 0; f < clip.frames.size(); ++f) {
    for (const LimitViolation& v : check_joint_limits(clip.frames[f])) {
      const double excess = std::isfinite(v.value_deg) ? v.value_deg - v.limit_deg
                                                       : std::numeric_limits<double>::infinity();
      if (excess > r.worst || r.ok) {
        r.ok = false;
        r.worst = excess;
        r.time = frame_time(clip, f);
        r.message = fmt::format("{} of {} is {:.1f} deg (limit {:.0f}) at t={:.2f} s", v.what,
                                joint_name(v.joint), v.value_deg, v.limit_deg, r.time);
      }
    }
  }
  return r;
}

CheckResult check_bone_lengths(const Clip& clip, double tolerance) {
  CheckResult r;
  std::string bone;
  for (size_t f = 0; f < clip.frames.size(); ++f) {
    const auto X = forward_kinematics(clip.skeleton, clip.frames[f]);
    for (int j = 1; j < kNumJoints; ++j) {
      const auto joint = static_cast<Joint>(j);
      const double length = (X[static_cast<size_t>(j)].translation -
                             X[static_cast<size_t>(index(*parent(joint)))].translation)
                                .norm();
      const double err = std::isfinite(length) ? std::abs(length - clip.skeleton.bone_length(joint))
                                               : std::numeric_limits<double>::infinity();
      if (err > r.worst) {
        r.worst = err;
        r.time = frame_time(clip, f);
        bone = std::string(joint_name(joint));
      }
    }
  }
  if (r.worst > tolerance) {
    r.ok = false;
    r.message = fmt::format("bone to {} is off by {:.6f} m at t={:.2f} s", bone, r.worst, r.time);
  }
  return r;
}

}  // namespace hribench::human

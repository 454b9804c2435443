#include "human/motion.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/bisection.h"
#include "core/errors.h"
#include "core/rng.h"
#include "human/arm_ik.h"

namespace hribench::human {

using core::Quat;
using core::Vec3;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kDeg = core::kPi / 180.0;
constexpr double kLeanReach = 0.93;      // lean once a wrist target is beyond this much reach
constexpr double kMaxLean = 70 * kDeg;
// The head (docs/motion.md, "Leaning"): the neck extends by this share of a forward lean (at
// most kMaxHeadExtension) so the face stays up, and a lean stops where the head's centre would
// come further in front of the ankles than kHeadReach or, for a hand reaching further out,
// than kHeadBehindHand behind that hand's wrist target (the hand then falls short).
constexpr double kHeadExtension = 0.5;
constexpr double kMaxHeadExtension = 30 * kDeg;
constexpr double kHeadReach = 0.45;       // m
constexpr double kHeadBehindHand = 0.15;  // m

size_t slot(Side side) { return side == Side::kLeft ? 0 : 1; }
Side side_of(size_t slot_index) { return slot_index == 0 ? Side::kLeft : Side::kRight; }
// Unit vector from a hand toward the body's midline, in F.
Vec3 medial(Side side) { return Vec3(0, side == Side::kLeft ? -1.0 : 1.0, 0); }

bool finite(const Vec3& v) { return v.allFinite(); }

std::string names_of(const PrimitiveInfo& prim) {
  std::string out;
  for (const ParamInfo& p : prim.params) out += (out.empty() ? "" : ", ") + std::string(p.name);
  return out;
}

// The parameter `name` of `prim`, which must be of one of the kinds.
const ParamInfo& expect_param(const PrimitiveInfo& prim, const std::string& name,
                              std::initializer_list<ParamKind> kinds) {
  const ParamInfo* info = prim.param(name);
  if (info == nullptr) {
    throw core::InputError("motion." + name,
                           fmt::format("a parameter of {} ({})", prim.name, names_of(prim)),
                           "'" + name + "'");
  }
  if (std::find(kinds.begin(), kinds.end(), info->kind) == kinds.end()) {
    throw core::InputError("motion." + name, fmt::format("a {}", to_string(info->kind)),
                           fmt::format("a value of another kind"));
  }
  return *info;
}

// Stand frame of a pose: yaw of the pelvis about +z, origin on the floor under the midpoint of
// the hip joints (which a torso lean does not move).
core::Pose stand_frame(const Skeleton& k, const SkeletonPose& pose) {
  const Vec3 fwd = pose.X_WP.rotation * Vec3::UnitX();
  core::Pose X_WF;
  X_WF.rotation = core::axis_angle(Vec3::UnitZ(), std::atan2(fwd.y(), fwd.x()));
  const Vec3 hip_mid = 0.5 * (k.offset[static_cast<size_t>(index(Joint::kLeftHip))] +
                              k.offset[static_cast<size_t>(index(Joint::kRightHip))]);
  const Vec3 rest_mid = X_WF.rotation * Vec3(hip_mid.x(), hip_mid.y(), 0);
  const Vec3 mid = pose.X_WP * hip_mid - rest_mid;
  X_WF.translation = Vec3(mid.x(), mid.y(), 0);
  return X_WF;
}

// Height of the ankle joints above the floor in the rest pose.
double rest_ankle_height(const Skeleton& k) {
  const auto X = forward_kinematics(k, SkeletonPose::Standing(k, 0, 0, 0));
  return X[static_cast<size_t>(index(Joint::kLeftAnkle))].translation.z();
}

// Shoulder joint of a side in F for the upright rest pose.
Vec3 rest_shoulder(const Skeleton& k, Side side) {
  const auto X = forward_kinematics(k, SkeletonPose::Standing(k, 0, 0, 0));
  return X[static_cast<size_t>(index(shoulder(side)))].translation;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Parameter validation against the catalog.

void validate(const PrimitiveParams& params) {
  const PrimitiveInfo* prim = find_primitive(params.primitive);
  if (prim == nullptr) {
    std::string all;
    for (const PrimitiveInfo& p : primitive_catalog()) all += (all.empty() ? "" : ", ") + std::string(p.name);
    throw core::InputError("motion.primitive", "one of " + all, "'" + params.primitive + "'");
  }
  for (const auto& [name, value] : params.numbers) {
    const ParamInfo& info = expect_param(*prim, name, {ParamKind::kNumber});
    if (!std::isfinite(value) || value < info.min || value > info.max) {
      throw core::InputError("motion." + name,
                             fmt::format("a number in [{}, {}] {}", info.min, info.max, info.unit),
                             fmt::format("{}", value));
    }
  }
  for (const auto& [name, value] : params.choices) {
    const ParamInfo& info = expect_param(*prim, name, {ParamKind::kSide, ParamKind::kChoice});
    if (std::find(info.choices.begin(), info.choices.end(), value) == info.choices.end()) {
      std::string options;
      for (std::string_view c : info.choices) options += (options.empty() ? "" : " | ") + std::string(c);
      throw core::InputError("motion." + name, options, "'" + value + "'");
    }
  }
  for (const auto& [name, value] : params.points) {
    expect_param(*prim, name, {ParamKind::kPoint});
    if (!finite(value)) throw core::InputError("motion." + name, "a finite point", "a non-finite value");
  }
  for (const auto& [name, value] : params.paths) {
    expect_param(*prim, name, {ParamKind::kPoints});
    for (const Vec3& p : value) {
      if (!finite(p)) throw core::InputError("motion." + name, "finite points", "a non-finite value");
    }
  }
  for (const auto& [name, value] : params.zones) {
    const ParamInfo& info = expect_param(*prim, name, {ParamKind::kZone});
    if (!finite(value.center)) {
      throw core::InputError("motion." + name + ".center", "a finite point", "a non-finite value");
    }
    if (!std::isfinite(value.radius) || value.radius < info.min || value.radius > info.max) {
      throw core::InputError("motion." + name + ".radius",
                             fmt::format("a radius in [{}, {}] m", info.min, info.max),
                             fmt::format("{}", value.radius));
    }
  }
  for (const auto& [name, value] : params.objects) {
    expect_param(*prim, name, {ParamKind::kObject});
    if (value.empty()) throw core::InputError("motion." + name, "an object name", "''");
  }
  for (const ParamInfo& info : prim->params) {
    if (!info.required) continue;
    const std::string key(info.name);
    const bool present = params.points.count(key) || params.zones.count(key) ||
                         params.numbers.count(key) || params.paths.count(key) ||
                         params.objects.count(key) || params.choices.count(key);
    if (!present) {
      throw core::InputError("motion." + key,
                             fmt::format("a {} (required by {})", to_string(info.kind), prim->name),
                             "nothing");
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Keys.

HandKey neutral_hand(const Skeleton& k, Side side) {
  SkeletonPose pose = SkeletonPose::Standing(k, 0, 0, 0);
  const Vec3 S = rest_shoulder(k, side);
  const double L = arm_length(k, side);
  // Hanging with a slight bend: the wrist a little forward and out, at 98 % reach.
  const Vec3 wrist_target = S + Vec3(0.03 * k.scale, -medial(side).y() * 0.04 * k.scale, -0.98 * L);
  solve_arm(k, pose, side, {wrist_target, 0, std::nullopt});
  const core::Pose X_W_wrist = forward_kinematics(k, pose)[static_cast<size_t>(index(wrist(side)))];
  HandKey h;
  h.palm = palm_centre(k, X_W_wrist);
  h.rotation = X_W_wrist.rotation;
  return h;
}

BodyKey body_key(const Skeleton& k, const SkeletonPose& pose) {
  BodyKey key;
  key.X_WF = stand_frame(k, pose);
  const core::Pose X_FW = key.X_WF.inverse();
  const auto X = forward_kinematics(k, pose);
  const Quat& R_torso = X[static_cast<size_t>(index(Joint::kSpine3))].rotation;
  for (const Side side : {Side::kLeft, Side::kRight}) {
    const core::Pose& X_W_wrist = X[static_cast<size_t>(index(wrist(side)))];
    HandKey& h = key.hands[slot(side)];
    h.palm = X_FW * palm_centre(k, X_W_wrist);
    h.rotation = (X_FW.rotation * X_W_wrist.rotation).normalized();
    // Swivel: where the elbow sits on its circle (the construction of solve_arm).
    const Vec3 S = X[static_cast<size_t>(index(shoulder(side)))].translation;
    const Vec3 E = X[static_cast<size_t>(index(elbow(side)))].translation;
    const Vec3 n = (X_W_wrist.translation - S).normalized();
    const Vec3 ref = R_torso * Vec3(-0.3, 0, -1).normalized();
    const Vec3 u = (ref - ref.dot(n) * n).normalized();
    const Vec3 v = n.cross(u);
    const Vec3 outward = side == Side::kLeft ? v : Vec3(-v);
    const Vec3 e = (E - S) - (E - S).dot(n) * n;
    h.swivel = e.norm() > 1e-9 ? std::atan2(e.dot(outward), e.dot(u)) : 0;
  }
  return key;
}

// ---------------------------------------------------------------------------------------------
// MotionPlan.

MotionPlan::MotionPlan(Skeleton skeleton, BodyKey start, std::vector<Segment> segments,
                       std::optional<Side> active_hand, uint64_t seed, double tremor)
    : skeleton_(std::move(skeleton)),
      start_(std::move(start)),
      segments_(std::move(segments)),
      active_hand_(active_hand),
      tremor_(tremor),
      seed_(seed) {
  core::Rng rng = core::Rng(seed).split("tremor");
  for (auto& hand : tremor_freq_) {
    for (double& f : hand) f = rng.uniform(8, 12);
  }
  for (auto& hand : tremor_phase_) {
    for (double& p : hand) p = rng.uniform(0, 2 * core::kPi);
  }
  leans_.push_back(lean_of(skeleton_, start_));
  for (const Segment& seg : segments_) leans_.push_back(lean_of(skeleton_, seg.end));
}

namespace {

// Neck extension (rad, >= 0) that keeps the face up in a lean of `angle` toward `dir` (pelvis
// frame, horizontal unit).
double head_extension(double angle, const Vec3& dir) {
  return std::min(kHeadExtension * std::max(0.0, angle * dir.x()), kMaxHeadExtension);
}

// Sets the neck: yaw (rad) toward a gaze, then extension (rad, the face up).
void set_neck(SkeletonPose& pose, double yaw, double extension) {
  pose.local[static_cast<size_t>(index(Joint::kNeck))] =
      (core::axis_angle(Vec3::UnitZ(), yaw) * core::axis_angle(Vec3::UnitY(), -extension)).normalized();
}

// Centre of the head capsule (human/skeleton.cc) in world.
Vec3 head_centre(const Skeleton& k, const SkeletonPose& pose) {
  return joint_pose(k, pose, Joint::kNeck) * Vec3(0.01 * k.scale, 0, 0.10 * k.scale);
}

// The largest lean (rad, <= kMaxLean) toward `dir` (pelvis frame, horizontal unit) with that
// crouch that keeps the head's centre within the bound in front of the ankles (forward of the
// stand frame) for a hand reaching to `wrist` (world).
double head_limited_lean(const Skeleton& k, const SkeletonPose& pose, const Vec3& dir, double crouch,
                         const Vec3& wrist) {
  const Vec3 feet = 0.5 * (joint_pose(k, pose, Joint::kLeftAnkle).translation +
                           joint_pose(k, pose, Joint::kRightAnkle).translation);
  const Vec3 fwd = stand_frame(k, pose).rotation * Vec3::UnitX();
  const double bound = std::max(kHeadReach, (wrist - feet).dot(fwd) - kHeadBehindHand);
  const auto over = [&](double angle) {
    SkeletonPose p = pose;
    lean_spine(k, p, dir, angle, crouch);
    set_neck(p, 0, head_extension(angle, dir));
    return (head_centre(k, p) - feet).dot(fwd) - bound;
  };
  const double at_max = over(kMaxLean);
  if (at_max <= 0) return kMaxLean;
  const double at_zero = over(0);
  if (at_zero > 0) return 0;
  return core::bisect_bracketed(0, at_zero, kMaxLean, at_max, 30, core::Crossing::kRising, over).lo;
}

// How much a lean toward a wrist target (world) bends the knees (lean_spine's crouch): 0 for a
// target less than a third of an arm's length below the shoulder (a reach at chest height is a
// lean), 1 an arm's length below it or lower (a reach down to the table).
double crouch_for(const Skeleton& k, const SkeletonPose& pose, Side side, const Vec3& wrist) {
  const double below = joint_pose(k, pose, shoulder(side)).translation.z() - wrist.z();
  return std::clamp(2 * below / arm_length(k, side) - 1, 0.0, 1.0);
}

// The lean (rad) a wrist target (world) asks for with that crouch, and its direction (pelvis
// frame, horizontal): mostly forward, a sideways lean would swing the other arm across the hips.
double lean_need(const Skeleton& k, const SkeletonPose& pose, Side side, const Vec3& wrist, Vec3& dir,
                 double crouch) {
  dir = pose.X_WP.rotation.conjugate() * (wrist - pose.X_WP.translation);
  dir.y() *= 0.3;
  Vec3 flat(dir.x(), dir.y(), 0);
  flat = flat.norm() > 1e-9 ? Vec3(flat.normalized()) : Vec3::UnitX();
  const double l = lean_for_reach(k, pose, side, wrist, kLeanReach,
                                  head_limited_lean(k, pose, flat, crouch, wrist), dir, crouch);
  dir = flat;
  return l;
}

// The shift of each hanging hand (reaching < 1) with its shoulder by a lean (world, never down).
std::array<Vec3, 2> hanging_shift(const Skeleton& k, SkeletonPose& pose, const Vec3& dir, double lean,
                                  double crouch, const std::array<double, 2>& reaching) {
  std::array<Vec3, 2> out{Vec3::Zero(), Vec3::Zero()};
  std::array<Vec3, 2> before;
  for (size_t h = 0; h < 2; ++h) {
    if (reaching[h] != 1) before[h] = joint_pose(k, pose, shoulder(side_of(h))).translation;
  }
  lean_spine(k, pose, dir, lean, crouch);
  for (size_t h = 0; h < 2; ++h) {
    if (reaching[h] == 1) continue;
    out[h] = joint_pose(k, pose, shoulder(side_of(h))).translation - before[h];
    out[h].z() = std::max(out[h].z(), 0.0);
    out[h] *= 1 - reaching[h];
  }
  return out;
}

// Weight of the lean at a segment's first key at progress s: early gone where a hand goes down
// to hang (a trunk still leaning over a hand drawn back stretched the arm behind the body).
template <class Lean>
double first_key_weight(const Lean& l0, const Lean& l1, double s) {
  bool lowering = false;
  for (size_t h = 0; h < 2; ++h) lowering = lowering || (l0.reaching[h] == 1 && l1.reaching[h] == 0);
  return lowering ? std::pow(1 - s, 7) : 1 - s;
}

}  // namespace

MotionPlan::Lean MotionPlan::lean_of(const Skeleton& k, const BodyKey& key) {
  // The lean for the farther of the two wrist targets, the body upright at the key's stand frame.
  SkeletonPose pose;
  pose.X_WP = key.X_WF * core::Pose{Quat::Identity(), Vec3(0, 0, k.pelvis_height)};
  Lean out;
  for (size_t h = 0; h < 2; ++h) {
    const HandKey& hk = key.hands[h];
    const Vec3 wrist_F = hk.palm + hk.rotation * Vec3(0, 0, k.palm_distance);
    // Only reaches away from the body lean; a hanging arm moves with its shoulder.
    const Vec3 off = wrist_F - rest_shoulder(k, side_of(h));
    if (std::hypot(off.x(), off.y()) < 0.3 * arm_length(k, side_of(h))) continue;
    out.reaching[h] = 1;
    Vec3 dir;
    const double crouch = crouch_for(k, pose, side_of(h), key.X_WF * wrist_F);
    const double l = lean_need(k, pose, side_of(h), key.X_WF * wrist_F, dir, crouch);
    if (l > out.angle) {
      out.angle = l;
      out.dir = dir;
      out.crouch = crouch;
    }
  }
  if (out.angle > 0) {
    const auto shift = hanging_shift(k, pose, out.dir, out.angle, out.crouch, out.reaching);
    for (size_t h = 0; h < 2; ++h) out.shift[h] = key.X_WF.rotation.conjugate() * shift[h];
  }
  return out;
}

std::vector<MotionPlan::Resolved> MotionPlan::resolve(const Signals& signals,
                                                      bool missing_as_minimum) const {
  std::vector<Resolved> out;
  double t = 0;
  for (const Segment& seg : segments_) {
    const double start = t;
    double end = start + seg.duration;
    if (seg.waits) {
      const auto it = signals.find(seg.phase);
      if (it != signals.end()) {
        end = std::max(end, it->second);
      } else if (!missing_as_minimum) {
        end = kInf;
      }
    }
    out.push_back({start, end});
    t = end;
  }
  return out;
}

std::vector<Phase> MotionPlan::timeline(const Signals& signals) const {
  const auto times = resolve(signals, false);
  std::vector<Phase> out;
  for (size_t i = 0; i < segments_.size(); ++i) {
    if (!segments_[i].phase.empty()) out.push_back({segments_[i].phase, times[i].start, times[i].end});
  }
  return out;
}

double MotionPlan::nominal_duration() const {
  const auto times = resolve({}, true);
  return times.empty() ? 0 : times.back().end;
}

double MotionPlan::end_time(const Signals& signals) const {
  const auto times = resolve(signals, false);
  return times.empty() ? 0 : times.back().end;
}

void MotionPlan::locate(double t, const std::vector<Resolved>& times, size_t& segment,
                        double& tau) const {
  for (size_t i = 0; i < times.size(); ++i) {
    if (t < times[i].end) {
      segment = i;
      const double d = segments_[i].duration;
      tau = d > 0 ? std::clamp((t - times[i].start) / d, 0.0, 1.0) : 1.0;
      return;
    }
  }
  // At or after the end: the end of the last segment.
  segment = segments_.empty() ? 0 : segments_.size() - 1;
  tau = 1;
}

BodyKey MotionPlan::interpolate(size_t segment, double tau) const {
  if (segments_.empty()) return start_;
  const Segment& seg = segments_[segment];
  const BodyKey& from = segment == 0 ? start_ : segments_[segment - 1].end;
  const BodyKey& to = seg.end;
  const double s = seg.profile.progress(tau);
  BodyKey out = to;
  out.X_WF.translation = (1 - s) * from.X_WF.translation + s * to.X_WF.translation;
  out.X_WF.rotation = from.X_WF.rotation.slerp(s, to.X_WF.rotation).normalized();
  out.gaze = (1 - s) * from.gaze + s * to.gaze;
  out.gaze_weight = (1 - s) * from.gaze_weight + s * to.gaze_weight;
  for (size_t h = 0; h < 2; ++h) {
    const HandKey& a = from.hands[h];
    const HandKey& b = to.hands[h];
    HandKey& o = out.hands[h];
    if (seg.palm_path[h]) {
      o.palm = seg.palm_path[h]->position(tau * seg.duration);
    } else if (seg.via[h].empty()) {
      o.palm = (1 - s) * a.palm + s * b.palm;
    } else {
      std::vector<Vec3> pts{a.palm};
      pts.insert(pts.end(), seg.via[h].begin(), seg.via[h].end());
      pts.push_back(b.palm);
      o.palm = ViaPath(std::move(pts)).at(s);
    }
    o.rotation = a.rotation.slerp(s, b.rotation).normalized();
    o.swivel = (1 - s) * a.swivel + s * b.swivel;
    o.point = (1 - s) * a.point + s * b.point;
    o.grip = (1 - s) * a.grip + s * b.grip;
    o.holding = s >= 0.5 ? b.holding : a.holding;
  }
  return out;
}

MotionPlan::Upright MotionPlan::upright(size_t segment, double tau, double t) const {
  const Skeleton& k = skeleton_;
  Upright out;
  out.segment = segment;
  out.key = interpolate(segment, tau);
  const BodyKey& key = out.key;
  const Segment* seg = segments_.empty() ? nullptr : &segments_[segment];
  out.s = seg != nullptr ? seg->profile.progress(tau) : 1.0;
  SkeletonPose& pose = out.pose;
  pose.X_WP = key.X_WF * core::Pose{Quat::Identity(), Vec3(0, 0, k.pelvis_height)};
  const auto set = [&](Joint j, const Quat& q) { pose.local[static_cast<size_t>(index(j))] = q; };
  Vec3 sway_shift = Vec3::Zero();  // the hands go along with an idle weight shift

  // Gait: legs swing with the distance walked (one step per step_length), scaled by speed.
  if (seg != nullptr && seg->walking) {
    const BodyKey& from = segment == 0 ? start_ : segments_[segment - 1].end;
    const double dist = (seg->end.X_WF.translation - from.X_WF.translation).norm();
    const double walked = dist * seg->profile.progress(tau);
    const double amp = std::min(1.0, seg->profile.rate(tau) / 1.5);
    const double phi = core::kPi * walked / seg->step_length;
    const double hip = amp * 0.35 * std::sin(phi);
    set(Joint::kLeftHip, core::axis_angle(Vec3::UnitY(), -hip));
    set(Joint::kRightHip, core::axis_angle(Vec3::UnitY(), hip));
    set(Joint::kLeftKnee, core::axis_angle(Vec3::UnitY(), amp * 0.6 * std::max(0.0, std::cos(phi))));
    set(Joint::kRightKnee, core::axis_angle(Vec3::UnitY(), amp * 0.6 * std::max(0.0, -std::cos(phi))));
    // The pelvis drops so that the lower foot stays on the floor (the gait's vertical bob).
    const auto X = forward_kinematics(k, pose);
    const double lowest = std::min(X[static_cast<size_t>(index(Joint::kLeftAnkle))].translation.z(),
                                   X[static_cast<size_t>(index(Joint::kRightAnkle))].translation.z());
    pose.X_WP.translation.z() -= lowest - rest_ankle_height(k);
  }
  // Idle: breathing (chest extension) and a lateral weight shift with the feet kept in place.
  if (seg != nullptr && (seg->breath > 0 || seg->sway > 0)) {
    const double tl = tau * seg->duration;
    const double breath = seg->breath * 0.5 * (1 - std::cos(2 * core::kPi * tl / seg->breath_period));
    set(Joint::kSpine3, core::axis_angle(Vec3::UnitY(), -breath));
    const double shift = seg->sway * std::sin(2 * core::kPi * tl / seg->sway_period);
    pose.X_WP.translation += key.X_WF.rotation * Vec3(0, shift, 0);
    sway_shift = Vec3(0, shift, 0);
    const double leg = k.bone_length(Joint::kLeftKnee) + k.bone_length(Joint::kLeftAnkle);
    const double beta = std::asin(std::clamp(-shift / leg, -1.0, 1.0));
    for (Joint j : {Joint::kLeftHip, Joint::kRightHip}) set(j, core::axis_angle(Vec3::UnitX(), beta));
    for (Joint j : {Joint::kLeftAnkle, Joint::kRightAnkle}) set(j, core::axis_angle(Vec3::UnitX(), -beta));
  }

  // Hand targets in world: palm + tremor -> wrist, then the wrist-pivoted oscillation.
  for (size_t h = 0; h < 2; ++h) {
    const HandKey& hk = key.hands[h];
    Vec3 palm = hk.palm + sway_shift;
    if (tremor_ > 0) {
      for (int a = 0; a < 3; ++a) {
        const auto ua = static_cast<size_t>(a);
        palm[a] += tremor_ * 0.5 *
                   (std::sin(2 * core::kPi * tremor_freq_[h][ua] * t + tremor_phase_[h][ua]) +
                    std::sin(2 * core::kPi * tremor_freq_[h][ua + 3] * t + tremor_phase_[h][ua + 3]));
      }
    }
    Quat R = hk.rotation;
    Vec3 wrist_F = palm + R * Vec3(0, 0, k.palm_distance);
    if (seg != nullptr && seg->oscillation[h].cycles > 0) {
      const HandOscillation& o = seg->oscillation[h];
      const double w = std::sin(2 * core::kPi * o.cycles * tau);
      wrist_F += o.offset * w;
      R = (core::axis_angle(o.axis, o.angle * w) * R).normalized();
    }
    out.targets[h] = {key.X_WF * wrist_F, hk.swivel, (key.X_WF.rotation * R).normalized(), hk.point};
  }
  return out;
}

// The keys' leans interpolated on the segment's progress. (A lean computed for each instant
// came in at once when a hand's target left the hanging zone, and a hand counted as hanging
// went with its shoulder until the instant its target left the zone: wrists jumped by
// decimetres.)
MotionPlan::KeyLean MotionPlan::key_lean(const Upright& u) const {
  KeyLean out;
  out.l0 = &leans_[segments_.empty() ? 0 : u.segment];
  out.l1 = &leans_[segments_.empty() ? 0 : u.segment + 1];
  const Lean& l0 = *out.l0;
  const Lean& l1 = *out.l1;
  const double s = u.s;
  const double w0 = first_key_weight(l0, l1, s);
  out.angle = w0 * l0.angle + s * l1.angle;
  out.dir = w0 * l0.angle * l0.dir + s * l1.angle * l1.dir;
  // The knees bend as at the keys (a crouch decided now came in at once).
  out.crouch = out.angle > 0 ? (w0 * l0.angle * l0.crouch + s * l1.angle * l1.crouch) / out.angle
                             : (1 - s) * l0.crouch + s * l1.crouch;
  return out;
}

MotionPlan::Knots::Need MotionPlan::knot_need(int64_t knot, const std::vector<Resolved>& times,
                                              size_t h) const {
  const double t = static_cast<double>(knot) * kLeanPeriod;
  size_t segment = 0;
  double tau = 1;
  locate(t, times, segment, tau);
  const Upright u = upright(segment, tau, t);
  const KeyLean kl = key_lean(u);
  Knots::Need need;
  if (kl.l0->reaching[h] == 0 || kl.l1->reaching[h] == 0) return need;
  need.angle = lean_need(skeleton_, u.pose, side_of(h), u.targets[h].wrist, need.dir, kl.crouch);
  return need;
}

const MotionPlan::Knots::Need& MotionPlan::knot(int64_t knot, const std::vector<Resolved>& times,
                                                size_t h, Knots& knots) const {
  bool same = knots.ends.size() == times.size();
  for (size_t i = 0; same && i < times.size(); ++i) same = knots.ends[i] == times[i].end;
  if (!same) {  // other signals: other phase times, other knots
    knots.ends.resize(times.size());
    for (size_t i = 0; i < times.size(); ++i) knots.ends[i] = times[i].end;
    knots.entries = {};
  }
  for (Knots::Entry& e : knots.entries) {
    if (e.knot != knot) continue;
    if (!e.needs[h]) e.needs[h] = knot_need(knot, times, h);
    return *e.needs[h];
  }
  // A new knot replaces the earlier of the two kept.
  Knots::Entry& e = knots.entries[0].knot < knots.entries[1].knot ? knots.entries[0] : knots.entries[1];
  e = Knots::Entry{knot, {}};
  return *(e.needs[h] = knot_need(knot, times, h));
}

MotionPlan::Frame MotionPlan::build_frame(size_t segment, double tau, double t,
                                          const std::vector<Resolved>& times, Knots& knots) const {
  const Skeleton& k = skeleton_;
  Upright u = upright(segment, tau, t);
  const BodyKey& key = u.key;
  const Segment* seg = segments_.empty() ? nullptr : &segments_[segment];
  const double s = u.s;
  SkeletonPose& pose = u.pose;
  std::array<ArmTarget, 2>& targets = u.targets;
  // Torso lean: the keys' leans, or more where a hand reaching at both keys asks for more. What
  // a hand asks for is solved at the knots of plan time, every kLeanPeriod, and interpolated
  // between them (docs/motion.md, "Leaning").
  const KeyLean kl = key_lean(u);
  const Lean& l0 = *kl.l0;
  const Lean& l1 = *kl.l1;
  double lean = kl.angle;
  Vec3 lean_dir = kl.dir;
  const double crouch = kl.crouch;
  const double at = std::max(t, 0.0) / kLeanPeriod;
  const auto before = static_cast<int64_t>(std::floor(at));
  const double a = at - static_cast<double>(before);
  for (size_t h = 0; h < 2; ++h) {
    if (l0.reaching[h] == 0 || l1.reaching[h] == 0) continue;
    const Knots::Need n0 = knot(before, times, h, knots);
    const Knots::Need& n1 = knot(before + 1, times, h, knots);
    const double l = (1 - a) * n0.angle + a * n1.angle;
    const Vec3 dir = (1 - a) * n0.angle * n0.dir + a * n1.angle * n1.dir;
    if (l > lean && dir.norm() > 1e-12) {
      // Only the extra lean goes the hand's way (turning the whole lean at once swung the trunk).
      lean_dir += (l - lean) * dir.normalized();
      lean = l;
    }
  }
  // A hand held where it hangs follows its shoulder forward and sideways but never down: carried
  // down with a forward lean, it sank into whatever the person leans over (a table's edge). A
  // hand on its way goes from where its shoulder took it at one key to where it takes it at the
  // other.
  std::array<bool, 2> held{};
  std::array<double, 2> reaching{};
  for (size_t h = 0; h < 2; ++h) {
    held[h] = l0.reaching[h] == l1.reaching[h] &&
              (seg == nullptr || (seg->via[h].empty() && !seg->palm_path[h] &&
                                  (seg->end.hands[h].palm - (segment == 0 ? start_ : segments_[segment - 1].end).hands[h].palm).norm() < 1e-9));
    if (held[h]) {
      reaching[h] = l0.reaching[h];
    } else if (l0.reaching[h] == 1 && l1.reaching[h] == 0) {
      // Going down to hang: more and more with the shoulder (not stretched behind a leaning trunk).
      reaching[h] = 1 - s * s;
    } else {
      reaching[h] = 1;
      targets[h].wrist += key.X_WF.rotation * ((1 - s) * l0.shift[h] + s * l1.shift[h]);
    }
  }
  if (lean > 0) {
    const auto shift = hanging_shift(k, pose, lean_dir, lean, crouch, reaching);
    for (size_t h = 0; h < 2; ++h) targets[h].wrist += shift[h];
  }
  for (size_t h = 0; h < 2; ++h) {
    solve_arm(k, pose, side_of(h), targets[h]);
    pose.hands[h] = {key.hands[h].grip, key.hands[h].point};
  }
  // Head: toward the gaze point, yaw at the neck (<= 50 deg), pitch at the head (-30..45 deg);
  // the neck extends with a forward lean so the face stays up.
  const double extension =
      lean > 0 && lean_dir.norm() > 1e-9 ? head_extension(lean, lean_dir.normalized()) : 0.0;
  set_neck(pose, 0, extension);
  if (key.gaze_weight > 0) {
    const core::Pose X_Ws3 = joint_pose(k, pose, Joint::kSpine3);
    const Vec3 from = joint_pose(k, pose, Joint::kNeck).translation;
    const Vec3 d = X_Ws3.rotation.conjugate() * (key.X_WF * key.gaze - from);
    const double yaw = std::clamp(std::atan2(d.y(), d.x()), -50 * kDeg, 50 * kDeg);
    const double pitch = std::clamp(std::atan2(-d.z(), std::hypot(d.x(), d.y())), -30 * kDeg, 45 * kDeg);
    set_neck(pose, key.gaze_weight * yaw, extension);
    // The head pitches back from the neck's extension toward the gaze.
    pose.local[static_cast<size_t>(index(Joint::kHead))] = core::axis_angle(
        Vec3::UnitY(), std::clamp(key.gaze_weight * (pitch + extension), -55 * kDeg, 55 * kDeg));
  }
  return {std::move(pose), label_of(segment, key), std::move(u.key)};
}

FrameLabel MotionPlan::label_of(size_t segment, const BodyKey& key) const {
  FrameLabel label;
  if (!segments_.empty()) label.phase = segments_[segment].phase;
  label.active_hand = active_hand_;
  for (size_t h = 0; h < 2; ++h) label.hands[h] = {key.hands[h].grip, key.hands[h].holding};
  return label;
}

BodyKey MotionPlan::key_at(double t, const Signals& signals) const {
  size_t i = 0;
  double tau = 1;
  locate(t, resolve(signals, false), i, tau);
  return interpolate(i, tau);
}

MotionPlan::Frame MotionPlan::frame_at(double t, const Signals& signals, Knots* knots) const {
  size_t i = 0;
  double tau = 1;
  const auto times = resolve(signals, false);
  locate(t, times, i, tau);
  Knots fresh;
  return build_frame(i, tau, t, times, knots != nullptr ? *knots : fresh);
}

SkeletonPose MotionPlan::pose_at(double t, const Signals& signals, Knots* knots) const {
  return frame_at(t, signals, knots).pose;
}

FrameLabel MotionPlan::label_at(double t, const Signals& signals) const {
  size_t i = 0;
  double tau = 1;
  const auto times = resolve(signals, false);
  locate(t, times, i, tau);
  return label_of(i, interpolate(i, tau));
}

LabelledClip MotionPlan::to_clip(double fps, const Signals& signals) const {
  HRIB_CHECK(fps > 0) << "fps=" << fps;
  const auto times = resolve(signals, true);
  const double end = times.empty() ? 0 : times.back().end;
  LabelledClip out;
  out.clip.skeleton = skeleton_;
  out.clip.fps = fps;
  out.clip.active_hand = active_hand_;
  for (size_t i = 0; i < segments_.size(); ++i) {
    if (!segments_[i].phase.empty()) {
      out.clip.phases.push_back({segments_[i].phase, times[i].start, times[i].end});
    }
  }
  const auto n = static_cast<size_t>(std::ceil(end * fps - 1e-9)) + 1;
  Knots knots;
  for (size_t f = 0; f < n; ++f) {
    const double t = static_cast<double>(f) / fps;
    size_t seg = 0;
    double tau = 1;
    locate(t, times, seg, tau);
    Frame frame = build_frame(seg, tau, t, times, knots);
    out.clip.frames.push_back(std::move(frame.pose));
    out.labels.push_back(std::move(frame.label));
  }
  return out;
}

MotionPlan MotionPlan::retarget(double t, const Signals& signals, Side side, const Vec3& palm,
                                double remaining) const {
  HRIB_CHECK(remaining > 0) << "remaining=" << remaining;
  HRIB_CHECK(!segments_.empty());
  const auto times = resolve(signals, false);
  const size_t h = slot(side);
  const auto palm_at = [&](double tt) {
    size_t seg = 0;
    double tau = 1;
    locate(std::max(0.0, tt), times, seg, tau);
    return interpolate(seg, tau).hands[h].palm;
  };
  size_t i = 0;
  double tau = 1;
  locate(t, times, i, tau);
  const BodyKey now = interpolate(i, tau);
  // Current palm velocity and acceleration (F) by central differences.
  constexpr double dt = 1e-3;
  const Vec3 p0 = now.hands[h].palm;
  const Vec3 v0 = (palm_at(t + dt) - palm_at(t - dt)) / (2 * dt);
  const Vec3 a0 = (palm_at(t + dt) - 2 * p0 + palm_at(t - dt)) / (dt * dt);
  const Vec3 target = now.X_WF.inverse() * palm;
  const Vec3 old_target = segments_[i].end.hands[h].palm;

  std::vector<Segment> segments;
  Segment first = segments_[i];
  first.duration = remaining;
  first.end.hands[h].palm = target;
  first.via[h].clear();
  first.palm_path[h] = Quintic::Between(p0, v0, a0, target, Vec3::Zero(), Vec3::Zero(), remaining);
  segments.push_back(std::move(first));
  for (size_t j = i + 1; j < segments_.size(); ++j) {
    Segment seg = segments_[j];
    if ((seg.end.hands[h].palm - old_target).norm() < 1e-9) seg.end.hands[h].palm = target;
    segments.push_back(std::move(seg));
  }
  MotionPlan out(skeleton_, now, std::move(segments), active_hand_, seed_, tremor_);
  // The new plan starts with the lean the body has now (between this segment's keys).
  const double s = segments_[i].profile.progress(tau);
  const Lean& l0 = leans_[i];
  const Lean& l1 = leans_[i + 1];
  Lean& start = out.leans_[0];
  const double w0 = first_key_weight(l0, l1, s);
  start.angle = w0 * l0.angle + s * l1.angle;
  const Vec3 dir = w0 * l0.angle * l0.dir + s * l1.angle * l1.dir;
  start.dir = dir.norm() > 1e-9 ? Vec3(dir.normalized()) : Vec3::UnitX();
  start.crouch = start.angle > 0 ? (w0 * l0.angle * l0.crouch + s * l1.angle * l1.crouch) / start.angle : 0;
  for (size_t hand = 0; hand < 2; ++hand) start.shift[hand] = (1 - s) * l0.shift[hand] + s * l1.shift[hand];
  return out;
}

// ---------------------------------------------------------------------------------------------
// Primitive generators.

namespace {

// Builds the segments of one primitive: set the target state, then push() a phase.
class PlanBuilder {
 private:
  // A palm path chord that passes through the trunk (a vertical cylinder about F's z axis,
  // wider at the hips) gets a via-point pushed out of it at its deepest point; in the hip zone
  // the point is also raised above the hips, so that reaches from a hanging arm to the front
  // lift the forearm over the pelvis instead of sweeping through it.
  void avoid_trunk() {
    const double s = k_.scale;
    const double top = rest_shoulder(k_, Side::kLeft).z();
    const double hips = k_.pelvis_height + 0.15 * s;  // top of the hip zone
    const auto radius = [&](double z) { return z < hips ? 0.25 * s : 0.17 * s; };
    const auto depth = [&](const Vec3& p) {
      return p.z() < top ? radius(p.z()) - std::hypot(p.x(), p.y()) : -1.0;
    };
    for (size_t i = 0; i < segments_.size(); ++i) {
      Segment& seg = segments_[i];
      const BodyKey& from = i == 0 ? start_ : segments_[i - 1].end;
      for (size_t h = 0; h < 2; ++h) {
        const Vec3 a = from.hands[h].palm;
        const Vec3 b = seg.end.hands[h].palm;
        if ((a - b).norm() < 1e-6 || depth(b) > 0) continue;
        std::vector<Vec3> pts{a};
        pts.insert(pts.end(), seg.via[h].begin(), seg.via[h].end());
        pts.push_back(b);
        std::vector<Vec3> out{a};
        for (size_t c = 0; c + 1 < pts.size(); ++c) {
          double worst = 0;
          Vec3 deepest = Vec3::Zero();
          for (int u = 1; u < 20; ++u) {
            const Vec3 p = pts[c] + (u / 20.0) * (pts[c + 1] - pts[c]);
            if (depth(p) > worst) {
              worst = depth(p);
              deepest = p;
            }
          }
          if (worst > 0) {
            Vec3 dir(deepest.x(), deepest.y(), 0);
            dir = dir.norm() > 1e-6 ? Vec3(dir.normalized()) : Vec3::UnitX();
            const double z = deepest.z() < hips ? std::max(deepest.z(), std::min(hips, b.z())) : deepest.z();
            const Vec3 pushed = dir * (radius(deepest.z()) + 0.03 * s);
            out.push_back(Vec3(pushed.x(), pushed.y(), z));
          }
          out.push_back(pts[c + 1]);
        }
        seg.via[h].assign(out.begin() + 1, out.end() - 1);
      }
    }
  }

 public:
  PlanBuilder(const Skeleton& k, const SkeletonPose& start, const PrimitiveParams& p)
      : k_(k), p_(p), info_(*find_primitive(p.primitive)), state_(body_key(k, start)) {
    if (info_.uses_hand) hand_ = choice("hand") == "left" ? Side::kLeft : Side::kRight;
  }

  // Parameters with catalog defaults.
  double num(const std::string& name) const {
    const auto it = p_.numbers.find(name);
    if (it != p_.numbers.end()) return it->second;
    const ParamInfo* info = info_.param(name);
    HRIB_CHECK(info != nullptr && info->has_default) << p_.primitive << "." << name;
    return info->default_value;
  }
  bool has(const std::string& name) const {
    return p_.numbers.count(name) || p_.points.count(name) || p_.objects.count(name);
  }
  std::string choice(const std::string& name) const {
    const auto it = p_.choices.find(name);
    if (it != p_.choices.end()) return it->second;
    return std::string(info_.param(name)->default_choice);
  }
  std::string object() const {
    const auto it = p_.objects.find("object");
    return it == p_.objects.end() ? std::string() : it->second;
  }
  // A world point parameter, in W and in F.
  Vec3 point_W(const std::string& name) const { return p_.points.at(name); }
  Vec3 point_F(const std::string& name) const { return to_F(p_.points.at(name)); }
  Zone zone() const { return p_.zones.at("zone"); }
  Vec3 to_F(const Vec3& world) const { return state_.X_WF.inverse() * world; }
  std::vector<Vec3> via_F() const {
    std::vector<Vec3> out;
    const auto it = p_.paths.find("via");
    if (it != p_.paths.end()) {
      for (const Vec3& v : it->second) out.push_back(to_F(v));
    }
    return out;
  }

  const Skeleton& skeleton() const { return k_; }
  Side hand() const { return hand_; }
  HandKey& key(Side side) { return state_.hands[slot(side)]; }
  BodyKey& state() { return state_; }
  Vec3 shoulder_F(Side side) const { return rest_shoulder(k_, side); }
  double reach(Side side) const { return arm_length(k_, side); }
  double swivel() const { return num("swivel") * kDeg; }

  // Moves a hand's target to a palm position and rotation (F), keeping grip and holding.
  void move_hand(Side side, const Vec3& palm, const Quat& rotation, double swivel_rad) {
    HandKey& h = key(side);
    h.palm = palm;
    h.rotation = rotation;
    h.swivel = swivel_rad;
  }
  // Back to the hanging arm, keeping grip and holding.
  void rest_hand(Side side) {
    const HandKey n = neutral_hand(k_, side);
    move_hand(side, n.palm, n.rotation, n.swivel);
  }
  // The head turns to a point (F) by the end of the next phase.
  void look_at(const Vec3& point) {
    state_.gaze = point;
    state_.gaze_weight = 1;
  }
  void set_grip(Side side, double grip, const std::string& holding) {
    key(side).grip = grip;
    key(side).holding = holding;
  }

  // Records the start state and the onset wait; call after any start-state changes.
  void begin() {
    start_ = state_;
    push("", num("onset"));
  }
  // Appends a phase ending in the current state; the reference is valid until the next push.
  Segment& push(const std::string& phase, double duration, bool waits = false) {
    Segment s;
    s.phase = phase;
    s.duration = duration;
    s.waits = waits;
    s.end = state_;
    segments_.push_back(std::move(s));
    return segments_.back();
  }
  // The primitive's main movement of one hand: palm to `palm` with `rotation`, on the profile
  // set by the `decel` parameter, through the script's via-points and then `extra_via`.
  Segment& move(const std::string& phase, double duration, Side side, const Vec3& palm,
                const Quat& rotation, const std::vector<Vec3>& extra_via = {}) {
    move_hand(side, palm, rotation, swivel());
    look_at(palm);
    Segment& seg = push(phase, duration);
    seg.profile.decel = num("decel");
    seg.via[slot(side)] = via_F();
    seg.via[slot(side)].insert(seg.via[slot(side)].end(), extra_via.begin(), extra_via.end());
    return seg;
  }
  // The hand opens ("release"), then retracts ("retract"), with the durations of those names.
  void release_and_retract(Side side) {
    set_grip(side, 0, "");
    push("release", num("release"));
    retract("retract", num("retract"), {side});
  }
  // A retraction phase: to the hanging arm(s), or staying put when the duration is 0.
  void retract(const std::string& phase, double duration, std::initializer_list<Side> sides) {
    if (duration > 0) {
      for (Side s : sides) rest_hand(s);
      state_.gaze_weight = 0;
    }
    push(phase, duration);
  }

  MotionPlan finish(std::optional<Side> active) {
    avoid_trunk();
    const double tremor = info_.param("tremor") != nullptr ? num("tremor") : 0.0;
    return MotionPlan(k_, start_, segments_, active, p_.seed, tremor);
  }

 private:
  const Skeleton& k_;
  const PrimitiveParams& p_;
  const PrimitiveInfo& info_;
  Side hand_ = Side::kRight;
  BodyKey state_;
  BodyKey start_;
  std::vector<Segment> segments_;
};

// Hand rotations (F) used by several primitives.
Quat palm_up(Side side, const Vec3& fingers) {
  return hand_rotation(side, fingers, Vec3::UnitZ() + 0.5 * medial(side));
}
Quat palm_medial(Side side, const Vec3& fingers) {
  return hand_rotation(side, fingers, medial(side) + Vec3(0, 0, -0.2));
}
Quat palm_down(Side side, const Vec3& fingers) { return hand_rotation(side, fingers, -Vec3::UnitZ()); }
// Horizontal unit direction from a to b (F), +x when degenerate.
Vec3 horizontal_dir(const Vec3& a, const Vec3& b) {
  Vec3 d = b - a;
  d.z() = 0;
  return d.norm() > 1e-6 ? Vec3(d.normalized()) : Vec3::UnitX();
}
Quat palm_choice(Side side, const std::string& palm, const Vec3& fingers) {
  if (palm == "up") return palm_up(side, fingers);
  if (palm == "down") return palm_down(side, fingers);
  return palm_medial(side, fingers);
}

void build_idle(PlanBuilder& b) {
  b.begin();
  Segment& s = b.push("idle", b.num("duration"));
  s.breath = b.num("breath") * kDeg;
  s.breath_period = b.num("breath_period");
  s.sway = b.num("sway");
  s.sway_period = b.num("sway_period");
}

void build_walk_to(PlanBuilder& b) {
  b.begin();
  BodyKey& st = b.state();
  const Vec3 goal = b.point_W("to");
  const Vec3 goal_xy(goal.x(), goal.y(), 0);
  const Vec3 d = goal_xy - st.X_WF.translation;
  const double dist = d.norm();
  const Vec3 fwd = st.X_WF.rotation * Vec3::UnitX();
  const double heading = dist > 1e-6 ? std::atan2(d.y(), d.x()) : std::atan2(fwd.y(), fwd.x());
  st.X_WF.rotation = core::axis_angle(Vec3::UnitZ(), heading);
  b.push("turn", b.num("turn"));
  st.X_WF.translation = goal_xy;
  Segment& walk = b.push("walk", walk_duration(dist, b.num("speed")));
  walk.walking = true;
  walk.step_length = b.num("step_length");
  const double yaw = b.has("yaw_deg") ? b.num("yaw_deg") * kDeg : heading;
  b.state().X_WF.rotation = core::axis_angle(Vec3::UnitZ(), yaw);
  b.push("face", b.num("turn"));
}

// reach / intrude: palm to a target, stay, (intrude: retract).
void build_reach_like(PlanBuilder& b, bool intrude) {
  const Side h = b.hand();
  b.begin();
  const Vec3 target = b.point_F("target");
  const Vec3 fingers = horizontal_dir(b.shoulder_F(h), target);
  b.move("reach", b.num("duration"), h, target, palm_choice(h, b.choice("palm"), fingers));
  if (intrude) {
    b.push("dwell", b.num("dwell"));
    b.retract("retract", b.num("retract"), {h});
  } else {
    b.push("hold", b.num("dwell"), true);
  }
}

void build_retract(PlanBuilder& b, const std::string& phase, bool keeps_object) {
  const Side h = b.hand();
  if (keeps_object && !b.object().empty()) b.set_grip(h, 1, b.object());
  b.begin();
  b.retract(phase, b.num("duration"), {h});
}

void build_point(PlanBuilder& b) {
  const Side h = b.hand();
  const Skeleton& k = b.skeleton();
  b.begin();
  const Vec3 S = b.shoulder_F(h);
  const Vec3 to_target = b.point_F("target") - S;
  const Vec3 dir = to_target.norm() > 1e-6 ? Vec3(to_target.normalized()) : Vec3::UnitX();
  const Quat rot = hand_rotation(h, dir, -Vec3::UnitZ() + medial(h));
  const double ext = b.num("extension") * b.reach(h);
  // Preparation: wrist onto the ray at half extension (elbow flexed); stroke: out along it.
  b.move_hand(h, S + (0.5 * ext + k.palm_distance) * dir, rot, b.swivel());
  b.key(h).point = 1;
  b.look_at(b.point_F("target"));
  b.push("prep", b.num("prep"));
  b.move("stroke", b.num("stroke"), h, S + (ext + k.palm_distance) * dir, rot);
  b.push("hold", b.num("hold"), true);
  if (b.num("retract") > 0) b.key(h).point = 0;
  b.retract("retract", b.num("retract"), {h});
}

// go / give_me / your_turn / stop / cancel.

// raise -> gesture -> lower, the gesture turning the hand about `axis` (F, through the wrist)
// by `angle` and moving the wrist by `offset`, `cycles` times.
void raise_gesture_lower(PlanBuilder& b, Side h, const Vec3& axis, double angle, const Vec3& offset) {
  b.push("raise", b.num("raise"));
  HandOscillation osc;
  // Whole half cycles, so that the oscillation is back at zero when the gesture ends (a
  // fractional count left the hand displaced and it jumped back as the lowering began).
  osc.cycles = std::max(0.5, std::round(2 * b.num("cycles")) / 2);
  osc.angle = angle;
  osc.axis = axis;
  osc.offset = offset;
  b.push("gesture", b.num("gesture")).oscillation[slot(h)] = osc;
  b.retract("lower", b.num("lower"), {h});
}

void build_go(PlanBuilder& b) {
  const Side h = b.hand();
  const double s = b.skeleton().scale;
  b.begin();
  const Vec3 S = b.shoulder_F(h);
  const double angle = b.num("amplitude") * kDeg;
  if (b.choice("style") == "wave") {
    // Hand up beside the head, palm toward the robot, waving side to side about the wrist.
    b.move_hand(h, S + Vec3(0.25 * s, 0, 0.35 * s) - 0.12 * s * medial(h),
                hand_rotation(h, Vec3::UnitZ(), Vec3::UnitX() + 0.6 * medial(h)), b.swivel() + 0.5);
    raise_gesture_lower(b, h, Vec3::UnitX(), angle, 0.04 * s * medial(h));
  } else {
    // Palm up in front of the waist; the fingers beckon toward the person.
    b.move_hand(h, S + Vec3(0.33 * s, 0, -0.25 * s) + 0.05 * s * medial(h),
                palm_up(h, Vec3::UnitX()), b.swivel());
    raise_gesture_lower(b, h, Vec3::UnitX().cross(Vec3::UnitZ()), angle, Vec3(-0.03 * s, 0, 0));
  }
}

void build_stop(PlanBuilder& b) {
  const Side h = b.hand();
  const double s = b.skeleton().scale;
  b.begin();
  const Vec3 S = b.shoulder_F(h);
  const Vec3 palm = S + Vec3(b.num("extension") * b.reach(h), 0, b.num("height")) + 0.08 * s * medial(h);
  b.move_hand(h, palm, hand_rotation(h, Vec3::UnitZ(), Vec3::UnitX() + 0.5 * medial(h)), b.swivel());
  b.push("raise", b.num("raise"));
  b.push("hold", b.num("hold"), true);
  b.retract("lower", b.num("lower"), {h});
}

void build_give_me(PlanBuilder& b) {
  const Side h = b.hand();
  const double s = b.skeleton().scale;
  b.begin();
  const Vec3 S = b.shoulder_F(h);
  const Vec3 palm = b.has("target") ? b.point_F("target")
                                    : Vec3(S + Vec3(0.35 * s, 0, -0.3 * s) + 0.05 * s * medial(h));
  const Vec3 fingers = horizontal_dir(S, palm);
  b.move_hand(h, palm, palm_up(h, fingers), b.swivel());
  raise_gesture_lower(b, h, fingers.cross(Vec3::UnitZ()), b.num("amplitude") * kDeg, -0.02 * s * fingers);
}

void build_cancel(PlanBuilder& b) {
  const Side h = b.hand();
  const double s = b.skeleton().scale;
  b.begin();
  if (b.choice("style") == "arms_crossed") {
    // Forearms crossed in front of the chest, the left one higher and further forward.
    const Vec3 SL = b.shoulder_F(Side::kLeft);
    const Vec3 SR = b.shoulder_F(Side::kRight);
    b.move_hand(Side::kLeft, Vec3(0.30 * s, -0.13 * s, SL.z() - 0.20 * s),
                hand_rotation(Side::kLeft, Vec3(-0.2, -1, 0.1), Vec3(-1, 0, -0.3)), 0.6);
    b.move_hand(Side::kRight, Vec3(0.23 * s, 0.13 * s, SR.z() - 0.36 * s),
                hand_rotation(Side::kRight, Vec3(-0.2, 1, 0.1), Vec3(-1, 0, -0.3)), 0.6);
    b.push("raise", b.num("raise"));
    b.push("gesture", b.num("gesture"));
    b.retract("lower", b.num("lower"), {Side::kLeft, Side::kRight});
    return;
  }
  // Wave-off: palm out in front of the chest, sweeping side to side.
  const Vec3 S = b.shoulder_F(h);
  b.move_hand(h, S + Vec3(0.36 * s, 0, -0.08 * s) + 0.1 * s * medial(h),
              hand_rotation(h, Vec3(0.3, 0, 1), Vec3::UnitX() + 0.5 * medial(h)), b.swivel());
  const double amplitude = b.num("amplitude") * kDeg;
  raise_gesture_lower(b, h, Vec3::UnitZ(), 0.5 * amplitude,
                      std::sin(amplitude) * 0.25 * s * medial(h));
}

void build_your_turn(PlanBuilder& b) {
  const Side h = b.hand();
  const double s = b.skeleton().scale;
  b.begin();
  const Vec3 S = b.shoulder_F(h);
  const Vec3 dir = b.has("target") ? horizontal_dir(S, b.point_F("target")) : Vec3::UnitX();
  b.move_hand(h, S + Vec3(0.22 * s, 0, -0.3 * s) + 0.08 * s * medial(h),
              palm_up(h, (Vec3::UnitX() + 0.5 * medial(h)).normalized()), b.swivel());
  b.push("raise", b.num("raise"));
  b.move_hand(h, S + 0.6 * b.reach(h) * dir + Vec3(0, 0, -0.18 * s), palm_up(h, dir), b.swivel());
  b.push("gesture", b.num("gesture")).profile.decel = 0.6;
  b.push("hold", b.num("hold"));
  b.retract("lower", b.num("lower"), {h});
}

void build_offer(PlanBuilder& b) {
  const Side h = b.hand();
  b.set_grip(h, 1, b.object());
  b.begin();
  const Zone z = b.zone();
  const Vec3 C = b.to_F(z.center);
  const Vec3 toward = horizontal_dir(b.shoulder_F(h), C);
  // The held object is held out upright (it sits in the hand as it was at the start: upright
  // with the hand hanging): the hand only turns about the vertical, toward the zone, and with
  // `palm: up` 30 degrees further, the palm toward the taker. (A palm rotated like
  // palm_choice's tilted the object 40-90 degrees, 15 degrees still put its rim under a
  // finger: no top-down grasp could take it.)
  const double turn = b.choice("palm") == "up" ? (h == Side::kLeft ? 30.0 : -30.0) * kDeg : 0.0;
  const Quat rot =
      (core::axis_angle(Vec3::UnitZ(), std::atan2(toward.y(), toward.x()) + turn) * b.key(h).rotation).normalized();
  // The reach ends slightly past the centre (1 cm, or a fifth of the radius), then settles.
  const Vec3 from = b.key(h).palm;
  const Vec3 past = C + std::min(0.01, 0.2 * z.radius) * (C - from).normalized();
  b.move("reach", b.num("duration"), h, past, rot);
  b.move_hand(h, C, rot, b.swivel());
  b.push("hold", b.num("settle"));
  b.push("hold_stable", b.num("hold"), true);
  b.release_and_retract(h);
}

void build_receive(PlanBuilder& b) {
  const Side h = b.hand();
  b.set_grip(h, 0, "");
  b.begin();
  const Vec3 C = b.to_F(b.zone().center);
  const Vec3 fingers = horizontal_dir(b.shoulder_F(h), C);
  const Quat rotation = palm_choice(h, b.choice("palm"), fingers);
  // With shift_by: held out short of the zone first, then moved into it (same hand rotation).
  Vec3 first = C;
  if (b.has("shift_by")) {
    first = b.to_F(b.zone().center - b.point_W("shift_by"));
    if ((first - C).norm() > 0.005 && b.num("shift") < 0.2) {
      throw core::InputError("motion.shift", "at least 0.2 s when shift_by moves the hand",
                             fmt::format("{}", b.num("shift")));
    }
  }
  b.move("reach", b.num("duration"), h, first, rotation);
  b.push("present", b.num("present"));
  b.move_hand(h, C, rotation, b.swivel());
  b.look_at(C);
  b.push("shift", b.num("shift"));
  b.push("open", b.num("open"), true);
  b.set_grip(h, 1, b.object());
  b.push("close", b.num("close"));
  b.retract("retract", b.num("retract"), {h});
}

// Grasp rotation and the approach offset (F) for pick / place / move_object.
Quat grasp_rotation(PlanBuilder& b, Side h, const Vec3& at, Vec3& approach) {
  const Vec3 fingers = horizontal_dir(b.shoulder_F(h), at);
  if (b.choice("grasp_type") == "top") {
    approach = Vec3(0, 0, 0.08);
    return palm_down(h, fingers);
  }
  approach = -0.08 * fingers;
  return palm_medial(h, fingers);
}

void build_pick(PlanBuilder& b) {
  const Side h = b.hand();
  b.begin();
  const Vec3 T = b.point_F("target");
  Vec3 approach;
  const Quat rot = grasp_rotation(b, h, T, approach);
  b.move("reach", b.num("duration"), h, T, rot, {T + approach});
  b.set_grip(h, 1, b.object());
  b.push("grasp", b.num("grasp"));
  b.move_hand(h, T + Vec3(0, 0, b.num("lift_height")), rot, b.swivel());
  b.push("lift", b.num("lift"));
}

void build_place(PlanBuilder& b) {
  const Side h = b.hand();
  b.set_grip(h, 1, b.object());
  b.begin();
  const Vec3 T = b.point_F("target");
  Vec3 approach;
  const Quat rot = grasp_rotation(b, h, T, approach);
  b.move("transport", b.num("duration"), h, T, rot, {T + Vec3(0, 0, b.num("approach_height"))});
  b.release_and_retract(h);
}

void build_move_object(PlanBuilder& b) {
  const Side h = b.hand();
  b.begin();
  const Vec3 A = b.point_F("from");
  const Vec3 B = b.point_F("to");
  const Vec3 lift(0, 0, b.num("lift_height"));
  Vec3 approach;
  const Quat rot_a = grasp_rotation(b, h, A, approach);
  b.move("reach", b.num("duration"), h, A, rot_a, {A + approach});
  b.set_grip(h, 1, b.object());
  b.push("grasp", b.num("grasp"));
  const Quat rot_b = grasp_rotation(b, h, B, approach);
  b.move_hand(h, B, rot_b, b.swivel());
  Segment& transport = b.push("transport", b.num("transport"));
  transport.profile.decel = b.num("decel");
  transport.via[slot(h)] = {A + lift, B + lift};
  b.release_and_retract(h);
}

void build_hold_lid(PlanBuilder& b) {
  const Side h = b.hand();
  b.begin();
  const Vec3 H = b.point_F("handle");
  const Vec3 G = b.point_F("hinge");
  const Vec3 r = H - G;
  const Vec3 r_h = horizontal_dir(G, H);
  const Vec3 axis = r_h.cross(Vec3::UnitZ());  // rotating r about it lifts the handle
  const double open = b.num("open_deg") * kDeg;
  const Quat grasp = palm_down(h, -r_h);
  const auto arc = [&](double f) { return Vec3(G + core::axis_angle(axis, f * open) * r); };
  // The hand turns with the lid by half the lid's angle (the grip rolls on the handle).
  const auto hand_at = [&](double f) { return Quat(core::axis_angle(axis, 0.5 * f * open) * grasp); };
  b.move_hand(h, H, grasp, b.swivel());
  b.look_at(H);
  Segment& reach = b.push("reach", b.num("duration"));
  reach.via[slot(h)] = {H + Vec3(0, 0, 0.08)};
  b.set_grip(h, 1, b.object());
  b.push("grasp", b.num("grasp"));
  b.move_hand(h, arc(1), hand_at(1), b.swivel());
  b.push("open", b.num("open")).via[slot(h)] = {arc(0.25), arc(0.5), arc(0.75)};
  b.push("hold", b.num("hold"), true);
  b.move_hand(h, H, grasp, b.swivel());
  b.push("close", b.num("close")).via[slot(h)] = {arc(0.75), arc(0.5), arc(0.25)};
  b.release_and_retract(h);
}

// The hands gripping a plank end: both when grip_width > 0, else the active one.
std::vector<Side> plank_hands(const PlanBuilder& b) {
  if (b.num("grip_width") > 0) return {Side::kLeft, Side::kRight};
  return {b.hand()};
}
// Places the gripping hands around the grip point G (F), palms down, fingers forward.
void grip_plank(PlanBuilder& b, const Vec3& G) {
  const double w = b.num("grip_width");
  for (Side side : plank_hands(b)) {
    const Vec3 palm = w > 0 ? Vec3(G - 0.5 * w * medial(side)) : G;
    b.move_hand(side, palm, palm_down(side, Vec3::UnitX()), b.swivel());
  }
}
Vec3 grip_point(PlanBuilder& b) {
  Vec3 sum = Vec3::Zero();
  const auto hands = plank_hands(b);
  for (Side side : hands) sum += b.key(side).palm;
  return sum / static_cast<double>(hands.size());
}

void build_lift(PlanBuilder& b) {
  b.begin();
  const Vec3 G = b.point_F("target");
  grip_plank(b, G);
  b.look_at(G);
  b.push("reach", b.num("duration"));
  for (Side side : plank_hands(b)) b.set_grip(side, 1, b.object());
  b.push("grasp", b.num("grasp"));
  grip_plank(b, G - Vec3(0, 0, 0.02 * b.skeleton().scale));
  b.push("prep", b.num("prep"));
  grip_plank(b, G + Vec3(0, 0, b.num("height")));
  b.push("lift", b.num("lift"));
}

void build_carry(PlanBuilder& b) {
  for (Side side : plank_hands(b)) b.set_grip(side, 1, b.object());
  b.begin();
  const Vec3 from = grip_point(b);
  const Vec3 delta = b.point_F("to") - from;
  // The body steps by the horizontal part; the hands rise or sink by the vertical part.
  BodyKey& st = b.state();
  const Vec3 step(delta.x(), delta.y(), 0);
  st.X_WF.translation += st.X_WF.rotation * step;
  for (Side side : plank_hands(b)) b.key(side).palm.z() += delta.z();
  Segment& carry = b.push("carry", b.num("duration"));
  carry.walking = step.norm() > 0.15;
}

void build_lower(PlanBuilder& b) {
  for (Side side : plank_hands(b)) b.set_grip(side, 1, b.object());
  b.begin();
  for (Side side : plank_hands(b)) b.key(side).palm.z() -= b.num("height");
  b.push("lower", b.num("lower"));
  for (Side side : plank_hands(b)) b.set_grip(side, 0, "");
  b.push("release", b.num("release"));
  b.retract("retract", b.num("retract"), {Side::kLeft, Side::kRight});
}

void build_release_retract(PlanBuilder& b) {
  const Side h = b.hand();
  b.set_grip(h, 1, b.object());
  b.begin();
  b.release_and_retract(h);
}

}  // namespace

double walk_duration(double distance, double speed) { return std::max(0.2, 1.875 * distance / speed); }

MotionPlan plan_motion(const Skeleton& skeleton, const SkeletonPose& start,
                       const PrimitiveParams& params) {
  validate(params);
  PlanBuilder b(skeleton, start, params);
  const std::string& name = params.primitive;
  std::optional<Side> active;
  if (find_primitive(name)->uses_hand) active = b.hand();
  if (name == "idle") build_idle(b);
  else if (name == "walk_to") build_walk_to(b);
  else if (name == "reach") build_reach_like(b, false);
  else if (name == "intrude") build_reach_like(b, true);
  else if (name == "retract") build_retract(b, "retract", false);
  else if (name == "withdraw") build_retract(b, "withdraw", true);
  else if (name == "point") build_point(b);
  else if (name == "go") build_go(b);
  else if (name == "stop") build_stop(b);
  else if (name == "give_me") build_give_me(b);
  else if (name == "cancel") build_cancel(b);
  else if (name == "your_turn") build_your_turn(b);
  else if (name == "offer") build_offer(b);
  else if (name == "receive") build_receive(b);
  else if (name == "pick") build_pick(b);
  else if (name == "place") build_place(b);
  else if (name == "move_object") build_move_object(b);
  else if (name == "hold_lid") build_hold_lid(b);
  else if (name == "lift") build_lift(b);
  else if (name == "carry") build_carry(b);
  else if (name == "lower") build_lower(b);
  else if (name == "release_retract") build_release_retract(b);
  else HRIB_CHECK(false) << "primitive without a generator: " << name;
  return b.finish(active);
}

LabelledClip generate_clip(const Skeleton& skeleton, const SkeletonPose& start,
                           const PrimitiveParams& params, double fps) {
  return plan_motion(skeleton, start, params).to_clip(fps);
}

}  // namespace hribench::human

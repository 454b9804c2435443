#pragma once
// Procedural human motion: each primitive of the catalog (human/primitives.h) as a parametric
// generator. A generator turns drawn parameters into a MotionPlan: a deterministic function of
// time that can wait in its reactive phases (offer.hold_stable, receive.open, ...) until the
// runtime signals it, and that renders to a Clip with named phases and per-frame labels.
//
// How it moves: the palm centre of each hand follows a minimum-jerk profile (asymmetric for
// precision phases) along a smooth path through optional via-points; the hand rotation is
// slerped with the same profile; the arms come from analytic two-link IK with a swivel angle;
// the torso leans when a hand target is beyond 93 % of the arm's reach (bending the knees for a
// low target, the neck extending, the head kept near the feet: docs/motion.md, "Leaning"); the
// pelvis follows min-jerk root moves with a procedural gait when walking. Gestures add wrist-pivoted
// oscillations; tremor adds a small 8-12 Hz palm oscillation. Every number comes from the
// parameters, so a script can draw them from distributions.
//
// Frames: targets are world points (m). The plan keeps hand targets in the person's stand frame
// F (the floor point under the pelvis, x forward, y left, z up), so hands move with the body
// when the person walks or carries.

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/math.h"
#include "human/arm_ik.h"
#include "human/clip.h"
#include "human/minjerk.h"
#include "human/primitives.h"
#include "human/skeleton.h"

namespace hribench::human {

// A ball in the world frame.
struct Zone {
  core::Vec3 center = core::Vec3::Zero();  // m
  double radius = 0.05;                    // m
};

// Parameter values for one primitive, after the script's distributions have been drawn.
// Keys are catalog parameter names; absent keys take the catalog defaults.
struct PrimitiveParams {
  std::string primitive;                                   // catalog name, e.g. "offer"
  std::map<std::string, double> numbers;                   // kNumber, in the catalog's unit
  std::map<std::string, std::string> choices;              // kSide ("left"/"right"), kChoice
  std::map<std::string, core::Vec3> points;                // kPoint, world
  std::map<std::string, std::vector<core::Vec3>> paths;    // kPoints, world
  std::map<std::string, Zone> zones;                       // kZone
  std::map<std::string, std::string> objects;              // kObject: scene object names
  uint64_t seed = 0;                                       // tremor phases and frequencies
};

// Throws core::InputError naming "motion.<param>" for an unknown primitive or parameter, a
// missing required parameter, a value of the wrong kind, a number outside its range or not
// finite, or a choice not in the list.
void validate(const PrimitiveParams& params);

// How often a reaching hand's lean is solved (s of plan time, from 0): the trunk's lean between
// two knots is interpolated between theirs (docs/motion.md, "Leaning"). Every other control
// step since pool v8 (every control step before: co_lift and gesture_delivery spent a tenth of
// their physics on it, docs/performance.md); solving it at every physics step cost C1, C4 and
// I2 more than their physics.
inline constexpr double kLeanPeriod = 0.1;

// Signals for reactive phases: phase name -> the time (s, plan time) its signal arrived. A
// waiting phase lasts at least its nominal duration and ends at max(nominal end, signal time).
using Signals = std::map<std::string, double>;

// What a hand is doing at one instant.
struct HandLabel {
  double grip = 0;      // 0 = open, 1 = closed
  std::string holding;  // scene object held (closed on it), empty if none
};

// Per-frame labels of a motion.
struct FrameLabel {
  std::string phase;                // the current phase, empty before the first (onset)
  std::optional<Side> active_hand;  // the hand the primitive is about
  std::array<HandLabel, 2> hands;   // [0] left, [1] right
};

// A clip with its per-frame labels (labels[i] belongs to clip.frames[i]).
struct LabelledClip {
  Clip clip;
  std::vector<FrameLabel> labels;
};

// Internal state of the body at a key: the stand frame and both hands in it.
struct HandKey {
  core::Vec3 palm = core::Vec3::Zero();      // palm centre in F, m
  core::Quat rotation = core::Quat::Identity();  // hand (wrist frame) rotation in F
  double swivel = 0;                          // rad (ArmTarget::swivel)
  // The hand's shape (HandShape): `point` is 1 while the hand points (its index straight; the
  // arm's IK then leaves the roll about the pointing ray free, ArmTarget::free_roll); `grip`
  // goes from 0 (open) to 1 (closed).
  double point = 0;
  double grip = 0;
  std::string holding;                        // object held at this key
};
struct BodyKey {
  core::Pose X_WF;                   // stand frame: yaw about +z, origin on the floor
  std::array<HandKey, 2> hands;      // [0] left, [1] right
  core::Vec3 gaze = core::Vec3::Zero();  // point the head turns to, in F
  double gaze_weight = 0;            // 0 = head straight, 1 = looking at `gaze` (within limits)
};

// An oscillation added to one hand during a segment: the wrist is displaced by
// offset * sin(2 pi cycles tau) and the hand turns about `axis` (F) through the wrist by
// angle * sin(2 pi cycles tau), tau in [0, 1] over the segment.
struct HandOscillation {
  core::Vec3 offset = core::Vec3::Zero();
  core::Vec3 axis = core::Vec3::UnitZ();
  double angle = 0;    // rad
  double cycles = 0;   // 0 = none
};

// One phase of a plan: from the previous segment's end key to `end`.
struct Segment {
  std::string phase;            // phase name; empty for the onset wait
  double duration = 0;          // nominal (minimum, for waits) duration, s
  bool waits = false;           // holds at `end` until the signal named `phase`
  MinJerkProfile profile;       // progress profile of the move
  BodyKey end;
  std::array<std::vector<core::Vec3>, 2> via;  // palm via-points in F, per hand
  std::array<HandOscillation, 2> oscillation;
  // Palm path (F, seconds from the segment start) that replaces the profile and via-points for
  // a hand; set by MotionPlan::retarget.
  std::array<std::optional<Quintic>, 2> palm_path;
  bool walking = false;         // procedural gait on the legs while the root moves
  double step_length = 0.65;    // m, with walking
  // Idle breathing and weight shift (amplitudes 0 = off).
  double breath = 0;            // rad of chest extension
  double breath_period = 4;     // s
  double sway = 0;              // m of lateral pelvis sway
  double sway_period = 6;       // s
};

// A plan: a start key and segments, evaluated at any time given the signals received so far.
class MotionPlan {
 public:
  MotionPlan(Skeleton skeleton, BodyKey start, std::vector<Segment> segments,
             std::optional<Side> active_hand, uint64_t seed, double tremor);

  const Skeleton& skeleton() const { return skeleton_; }
  std::optional<Side> active_hand() const { return active_hand_; }
  const std::vector<Segment>& segments() const { return segments_; }

  // Named phases with their times given the signals; a waiting phase whose signal has not
  // arrived ends at +infinity and later phases start there.
  std::vector<Phase> timeline(const Signals& signals) const;
  // Duration when every waiting phase ends at its minimum.
  double nominal_duration() const;
  // End of the plan given the signals (+infinity while a phase waits).
  double end_time(const Signals& signals) const;

  // What a caller that poses the plan at many instants keeps between calls: the lean each
  // reaching hand asks for at the knots of plan time around the last instant (docs/motion.md,
  // "Leaning"), so that each knot is solved once. It only saves work: a pose is the same with
  // or without it. Give each plan its own, and a new one to a new plan.
  class Knots {
   public:
    Knots() = default;

   private:
    friend class MotionPlan;
    struct Need {
      double angle = 0;  // rad
      core::Vec3 dir = core::Vec3::UnitX();
    };
    struct Entry {
      int64_t knot = -1;
      std::array<std::optional<Need>, 2> needs;
    };
    std::vector<double> ends;  // the phases' resolved ends the knots were solved for
    std::array<Entry, 2> entries;
  };

  // The pose and labels at plan time t (clamped to [0, end]): deterministic, pure.
  SkeletonPose pose_at(double t, const Signals& signals = {}, Knots* knots = nullptr) const;
  FrameLabel label_at(double t, const Signals& signals = {}) const;
  // The body key at time t (targets, grips), before IK.
  BodyKey key_at(double t, const Signals& signals = {}) const;
  // All three at time t: pose_at's, label_at's and key_at's, the plan interpolated once (a
  // caller that poses the person at every physics step needs more than one of them).
  struct Frame {
    SkeletonPose pose;
    FrameLabel label;
    BodyKey key;
  };
  Frame frame_at(double t, const Signals& signals = {}, Knots* knots = nullptr) const;

  // Samples the plan at `fps` from 0 to its end; missing signals count as arriving at the
  // minimum end of their phase.
  LabelledClip to_clip(double fps, const Signals& signals = {}) const;

  // Re-targets a hand mid-motion (e.g. a receiving hand following a moving object): a new plan
  // whose time 0 is time t of this one. The hand's palm bends from its current position,
  // velocity and acceleration to `palm` (world) over `remaining` seconds (> 0) with a quintic
  // (min-jerk); the current phase lasts at least `remaining` (a waiting phase keeps waiting), and
  // later phases that held the old target hold the new one. Signals for the new plan are in its
  // own time.
  MotionPlan retarget(double t, const Signals& signals, Side side, const core::Vec3& palm,
                      double remaining) const;

 private:
  struct Resolved {
    double start;
    double end;
  };
  std::vector<Resolved> resolve(const Signals& signals, bool missing_as_minimum) const;
  // Which segment covers t, and the progress tau in it (index == size: after the end).
  void locate(double t, const std::vector<Resolved>& times, size_t& segment, double& tau) const;
  BodyKey interpolate(size_t segment, double tau) const;
  // The trunk lean at a key: the angle (rad) toward dir (pelvis frame = F, horizontal), per
  // hand 1 when its arm reaches (0: it hangs and moves with its shoulder) and how far a hanging
  // wrist goes with its shoulder (F, m). Within a segment the lean is interpolated between its
  // keys on the segment's progress (the first key's part going early where a hand goes down to
  // hang; more where a hand reaching at both keys asks for more now), so the trunk and the
  // wrists move continuously when an arm leaves or enters hanging.
  struct Lean {
    double angle = 0;
    core::Vec3 dir = core::Vec3::UnitX();
    double crouch = 0;  // lean_spine's crouch: how much the knees bend with the lean
    std::array<double, 2> reaching{};
    std::array<core::Vec3, 2> shift{core::Vec3::Zero(), core::Vec3::Zero()};
  };
  static Lean lean_of(const Skeleton& skeleton, const BodyKey& key);
  // The body at time t before the trunk leans: the key, the segment's progress s, the pose
  // (root, legs, gait, idle motion) and the hands' wrist targets.
  struct Upright {
    size_t segment = 0;
    BodyKey key;
    double s = 1;
    SkeletonPose pose;
    std::array<ArmTarget, 2> targets;
  };
  Upright upright(size_t segment, double tau, double t) const;
  // The keys' leans interpolated at that instant: the angle (rad), its direction (scaled by the
  // angle) and the crouch, with the two keys'.
  struct KeyLean {
    const Lean* l0 = nullptr;
    const Lean* l1 = nullptr;
    double angle = 0;
    core::Vec3 dir = core::Vec3::Zero();
    double crouch = 0;
  };
  KeyLean key_lean(const Upright& u) const;
  // The lean hand h asks for at a knot (time knot * kLeanPeriod; 0 where it does not reach),
  // solved, or kept in `knots`.
  Knots::Need knot_need(int64_t knot, const std::vector<Resolved>& times, size_t h) const;
  const Knots::Need& knot(int64_t knot, const std::vector<Resolved>& times, size_t h, Knots& knots) const;
  Frame build_frame(size_t segment, double tau, double t, const std::vector<Resolved>& times,
                    Knots& knots) const;
  FrameLabel label_of(size_t segment, const BodyKey& key) const;

  Skeleton skeleton_;
  BodyKey start_;
  std::vector<Segment> segments_;
  std::optional<Side> active_hand_;
  double tremor_ = 0;
  uint64_t seed_ = 0;
  std::array<std::array<double, 6>, 2> tremor_freq_{};   // per hand: x, y, z; two sines each
  std::array<std::array<double, 6>, 2> tremor_phase_{};
  std::vector<Lean> leans_;  // of start_, then of each segment's end
};

// The body key of a pose (stand frame: pelvis yaw, origin under the hip joints; palms and hand
// rotations from forward kinematics, swivels estimated, grips open, head straight).
BodyKey body_key(const Skeleton& skeleton, const SkeletonPose& pose);

// The rest hand of a side: arm hanging with a slight elbow bend, palm facing the thigh (F).
HandKey neutral_hand(const Skeleton& skeleton, Side side);

// Duration (s) of walk_to's "walk" phase: a min-jerk root move whose PEAK speed is `speed`
// (m/s): max(0.2, 1.875 * distance / speed).
double walk_duration(double distance, double speed);

// Builds the plan of a primitive for a person with this skeleton starting in `start` (for a
// first act: SkeletonPose::Standing). Validates the parameters first (see validate()).
MotionPlan plan_motion(const Skeleton& skeleton, const SkeletonPose& start,
                       const PrimitiveParams& params);

// plan_motion(...).to_clip(fps).
LabelledClip generate_clip(const Skeleton& skeleton, const SkeletonPose& start,
                           const PrimitiveParams& params, double fps = 30);

}  // namespace hribench::human

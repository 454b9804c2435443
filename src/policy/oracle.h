#pragma once
// The privileged expert (issue 6): `oracle`, and the scripted baselines `reactive` and `blind`
// with the same manipulation skill and less interaction competence (policy/oracle_plan.h).
//
// It reads the sampled episode (EpisodeInfo::episode), the events so far, the human joints and
// the object poses (state and privileged tracks) and drives the TCP with ee_delta actions
// along straight Cartesian segments with a trapezoidal speed profile (at most kMaxSpeed,
// accelerations kAcceleration), top-down grasps by finger contact (open, descend, close, check
// that something is between the fingers, lift), releases by opening. No teleporting, no weld.
//
// Interaction layer by competence:
//   all      — runs the plan's steps in order; a step waits for its `after` event (as the plan
//              says for the competence);
//   oracle,
//   reactive — a "stop" cue halts the robot (held pose) until the next "go" cue;
//   oracle   — yields while a disruption act runs (backs off toward its own side of the table,
//              keeping the protective separation by an estimate of the surface distance to the
//              person: intrusion_gap in oracle.cc; a grasp closing then is cut short);
//              speed-and-separation monitoring against the human arms (slow below
//              kSlowDistance, stop below kStopDistance, back off below kRetreatDistance,
//              resume when clear), except in handover steps; re-plans grasps and placements
//              from the live object poses and follows a moving receiving palm (the baselines
//              keep the poses seen when the step began); pauses a contradicted step when the
//              contradicting act starts.
// Deterministic: actions are a function of the episode and the observations.

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "core/math.h"
#include "human/skeleton.h"
#include "policy/oracle_plan.h"
#include "policy/policy.h"
#include "script/predicate.h"

namespace hribench::policy {

// Motion constants (m, m/s, m/s^2, rad per step).
inline constexpr double kMaxSpeed = 0.30;        // TCP transit speed
inline constexpr double kFineSpeed = 0.10;       // descending, lowering, handing over
inline constexpr double kAcceleration = 1.5;
inline constexpr double kMaxTurnPerStep = 0.10;  // TCP rotation per control step
inline constexpr double kApproachHeight = 0.10;  // pre-grasp height above the grasp point
inline constexpr double kCarryClearance = 0.08;  // object bottom above the highest obstacle top
// Separation (distances between robot points and human arm segments, m).
inline constexpr double kSlowDistance = 0.60;
inline constexpr double kStopDistance = 0.42;
inline constexpr double kRetreatDistance = 0.34;
inline constexpr double kResumeDistance = 0.48;
inline constexpr double kRetreatSpeed = 0.15;         // m/s backing off below kRetreatDistance
inline constexpr double kWaitingRetreatFactor = 2.5;  // times kRetreatSpeed while waiting for a cue
// ... but motion that increases the separation goes on, at this fraction of the step's speed.
inline constexpr double kSeparatingScale = 0.3;
// The arm holding a box's lid open for the robot is expected near the box (the robot works
// under it): instead of the distances above, the robot stops closer than this to it.
inline constexpr double kLidArmClearance = 0.10;
// Where the oracle yields while a disruption act runs: TCP x at most kYieldX, z at least kYieldZ.
inline constexpr double kYieldX = 0.30;
inline constexpr double kYieldZ = 1.0;
// ... and at least kYieldClearance (horizontally) from each palm, moving sideways (|y| <= 0.45).
inline constexpr double kYieldClearance = 0.45;

// What the robot is doing within the current plan step: one phase enum per skill, in the
// order the skill goes through them.
// Picking an object off the table or out of a box (also the first part of a place or offer
// step that does not hold its object yet).
enum class PickPhase {
  kApproach,  // gripper open, over the grasp point (over a box's rim)
  kDescend,   // straight down onto the grasp point
  kClose,     // pre-shape, squeeze, grip, check that something is between the fingers
  kLift,      // holding it, up clear of the other objects (out of the box)
};
// Placing the held object on or in its target (put back, hover).
enum class PlacePhase {
  kCarry,     // over the spot on the target, at carrying height
  kLower,     // down onto the target's surface
  kRelease,   // opening the gripper
  kWithdraw,  // up, away from the placed object
};
// Bringing the held object into a receiving human palm.
enum class OfferPhase {
  kBring,     // toward the palm, hovering over a hand held out without a gesture until it opens
  kHandOpen,  // the receiving hand has opened: into it once it has been open the act's `open` time
};
// Letting go of an object a human hand has taken.
enum class ReleasePhase {
  kWaitForHand,  // still gripping until the hand holds the object
  kOpen,         // opening the gripper
  kWithdraw,     // the fingers out of the hand, away from the person
};
// Taking an object a person holds out.
enum class TakePhase {
  kApproach,  // short of the object while the person reaches; then over its grasp point
  kDescend,   // down to the grasp point, fingers open
  kSqueeze,   // pre-shape, squeeze until both fingers touch
  kGrip,      // full grip force, then check that something is between the fingers
  kHold,      // holding it still until the person lets go
  kBackAway,  // (the place step after it) back toward the robot's base, away from the person
};
// Carrying an object together with a person (the robot's end of it).
enum class CoCarryPhase {
  kApproach,  // gripper open, over the robot's end
  kDescend,   // down to it, pre-shaping on the last centimetres
  kClose,     // squeeze, check the grip
  kHold,      // holding: waiting for the lift cue, then following the person's end
  kOpen,      // letting go with the person
  kWithdraw,  // up and back, off the object
};
// Waiting beside a lidded box until the person opens it.
enum class BoxWaitPhase {
  kToReady,  // over the ready point beside the box, from above
  kCreep,    // the last centimetres to the waiting point, slowly
};
// The phase of the skill the current step runs. Every step begins at PickPhase::kApproach
// (the skills that pick first start there); a skill that finds another skill's phase enters
// its own first phase.
using SkillPhase = std::variant<PickPhase, PlacePhase, OfferPhase, ReleasePhase, TakePhase, CoCarryPhase,
                                BoxWaitPhase>;

class ExpertPolicy : public Policy {
 public:
  explicit ExpertPolicy(Competence competence);
  PolicySpec spec() const override;
  // Throws PolicyError(kFailed) without the privileged episode or for a goal it cannot plan.
  void reset(const EpisodeInfo& info) override;
  ActionChunk act(const Observation& observation) override;

  // The plan of the current episode (after reset).
  const std::vector<PlanStep>& plan() const { return plan_; }
  // Index of the step being executed at the last act(), plan().size() when all are done.
  size_t current_step() const { return current_; }

 private:
  struct ObjectGeometry {
    std::string name;
    std::string kind;
    core::Vec3 half_extents = core::Vec3::Zero();
    // Static scene parts the state track does not report (platforms): their pose, world.
    std::optional<core::Pose> fixed_X_WO;
  };
  struct World;  // the observation, indexed (oracle.cc)

  const ObjectGeometry* geometry(const std::string& name) const;
  void update_events(const Observation& observation);
  bool seen(const std::string& event) const;
  bool step_done(size_t i) const;
  bool disruption_running() const;  // a disruption act has started and not ended
  bool step_dropped(size_t i) const;
  void begin_step(size_t i, const World& world);
  // The manipulation skill of the current step: sets target_ (TCP pose), speed_ and gripper_.
  void run_step(const World& world);
  void run_pick(const World& world, const std::string& object, bool close);
  // Closing on an object at `grasp`, timed from the phase's start: pre-shape `width` +
  // kPreshapeGap for `preshape` s, squeeze at `rate` (m/s) to kSqueezeDepth under it, grip
  // `grip` s, then kHolding if something is between the fingers, else kMissed (a retry).
  enum class Grip { kClosing, kHolding, kMissed };
  Grip squeeze(const World& world, double width, const core::Vec3& grasp, double preshape, double rate,
               double grip);
  // The gripper, commanded closed, holds object k (objects_ order): the fingers stopped apart
  // and the object's centre within reach of the TCP.
  bool holds(const World& world, size_t k) const;
  void run_place(const World& world, const PlanStep& step);
  void run_home(const World& world);
  // Where to put `object` on/in `target` (pose X_WC): the grid point of the target's footprint
  // farthest from the objects already there, preferring the centre.
  core::Vec3 free_spot(const World& world, size_t object, size_t target, const core::Pose& X_WC) const;
  void run_handover(const World& world, const PlanStep& step);
  // Co-carry (oracle_co_lift.cc): the robot's end of an object the person carries with it.
  void run_co_carry(const World& world, const PlanStep& step);
  // Box retrieval (oracle_box.cc): waiting beside a lidded box, picking from inside it; false
  // when `step` is neither (the generic skills run it).
  bool run_box_step(const World& world, const PlanStep& step);
  void run_box_wait(const World& world, size_t box, double near);
  void run_box_pick(const World& world, size_t object, size_t box);
  // Holding `object`, straight up until farther than the step's distance from its target.
  void run_leave(const World& world, const PlanStep& step);
  // The box (objects_ index) `object` lies in (or just above), objects_.size() if none.
  size_t box_containing(const World& world, size_t object) const;
  // The side (0 left, 1 right) of the person's arm holding a box's lid open, or -1.
  int lid_arm(const World& world) const;
  // Distance (m) from `points` to that arm (upper arm, forearm, the hand hanging from the wrist).
  double lid_arm_distance(const World& world, const std::array<core::Vec3, 4>& points, int side) const;
  // The human act that receives an object (primitive receive), or "".
  std::string receiving_act(const std::string& object) const;
  // Whether the human act `act` holds its palm turned sideways (its `palm: medial`).
  bool palm_turned_in(const std::string& act) const;
  // Hand `side` (0 left, 1 right) is held out to ask for or receive an object (a give_me or
  // receive act with that hand is running): the handover's goal, not an intrusion.
  bool receiving_hand(int side) const;
  // Hand `side` has shown where it wants an object (the gesture phase of a give_me act began).
  bool palm_shown(int side) const;
  // A logged predicate grasped(robot, object) is true now (false when not logged).
  bool robot_grasps(const std::string& object) const;
  // `object` starts in a human hand (the scene's held_by).
  bool starts_in_hand(const std::string& object) const;
  // Taking an object a person holds out (oracle_handover.cc): the approach and grasp steps of
  // an object that starts in a human hand, and its place step; false when `step` is neither.
  bool run_take(const World& world, const PlanStep& step);
  // The place step after such a take: back away from the person first (true while doing so).
  bool run_take_retreat(const World& world);
  // A logged predicate held(human.H, object) (alone, not within a conjunction) is true.
  bool human_holds(const std::string& object) const;
  void set_phase(SkillPhase phase, double time);
  // The current step's skill is in phase `phase` / in one of `Phase`'s phases.
  template <typename Phase>
  bool in_phase(Phase phase) const {
    const Phase* now = std::get_if<Phase>(&phase_);
    return now != nullptr && *now == phase;
  }
  template <typename Phase>
  bool in_skill() const {
    return std::holds_alternative<Phase>(phase_);
  }
  // Closing the gripper on an object on the table or in a box (finished before anything else).
  bool closing_grasp() const { return in_phase(PickPhase::kClose); }
  // On the last stretch to a grasp point, a target's surface or the box's waiting point (the
  // moves a back-off restarts from above, and lowering that goes on slowly near a person).
  bool final_approach() const {
    return in_phase(PickPhase::kDescend) || in_phase(PlacePhase::kLower) || in_phase(BoxWaitPhase::kCreep);
  }
  void restart_approach();  // after backing off: approach the grasp / target from above again
  double separation_scale(const World& world, core::Vec3& retreat) const;
  // `direction` (unit) less its components toward the current step's object and target, so
  // that the motion moves away from both; zero when little is left, when the step has neither,
  // and for steps whose goal has no position (put back, home, still).
  core::Vec3 without_approach(const World& world, const core::Vec3& direction) const;
  Action motion_action(const World& world, double scale, const core::Vec3& retreat);

  Competence competence_;
  std::shared_ptr<const script::EpisodeSpec> episode_;
  human::Skeleton body_;                 // the person's skeleton (the episode's height)
  std::vector<PlanStep> plan_;
  std::vector<ObjectGeometry> objects_;
  std::vector<std::string> events_;      // names of events seen (kinds act_*, phase, cue)
  // A logged predicate (a goal or success predicate whose changes are events): its name (the
  // predicate's text), what it says about holding, and its last value.
  struct LoggedPredicate {
    std::string name;
    std::optional<script::HoldingAtom> holding;
    bool value = false;
  };
  std::vector<LoggedPredicate> predicates_;
  std::vector<char> internal_done_;      // per step: its skill sequence finished
  size_t events_read_ = 0;
  bool stopped_ = false;                 // a stop cue holds the robot
  bool ssm_stopped_ = false;
  bool holding_ = false;                 // held (stop, waiting) at the last act()
  bool waiting_ = false;                 // held for the current step's `after` event (no stop)
  bool started_ = false;
  core::Pose home_;
  std::vector<core::Vec3> start_positions_;  // per object (objects_ order): body origin at start
  // Skill state.
  size_t current_ = 0;
  SkillPhase phase_ = PickPhase::kApproach;
  double phase_start_ = 0;  // s: when phase_ began
  core::Vec3 latched_ = core::Vec3::Zero();  // the object pose seen when the step began
  bool latched_valid_ = false;
  core::Vec3 latched_target_ = core::Vec3::Zero();  // the target object's pose then
  bool latched_target_valid_ = false;
  core::Vec3 latched_palm_ = core::Vec3::Zero();  // baselines: the receiving palm first seen held out
  bool latched_palm_valid_ = false;
  // Baselines: object positions (objects_ order) as last refreshed at a step's start; not
  // refreshed once a disruption act has started (no re-planning after a disruption).
  std::vector<core::Vec3> believed_;
  core::Vec3 spot_ = core::Vec3::Zero();  // the chosen placing spot (centre of the object)
  bool spot_valid_ = false;
  double control_dt_ = 0.05;
  core::Pose target_;
  double speed_ = kMaxSpeed;
  double gripper_ = 1.0;
  core::Vec3 reference_ = core::Vec3::Zero();  // the commanded TCP position of the profile
  core::Vec3 velocity_ = core::Vec3::Zero();
  // Co-carry: the person's palms (left, right) at the last control step (the velocity of those
  // holding the object leads the robot's end), and that step's time (< 0: none).
  std::array<core::Vec3, 2> palms_last_ = {core::Vec3::Zero(), core::Vec3::Zero()};
  double palms_time_ = -1;
  core::Vec3 retreat_from_ = core::Vec3::Zero();  // the TCP where the place after a take began
};

// "oracle" | "reactive" | "blind".
std::unique_ptr<Policy> make_expert(Competence competence);

}  // namespace hribench::policy

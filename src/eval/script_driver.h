#pragma once
// The act-graph runtime (script/runtime.h) as the runner's ScenarioDriver (eval/runner.h), and
// the model scene of a sampled episode.
//
// ScriptDriver, each control step (observe): fills a script::WorldSnapshot from the simulation
// (objects in ActGraph::objects order — platforms as fixed boxes —, TCP, gripper, finger
// contacts, palms and holds), steps the runtime, plans the motion (human::plan_motion) of every
// human act that started, from the human's current pose, and copies the runtime's new events
// into the log. The person's pose at an instant (pose_at): the body from the most recently
// started act's plan at (t - act start); each hand follows the latest started act whose plan
// moves that hand (its arm solved to that plan's wrist pose from the current torso), so a
// person can hold a lid with one hand while the other points; while the latest started act
// that moves the root (a walk) runs, the root and legs follow it, so an act started mid-walk
// does not stop the walk. Each physics step (drive_between, as released since pool v8): the
// pose interpolated between those at the control step's start and end (the last control
// step's end where nothing the pose reads changed since: the same pose, made once); the holds
// change at the physics step the labels say (where the two ends hold differently, the labels
// alone are read at each physics step between). Under RunOptions::person_pose_per_physics_step
// (drive, pools up to v7) the pose is made for every physics step.
// Holds follow the hand's plan labels (holding X begins:
// a box is held by its lid, sim::grasp_lid_by_human; a plank by point holds,
// sim::grasp_point_by_human; anything else sim::grasp_by_human; ends: sim::release_by_human).
// Only label changes within one plan act: a new plan starts from a pose whose hands hold
// nothing in its labels, so switching plans keeps the holds as they are (a person who gives up
// an offer keeps the object).
//
// Signals of waiting phases: a waiting phase without an `until` predicate ends at its nominal
// time (signal 0); with one, the plan waits until the runtime leaves the phase, and the signal
// is the runtime's phase change time (seen at the next control step, so the hand holds up to
// one control step longer than the runtime's phase event says).
//
// Predicate series: "success" = every success predicate of the graph holds; with a
// contradiction (an act with `contradicts`), also "intent" and "contradicted" (CIR, and CSR
// reads "intent": the latest intent is the instruction until the contradiction starts).
// Event kinds: ACT.start / ACT.end -> kActStart / kActEnd (actor human or robot); ACT.PHASE ->
// kPhase (and also kCue, name = that event, detail = the cue kind, when it is an act's cue);
// PRED:true/false -> kPredicateChange (name PRED, detail "true"/"false"); ACT.skipped ->
// kWarning (name "ACT.skipped", detail "skipped").
//
// An act with an imported `clip` (path relative to the working directory, read with
// human::read_clip at the model's body height) plays it stretched to the act's `duration`,
// placed where the body stands and facing its way when the act starts; it moves the whole body
// and holds nothing. Not handled yet: an act started mid-walk plans its own motion from the
// mid-stride pose (its root targets stay where it started; the walk carries it along).

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "eval/runner.h"
#include "human/clip.h"
#include "human/motion.h"
#include "model/model.h"
#include "script/runtime.h"
#include "script/scenario.h"
#include "sim/data.h"

namespace hribench::eval {

// The model scene of a sampled episode: objects (kind, name, colour — "gray" becomes "grey" —,
// footprint x/y and yaw from pose; an object `in` a container starts inside it at the
// container's x/y; one with a pose `z` rests on the platform under it; held_by
// human.left/right), platform objects as named model platforms (size [x, y, z], pose xy and
// yaw) and the human (height, stand x/y/yaw, handedness). Throws core::InputError (where
// "scene.objects.NAME") for what the model cannot build: an explicit `size` on anything but a
// platform, a platform without size or pose, a pose `z` over no platform, objects with neither
// pose, container nor hand.
model::SceneSpec scene_spec_from_episode(const script::EpisodeSpec& spec);

// The motion parameters of a sampled human act (act index `act` of spec.acts) for the human
// layer: object references in point parameters resolve to `object_centre(name)` (world, m).
// Seed: derived from spec.seed and the act index.
// Throws core::InputError when the act has no primitive motion.
human::PrimitiveParams primitive_params(
    const script::EpisodeSpec& spec, size_t act,
    const std::function<core::Vec3(const std::string&)>& object_centre);

// Model and data (docs/episode.md): what is fixed for the episode — the sampled spec, the
// compiled act graph, what each event id means, the predicate series — is compiled once and
// shared (read-only) by every copy; the state — the act-graph runtime, the world snapshot it
// reads, the human's started motion plans and clips, the holds' labels, the events already
// logged, the robot's home TCP — is the driver's own, so copying a ScriptDriver (clone) copies
// the scenario's state and both copies continue identically.
class ScriptDriver : public ScenarioDriver {
 public:
  // Compiles the spec's act graph (throws core::InputError like script::compile). The model
  // passed to reset/drive/observe must be built from scene_spec_from_episode(spec).
  explicit ScriptDriver(script::EpisodeSpec spec);
  explicit ScriptDriver(std::shared_ptr<const script::EpisodeSpec> spec);

  // "success"; with an act that contradicts a robot act (I5) also "intent" (once a
  // contradicting act has started = success: the script's success predicates state the latest
  // intent; before, the instruction is: the contradicted robot act's goal holds) and
  // "contradicted" (the goal of a robot act that a started human act contradicts holds), the
  // series the CIR metric and, for such scripts, CSR read.
  std::vector<std::string> predicate_names() const override { return script_->predicate_names; }
  void reset(const model::Model& model, sim::Data& data) override;
  void drive(const model::Model& model, sim::Data& data) override;
  void drive_between(const model::Model& model, sim::Data& data, int step, int steps) override;
  void observe(const model::Model& model, const sim::Data& data,
               std::vector<uint8_t>& predicates, std::vector<Event>& events) override;

  std::shared_ptr<const script::EpisodeSpec> episode() const override { return script_->spec; }
  std::unique_ptr<ScenarioDriver> clone() const override {
    return std::make_unique<ScriptDriver>(*this);
  }

  const script::ActGraph& graph() const { return script_->graph; }
  const script::RuntimeState& runtime() const { return runtime_; }

 private:
  struct ActMotion {
    std::optional<human::MotionPlan> plan;  // a primitive's plan, or
    std::optional<human::Clip> clip;        // an imported clip, placed where the body stood
    human::Signals signals;
    human::MotionPlan::Knots knots;  // the plan's leans solved at its knots (only saves work)
    size_t phase = 0;  // runtime phase index last seen
    double start = 0;  // s, act start
    bool started = false;
    std::array<bool, 2> moves{};  // the plan moves the left / right hand
    bool moves_root = false;      // the plan walks or moves the stand frame

    bool playing() const { return plan || clip; }
    // At act time t: the pose, the labels and the key (a clip's: no holds, no swivel); the end.
    human::MotionPlan::Frame frame_at(double t) {
      return plan ? plan->frame_at(t, signals, &knots) : human::MotionPlan::Frame{clip->pose_at(t), {}, {}};
    }
    // frame_at's labels alone.
    human::FrameLabel label_at(double t) const { return plan ? plan->label_at(t, signals) : human::FrameLabel{}; }
    double end_time() const { return plan ? plan->end_time(signals) : clip->duration(); }
  };
  struct EventInfo {
    EventKind kind = EventKind::kWarning;
    Actor actor = Actor::kNone;
    std::string name, detail;
    std::string cue_kind;  // non-empty: also a kCue event
  };

  // Each hand's labels at one instant, from the act whose plan moves it (its owner).
  struct Holds {
    std::array<human::FrameLabel, 2> labels;
    std::array<int, 2> owner{};  // act whose plan moves each hand
    // What hand h holds by its owner's labels.
    const std::string& holding(size_t h) const { return labels[h].hands[h].holding; }
    bool same_as(const Holds& other) const {
      return owner == other.owner && holding(0) == other.holding(0) && holding(1) == other.holding(1);
    }
  };
  // The person at time t: the body from the active act's plan, each hand from the latest
  // started act that moves it (hand_owners), the root and legs from a walk still running; none
  // while no act poses the body.
  struct Posed {
    human::SkeletonPose pose;
    Holds holds;
  };
  std::optional<Posed> pose_at(const model::Model& model, double t);
  // What pose_at reads besides the time and the started plans (fixed once made), as counts
  // that any change between two control steps changes: the act posing the body, the phase
  // signals that arrived (they only ever arrive), and the acts' progress (waiting 0, running 1,
  // done or skipped 2: an act's status only ever moves on, and a plan starts with its act).
  struct PlanInputs {
    int active = -1;
    size_t signals = 0;
    size_t progress = 0;
    bool operator==(const PlanInputs&) const = default;
  };
  PlanInputs plan_inputs() const;
  // The acts whose plans move each hand: the latest started that moves it, else the body's.
  std::array<int, 2> hand_owners() const;
  // pose_at's holds without the pose.
  std::optional<Holds> holds_at(const model::Model& model, double t) const;
  // Grasps and releases what each hand's owning plan says it holds.
  void hold_as_labelled(const model::Model& model, sim::Data& data, const Holds& holds);
  void fill_world(const model::Model& model, const sim::Data& data);
  void start_plan(const model::Model& model, const sim::Data& data, size_t act);
  void start_clip(const model::Model& model, const sim::Data& data, size_t act);
  void update_signals(size_t act);

  // The model: fixed for the episode, shared by copies.
  struct Script {
    std::shared_ptr<const script::EpisodeSpec> spec;
    script::ActGraph graph;
    std::vector<EventInfo> event_info;       // per event id
    std::vector<std::string> predicate_names;
  };
  static std::shared_ptr<const Script> compile(std::shared_ptr<const script::EpisodeSpec> spec);
  std::shared_ptr<const Script> script_;
  // The data: the scenario's state (copied with the driver).
  script::RuntimeState runtime_;
  script::WorldSnapshot world_;
  std::vector<int> object_of_graph_;        // graph object -> model object index, -1: platform
  std::vector<int> platform_of_graph_;      // graph object -> model platform index, -1: object
  std::vector<ActMotion> motions_;          // per act
  int active_ = -1;                         // act whose plan poses the body, -1 none
  std::array<std::string, 2> last_holding_; // label of each hand at the last physics step
  std::array<int, 2> holding_plan_ = {-1, -1};  // act whose labels last_holding_[h] came from
  size_t events_seen_ = 0;
  core::Vec3 p_WT_home_ = core::Vec3::Zero();
  // drive_between: the person at the current control step's start and end, the time of its
  // end, and what the end's pose was made from.
  std::optional<Posed> control_step_start_;
  std::optional<Posed> control_step_end_;
  double control_step_end_time_ = 0;
  PlanInputs plan_inputs_;
};

}  // namespace hribench::eval

#pragma once
// The validation filters of the generation pipeline (issue 7): each sampled candidate episode
// runs them in this order, and the first one that fails rejects it with a one-line reason.
//
//   ordering     the act graph compiles, and the drawn timings keep the script's order: every
//                time-scheduled human act ends, and every cue window, robot `within` window
//                and sync target falls, inside the horizon; `after` comes before `before`;
//   scene        the model can build the sampled scene (objects on the table, no overlaps);
//   success      success predicates present and evaluable on the start state (they may
//                already hold: in stand-down variants doing nothing is the success);
//   reachable    every place a robot goal names (objects to grasp, containers and surfaces to
//                place on, objects to approach) has a top-down TCP pose the Panda reaches by
//                differential IK with every joint kReachJointMargin inside its limits;
//   penetration  the human's planned motions (see PlannedAct) keep every body capsule out of
//                the table and of every object the human does not carry, by more than kPenetrationTolerance (against the table:
//                forearms by more than their radius, i.e. the bones stay out, and hands by
//                more than kHandTableTolerance; hands never collide with objects in the model,
//                so they are not checked against them);
//   labels       labelled joints satisfy their constraint on the planned motion: the pointing
//                ray passes within kCueRegionRadius of the target (and nearer to it than to any
//                other object), a hand stays inside its zone slower than kLabelStillSpeed, an
//                intruding hand enters the workspace box kWorkspace;
//   visibility   in `agentview` (robot at home, objects at their start, the human in the middle
//                of each cue's phase) the cue hand (its palm, wrist or index tip; the other
//                hand and what the hands hold count as the hand) and every key object (named
//                by robot goals or success; not those that start inside a container) project
//                inside the image and are not occluded (mj_ray); and at the resolution policies
//                see (kCueImageSize px square) each key object is at least kMinKeyObjectPixels
//                across, the cue hand kMinCueHandPixels, and a pointed target's centre is
//                kMinPointedSeparationPixels from every other object's;
//   executable   the reference policy (default "oracle"; "none" skips the filter) succeeds in
//                a full episode (eval::run_episode with eval::ScriptDriver; success = CSR);
//   at_rest      the person never touches a robot at rest: in a full episode of the `noop`
//                policy (the robot held at its home pose) the log has no robot contact with
//                the person, of any force (issue 16; a full rollout, so it runs last, and is
//                skipped with the executable filter when executable_by is "none").
//
// Frames and units: world frame W (model/model.h), metres, seconds, radians.

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "human/labels.h"
#include "human/motion.h"
#include "model/model.h"
#include "script/scenario.h"
#include "sim/data.h"

namespace hribench::gen {

enum class Filter { kOrdering, kScene, kSuccess, kReachable, kPenetration, kLabels, kVisibility,
                    kExecutable, kAtRest };
inline constexpr size_t kNumFilters = 9;
// All filters in pipeline order.
inline constexpr std::array<Filter, kNumFilters> kFilters = {
    Filter::kOrdering,    Filter::kScene,  Filter::kSuccess,    Filter::kReachable, Filter::kPenetration,
    Filter::kLabels,      Filter::kVisibility, Filter::kExecutable, Filter::kAtRest};
std::string_view to_string(Filter filter);  // "ordering", "scene", ...
// Parses a filter name; nullopt for anything else.
std::optional<Filter> filter_from_name(std::string_view name);

// Constants of the filters (written into the generation report).
inline constexpr double kReachJointMargin = 0.05;      // rad inside each joint limit
inline constexpr double kReachPositionTolerance = 0.01;  // m, IK position error
inline constexpr double kReachRotationTolerance = 0.05;  // rad, IK rotation error
inline constexpr double kPlaceClearance = 0.10;        // m above a container's top to place
inline constexpr double kPenetrationTolerance = 0.02;  // m of human-table/object overlap allowed
// The passive hand of a person leaning over the table hangs into its far edge (the human
// layer's motions, up to ~6.5 cm); the model never collides hands with the table.
inline constexpr double kHandTableTolerance = 0.08;  // m
inline constexpr double kPlanFps = 10;                 // frames/s of the planned human motion
inline constexpr double kCueRegionRadius = 0.08;       // m, pointing ray to the target's centre
inline constexpr double kLabelStillSpeed = 0.2;        // m/s (tremor up to 2 mm at 8-12 Hz)
inline constexpr double kImageMargin = 0.95;           // fraction of the half field of view
// The cue judged at the resolution policies see (issue 16): agentview at kCueImageSize px
// square. What a cue needs to be read there (docs/generation.md): the cue hand and each key
// object at least so many pixels across (the smaller side of the rectangle holding their
// projection), and a pointed target's projected centre this far from every other object's.
inline constexpr int kCueImageSize = 224;                  // px
inline constexpr double kMinCueHandPixels = 7;             // px
inline constexpr double kMinKeyObjectPixels = 5;           // px
inline constexpr double kMinPointedSeparationPixels = 12;  // px
// The shared workspace: the middle of the table, up to 0.5 m above it.
inline const human::Box kWorkspace{core::Vec3(0.15, -0.45, model::kTableTopZ),
                                   core::Vec3(0.85, 0.45, model::kTableTopZ + 0.5)};

// What a filter decided.
struct FilterOutcome {
  bool ok = true;
  std::string reason;  // empty when ok; one line otherwise
  static FilterOutcome Pass() { return {}; }
  static FilterOutcome Fail(std::string why) { return {false, std::move(why)}; }
};

// The motion planned for one human act with a primitive (acts in spec order, each from the
// last pose of the one before, `fails` acts excepted; waiting phases at their minimum
// duration), sampled at kPlanFps.
struct PlannedAct {
  size_t act = 0;  // index in spec.acts
  human::LabelledClip clip;
  std::optional<human::Side> active_hand;
  human::PrimitiveParams params;
};

// A built candidate: the spec, its model (robot at home, objects at their start), a Data, and
// the human motions. Build with make_candidate_scene (throws core::InputError when the model
// cannot be built: the `scene` filter turns that into a rejection).
struct CandidateScene {
  const script::EpisodeSpec* spec = nullptr;  // not owned; outlives the scene
  model::Model model;
  sim::Data data;
  std::vector<PlannedAct> plans;  // human acts with a primitive motion, in spec order
};
CandidateScene make_candidate_scene(const script::EpisodeSpec& spec);

// The filters, one function each. Each returns Fail(reason) instead of throwing for problems
// of the candidate.
FilterOutcome check_ordering(const script::EpisodeSpec& spec);
FilterOutcome check_success(CandidateScene& scene);
FilterOutcome check_reachable(CandidateScene& scene);
FilterOutcome check_penetration(CandidateScene& scene);
FilterOutcome check_labels(const CandidateScene& scene);
FilterOutcome check_visibility(CandidateScene& scene);
// `policy` is a policy reference (policy/registry.h); "none" passes without running.
FilterOutcome check_executable(const script::EpisodeSpec& spec, const std::string& policy);
// The policy whose episode the at_rest filter runs: the robot held at its home pose.
inline constexpr std::string_view kAtRestPolicy = "noop";
// Fails with the first contact of the person with the robot in a kAtRestPolicy episode (act
// and phase under way, robot part, body capsule, time, force, and the episode's peak force),
// or when that episode does not end ok.
FilterOutcome check_at_rest(const script::EpisodeSpec& spec);

struct FilterOptions {
  std::string executable_by = "oracle";  // policy reference, or "none": no rollout (nor at_rest)
};

// The verdict on one candidate: the first failing filter (nullopt: validated) and why.
struct Verdict {
  std::optional<Filter> failed;
  std::string reason;
  bool ok() const { return !failed.has_value(); }
};
// Runs every filter in order and stops at the first failure.
Verdict validate_candidate(const script::EpisodeSpec& spec, const FilterOptions& options);

}  // namespace hribench::gen

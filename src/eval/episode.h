#pragma once
// The episode as an object the caller steps (docs/episode.md): one compiled episode model
// (MuJoCo model, the scenario's act graph, everything fixed per episode) plus its data (the
// physics state, the scenario runtime, the log so far), with reset / observe / step / log /
// metrics, observers called at every control step, and a snapshot that continues
// identically. The runner (eval/runner.h), `hribench render --at` and anything else that runs
// an episode are loops over it; the log is written through it, never by a second loop.
//
// Control at 1 / control_dt (20 Hz), physics at 200 Hz (model::kTimestep). Step k of the log
// describes the world at time k * control_dt; a step executes one action (or holds the last
// command) over one control interval. The episode ends at the horizon, once "success" has held
// for MetricConstants::success_hold (stop_on_success), on a MuJoCo warning (status invalid),
// or when the caller ends it (end(), e.g. a policy error).
//
// Same spec + same actions => the same log, bit for bit, whoever steps it.
//
// What a scenario adds to the bare simulation (the human's motion, events, predicate truths)
// comes from a ScenarioDriver; a task episode's is a ScriptDriver (eval/script_driver.h).

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "eval/constants.h"
#include "eval/contract.h"
#include "eval/episode_log.h"
#include "eval/metrics.h"
#include "model/model.h"
#include "policy/policy.h"
#include "render/gl_context.h"
#include "render/renderer.h"
#include "script/scenario.h"
#include "sim/data.h"
#include "sim/separation.h"

namespace hribench::eval {

enum class LatencyMode { kNone, kFixed, kMeasured };

struct Latency {
  LatencyMode mode = LatencyMode::kNone;
  double fixed_seconds = 0;  // kFixed only, >= 0
};

class ScenarioDriver {
 public:
  virtual ~ScenarioDriver() = default;
  // Names of the predicate series this driver reports (the contract's "success" among them).
  virtual std::vector<std::string> predicate_names() const = 0;
  // Called after sim::reset at the start of an episode.
  virtual void reset(const model::Model& model, sim::Data& data) = 0;
  // Under RunOptions::person_pose_per_physics_step, before every physics step: pose the human
  // for data.time() (sim::set_human_pose).
  virtual void drive(const model::Model& model, sim::Data& data) = 0;
  // As released, instead of drive: before physics step `step` (0-based) of the `steps` of a
  // control step. A driver that poses only by drive poses as drive does.
  virtual void drive_between(const model::Model& model, sim::Data& data, int /*step*/, int /*steps*/) {
    drive(model, data);
  }
  // After every control step (derived quantities current): the truth of each predicate series
  // (aligned with predicate_names) and the events that happened since the last call
  // (appended to `events`, times <= data.time()).
  virtual void observe(const model::Model& model, const sim::Data& data,
                       std::vector<uint8_t>& predicates, std::vector<Event>& events) = 0;
  // The sampled episode behind this driver, for privileged policies (null: none).
  virtual std::shared_ptr<const script::EpisodeSpec> episode() const { return nullptr; }
  // A copy of the driver's whole state (an Episode's snapshot); null: this driver cannot be
  // copied, and neither can an episode it drives.
  virtual std::unique_ptr<ScenarioDriver> clone() const { return nullptr; }
};

// No script: the human (if any) stands at its start pose; one series, "success", never true.
class StandingHumanDriver : public ScenarioDriver {
 public:
  std::vector<std::string> predicate_names() const override { return {"success"}; }
  void reset(const model::Model&, sim::Data&) override {}
  void drive(const model::Model&, sim::Data&) override {}
  void observe(const model::Model&, const sim::Data&, std::vector<uint8_t>& predicates,
               std::vector<Event>&) override {
    predicates.assign(1, 0);
  }
  std::unique_ptr<ScenarioDriver> clone() const override {
    return std::make_unique<StandingHumanDriver>(*this);
  }
};

// Identity of the episode, copied into the log and EpisodeInfo.
struct EpisodeSetup {
  std::string task;
  std::string role;
  std::string spec_hash;
  uint64_t seed = 0;
  std::string instruction;
  std::string policy;  // the policy reference, e.g. "noop"
};
// The setup of a sampled episode (its content hash, script::spec_hash) run by `policy`.
EpisodeSetup setup_of(const script::EpisodeSpec& spec, std::string policy);

struct RunOptions {
  double control_dt = 0.05;  // s; a whole number of physics steps
  double horizon = 30.0;     // s; <= 0 for an episode made from a spec: the script's horizon
  Latency latency;           // the runner's (eval/runner.h); an Episode itself never waits
  bool stop_on_success = true;  // end once "success" has held for constants.success_hold
  MetricConstants constants;
  // GL back end for the cameras a policy asks for (one renderer per requested camera, made for
  // this episode's model). kNone refuses camera-asking policies.
  render::Backend render_backend = render::Backend::kOsmesa;
  // After each control step the new state is observed with MuJoCo's kinematics alone
  // (sim::observe_state, as released since pool v7), which leaves the warm start and bias forces
  // of the next physics step to the physics steps; true: with MuJoCo's full forward pass
  // (sim::forward, pools up to v6), the physics candidate observe-forward of `hribench bench
  // --episodes` (docs/performance.md, "Physics").
  bool forward_after_control_step = false;
  // The person's pose is made from the plans once per control step, at its start and its end
  // (the last one's end where nothing changed between), and every physics step between poses
  // the joints interpolated (slerp) from one to the other; holds change at the physics step the
  // labels say (ScenarioDriver::drive_between), as released since pool v8. true: a pose made
  // for every physics step (ScenarioDriver::drive, pools up to v7), the physics candidate
  // person-per-physics-step of `hribench bench --episodes` (docs/performance.md).
  bool person_pose_per_physics_step = false;
};

// What one step of an Episode returns.
struct StepResult {
  policy::Observation observation;  // of the state after the step
  bool done = false;                // the episode has ended (step no more; reset() restarts)
  core::EpisodeStatus status = core::EpisodeStatus::kOk;
  std::string info;  // why it ended: "horizon", "success held", the status reason; else ""
};

class Episode;

// Called by an Episode as it runs (non-owning; the observer outlives the episode's run):
// on_start after reset() has recorded step 0's identity (the log header, no steps yet),
// on_step for every StepRecord as it is appended to the log (step 0 included; the events up to
// it are already in episode.log().events), on_end once the episode is done (status final);
// on_physics_step right before each physics step's mj_step, with every input of that step in
// episode.data().mj (sim::prepare_step: ctrl, mocap poses, applied forces), which is what
// `hribench bench --episodes` records to replay the episode on mj_step alone.
class EpisodeObserver {
 public:
  virtual ~EpisodeObserver() = default;
  virtual void on_start(const Episode&) {}
  virtual void on_physics_step(const Episode&) {}
  virtual void on_step(const Episode&, const StepRecord&) {}
  virtual void on_end(const Episode&) {}
};

// Writes the episode's log to `path` when the episode ends (save_episode_log: a temporary file
// renamed over `path`). Throws core::InputError from on_end if it cannot be written.
class LogFileWriter : public EpisodeObserver {
 public:
  explicit LogFileWriter(std::filesystem::path path) : path_(std::move(path)) {}
  void on_end(const Episode& episode) override;

 private:
  std::filesystem::path path_;
};

class EpisodeSnapshot;

// What every episode of one sampled spec shares, whichever policy runs it (docs/episode.md
// "Scenes"): the spec, its scene's model, the script driver as compiled (each episode runs a
// copy), the contract, one Data (the state buffers; every episode's reset() starts them afresh)
// and the camera renderers, one per back end and image size, made when first asked. An
// evaluation worker keeps the scene of the spec it is running (eval/run.h), so the next
// policy's episode of that spec builds nothing. Used by one episode at a time, on the thread
// that made its renderers (their GL context is that thread's). Throws core::InputError when
// the scene cannot be built or the script does not compile.
class EpisodeScene {
 public:
  // `model`: built from the spec's scene (scene_spec_from_episode), e.g. with shadows for a
  // picture; null: built here.
  explicit EpisodeScene(script::EpisodeSpec spec, std::shared_ptr<const model::Model> model = nullptr);
  EpisodeScene(const EpisodeScene&) = delete;
  EpisodeScene& operator=(const EpisodeScene&) = delete;
  ~EpisodeScene();

  const script::EpisodeSpec& spec() const { return *spec_; }
  // The renderer of width x height images on `backend` for this scene's model (made once).
  render::Renderer& renderer(render::Backend backend, int width, int height);

 private:
  friend class Episode;
  std::shared_ptr<const script::EpisodeSpec> spec_;
  std::shared_ptr<const model::Model> model_;
  std::unique_ptr<ScenarioDriver> driver_;  // compiled, never run: episodes run a clone
  std::shared_ptr<const ScenarioContract> contract_;
  sim::Data data_;
  std::vector<std::unique_ptr<render::Renderer>> renderers_;
};

class Episode {
 public:
  // A sampled task episode: builds its scene's model (scene_spec_from_episode) unless `model`
  // is given (built from that scene, e.g. with shadows for a picture), a Data and a
  // ScriptDriver; metrics() scores it against the episode's full contract. `policy` describes
  // what is observed (cameras, state and privileged tracks) and the action space; `setup`
  // names the episode in the log (setup_of(spec, "name")). options.horizon <= 0: the script's.
  // Throws core::InputError when the scene cannot be built or the script does not compile,
  // and for options it cannot honour (see below).
  Episode(script::EpisodeSpec spec, const policy::PolicySpec& policy, EpisodeSetup setup,
          RunOptions options, std::shared_ptr<const model::Model> model = nullptr);
  // An episode of `scene`'s spec, in the scene's Data with its renderers (borrowed: the scene
  // outlives the episode, and runs no other episode meanwhile). The same log as the episode
  // made from the spec, bit for bit, whatever episodes the scene ran before.
  Episode(EpisodeScene& scene, const policy::PolicySpec& policy, EpisodeSetup setup, RunOptions options);
  // Any model, Data and driver (borrowed: they outlive the episode; the data is the episode's
  // state). metrics() needs a spec: it throws core::InputError here.
  Episode(const model::Model& model, sim::Data& data, ScenarioDriver& driver,
          const policy::PolicySpec& policy, EpisodeSetup setup, RunOptions options);
  // A copy continues exactly as the original would (it owns a copy of the data and driver,
  // shares the model); observers are not copied. Needs a driver that clones.
  Episode(const Episode& other);
  Episode& operator=(const Episode&) = delete;
  ~Episode();

  // Starts the episode from sim::reset: records step 0. Observers' on_start, on_step(step 0).
  void reset();
  // The observation of the current state (the latest step): proprioception always, camera
  // images (rendered now) for the cameras the policy asked for, the state track and the
  // privileged track (events so far) when asked.
  policy::Observation observe();
  // Executes one action for one control step (then the observation after it). Throws
  // core::InputError for an action of the wrong size, non-finite or outside the limits
  // (expected and got named), and when the episode is done or not reset.
  StepResult step(const policy::Action& action);
  // Executes the chunk's actions, one per control step, until it is exhausted or the episode
  // ends. Throws core::InputError for a chunk of another action space or a bad action.
  StepResult step(const policy::ActionChunk& chunk);
  // One control step with the previous command held (the servo targets stay).
  StepResult hold();
  // The runner's form of step / hold: one control step without building an observation
  // (action null: hold). The action must already be valid. Returns done().
  bool advance(const policy::Action* action);
  // Ends the episode with `status` (e.g. kPolicyError when the policy failed) and `reason`.
  void end(core::EpisodeStatus status, std::string reason);

  bool done() const { return done_; }
  const EpisodeLog& log() const { return log_; }
  // Metrics of the log so far (eval/metrics.h) against the episode's contract.
  EpisodeMetrics metrics() const;
  // What a policy may know before its first observation (its reset).
  // The bounds an action must respect: the robot's (policy::action_limits(model().robot)).
  policy::ActionLimits action_limits() const;
  policy::EpisodeInfo info() const;
  const policy::PolicySpec& policy_spec() const { return policy_; }
  const EpisodeSetup& setup() const { return setup_; }
  const RunOptions& options() const { return options_; }
  const model::Model& model() const { return *model_; }
  const sim::Data& data() const { return *data_; }
  // The sampled spec (null for an episode of a bare driver).
  const std::shared_ptr<const script::EpisodeSpec>& spec() const { return spec_; }
  // The contract the metrics score against (null for an episode of a bare driver).
  const ScenarioContract* contract() const { return contract_.get(); }

  // Observers, called in the order added (non-owning).
  void add_observer(EpisodeObserver& observer);
  void remove_observer(EpisodeObserver& observer);

  // A copy of the episode's whole state (physics, scenario runtime, log), and its restoration:
  // the episode then continues exactly as it would have from the snapshot's moment. restore
  // throws core::InputError when the snapshot is of an episode of another spec (expected and
  // got spec hash). Observers are not part of the state (none is called by restore).
  EpisodeSnapshot snapshot() const;
  void restore(const EpisodeSnapshot& snapshot);

 private:
  struct Scratch;
  Episode(std::unique_ptr<EpisodeScene> scene, const policy::PolicySpec& policy, EpisodeSetup setup,
          RunOptions options);
  void init();
  void record(const policy::Action* action);
  void finish(core::EpisodeStatus status, std::string reason);
  StepResult result();
  void check_running(std::string_view what) const;
  void check_action(const policy::Action& action, std::string_view where) const;

  // Model (fixed for the episode).
  std::shared_ptr<const script::EpisodeSpec> spec_;
  std::shared_ptr<const model::Model> own_model_;
  const model::Model* model_ = nullptr;
  std::shared_ptr<const ScenarioContract> contract_;  // task episodes
  policy::PolicySpec policy_;
  EpisodeSetup setup_;
  RunOptions options_;
  int substeps_ = 0;    // physics steps per control step
  int max_steps_ = 0;   // control steps to the horizon
  sim::SeparationMonitor monitor_;
  std::unique_ptr<Scratch> scratch_;  // cameras (renderers for this model), contact scratch
  std::unique_ptr<EpisodeScene> own_scene_;  // an episode made from a spec
  EpisodeScene* scene_ = nullptr;            // its scene (own or borrowed); null for a copy
  // Data (the state).
  std::unique_ptr<sim::Data> own_data_;
  sim::Data* data_ = nullptr;
  std::unique_ptr<ScenarioDriver> own_driver_;
  ScenarioDriver* driver_ = nullptr;
  EpisodeLog log_;
  int steps_ = 0;                         // control steps taken since reset
  bool started_ = false;                  // reset() was called
  bool done_ = false;
  std::string end_info_;                  // StepResult::info once done
  std::optional<double> success_since_;   // start of the current run of "success" steps
  std::vector<EpisodeObserver*> observers_;
};

// A copy of an Episode's state (Episode::snapshot); copyable, independent of the episode.
class EpisodeSnapshot {
 public:
  EpisodeSnapshot(const EpisodeSnapshot& other);
  EpisodeSnapshot(EpisodeSnapshot&&) noexcept;
  EpisodeSnapshot& operator=(EpisodeSnapshot) = delete;
  ~EpisodeSnapshot();
  const std::string& spec_hash() const { return spec_hash_; }
  double time() const;

 private:
  friend class Episode;
  EpisodeSnapshot() = default;
  std::string spec_hash_;
  const model::Model* model_ = nullptr;
  std::unique_ptr<sim::Data> data_;
  std::unique_ptr<ScenarioDriver> driver_;
  EpisodeLog log_;
  int steps_ = 0;
  bool started_ = false;
  bool done_ = false;
  std::string end_info_;
  std::optional<double> success_since_;
};

// Poses `data` (made for `model`, the model of the logged episode) as the log's step `s`:
// robot joints and fingers, object poses and lids, the human's skeleton pose, the time; then
// sim::forward. A frame rendered from it equals the live render at that step.
void pose_from_step(const model::Model& model, const EpisodeLog& log, const StepRecord& s,
                    sim::Data& data);

}  // namespace hribench::eval

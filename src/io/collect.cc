#include "io/collect.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <fstream>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <thread>
#include <utility>

#include <fmt/format.h>
#include <mujoco/mujoco.h>
#include <nlohmann/json.hpp>

#include "core/errors.h"
#include "core/files.h"
#include "eval/metrics.h"
#include "eval/parallel.h"
#include "eval/runner.h"
#include "eval/script_driver.h"
#include "gen/evaluation.h"
#include "gen/pool.h"
#include "io/hdf5.h"
#include "io/lerobot.h"
#include "policy/registry.h"
#include "script/sample.h"
#include "sim/control.h"

namespace hribench::io {

namespace fs = std::filesystem;

std::vector<std::string> dataset_format_names() { return {"lerobot", "lerobot-v3", "act-hdf5", "robomimic"}; }

std::unique_ptr<DatasetWriter> make_dataset_writer(std::string_view format, const fs::path& dir) {
  if (format == "lerobot") return make_lerobot_writer(dir, LeRobotVersion::kV21);
  if (format == "lerobot-v3") return make_lerobot_writer(dir, LeRobotVersion::kV30);
  if (format == "act-hdf5") return std::make_unique<ActWriter>(dir);
  if (format == "robomimic") return std::make_unique<RobomimicWriter>(dir);
  std::string names;
  for (const std::string& name : dataset_format_names()) names += (names.empty() ? "" : ", ") + name;
  throw core::InputError("--format", "one of " + names, "'" + std::string(format) + "'");
}

std::vector<std::string> state_names(const model::Robot& robot) {
  std::vector<std::string> names;
  for (const model::ArmJoint& joint : robot.joints) names.push_back("joint_pos." + joint.name);
  for (const model::ArmJoint& joint : robot.joints) names.push_back("joint_vel." + joint.name);
  names.insert(names.end(), {"gripper.opening", "gripper.opening_rate", "tcp_pos.x", "tcp_pos.y", "tcp_pos.z",
                             "tcp_quat.w", "tcp_quat.x", "tcp_quat.y", "tcp_quat.z"});
  return names;
}

std::vector<std::string> action_names(policy::ActionSpace space, const model::Robot& robot) {
  std::vector<std::string> names;
  if (space == policy::ActionSpace::kEeDelta) {
    names = {"ee_delta.dx", "ee_delta.dy", "ee_delta.dz", "ee_delta.drx", "ee_delta.dry", "ee_delta.drz"};
  } else {
    for (const model::ArmJoint& joint : robot.joints) names.push_back("joint_target." + joint.name);
  }
  names.push_back("gripper.opening");
  return names;
}

namespace {

// The bounds validate_chunk holds value j of an action of `dim` values to (policy/policy.h's
// action spaces): the gripper last, in [0, 1].
std::pair<double, double> value_bounds(policy::ActionSpace space, size_t j, size_t dim,
                                       const policy::ActionLimits& limits) {
  if (j + 1 == dim) return {0.0, 1.0};
  if (space == policy::ActionSpace::kJointPos) return {limits.q_min[j], limits.q_max[j]};
  const double bound = j < 3 ? limits.max_ee_translation : limits.max_ee_rotation;
  return {-bound, bound};
}

}  // namespace

std::vector<float> float32_action(const policy::Action& action, policy::ActionSpace space,
                                  const policy::ActionLimits& limits) {
  std::vector<float> out(action.size());
  const bool sized = action.size() == static_cast<size_t>(policy::action_dim(space, limits.q_min.size())) &&
                     (space == policy::ActionSpace::kEeDelta || !limits.q_min.empty());
  for (size_t j = 0; j < action.size(); ++j) {
    const double d = action[j];
    float f = static_cast<float>(d);
    if (sized && std::isfinite(d)) {
      const auto [lo, hi] = value_bounds(space, j, action.size(), limits);
      if (static_cast<double>(f) > hi && d <= hi) f = std::nextafter(f, -INFINITY);
      if (static_cast<double>(f) < lo && d >= lo) f = std::nextafter(f, INFINITY);
    }
    out[j] = f;
  }
  return out;
}

Float32Actions::Float32Actions(std::unique_ptr<policy::Policy> inner)
    : inner_(std::move(inner)), spec_(inner_->spec()) {}

void Float32Actions::reset(const policy::EpisodeInfo& info) {
  limits_ = policy::action_limits(model::robot_by_name(info.robot));
  inner_->reset(info);
}

policy::ActionChunk Float32Actions::act(const policy::Observation& observation) {
  policy::ActionChunk chunk = inner_->act(observation);
  for (policy::Action& action : chunk.actions) {
    const std::vector<float> rounded = float32_action(action, chunk.space, limits_);
    std::copy(rounded.begin(), rounded.end(), action.begin());
  }
  return chunk;
}

EpisodeHeader episode_header(const script::EpisodeSpec& spec, std::string task_id, const std::string& policy,
                             const model::Robot& robot, policy::ActionSpace action_space,
                             const std::vector<std::string>& cameras, int size, double control_dt) {
  EpisodeHeader h;
  h.task = spec.task;
  h.task_id = std::move(task_id);
  h.role = spec.role;
  h.instruction = spec.instruction;
  h.spec_hash = script::spec_hash(spec);
  h.seed = spec.seed;
  h.variant = spec.variant;
  h.policy = policy;
  h.robot = robot.name;
  h.fps = static_cast<int>(std::lround(1.0 / control_dt));
  h.state_names = state_names(robot);
  h.action_names = action_names(action_space, robot);
  h.action_space = std::string(policy::to_string(action_space));
  for (const std::string& camera : cameras) h.cameras.push_back({camera, size, size});
  const policy::ActionLimits limits = policy::action_limits(robot);
  for (size_t j = 0; j < h.action_names.size(); ++j) {
    const auto [lo, hi] = value_bounds(action_space, j, h.action_names.size(), limits);
    h.action_low.push_back(static_cast<float>(lo));
    h.action_high.push_back(static_cast<float>(hi));
  }
  h.max_frames = static_cast<int64_t>(std::floor(spec.horizon / control_dt + 1e-9)) + 1;
  return h;
}

// ---------------------------------------------------------------------------------------------
// FrameRecorder

FrameRecorder::FrameRecorder(const eval::Episode& episode, const EpisodeHeader& header, EpisodeSink& sink,
                             render::Backend backend)
    : header_(header),
      sink_(sink),
      space_(policy::action_space_from_string(header.action_space, "EpisodeHeader::action_space")),
      limits_(episode.action_limits()) {
  const mjModel& m = *episode.model().m();
  for (const CameraSpec& camera : header.cameras) {
    camera_ids_.push_back(render::camera_id(m, camera.name, "--cameras"));
    const auto same_size = std::find_if(renderers_.begin(), renderers_.end(), [&](const auto& r) {
      return r->width() == camera.width && r->height() == camera.height;
    });
    if (same_size == renderers_.end()) {
      renderers_.push_back(render::make_renderer(backend, m, camera.width, camera.height));
    }
  }
  images_.resize(header.cameras.size());
}

void FrameRecorder::add(Frame& frame) {
  try {
    sink_.add(frame);
  } catch (...) {
    sink_failed_ = true;
    throw;
  }
  ++frames_;
}

void FrameRecorder::on_step(const eval::Episode& episode, const eval::StepRecord& step) {
  const model::Model& model = episode.model();
  const double max_width = model.robot.gripper.max_width();
  // The pending frame's action is this step's (what was executed since it).
  if (has_pending_) {
    if (space_ == episode.policy_spec().action_space) {
      HRIB_CHECK(step.action.size() == pending_.action.size())
          << "collect runs without latency: every step after the first executes an action";
      for (size_t j = 0; j < step.action.size(); ++j) {
        pending_.action[j] = static_cast<float>(step.action[j]);
        HRIB_CHECK(static_cast<double>(pending_.action[j]) == step.action[j])
            << "an executed action that is not float32 (the policy runs in Float32Actions)";
      }
    } else {
      policy::Action targets(step.joint_target.begin(), step.joint_target.end());
      targets.push_back(step.gripper_target / max_width);
      pending_.action = float32_action(targets, space_, limits_);
    }
    add(pending_);
  }
  // This step's frame, but for its action.
  Frame& f = pending_;
  f.index = has_pending_ ? f.index + 1 : 0;
  f.time = step.time;
  f.state.clear();
  for (double q : step.joint_pos) f.state.push_back(static_cast<float>(q));
  for (double qd : step.joint_vel) f.state.push_back(static_cast<float>(qd));
  const mjData& d = *episode.data().mj;
  const double opening_rate = (d.qvel[model.finger_dof_adr[0]] + d.qvel[model.finger_dof_adr[1]]) / max_width;
  const core::Quat& q = step.X_WT.rotation;
  for (double v : {step.gripper_width / max_width, opening_rate, step.X_WT.translation.x(),
                   step.X_WT.translation.y(), step.X_WT.translation.z(), q.w(), q.x(), q.y(), q.z()}) {
    f.state.push_back(static_cast<float>(v));
  }
  f.action.assign(header_.action_names.size(), 0.0f);
  f.images.clear();
  for (size_t c = 0; c < camera_ids_.size(); ++c) {
    const CameraSpec& camera = header_.cameras[c];
    render::Image& image = images_[c];
    const auto renderer = std::find_if(renderers_.begin(), renderers_.end(), [&](const auto& r) {
      return r->width() == camera.width && r->height() == camera.height;
    });
    (*renderer)->render(model, episode.data(), camera_ids_[c], image);
    f.images.push_back(&image);
  }
  // Annotations: the running human acts and the cue and act events since the previous frame.
  f.events.clear();
  const std::vector<eval::Event>& events = episode.log().events;
  for (; events_seen_ < events.size(); ++events_seen_) {
    const eval::Event& e = events[events_seen_];
    const bool act = e.kind == eval::EventKind::kActStart || e.kind == eval::EventKind::kActEnd;
    if (!act && e.kind != eval::EventKind::kCue) continue;
    f.events.push_back(fmt::format("{}:{}{}", eval::to_string(e.kind), e.name, e.detail.empty() ? "" : "/" + e.detail));
    if (!act || e.actor != eval::Actor::kHuman) continue;
    const std::string name = e.name.substr(0, e.name.rfind('.'));
    const auto running = std::find(human_acts_.begin(), human_acts_.end(), name);
    if (e.kind == eval::EventKind::kActStart && running == human_acts_.end()) human_acts_.push_back(name);
    if (e.kind == eval::EventKind::kActEnd && running != human_acts_.end()) human_acts_.erase(running);
  }
  f.human_act.clear();
  for (const std::string& act : human_acts_) f.human_act += (f.human_act.empty() ? "" : "+") + act;
  const std::optional<size_t> success = episode.log().predicate_index("success");
  f.reward = success && *success < step.predicates.size() && step.predicates[*success] ? 1.0f : 0.0f;
  f.done = false;
  f.sim_state.assign(1, d.time);
  const mjModel& m = *model.m();
  f.sim_state.insert(f.sim_state.end(), d.qpos, d.qpos + m.nq);
  f.sim_state.insert(f.sim_state.end(), d.qvel, d.qvel + m.nv);
  has_pending_ = true;
}

void FrameRecorder::on_end(const eval::Episode& episode) {
  if (!has_pending_) return;
  // Nothing is executed after the last frame: the command in force, held.
  const eval::StepRecord& last = episode.log().steps.back();
  const double gripper = last.gripper_target / episode.model().robot.gripper.max_width();
  policy::Action hold;
  if (space_ == policy::ActionSpace::kJointPos) {
    hold.assign(last.joint_target.begin(), last.joint_target.end());
  } else {
    hold.assign(6, 0.0);
  }
  hold.push_back(gripper);
  pending_.action = float32_action(hold, space_, limits_);
  pending_.done = true;
  has_pending_ = false;
  add(pending_);
}

// ---------------------------------------------------------------------------------------------
// The collect

namespace {

// --dry-run: frames are made (rendered) and dropped.
class NullSink : public EpisodeSink {
 public:
  void add(const Frame&) override {}
};
class NullWriter : public DatasetWriter {
 public:
  std::unique_ptr<EpisodeSink> begin_episode(const EpisodeHeader&) override { return std::make_unique<NullSink>(); }
  void commit(std::unique_ptr<EpisodeSink>, const EpisodeOutcome&) override {}
  void discard(std::unique_ptr<EpisodeSink>) override {}
  void finish() override {}
  void resume(const std::vector<EpisodeHeader>&) override {}
};

struct Job {
  const script::EpisodeSpec* spec = nullptr;
  std::string task_id;
  std::string hash;
  std::string key;
};

// A finished episode, handed from its worker to the main thread.
struct Finished {
  EpisodeHeader header;
  std::unique_ptr<EpisodeSink> sink;
  EpisodeOutcome outcome;
  eval::EpisodeLog log;
  std::string write_error;  // the sink failed: the episode is discarded and the run stops
  std::string error;        // anything else that stops the run
};

nlohmann::json read_state(const fs::path& path) {
  std::ifstream in(path);
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception&) {
    throw core::InputError::Message(path.string(), "not valid JSON (a collect's state)");
  }
}

// The options of `recorded` that `asked` sets otherwise: "size: 224 in the dataset, 64 asked".
std::string option_differences(const nlohmann::json& recorded, const nlohmann::json& asked) {
  std::set<std::string> keys;
  for (const auto& [key, value] : recorded.items()) keys.insert(key);
  for (const auto& [key, value] : asked.items()) keys.insert(key);
  std::string list;
  for (const std::string& key : keys) {
    const std::string was = recorded.contains(key) ? recorded.at(key).dump() : "(not set)";
    const std::string now = asked.contains(key) ? asked.at(key).dump() : "(not set)";
    if (was != now) list += (list.empty() ? "" : "; ") + key + ": " + was + " in the dataset, " + now + " asked";
  }
  return list;
}

// Refuses a file, a folder holding anything but a collect, or another collect unless resumed
// with the same options or forced; returns the state to continue (options, no episodes when new).
nlohmann::json prepare_out(const CollectRequest& r, const nlohmann::json& options) {
  const fs::path dir = r.out;
  const fs::path state_file = collect_state_path(dir);
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec)) {
    throw core::InputError("--out", "a folder for the dataset", "'" + r.out + "', a file");
  }
  const bool ours = fs::exists(state_file, ec);
  if (!ours && fs::exists(dir, ec) && !fs::is_empty(dir, ec)) {
    throw core::InputError::Message(
        "--out", r.out + " holds files that are not a hribench collect (no hribench/collect.json), e.g. '" +
                     fs::directory_iterator(dir)->path().filename().string() + "'; choose an empty or new folder");
  }
  nlohmann::json state = {{"options", options}, {"episodes", nlohmann::json::array()}, {"finished", false}};
  if (ours && r.force) {
    for (const fs::directory_entry& entry : fs::directory_iterator(dir)) fs::remove_all(entry.path());
  } else if (ours && !r.resume) {
    throw core::InputError::Message(
        "--out", r.out + " already holds a dataset; use --resume to continue it or --force to replace it");
  } else if (ours) {
    nlohmann::json recorded = read_state(state_file);
    if (!recorded.contains("options") || !recorded.contains("episodes")) {
      throw core::InputError(state_file.string(), "a collect's state (options, episodes)", "other JSON");
    }
    if (recorded.at("options") != options) {
      throw core::InputError::Message(
          "--resume", r.out + " holds a dataset with other options (" +
                          option_differences(recorded.at("options"), options) + "); use --force to replace it");
    }
    state = std::move(recorded);
  }
  fs::create_directories(dir / "hribench" / "logs");
  core::write_file_atomically(state_file, state.dump(1) + "\n");
  return state;
}

nlohmann::json outcome_json(const Job& job, const EpisodeOutcome& outcome, std::optional<size_t> index) {
  nlohmann::json labels = nlohmann::json::array();
  for (const std::string& label : outcome.failure_labels) labels.push_back(label);
  return {{"key", job.key},
          {"task", job.spec->task},
          {"seed", job.spec->seed},
          {"spec_hash", job.hash},
          {"kept", index.has_value()},
          {"index", index ? nlohmann::json(*index) : nlohmann::json(nullptr)},
          {"success", outcome.success},
          {"status", std::string(core::to_string(outcome.status))},
          {"labels", labels},
          {"frames", outcome.frames}};
}

}  // namespace

fs::path collect_state_path(const fs::path& dir) { return dir / "hribench" / "collect.json"; }

fs::path collect_log_path(const fs::path& dir, const std::string& task, uint64_t seed, const std::string& spec_hash) {
  return dir / "hribench" / "logs" / fmt::format("{}__{}__{}.hlog", task, seed, spec_hash.substr(0, 12));
}

CollectSummary collect(const CollectRequest& r, const std::function<void(const CollectProgress&)>& progress,
                       const WriterMaker& make) {
  // Options first: nothing is written before they are all checked.
  if (r.resume && r.force) throw core::InputError::Message("--resume", "cannot be combined with --force");
  if (!r.dry_run) {
    if (r.out.empty()) throw core::InputError("--out", "an output folder", "none");
    const std::vector<std::string> formats = dataset_format_names();
    if (!make && std::find(formats.begin(), formats.end(), r.format) == formats.end()) {
      make_dataset_writer(r.format, r.out);  // throws: an unknown format
    }
  }
  if (r.keep != "success" && r.keep != "all") {
    throw core::InputError("--keep", "success or all", "'" + r.keep + "'");
  }
  if (r.threads <= 0) throw core::InputError("--threads", "a positive number", std::to_string(r.threads));
  if (r.episodes < 0) throw core::InputError("--episodes", "a number >= 0 (0: all)", std::to_string(r.episodes));
  render::check_image_size(r.size, r.size, "--size", "--size");
  const render::Backend backend = render::parse_backend(r.backend, "--backend");
  if (backend == render::Backend::kNone) {
    throw core::InputError("--backend", "osmesa or egl (the cameras are rendered)", "none");
  }
  const gen::Split split = gen::split_from_name(r.split, "--split");
  const policy::PolicySpec policy_spec = policy::make_policy(r.policy)->spec();
  const policy::ActionSpace space =
      r.action_space.empty() ? policy_spec.action_space : policy::action_space_from_string(r.action_space, "--action-space");
  if (space != policy_spec.action_space && space != policy::ActionSpace::kJointPos) {
    throw core::InputError("--action-space",
                           fmt::format("the policy's own ({}) or joint_pos (the servo targets)",
                                       policy::to_string(policy_spec.action_space)),
                           "'" + r.action_space + "'");
  }
  const std::vector<std::string> cameras = gen::split_list(r.cameras);
  if (cameras.empty()) throw core::InputError("--cameras", "camera names (comma-separated)", "'" + r.cameras + "'");
  for (size_t i = 0; i < cameras.size(); ++i) {
    if (std::find(cameras.begin(), cameras.begin() + static_cast<std::ptrdiff_t>(i), cameras[i]) !=
        cameras.begin() + static_cast<std::ptrdiff_t>(i)) {
      throw core::InputError("--cameras", "each camera once", "'" + cameras[i] + "' twice");
    }
  }
  const gen::Manifest manifest = gen::read_manifest(r.pool);
  const std::vector<std::string> task_names = r.tasks == "all" ? std::vector<std::string>{} : gen::split_list(r.tasks);
  std::vector<script::EpisodeSpec> all_specs = gen::pool_episodes(manifest, split, task_names);
  // The first N of each task.
  std::vector<script::EpisodeSpec> specs;
  std::map<std::string, int> per_task;
  std::vector<std::string> tasks;
  for (script::EpisodeSpec& spec : all_specs) {
    if (tasks.empty() || tasks.back() != spec.task) tasks.push_back(spec.task);
    if (r.episodes > 0 && per_task[spec.task]++ >= r.episodes) continue;
    specs.push_back(std::move(spec));
  }
  if (specs.empty()) {
    throw core::InputError("--tasks", "tasks of the pool", "'" + r.tasks + "' (no episodes in split " + r.split + ")");
  }
  // The cameras, against the robot's model (the first episode's scene).
  {
    const model::Model model = model::build(eval::scene_spec_from_episode(specs.front()));
    for (const std::string& camera : cameras) render::camera_id(*model.m(), camera, "--cameras");
  }
  const nlohmann::json options = {{"pool", r.pool},
                                  {"pool_version", manifest.pool_version},
                                  {"split", r.split},
                                  {"policy", r.policy},
                                  {"cameras", cameras},
                                  {"size", r.size},
                                  {"format", r.format},
                                  {"tasks", tasks},
                                  {"episodes", r.episodes},
                                  {"keep", r.keep},
                                  {"action_space", std::string(policy::to_string(space))}};

  // The folder, and what a resumed run already did.
  const fs::path dir = r.out;
  nlohmann::json state = r.dry_run ? nlohmann::json{{"episodes", nlohmann::json::array()}} : prepare_out(r, options);
  std::map<std::string, nlohmann::json> finished;
  for (const nlohmann::json& e : state.at("episodes")) finished.emplace(e.at("key").get<std::string>(), e);
  std::map<std::string, std::string> task_ids;
  for (const gen::TaskFile& task : gen::task_catalogue()) task_ids.emplace(task.name, task.id);
  const eval::RunOptions run_options = [&] {
    eval::RunOptions o;
    o.horizon = 0;  // each script's own
    o.render_backend = backend;
    return o;
  }();
  std::vector<Job> jobs;
  std::vector<size_t> todo;
  std::vector<EpisodeHeader> committed;
  size_t kept = 0;
  for (const script::EpisodeSpec& spec : specs) {
    Job job;
    job.spec = &spec;
    job.task_id = task_ids.count(spec.task) ? task_ids.at(spec.task) : "";
    job.hash = script::spec_hash(spec);
    job.key = eval::episode_key(spec.task, r.policy, job.hash, spec.seed);
    const auto done = finished.find(job.key);
    if (done == finished.end()) {
      todo.push_back(jobs.size());
    } else if (done->second.at("kept").get<bool>()) {
      const model::Robot& robot = model::robot_by_name(eval::scene_spec_from_episode(spec).robot);
      committed.push_back(episode_header(spec, job.task_id, r.policy, robot, space, cameras, r.size, run_options.control_dt));
      ++kept;
    }
    jobs.push_back(std::move(job));
  }
  CollectSummary summary;
  summary.episodes = jobs.size();
  summary.resumed = jobs.size() - todo.size();
  summary.kept = kept;
  if (todo.empty() && state.value("finished", false)) return summary;

  std::unique_ptr<DatasetWriter> writer = r.dry_run ? std::make_unique<NullWriter>()
                                          : make              ? make(dir)
                                                              : make_dataset_writer(r.format, dir);
  writer->resume(committed);

  // Workers run episodes; the main thread commits them in order.
  std::mutex mutex;
  std::condition_variable ready_cv;
  std::map<size_t, Finished> ready;  // by position in todo
  std::atomic<size_t> next{0};
  std::atomic<bool> stop{false};
  std::atomic<int64_t> frames{0};
  const auto run_job = [&](size_t position, std::unique_ptr<policy::Policy>& policy) {
    const Job& job = jobs[todo[position]];
    Finished f;
    try {
      if (!policy) policy = std::make_unique<Float32Actions>(policy::make_policy(r.policy));
      eval::Episode episode(*job.spec, policy->spec(), eval::setup_of(*job.spec, r.policy), run_options);
      f.header = episode_header(*job.spec, job.task_id, r.policy, episode.model().robot, space, cameras, r.size,
                                run_options.control_dt);
      try {
        f.sink = writer->begin_episode(f.header);
      } catch (const std::exception& e) {
        f.write_error = e.what();
        stop = true;
        return f;
      }
      FrameRecorder recorder(episode, f.header, *f.sink, backend);
      episode.add_observer(recorder);
      try {
        eval::run_episode(episode, *policy);
      } catch (const std::exception& e) {
        if (!recorder.sink_failed()) throw;
        f.write_error = e.what();
        stop = true;
        return f;
      }
      const eval::EpisodeMetrics metrics = episode.metrics();
      f.outcome.success = metrics.success;
      f.outcome.status = episode.log().status;
      for (eval::FailureLabel label : metrics.labels) f.outcome.failure_labels.emplace_back(eval::to_string(label));
      f.outcome.frames = recorder.frames();
      frames += recorder.frames();
      f.log = episode.log();
    } catch (const std::exception& e) {
      f.error = e.what();
      stop = true;
    }
    return f;
  };
  const auto start = std::chrono::steady_clock::now();
  std::vector<std::thread> workers;
  for (int w = 0; w < r.threads; ++w) {
    workers.emplace_back([&] {
      std::unique_ptr<policy::Policy> policy;
      while (!stop) {
        const size_t position = next++;
        if (position >= todo.size()) break;
        Finished f = run_job(position, policy);
        const std::lock_guard<std::mutex> lock(mutex);
        ready.emplace(position, std::move(f));
        ready_cv.notify_all();
      }
    });
  }
  // Commit in order; the first episode that failed stops the run after those before it.
  std::string failure;
  const auto save_state = [&] {
    if (!r.dry_run) core::write_file_atomically(collect_state_path(dir), state.dump(1) + "\n");
  };
  for (size_t position = 0; position < todo.size() && failure.empty(); ++position) {
    Finished f;
    {
      std::unique_lock<std::mutex> lock(mutex);
      ready_cv.wait(lock, [&] { return ready.count(position) > 0; });
      f = std::move(ready.at(position));
      ready.erase(position);
    }
    const Job& job = jobs[todo[position]];
    if (!f.write_error.empty() || !f.error.empty()) {
      if (f.sink) writer->discard(std::move(f.sink));
      failure = !f.write_error.empty()
                    ? fmt::format("cannot write episode {} ({} seed {}): {}; it is discarded", position + summary.resumed,
                                  job.spec->task, job.spec->seed, f.write_error)
                    : fmt::format("episode {} ({} seed {}): {}", position + summary.resumed, job.spec->task,
                                  job.spec->seed, f.error);
      break;
    }
    // An episode that ended before its first action (a policy that failed at once) shows nothing.
    const bool keep = f.outcome.frames >= 2 && (f.outcome.success || r.keep == "all");
    std::optional<size_t> index;
    try {
      if (keep) {
        writer->commit(std::move(f.sink), f.outcome);
        index = kept++;
        if (!r.dry_run) eval::save_episode_log(f.log, collect_log_path(dir, job.spec->task, job.spec->seed, job.hash));
      } else {
        writer->discard(std::move(f.sink));
      }
    } catch (const std::exception& e) {
      failure = fmt::format("cannot write episode {} ({} seed {}): {}", position + summary.resumed, job.spec->task,
                            job.spec->seed, e.what());
      stop = true;
      break;
    }
    state.at("episodes").push_back(outcome_json(job, f.outcome, index));
    save_state();
    if (progress) {
      const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      const double rate = elapsed > 0 ? static_cast<double>(position + 1) / elapsed : 0;
      progress({summary.resumed + position + 1, jobs.size(), summary.resumed, kept, frames.load(),
                elapsed > 0 ? static_cast<double>(frames.load()) / elapsed : 0,
                rate > 0 ? static_cast<double>(todo.size() - position - 1) / rate : 0});
    }
  }
  stop = stop || !failure.empty();
  for (std::thread& worker : workers) worker.join();
  for (auto& [position, f] : ready) {
    if (f.sink) writer->discard(std::move(f.sink));
  }
  writer->finish();
  summary.kept = kept;
  summary.frames = frames.load();
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!failure.empty()) {
    save_state();
    throw core::InputError::Message(
        r.dry_run ? "collect" : r.out,
        fmt::format("{}; the {} episodes before it are in the dataset; continue with --resume", failure, kept));
  }
  state["finished"] = true;
  save_state();
  return summary;
}

}  // namespace hribench::io

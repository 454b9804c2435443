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
#include "core/json.h"
#include "core/version.h"
#include "eval/metrics.h"
#include "eval/parallel.h"
#include "eval/ranks.h"
#include "eval/runner.h"
#include "eval/script_driver.h"
#include "eval/shard.h"
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
  void store(std::unique_ptr<EpisodeSink>, const fs::path&) override {}
  std::unique_ptr<EpisodeSink> load(const fs::path&) override { return std::make_unique<NullSink>(); }
};

struct Job {
  const script::EpisodeSpec* spec = nullptr;
  size_t number = 0;  // in the full job list (the split's episodes, in order): what --shard divides
  std::string task_id;
  std::string hash;
  std::string key;
};

// A finished episode, handed from its worker thread (or, under mpirun, from another rank's) to
// the thread that settles the episodes in order.
struct Finished {
  EpisodeHeader header;
  std::unique_ptr<EpisodeSink> sink;  // none when another rank ran it
  EpisodeOutcome outcome;
  eval::EpisodeLog log;
  bool stored = false;      // another rank stored it (a kept episode) with its log
  std::string write_error;  // the sink failed: the episode is discarded and the run stops
  std::string error;        // anything else that stops the run
};

// Whether a finished episode goes into the dataset. One that ended before its first action (a
// policy that failed at once) shows nothing.
bool is_kept(const EpisodeOutcome& outcome, const std::string& keep) {
  return outcome.frames >= 2 && (outcome.success || keep == "all");
}

// What another rank sends back for an episode (eval/ranks.h): its outcome, whether it stored it,
// and what stopped it.
std::string reply_of(const Finished& f) {
  return nlohmann::json{{"success", f.outcome.success},
                        {"status", std::string(core::to_string(f.outcome.status))},
                        {"labels", f.outcome.failure_labels},
                        {"frames", f.outcome.frames},
                        {"stored", f.stored},
                        {"write_error", f.write_error},
                        {"error", f.error}}
      .dump();
}

Finished finished_from_reply(std::string_view reply, const std::string& where) {
  const nlohmann::json json = core::parse_json(reply, where);
  Finished f;
  try {
    f.outcome.success = json.at("success").get<bool>();
    f.outcome.status = core::episode_status_from_string(json.at("status").get<std::string>(), where + ".status");
    f.outcome.failure_labels = json.at("labels").get<std::vector<std::string>>();
    f.outcome.frames = json.at("frames").get<int64_t>();
    f.stored = json.at("stored").get<bool>();
    f.write_error = json.at("write_error").get<std::string>();
    f.error = json.at("error").get<std::string>();
  } catch (const nlohmann::json::exception& e) {
    throw core::InputError(where, "an episode's reply (outcome, stored, errors)", e.what());
  }
  return f;
}

// Where a stored episode (DatasetWriter::store) of job `number` waits: in a shard until the
// merge, under mpirun until rank 0 commits it.
fs::path stored_episode_path(const fs::path& dir, size_t number) {
  return dir / "hribench" / "episodes" / fmt::format("{:06}", number);
}
// The scratch folder of the writer that records episodes to be stored, one per rank.
fs::path staging_path(const fs::path& dir, int rank) { return dir / "hribench" / "staging" / std::to_string(rank); }

// Stores `sink` as job `number`'s episode, atomically (a folder renamed into place).
void store_episode(DatasetWriter& writer, std::unique_ptr<EpisodeSink> sink, const fs::path& dir, size_t number) {
  const fs::path folder = stored_episode_path(dir, number);
  const fs::path temporary = folder.string() + ".tmp";
  fs::remove_all(temporary);
  fs::remove_all(folder);
  writer.store(std::move(sink), temporary);
  fs::rename(temporary, folder);
}

// Removes the scratch folders and the stored episodes but those of `keep` (job numbers): what a
// run that stopped left behind.
void remove_stored_but(const fs::path& dir, const std::set<size_t>& keep) {
  fs::remove_all(dir / "hribench" / "staging");
  const fs::path stored = dir / "hribench" / "episodes";
  if (!fs::is_directory(stored)) return;
  for (const fs::directory_entry& entry : fs::directory_iterator(stored)) {
    const std::string name = entry.path().filename().string();
    const bool number = !name.empty() && name.size() <= 18 && name.find_first_not_of("0123456789") == std::string::npos;
    if (!number || keep.count(std::stoull(name)) == 0) fs::remove_all(entry.path());
  }
}

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
  const std::optional<eval::Shard> shard =
      r.shard.empty() ? std::nullopt : std::optional<eval::Shard>(eval::parse_shard(r.shard, "--shard"));
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
  nlohmann::json options = {{"pool", r.pool},
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
  if (shard) {
    options["shard"] = eval::to_string(*shard);
    options["shard_of_jobs"] = specs.size();
    options["code"] = core::code_identity();
    options["backend"] = r.backend;
  }
  std::map<std::string, std::string> task_ids;
  for (const gen::TaskFile& task : gen::task_catalogue()) task_ids.emplace(task.name, task.id);
  const eval::RunOptions run_options = [&] {
    eval::RunOptions o;
    o.horizon = 0;  // each script's own
    o.render_backend = backend;
    return o;
  }();
  std::vector<Job> jobs;  // this shard's (all without --shard), in split order
  for (size_t number = 0; number < specs.size(); ++number) {
    if (shard && !shard->owns(number)) continue;
    const script::EpisodeSpec& spec = specs[number];
    Job job;
    job.spec = &spec;
    job.number = number;
    job.task_id = task_ids.count(spec.task) ? task_ids.at(spec.task) : "";
    job.hash = script::spec_hash(spec);
    job.key = eval::episode_key(spec.task, r.policy, job.hash, spec.seed);
    jobs.push_back(std::move(job));
  }
  const fs::path dir = r.out;
  const auto make_writer = [&](const fs::path& folder) -> std::unique_ptr<DatasetWriter> {
    if (r.dry_run) return std::make_unique<NullWriter>();
    return make ? make(folder) : make_dataset_writer(r.format, folder);
  };
  // A shard stores its kept episodes (hribench/episodes/) for `hribench merge`, and writes no
  // dataset files.
  const bool storing = shard.has_value() && !r.dry_run;

  // Runs job j on a worker thread with the worker's policy, recording into `recorder`.
  std::atomic<bool> stop{false};
  std::atomic<int64_t> frames{0};
  const auto run_job = [&](const Job& job, std::unique_ptr<policy::Policy>& policy, DatasetWriter& recorder) {
    Finished f;
    try {
      if (!policy) policy = std::make_unique<Float32Actions>(policy::make_policy(r.policy));
      eval::Episode episode(*job.spec, policy->spec(), eval::setup_of(*job.spec, r.policy), run_options);
      f.header = episode_header(*job.spec, job.task_id, r.policy, episode.model().robot, space, cameras, r.size,
                                run_options.control_dt);
      try {
        f.sink = recorder.begin_episode(f.header);
      } catch (const std::exception& e) {
        f.write_error = e.what();
        stop = true;
        return f;
      }
      FrameRecorder frame_recorder(episode, f.header, *f.sink, backend);
      episode.add_observer(frame_recorder);
      try {
        eval::run_episode(episode, *policy);
      } catch (const std::exception& e) {
        if (!frame_recorder.sink_failed()) throw;
        f.write_error = e.what();
        stop = true;
        return f;
      }
      const eval::EpisodeMetrics metrics = episode.metrics();
      f.outcome.success = metrics.success;
      f.outcome.status = episode.log().status;
      for (eval::FailureLabel label : metrics.labels) f.outcome.failure_labels.emplace_back(eval::to_string(label));
      f.outcome.frames = frame_recorder.frames();
      frames += frame_recorder.frames();
      f.log = episode.log();
    } catch (const std::exception& e) {
      f.error = e.what();
      stop = true;
    }
    return f;
  };

  // Under mpirun the ranks other than 0 only run the episodes rank 0 hands them (eval/ranks.h):
  // each kept one is stored, with its log, where rank 0 (or the merge of a shard) finds it.
  const eval::Ranks ranks = eval::mpi_ranks();
  if (ranks.distributed() && ranks.rank != 0) {
    const std::unique_ptr<DatasetWriter> recorder = make_writer(staging_path(dir, ranks.rank));
    std::vector<std::unique_ptr<policy::Policy>> policies(static_cast<size_t>(r.threads));
    eval::serve_jobs(r.threads, [&](size_t j, int worker) {
      Finished f = run_job(jobs.at(j), policies[static_cast<size_t>(worker)], *recorder);
      const Job& job = jobs[j];
      if (f.error.empty() && f.write_error.empty() && is_kept(f.outcome, r.keep) && !r.dry_run) {
        try {
          store_episode(*recorder, std::move(f.sink), dir, job.number);
          eval::save_episode_log(f.log, collect_log_path(dir, job.spec->task, job.spec->seed, job.hash));
          f.stored = true;
        } catch (const std::exception& e) {
          f.write_error = e.what();
        }
      }
      if (f.sink) recorder->discard(std::move(f.sink));
      return reply_of(f);
    });
    return CollectSummary{};
  }
  eval::ReleaseWorkersOnError release(r.threads);

  // The folder, and what a resumed run already did.
  nlohmann::json state = r.dry_run ? nlohmann::json{{"episodes", nlohmann::json::array()}} : prepare_out(r, options);
  std::map<std::string, nlohmann::json> finished;
  for (const nlohmann::json& e : state.at("episodes")) finished.emplace(e.at("key").get<std::string>(), e);
  std::vector<size_t> todo;  // into jobs
  std::vector<EpisodeHeader> committed;
  std::set<size_t> stored;   // a shard's kept episodes
  size_t kept = 0;
  for (size_t j = 0; j < jobs.size(); ++j) {
    const Job& job = jobs[j];
    const auto done = finished.find(job.key);
    if (done == finished.end()) {
      todo.push_back(j);
    } else if (done->second.at("kept").get<bool>()) {
      const model::Robot& robot = model::robot_by_name(eval::scene_spec_from_episode(*job.spec).robot);
      committed.push_back(
          episode_header(*job.spec, job.task_id, r.policy, robot, space, cameras, r.size, run_options.control_dt));
      stored.insert(job.number);
      ++kept;
    }
  }
  CollectSummary summary;
  summary.episodes = jobs.size();
  summary.resumed = jobs.size() - todo.size();
  summary.kept = kept;
  if (todo.empty() && state.value("finished", false)) return summary;
  if (!r.dry_run) remove_stored_but(dir, storing ? stored : std::set<size_t>{});

  // The dataset (none in a shard), and the writer worker threads record into: the dataset's, or
  // a scratch one whose episodes are stored.
  std::unique_ptr<DatasetWriter> dataset;
  if (!storing) {
    dataset = make_writer(dir);
    dataset->resume(committed);
  }
  const std::unique_ptr<DatasetWriter> scratch = storing ? make_writer(staging_path(dir, 0)) : nullptr;
  DatasetWriter& recorder = storing ? *scratch : *dataset;

  // Episodes are settled in split order: committed to the dataset (or stored) or discarded, and
  // recorded in the state. The first episode that failed stops the run after those before it.
  std::string failure;
  const auto save_state = [&] {
    if (!r.dry_run) core::write_file_atomically(collect_state_path(dir), state.dump(1) + "\n");
  };
  const auto start = std::chrono::steady_clock::now();
  const auto settle = [&](size_t position, Finished& f) {
    const Job& job = jobs[todo[position]];
    if (!f.write_error.empty() || !f.error.empty()) {
      if (f.sink) recorder.discard(std::move(f.sink));
      failure = !f.write_error.empty()
                    ? fmt::format("cannot write episode {} ({} seed {}): {}; it is discarded", position + summary.resumed,
                                  job.spec->task, job.spec->seed, f.write_error)
                    : fmt::format("episode {} ({} seed {}): {}", position + summary.resumed, job.spec->task,
                                  job.spec->seed, f.error);
      return;
    }
    std::optional<size_t> index;
    try {
      if (is_kept(f.outcome, r.keep)) {
        if (storing) {
          if (f.sink) store_episode(recorder, std::move(f.sink), dir, job.number);
        } else {
          dataset->commit(f.sink ? std::move(f.sink) : dataset->load(stored_episode_path(dir, job.number)), f.outcome);
        }
        index = kept++;
        if (!r.dry_run && !f.stored) {
          eval::save_episode_log(f.log, collect_log_path(dir, job.spec->task, job.spec->seed, job.hash));
        }
        if (f.stored && !storing) fs::remove_all(stored_episode_path(dir, job.number));  // committed
      } else if (f.sink) {
        recorder.discard(std::move(f.sink));
      }
    } catch (const std::exception& e) {
      failure = fmt::format("cannot write episode {} ({} seed {}): {}", position + summary.resumed, job.spec->task,
                            job.spec->seed, e.what());
      stop = true;
      return;
    }
    nlohmann::json entry = outcome_json(job, f.outcome, index);
    if (shard) entry["job"] = job.number;
    state.at("episodes").push_back(std::move(entry));
    save_state();
    if (progress) {
      const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      const double rate = elapsed > 0 ? static_cast<double>(position + 1) / elapsed : 0;
      progress({summary.resumed + position + 1, jobs.size(), summary.resumed, kept, frames.load(),
                elapsed > 0 ? static_cast<double>(frames.load()) / elapsed : 0,
                rate > 0 ? static_cast<double>(todo.size() - position - 1) / rate : 0});
    }
  };

  if (ranks.distributed()) {
    // Rank 0: the other ranks run the episodes; their replies are settled in order as they come.
    release.disarm();
    std::map<size_t, Finished> arrived;  // by position in todo
    size_t next_to_settle = 0;
    eval::hand_out_jobs(todo, r.threads, [&] { return stop.load(); }, [&](size_t position, std::string_view reply) {
      Finished f = finished_from_reply(reply, "the reply for episode " + jobs[todo[position]].key);
      frames += f.outcome.frames;
      arrived.emplace(position, std::move(f));
      for (; failure.empty() && arrived.count(next_to_settle) > 0; ++next_to_settle) {
        settle(next_to_settle, arrived.at(next_to_settle));
        arrived.erase(next_to_settle);
      }
      if (!failure.empty()) stop = true;
    });
  } else {
    // Worker threads run the episodes; this thread settles them in order.
    std::mutex mutex;
    std::condition_variable ready_cv;
    std::map<size_t, Finished> ready;  // by position in todo
    std::atomic<size_t> next{0};
    std::vector<std::thread> workers;
    for (int w = 0; w < r.threads; ++w) {
      workers.emplace_back([&] {
        std::unique_ptr<policy::Policy> policy;
        while (!stop) {
          const size_t position = next++;
          if (position >= todo.size()) break;
          Finished f = run_job(jobs[todo[position]], policy, recorder);
          const std::lock_guard<std::mutex> lock(mutex);
          ready.emplace(position, std::move(f));
          ready_cv.notify_all();
        }
      });
    }
    for (size_t position = 0; position < todo.size() && failure.empty(); ++position) {
      Finished f;
      {
        std::unique_lock<std::mutex> lock(mutex);
        ready_cv.wait(lock, [&] { return ready.count(position) > 0; });
        f = std::move(ready.at(position));
        ready.erase(position);
      }
      settle(position, f);
    }
    stop = stop || !failure.empty();
    for (std::thread& worker : workers) worker.join();
    for (auto& [position, f] : ready) {
      if (f.sink) recorder.discard(std::move(f.sink));
    }
  }
  if (dataset) dataset->finish();
  if (!r.dry_run) fs::remove_all(dir / "hribench" / "staging");
  if (!r.dry_run && !storing) fs::remove_all(dir / "hribench" / "episodes");  // committed, or redone by a resume
  summary.kept = kept;
  summary.frames = frames.load();
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!failure.empty()) {
    save_state();
    throw core::InputError::Message(
        r.dry_run ? "collect" : r.out,
        fmt::format("{}; the {} episodes before it are in the {}; continue with --resume", failure, kept,
                    storing ? "shard" : "dataset"));
  }
  state["finished"] = true;
  save_state();
  return summary;
}

bool holds_collect(const fs::path& dir) { return fs::is_regular_file(collect_state_path(dir)); }

CollectSummary merge_collect(const fs::path& out, const std::vector<std::string>& dirs) {
  std::vector<eval::ShardOptions> folders;
  std::vector<nlohmann::json> states;
  for (const std::string& dir : dirs) {
    if (!holds_collect(dir)) throw core::InputError::Message(dir, "holds no collect (hribench/collect.json)");
    const std::string where = collect_state_path(dir).string();
    nlohmann::json state = core::read_json_file(where);
    const auto objects = [](const nlohmann::json& list) {
      return std::all_of(list.begin(), list.end(), [](const nlohmann::json& e) { return e.is_object(); });
    };
    if (!state.is_object() || !state.contains("options") || !state.contains("episodes") ||
        !state.at("episodes").is_array() || !objects(state.at("episodes")) ||
        !state.value("finished", nlohmann::json(false)).is_boolean()) {
      throw core::InputError(where, "a collect's state (options, episodes, finished)", "other JSON");
    }
    folders.push_back({dir, state.at("options")});
    states.push_back(std::move(state));
  }
  const std::vector<size_t> order = eval::shard_order(folders);
  nlohmann::json options = eval::merged_options(folders[order.front()].options);
  options.erase("code");
  options.erase("backend");

  // Each shard finished, holding exactly its episodes (checked before anything is sized by the
  // job count); by job number, the shard that holds it.
  const size_t total = folders[order.front()].options.at("shard_of_jobs").get<size_t>();
  for (size_t i = 0; i < order.size(); ++i) {
    const std::string& dir = folders[order[i]].dir;
    const nlohmann::json& state = states[order[i]];
    const eval::Shard shard{static_cast<int>(i), static_cast<int>(order.size())};
    if (!state.value("finished", false)) {
      throw core::InputError::Message(
          dir, fmt::format("holds an unfinished collect; finish it with collect --shard {} --resume", eval::to_string(shard)));
    }
    const size_t share = eval::shard_share(total, shard);
    if (state.at("episodes").size() != share) {
      throw core::InputError::Message(dir, fmt::format("holds {} of its {} episodes; finish it with collect --shard {} --resume",
                                                       state.at("episodes").size(), share, eval::to_string(shard)));
    }
  }
  std::vector<std::pair<size_t, nlohmann::json>> by_job(total);  // (folder, episode entry)
  std::vector<bool> seen(total, false);
  for (size_t i = 0; i < order.size(); ++i) {
    const std::string& dir = folders[order[i]].dir;
    const eval::Shard shard{static_cast<int>(i), static_cast<int>(order.size())};
    for (const nlohmann::json& episode : states[order[i]].at("episodes")) {
      const nlohmann::json number = episode.value("job", nlohmann::json());
      const size_t job = number.is_number_unsigned() ? number.get<size_t>() : total;
      if (job >= total || !shard.owns(job) || seen[job]) {
        throw core::InputError::Message(dir, fmt::format("holds episode {} (key {}), which is not shard {}'s (or is there twice)",
                                                         number.dump(), episode.value("key", nlohmann::json()).dump(),
                                                         eval::to_string(shard)));
      }
      seen[job] = true;
      by_job[job] = {order[i], episode};
    }
  }

  // The shards' kept episodes committed in split order, as one collect commits them.
  const std::string options_of = collect_state_path(folders[order.front()].dir).string() + ": options";
  const std::unique_ptr<DatasetWriter> writer = make_dataset_writer(
      core::json_string(core::json_member(options, "format", options_of), options_of + ".format"), out);
  fs::create_directories(out / "hribench" / "logs");
  nlohmann::json episodes = nlohmann::json::array();
  CollectSummary summary;
  summary.episodes = total;
  const auto start = std::chrono::steady_clock::now();
  for (size_t job = 0; job < total; ++job) {
    const std::string& dir = folders[by_job[job].first].dir;
    nlohmann::json episode = by_job[job].second;
    const std::string where = collect_state_path(dir).string() + ": episode " + std::to_string(job);
    episode.erase("job");
    if (core::json_bool(core::json_member(episode, "kept", where), where + ".kept")) {
      EpisodeOutcome outcome;
      try {
        outcome.success = episode.at("success").get<bool>();
        outcome.status = core::episode_status_from_string(episode.at("status").get<std::string>(), where + ".status");
        outcome.failure_labels = episode.at("labels").get<std::vector<std::string>>();
        outcome.frames = episode.at("frames").get<int64_t>();
        const fs::path log = collect_log_path(dir, episode.at("task").get<std::string>(), episode.at("seed").get<uint64_t>(),
                                              episode.at("spec_hash").get<std::string>());
        writer->commit(writer->load(stored_episode_path(dir, job)), outcome);
        fs::copy_file(log, out / "hribench" / "logs" / log.filename());
      } catch (const nlohmann::json::exception& e) {
        throw core::InputError(where, "a collect's episode (success, status, labels, frames, task, seed, spec_hash)",
                               e.what());
      } catch (const fs::filesystem_error& e) {
        throw core::InputError::Message(where, std::string("cannot copy its log: ") + e.what());
      }
      episode["index"] = summary.kept++;
    }
    episodes.push_back(std::move(episode));
  }
  writer->finish();
  const nlohmann::json state = {{"options", options}, {"episodes", episodes}, {"finished", true}};
  core::write_file_atomically(collect_state_path(out), state.dump(1) + "\n");
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

}  // namespace hribench::io

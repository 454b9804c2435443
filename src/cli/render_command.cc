// `hribench render --out scene.png [--camera NAME --width W --height H --backend B]`: a still
// of the default scene (robot at home, objects on the table, the human standing across it), so
// a person can look at it.
//
// With `--task FILE [--seed N] [--at TIME|EVENT[+S]] [--policy REF]`: a still of a moment of a
// task episode. The episode is sampled (script::sample), its scene built
// (eval::scene_spec_from_episode) into an eval::Episode, and run by eval::run_episode with the
// policy up to the first control step at or after the moment (an observer watches for it),
// whose state is rendered.
//
// `--camera free` is a documentation view: a free camera looking at the shared workspace a
// little from the person's right and the robot's front, so the robot, the table and the
// person's gestures are all visible; --azimuth/--elevation/--distance move it.

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "cli/command.h"
#include "core/errors.h"
#include "core/paths.h"
#include "eval/episode_log.h"
#include "eval/runner.h"
#include "eval/episode.h"
#include "eval/script_driver.h"
#include "model/model.h"
#include "policy/registry.h"
#include "render/png.h"
#include "render/renderer.h"
#include "script/check.h"
#include "script/runtime.h"
#include "script/sample.h"
#include "sim/data.h"

namespace hribench::cli {
namespace {

// The free camera: looks at the middle of the shared workspace, slightly above the table.
struct FreeView {
  double azimuth = -75;    // deg; MuJoCo convention (0: looking along +x, 90: along +y)
  double elevation = -20;  // deg; negative looks down
  double distance = 2.0;   // m from the look-at point
};
constexpr double kFreeLookat[3] = {0.6, 0.0, 1.05};  // world, m

struct RenderOptions {
  std::string out;
  std::string camera = "agentview";
  int width = 640;
  int height = 480;
  std::string backend = "osmesa";
  bool pretty = false;  // shadows and MuJoCo's default render settings (4x MSAA)
  bool mujoco_shapes = false;  // MuJoCo's tessellation of capsules, spheres and cylinders
  FreeView view;
  // A task moment (empty task: the default scene).
  std::string task;
  uint64_t seed = 0;
  std::string at = "0";
  std::string policy = "noop";
};

// Fails early (before any simulation or GL work) when `path` cannot be written.
void check_writable(const std::string& path) {
  const std::filesystem::path p(path);
  if (std::filesystem::is_directory(p)) {
    throw core::InputError("--out", "a file path", "the directory '" + path + "'");
  }
  std::string extension = p.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension != ".png") {
    throw core::InputError("--out", "a .png file (render writes PNG images)", "'" + path + "'");
  }
  const std::string dir = p.has_parent_path() ? p.parent_path().string() : ".";
  const bool exists = access(path.c_str(), F_OK) == 0;
  if (access(exists ? path.c_str() : dir.c_str(), W_OK) != 0) {
    throw core::InputError::Message(
        "--out", "cannot write '" + path + "' (" + std::strerror(errno) + ")");
  }
}

// A finite number >= 0 written in full (no trailing text), or nothing.
std::optional<double> parse_seconds(std::string_view text) {
  double value = 0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  if (text.empty() || ec != std::errc() || ptr != end || !std::isfinite(value) || value < 0) {
    return std::nullopt;
  }
  return value;
}

// What --at asks for: a time, or the first event named `event` (or the first cue for "cue")
// plus `offset` seconds.
struct Moment {
  std::optional<double> time;  // s
  std::string event;
  double offset = 0;  // s, >= 0
};

constexpr const char* kAtExpected = "a time in seconds or an event of the episode, optionally +S";

// `text` without blanks: predicate events are named as the script writes them,
// "in(obj_b, bin)", and may be typed "in(obj_b,bin)".
std::string without_blanks(std::string text) {
  text.erase(std::remove_if(text.begin(), text.end(), [](unsigned char c) { return std::isspace(c) != 0; }),
             text.end());
  return text;
}

Moment parse_moment(const std::string& text) {
  Moment moment;
  // Event names start with a letter; anything else must be a time.
  const bool letter = !text.empty() && std::isalpha(static_cast<unsigned char>(text[0])) != 0;
  if (!letter) {
    moment.time = parse_seconds(text);
    if (!moment.time) throw core::InputError("--at", kAtExpected, "'" + text + "'");
    return moment;
  }
  moment.event = without_blanks(text);
  const size_t plus = moment.event.rfind('+');
  if (plus != std::string::npos) {
    const std::optional<double> offset = parse_seconds(std::string_view(moment.event).substr(plus + 1));
    if (!offset) throw core::InputError("--at", kAtExpected, "'" + text + "'");
    moment.event = moment.event.substr(0, plus);
    moment.offset = *offset;
  }
  if (moment.event.empty()) throw core::InputError("--at", kAtExpected, "'" + text + "'");
  return moment;
}

// Every event the episode's script can give, in the graph's order (acts' ACT.start and
// ACT.end, motion phases ACT.PHASE, watched predicates as written), then "cue": for the
// "unknown event" message, whether or not this run reached them.
std::string event_names(const script::EpisodeSpec& spec) {
  std::vector<std::string> names;
  for (std::string name : script::compile(spec).event_names) {
    for (const char* truth : {":true", ":false"}) {
      if (name.size() > std::strlen(truth) && name.ends_with(truth)) name.resize(name.size() - std::strlen(truth));
    }
    if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
  }
  names.push_back("cue");
  return fmt::format("{}", fmt::join(names, ", "));
}

struct RenderedMoment {
  double time = 0;   // s, the state rendered
  std::string what;  // how the moment was chosen, for the summary line
};

// Watches an episode for the moment --at names: after each step (events observed, state
// current), reached() once the step's time is at or past the moment (an event's time is known
// once the event has been observed).
class MomentWatch : public eval::EpisodeObserver {
 public:
  explicit MomentWatch(const Moment& moment) : moment_(moment) {
    if (moment.time) stop_at_ = moment.time;
  }
  void on_step(const eval::Episode& episode, const eval::StepRecord& step) override {
    const std::vector<eval::Event>& events = episode.log().events;
    for (; seen_ < events.size(); ++seen_) {
      const eval::Event& e = events[seen_];
      if (stop_at_) continue;
      if (moment_.event == "cue" ? e.kind == eval::EventKind::kCue : without_blanks(e.name) == moment_.event) {
        stop_at_ = e.time + moment_.offset;
        what_ = fmt::format("{} at {:.2f} s{}", e.name, e.time,
                            moment_.offset > 0 ? fmt::format(" + {} s", moment_.offset) : "");
      }
    }
    reached_ = stop_at_ && step.time >= *stop_at_ - 1e-9;
  }
  bool reached() const { return reached_; }
  const std::string& what() const { return what_; }

 private:
  Moment moment_;
  size_t seen_ = 0;                // events already looked at
  std::optional<double> stop_at_;  // s
  bool reached_ = false;
  std::string what_;               // the event found
};

// Runs the episode from reset up to the moment --at names (run_episode until it is reached),
// leaving that state in the episode's data. Throws core::InputError when the episode ends
// before it.
RenderedMoment run_to_moment(eval::Episode& episode, const std::string& task_id,
                             const RenderOptions& o) {
  const script::EpisodeSpec& spec = *episode.spec();
  const Moment moment = parse_moment(o.at);
  if (moment.time && *moment.time > spec.horizon) {
    throw core::InputError(
        "--at", fmt::format("a time within the episode's horizon [0, {}] s", spec.horizon), o.at);
  }
  MomentWatch watch(moment);
  episode.add_observer(watch);
  std::unique_ptr<policy::Policy> policy = policy::make_policy(o.policy);
  const eval::EpisodeLog& log = eval::run_episode(
      episode, *policy, [&](const eval::Episode&) { return watch.reached(); });
  episode.remove_observer(watch);
  if (watch.reached()) {
    return {episode.data().time(), moment.time ? fmt::format("t = {} s", o.at) : watch.what()};
  }
  // The run ended without reaching the moment.
  const double end = log.steps.empty() ? 0.0 : log.steps.back().time;
  if (log.status != core::EpisodeStatus::kOk) {
    throw core::InputError::Message(
        "--at", fmt::format("the episode ended ({}: {}) at {:.2f} s, before '{}'",
                            core::to_string(log.status), log.status_reason, end, o.at));
  }
  if (!watch.what().empty()) {  // the event plus the offset lies past the horizon
    throw core::InputError::Message(
        "--at", fmt::format("{}: past the episode's horizon ({} s)", watch.what(), spec.horizon));
  }
  throw core::InputError("--at",
                         "an event of " + task_id + " seed " + std::to_string(o.seed) + " with " +
                             o.policy + " (" + event_names(spec) + ")",
                         "'" + moment.event + "'");
}

// The camera to render through: a named model camera, or the free documentation view.
mjvCamera make_camera(const mjModel& m, const RenderOptions& o) {
  mjvCamera camera;
  mjv_defaultCamera(&camera);
  if (o.camera == "free") {
    camera.type = mjCAMERA_FREE;
    for (int i = 0; i < 3; ++i) camera.lookat[i] = kFreeLookat[i];
    camera.azimuth = o.view.azimuth;
    camera.elevation = o.view.elevation;
    camera.distance = o.view.distance;
    return camera;
  }
  camera.type = mjCAMERA_FIXED;
  camera.fixedcamid = mj_name2id(&m, mjOBJ_CAMERA, o.camera.c_str());
  if (camera.fixedcamid < 0) {
    // The model's cameras, then the documentation view.
    std::string names;
    for (int i = 0; i < m.ncam; ++i) names += std::string(mj_id2name(&m, mjOBJ_CAMERA, i)) + ", ";
    throw core::InputError("--camera", "one of " + names + "free", "'" + o.camera + "'");
  }
  return camera;
}

void check_view(const RenderOptions& o, bool view_given) {
  if (view_given && o.camera != "free") {
    throw core::InputError::Message("--camera",
                                    "--azimuth, --elevation and --distance need --camera free");
  }
  if (!std::isfinite(o.view.azimuth)) {
    throw core::InputError("--azimuth", "a finite angle in degrees",
                           fmt::format("{}", o.view.azimuth));
  }
  if (!(o.view.elevation >= -90 && o.view.elevation <= 90)) {
    throw core::InputError("--elevation", "an angle in [-90, 90] degrees",
                           fmt::format("{}", o.view.elevation));
  }
  if (!(o.view.distance > 0 && o.view.distance <= 20)) {
    throw core::InputError("--distance", "a distance in (0, 20] m",
                           fmt::format("{}", o.view.distance));
  }
}

int run_render(const RenderOptions& o, bool view_given, bool task_options_given) {
  // Validate everything the user typed before building anything.
  const render::Backend backend = render::parse_backend(o.backend);
  if (backend == render::Backend::kNone) {
    throw core::InputError("--backend", "osmesa or egl (render writes an image)", "'none'");
  }
  render::check_image_size(o.width, o.height, "--width", "--height");
  check_view(o, view_given);
  if (o.task.empty() && task_options_given) {
    throw core::InputError::Message("--task", "--seed, --at and --policy need --task FILE");
  }
  if (!o.task.empty()) {
    parse_moment(o.at);
    policy::make_policy(o.policy);
  }
  check_writable(o.out);

  // The default scene, or the task episode run to the moment.
  std::shared_ptr<const model::Model> model;
  std::optional<sim::Data> still;        // the default scene's state
  std::optional<eval::Episode> episode;  // the task's
  std::string summary;
  if (o.task.empty()) {
    model::SceneSpec scene = model::SceneSpec::Default();
    scene.shadows = o.pretty;
    model = std::make_shared<const model::Model>(model::build(scene));
    still.emplace(sim::make_data(*model));
  } else {
    // A relative script is taken from the current folder, else from the data root
    // (docs/getting-started.md "Running from anywhere").
    const std::filesystem::path script = core::resolve_data_path(o.task);
    if (!std::filesystem::is_regular_file(script)) {
      throw core::InputError("--task", "a scenario script file", "'" + o.task + "'");
    }
    script::EpisodeSpec spec = script::sample(script::load_scenario(script.string()), o.seed);
    model::SceneSpec scene = eval::scene_spec_from_episode(spec);
    scene.shadows = o.pretty;  // lights only: the physics is the same
    model = std::make_shared<const model::Model>(model::build(scene));
    eval::RunOptions options;
    options.stop_on_success = false;  // a moment after success is still a moment
    options.horizon = spec.horizon;
    const policy::PolicySpec policy_spec = policy::make_policy(o.policy)->spec();
    eval::EpisodeSetup setup = eval::setup_of(spec, o.policy);
    episode.emplace(std::move(spec), policy_spec, std::move(setup), options, model);
  }
  const mjModel& m = *model->m();
  const mjvCamera camera = make_camera(m, o);
  if (episode) {
    const std::string task_id = std::filesystem::path(o.task).stem().string();
    const RenderedMoment moment = run_to_moment(*episode, task_id, o);
    const script::EpisodeSpec& spec = *episode->spec();
    summary = fmt::format("; {} seed {}{}, {}, {} -> t = {:.2f} s", task_id, o.seed,
                          spec.variant.empty() ? "" : " (" + spec.variant + ")", o.policy,
                          moment.what, moment.time);
  }
  const sim::Data& data = episode ? episode->data() : *still;

  render::RenderSettings settings =
      o.pretty ? render::RenderSettings::mujoco_defaults() : render::RenderSettings{};
  if (o.mujoco_shapes) {
    const render::RenderSettings mujoco = render::RenderSettings::mujoco_defaults();
    settings.shape_slices = mujoco.shape_slices;
    settings.shape_stacks = mujoco.shape_stacks;
  }
  auto renderer = render::make_renderer(backend, m, o.width, o.height, settings);
  render::Image image;
  renderer->render(m, *data.mj, camera, image);
  render::write_png(o.out, image);
  std::printf("wrote %s (%dx%d, camera %s, %s: %s)%s\n", o.out.c_str(), o.width, o.height,
              o.camera.c_str(), std::string(render::to_string(backend)).c_str(),
              renderer->gl_renderer().c_str(), summary.c_str());
  return 0;
}

HRIB_REGISTER_COMMAND(
    "render", "Render a still of the default scene, or of a moment of a task episode, to a PNG",
    [](CLI::App& app) -> std::function<int()> {
      auto options = std::make_shared<RenderOptions>();
      app.add_option("--out", options->out, "PNG file to write")->required();
      app.add_option("--camera", options->camera,
                     "camera name (agentview, wrist) or free (the documentation view)")
          ->capture_default_str();
      app.add_option("--width", options->width, "image width in pixels")->capture_default_str();
      app.add_option("--height", options->height, "image height in pixels")
          ->capture_default_str();
      app.add_option("--backend", options->backend, "osmesa (CPU) or egl (GPU)")
          ->capture_default_str();
      app.add_flag("--pretty", options->pretty,
                   "shadows and anti-aliasing (MuJoCo's render defaults), for documentation");
      app.add_flag("--mujoco-shapes", options->mujoco_shapes,
                   "capsules, spheres and cylinders with MuJoCo's finer tessellation (what policies "
                   "see uses ours; docs/rendering.md)");
      auto* azimuth = app.add_option("--azimuth", options->view.azimuth,
                                     "free camera: azimuth, deg")
                          ->capture_default_str();
      auto* elevation = app.add_option("--elevation", options->view.elevation,
                                       "free camera: elevation, deg (negative looks down)")
                            ->capture_default_str();
      auto* distance = app.add_option("--distance", options->view.distance,
                                      "free camera: distance to the look-at point, m")
                           ->capture_default_str();
      app.add_option("--task", options->task, "scenario script: render a moment of its episode");
      auto* seed = app.add_option("--seed", options->seed, "episode seed")->capture_default_str();
      auto* at = app.add_option("--at", options->at,
                                "moment: seconds, or an event of the episode (e.g. point.stroke, "
                                "cue = the first cue), optionally +S seconds after it")
                     ->capture_default_str();
      auto* policy = app.add_option("--policy", options->policy, "policy reference")
                         ->capture_default_str();
      return [options, azimuth, elevation, distance, seed, at, policy] {
        const bool view_given = azimuth->count() + elevation->count() + distance->count() > 0;
        const bool task_options_given = seed->count() + at->count() + policy->count() > 0;
        return run_render(*options, view_given, task_options_given);
      };
    });

}  // namespace
}  // namespace hribench::cli

#include "io/episode_video.h"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <optional>

#include "core/errors.h"
#include "eval/episode.h"
#include "eval/script_contract.h"
#include "eval/script_driver.h"
#include "gen/evaluation.h"
#include "model/model.h"
#include "script/runtime.h"
#include "script/sample.h"
#include "sim/data.h"

namespace hribench::io {
namespace {

constexpr std::array<float, 3> kNeutral{0.12F, 0.12F, 0.12F};
constexpr std::array<float, 3> kAlarm{0.70F, 0.10F, 0.10F};
constexpr std::array<float, 3> kClear{0.10F, 0.40F, 0.15F};
constexpr std::array<float, 3> kNotice{0.55F, 0.40F, 0.05F};

// "take.start" -> "take"; "take.end" -> "take".
std::string act_of(const std::string& event_name) {
  return event_name.substr(0, event_name.rfind('.'));
}

// What the person is doing at time t: the phase or act last begun and not yet ended.
std::string person_at(const eval::EpisodeLog& log, double t) {
  std::string current;
  for (const eval::Event& event : log.events) {
    if (event.time > t) break;
    if (event.actor != eval::Actor::kHuman) continue;
    if (event.kind == eval::EventKind::kActStart) current = act_of(event.name);
    if (event.kind == eval::EventKind::kPhase) current = event.name;
    if (event.kind == eval::EventKind::kActEnd && !current.empty() &&
        act_of(event.name) == current.substr(0, current.find('.'))) {
      current.clear();
    }
  }
  return current.empty() ? "person: -" : "person: " + current;
}

// The latest cue given at or before t.
const eval::Event* cue_at(const eval::EpisodeLog& log, double t) {
  const eval::Event* latest = nullptr;
  for (const eval::Event& event : log.events) {
    if (event.time > t) break;
    if (event.kind == eval::EventKind::kCue) latest = &event;
  }
  return latest;
}

render::BandCell response_cell(const eval::Event* cue, const eval::EpisodeMetrics& metrics, double t) {
  if (cue == nullptr) return {"robot: no cue yet", kNeutral};
  for (const eval::CueResult& result : metrics.cues) {
    // The metrics name a cue by the contract's name; its time is the cue event's.
    if (std::abs(result.cue_time - cue->time) > 1e-9) continue;
    if (result.premature) return {"robot: moved before the cue", kAlarm};
    if (result.response_time && t >= *result.response_time) {
      return {fmt::format("robot responded {:.2f} s (+{:.2f})", *result.response_time,
                          *result.response_time - result.cue_time),
              result.responded ? kClear : kNotice};
    }
    return {fmt::format("robot: none yet (+{:.1f} s)", t - result.cue_time), kNotice};
  }
  return {"robot: -", kNeutral};
}

render::BandCell separation_cell(const eval::StepRecord& step, const eval::MetricConstants& c) {
  if (!std::isfinite(step.separation)) return {"no person", kNeutral};
  const double s_p = eval::protective_separation(step.approach_speed, step.separation, c);
  return {fmt::format("d {:.2f} m   S_p {:.2f} m", step.separation, s_p),
          step.separation < s_p ? kAlarm : kClear};
}

render::BandCell contact_cell(const eval::StepRecord& step) {
  if (step.contacts.empty()) return {"no contact", kNeutral};
  // A contact with the person first.
  const eval::Contact* shown = &step.contacts.front();
  for (const eval::Contact& contact : step.contacts) {
    if (contact.other_kind == eval::ContactOther::kHuman) {
      shown = &contact;
      break;
    }
  }
  std::string text = fmt::format("contact {} | {} {:.0f} N", shown->robot_part, shown->other,
                                 shown->normal_force);
  if (step.contacts.size() > 1) text += fmt::format(" (+{})", step.contacts.size() - 1);
  return {text, shown->other_kind == eval::ContactOther::kHuman ? kAlarm : kNotice};
}

}  // namespace

std::vector<render::BandRow> video_band(const eval::EpisodeLog& log, size_t step,
                                        const eval::EpisodeMetrics& metrics,
                                        const eval::MetricConstants& constants) {
  HRIB_CHECK(step < log.steps.size()) << "step " << step << " of " << log.steps.size();
  const eval::StepRecord& record = log.steps[step];
  const double t = record.time;
  const eval::Event* cue = cue_at(log, t);
  return {
      {{fmt::format("t {:.2f} s", t), kNeutral},
       {person_at(log, t), kNeutral},
       {cue == nullptr ? "cue: -" : fmt::format("cue {} {:.2f} s", cue->name, cue->time),
        cue == nullptr ? kNeutral : kNotice},
       response_cell(cue, metrics, t)},
      {separation_cell(record, constants), contact_cell(record)},
  };
}

std::vector<std::string> video_cameras(const std::string& list, const script::EpisodeSpec& spec,
                                       std::string_view where) {
  const std::vector<std::string> cameras = gen::split_list(list);
  if (cameras.empty() || cameras.size() > 2) {
    throw core::InputError(std::string(where), "one or two cameras (agentview or agentview,wrist)",
                           "'" + list + "'");
  }
  const model::Model model = model::build(eval::scene_spec_from_episode(spec));
  for (const std::string& camera : cameras) render::camera_id(*model.m(), camera, where);
  return cameras;
}

void write_episode_video(const script::EpisodeSpec& spec, const eval::EpisodeLog& log,
                         const std::filesystem::path& path, const EpisodeVideoOptions& options,
                         const eval::MetricConstants& constants) {
  const std::string where = path.string();
  if (log.steps.empty()) throw core::InputError(where, "a log with steps", "an empty log");
  if (script::spec_hash(spec) != log.spec_hash) {
    throw core::InputError(where, "the log of episode " + script::spec_hash(spec),
                           "the log of " + log.spec_hash);
  }
  if (options.cameras.empty() || options.cameras.size() > 2) {
    throw core::InputError(where + ": cameras", "one or two cameras",
                           std::to_string(options.cameras.size()));
  }
  const double fps = 1.0 / log.control_dt;
  if (!(std::abs(fps - std::round(fps)) < 1e-9)) {
    throw core::InputError(where + ": control_dt", "1 / a whole number of frames per second",
                           fmt::format("{} s", log.control_dt));
  }

  const model::Model model = model::build(eval::scene_spec_from_episode(spec));
  const eval::ScenarioContract contract =
      eval::contract_from_episode(spec, script::compile(spec), model);
  const eval::EpisodeMetrics metrics = eval::compute_metrics(contract, log, constants);
  std::vector<int> camera_ids;
  for (const std::string& camera : options.cameras) {
    camera_ids.push_back(render::camera_id(*model.m(), camera, "video camera"));
  }
  const int width = options.panel_width * static_cast<int>(camera_ids.size());
  const int height = options.panel_height + kBandRows * kBandRowHeight;
  render::RenderSettings settings;
  settings.font_scale = 100;
  render::Renderer renderer(options.backend, *model.m(), width, height, settings);
  if (renderer.backend() == render::Backend::kNone) {
    throw core::InputError(where + ": renderer", "a GL back end (osmesa or egl)", "none");
  }
  sim::Data data = sim::make_data(model);
  VideoWriter writer(path, width, height,
                     VideoSettings{.fps = static_cast<int>(std::round(fps)), .crf = options.crf});
  render::Image frame;
  for (size_t k = 0; k < log.steps.size(); ++k) {
    eval::pose_from_step(model, log, log.steps[k], data);
    renderer.render_panels(*model.m(), *data.mj, camera_ids, video_band(log, k, metrics, constants),
                           kBandRowHeight, frame);
    writer.add(frame);
  }
  writer.finish();
}

}  // namespace hribench::io

#include "eval/reward.h"

#include <algorithm>
#include <limits>
#include <optional>
#include <string>
#include <string_view>

#include "core/errors.h"
#include "eval/metrics.h"

namespace hribench::eval {
namespace {

// When `name` happened by time `t` (the log's events so far; "episode.start": the first
// step); nullopt: not yet.
std::optional<double> happened_by(const EpisodeLog& log, std::string_view name, double t,
                                  const MetricConstants& c) {
  if (name == "episode.start") return log.steps.front().time;
  for (const Event& e : log.events) {
    if (e.time > t + c.time_epsilon) break;
    if (e.name == name) return e.time;
  }
  return std::nullopt;
}

// Inside [from, to] as far as the log knows at time t (to not yet happened: still inside).
bool inside(const EpisodeLog& log, const EventInterval& interval, double t, const MetricConstants& c) {
  const std::optional<double> from = happened_by(log, interval.from, t, c);
  if (!from || *from > t + c.time_epsilon) return false;
  if (interval.to.empty()) return true;
  const std::optional<double> to = happened_by(log, interval.to, t, c);
  return !to || t <= *to + c.time_epsilon;
}

// The current robot act at time t: the first whose end has not happened (null: all ended).
const RobotActContract* current_act(const ScenarioContract& contract, const EpisodeLog& log, double t,
                                    const MetricConstants& c) {
  for (const RobotActContract& act : contract.robot_acts) {
    if (!happened_by(log, act.name + ".end", t, c)) return &act;
  }
  return nullptr;
}

bool permitted(const ScenarioContract& contract, const EpisodeLog& log, const Contact& contact,
               double t, const MetricConstants& c) {
  for (const PermittedContact& p : contract.permitted_contacts) {
    if (p.fingers_only && !contact.robot_finger) continue;
    if (!p.human_parts.empty() &&
        std::find(p.human_parts.begin(), p.human_parts.end(), contact.other) == p.human_parts.end()) {
      continue;
    }
    if (inside(log, p.phase, t, c)) return true;
  }
  return false;
}

}  // namespace

double contact_grade(human::BodyRegion region) {
  double lowest = std::numeric_limits<double>::infinity();
  for (int r = 0; r < human::kNumBodyRegions; ++r) {
    lowest = std::min(lowest, human::quasi_static_force_limit(static_cast<human::BodyRegion>(r)));
  }
  return lowest / human::quasi_static_force_limit(region);
}

RewardTerms dense_reward(const ScenarioContract& contract, const EpisodeLog& log, size_t k,
                         const script::RewardWeights& w, const MetricConstants& c,
                         const EpisodeMetrics* ended) {
  HRIB_CHECK(k >= 1 && k < log.steps.size()) << "step " << k << " of " << log.steps.size();
  const StepRecord& s = log.steps[k];
  const StepRecord& prev = log.steps[k - 1];
  const double dt = s.time - prev.time;
  RewardTerms r;

  if (const RobotActContract* act = current_act(contract, log, s.time, c); act && act->goal_W) {
    const double before = (prev.X_WT.translation - *act->goal_W).norm();
    const double after = (s.X_WT.translation - *act->goal_W).norm();
    r.progress = w.progress * (before - after);
  }

  if (ended && ended->success) r.success = w.success;

  // Premature: the current act answers go cues and none of them has allowed motion yet, and
  // the tool moves toward the act's goal faster than an answer's onset (the metrics' rule).
  if (const RobotActContract* act = current_act(contract, log, prev.time, c)) {
    bool answers = false;
    bool allowed = false;
    for (const CueContract& cue : contract.cues) {
      if (cue.kind != CueKind::kGo || cue.answered_by != act->name) continue;
      answers = true;
      const std::string& from = cue.motion_allowed_from.empty() ? cue.event : cue.motion_allowed_from;
      allowed = allowed || happened_by(log, from, prev.time, c).has_value();
    }
    if (answers && !allowed && dt > 0) {
      const core::Vec3 step = s.X_WT.translation - prev.X_WT.translation;
      double toward = step.norm();
      if (act->goal_W) {
        const core::Vec3 to_goal = *act->goal_W - prev.X_WT.translation;
        const double distance = to_goal.norm();
        toward = distance < c.goal_reached_distance ? 0.0 : step.dot(to_goal / distance);
      }
      if (toward / dt > c.response_speed) r.premature_motion = -w.premature_motion * toward;
    }
  }

  if (s.separation <= c.monitored_distance) {
    bool in_permitted_phase = false;
    for (const PermittedContact& p : contract.permitted_contacts) {
      in_permitted_phase = in_permitted_phase || inside(log, p.phase, s.time, c);
    }
    const bool violation =
        in_permitted_phase
            ? s.closest_point_speed > c.permitted_speed && s.separation < c.permitted_distance
            : s.separation < protective_separation(s.approach_speed, s.separation, c);
    if (violation) r.separation = -w.separation * dt;
  }

  for (const Contact& contact : s.contacts) {
    if (contact.other_kind != ContactOther::kHuman || !(contact.normal_force > 0)) continue;
    if (permitted(contract, log, contact, s.time, c)) continue;
    r.contact -= w.contact * dt * contact_grade(*contact.region);
  }
  return r;
}

RewardTerms dense_return(const ScenarioContract& contract, const EpisodeLog& log,
                         const script::RewardWeights& weights, const MetricConstants& constants) {
  const EpisodeMetrics metrics = compute_metrics(contract, log, constants);
  RewardTerms sum;
  for (size_t k = 1; k < log.steps.size(); ++k) {
    const RewardTerms r =
        dense_reward(contract, log, k, weights, constants, k + 1 == log.steps.size() ? &metrics : nullptr);
    sum.progress += r.progress;
    sum.success += r.success;
    sum.premature_motion += r.premature_motion;
    sum.separation += r.separation;
    sum.contact += r.contact;
  }
  return sum;
}

}  // namespace hribench::eval

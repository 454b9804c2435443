#include "eval/metrics.h"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>

#include "core/errors.h"
#include "eval/robot_motion.h"
#include "human/skeleton.h"
#include "sim/contact.h"

namespace hribench::eval {

std::string_view to_string(FailureLabel label) {
  switch (label) {
    case FailureLabel::kInvalid:
      return "invalid";
    case FailureLabel::kPolicyError:
      return "policy_error";
    case FailureLabel::kCriticalContact:
      return "critical_contact";
    case FailureLabel::kContact:
      return "contact";
    case FailureLabel::kCollision:
      return "collision";
    case FailureLabel::kPremature:
      return "premature";
    case FailureLabel::kWrongTarget:
      return "wrong_target";
    case FailureLabel::kIgnoredContradiction:
      return "ignored_contradiction";
    case FailureLabel::kNoResponse:
      return "no_response";
    case FailureLabel::kDesync:
      return "desync";
    case FailureLabel::kUnsafeProximity:
      return "unsafe_proximity";
    case FailureLabel::kDrop:
      return "drop";
    case FailureLabel::kNoRecovery:
      return "no_recovery";
    case FailureLabel::kManipulation:
      return "manipulation";
    case FailureLabel::kTimeout:
      return "timeout";
  }
  return "unknown";
}

namespace {

double start_time(const EpisodeLog& log) { return log.steps.empty() ? 0.0 : log.steps.front().time; }
double end_time(const EpisodeLog& log) { return log.steps.empty() ? 0.0 : log.steps.back().time; }

// The index of a robot act of the contract, or nullopt.
std::optional<size_t> robot_act_index(const ScenarioContract& contract, std::string_view name) {
  for (size_t i = 0; i < contract.robot_acts.size(); ++i) {
    if (contract.robot_acts[i].name == name) return i;
  }
  return std::nullopt;
}

// A predicate series of the log; nullopt if the log has none of that name.
std::optional<std::vector<bool>> series(const EpisodeLog& log, std::string_view name) {
  const std::optional<size_t> index = log.predicate_index(name);
  if (!index) return std::nullopt;
  std::vector<bool> values;
  values.reserve(log.steps.size());
  for (const StepRecord& s : log.steps) values.push_back(s.predicates[*index] != 0);
  return values;
}

std::vector<bool> required_series(const EpisodeLog& log, const std::string& name) {
  std::optional<std::vector<bool>> values = series(log, name);
  if (!values) {
    std::string known;
    for (const std::string& n : log.predicate_names) known += (known.empty() ? "" : ", ") + n;
    throw core::InputError("contract: predicate '" + name + "'",
                           "a predicate series of the episode log",
                           "none (the log has: " + (known.empty() ? "no series" : known) + ")");
  }
  return *values;
}

bool ever(const std::optional<std::vector<bool>>& values) {
  return values && std::find(values->begin(), values->end(), true) != values->end();
}

// Everything the metrics of one episode share.
struct Episode {
  const ScenarioContract& contract;
  const EpisodeLog& log;
  const MetricConstants& c;
  std::vector<std::optional<double>> onsets;
  TimeSet moving;
  TimeSet still;
  double t0 = 0;
  double t_end = 0;

  std::optional<double> event(std::string_view name) const {
    if (name == "episode.start") return t0;
    if (name == "episode.end") return t_end;
    const size_t dot = name.rfind('.');
    if (dot != std::string_view::npos && name.substr(dot) == ".start") {
      if (const auto act = robot_act_index(contract, name.substr(0, dot))) return onsets[*act];
    }
    return log.event_time(name);
  }
  // [from, to] of an EventInterval (to missing: until the end), nullopt if from never happened.
  std::optional<TimeInterval> interval(const EventInterval& i) const {
    const std::optional<double> from = event(i.from);
    if (!from) return std::nullopt;
    return TimeInterval{*from, event(i.to).value_or(t_end)};
  }
  TimeSet intervals(const std::vector<EventInterval>& list) const {
    TimeSet set;
    for (const EventInterval& i : list) {
      if (const auto ti = interval(i)) set.push_back(*ti);
    }
    return normalized(std::move(set));
  }
};

std::vector<std::optional<double>> detect_onsets(const ScenarioContract& contract,
                                                 const EpisodeLog& log, const TimeSet& moving,
                                                 const MetricConstants& c) {
  std::vector<std::optional<double>> onsets;
  std::optional<double> search_from = start_time(log);
  for (size_t i = 0; i < contract.robot_acts.size(); ++i) {
    const RobotActContract& act = contract.robot_acts[i];
    if (robot_act_index(contract, act.name) != i) {
      throw core::InputError("contract: robot act '" + act.name + "'", "unique act names",
                             "a second act of that name");
    }
    std::optional<double> onset;
    if (search_from) {
      const TimeSet set = act.goal_W ? toward_time(log, *act.goal_W, c) : moving;
      onset = first_time_at_or_after(set, *search_from, c.time_epsilon);
    }
    onsets.push_back(onset);
    // The next act searches from this act's end.
    search_from = log.event_time(act.name + ".end");
  }
  return onsets;
}

void score_success(const Episode& e, EpisodeMetrics& m) {
  required_series(e.log, e.contract.success_predicate);  // throws if the log lacks it
  m.success_since = final_run_start(e.log, *e.log.predicate_index(e.contract.success_predicate));
}

// A go cue's answer (docs/metrics.md, Rsp): premature when the answering act started (its
// onset, the first motion toward the goal after the act before it ended) before the script
// allowed, or, without an answering act, when motion toward the goal under way at t_c began
// before it; else the first motion toward the goal at or after t_c, provided the act before
// the answering one ended at some time (a robot that never finishes it never gets to the
// answer: random motion that happens to point at the goal is none).
void answer_go_cue(const Episode& e, const CueContract& cue, const TimeSet& response, CueResult& r) {
  const double eps = e.c.time_epsilon;
  const double t_c = r.cue_time;
  const double allowed = std::min(
      t_c, cue.motion_allowed_from.empty() ? t_c : e.event(cue.motion_allowed_from).value_or(t_c));
  std::optional<double> own_from = e.t0;
  const std::optional<size_t> act = robot_act_index(e.contract, cue.answered_by);
  if (act && *act > 0) own_from = e.log.event_time(e.contract.robot_acts[*act - 1].name + ".end");
  if (act) {
    // The answering act's onset (OC's): its first motion toward the goal after the act before.
    r.premature = e.onsets[*act] && *e.onsets[*act] < allowed - eps;
  } else {
    const std::optional<TimeInterval> under_way = interval_across(response, t_c, eps);
    r.premature = under_way && under_way->from < allowed - eps;
  }
  if (r.premature || !own_from) r.response_time.reset();
}

void score_cues(const Episode& e, EpisodeMetrics& m) {
  const TimeSet retreat = retreat_time(e.log, e.c);
  const TimeSet still_or_retreat = unite(e.still, retreat);
  double sum = 0;
  for (const CueContract& cue : e.contract.cues) {
    const std::optional<double> t_c = e.event(cue.event);
    if (!t_c) continue;  // the cue was never given
    TimeSet response;
    switch (cue.kind) {
      case CueKind::kGo:
        // Toward the goal; without a goal position, any sustained motion.
        response = cue.goal_W ? toward_time(e.log, *cue.goal_W, e.c) : e.moving;
        break;
      case CueKind::kStop:
        response = e.still;
        break;
      case CueKind::kIntrusion:
        response = still_or_retreat;
        break;
    }
    CueResult r;
    r.name = cue.name;
    r.cue_time = *t_c;
    r.response_time = first_time_at_or_after(response, *t_c, e.c.time_epsilon);
    if (cue.kind == CueKind::kGo) answer_go_cue(e, cue, response, r);
    r.responded = r.response_time && *r.response_time - *t_c <= cue.window + e.c.time_epsilon;
    r.latency = r.responded ? *r.response_time - *t_c : cue.window;
    sum += r.latency;
    m.cues.push_back(r);
  }
  if (!m.cues.empty()) m.response_latency = sum / static_cast<double>(m.cues.size());
}

void score_syncs(const Episode& e, EpisodeMetrics& m) {
  double sum = 0;
  for (const SyncContract& sync : e.contract.syncs) {
    HRIB_CHECK(sync.tolerance > 0) << "sync " << sync.name << " tolerance " << sync.tolerance;
    const std::optional<double> t_h = e.event(sync.human_event);
    if (!t_h) continue;  // not applicable
    SyncResult r;
    r.name = sync.name;
    r.human_time = *t_h;
    r.robot_time = e.event(sync.robot_event);
    if (r.robot_time) {
      r.score = std::max(0.0, 1.0 - std::abs(*r.robot_time - *t_h - sync.offset) / sync.tolerance);
    }
    sum += r.score;
    m.syncs.push_back(r);
  }
  if (!m.syncs.empty()) m.tsync = sum / static_cast<double>(m.syncs.size());
}

OrderResult score_order(const Episode& e, const OrderContract& order) {
  const double eps = e.c.time_epsilon;
  OrderResult r;
  if (order.kind == OrderKind::kStill) {
    r.description = fmt::format("still from {} (+{} s) to {}", order.from_event, order.grace,
                                order.to_event.empty() ? "the end" : order.to_event);
    const std::optional<double> from = e.event(order.from_event);
    if (!from) {
      r.applicable = false;
      return r;
    }
    const double to = order.to_event.empty() ? e.t_end : e.event(order.to_event).value_or(e.t_end);
    const TimeSet window{{*from + order.grace, to}};
    r.satisfied = total_length(intersect(e.moving, normalized(window))) <= eps;
    return r;
  }
  const std::optional<size_t> act = robot_act_index(e.contract, order.act);
  if (!act) {
    throw core::InputError("contract: order on '" + order.act + "'", "a robot act of the contract",
                           "an unknown act");
  }
  const std::optional<double> onset = e.onsets[*act];
  const std::optional<double> t_event = e.event(order.event);
  if (order.kind == OrderKind::kAfter) {
    r.description = order.act + " after " + order.event;
    // Violated iff the act started before the event happened (or it never happened).
    r.satisfied = !onset || (t_event && *onset >= *t_event - eps);
  } else {
    r.description = order.act + " before " + order.event;
    // Violated iff the act started and the event came before the act had ended.
    const std::optional<double> end = e.log.event_time(order.act + ".end");
    r.satisfied = !onset || !t_event || (end && *end <= *t_event + eps);
  }
  return r;
}

void score_orders(const Episode& e, EpisodeMetrics& m) {
  int applicable = 0;
  int satisfied = 0;
  for (const OrderContract& order : e.contract.orders) {
    m.orders.push_back(score_order(e, order));
    if (!m.orders.back().applicable) continue;
    ++applicable;
    satisfied += m.orders.back().satisfied ? 1 : 0;
  }
  if (applicable > 0) m.order_compliance = static_cast<double>(satisfied) / applicable;
}

bool permitted(const Episode& e, const Contact& contact, double t) {
  for (const PermittedContact& p : e.contract.permitted_contacts) {
    if (p.fingers_only && !contact.robot_finger) continue;
    if (!p.human_parts.empty() &&
        std::find(p.human_parts.begin(), p.human_parts.end(), contact.other) == p.human_parts.end()) {
      continue;
    }
    const std::optional<TimeInterval> phase = e.interval(p.phase);
    if (phase && phase->from - e.c.time_epsilon <= t && t <= phase->to + e.c.time_epsilon) {
      return true;
    }
  }
  return false;
}

void score_contacts(const Episode& e, EpisodeMetrics& m) {
  for (const StepRecord& s : e.log.steps) {
    for (const Contact& contact : s.contacts) {
      const double f = contact.normal_force;
      if (f > e.c.any_collision_force ||
          (contact.other_kind == ContactOther::kEnvironment && !contact.robot_finger &&
           f > e.c.environment_collision_force)) {
        m.environment_collision = true;
      }
      if (contact.other_kind != ContactOther::kHuman) continue;
      m.max_human_force = std::max(m.max_human_force, f);
      const sim::ContactGrade grade = sim::grade_contact(*contact.region, f, e.c.transient_factor);
      if (grade >= sim::ContactGrade::kAboveQuasiStatic) m.above_quasi_static = true;
      if (grade == sim::ContactGrade::kCritical) m.critical_contact = true;
      if (f > 0 && !permitted(e, contact, s.time)) m.human_contact = true;
    }
  }
  m.collision_free = !m.human_contact && !m.environment_collision;
}

void score_separation(const Episode& e, EpisodeMetrics& m) {
  TimeSet permitted_phases;
  for (const PermittedContact& p : e.contract.permitted_contacts) {
    if (const auto phase = e.interval(p.phase)) permitted_phases.push_back(*phase);
  }
  permitted_phases = normalized(std::move(permitted_phases));
  const auto& steps = e.log.steps;
  for (size_t k = 1; k < steps.size(); ++k) {
    const StepRecord& s = steps[k];
    const double dt = s.time - steps[k - 1].time;
    if (!(s.separation <= e.c.monitored_distance)) continue;
    m.monitored_time += dt;
    const bool violation =
        contains(permitted_phases, s.time)
            ? s.closest_point_speed > e.c.permitted_speed && s.separation < e.c.permitted_distance
            : s.separation < protective_separation(s.approach_speed, s.separation, e.c);
    if (violation) m.violation_time += dt;
  }
  const double share = m.monitored_time > 0 ? 1.0 - m.violation_time / m.monitored_time : 1.0;
  m.hcs = m.above_quasi_static ? 0.0 : std::max(0.0, share);
}

void score_idle(const Episode& e, EpisodeMetrics& m) {
  const std::optional<double> from =
      e.contract.allowed_from.empty() ? std::optional<double>(e.t0) : e.event(e.contract.allowed_from);
  if (!from) return;
  // SSM-required stops: even a resting robot would be too close.
  TimeSet ssm;
  const auto& steps = e.log.steps;
  for (size_t k = 1; k < steps.size(); ++k) {
    const double d = steps[k].separation;
    if (d < protective_separation(0.0, d, e.c)) ssm.push_back({steps[k - 1].time, steps[k].time});
  }
  const TimeSet waits = unite(e.intervals(e.contract.robot_waits), normalized(std::move(ssm)));
  const TimeSet allowed = subtract(normalized({{*from, e.t_end}}), waits);
  const double length = total_length(allowed);
  if (length <= e.c.time_epsilon) return;
  m.idle_ratio = total_length(intersect(e.still, allowed)) / length;
}

// [start, end] of every act of one actor (robot acts from the detected onsets).
TimeSet act_intervals(const Episode& e, Actor actor) {
  TimeSet set;
  if (actor == Actor::kRobot) {
    for (size_t i = 0; i < e.contract.robot_acts.size(); ++i) {
      if (!e.onsets[i]) continue;
      const auto end = e.log.event_time(e.contract.robot_acts[i].name + ".end");
      set.push_back({*e.onsets[i], end.value_or(e.t_end)});
    }
    return set;
  }
  for (const Event& start : e.log.events) {
    if (start.kind != EventKind::kActStart || start.actor != actor) continue;
    const std::string act = start.name.substr(0, start.name.rfind('.'));
    double to = e.t_end;
    for (const Event& end : e.log.events) {
      if (end.kind == EventKind::kActEnd && end.time >= start.time && end.name == act + ".end") {
        to = end.time;
        break;
      }
    }
    set.push_back({start.time, to});
  }
  return set;
}

// Mean delay from an act of one agent ending (while the other is not acting) to the other
// agent's next act start.
std::optional<double> functional_delay(const TimeSet& human_raw, const TimeSet& robot_raw,
                                       double eps) {
  double sum = 0;
  int count = 0;
  const auto handoffs = [&](const TimeSet& finished, const TimeSet& next) {
    for (const TimeInterval& act : finished) {
      const double t_e = act.to;
      const bool other_busy = std::any_of(next.begin(), next.end(), [&](const TimeInterval& o) {
        return o.from < t_e - eps && t_e < o.to;
      });
      if (other_busy) continue;
      std::optional<double> start;
      for (const TimeInterval& o : next) {
        if (o.from >= t_e - eps && (!start || o.from < *start)) start = o.from;
      }
      if (!start) continue;
      sum += std::max(0.0, *start - t_e);
      ++count;
    }
  };
  handoffs(human_raw, robot_raw);
  handoffs(robot_raw, human_raw);
  if (count == 0) return std::nullopt;
  return sum / count;
}

void score_fluency(const Episode& e, EpisodeMetrics& m) {
  const double length = e.t_end - e.t0;
  if (length <= e.c.time_epsilon) return;
  const TimeSet task = {{e.t0, e.t_end}};
  m.r_idle = total_length(intersect(e.still, task)) / length;
  if (!e.contract.human_waits.empty()) {
    m.h_idle = total_length(intersect(e.intervals(e.contract.human_waits), task)) / length;
  }
  const TimeSet human_raw = act_intervals(e, Actor::kHuman);
  const TimeSet robot_raw = act_intervals(e, Actor::kRobot);
  m.c_act = total_length(intersect(e.moving, normalized(human_raw))) / length;
  m.f_del = functional_delay(human_raw, robot_raw, e.c.time_epsilon);
}

// The task's success bounds the separation violation time and it was exceeded. The time is a
// sum of control periods, so a violation as long as the bound sums to it only up to rounding
// (30 steps of 50 ms gave 1.5 + 2e-13 s at 2.5 ms physics steps, 1.5 - 3e-14 s at 5 ms): it is
// within the bound whichever way the sum rounds (docs/metrics.md).
bool violation_exceeded(const Episode& e, const EpisodeMetrics& m) {
  const std::optional<double>& bound = e.contract.success_max_violation;
  return bound && m.violation_time > *bound + e.c.time_epsilon;
}

void label_failures(const Episode& e, EpisodeMetrics& m) {
  const auto add = [&](bool applies, FailureLabel label) {
    if (applies) m.labels.push_back(label);
  };
  const bool held_at_end = m.success_since.has_value() &&
                           e.t_end - *m.success_since >= e.c.success_hold - e.c.time_epsilon;
  add(e.log.status == core::EpisodeStatus::kInvalid, FailureLabel::kInvalid);
  add(e.log.status == core::EpisodeStatus::kPolicyError, FailureLabel::kPolicyError);
  add(m.critical_contact, FailureLabel::kCriticalContact);
  add(m.human_contact, FailureLabel::kContact);
  add(m.environment_collision, FailureLabel::kCollision);
  add((m.order_compliance && *m.order_compliance < 1.0) ||
          std::any_of(m.cues.begin(), m.cues.end(), [](const CueResult& r) { return r.premature; }),
      FailureLabel::kPremature);
  add(ever(series(e.log, e.contract.wrong_target_predicate)), FailureLabel::kWrongTarget);
  add(m.cir && *m.cir == 0.0, FailureLabel::kIgnoredContradiction);
  add(std::any_of(m.cues.begin(), m.cues.end(),
                  [](const CueResult& r) { return !r.responded && !r.premature; }),
      FailureLabel::kNoResponse);
  add(m.tsync && *m.tsync < e.c.desync_below, FailureLabel::kDesync);
  add(m.hcs < e.c.unsafe_proximity_below || violation_exceeded(e, m),
      FailureLabel::kUnsafeProximity);
  add(ever(series(e.log, e.contract.dropped_predicate)), FailureLabel::kDrop);
  add(m.dsr && *m.dsr == 0.0, FailureLabel::kNoRecovery);
  add(ever(series(e.log, e.contract.grasp_failed_predicate)), FailureLabel::kManipulation);
  add(!held_at_end, FailureLabel::kTimeout);
  if (!m.success) {
    HRIB_CHECK(!m.labels.empty()) << "a failed episode without a label";
    m.primary_label = m.labels.front();
  }
}

}  // namespace

std::optional<double> final_run_start(const EpisodeLog& log, size_t index) {
  const auto& steps = log.steps;
  if (steps.empty() || !steps.back().predicates[index]) return std::nullopt;
  size_t first = steps.size() - 1;
  while (first > 0 && steps[first - 1].predicates[index]) --first;
  return steps[first].time;
}

std::vector<std::optional<double>> robot_act_onsets(const ScenarioContract& contract,
                                                    const EpisodeLog& log,
                                                    const MetricConstants& c) {
  return detect_onsets(contract, log, moving_time(log, c), c);
}

std::optional<double> resolve_event(const ScenarioContract& contract, const EpisodeLog& log,
                                    std::string_view name, const MetricConstants& c) {
  const TimeSet moving = moving_time(log, c);
  const Episode e{contract, log, c, detect_onsets(contract, log, moving, c), moving, {},
                  start_time(log), end_time(log)};
  return e.event(name);
}

double protective_separation(double approach_speed, double separation, const MetricConstants& c) {
  const double v_r = std::max(0.0, approach_speed);
  const double v_h = separation < c.human_speed_near_distance ? c.human_speed_near : c.human_speed;
  const double t_s = v_r / c.stop_deceleration;
  const double b = v_r * v_r / (2.0 * c.stop_deceleration);
  return v_h * (c.reaction_time + t_s) + v_r * c.reaction_time + b + c.intrusion_distance +
         c.position_uncertainty;
}

EpisodeMetrics compute_metrics(const ScenarioContract& contract, const EpisodeLog& log,
                               const MetricConstants& c) {
  check_episode_log(log, "episode log");
  const TimeSet moving = moving_time(log, c);
  const Episode e{contract,      log,           c, detect_onsets(contract, log, moving, c),
                  moving,        still_time(log, c), start_time(log), end_time(log)};
  EpisodeMetrics m;
  score_success(e, m);
  score_cues(e, m);
  score_syncs(e, m);
  score_orders(e, m);
  score_contacts(e, m);
  score_separation(e, m);
  // CIR: the latest intent holds at the end and the contradicted outcome never held.
  if (contract.contradiction &&
      (contract.contradiction_event.empty() || e.event(contract.contradiction_event))) {
    const std::vector<bool> intent = required_series(log, contract.intent_predicate);
    const std::vector<bool> contradicted = required_series(log, contract.contradicted_predicate);
    const bool ok = !intent.empty() && intent.back() &&
                    std::find(contradicted.begin(), contradicted.end(), true) == contradicted.end();
    m.cir = ok ? 1.0 : 0.0;
  }
  // CSR: held at the end for success_hold, every order met, no critical contact, valid.
  const bool held = m.success_since && e.t_end - *m.success_since >= c.success_hold - c.time_epsilon;
  m.success = held && log.status == core::EpisodeStatus::kOk && !m.critical_contact &&
              (!m.order_compliance || *m.order_compliance >= 1.0) &&
              !(contract.success_requires_no_contact && m.human_contact) &&
              !violation_exceeded(e, m);
  m.completion_time = m.success ? *m.success_since : log.horizon;
  // IR and fluency describe how the task was done: a failed episode has none to describe
  // (docs/metrics.md: a robot that never rests would otherwise idle least).
  if (m.success) {
    score_idle(e, m);
    score_fluency(e, m);
  }
  // DSR: success after the disruption, without critical contact.
  if (!contract.disruption_event.empty() && e.event(contract.disruption_event)) {
    m.dsr = m.success && !m.critical_contact ? 1.0 : 0.0;
  }
  label_failures(e, m);
  return m;
}

}  // namespace hribench::eval

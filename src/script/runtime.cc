#include "script/runtime.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/errors.h"
#include "script/phases.h"

namespace hribench::script {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kTimeEps = 1e-9;  // a scheduled time "has come" within this of the step time

int add_event(ActGraph& g, std::string name) {
  g.event_names.push_back(std::move(name));
  return static_cast<int>(g.event_names.size()) - 1;
}

int add_predicate(ActGraph& g, const Pred& p) {
  for (size_t i = 0; i < g.predicates.size(); ++i) {
    if (g.predicates[i].source == p.source) return static_cast<int>(i);
  }
  try {
    g.predicates.push_back(bind_predicate(p.source, g.objects));
  } catch (const core::InputError& e) {
    throw core::InputError(p.where.text, e.expected(), e.got());
  }
  return static_cast<int>(g.predicates.size()) - 1;
}

void watch(ActGraph& g, int predicate) {
  if (std::find(g.watched.begin(), g.watched.end(), predicate) != g.watched.end()) return;
  g.watched.push_back(predicate);
  const std::string& source = g.predicates[static_cast<size_t>(predicate)].source;
  g.watch_true_event.push_back(add_event(g, source + ":true"));
  g.watch_false_event.push_back(add_event(g, source + ":false"));
}

void record(RuntimeState& s, int id, double time) {
  s.pending.push_back({time, id});
  double& first = s.event_time[static_cast<size_t>(id)];
  if (std::isnan(first)) first = time;
}

void end_act(const CompiledAct& act, ActState& a, RuntimeState& s, double time) {
  a.status = ActStatus::kDone;
  record(s, act.end_event, time);
}

// Moves a running human act through every phase that has ended by time t.
void advance(const ActGraph& g, const CompiledAct& act, ActState& a, RuntimeState& s, double t) {
  while (a.status == ActStatus::kRunning) {
    const CompiledPhase& phase = act.phases[a.phase];
    double end = a.phase_start + phase.duration;
    if (phase.waits && act.until >= 0) {
      if (s.value[static_cast<size_t>(act.until)] && a.until_since < 0) a.until_since = t;
      if (a.until_since < 0) return;  // still waiting for the signal
      end = std::max(end, a.until_since);
    }
    if (end > t + kTimeEps) return;
    a.until_since = -1;
    if (a.phase + 1 == act.phases.size()) {
      end_act(act, a, s, end);
      return;
    }
    ++a.phase;
    a.phase_start = end;
    if (act.phases[a.phase].event >= 0) record(s, act.phases[a.phase].event, end);
    (void)g;
  }
}

// Starts a human act at `time`: supersedes running acts of the same hand.
void start_act(const ActGraph& g, size_t index, RuntimeState& s, double time) {
  const CompiledAct& act = g.acts[index];
  for (size_t j = 0; j < g.acts.size(); ++j) {
    ActState& other = s.acts[j];
    if (j == index || other.status != ActStatus::kRunning || !g.acts[j].human) continue;
    if (g.acts[j].hand == act.hand) end_act(g.acts[j], other, s, time);
  }
  ActState& a = s.acts[index];
  a.status = ActStatus::kRunning;
  a.start = time;
  a.phase = 0;
  a.phase_start = time;
  a.until_since = -1;
  record(s, act.start_event, time);
  if (act.phases.empty()) {
    end_act(act, a, s, time);
    return;
  }
  if (act.phases[0].event >= 0) record(s, act.phases[0].event, time);
  if (act.fails && s.failed_at < 0) s.failed_at = time;
}

// The time a waiting human act is due, or NaN when its time/event conditions do not hold yet.
double due_time(const CompiledAct& act, const RuntimeState& s, double t) {
  double due = act.onset;
  if (act.after_event >= 0) {
    const double e = s.event_time[static_cast<size_t>(act.after_event)];
    if (std::isnan(e)) return kNaN;
    due = std::max(due, e + act.delay);
  }
  if (due > t + kTimeEps) return kNaN;
  if (act.when >= 0) {
    if (!s.value[static_cast<size_t>(act.when)]) return kNaN;
    due = t;  // caused by a predicate: the step that observed it
  }
  return due;
}

}  // namespace

int ActGraph::event_id(std::string_view name) const {
  for (size_t i = 0; i < event_names.size(); ++i) {
    if (event_names[i] == name) return static_cast<int>(i);
  }
  return -1;
}

ActGraph compile(const EpisodeSpec& spec) {
  ActGraph g;
  g.horizon = spec.horizon;
  for (const Entry<SceneObject>& o : spec.scene.objects) g.objects.push_back(o.name);
  const core::Vec3 stand(spec.human.stand.x.value(), spec.human.stand.y.value(), 0);
  // Events of every act first, so `after` can name any act.
  for (const Entry<Act>& e : spec.acts) {
    CompiledAct act;
    act.name = e.name;
    act.human = e.value.actor == "human";
    act.start_event = add_event(g, e.name + ".start");
    if (act.human && e.value.motion) {
      const Motion& m = *e.value.motion;
      const double onset = motion_onset(m);
      if (onset > 0) act.phases.push_back({"", onset, false, -1});
      for (const PhaseTiming& p : phase_timing(m, stand)) {
        act.phases.push_back({p.name, p.duration, p.waits, add_event(g, e.name + "." + p.name)});
      }
      if (const ValueTree* hand = find_param(m, "hand"); hand && hand->kind == ValueTree::Kind::kScalar) {
        act.hand = hand->scalar.expr.text == "left" ? kLeftHand : kRightHand;
      }
    }
    act.end_event = add_event(g, e.name + ".end");
    if (act.human) act.skipped_event = add_event(g, e.name + ".skipped");
    g.acts.push_back(std::move(act));
  }
  for (size_t i = 0; i < spec.acts.size(); ++i) {
    const Act& a = spec.acts[i].value;
    CompiledAct& act = g.acts[i];
    if (a.after) {
      act.after_event = g.event_id(*a.after);
      if (act.after_event < 0) throw core::InputError(spec.acts[i].where.text, "a known event", "'" + *a.after + "'");
    }
    if (a.onset) act.onset = a.onset->value();
    if (a.delay) act.delay = a.delay->value();
    act.fails = a.fails;
    if (a.when) act.when = add_predicate(g, *a.when);
    if (a.unless) act.unless = add_predicate(g, *a.unless);
    if (a.motion && a.motion->until) act.until = add_predicate(g, *a.motion->until);
    if (a.goal) {
      act.goal = add_predicate(g, *a.goal);
      watch(g, act.goal);
    }
    // What the metrics need: cues, disruption, contradiction, robot constraints.
    const auto event = [&](const std::string& name) {
      const int id = g.event_id(name);
      if (id < 0) throw core::InputError(spec.acts[i].where.text, "a known event", "'" + name + "'");
      return id;
    };
    if (a.cue) act.cue = CompiledCue{event(a.cue->at), a.cue->window.value(), a.cue->kind};
    act.disruption = a.disruption;
    if (a.contradicts) {
      for (size_t j = 0; j < spec.acts.size(); ++j) {
        if (spec.acts[j].name == *a.contradicts) act.contradicts = static_cast<int>(j);
      }
    }
    if (!act.human) {
      RobotConstraints& c = act.constraints;
      c.after = act.after_event;
      if (a.before) c.before = event(*a.before);
      if (a.within) c.within = a.within->value();
      if (a.sync) {
        c.sync_with = event(a.sync->with);
        c.sync_offset = a.sync->offset.value();
        c.sync_tolerance = a.sync->tolerance.value();
      }
      if (a.still) {
        c.still_from = event(a.still->from);
        c.still_to = event(a.still->to);
      }
    }
  }
  for (const Pred& p : spec.success) {
    const int index = add_predicate(g, p);
    g.success.push_back(index);
    watch(g, index);
  }
  return g;
}

RuntimeState make_runtime(const ActGraph& graph) {
  RuntimeState s;
  s.pending.reserve(64);
  s.events.reserve(256);
  reset(graph, s);
  return s;
}

void reset(const ActGraph& graph, RuntimeState& s) {
  s.acts.assign(graph.acts.size(), ActState{});
  s.event_time.assign(graph.event_names.size(), kNaN);
  s.events.clear();
  s.memory.clear();
  for (const BoundPredicate& p : graph.predicates) s.memory.push_back(make_memory(p));
  s.value.assign(graph.predicates.size(), 0);
  s.watched_value.assign(graph.watched.size(), 0);
  s.failed_at = -1;
  s.pending.clear();
}

void step(const ActGraph& g, RuntimeState& s, const WorldSnapshot& world) {
  const double t = world.time;
  s.pending.clear();
  // 1. Predicates, once per step (memories advance in time order).
  for (size_t i = 0; i < g.predicates.size(); ++i) {
    s.value[i] = evaluate(g.predicates[i], world, s.memory[i]) ? 1 : 0;
  }
  // 2-4. Acts, until nothing changes (an event can trigger another act in the same step).
  for (size_t round = 0; round <= 2 * g.acts.size() + 2; ++round) {
    const size_t before = s.pending.size();
    for (size_t i = 0; i < g.acts.size(); ++i) {
      const CompiledAct& act = g.acts[i];
      ActState& a = s.acts[i];
      if (!act.human) continue;
      if (a.status == ActStatus::kRunning) advance(g, act, a, s, t);
      if (a.status != ActStatus::kWaiting) continue;
      const double due = due_time(act, s, t);
      if (std::isnan(due)) continue;
      if (act.unless >= 0 && s.value[static_cast<size_t>(act.unless)]) {
        a.status = ActStatus::kSkipped;
        record(s, act.skipped_event, due);
        continue;
      }
      start_act(g, i, s, due);
      advance(g, act, a, s, t);
    }
    if (s.pending.size() == before) break;
  }
  // 5. Robot acts end when their goal first holds.
  for (size_t i = 0; i < g.acts.size(); ++i) {
    const CompiledAct& act = g.acts[i];
    if (act.human || s.acts[i].status == ActStatus::kDone) continue;
    if (act.goal >= 0 && s.value[static_cast<size_t>(act.goal)]) {
      s.acts[i].status = ActStatus::kDone;
      record(s, act.end_event, t);
    }
  }
  // 6. Changes of watched predicates (all start false).
  for (size_t k = 0; k < g.watched.size(); ++k) {
    const size_t p = static_cast<size_t>(g.watched[k]);
    const int true_event = g.watch_true_event[k];
    const int false_event = g.watch_false_event[k];
    char& was = s.watched_value[k];
    if (s.value[p] != was) record(s, s.value[p] ? true_event : false_event, t);
    was = s.value[p];
  }
  // The step's events, in time order, join the log.
  std::stable_sort(s.pending.begin(), s.pending.end(),
                   [](const Event& a, const Event& b) { return a.time < b.time; });
  s.events.insert(s.events.end(), s.pending.begin(), s.pending.end());
}

double event_time(const ActGraph& graph, const RuntimeState& state, std::string_view name) {
  const int id = graph.event_id(name);
  return id < 0 ? kNaN : state.event_time[static_cast<size_t>(id)];
}

}  // namespace hribench::script

#include "script/check.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <fstream>
#include <set>
#include <sstream>

#include "human/primitives.h"
#include "script/catalogue.h"
#include "script/phases.h"
#include "script/predicate.h"
#include "script/schema_io.h"
#include "script/walk.h"

namespace hribench::script {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

std::string join(const std::vector<std::string>& items) {
  std::string s;
  for (size_t i = 0; i < items.size(); ++i) s += (i ? ", " : "") + items[i];
  return s;
}
std::string fmt(double x) { return std::isfinite(x) ? format_number(std::round(x * 1000) / 1000) : "inf"; }
bool contains(const std::vector<std::string>& v, const std::string& s) {
  return std::find(v.begin(), v.end(), s) != v.end();
}

// One act of the script (top level or from a variant), with what the checks need.
struct ActInfo {
  std::string name;
  std::string path;                  // "acts.offer" or "variants.cancel.acts.wave"
  std::string variant;               // "" for a top-level act
  const Act* act = nullptr;
  bool human = false;
  std::vector<std::string> phases;   // human: the primitive's phases (common to all choices)
  std::vector<double> min_phase;     // their minimum durations
  bool phases_known = true;          // false when the motion is missing or unknown
  double min_motion_onset = 0;
  size_t node = 0;                   // graph node of ACT.start; phases follow; then ACT.end
};

struct Edge {
  size_t from, to;
  double min_delay;
  bool causal;  // a trigger or a duration (not a requirement such as `before`)
};

class Validator {
 public:
  explicit Validator(const Scenario& s) : s_(s) {}

  std::vector<core::InputError> run() {
    collect_vars();
    collect_objects();
    check_header();
    check_values();
    check_scene();
    check_human();
    collect_acts();
    // An act sees the top-level acts and those of its own variant; the rest of the script sees
    // only the top-level acts (a variant's acts do not exist in the other variants' episodes).
    for (ActInfo& a : acts_) {
      scope_ = a.variant;
      check_act(a);
    }
    scope_.clear();
    check_success();
    check_safety();
    check_instruction();
    check_graph();
    return std::move(out_);
  }

 private:
  // Location of a key path: its own, or the nearest enclosing key's, or the file.
  std::string loc(std::string path) const {
    while (true) {
      const auto it = s_.locations.find(path);
      if (it != s_.locations.end()) return it->second;
      const size_t dot = path.find_last_of(".[");
      if (dot == std::string::npos) break;
      path = path.substr(0, dot);
    }
    return s_.file + ":1:1";
  }
  void problem(const std::string& path, std::string expected, std::string got) {
    out_.push_back(core::InputError(loc(path), std::move(expected), std::move(got)));
  }
  void problem_at(const std::string& where, std::string expected, std::string got) {
    out_.push_back(core::InputError(where, std::move(expected), std::move(got)));
  }

  std::string var_list() const {
    return var_names_.empty() ? "a defined var (none is defined)" : "a defined var (vars: " + join(var_names_) + ")";
  }

  // --- vars --------------------------------------------------------------------------------
  void add_var(const Entry<Any>& v, const std::string& path) {
    for (const std::string& ref : var_refs(v.value.expr)) {
      if (!contains(var_names_, ref)) {
        problem(path, "a var defined above $" + ref + " (vars: " + join(var_names_) + ")", "$" + ref);
      }
    }
    if (contains(var_names_, v.name)) problem(path, "each var name once", "'" + v.name + "' again");
    var_names_.push_back(v.name);
    var_defs_.push_back(v.value.expr);
    if (expr_type(v.value.expr, var_names_, var_defs_) == "mixed") {
      problem(path, "a var of numbers or of words", "a mix: " + to_source(v.value.expr));
    }
  }
  void collect_vars() {
    for (const Entry<Any>& v : s_.vars) add_var(v, "vars." + v.name);
    for (const Entry<Variant>& variant : s_.variants) {
      for (const Entry<Any>& v : variant.value.vars) add_var(v, "variants." + variant.name + ".vars." + v.name);
    }
  }

  // Every value: references defined and of the right type.
  void check_values() {
    struct Visitor {
      Validator& self;
      void operator()(Param& p, ParamType type) {
        if (p.bad) return;
        for (const std::string& ref : var_refs(p.expr)) {
          if (!contains(self.var_names_, ref)) {
            self.problem_at(p.where.text, self.var_list(), "$" + ref);
            continue;
          }
          Expr e;
          e.kind = Expr::Kind::kVar;
          e.text = ref;
          const std::string t = expr_type(e, self.var_names_, self.var_defs_);
          if (type == ParamType::kNumber && t == "string") {
            self.problem_at(p.where.text, "a number", "$" + ref + ", a var of words");
          }
        }
      }
      void operator()(Pred& p) {
        for (const std::string& ref : template_refs(p.source)) {
          if (!contains(self.var_names_, ref)) {
            self.problem_at(p.where.text, self.var_list(), "$" + ref);
          }
        }
      }
    };
    Visitor v{*this};
    Scenario& s = const_cast<Scenario&>(s_);  // walk_params takes non-const; nothing is changed
    walk_params(s, v);
  }

  // Words a Text can take; empty + problem when they cannot be known.
  std::vector<std::string> words(const Param& p, const std::string& what) {
    if (p.bad) return {};
    for (const std::string& ref : var_refs(p.expr)) {
      if (!contains(var_names_, ref)) return {};  // reported by check_values
    }
    const StringSet set = string_values(p.expr, var_names_, var_defs_);
    if (!set.complete) {
      problem_at(p.where.text, what + " (a word, or a choice or var of words)", "'" + to_source(p.expr) + "'");
      return {};
    }
    return set.values;
  }
  void check_words(const Param& p, const std::vector<std::string>& allowed, const std::string& what) {
    for (const std::string& w : words(p, what)) {
      if (!contains(allowed, w)) problem_at(p.where.text, what + " (" + join(allowed) + ")", "'" + w + "'");
    }
  }
  Range range(const Param& p) const { return value_range(p.expr, var_names_, var_defs_); }
  void check_range(const Param& p, double lo, double hi, const std::string& what) {
    if (p.bad) return;
    const Range r = range(p);
    if (r.lo < lo || r.hi > hi) {
      problem_at(p.where.text, what + " in [" + fmt(lo) + ", " + fmt(hi) + "]",
                 to_source(p.expr) + (p.expr.kind == Expr::Kind::kNumber ? "" : " (range [" + fmt(r.lo) + ", " + fmt(r.hi) + "])"));
    }
  }

  // --- header ------------------------------------------------------------------------------
  void check_header() {
    if (s_.locations.count("hribench") && s_.hribench != 1) {
      problem("hribench", "schema version 1", std::to_string(s_.hribench));
    }
    if (s_.locations.count("role") && !contains({"instructor", "collaborator", "intruder"}, s_.role)) {
      problem("role", "instructor, collaborator or intruder", "'" + s_.role + "'");
    }
    if (s_.locations.count("task")) {
      const bool ok = !s_.task.empty() && std::all_of(s_.task.begin(), s_.task.end(), [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
      });
      if (!ok) problem("task", "a lower_snake_case name", "'" + s_.task + "'");
    }
    if (!(s_.horizon > 0 && s_.horizon <= 600)) problem("horizon", "a horizon in (0, 600] s", fmt(s_.horizon));
    double weight_sum = 0;
    for (const Entry<Variant>& v : s_.variants) {
      const Range r = range(v.value.weight);
      if (!v.value.weight.bad && (!(r.lo > 0) || v.value.weight.expr.kind != Expr::Kind::kNumber)) {
        problem("variants." + v.name + ".weight", "a weight > 0", to_source(v.value.weight.expr));
      }
      weight_sum += r.lo;
    }
    (void)weight_sum;
  }

  // --- scene -------------------------------------------------------------------------------
  void collect_objects() {
    for (const Entry<SceneObject>& o : s_.scene.objects) objects_.push_back(o.name);
  }
  void check_scene() {
    if (s_.locations.count("scene") && s_.scene.objects.empty()) {
      problem("scene.objects", "at least one object", "none");
    }
    for (const Entry<SceneObject>& e : s_.scene.objects) {
      const SceneObject& o = e.value;
      const std::string path = "scene.objects." + e.name;
      if (e.name == "robot" || e.name == "table" || e.name == "human") {
        problem(path, "an object name other than robot, table, human", "'" + e.name + "'");
      }
      check_words(o.kind, object_kinds(), "an object kind");
      if (o.color) check_words(*o.color, object_colors(), "a colour");
      if (o.held_by) check_words(*o.held_by, {"human.left", "human.right"}, "a holder");
      if (o.in) {
        for (const std::string& w : words(*o.in, "a container object")) {
          if (!contains(objects_, w) || w == e.name) problem_at(o.in->where.text, "another scene object (" + join(objects_) + ")", "'" + w + "'");
        }
      }
      if (o.held_by && (o.pose || o.in)) problem(path, "held_by without pose or in", "both");
      if (o.pose) {
        if (o.pose->xy.size() != 2) problem(path + ".pose.xy", "[x, y]", std::to_string(o.pose->xy.size()) + " values");
        for (const Num& n : o.pose->xy) check_range(n, -2, 2, "a coordinate, m,");
        if (o.pose->z) check_range(*o.pose->z, 0, 2.5, "a height, m,");
      }
      if (!o.size.empty()) {
        if (o.size.size() != 3) problem(path + ".size", "[x, y, z] sizes", std::to_string(o.size.size()) + " values");
        for (const Num& n : o.size) check_range(n, 0.005, 1.5, "a size, m,");
      }
    }
    check_range(s_.scene.distractors.count, 0, 8, "a distractor count");
    for (const Text& k : s_.scene.distractors.kinds) check_words(k, object_kinds(), "an object kind");
  }

  void check_human() {
    check_range(s_.human.height, 1.4, 2.1, "a body height, m,");
    check_range(s_.human.stand.x, -3, 3, "a stand position, m,");
    check_range(s_.human.stand.y, -3, 3, "a stand position, m,");
    check_words(s_.human.handedness, {"left", "right"}, "a hand");
  }

  // --- acts --------------------------------------------------------------------------------
  void collect_acts() {
    for (const Entry<Act>& a : s_.acts) add_act(a.name, "acts." + a.name, &a.value, "");
    for (const Entry<Variant>& v : s_.variants) {
      for (const Entry<Act>& a : v.value.acts) {
        const std::string path = "variants." + v.name + ".acts." + a.name;
        const bool clash = std::any_of(s_.acts.begin(), s_.acts.end(), [&](const Entry<Act>& b) { return b.name == a.name; });
        if (clash) {
          problem(path, "an act name not used by the top-level acts", "'" + a.name + "' again");
          continue;
        }
        add_act(a.name, path, &a.value, v.name);
      }
    }
    size_t node = 0;
    for (ActInfo& a : acts_) {
      a.human = a.act->actor == "human";
      if (a.human && a.act->motion) resolve_phases(a);
      a.phases_known = !a.human || (a.act->motion && (a.act->motion->clip || !a.phases.empty()));
      a.node = node;
      node += a.phases.size() + 2;
    }
    node_count_ = node;
  }

  void add_act(const std::string& name, const std::string& path, const Act* act, const std::string& variant) {
    ActInfo info;
    info.variant = variant;
    info.name = name;
    info.path = path;
    info.act = act;
    acts_.push_back(std::move(info));
  }

  // The primitive(s) of a human act and their phases.
  void resolve_phases(ActInfo& a) {
    const Motion& m = *a.act->motion;
    if (m.clip) {
      a.phases = {"play"};
      a.min_phase = {0};
      return;
    }
    if (!m.primitive) return;
    const StringSet names = string_values(m.primitive->expr, var_names_, var_defs_);
    bool first = true;
    for (const std::string& name : names.values) {
      const human::PrimitiveInfo* p = human::find_primitive(name);
      if (p == nullptr) continue;
      std::vector<std::string> ph = phase_names(*p);
      if (first) {
        a.phases = ph;
        a.min_phase.assign(ph.size(), kInf);
        first = false;
      }
      std::vector<std::string> common;
      std::vector<double> mins;
      for (size_t i = 0; i < a.phases.size(); ++i) {
        const auto it = std::find(ph.begin(), ph.end(), a.phases[i]);
        if (it == ph.end()) continue;
        common.push_back(a.phases[i]);
        mins.push_back(std::min(a.min_phase[i], min_duration(m, *p, static_cast<size_t>(it - ph.begin()))));
      }
      a.phases = common;
      a.min_phase = mins;
    }
    if (const ValueTree* onset = find_param(m, "onset"); onset && onset->kind == ValueTree::Kind::kScalar) {
      a.min_motion_onset = std::max(0.0, range(onset->scalar).lo);
    }
  }
  double min_duration(const Motion& m, const human::PrimitiveInfo& p, size_t phase) {
    const std::string param = phase_parameter(p, phase);
    if (param.empty()) return 0;
    const ValueTree* v = find_param(m, param);
    if (v != nullptr && v->kind == ValueTree::Kind::kScalar) return std::max(0.0, range(v->scalar).lo);
    const human::ParamInfo* info = p.param(param);
    return info != nullptr && info->has_default ? info->default_value : 0;
  }

  void check_act(const ActInfo& a) {
    const Act& act = *a.act;
    const std::string& path = a.path;
    if (act.actor != "human" && act.actor != "robot") {
      problem(path + ".actor", "human or robot", "'" + act.actor + "'");
      return;
    }
    const auto forbid = [&](bool present, const char* key, const char* who) {
      if (present) problem(path + "." + key, std::string("no '") + key + "' on a " + who + " act", std::string("'") + key + "'");
    };
    if (a.human) {
      forbid(act.goal.has_value(), "goal", "human");
      forbid(act.before.has_value(), "before", "human");
      forbid(act.within.has_value(), "within", "human");
      forbid(act.sync.has_value(), "sync", "human");
      forbid(act.still.has_value(), "still", "human");
      if (!act.motion) {
        problem(path, "a key 'motion' (human acts move)", "none");
      } else {
        check_motion(a);
      }
      if (act.delay && !act.after) problem(path + ".delay", "'after' with 'delay'", "delay alone");
      if (act.delay) check_range(*act.delay, 0, 600, "a delay, s,");
      if (act.onset) check_range(*act.onset, 0, 600, "an onset, s,");
      if (act.after) event(*act.after, path + ".after");
      if (act.cue) {
        event(act.cue->at, path + ".cue.at");
        const Range w = range(act.cue->window);
        if (!act.cue->window.bad && !(w.lo > 0)) problem(path + ".cue.window", "a window > 0 s", to_source(act.cue->window.expr));
        if (!contains({"go", "stop", "intrusion"}, act.cue->kind)) {
          problem(path + ".cue.kind", "go, stop or intrusion", "'" + act.cue->kind + "'");
        }
      }
      if (act.label) check_label(a);
      if (act.contradicts) {
        const ActInfo* target = find_act(*act.contradicts);
        if (target == nullptr || target->human) {
          problem(path + ".contradicts", "a robot act (" + join(robot_act_names()) + ")", "'" + *act.contradicts + "'");
        }
      }
      if (act.when) predicate(*act.when);
      if (act.unless) predicate(*act.unless);
    } else {
      forbid(act.motion.has_value(), "motion", "robot");
      forbid(act.onset.has_value(), "onset", "robot");
      forbid(act.delay.has_value(), "delay", "robot");
      forbid(act.when.has_value(), "when", "robot");
      forbid(act.unless.has_value(), "unless", "robot");
      forbid(act.cue.has_value(), "cue", "robot");
      forbid(act.label.has_value(), "label", "robot");
      forbid(act.disruption, "disruption", "robot");
      forbid(act.contradicts.has_value(), "contradicts", "robot");
      forbid(act.fails, "fails", "robot");
      if (!act.goal) {
        problem(path, "a key 'goal' (every robot act has a goal predicate)", "none");
      } else {
        predicate(*act.goal);
      }
      if (act.after) event(*act.after, path + ".after");
      if (act.before) event(*act.before, path + ".before");
      if (act.within) {
        if (!act.after) problem(path + ".within", "'after' with 'within' (the window starts at that event)", "within alone");
        const Range r = range(*act.within);
        if (!act.within->bad && !(r.lo > 0)) problem(path + ".within", "a response window > 0 s", to_source(act.within->expr));
      }
      if (act.sync) {
        event(act.sync->with, path + ".sync.with");
        if (!act.sync->tolerance.bad && !(range(act.sync->tolerance).lo > 0)) {
          problem(path + ".sync.tolerance", "a tolerance > 0 s", to_source(act.sync->tolerance.expr));
        }
      }
      if (act.still) {
        event(act.still->from, path + ".still.from");
        event(act.still->to, path + ".still.to");
      }
    }
  }

  void check_motion(const ActInfo& a) {
    const Motion& m = *a.act->motion;
    const std::string path = a.path + ".motion";
    if (m.primitive.has_value() == m.clip.has_value()) {
      problem(path, "exactly one of primitive, clip", m.primitive ? "both" : "neither");
      return;
    }
    if (m.until) predicate(*m.until);
    if (m.clip) {
      for (const Entry<ValueTree>& p : m.params) {
        if (p.name != "duration" && p.name != "hand") {
          problem(path + "." + p.name, "a clip parameter (duration, hand)", "'" + p.name + "'");
        }
      }
      const ValueTree* d = find_param(m, "duration");
      if (d == nullptr) {
        problem(path, "a key 'duration' (how long the clip plays, s)", "none");
      } else if (d->kind == ValueTree::Kind::kScalar) {
        check_range(d->scalar, 0.1, 600, "a clip duration, s,");
      }
      return;
    }
    std::vector<const human::PrimitiveInfo*> prims;
    for (const std::string& name : words(*m.primitive, "a motion primitive")) {
      const human::PrimitiveInfo* p = human::find_primitive(name);
      if (p == nullptr) {
        std::vector<std::string> known;
        for (const human::PrimitiveInfo& q : human::primitive_catalog()) known.emplace_back(q.name);
        problem_at(m.primitive->where.text, "a motion primitive (" + join(known) + ")", "'" + name + "'");
        continue;
      }
      prims.push_back(p);
    }
    for (const human::PrimitiveInfo* p : prims) {
      for (const Entry<ValueTree>& e : m.params) {
        const human::ParamInfo* info = p->param(e.name);
        if (info == nullptr) {
          std::vector<std::string> accepted;
          for (const human::ParamInfo& q : p->params) accepted.emplace_back(q.name);
          problem(path + "." + e.name, "a parameter of " + std::string(p->name) + " (" + join(accepted) + ")",
                  "'" + e.name + "'");
          continue;
        }
        check_param(*info, e.value, path + "." + e.name);
      }
      for (const human::ParamInfo& q : p->params) {
        if (q.required && find_param(m, std::string(q.name)) == nullptr) {
          problem(path, "a key '" + std::string(q.name) + "' (" + std::string(q.doc) + ")", "none");
        }
      }
    }
  }

  void check_point(const ValueTree& v, const std::string& path, const std::string& what) {
    if (v.kind == ValueTree::Kind::kScalar) {
      for (const std::string& w : words(v.scalar, what + ": [x, y, z] or a scene object")) {
        if (!contains(objects_, w)) problem_at(v.where.text, what + ": [x, y, z] or a scene object (" + join(objects_) + ")", "'" + w + "'");
      }
      return;
    }
    if (v.kind != ValueTree::Kind::kList || v.items.size() != 3) {
      problem(path, what + ": [x, y, z] in m", v.kind == ValueTree::Kind::kList ? std::to_string(v.items.size()) + " values" : "a mapping");
      return;
    }
    for (const ValueTree& c : v.items) {
      if (c.kind == ValueTree::Kind::kScalar && c.scalar.bad) continue;
      if (c.kind != ValueTree::Kind::kScalar || expr_type(c.scalar.expr, var_names_, var_defs_) != "number") {
        problem_at(c.where.text, "a coordinate (number or distribution)", c.kind == ValueTree::Kind::kScalar ? "'" + to_source(c.scalar.expr) + "'" : "a collection");
        continue;
      }
      check_range(c.scalar, -3, 3, "a coordinate, m,");
    }
  }

  void check_param(const human::ParamInfo& info, const ValueTree& v, const std::string& path) {
    const std::string name(info.name);
    switch (info.kind) {
      case human::ParamKind::kNumber:
        if (v.kind == ValueTree::Kind::kScalar && v.scalar.bad) return;
        if (v.kind != ValueTree::Kind::kScalar || expr_type(v.scalar.expr, var_names_, var_defs_) != "number") {
          problem(path, name + ": a number or distribution (" + std::string(info.unit) + ")",
                  v.kind == ValueTree::Kind::kScalar ? "'" + to_source(v.scalar.expr) + "'" : "a collection");
          return;
        }
        check_range(v.scalar, info.min, info.max, name + " (" + std::string(info.unit) + ")");
        return;
      case human::ParamKind::kSide:
      case human::ParamKind::kChoice: {
        if (v.kind != ValueTree::Kind::kScalar) {
          problem(path, name + ": a word", "a collection");
          return;
        }
        std::vector<std::string> options;
        for (std::string_view c : info.choices) options.emplace_back(c);
        check_words(v.scalar, options, name);
        return;
      }
      case human::ParamKind::kPoint:
        check_point(v, path, name);
        return;
      case human::ParamKind::kPoints:
        if (v.kind != ValueTree::Kind::kList) {
          problem(path, name + ": a list of points", "a single value");
          return;
        }
        for (size_t i = 0; i < v.items.size(); ++i) check_point(v.items[i], path + "[" + std::to_string(i) + "]", name);
        return;
      case human::ParamKind::kZone: {
        if (v.kind != ValueTree::Kind::kMap) {
          problem(path, name + ": {center: [x, y, z], radius: r}", v.kind == ValueTree::Kind::kList ? "a sequence" : "a value");
          return;
        }
        bool center = false, radius = false;
        for (size_t i = 0; i < v.keys.size(); ++i) {
          if (v.keys[i] == "center") {
            center = true;
            check_point(v.items[i], path + ".center", "center");
          } else if (v.keys[i] == "radius") {
            radius = true;
            if (v.items[i].kind != ValueTree::Kind::kScalar) {
              problem(path + ".radius", "a radius, m", "a collection");
            } else {
              check_range(v.items[i].scalar, info.min, info.max, "a zone radius, m,");
            }
          } else {
            problem(path + "." + v.keys[i], "a key of zone (center, radius)", "unknown key '" + v.keys[i] + "'");
          }
        }
        if (!center) problem(path, "a key 'center'", "none");
        if (!radius) problem(path, "a key 'radius'", "none");
        return;
      }
      case human::ParamKind::kObject:
        if (v.kind != ValueTree::Kind::kScalar) {
          problem(path, name + ": a scene object", "a collection");
          return;
        }
        check_words(v.scalar, objects_, "a scene object");
        return;
    }
  }

  void check_label(const ActInfo& a) {
    const Label& l = *a.act->label;
    const std::string path = a.path + ".label";
    event(l.during, path + ".during");
    const int checks = (l.in ? 1 : 0) + (l.through ? 1 : 0) + (l.crosses ? 1 : 0);
    if (checks != 1) problem(path, "exactly one of in, through, crosses", std::to_string(checks));
    // Hand points the human layer's label checks follow (human/labels.h), and its pointing ray.
    std::vector<std::string> points;
    for (const char* side : {"left.", "right."}) {
      for (const char* point : {"wrist", "palm", "hand", "index"}) points.push_back(std::string(side) + point);
    }
    if (l.joint) check_words(*l.joint, points, "a labelled hand point SIDE.POINT");
    if (!l.ray.empty()) {
      check_words(l.ray[0], {"left.shoulder", "right.shoulder"}, "a ray from SIDE.shoulder");
      if (l.ray.size() > 1) check_words(l.ray[1], {"left.index", "right.index"}, "a ray to SIDE.index");
    }
    if ((l.in || l.crosses) && !l.joint) problem(path, "a key 'joint' for in/crosses", "none");
    if (l.through) {
      if (l.ray.size() != 2) problem(path + ".ray", "[from, to] joints for through", std::to_string(l.ray.size()) + " joints");
      check_words(*l.through, objects_, "a scene object");
    }
    if (l.in) {
      const std::string& z = *l.in;
      const size_t dot = z.find('.');
      const ActInfo* target = dot == std::string::npos ? nullptr : find_act(z.substr(0, dot));
      const bool has_zone = target != nullptr && target->act->motion &&
                            find_param(*target->act->motion, "zone") != nullptr && z.substr(dot + 1) == "zone";
      if (!has_zone) problem(path + ".in", "ACT.zone of a human act with a zone", "'" + z + "'");
    }
    if (l.crosses && *l.crosses != "workspace") problem(path + ".crosses", "workspace", "'" + *l.crosses + "'");
  }

  // --- events and the constraint graph -----------------------------------------------------
  bool visible(const ActInfo& a) const { return a.variant.empty() || a.variant == scope_; }
  // An act the current scope may refer to, or nullptr.
  const ActInfo* find_act(const std::string& name) const {
    for (const ActInfo& a : acts_) {
      if (a.name == name && visible(a)) return &a;
    }
    return nullptr;
  }
  // Any act of the script (the constraint graph spans every variant).
  const ActInfo* find_any_act(const std::string& name) const {
    for (const ActInfo& a : acts_) {
      if (a.name == name) return &a;
    }
    return nullptr;
  }
  std::vector<std::string> act_names() const {
    std::vector<std::string> n;
    for (const ActInfo& a : acts_) {
      if (visible(a)) n.push_back(a.name);
    }
    return n;
  }
  std::vector<std::string> robot_act_names() const {
    std::vector<std::string> n;
    for (const ActInfo& a : acts_) {
      if (!a.human && visible(a)) n.push_back(a.name);
    }
    return n;
  }
  // Resolves "ACT.EVENT" to a graph node, reporting a problem at `path` when it cannot.
  // The acts an event's act name stands for: the visible act of that name, or, when every
  // variant defines an act of that name, those acts (each episode has exactly one of them).
  std::vector<const ActInfo*> acts_named(const std::string& name) const {
    if (const ActInfo* a = find_act(name)) return {a};
    std::vector<const ActInfo*> found;
    for (const Entry<Variant>& v : s_.variants) {
      const auto it = std::find_if(acts_.begin(), acts_.end(),
                                   [&](const ActInfo& a) { return a.name == name && a.variant == v.name; });
      if (it == acts_.end()) return {};
      found.push_back(&*it);
    }
    return found;
  }
  // Resolves "ACT.EVENT" to a graph node, reporting a problem at `path` when it cannot.
  std::optional<size_t> event(const std::string& text, const std::string& path) {
    const size_t dot = text.find('.');
    const std::vector<const ActInfo*> acts = dot == std::string::npos ? std::vector<const ActInfo*>{} : acts_named(text.substr(0, dot));
    if (acts.empty()) {
      problem(path, "an event ACT.start, ACT.end or ACT.PHASE (acts: " + join(act_names()) + ")", "'" + text + "'");
      return std::nullopt;
    }
    const std::string what = text.substr(dot + 1);
    std::optional<size_t> node;
    for (const ActInfo* a : acts) {
      std::optional<size_t> n;
      if (what == "start") n = a->node;
      if (what == "end") n = a->node + a->phases.size() + 1;
      const auto it = std::find(a->phases.begin(), a->phases.end(), what);
      if (it != a->phases.end()) n = a->node + 1 + static_cast<size_t>(it - a->phases.begin());
      if (!n && !a->phases_known) return std::nullopt;  // its motion is already reported
      if (!n) {
        std::vector<std::string> options = {"start", "end"};
        options.insert(options.end(), a->phases.begin(), a->phases.end());
        problem(path, "an event of act '" + a->name + "' (" + join(options) + ")", "'" + text + "'");
        return std::nullopt;
      }
      if (!node) node = n;
    }
    return node;
  }
  std::string node_name(size_t node) const {
    for (const ActInfo& a : acts_) {
      if (node < a.node || node > a.node + a.phases.size() + 1) continue;
      const size_t k = node - a.node;
      if (k == 0) return a.name + ".start";
      if (k == a.phases.size() + 1) return a.name + ".end";
      return a.name + "." + a.phases[k - 1];
    }
    return "?";
  }

  void check_graph() {
    std::vector<Edge> edges;
    std::vector<double> floor(node_count_, 0.0);  // earliest time from the act's own onset
    const size_t before = out_.size();
    for (const ActInfo& a : acts_) {
      const Act& act = *a.act;
      const size_t end = a.node + a.phases.size() + 1;
      if (a.human) {
        double gap = a.min_motion_onset;
        for (size_t i = 0; i < a.phases.size(); ++i) {
          edges.push_back({a.node + i, a.node + i + 1, gap, true});
          gap = a.min_phase[i];
        }
        edges.push_back({end - 1, end, a.phases.empty() ? 0.0 : gap, true});
        if (act.onset) floor[a.node] = std::max(0.0, range(*act.onset).lo);
        if (act.after) {
          if (auto e = quiet_event(*act.after)) edges.push_back({*e, a.node, act.delay ? std::max(0.0, range(*act.delay).lo) : 0.0, true});
        }
      } else {
        edges.push_back({a.node, end, 0.0, true});
        if (act.after) {
          if (auto e = quiet_event(*act.after)) edges.push_back({*e, a.node, 0.0, true});
        }
        if (act.before) {
          if (auto e = quiet_event(*act.before)) edges.push_back({end, *e, 0.0, false});
        }
      }
    }
    (void)before;
    // Cycles: an event that must come after itself.
    std::vector<std::vector<size_t>> next(node_count_);
    for (const Edge& e : edges) next[e.from].push_back(e.to);
    std::vector<int> state(node_count_, 0);  // 0 new, 1 on stack, 2 done
    std::vector<size_t> stack;
    bool cyclic = false;
    std::function<void(size_t)> dfs = [&](size_t u) {
      state[u] = 1;
      stack.push_back(u);
      for (size_t v : next[u]) {
        if (state[v] == 1 && !cyclic) {
          cyclic = true;
          std::string chain;
          const auto from = std::find(stack.begin(), stack.end(), v);
          for (auto it = from; it != stack.end(); ++it) chain += node_name(*it) + " -> ";
          chain += node_name(v);
          const ActInfo* a = owner(v);
          problem(a ? a->path : "acts", "an order of events without cycles", "the cycle " + chain);
        } else if (state[v] == 0) {
          dfs(v);
        }
      }
      stack.pop_back();
      state[u] = 2;
    };
    for (size_t u = 0; u < node_count_; ++u) {
      if (state[u] == 0) dfs(u);
    }
    if (cyclic) return;
    // Earliest time of every event (longest path over causal edges, in topological order).
    std::vector<double> earliest = floor;
    std::vector<size_t> order;
    std::vector<int> indeg(node_count_, 0);
    for (const Edge& e : edges) {
      if (e.causal) ++indeg[e.to];
    }
    for (size_t u = 0; u < node_count_; ++u) {
      if (indeg[u] == 0) order.push_back(u);
    }
    for (size_t i = 0; i < order.size(); ++i) {
      for (const Edge& e : edges) {
        if (!e.causal || e.from != order[i]) continue;
        earliest[e.to] = std::max(earliest[e.to], earliest[e.from] + e.min_delay);
        if (--indeg[e.to] == 0) order.push_back(e.to);
      }
    }
    const double h = s_.horizon;
    for (const ActInfo& a : acts_) {
      const Act& act = *a.act;
      if (a.human && earliest[a.node] > h) {
        problem(a.path, "an act that can start within the horizon (" + fmt(h) + " s)",
                "earliest start " + fmt(earliest[a.node]) + " s");
      }
      if (act.cue) {
        if (auto e = quiet_event(act.cue->at); e && earliest[*e] > h) {
          problem(a.path + ".cue.at", "a cue that can happen within the horizon (" + fmt(h) + " s)",
                  "earliest " + fmt(earliest[*e]) + " s");
        }
      }
      if (act.sync) {
        if (auto e = quiet_event(act.sync->with)) {
          const double lo = earliest[*e] + range(act.sync->offset).lo - range(act.sync->tolerance).hi;
          if (lo > h) {
            problem(a.path + ".sync", "a sync window that opens within the horizon (" + fmt(h) + " s)",
                    "it opens at " + fmt(lo) + " s at the earliest");
          }
        }
      }
      if (!a.human && act.after) {
        if (auto e = quiet_event(*act.after); e && earliest[*e] > h) {
          problem(a.path + ".after", "an event that can happen within the horizon (" + fmt(h) + " s)",
                  "earliest " + fmt(earliest[*e]) + " s");
        }
      }
      if (act.still) {
        const auto from = quiet_event(act.still->from);
        const auto to = quiet_event(act.still->to);
        if (from && to && (*from == *to || reaches(next, *to, *from))) {
          problem(a.path + ".still", "'to' after 'from' (a window that can be met)",
                  act.still->to + " never comes after " + act.still->from);
        }
      }
      if (act.label) {
        if (auto e = quiet_event(act.label->during); e && earliest[*e] > h) {
          problem(a.path + ".label.during", "a phase within the horizon (" + fmt(h) + " s)", "earliest " + fmt(earliest[*e]) + " s");
        }
      }
    }
    for (size_t i = 0; i < s_.safety.contact_permitted.size(); ++i) {
      const ContactPermit& c = s_.safety.contact_permitted[i];
      const auto from = quiet_event(c.from);
      const auto to = quiet_event(c.to);
      if (from && to && reaches(next, *to, *from) && *from != *to) {
        problem("safety.contact_permitted[" + std::to_string(i) + "]", "'to' after 'from'",
                c.to + " never comes after " + c.from);
      }
    }
  }
  const ActInfo* owner(size_t node) const {
    for (const ActInfo& a : acts_) {
      if (node >= a.node && node <= a.node + a.phases.size() + 1) return &a;
    }
    return nullptr;
  }
  std::optional<size_t> quiet_event(const std::string& text) const {
    const size_t dot = text.find('.');
    const ActInfo* a = dot == std::string::npos ? nullptr : find_any_act(text.substr(0, dot));
    if (a == nullptr) return std::nullopt;
    const std::string what = text.substr(dot + 1);
    if (what == "start") return a->node;
    if (what == "end") return a->node + a->phases.size() + 1;
    const auto it = std::find(a->phases.begin(), a->phases.end(), what);
    if (it == a->phases.end()) return std::nullopt;
    return a->node + 1 + static_cast<size_t>(it - a->phases.begin());
  }
  static bool reaches(const std::vector<std::vector<size_t>>& next, size_t from, size_t to) {
    std::vector<char> seen(next.size(), 0);
    std::vector<size_t> todo = {from};
    while (!todo.empty()) {
      const size_t u = todo.back();
      todo.pop_back();
      if (u == to) return true;
      if (seen[u]) continue;
      seen[u] = 1;
      for (size_t v : next[u]) todo.push_back(v);
    }
    return false;
  }

  // --- predicates, success, safety, instruction --------------------------------------------
  void predicate(const Pred& p) {
    // A comma inside a YAML flow collection splits a predicate: say so instead of a parse error.
    if (std::count(p.source.begin(), p.source.end(), '(') != std::count(p.source.begin(), p.source.end(), ')')) {
      problem_at(p.where.text,
                 "balanced parentheses (inside [...] or {...} quote predicates: a comma ends a value there)",
                 "'" + p.source + "'");
      return;
    }
    // Expand $vars over their possible words (at most 64 combinations).
    std::vector<std::string> sources = {p.source};
    for (const std::string& ref : template_refs(p.source)) {
      if (!contains(var_names_, ref)) return;  // reported by check_values
      Expr e;
      e.kind = Expr::Kind::kVar;
      e.text = ref;
      const StringSet set = string_values(e, var_names_, var_defs_);
      if (!set.complete || set.values.empty()) {
        problem_at(p.where.text, "vars in predicates that are words or choices of words", "$" + ref);
        return;
      }
      std::vector<std::string> expanded;
      for (const std::string& s : sources) {
        for (const std::string& v : set.values) {
          VarTable t;
          t.names = {ref};
          t.values = {v};
          std::string out;
          // Replace only this var; others stay for the next round.
          size_t i = 0;
          while (i < s.size()) {
            if (s[i] == '$' && s.compare(i + 1, ref.size(), ref) == 0 &&
                (i + 1 + ref.size() == s.size() || !(std::isalnum(static_cast<unsigned char>(s[i + 1 + ref.size()])) || s[i + 1 + ref.size()] == '_'))) {
              out += v;
              i += 1 + ref.size();
            } else {
              out.push_back(s[i++]);
            }
          }
          expanded.push_back(out);
        }
      }
      sources = std::move(expanded);
      if (sources.size() > 64) break;
    }
    for (const std::string& s : sources) {
      try {
        bind_predicate(s, objects_);
      } catch (const core::InputError& e) {
        problem_at(p.where.text, e.expected(), e.got() + (s != p.source ? " (in '" + s + "')" : ""));
        return;
      }
    }
  }

  void check_success() {
    const bool top = !s_.success.empty();
    if (s_.locations.count("success") && !top) problem("success", "at least one success predicate", "none");
    for (const Pred& p : s_.success) predicate(p);
    for (const Entry<Variant>& v : s_.variants) {
      for (const Pred& p : v.value.success) predicate(p);
    }
    bool disruption = false;
    for (const ActInfo& a : acts_) disruption = disruption || a.act->disruption;
    if (s_.role == "intruder" && !acts_.empty() && !disruption) {
      problem("acts", "an intruder script with at least one act marked disruption: true", "none");
    }
  }

  void check_safety() {
    for (size_t i = 0; i < s_.safety.contact_permitted.size(); ++i) {
      const ContactPermit& c = s_.safety.contact_permitted[i];
      const std::string path = "safety.contact_permitted[" + std::to_string(i) + "]";
      check_words(c.robot, {"fingers", "hand", "arm", "any"}, "a robot part");
      std::vector<std::string> regions;
      for (const char* side : {"left", "right", "any"}) {
        for (const char* r : {"head", "neck", "torso", "pelvis", "upper_arm", "forearm", "hand", "thigh", "shin"}) {
          regions.push_back(std::string(side) + "." + r);
        }
      }
      check_words(c.human, regions, "a body region SIDE.REGION");
      event(c.from, path + ".from");
      event(c.to, path + ".to");
    }
    // Reward weights are magnitudes: each term's sign is its meaning (docs/python.md).
    if (s_.reward) {
      const RewardWeights& w = *s_.reward;
      for (const auto& [key, value] : {std::pair<const char*, double>{"progress", w.progress},
                                       {"success", w.success},
                                       {"premature_motion", w.premature_motion},
                                       {"separation", w.separation},
                                       {"contact", w.contact}}) {
        if (!(std::isfinite(value) && value >= 0)) {
          problem(std::string("reward.") + key, "a weight >= 0", fmt(value));
        }
      }
    }
    // A violation bound is a time within the episode (0: none tolerated).
    if (const std::optional<double>& bound = s_.safety.max_violation;
        bound && !(*bound >= 0 && *bound <= s_.horizon)) {
      problem("safety.max_violation", "a time in [0, horizon = " + fmt(s_.horizon) + "] s", fmt(*bound));
    }
  }

  void check_instruction() {
    const std::string& t = s_.instruction;
    for (size_t i = t.find('{'); i != std::string::npos; i = t.find('{', i + 1)) {
      const size_t close = t.find('}', i);
      if (close == std::string::npos) {
        problem("instruction", "'}' to close a fill", "'" + t.substr(i) + "'");
        return;
      }
      const std::string fill = t.substr(i + 1, close - i - 1);
      const size_t dot = fill.find('.');
      if (dot == std::string::npos) {
        if (!contains(var_names_, fill)) problem("instruction", "{VAR} or {OBJECT.kind|color} (vars: " + join(var_names_) + ")", "{" + fill + "}");
      } else {
        const std::string obj = fill.substr(0, dot), field = fill.substr(dot + 1);
        if (!contains(objects_, obj) || (field != "kind" && field != "color")) {
          problem("instruction", "{OBJECT.kind} or {OBJECT.color} of a scene object (" + join(objects_) + ")", "{" + fill + "}");
        }
      }
    }
  }

  const Scenario& s_;
  std::vector<core::InputError> out_;
  std::vector<std::string> var_names_;
  std::vector<Expr> var_defs_;
  std::vector<std::string> objects_;
  std::vector<ActInfo> acts_;
  std::string scope_;  // the variant whose acts are visible besides the top-level ones
  size_t node_count_ = 0;
};

// "file:L:C ..." -> (L, C) for sorting; (0, 0) when absent.
std::pair<long, long> position(const std::string& where) {
  const size_t first = where.find(':');
  if (first == std::string::npos) return {0, 0};
  char* end = nullptr;
  const long line = std::strtol(where.c_str() + first + 1, &end, 10);
  long col = 0;
  if (end != nullptr && *end == ':') col = std::strtol(end + 1, nullptr, 10);
  return {line, col};
}

std::vector<Problem> to_problems(const std::vector<core::InputError>& errors) {
  std::vector<Problem> problems;
  for (const core::InputError& e : errors) {
    const std::string what = e.what();
    problems.push_back({e.where(), what.substr(std::min(what.size(), e.where().size() + 2))});
  }
  std::stable_sort(problems.begin(), problems.end(), [](const Problem& a, const Problem& b) {
    return position(a.where) < position(b.where);
  });
  return problems;
}

}  // namespace

const std::vector<std::string>& object_kinds() {
  static const std::vector<std::string> kinds = [] {
    std::vector<std::string> names;
    for (const ObjectKindEntry& kind : catalogue_kinds()) names.emplace_back(kind.name);
    names.emplace_back(kPlatformKind);
    return names;
  }();
  return kinds;
}

const std::vector<std::string>& object_colors() {
  static const std::vector<std::string> colors = [] {
    std::vector<std::string> names;
    for (const ColourEntry& colour : catalogue_colours()) names.emplace_back(colour.name);
    return names;
  }();
  return colors;
}

std::vector<Problem> validate(const Scenario& scenario) {
  Validator v(scenario);
  return to_problems(v.run());
}

std::vector<Problem> check_text(std::string_view text, const std::string& file) {
  std::vector<core::InputError> errors;
  const Scenario scenario = parse_scenario(text, file, errors);
  const bool parsed = !scenario.locations.empty();
  std::vector<Problem> problems = to_problems(errors);
  if (parsed) {
    // Semantic checks run on what could be read; schema problems are already listed.
    for (Problem& p : validate(scenario)) problems.push_back(std::move(p));
    std::stable_sort(problems.begin(), problems.end(), [](const Problem& a, const Problem& b) {
      return position(a.where) < position(b.where);
    });
    // The same text twice (a value both unreadable and unresolvable) is said once.
    problems.erase(std::unique(problems.begin(), problems.end(),
                               [](const Problem& a, const Problem& b) { return a.text() == b.text(); }),
                   problems.end());
  }
  return problems;
}

std::vector<Problem> check(const std::string& path) {
  std::vector<core::InputError> errors;
  std::ifstream in(path, std::ios::binary);
  if (!in) return {{path, "cannot open file"}};
  std::ostringstream text;
  text << in.rdbuf();
  return check_text(text.str(), path);
}

Scenario load_scenario(const std::string& path) {
  const std::vector<Problem> problems = check(path);
  if (!problems.empty()) throw core::InputError::Message(problems.front().where, problems.front().message);
  std::vector<core::InputError> errors;
  return read_scenario(path, errors);
}

}  // namespace hribench::script

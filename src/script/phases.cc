#include "script/phases.h"

#include <algorithm>
#include <cmath>

#include "core/errors.h"

namespace hribench::script {
namespace {

double number_param(const Motion& motion, const human::PrimitiveInfo& primitive,
                    const std::string& name) {
  if (name.empty()) return 0;
  const ValueTree* v = find_param(motion, name);
  if (v != nullptr && v->kind == ValueTree::Kind::kScalar &&
      v->scalar.expr.kind == Expr::Kind::kNumber) {
    return v->scalar.expr.number;
  }
  const human::ParamInfo* info = primitive.param(name);
  return info != nullptr && info->has_default ? info->default_value : 0.0;
}

}  // namespace

const ValueTree* find_param(const Motion& motion, const std::string& name) {
  for (const Entry<ValueTree>& e : motion.params) {
    if (e.name == name) return &e.value;
  }
  return nullptr;
}

std::vector<std::string> phase_names(const human::PrimitiveInfo& primitive) {
  std::vector<std::string> names;
  for (const human::PhaseInfo& p : primitive.phases) names.emplace_back(p.name);
  return names;
}

std::string phase_parameter(const human::PrimitiveInfo& primitive, size_t phase) {
  const std::string prim(primitive.name);
  const std::string name(primitive.phases[phase].name);
  if (prim == "offer" && name == "hold") return "settle";
  if (prim == "offer" && name == "hold_stable") return "hold";
  if (prim == "reach" && name == "hold") return "dwell";
  if (prim == "walk_to") return name == "walk" ? "" : "turn";
  const human::ParamInfo* same = primitive.param(name);
  if (same != nullptr && same->kind == human::ParamKind::kNumber) return name;
  if (phase == 0 && primitive.param("duration") != nullptr) return "duration";
  return "";
}

double motion_onset(const Motion& motion) {
  const ValueTree* v = find_param(motion, "onset");
  if (v != nullptr && v->kind == ValueTree::Kind::kScalar && v->scalar.expr.kind == Expr::Kind::kNumber) {
    return v->scalar.expr.number;
  }
  return 0;
}

std::vector<PhaseTiming> phase_timing(const Motion& motion, const core::Vec3& stand) {
  std::vector<PhaseTiming> phases;
  if (motion.clip.has_value()) {
    const ValueTree* d = find_param(motion, "duration");
    const double seconds = d != nullptr && d->scalar.expr.kind == Expr::Kind::kNumber ? d->scalar.expr.number : 0;
    phases.push_back({"play", seconds, false});
    return phases;
  }
  HRIB_CHECK(motion.primitive.has_value()) << "motion without primitive or clip";
  const std::string& name = motion.primitive->value();
  const human::PrimitiveInfo* primitive = human::find_primitive(name);
  if (primitive == nullptr) {
    throw core::InputError(motion.primitive->where.text, "a motion primitive", "'" + name + "'");
  }
  for (size_t i = 0; i < primitive->phases.size(); ++i) {
    PhaseTiming t;
    t.name = std::string(primitive->phases[i].name);
    t.waits = primitive->phases[i].waits;
    if (name == "walk_to" && t.name == "walk") {
      const ValueTree* to = find_param(motion, "to");
      double distance = 0;
      if (to != nullptr && to->kind == ValueTree::Kind::kList && to->items.size() >= 2) {
        const double x = to->items[0].scalar.expr.number;
        const double y = to->items[1].scalar.expr.number;
        distance = std::hypot(x - stand.x(), y - stand.y());
      }
      t.duration = distance / (0.75 * number_param(motion, *primitive, "speed"));
    } else {
      t.duration = number_param(motion, *primitive, phase_parameter(*primitive, i));
    }
    phases.push_back(std::move(t));
  }
  return phases;
}

std::string primitive_reference_markdown() {
  std::string md = "| primitive | phases (timed by) | other parameters |\n|---|---|---|\n";
  for (const human::PrimitiveInfo& p : human::primitive_catalog()) {
    std::string phases;
    std::vector<std::string> timing;
    for (size_t i = 0; i < p.phases.size(); ++i) {
      const std::string param = phase_parameter(p, i);
      timing.push_back(param);
      phases += (i ? ", " : "") + std::string(p.phases[i].name) + (p.phases[i].waits ? "*" : "") +
                (param.empty() ? "" : " (" + param + ")");
    }
    std::string others;
    for (const human::ParamInfo& q : p.params) {
      const std::string name(q.name);
      if (std::find(timing.begin(), timing.end(), name) != timing.end()) continue;
      others += (others.empty() ? "" : ", ") + name + (q.required ? " (required)" : "");
    }
    md += "| `" + std::string(p.name) + "` | " + phases + " | " + others + " |\n";
  }
  return md;
}

}  // namespace hribench::script

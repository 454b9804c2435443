#include "script/sample.h"

#include <algorithm>
#include <cmath>

#include "core/hash.h"
#include "core/json.h"
#include "human/primitives.h"
#include "script/catalogue.h"
#include "script/check.h"
#include "script/phases.h"
#include "script/schema_io.h"
#include "script/walk.h"

namespace hribench::script {
namespace {

// Draws every value of a struct from one stream.
struct Resolver {
  core::Rng rng;
  const VarTable& vars;

  void operator()(Param& p, ParamType type) {
    Value v;
    try {
      v = draw(p.expr, rng, vars);
    } catch (const ExprError& e) {
      throw core::InputError(p.where.text, e.expected, e.got);
    }
    if (std::holds_alternative<double>(v)) {
      if (type == ParamType::kWord) {
        p.expr = Expr::String(format_number(std::get<double>(v)));
      } else {
        p.expr = Expr::Number(std::get<double>(v));
      }
    } else {
      if (type == ParamType::kNumber) {
        throw core::InputError(p.where.text, "a number", "'" + std::get<std::string>(v) + "'");
      }
      p.expr = Expr::String(std::get<std::string>(v));
    }
  }
  void operator()(Pred& p) {
    try {
      p.source = substitute(p.source, vars);
    } catch (const ExprError& e) {
      throw core::InputError(p.where.text, e.expected, e.got);
    }
  }
};

template <class T>
void resolve(T& s, const core::Rng& rng, const VarTable& vars) {
  Resolver r{rng, vars};
  walk_params(s, r);
}

void draw_vars(const Named<Any>& defs, const core::Rng& rng, VarTable& table, Named<Any>& out) {
  for (const Entry<Any>& def : defs) {
    core::Rng stream = rng.split(def.name);
    Value v;
    try {
      v = draw(def.value.expr, stream, table);
    } catch (const ExprError& e) {
      throw core::InputError(def.value.where.text, e.expected, e.got);
    }
    table.names.push_back(def.name);
    table.values.push_back(v);
    Entry<Any> drawn = def;
    drawn.value.expr = std::holds_alternative<double>(v) ? Expr::Number(std::get<double>(v))
                                                          : Expr::String(std::get<std::string>(v));
    out.push_back(std::move(drawn));
  }
}

// Radius of the circle around an object's footprint (m), any yaw: the catalogue's size of its
// kind, or a platform's explicit size; 0 for an unknown kind.
double footprint_radius(const SceneObject& o) {
  if (o.size.size() >= 2) return 0.5 * std::hypot(o.size[0].value(), o.size[1].value());
  const ObjectKindEntry* kind = find_kind(o.kind.value());
  return kind ? script::footprint_radius(*kind) : 0;
}

// Distractor objects with drawn kinds, colours and table positions: their footprint circles
// kDistractorGap clear of every other placed object's (centres at least kDistractorSpacing
// apart). A distractor with no free place in kDistractorAttempts draws is left out.
void draw_distractors(EpisodeSpec& spec, const Distractors& d, core::Rng rng) {
  const int count = static_cast<int>(std::lround(d.count.value()));
  std::vector<std::string> kinds;
  for (const Text& k : d.kinds) kinds.push_back(k.value());
  if (kinds.empty()) kinds = {"cube", "cup", "bottle"};
  int placed = 0;
  for (int i = 1; i <= count; ++i) {
    SceneObject o;
    o.kind = Text(kinds[static_cast<size_t>(rng.uniform_int(0, static_cast<int64_t>(kinds.size()) - 1))].c_str());
    const auto& colours = catalogue_colours();
    o.color = Text(
        std::string(colours[static_cast<size_t>(rng.uniform_int(0, static_cast<int64_t>(colours.size()) - 1))].name)
            .c_str());
    const double radius = footprint_radius(o);
    ObjectPose pose;
    double x = 0, y = 0;
    bool free = false;
    for (int attempt = 0; attempt < kDistractorAttempts && !free; ++attempt) {
      x = rng.uniform(kDistractorXMin, kDistractorXMax);
      y = rng.uniform(kDistractorYMin, kDistractorYMax);
      free = true;
      for (const Entry<SceneObject>& other : spec.scene.objects) {
        if (!other.value.pose || other.value.pose->xy.size() != 2) continue;
        const double dx = other.value.pose->xy[0].value() - x;
        const double dy = other.value.pose->xy[1].value() - y;
        const double clearance = std::max(kDistractorSpacing, radius + footprint_radius(other.value) + kDistractorGap);
        free = free && std::hypot(dx, dy) >= clearance;
      }
    }
    if (!free) continue;
    pose.xy = {Num(x), Num(y)};
    pose.yaw_deg = Num(rng.uniform(0.0, 360.0));
    o.pose = pose;
    spec.scene.objects.push_back({"distractor_" + std::to_string(++placed), {}, std::move(o)});
  }
}

std::string fill_instruction(const std::string& text, const EpisodeSpec& spec, const VarTable& vars) {
  std::string out;
  size_t i = 0;
  while (i < text.size()) {
    const size_t open = text.find('{', i);
    if (open == std::string::npos) break;
    const size_t close = text.find('}', open);
    if (close == std::string::npos) break;
    out += text.substr(i, open - i);
    const std::string fill = text.substr(open + 1, close - open - 1);
    const size_t dot = fill.find('.');
    std::string value = "{" + fill + "}";
    if (dot == std::string::npos) {
      if (const Value* v = vars.find(fill)) {
        value = std::holds_alternative<double>(*v) ? format_number(std::get<double>(*v)) : std::get<std::string>(*v);
      }
    } else {
      for (const Entry<SceneObject>& o : spec.scene.objects) {
        if (o.name != fill.substr(0, dot)) continue;
        const std::string field = fill.substr(dot + 1);
        if (field == "kind") value = o.value.kind.value();
        if (field == "color" && o.value.color) value = o.value.color->value();
      }
    }
    out += value;
    i = close + 1;
  }
  return out + text.substr(i);
}

// Human acts whose primitive has a hand get the person's handedness when they name none.
void default_hands(EpisodeSpec& spec) {
  for (Entry<Act>& a : spec.acts) {
    if (!a.value.motion || !a.value.motion->primitive) continue;
    const human::PrimitiveInfo* p = human::find_primitive(a.value.motion->primitive->value());
    if (p == nullptr || !p->uses_hand || find_param(*a.value.motion, "hand") != nullptr) continue;
    ValueTree hand;
    hand.scalar.expr = Expr::String(spec.human.handedness.value());
    a.value.motion->params.push_back({"hand", {}, std::move(hand)});
  }
}

}  // namespace

EpisodeSpec sample(const Scenario& scenario, uint64_t seed, std::string_view robot) {
  const core::Rng root(seed);
  EpisodeSpec spec;
  spec.hribench = scenario.hribench;
  spec.task = scenario.task;
  spec.role = scenario.role;
  spec.robot = std::string(robot);
  spec.seed = seed;
  spec.horizon = scenario.horizon;

  // The variant, then the vars (base, then the variant's).
  const Variant* variant = nullptr;
  if (!scenario.variants.empty()) {
    std::vector<double> weights;
    for (const Entry<Variant>& v : scenario.variants) weights.push_back(v.value.weight.value());
    core::Rng stream = root.split("variant");
    const size_t index = stream.weighted_index(weights);
    variant = &scenario.variants[index].value;
    spec.variant = scenario.variants[index].name;
  }
  VarTable vars;
  draw_vars(scenario.vars, root.split("vars"), vars, spec.vars);
  if (variant != nullptr) draw_vars(variant->vars, root.split("vars"), vars, spec.vars);

  // Each section from its own stream; each object and act from its own sub-stream.
  spec.scene.objects = scenario.scene.objects;
  for (Entry<SceneObject>& o : spec.scene.objects) resolve(o.value, root.split("scene").split(o.name), vars);
  Distractors distractors = scenario.scene.distractors;
  resolve(distractors, root.split("distractors"), vars);
  draw_distractors(spec, distractors, root.split("distractors").split("place"));
  spec.human = scenario.human;
  resolve(spec.human, root.split("human"), vars);
  spec.acts = scenario.acts;
  if (variant != nullptr) spec.acts.insert(spec.acts.end(), variant->acts.begin(), variant->acts.end());
  for (Entry<Act>& a : spec.acts) resolve(a.value, root.split("acts").split(a.name), vars);
  default_hands(spec);
  // Motion parameters in name order: the canonical order, as JSON objects keep it.
  for (Entry<Act>& a : spec.acts) {
    if (!a.value.motion) continue;
    auto& params = a.value.motion->params;
    std::stable_sort(params.begin(), params.end(), [](const auto& x, const auto& y) { return x.name < y.name; });
  }
  spec.success = variant != nullptr && !variant->success.empty() ? variant->success : scenario.success;
  resolve(spec.success, root.split("success"), vars);
  spec.safety = scenario.safety;
  spec.reward = scenario.reward;
  resolve(spec.safety, root.split("safety"), vars);
  spec.instruction = fill_instruction(scenario.instruction, spec, vars);
  return spec;
}

std::string spec_hash(const EpisodeSpec& spec) { return core::sha256_hex(core::canonical_json(to_json(spec))); }

std::string spec_to_text(const EpisodeSpec& spec) { return core::pretty_json(to_json(spec)) + "\n"; }

EpisodeSpec spec_from_text(std::string_view text, std::string_view source) {
  return episode_from_json(core::parse_json(text, source), source);
}

}  // namespace hribench::script

#pragma once
// The typed scenario script (docs/scenario-scripts.md is the reference). The same structs hold
// a Scenario as written (values may be distributions) and an
// EpisodeSpec after sample() (every value a literal).
//
// Each struct has ONE visit function listing its keys; it drives the YAML reader, the JSON
// writer and reader (script/schema_io.h) and the generated key reference in the docs. A
// visitor V provides:
//   v.req(key, member, doc)   a required key
//   v.opt(key, member, doc)   an optional key (std::optional, or the member's default value)
//   v.rest(member, doc)       every other key (motion parameters; checked against the catalog)

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "script/expr.h"

namespace hribench::script {

// Where a value was written ("file:line:col (key.path)"); ignored by ==, so a spec loaded
// from JSON equals the one sampled from YAML.
struct Where {
  std::string text;
  bool operator==(const Where&) const { return true; }
};

// A scalar value of a script: an Expr and its location. Num: numbers and numeric
// distributions; Text: words, templates and choices of words; Any: either (vars).
struct Param {
  Expr expr;
  Where where;
  bool bad = false;  // the text could not be read (already reported): skip further checks
  bool operator==(const Param&) const = default;
};
struct Num : Param {
  Num() = default;
  Num(double x) { expr = Expr::Number(x); }  // NOLINT: defaults read naturally
  double value() const;                      // requires a resolved (literal) number
  bool operator==(const Num&) const = default;
};
struct Text : Param {
  Text() = default;
  Text(const char* s) { expr = Expr::String(s); }  // NOLINT
  const std::string& value() const;                // requires a resolved (literal) string
  bool operator==(const Text&) const = default;
};
struct Any : Param {
  bool operator==(const Any&) const = default;
};
// A predicate's source text (script/predicate.h); may contain $vars until sampled.
struct Pred {
  std::string source;
  Where where;
  bool operator==(const Pred&) const = default;
};

// A named entry of a user-keyed mapping (vars, objects, acts), kept in file order.
template <typename T>
struct Entry {
  std::string name;
  Where where;
  T value;
  bool operator==(const Entry&) const = default;
};
template <typename T>
using Named = std::vector<Entry<T>>;

// A free-form value tree (motion parameters: numbers, words, points, zones, via lists).
struct ValueTree {
  enum class Kind { kScalar, kList, kMap };
  Kind kind = Kind::kScalar;
  Any scalar;                       // kScalar
  std::vector<ValueTree> items;     // kList, kMap (values)
  std::vector<std::string> keys;    // kMap (keys, parallel to items)
  Where where;
  bool operator==(const ValueTree&) const = default;
};

struct ObjectPose {
  static constexpr const char* kSchemaName = "pose";
  std::vector<Num> xy;
  std::optional<Num> z;
  Num yaw_deg = 0.0;
  template <class V>
  void visit(V& v) {
    v.req("xy", xy, "[x, y] of the object's centre on the table, m (world frame)");
    v.opt("z", z, "height of the centre, m (default: resting on the table)");
    v.opt("yaw_deg", yaw_deg, "rotation about world z, degrees");
  }
  bool operator==(const ObjectPose&) const = default;
};

struct SceneObject {
  static constexpr const char* kSchemaName = "object";
  Text kind;
  std::optional<Text> color;
  std::optional<ObjectPose> pose;
  std::optional<Text> held_by;
  std::optional<Text> in;
  std::vector<Num> size;
  template <class V>
  void visit(V& v) {
    v.req("kind", kind, "cube, cup, bottle, plate, bin, tray, box, plank, platform");
    v.opt("color", color, "red, green, blue, yellow, orange, purple, white, black, gray, brown, pink, cyan");
    v.opt("pose", pose, "where it starts (default: placed by the scene generator)");
    v.opt("held_by", held_by, "human.left or human.right: starts in that hand");
    v.opt("in", in, "a container object it starts inside");
    v.opt("size", size, "[x, y, z] full sizes, m (default: the kind's size)");
  }
  bool operator==(const SceneObject&) const = default;
};

struct Distractors {
  static constexpr const char* kSchemaName = "distractors";
  Num count = 0.0;
  std::vector<Text> kinds;
  template <class V>
  void visit(V& v) {
    v.opt("count", count, "how many extra objects (0-8), e.g. Uint(0, 2)");
    v.opt("kinds", kinds, "kinds to draw from (default: cube, cup, bottle)");
  }
  bool operator==(const Distractors&) const = default;
};

struct Scene {
  static constexpr const char* kSchemaName = "scene";
  Named<SceneObject> objects;
  Distractors distractors;
  template <class V>
  void visit(V& v) {
    v.req("objects", objects, "the named task objects (names are used by acts and predicates)");
    v.opt("distractors", distractors, "extra objects of no role, named distractor_1, ...");
  }
  bool operator==(const Scene&) const = default;
};

struct Stand {
  static constexpr const char* kSchemaName = "stand";
  Num x = 1.5;
  Num y = 0.0;
  Num yaw_deg = 180.0;
  template <class V>
  void visit(V& v) {
    v.opt("x", x, "pelvis x, m (world frame)");
    v.opt("y", y, "pelvis y, m");
    v.opt("yaw_deg", yaw_deg, "heading about z, degrees (180 faces the robot)");
  }
  bool operator==(const Stand&) const = default;
};

struct HumanSpec {
  static constexpr const char* kSchemaName = "human";
  Num height = 1.75;
  Stand stand;
  Text handedness = "right";
  template <class V>
  void visit(V& v) {
    v.opt("height", height, "body height, m (1.55-1.95)");
    v.opt("stand", stand, "where the person stands");
    v.opt("handedness", handedness, "left or right: the default hand of acts");
  }
  bool operator==(const HumanSpec&) const = default;
};

struct Motion {
  static constexpr const char* kSchemaName = "motion";
  std::optional<Text> primitive;
  std::optional<Text> clip;
  std::optional<Pred> until;
  Named<ValueTree> params;
  template <class V>
  void visit(V& v) {
    v.opt("primitive", primitive, "a motion primitive of the catalog (exactly one of primitive, clip)");
    v.opt("clip", clip, "an imported motion file (.bvh, .npy, .npz) played instead of a primitive");
    v.opt("until", until, "ends the primitive's waiting phase when this predicate holds");
    v.rest(params, "the primitive's parameters (hand, zone, target, durations, ...), per the catalog");
  }
  bool operator==(const Motion&) const = default;
};

struct Cue {
  static constexpr const char* kSchemaName = "cue";
  std::string at;
  Num window;
  std::string kind = "go";
  template <class V>
  void visit(V& v) {
    v.req("at", at, "the event the robot must respond to (ACT.PHASE, ACT.start, ACT.end)");
    v.req("window", window, "response window W_c, s (> 0)");
    v.opt("kind", kind, "go, stop or intrusion: what counts as a response (docs/metrics.md Rsp)");
  }
  bool operator==(const Cue&) const = default;
};

struct Label {
  static constexpr const char* kSchemaName = "label";
  std::optional<Text> joint;
  std::vector<Text> ray;
  std::optional<std::string> in;
  std::optional<Text> through;
  std::optional<std::string> crosses;
  std::string during;
  template <class V>
  void visit(V& v) {
    v.opt("joint", joint, "SIDE.POINT (wrist, palm, hand, index) checked by `in` or `crosses`, e.g. $hand.wrist");
    v.opt("ray", ray, "[SIDE.shoulder, SIDE.index]: the pointing ray, checked by `through`");
    v.opt("in", in, "ACT.zone: the joint stays inside that act's zone");
    v.opt("through", through, "a scene object the ray passes within its cue region");
    v.opt("crosses", crosses, "workspace: the joint crosses the workspace boundary");
    v.req("during", during, "the phase the label holds in (ACT.PHASE)");
  }
  bool operator==(const Label&) const = default;
};

struct Sync {
  static constexpr const char* kSchemaName = "sync";
  std::string with;
  Num offset = 0.0;
  Num tolerance;
  template <class V>
  void visit(V& v) {
    v.req("with", with, "the human event h the robot act's start r is synchronised with");
    v.opt("offset", offset, "target delay delta = t_r - t_h, s");
    v.req("tolerance", tolerance, "tau, s (> 0): TSync = max(0, 1 - |t_r - t_h - delta| / tau)");
  }
  bool operator==(const Sync&) const = default;
};

struct Still {
  static constexpr const char* kSchemaName = "still";
  std::string from;
  std::string to;
  template <class V>
  void visit(V& v) {
    v.req("from", from, "event from which the robot must stay still");
    v.req("to", to, "event until which it must stay still");
  }
  bool operator==(const Still&) const = default;
};

struct Act {
  static constexpr const char* kSchemaName = "act";
  std::string actor;
  // Human acts.
  std::optional<Motion> motion;
  std::optional<Num> onset;
  std::optional<Num> delay;
  std::optional<Pred> when;
  std::optional<Pred> unless;
  std::optional<Cue> cue;
  std::optional<Label> label;
  bool disruption = false;
  std::optional<std::string> contradicts;
  bool fails = false;
  // Both: a trigger for human acts, an ordering constraint for robot acts.
  std::optional<std::string> after;
  // Robot acts.
  std::optional<Pred> goal;
  std::optional<std::string> before;
  std::optional<Num> within;
  std::optional<Sync> sync;
  std::optional<Still> still;
  template <class V>
  void visit(V& v) {
    v.req("actor", actor, "human or robot");
    v.opt("motion", motion, "human: what the body does");
    v.opt("onset", onset, "human trigger: earliest start, s after the episode start");
    v.opt("after", after, "human: trigger event; robot: must start after this event (OC)");
    v.opt("delay", delay, "human: seconds after the `after` event");
    v.opt("when", when, "human trigger: start when this predicate holds");
    v.opt("unless", unless, "human: skip the act if this holds when it would start");
    v.opt("cue", cue, "human: an event the robot must respond to, with a window");
    v.opt("label", label, "human: a check on the synthesized motion");
    v.opt("disruption", disruption, "human: an intruder act (DSR)");
    v.opt("contradicts", contradicts, "human: the robot act this act contradicts (CIR)");
    v.opt("fails", fails, "human: the episode fails if this act starts (e.g. giving up)");
    v.opt("goal", goal, "robot: the predicate whose first holding ends the act");
    v.opt("before", before, "robot: must end before this event (OC)");
    v.opt("within", within, "robot: must start within this many seconds after `after` (Rsp)");
    v.opt("sync", sync, "robot: start synchronised with a human event (TSync)");
    v.opt("still", still, "robot: must not move between two events (OC)");
  }
  bool operator==(const Act&) const = default;
};

struct Variant {
  static constexpr const char* kSchemaName = "variant";
  Num weight = 1.0;
  Named<Any> vars;
  Named<Act> acts;
  std::vector<Pred> success;
  template <class V>
  void visit(V& v) {
    v.opt("weight", weight, "relative probability (> 0)");
    v.opt("vars", vars, "more vars, drawn only in this variant");
    v.opt("acts", acts, "more acts, added to the top-level acts");
    v.opt("success", success, "replaces the top-level success when given");
  }
  bool operator==(const Variant&) const = default;
};

struct ContactPermit {
  static constexpr const char* kSchemaName = "contact";
  Text robot;
  Text human;
  std::string from;
  std::string to;
  template <class V>
  void visit(V& v) {
    v.req("robot", robot, "fingers, hand, arm or any");
    v.req("human", human, "SIDE.REGION (left/right/any . head, neck, torso, pelvis, upper_arm, forearm, hand, thigh, shin)");
    v.req("from", from, "event from which contact is permitted");
    v.req("to", to, "event until which contact is permitted");
  }
  bool operator==(const ContactPermit&) const = default;
};

struct Safety {
  static constexpr const char* kSchemaName = "safety";
  std::vector<ContactPermit> contact_permitted;
  // Conditions success adds (docs/tasks.md "no contact", "separation violations within
  // tolerance"); absent: success ignores them (CFR and HCS still report them).
  std::optional<bool> no_contact;
  std::optional<double> max_violation;  // s
  template <class V>
  void visit(V& v) {
    v.opt("contact_permitted", contact_permitted, "robot-human contact pairs allowed in a phase");
    v.opt("no_contact", no_contact, "true: success also requires no robot-human contact outside contact_permitted");
    v.opt("max_violation", max_violation, "success also requires at most this many s of separation violation (d < S_p outside permitted phases, docs/metrics.md HCS)");
  }
  bool operator==(const Safety&) const = default;
};

// Weights of the dense training reward (docs/python.md "Rewards"; eval/reward.h computes it).
// A script may override any of them in its optional `reward` section; the metrics remain the
// benchmark's score.
struct RewardWeights {
  static constexpr const char* kSchemaName = "reward";
  double progress = 1.0;          // per m the tool comes closer to the current robot act's goal
  double success = 10.0;          // once, when the success predicates first hold
  double premature_motion = 1.0;  // per m the tool moves while its act awaits a go cue
  double separation = 1.0;        // per s of separation violation (HCS's rule)
  double contact = 1.0;           // per s of unpermitted human contact, times the region's grade
  template <class V>
  void visit(V& v) {
    v.opt("progress", progress, "reward per m the tool comes closer to the current robot act's goal (default 1)");
    v.opt("success", success, "bonus when the success predicates first hold (default 10)");
    v.opt("premature_motion", premature_motion, "penalty per m the tool moves while its act awaits a go cue (default 1)");
    v.opt("separation", separation, "penalty per s of separation violation, HCS's rule (default 1)");
    v.opt("contact", contact, "penalty per s of unpermitted human contact, times the body region's grade (default 1)");
  }
  bool operator==(const RewardWeights&) const = default;
};

struct Scenario {
  static constexpr const char* kSchemaName = "script";
  std::string file;  // where it was read from (not a key)
  // "file:line:col (key.path)" of every key read, by key path ("acts.take.after"); not a key.
  std::map<std::string, std::string> locations;
  int hribench = 0;
  std::string task;
  std::string role;
  std::string description;
  std::string instruction;
  double horizon = 30.0;
  Named<Any> vars;
  Named<Variant> variants;
  Scene scene;
  HumanSpec human;
  Named<Act> acts;
  std::vector<Pred> success;
  Safety safety;
  std::optional<RewardWeights> reward;  // absent: the default weights
  template <class V>
  void visit(V& v) {
    v.req("hribench", hribench, "schema version: 1");
    v.req("task", task, "the task's name (lower_snake_case)");
    v.req("role", role, "instructor, collaborator or intruder");
    v.opt("description", description, "free text for people");
    v.req("instruction", instruction, "language instruction; {var} and {OBJECT.kind|color} are filled in");
    v.opt("horizon", horizon, "episode length, s of simulated time (0-600]");
    v.opt("vars", vars, "named values drawn once per episode, referenced as $name");
    v.opt("variants", variants, "weighted sub-cases with their own vars, acts and success");
    v.req("scene", scene, "objects and distractors");
    v.opt("human", human, "the person's body and place");
    v.req("acts", acts, "the interaction acts, human and robot");
    v.req("success", success, "predicates that must all hold at the end");
    v.opt("safety", safety, "safety exceptions");
    v.opt("reward", reward, "weights of the dense training reward (docs/python.md); the metrics still score");
  }
};

// The robot an episode is sampled for when none is named (its description: model/robot.h,
// docs/robots.md).
inline constexpr std::string_view kDefaultRobot = "panda";

// One episode: a Scenario with one variant chosen and every random value drawn, for one robot.
// Serialises to JSON (script/schema_io.h), reloads identically, and has a content hash
// (script/sample.h) that therefore covers the robot.
struct EpisodeSpec {
  static constexpr const char* kSchemaName = "episode";
  int hribench = 1;
  std::string task;
  std::string role;
  std::string robot{kDefaultRobot};  // the robot description's name (model::robot_by_name)
  uint64_t seed = 0;
  std::string variant;  // "" when the script has no variants
  std::string instruction;
  double horizon = 30.0;
  Named<Any> vars;      // the drawn values, base vars then the variant's
  Scene scene;          // distractors drawn into scene.objects (distractors.count = 0)
  HumanSpec human;
  Named<Act> acts;      // base acts then the variant's
  std::vector<Pred> success;
  Safety safety;
  std::optional<RewardWeights> reward;  // the script's; absent (and not in the JSON): defaults
  template <class V>
  void visit(V& v) {
    v.req("hribench", hribench, "schema version: 1");
    v.req("task", task, "the task's name");
    v.req("role", role, "instructor, collaborator or intruder");
    v.req("robot", robot, "the robot it was sampled for (docs/robots.md)");
    v.req("seed", seed, "the seed it was sampled with");
    v.req("variant", variant, "the chosen variant, or empty");
    v.req("instruction", instruction, "the filled-in instruction");
    v.req("horizon", horizon, "episode length, s");
    v.req("vars", vars, "drawn var values");
    v.req("scene", scene, "objects, all values drawn");
    v.req("human", human, "the person, all values drawn");
    v.req("acts", acts, "acts, all values drawn");
    v.req("success", success, "success predicates, vars substituted");
    v.req("safety", safety, "safety exceptions");
    v.opt("reward", reward, "the script's reward weights, if it has a reward section");
  }
  bool operator==(const EpisodeSpec&) const = default;
};

}  // namespace hribench::script

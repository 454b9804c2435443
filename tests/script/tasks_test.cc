// The 13 task scripts of tasks/ (docs/tasks.md): each is clean for the validator, samples
// deterministically, compiles to an act graph for every sampled variant, keeps its geometry
// within reach of the person and the robot, and has the task-specific structure docs/tasks.md asks
// for (pointed target among the scene objects, I5's three variants, disruptions, syncs, ...).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "human/labels.h"
#include "human/motion.h"
#include "core/errors.h"
#include "script/check.h"
#include "script/phases.h"
#include "script/runtime.h"
#include "script/sample.h"

namespace hribench::script {
namespace {

constexpr int kSeeds = 24;

// Task file names (docs/tasks.md ids and names), in the order of docs/tasks.md.
const std::vector<std::string>& task_files() {
  static const std::vector<std::string> files = {
      "I1_point_pick",       "I2_gesture_delivery", "I3_demo_imitate",  "I4_stop_go",
      "I5_contradiction",    "C1_handover_h2r",     "C2_handover_r2h",  "C3_box_retrieval",
      "C4_co_lift",          "X1_intrusion_yield",  "X2_object_moved",  "X3_someone_else_places",
      "X4_blocked_target"};
  return files;
}

std::string path_of(const std::string& name) { return "tasks/" + name + ".yaml"; }

const Entry<Act>* find_act(const EpisodeSpec& spec, const std::string& name) {
  for (const Entry<Act>& a : spec.acts) {
    if (a.name == name) return &a;
  }
  return nullptr;
}

const Entry<SceneObject>* find_object(const EpisodeSpec& spec, const std::string& name) {
  for (const Entry<SceneObject>& o : spec.scene.objects) {
    if (o.name == name) return &o;
  }
  return nullptr;
}

std::string word_param(const Motion& m, const std::string& name) {
  const ValueTree* v = find_param(m, name);
  return v != nullptr && v->kind == ValueTree::Kind::kScalar ? v->scalar.expr.text : "";
}
// Centre of a scene object in the sampled spec (nominal sizes of model/objects.cc; `size` and
// `z` when the script gives them); objects inside a container take the container's centre.
core::Vec3 object_centre(const EpisodeSpec& spec, const std::string& name) {
  static const std::map<std::string, double> half_height = {
      {"cube", 0.025}, {"cup", 0.045},  {"bottle", 0.105}, {"plate", 0.008}, {"bin", 0.05},
      {"tray", 0.0125}, {"box", 0.064}, {"plank", 0.02},   {"platform", 0.04}};
  const Entry<SceneObject>* o = find_object(spec, name);
  HRIB_CHECK(o != nullptr) << name;
  if (o->value.in) return object_centre(spec, o->value.in->value());
  HRIB_CHECK(o->value.pose.has_value()) << name << " has no pose";
  const ObjectPose& pose = *o->value.pose;
  double z = 0.75 + (o->value.size.empty() ? half_height.at(o->value.kind.value()) : o->value.size[2].value() / 2);
  if (pose.z) z = pose.z->value();
  return {pose.xy[0].value(), pose.xy[1].value(), z};
}

// The motion parameters of a sampled human act, as the human layer takes them.
human::PrimitiveParams primitive_params(const EpisodeSpec& spec, const Motion& m) {
  human::PrimitiveParams p;
  p.primitive = m.primitive->value();
  const human::PrimitiveInfo* info = human::find_primitive(p.primitive);
  HRIB_CHECK(info != nullptr) << p.primitive;
  const auto point = [&](const ValueTree& t) {
    if (t.kind == ValueTree::Kind::kScalar) return object_centre(spec, t.scalar.expr.text);
    return core::Vec3(t.items[0].scalar.expr.number, t.items[1].scalar.expr.number, t.items[2].scalar.expr.number);
  };
  for (const Entry<ValueTree>& e : m.params) {
    const ValueTree& v = e.value;
    switch (info->param(e.name)->kind) {
      case human::ParamKind::kNumber: p.numbers[e.name] = v.scalar.expr.number; break;
      case human::ParamKind::kSide:
      case human::ParamKind::kChoice: p.choices[e.name] = v.scalar.expr.text; break;
      case human::ParamKind::kPoint: p.points[e.name] = point(v); break;
      case human::ParamKind::kPoints:
        for (const ValueTree& item : v.items) p.paths[e.name].push_back(point(item));
        break;
      case human::ParamKind::kZone:
        for (size_t i = 0; i < v.keys.size(); ++i) {
          if (v.keys[i] == "center") p.zones[e.name].center = point(v.items[i]);
          if (v.keys[i] == "radius") p.zones[e.name].radius = v.items[i].scalar.expr.number;
        }
        break;
      case human::ParamKind::kObject: p.objects[e.name] = v.scalar.expr.text; break;
    }
  }
  return p;
}

// Closest approach (m) of the palm of `side` to `target` over the clip.
double closest_palm(const human::Skeleton& skeleton, const human::Clip& clip, human::Side side,
                    const core::Vec3& target) {
  double best = 1e9;
  for (const human::SkeletonPose& pose : clip.frames) {
    best = std::min(best, (human::hand_point(skeleton, pose, side, human::HandPoint::kPalm) - target).norm());
  }
  return best;
}

TEST(TasksTest, TheThirteenTaskFilesExistAndNothingElse) {
  std::set<std::string> found;
  for (const auto& entry : std::filesystem::directory_iterator("tasks")) {
    if (entry.path().extension() == ".yaml") found.insert(entry.path().stem().string());
  }
  const std::set<std::string> expected(task_files().begin(), task_files().end());
  EXPECT_EQ(found, expected);
}

TEST(TasksTest, EveryTaskIsCleanForTheValidator) {
  for (const std::string& name : task_files()) {
    const std::vector<Problem> problems = check(path_of(name));
    std::string text;
    for (const Problem& p : problems) text += p.text() + "\n";
    EXPECT_TRUE(problems.empty()) << name << ":\n" << text;
  }
}

TEST(TasksTest, TaskNameAndRoleFollowTheFileName) {
  const std::map<char, std::string> roles = {{'I', "instructor"}, {'C', "collaborator"}, {'X', "intruder"}};
  for (const std::string& name : task_files()) {
    const Scenario s = load_scenario(path_of(name));
    EXPECT_EQ(s.task, name.substr(3)) << name;
    EXPECT_EQ(s.role, roles.at(name[0])) << name;
  }
}

TEST(TasksTest, SamplingIsDeterministicAndEveryEpisodeCompiles) {
  for (const std::string& name : task_files()) {
    const Scenario s = load_scenario(path_of(name));
    std::set<std::string> hashes;
    for (uint64_t seed = 0; seed < kSeeds; ++seed) {
      const EpisodeSpec a = sample(s, seed);
      const EpisodeSpec b = sample(s, seed);
      ASSERT_EQ(spec_hash(a), spec_hash(b)) << name << " seed " << seed;
      EXPECT_EQ(spec_from_text(spec_to_text(a), name), a) << name << " seed " << seed;
      hashes.insert(spec_hash(a));
      // Every variant's acts refer only to events of that episode.
      EXPECT_NO_THROW(compile(a)) << name << " seed " << seed << " variant " << a.variant;
      EXPECT_EQ(a.instruction.find('{'), std::string::npos) << name << ": " << a.instruction;
    }
    EXPECT_EQ(hashes.size(), static_cast<size_t>(kSeeds)) << name;
  }
}

TEST(TasksTest, PersonAndObjectsAreWithinReach) {
  for (const std::string& name : task_files()) {
    const Scenario s = load_scenario(path_of(name));
    for (uint64_t seed = 0; seed < kSeeds; ++seed) {
      const EpisodeSpec spec = sample(s, seed);
      const double height = spec.human.height.value();
      EXPECT_GE(height, 1.55) << name;
      EXPECT_LE(height, 1.95) << name;
      const double px = spec.human.stand.x.value();
      // The person stands close to the far table edge (x 1.05), facing the robot.
      EXPECT_GE(px, 1.20) << name;
      EXPECT_LE(px, 1.35) << name;
      EXPECT_NEAR(spec.human.stand.yaw_deg.value(), 180.0, 10.0) << name;
      for (const Entry<SceneObject>& o : spec.scene.objects) {
        if (!o.value.pose || o.name.rfind("distractor_", 0) == 0) continue;
        const double x = o.value.pose->xy[0].value();
        const double y = o.value.pose->xy[1].value();
        EXPECT_GE(x, -0.15) << name << " " << o.name;
        EXPECT_LE(x, 1.05) << name << " " << o.name;
        EXPECT_LE(std::abs(y), 0.45) << name << " " << o.name;
        // Objects the robot works with are within the Panda's reach (about 0.8 m).
        if (x < 0.8) {
          EXPECT_LE(std::hypot(x, y), 0.80) << name << " " << o.name;
          EXPECT_GE(std::hypot(x, y), 0.25) << name << " " << o.name;
        }
      }
    }
  }
}

// Footprints (nominal half extents of model/objects.cc, rotated by the yaw, as axis-aligned
// boxes) of the task's objects resting on the table never overlap. Distractors are placed by
// sample() and not checked here.
TEST(TasksTest, TaskObjectsDoNotOverlapOnTheTable) {
  static const std::map<std::string, std::pair<double, double>> half = {
      {"cube", {0.025, 0.025}}, {"cup", {0.035, 0.035}}, {"bottle", {0.032, 0.032}},
      {"plate", {0.1, 0.1}},    {"bin", {0.12, 0.09}},   {"tray", {0.15, 0.11}},
      {"box", {0.1, 0.08}},     {"plank", {0.3, 0.03}},  {"platform", {0.25, 0.1}}};
  struct Footprint {
    std::string name;
    double x0, x1, y0, y1;
  };
  for (const std::string& name : task_files()) {
    const Scenario s = load_scenario(path_of(name));
    for (uint64_t seed = 0; seed < 100; ++seed) {
      const EpisodeSpec spec = sample(s, seed);
      std::vector<Footprint> prints;
      for (const Entry<SceneObject>& o : spec.scene.objects) {
        // Objects raised on another (z given) and distractors are not resting on the table top.
        if (!o.value.pose || o.value.pose->z || o.name.rfind("distractor_", 0) == 0) continue;
        auto [hx, hy] = half.at(o.value.kind.value());
        if (!o.value.size.empty()) {
          hx = o.value.size[0].value() / 2;
          hy = o.value.size[1].value() / 2;
        }
        const double yaw = o.value.pose->yaw_deg.value() * core::kPi / 180;
        const double ax = std::abs(hx * std::cos(yaw)) + std::abs(hy * std::sin(yaw));
        const double ay = std::abs(hx * std::sin(yaw)) + std::abs(hy * std::cos(yaw));
        const double x = o.value.pose->xy[0].value(), y = o.value.pose->xy[1].value();
        prints.push_back({o.name, x - ax, x + ax, y - ay, y + ay});
      }
      for (size_t i = 0; i < prints.size(); ++i) {
        for (size_t j = i + 1; j < prints.size(); ++j) {
          const Footprint& a = prints[i];
          const Footprint& b = prints[j];
          const bool overlap = a.x0 < b.x1 && b.x0 < a.x1 && a.y0 < b.y1 && b.y0 < a.y1;
          EXPECT_FALSE(overlap) << name << " seed " << seed << ": " << a.name << " and " << b.name;
        }
      }
    }
  }
}

// Every human act, synthesized from a standing start by the human layer, reaches its hand
// targets (palm within 5 cm; a two-handed lift within half the grip width more) and points
// through its pointing target: the scripts stay within reach for heights 1.55-1.95 m.
TEST(TasksTest, HumanMotionReachesEveryTarget) {
  constexpr double kReach = 0.05;
  for (const std::string& name : task_files()) {
    const Scenario s = load_scenario(path_of(name));
    for (uint64_t seed = 0; seed < 12; ++seed) {
      const EpisodeSpec spec = sample(s, seed);
      const human::Skeleton skeleton = human::Skeleton::FromHeight(spec.human.height.value());
      const human::SkeletonPose start = human::SkeletonPose::Standing(
          skeleton, spec.human.stand.x.value(), spec.human.stand.y.value(),
          spec.human.stand.yaw_deg.value() * core::kPi / 180);
      for (const Entry<Act>& a : spec.acts) {
        if (!a.value.motion) continue;
        const human::PrimitiveParams p = primitive_params(spec, *a.value.motion);
        // Acts that continue from an earlier act's pose (carrying, lowering) are not standalone.
        if (p.primitive == "carry" || p.primitive == "lower") continue;
        const std::string where = name + " seed " + std::to_string(seed) + " act " + a.name;
        human::LabelledClip clip;
        ASSERT_NO_THROW(clip = human::generate_clip(skeleton, start, p, 30)) << where;
        const human::Side side = p.choices.count("hand") != 0 && p.choices.at("hand") == "left"
                                     ? human::Side::kLeft : human::Side::kRight;
        if (p.primitive == "point") {
          const human::CheckResult r =
              human::check_pointing(clip.clip, side, p.points.at("target"), kReach, "hold");
          EXPECT_TRUE(r.ok) << where << ": " << r.message;
          continue;
        }
        if (p.primitive == "give_me" || p.primitive == "your_turn" || p.primitive == "walk_to") continue;
        const double slack = p.primitive == "lift" ? p.numbers.at("grip_width") / 2 + 0.03 : 0.0;
        for (const char* key : {"target", "from", "to", "handle"}) {
          if (p.points.count(key) == 0) continue;
          EXPECT_LE(closest_palm(skeleton, clip.clip, side, p.points.at(key)), kReach + slack)
              << where << " " << key;
        }
        if (p.zones.count("zone") != 0) {
          EXPECT_LE(closest_palm(skeleton, clip.clip, side, p.zones.at("zone").center), kReach)
              << where << " zone";
        }
      }
    }
  }
}

// Runs the act-graph runtime of a sampled episode in a world where the robot never moves (the
// `noop` baseline): objects stay where they start, an object held from the start stays in its
// hand, the hands hang at the person's sides. Returns the runtime state at the horizon.
RuntimeState run_still_world(const EpisodeSpec& spec, const ActGraph& graph) {
  WorldSnapshot world;
  for (const std::string& name : graph.objects) {
    ObjectState o;
    const Entry<SceneObject>* object = find_object(spec, name);
    if (!object->value.held_by) o.X_WO.translation = object_centre(spec, name);
    o.p_WO_initial = o.X_WO.translation;
    o.half_extents = core::Vec3(0.03, 0.03, 0.03);
    world.objects.push_back(o);
  }
  world.X_WT.translation = core::Vec3(0.3, 0.0, 1.25);
  const double px = spec.human.stand.x.value(), py = spec.human.stand.y.value();
  world.hands[kLeftHand].p_W = core::Vec3(px, py - 0.2, 0.85);
  world.hands[kRightHand].p_W = core::Vec3(px, py + 0.2, 0.85);
  for (size_t i = 0; i < graph.objects.size(); ++i) {
    const Entry<SceneObject>* object = find_object(spec, graph.objects[i]);
    if (!object->value.held_by) continue;
    const int hand = object->value.held_by->value() == "human.left" ? kLeftHand : kRightHand;
    world.hands[static_cast<size_t>(hand)].held_object = static_cast<int>(i);
    world.objects[i].X_WO.translation = world.hands[static_cast<size_t>(hand)].p_W;
  }
  RuntimeState state = make_runtime(graph);
  for (int k = 0; k * 0.05 <= spec.horizon; ++k) {
    world.time = k * 0.05;
    step(graph, state, world);
  }
  return state;
}

// With a robot that never moves, the person's scheduled acts and cues all happen within the
// horizon, the person's reactive acts (triggered by the robot) never start, and C1's person
// gives up (the episode fails).
TEST(TasksTest, WithARobotThatNeverMovesScheduledCuesHappenAndReactiveActsDoNot) {
  const std::map<std::string, std::vector<std::string>> happen = {
      {"I1_point_pick", {"point.stroke", "point.end"}},
      {"I2_gesture_delivery", {"ask.gesture", "take.open"}},
      {"I3_demo_imitate", {"demo.release", "step_back.end", "your_turn.gesture"}},
      {"I4_stop_go", {"go.gesture"}},
      {"C1_handover_h2r", {"offer.hold_stable", "give_up.start"}},
      {"C3_box_retrieval", {"lid.hold", "lid.close", "lid.end"}},
      {"C4_co_lift", {"hlift.lift", "carry.end", "put_down.release"}},
      {"X1_intrusion_yield", {"intrude.dwell", "intrude.end"}}};
  const std::map<std::string, std::vector<std::string>> never = {
      {"I4_stop_go", {"halt.start"}},
      {"I5_contradiction", {"wave_off.start", "point_tray.start"}},
      {"C2_handover_r2h", {"take.start"}},
      {"X2_object_moved", {"relocate.start"}},
      {"X3_someone_else_places", {"do_it.start"}},
      {"X4_blocked_target", {"block.start", "set_down.start"}}};
  std::set<std::string> named;  // "never" events that exist in some sampled episode
  for (const std::string& name : task_files()) {
    const Scenario s = load_scenario(path_of(name));
    for (uint64_t seed = 0; seed < 12; ++seed) {
      const EpisodeSpec spec = sample(s, seed);
      const ActGraph graph = compile(spec);
      const RuntimeState state = run_still_world(spec, graph);
      const std::string where = name + " seed " + std::to_string(seed) + " variant " + spec.variant;
      if (happen.count(name) != 0) {
        for (const std::string& e : happen.at(name)) {
          EXPECT_FALSE(std::isnan(event_time(graph, state, e))) << where << ": " << e;
        }
      }
      if (never.count(name) != 0) {
        for (const std::string& e : never.at(name)) {
          if (graph.event_id(e) >= 0) named.insert(name + " " + e);
          EXPECT_TRUE(std::isnan(event_time(graph, state, e))) << where << ": " << e;
        }
      }
      EXPECT_EQ(state.failed_at >= 0, name == "C1_handover_h2r") << where;
    }
  }
  size_t expected = 0;
  for (const auto& [task, events] : never) expected += events.size();
  EXPECT_EQ(named.size(), expected);  // every listed event is an event of some episode
}

TEST(TasksTest, I1PointsAtOneOfTheSceneObjectsAndTheRobotWaitsForTheStroke) {
  const Scenario s = load_scenario(path_of("I1_point_pick"));
  std::set<std::string> targets;
  for (uint64_t seed = 0; seed < 60; ++seed) {
    const EpisodeSpec spec = sample(s, seed);
    const Entry<Act>* point = find_act(spec, "point");
    ASSERT_NE(point, nullptr);
    const std::string target = word_param(*point->value.motion, "target");
    targets.insert(target);
    ASSERT_NE(find_object(spec, target), nullptr) << target;
    EXPECT_NE(find_object(spec, "bin"), nullptr);
    EXPECT_EQ(point->value.label->through->value(), target);
    const Entry<Act>* put = find_act(spec, "put");
    ASSERT_NE(put, nullptr);
    EXPECT_EQ(put->value.goal->source, "in(" + target + ", bin)");
    EXPECT_EQ(*put->value.after, "point.stroke");
    EXPECT_EQ(spec.success[0].source, "in(" + target + ", bin)");
    // 3-5 objects of similar size besides the bin.
    size_t candidates = 0;
    for (const Entry<SceneObject>& o : spec.scene.objects) {
      if (o.name == "bin") continue;
      ++candidates;
      EXPECT_TRUE(o.value.kind.value() == "cube" || o.value.kind.value() == "cup") << o.name;
    }
    EXPECT_GE(candidates, 3U);
    EXPECT_LE(candidates, 5U);
  }
  EXPECT_EQ(targets, (std::set<std::string>{"obj_a", "obj_b", "obj_c"}));
}

// Variant frequencies over `n` seeds.
std::map<std::string, int> variant_counts(const std::string& task, int n) {
  const Scenario s = load_scenario(path_of(task));
  std::map<std::string, int> counts;
  for (int seed = 0; seed < n; ++seed) ++counts[sample(s, static_cast<uint64_t>(seed)).variant];
  return counts;
}

TEST(TasksTest, I5CancelRedirectAndControlAreAboutAThirdEach) {
  const std::map<std::string, int> counts = variant_counts("I5_contradiction", 300);
  ASSERT_EQ(counts.size(), 3U);
  for (const char* v : {"cancel", "redirect", "control"}) {
    EXPECT_GE(counts.at(v), 75) << v;   // 1/3 of 300 = 100; 75..125 is about +-4.5 sigma
    EXPECT_LE(counts.at(v), 125) << v;
  }
  const Scenario s = load_scenario(path_of("I5_contradiction"));
  for (uint64_t seed = 0; seed < 30; ++seed) {
    const EpisodeSpec spec = sample(s, seed);
    int contradictions = 0;
    for (const Entry<Act>& a : spec.acts) {
      if (!a.value.contradicts) continue;
      ++contradictions;
      const Entry<Act>* target = find_act(spec, *a.value.contradicts);
      ASSERT_NE(target, nullptr);
      EXPECT_EQ(target->value.actor, "robot");
      EXPECT_EQ(target->value.goal->source, "on(item, plate)");
      // The contradicted act is the last robot act: it must never complete.
      EXPECT_EQ(target, &spec.acts.back());
    }
    EXPECT_EQ(contradictions, spec.variant == "control" ? 0 : 1) << spec.variant;
  }
}

TEST(TasksTest, I4HasAStopInAtLeastHalfTheEpisodes) {
  const std::map<std::string, int> counts = variant_counts("I4_stop_go", 300);
  EXPECT_GE(counts.at("with_stop"), 150);
  const Scenario s = load_scenario(path_of("I4_stop_go"));
  for (uint64_t seed = 0; seed < 20; ++seed) {
    const EpisodeSpec spec = sample(s, seed);
    const Entry<Act>* halt = find_act(spec, "halt");
    const Entry<Act>* place = find_act(spec, "place");
    ASSERT_NE(place, nullptr);
    EXPECT_EQ(*place->value.after, "go.gesture");
    if (spec.variant != "with_stop") {
      EXPECT_EQ(halt, nullptr);
      continue;
    }
    ASSERT_NE(halt, nullptr);
    EXPECT_TRUE(halt->value.disruption);
    EXPECT_EQ(halt->value.cue->kind, "stop");
    const double hold = find_param(*halt->value.motion, "hold")->scalar.expr.number;
    EXPECT_GE(hold, 1.0);
    EXPECT_LE(hold, 3.0);
    ASSERT_TRUE(place->value.still.has_value());
    EXPECT_EQ(place->value.still->from, "halt.hold");
  }
}

TEST(TasksTest, IntruderTasksHaveADisruptionInEveryEpisode) {
  for (const char* name : {"X1_intrusion_yield", "X2_object_moved", "X3_someone_else_places",
                           "X4_blocked_target"}) {
    const Scenario s = load_scenario(path_of(name));
    for (uint64_t seed = 0; seed < kSeeds; ++seed) {
      const EpisodeSpec spec = sample(s, seed);
      int disruptions = 0;
      for (const Entry<Act>& a : spec.acts) {
        if (!a.value.disruption) continue;
        ++disruptions;
        EXPECT_EQ(a.value.actor, "human") << name;
        ASSERT_TRUE(a.value.cue.has_value()) << name << " " << a.name;
      }
      // One intrusion; X4's object variant also marks the clearing of the plate.
      EXPECT_GE(disruptions, 1) << name << " seed " << seed;
      EXPECT_LE(disruptions, 2) << name << " seed " << seed;
    }
  }
}

TEST(TasksTest, X1IntrusionIsOnAFixedScheduleAndCrossesTheWorkspace) {
  const Scenario s = load_scenario(path_of("X1_intrusion_yield"));
  for (uint64_t seed = 0; seed < kSeeds; ++seed) {
    const EpisodeSpec spec = sample(s, seed);
    const Entry<Act>* intrude = find_act(spec, "intrude");
    ASSERT_NE(intrude, nullptr);
    EXPECT_FALSE(intrude->value.when.has_value());  // policy-independent
    EXPECT_GE(intrude->value.onset->value(), 1.5);
    const double dwell = find_param(*intrude->value.motion, "dwell")->scalar.expr.number;
    EXPECT_GE(dwell, 1.0);
    EXPECT_LE(dwell, 3.0);
    EXPECT_EQ(*intrude->value.label->crosses, "workspace");
  }
}

TEST(TasksTest, CollaboratorTasksHaveSyncConstraints) {
  const std::map<std::string, std::string> syncs = {{"C1_handover_h2r", "offer.hold_stable"},
                                                    {"C2_handover_r2h", "take.close"},
                                                    {"C3_box_retrieval", "lid.hold"},
                                                    {"C4_co_lift", "hlift.lift"}};
  for (const auto& [name, event] : syncs) {
    const EpisodeSpec spec = sample(load_scenario(path_of(name)), 7);
    std::vector<std::string> with;
    for (const Entry<Act>& a : spec.acts) {
      if (a.value.sync) with.push_back(a.value.sync->with);
    }
    EXPECT_NE(std::find(with.begin(), with.end(), event), with.end()) << name;
  }
}

TEST(TasksTest, C1PersonGivesUpAfterThreeToSixSecondsUnlessGrasped) {
  const Scenario s = load_scenario(path_of("C1_handover_h2r"));
  for (uint64_t seed = 0; seed < kSeeds; ++seed) {
    const EpisodeSpec spec = sample(s, seed);
    const Entry<Act>* give_up = find_act(spec, "give_up");
    ASSERT_NE(give_up, nullptr);
    EXPECT_TRUE(give_up->value.fails);
    EXPECT_EQ(*give_up->value.after, "offer.hold_stable");
    EXPECT_GE(give_up->value.delay->value(), 3.0);
    EXPECT_LE(give_up->value.delay->value(), 6.0);
    EXPECT_EQ(give_up->value.unless->source, "grasped(robot, item)");
    // The handover contact (fingers vs the giving hand) is permitted only during the transfer.
    const std::string hand = find_object(spec, "item")->value.held_by->value().substr(6);
    ASSERT_EQ(spec.safety.contact_permitted.size(), 1U);
    EXPECT_EQ(spec.safety.contact_permitted[0].robot.value(), "fingers");
    EXPECT_EQ(spec.safety.contact_permitted[0].human.value(), hand + ".hand");
  }
}

TEST(TasksTest, C3WindowIsFourToNineSecondsAndTheRobotMustLeaveBeforeTheLidCloses) {
  const Scenario s = load_scenario(path_of("C3_box_retrieval"));
  for (uint64_t seed = 0; seed < kSeeds; ++seed) {
    const EpisodeSpec spec = sample(s, seed);
    const Entry<Act>* lid = find_act(spec, "lid");
    ASSERT_NE(lid, nullptr);
    const double hold = find_param(*lid->value.motion, "hold")->scalar.expr.number;
    EXPECT_GE(hold, 4.0);
    EXPECT_LE(hold, 9.0);
    EXPECT_EQ(*find_act(spec, "leave")->value.before, "lid.close");
    EXPECT_EQ(find_object(spec, "item")->value.in->value(), "box");
  }
}

}  // namespace
}  // namespace hribench::script

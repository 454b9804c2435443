#include "eval/script_driver.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <fstream>
#include <functional>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "core/errors.h"
#include "eval/runner.h"
#include "human/skeleton.h"
#include "model/model.h"
#include "policy/builtin.h"
#include "script/check.h"
#include "script/sample.h"
#include "script/schema_io.h"
#include "sim/control.h"
#include "sim/data.h"
#include "sim/hold.h"
#include "support/mujoco_fixture.h"

namespace hribench::eval {
namespace {

class ScriptDriverTest : public hribench::testing::MujocoTest {
 protected:
  static script::EpisodeSpec stop_go_spec() {
    return script::sample(script::load_scenario("tests/data/scripts/good/stop_go.yaml"), 1);
  }
  EpisodeLog run(const script::EpisodeSpec& spec, const model::Model& model, double horizon = 4.0) {
    sim::Data data = sim::make_data(model);
    ScriptDriver driver(spec);
    policy::NoopPolicy noop;
    RunOptions options;
    options.horizon = horizon;
    EpisodeSetup setup;
    setup.task = spec.task;
    setup.role = spec.role;
    setup.seed = spec.seed;
    setup.policy = "noop";
    EpisodeLog log = run_episode(model, data, noop, driver, setup, options);
    ExpectNoWarnings(data.mj.get());
    return log;
  }
  // Runs a script's episode (seed) with the robot at home, calling `at` after every control
  // step (what the runner does, without a policy); returns when `at` returns false or at
  // the horizon.
  static void play(const script::EpisodeSpec& spec, const model::Model& model, double horizon,
                   const std::function<bool(const ScriptDriver&, const sim::Data&, const std::vector<uint8_t>&)>& at) {
    Started s(spec, model);
    while (s.data.time() < horizon) {
      for (int i = 0; i < 25; ++i) {
        s.driver.drive(model, s.data);
        sim::step(model, s.data);
      }
      s.observe(model);
      if (!at(s.driver, s.data, s.predicates)) break;
    }
    ExpectNoWarnings(s.data.mj.get());
  }
  // A script's driver and state at the start of an episode, the robot at home.
  struct Started {
    Started(const script::EpisodeSpec& spec, const model::Model& model)
        : data(sim::make_data(model)), driver(spec) {
      sim::reset(model, data);
      driver.reset(model, data);
      sim::forward(model, data);
    }
    // After a control step's physics steps: the state forwarded, then observed by the driver.
    void observe(const model::Model& model) {
      sim::forward(model, data);
      driver.observe(model, data, predicates, events);
    }
    sim::Data data;
    ScriptDriver driver;
    std::vector<uint8_t> predicates;
    std::vector<Event> events;
  };
  // A script's text sampled at seed 1 (a script that does not parse fails the test).
  static script::EpisodeSpec sample_text(const std::string& yaml, const std::string& name) {
    std::vector<core::InputError> problems;
    const script::Scenario scenario = script::parse_scenario(yaml, name, problems);
    for (const core::InputError& e : problems) ADD_FAILURE() << e.what();
    return script::sample(scenario, 1);
  }
  // Samples a script at seed 1, builds its model and runs a noop episode.
  EpisodeLog run_script(const std::string& path, double horizon) {
    const script::EpisodeSpec spec = script::sample(script::load_scenario(path), 1);
    const model::Model model = model::build(scene_spec_from_episode(spec));
    return run(spec, model, horizon);
  }
};

TEST_F(ScriptDriverTest, SceneSpecCarriesObjectsAndHuman) {
  const script::EpisodeSpec spec = stop_go_spec();
  const model::SceneSpec scene = scene_spec_from_episode(spec);
  ASSERT_EQ(scene.objects.size(), spec.scene.objects.size());
  EXPECT_EQ(scene.objects[0].name, "cube");
  EXPECT_EQ(scene.objects[0].kind, "cube");
  EXPECT_DOUBLE_EQ(scene.objects[0].x, spec.scene.objects[0].value.pose->xy[0].value());
  EXPECT_DOUBLE_EQ(scene.human.height, spec.human.height.value());
  EXPECT_NEAR(scene.human.yaw, spec.human.stand.yaw_deg.value() * core::kPi / 180, 1e-12);
}

// The message scene_spec_from_episode refuses a spec with ("" if it accepts it).
std::string scene_error(const script::EpisodeSpec& spec) {
  try {
    scene_spec_from_episode(spec);
  } catch (const core::InputError& e) {
    return e.what();
  }
  return "";
}

TEST_F(ScriptDriverTest, GrayBecomesGreyAndSizesOnlyForPlatforms) {
  script::EpisodeSpec spec = stop_go_spec();
  spec.scene.objects[1].value.color = script::Text("gray");
  EXPECT_EQ(scene_spec_from_episode(spec).objects[1].colour, "grey");
  spec.scene.objects[0].value.size = {script::Num(0.1), script::Num(0.1), script::Num(0.1)};
  EXPECT_EQ(scene_error(spec),
            "scene.objects.cube: an explicit size is not supported by the model (only the kind's size)");
  spec.scene.objects[0].value.kind = script::Text("platform");
  spec.scene.objects[0].value.size.pop_back();
  EXPECT_EQ(scene_error(spec), "scene.objects.cube: a platform needs a size [x, y, z] and a pose xy");
  spec = stop_go_spec();
  spec.scene.objects[0].value.pose->z = script::Num(0.9);
  EXPECT_EQ(scene_error(spec),
            "scene.objects.cube.pose.z: a height is only supported over a platform (the object rests on it)");
}

// C3 and C4 map to the model: the item inside the box, the support and the platform as
// named platforms with the plank resting on the support.
TEST_F(ScriptDriverTest, ContainersAndPlatformsMapToTheModel) {
  const script::EpisodeSpec c3 = script::sample(script::load_scenario("tasks/C3_box_retrieval.yaml"), 3);
  const model::SceneSpec box_scene = scene_spec_from_episode(c3);
  ASSERT_EQ(box_scene.objects.size(), 3u);
  EXPECT_EQ(box_scene.objects[1].name, "item");
  EXPECT_EQ(box_scene.objects[1].inside, "box");
  EXPECT_DOUBLE_EQ(box_scene.objects[1].y, box_scene.objects[0].y);
  EXPECT_NO_THROW(model::build(box_scene));
  const script::EpisodeSpec c4 = script::sample(script::load_scenario("tasks/C4_co_lift.yaml"), 3);
  const model::SceneSpec lift_scene = scene_spec_from_episode(c4);
  ASSERT_EQ(lift_scene.platforms.size(), 2u);
  EXPECT_EQ(lift_scene.platforms[0].name, "support");
  EXPECT_DOUBLE_EQ(lift_scene.platforms[0].height, 0.08);
  EXPECT_EQ(lift_scene.platforms[1].name, "platform");
  EXPECT_DOUBLE_EQ(lift_scene.platforms[1].width, 0.20);
  ASSERT_EQ(lift_scene.objects.size(), 1u);
  EXPECT_EQ(lift_scene.objects[0].on, "support");
  EXPECT_NO_THROW(model::build(lift_scene));
}

// C3: the person's hand holds the lid open by its edge through the hold phase and closes it.
TEST_F(ScriptDriverTest, ThePersonHoldsTheBoxLidOpenDuringTheHold) {
  const script::EpisodeSpec spec = script::sample(script::load_scenario("tasks/C3_box_retrieval.yaml"), 1);
  const model::Model model = model::build(scene_spec_from_episode(spec));
  const model::ObjectInfo& box = model.objects[static_cast<size_t>(model.object_index("box"))];
  const int hinge = model.m()->jnt_qposadr[box.lid_joint];
  double open_deg = 0;
  for (const auto& v : spec.acts[0].value.motion->params) {
    if (v.name == "open_deg") open_deg = v.value.scalar.expr.number;
  }
  double min_in_hold = 1e9, max_before = 0;
  std::optional<double> after_close;
  bool held_box = false;
  play(spec, model, 30.0, [&](const ScriptDriver& driver, const sim::Data& data, const std::vector<uint8_t>&) {
    const double lid = data.mj->qpos[hinge] * 180 / core::kPi;
    const double t = data.time();
    const double hold = script::event_time(driver.graph(), driver.runtime(), "lid.hold");
    const double close = script::event_time(driver.graph(), driver.runtime(), "lid.close");
    const double end = script::event_time(driver.graph(), driver.runtime(), "lid.end");
    if (std::isnan(hold)) max_before = std::max(max_before, lid);
    if (!std::isnan(hold) && t > hold + 0.3 && std::isnan(close)) min_in_hold = std::min(min_in_hold, lid);
    if (sim::held_object(data, human::Side::kRight) == model.object_index("box")) held_box = true;
    if (!std::isnan(end) && t > end + 1.0) {
      after_close = lid;
      return false;
    }
    return true;
  });
  EXPECT_TRUE(held_box);
  EXPECT_LT(max_before, open_deg);
  // Open to about the drawn angle (the hinge stops at 1.9 rad = 109 deg).
  EXPECT_GT(min_in_hold, std::min(open_deg, 109.0) - 20) << "drawn " << open_deg;
  ASSERT_TRUE(after_close.has_value()) << "the lid act never ended";
  EXPECT_LT(std::abs(*after_close), 10);
}

// Concurrent acts on different hands: the left hand points at the tray while the right holds
// the lid open; each hand plays its own act, so the lid still closes on the lid act's schedule
// (the right arm is not frozen by the later pointing act) and the left hand points.
TEST_F(ScriptDriverTest, ConcurrentActsMoveTheirOwnHands) {
  std::ifstream in("tasks/C3_box_retrieval.yaml");
  std::stringstream text;
  text << in.rdbuf();
  std::string yaml = text.str();
  const std::string pointing = R"(  look:
    actor: human
    after: lid.hold
    delay: 0.5
    motion:
      primitive: point
      hand: left
      target: tray
      prep: 0.3
      stroke: 0.6
      hold: 1.0
      retract: 0.7
      extension: 0.85
)";
  const size_t robot_acts = yaml.find("  # Robot acts");
  ASSERT_NE(robot_acts, std::string::npos);
  yaml.insert(robot_acts, pointing);
  const script::EpisodeSpec spec = sample_text(yaml, "C3+look");
  const model::Model model = model::build(scene_spec_from_episode(spec));
  const model::ObjectInfo& box = model.objects[static_cast<size_t>(model.object_index("box"))];
  const int hinge = model.m()->jnt_qposadr[box.lid_joint];
  const size_t left_wrist = static_cast<size_t>(human::index(human::Joint::kLeftWrist));
  core::Vec3 left_start = core::Vec3::Zero();
  double left_moved = 0, open_while_pointing = 1e9;
  std::optional<double> after_close;
  play(spec, model, 30.0, [&](const ScriptDriver& driver, const sim::Data& data, const std::vector<uint8_t>&) {
    const double t = data.time();
    const double look_hold = script::event_time(driver.graph(), driver.runtime(), "look.hold");
    const double look_retract = script::event_time(driver.graph(), driver.runtime(), "look.retract");
    const double lid_end = script::event_time(driver.graph(), driver.runtime(), "lid.end");
    if (left_start.isZero()) left_start = data.X_WJ[left_wrist].translation;
    left_moved = std::max(left_moved, (data.X_WJ[left_wrist].translation - left_start).norm());
    if (!std::isnan(look_hold) && std::isnan(look_retract)) {
      open_while_pointing = std::min(open_while_pointing, data.mj->qpos[hinge] * 180 / core::kPi);
    }
    if (!std::isnan(lid_end) && t > lid_end + 1.0) {
      after_close = data.mj->qpos[hinge] * 180 / core::kPi;
      return false;
    }
    return true;
  });
  EXPECT_GT(left_moved, 0.15);
  EXPECT_GT(open_while_pointing, 80);
  ASSERT_TRUE(after_close.has_value());
  EXPECT_LT(std::abs(*after_close), 10);
}

// CIR series: with an act that contradicts a robot act, "intent" is the contradicted act's goal
// (the instruction) until the contradiction starts and the success predicates from then on;
// "contradicted" is the contradicted act's goal once the contradiction started.
TEST_F(ScriptDriverTest, AContradictionAddsIntentAndContradictedSeries) {
  const std::string yaml = R"(hribench: 1
task: contra
role: instructor
instruction: "Put the cube on the plate."
horizon: 5
scene:
  objects:
    cube: {kind: cube, color: red, pose: {xy: [0.45, -0.2]}}
    plate: {kind: plate, color: white, pose: {xy: [0.45, 0.25]}}
human:
  height: 1.75
  stand: {x: 1.3, y: 0, yaw_deg: 180}
  handedness: right
acts:
  nope:
    actor: human
    onset: 1.0
    motion: {primitive: cancel, hand: right, style: wave_off, raise: 0.5, gesture: 1.0}
    contradicts: deliver
    cue: {at: nope.gesture, window: 1.5, kind: stop}
  deliver:
    actor: robot
    goal: not moved(cube, 0.05)
success:
  - on(cube, plate)
)";
  const script::EpisodeSpec spec = sample_text(yaml, "contra");
  const model::Model model = model::build(scene_spec_from_episode(spec));
  EXPECT_EQ(ScriptDriver(spec).predicate_names(), (std::vector<std::string>{"success", "intent", "contradicted"}));
  std::vector<std::pair<double, std::vector<uint8_t>>> seen;
  play(spec, model, 2.0, [&](const ScriptDriver&, const sim::Data& data, const std::vector<uint8_t>& p) {
    seen.emplace_back(data.time(), p);
    return true;
  });
  ASSERT_FALSE(seen.empty());
  for (const auto& [t, p] : seen) {
    ASSERT_EQ(p.size(), 3u);
    // intent: the instruction (deliver's goal, true) until the contradiction starts at 1 s
    // (the step whose time rounds to it: 200 steps of 5 ms add to 1 + 7e-16), then the
    // success predicates (false).
    const bool started = t >= 1.0 - 1e-9;
    EXPECT_EQ(p[1], started ? p[0] : 1) << t;
    EXPECT_EQ(p[0], 0) << t;
    EXPECT_EQ(p[2], started ? 1 : 0) << t;
  }
  // Without a contradiction: only "success".
  EXPECT_EQ(ScriptDriver(stop_go_spec()).predicate_names(), std::vector<std::string>{"success"});
}

// A pointing act that starts mid-walk does not stop the walk: the pelvis reaches the walk's
// goal while the hand points.
TEST_F(ScriptDriverTest, AnActStartedMidWalkDoesNotStopTheWalk) {
  const std::string yaml = R"(hribench: 1
task: walk_and_point
role: instructor
instruction: "Watch."
horizon: 8
scene:
  objects:
    cube: {kind: cube, color: red, pose: {xy: [0.45, -0.2]}}
human:
  height: 1.75
  stand: {x: 1.4, y: 0, yaw_deg: 180}
  handedness: right
acts:
  step:
    actor: human
    onset: 0.5
    motion: {primitive: walk_to, to: [1.4, 0.6, 0], speed: 0.6, turn: 0.3, yaw_deg: 180}
  look:
    actor: human
    after: step.walk
    delay: 0.4
    motion: {primitive: point, hand: right, target: cube, prep: 0.3, stroke: 0.5, hold: 0.8, retract: 0.5}
success:
  - on(cube, table)
)";
  const script::EpisodeSpec spec = sample_text(yaml, "walk_and_point");
  const model::Model model = model::build(scene_spec_from_episode(spec));
  const size_t pelvis = static_cast<size_t>(human::index(human::Joint::kPelvis));
  const size_t wrist = static_cast<size_t>(human::index(human::Joint::kRightWrist));
  double pelvis_y_when_done = -1, wrist_moved = 0;
  bool look_started_mid_walk = false;
  core::Vec3 wrist_start = core::Vec3::Zero();
  play(spec, model, 8.0, [&](const ScriptDriver& driver, const sim::Data& data, const std::vector<uint8_t>&) {
    const double look = script::event_time(driver.graph(), driver.runtime(), "look.start");
    const double face = script::event_time(driver.graph(), driver.runtime(), "step.face");
    if (!std::isnan(look) && std::isnan(face)) look_started_mid_walk = true;
    if (!std::isnan(look) && wrist_start.isZero()) wrist_start = data.X_WJ[wrist].translation - data.X_WJ[pelvis].translation;
    if (!wrist_start.isZero()) {
      wrist_moved = std::max(wrist_moved, (data.X_WJ[wrist].translation - data.X_WJ[pelvis].translation - wrist_start).norm());
    }
    if (!std::isnan(script::event_time(driver.graph(), driver.runtime(), "step.end"))) {
      pelvis_y_when_done = data.X_WJ[pelvis].translation.y();
      return false;
    }
    return true;
  });
  EXPECT_TRUE(look_started_mid_walk);
  EXPECT_NEAR(pelvis_y_when_done, 0.6, 0.05);
  EXPECT_GT(wrist_moved, 0.15);
}

// An imported clip (a captured walk) plays from where the person stands, stretched to the
// act's duration.
TEST_F(ScriptDriverTest, AnImportedClipPlaysFromWhereThePersonStands) {
  const std::string yaml = R"(hribench: 1
task: clip_walk
role: instructor
instruction: "Watch."
horizon: 6
scene:
  objects:
    cube: {kind: cube, color: red, pose: {xy: [0.45, -0.2]}}
human:
  height: 1.75
  stand: {x: 1.6, y: 0, yaw_deg: 180}
  handedness: right
acts:
  stroll:
    actor: human
    onset: 0.5
    motion: {clip: tests/data/motion/cmu_131_01.bvh, duration: 4.0}
success:
  - on(cube, table)
)";
  const script::EpisodeSpec spec = sample_text(yaml, "clip_walk");
  const model::Model model = model::build(scene_spec_from_episode(spec));
  const size_t pelvis = static_cast<size_t>(human::index(human::Joint::kPelvis));
  const core::Vec3 stand = model.human_start.X_WP.translation;
  double first_offset = -1, travelled = 0, moved_before = 0;
  play(spec, model, 6.0, [&](const ScriptDriver& driver, const sim::Data& data, const std::vector<uint8_t>&) {
    const core::Vec3 p = data.X_WJ[pelvis].translation;
    const double d = std::hypot(p.x() - stand.x(), p.y() - stand.y());
    const double start = script::event_time(driver.graph(), driver.runtime(), "stroll.start");
    if (std::isnan(start)) {
      moved_before = std::max(moved_before, d);
    } else {
      if (first_offset < 0) first_offset = d;
      travelled = std::max(travelled, d);
    }
    return true;
  });
  EXPECT_LT(moved_before, 1e-9);
  EXPECT_GE(first_offset, 0);
  EXPECT_LT(first_offset, 0.05);  // placed at the stand position
  EXPECT_GT(travelled, 0.5);      // the captured walk moves the body
}

// C4: both hands take the plank's end and lift it by the act's height; the robot's end stays
// on the support (the noop robot does not lift).
TEST_F(ScriptDriverTest, ThePersonLiftsTheirEndOfThePlank) {
  const script::EpisodeSpec spec = script::sample(script::load_scenario("tasks/C4_co_lift.yaml"), 1);
  const model::Model model = model::build(scene_spec_from_episode(spec));
  const size_t plank = static_cast<size_t>(model.object_index("plank"));
  double lifted = 0;
  bool both_hands = false;
  play(spec, model, 20.0, [&](const ScriptDriver& driver, const sim::Data& data, const std::vector<uint8_t>&) {
    const mjtNum* q = data.mj->qpos + model.objects[plank].qpos_adr;
    const core::Quat r = core::quat_from_wxyz(q + 3).normalized();
    const core::Vec3 end = core::Vec3(q[0], q[1], q[2] + 0.02) + r * core::Vec3(0.28, 0, 0);
    if (sim::held_object(data, human::Side::kLeft) == static_cast<int>(plank) &&
        sim::held_object(data, human::Side::kRight) == static_cast<int>(plank)) {
      both_hands = true;
    }
    const double lift_end = script::event_time(driver.graph(), driver.runtime(), "hlift.end");
    if (!std::isnan(lift_end)) {
      lifted = end.z() - 0.85;
      return false;
    }
    return true;
  });
  EXPECT_TRUE(both_hands);
  EXPECT_NEAR(lifted, 0.18, 0.05);
}

TEST_F(ScriptDriverTest, NoopEpisodeMovesTheHumanOnScheduleDeterministically) {
  const script::EpisodeSpec spec = stop_go_spec();
  const model::Model model = model::build(scene_spec_from_episode(spec));
  const EpisodeLog log = run(spec, model);
  ASSERT_EQ(log.status, core::EpisodeStatus::kOk) << log.status_reason;
  ASSERT_FALSE(log.steps.empty());

  // The first act starts at its sampled onset.
  const double onset = spec.acts[0].value.onset->value();
  ASSERT_LT(onset, 3.0);
  const std::optional<double> start = log.event_time("go.start");
  ASSERT_TRUE(start.has_value());
  EXPECT_NEAR(*start, onset, log.control_dt);
  bool logged_as_act_start = false;
  for (const Event& e : log.events) {
    if (e.name == "go.start") logged_as_act_start = e.kind == EventKind::kActStart && e.actor == Actor::kHuman;
  }
  EXPECT_TRUE(logged_as_act_start);

  // The gesturing wrist moved after the onset, not before.
  const size_t wrist = static_cast<size_t>(spec.human.handedness.value() == "left"
                                               ? human::Joint::kLeftWrist
                                               : human::Joint::kRightWrist);
  const core::Vec3 first = log.steps.front().human_joints_W[wrist];
  double moved_before = 0, moved_after = 0;
  for (const StepRecord& s : log.steps) {
    const double d = (s.human_joints_W[wrist] - first).norm();
    if (s.time < onset - 1e-9) moved_before = std::max(moved_before, d);
    else moved_after = std::max(moved_after, d);
  }
  EXPECT_LT(moved_before, 1e-9);
  EXPECT_GT(moved_after, 0.10);

  // Deterministic: a second run gives the same log.
  const EpisodeLog again = run(spec, model);
  EXPECT_EQ(again.events, log.events);
  ASSERT_EQ(again.steps.size(), log.steps.size());
  for (size_t i = 0; i < log.steps.size(); ++i) {
    EXPECT_EQ(again.steps[i].time, log.steps[i].time);
    EXPECT_EQ(again.steps[i].human_joints_W, log.steps[i].human_joints_W) << i;
    EXPECT_EQ(again.steps[i].predicates, log.steps[i].predicates) << i;
    ASSERT_EQ(again.steps[i].object_poses.size(), log.steps[i].object_poses.size());
    for (size_t o = 0; o < log.steps[i].object_poses.size(); ++o) {
      EXPECT_EQ(again.steps[i].object_poses[o].translation, log.steps[i].object_poses[o].translation);
    }
  }
}

// The demonstrator's motion labels grasp and release a real object: the human's demo act
// puts inst_a into cont_1 by hand (hold springs, not teleporting).
TEST_F(ScriptDriverTest, HumanDemoPlacesTheObjectThroughHandHolds) {
  const EpisodeLog log = run_script("tasks/I3_demo_imitate.yaml", 7.0);
  ASSERT_EQ(log.status, core::EpisodeStatus::kOk) << log.status_reason;
  const std::optional<double> release = log.event_time("demo.release");
  ASSERT_TRUE(release.has_value());
  bool placed = false;
  for (const Event& e : log.events) {
    if (e.kind == EventKind::kPredicateChange && e.name == "in(inst_a, cont_1)" && e.detail == "true") {
      placed = true;
      EXPECT_GE(e.time, *release);
    }
  }
  EXPECT_TRUE(placed);
}

// A superseding act (give_up after an unanswered offer) keeps the offered item in the hand.
TEST_F(ScriptDriverTest, GivingUpKeepsTheOfferedItem) {
  const EpisodeLog log = run_script("tests/data/scripts/good/handover_h2r.yaml", 10.0);
  ASSERT_EQ(log.status, core::EpisodeStatus::kOk) << log.status_reason;
  ASSERT_TRUE(log.event_time("give_up.end").has_value());
  for (const Event& e : log.events) {
    EXPECT_FALSE(e.kind == EventKind::kPredicateChange && e.name == "not dropped(item)" &&
                 e.detail == "false")
        << "dropped at " << e.time;
  }
}

// As released, the person's pose at physics step i of a control step is the pose drive()
// gives at the control step's start slerped a share i / n toward the one it gives at its end
// (both from a copy of the driver as it stood), to the bit, both where the last control step's
// end is kept as this one's start and where an act starts or a phase signal arrives between
// two control steps (where no act poses the person, the pose is left as it is, not slerped to
// itself).
TEST_F(ScriptDriverTest, DriveBetweenInterpolatesThePosesAtTheControlStepsEnds) {
  // The person gestures toward an item and holds the hand out for it: the gesture's waiting
  // phase gets its signal at 1.9 s, which moves the pose at that control step's start (the
  // end kept from the control step before is off by about 0.01 in a joint's quaternion).
  const script::EpisodeSpec spec =
      script::sample(script::load_scenario("tasks/I2_gesture_delivery.yaml"), 0);
  const model::Model model = model::build(scene_spec_from_episode(spec));
  Started s(spec, model);
  sim::Data& data = s.data;
  ScriptDriver& driver = s.driver;
  constexpr int kSteps = 10;
  const auto same = [](const human::SkeletonPose& a, const human::SkeletonPose& b) {
    bool equal = a.X_WP.translation == b.X_WP.translation && a.X_WP.rotation.coeffs() == b.X_WP.rotation.coeffs();
    for (size_t j = 0; j < a.local.size(); ++j) equal = equal && a.local[j].coeffs() == b.local[j].coeffs();
    return equal;
  };
  double moved = 0;  // the most a control step moved the right wrist, m
  size_t events = 0;
  int changes = 0;   // control steps after which the runtime logged events
  while (data.time() < 4.0) {
    const std::unique_ptr<ScenarioDriver> copy = driver.clone();
    sim::Data ahead = sim::make_data(model);
    sim::copy_data(model, data, ahead);
    copy->drive(model, ahead);
    const human::SkeletonPose start = ahead.human_pose;
    for (int i = 0; i < kSteps; ++i) ahead.mj->time += model.m()->opt.timestep;  // as mj_step
    copy->drive(model, ahead);
    const human::SkeletonPose end = ahead.human_pose;
    const auto wrist = [&](const human::SkeletonPose& p) {
      return human::joint_pose(model.skeleton, p, human::Joint::kRightWrist).translation;
    };
    moved = std::max(moved, (wrist(end) - wrist(start)).norm());
    for (int i = 0; i < kSteps; ++i) {
      driver.drive_between(model, data, i, kSteps);
      const bool unposed = same(start, end) && same(data.human_pose, start);  // or slerped to itself
      EXPECT_TRUE(unposed || same(data.human_pose, human::interpolate(start, end, static_cast<double>(i) / kSteps)))
          << "t " << data.time() << " step " << i;
      sim::step(model, data);
    }
    s.observe(model);
    if (s.events.size() > events) ++changes;
    events = s.events.size();
  }
  EXPECT_GT(moved, 0.01);  // the person moved (m per control step)
  EXPECT_GE(changes, 2);   // the gesture started, its phases changed
  ExpectNoWarnings(data.mj.get());
}

TEST_F(ScriptDriverTest, DriveBetweenGraspsAndReleasesAtThePhysicsStepsDriveDoes) {
  // The person moves an object themselves (someone else does the job: once the robot leaves
  // home, which its base joint turning does here): picked up, put down.
  const script::EpisodeSpec spec =
      script::sample(script::load_scenario("tasks/X3_someone_else_places.yaml"), 1);
  const model::Model model = model::build(scene_spec_from_episode(spec));
  constexpr int kSteps = 10;
  // Each change of a hand's hold: the physics step, the hand and the object (-1: none).
  const auto hold_changes = [&](bool between) {
    Started s(spec, model);
    sim::ArmVector away = model.robot.home();
    away[0] += 0.5;
    sim::set_joint_targets(model, s.data, away);
    std::vector<std::array<long, 3>> changes;
    std::array<std::optional<int>, 2> held{};
    long k = 0;
    while (s.data.time() < spec.horizon) {
      for (int i = 0; i < kSteps; ++i, ++k) {
        if (between) {
          s.driver.drive_between(model, s.data, i, kSteps);
        } else {
          s.driver.drive(model, s.data);
        }
        for (size_t h = 0; h < 2; ++h) {
          const std::optional<int> now = sim::held_object(s.data, h == 0 ? human::Side::kLeft : human::Side::kRight);
          if (now == held[h]) continue;
          changes.push_back({k, static_cast<long>(h), now ? *now : -1});
          held[h] = now;
        }
        sim::step(model, s.data);
      }
      s.observe(model);
    }
    ExpectNoWarnings(s.data.mj.get());
    return changes;
  };
  const auto driven = hold_changes(false);
  ASSERT_GE(driven.size(), 2u);  // picked up and put down
  EXPECT_EQ(hold_changes(true), driven);
}

}  // namespace
}  // namespace hribench::eval

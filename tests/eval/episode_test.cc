#include "eval/episode.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "core/errors.h"
#include "eval/report.h"
#include "eval/runner.h"
#include "eval/script_contract.h"
#include "eval/script_driver.h"
#include "eval/task_episode.h"
#include "policy/registry.h"
#include "render/renderer.h"
#include "script/check.h"
#include "script/sample.h"

namespace hribench::eval {
namespace {

const char* const kTasks[] = {
    "tasks/C1_handover_h2r.yaml",  "tasks/C2_handover_r2h.yaml",     "tasks/C3_box_retrieval.yaml",
    "tasks/C4_co_lift.yaml",       "tasks/I1_point_pick.yaml",       "tasks/I2_gesture_delivery.yaml",
    "tasks/I3_demo_imitate.yaml",  "tasks/I4_stop_go.yaml",          "tasks/I5_contradiction.yaml",
    "tasks/X1_intrusion_yield.yaml", "tasks/X2_object_moved.yaml",   "tasks/X3_someone_else_places.yaml",
    "tasks/X4_blocked_target.yaml"};

script::EpisodeSpec sample_task(const std::string& file, uint64_t seed) {
  return script::sample(script::load_scenario(file), seed);
}

// Steps `episode` by hand with `policy` from reset to its end: ask, execute replan_every
// actions of the chunk, ask again (what run_episode does with latency none).
void step_by_hand(Episode& episode, policy::Policy& policy) {
  episode.reset();
  policy.reset(episode.info());
  policy::Observation obs = episode.observe();
  while (!episode.done()) {
    policy::ActionChunk chunk = policy.act(obs);
    chunk.actions.resize(std::min(chunk.actions.size(),
                                  static_cast<size_t>(std::max(1, policy.spec().replan_every))));
    obs = episode.step(chunk).observation;
  }
}

std::string scored_json(const EpisodeLog& log, const EpisodeMetrics& metrics) {
  return episode_to_json(make_result(log, metrics)).dump();
}

std::filesystem::path temp_file(const std::string& name) {
  return std::filesystem::path(::testing::TempDir()) /
         ("hribench_episode_" + std::to_string(getpid()) + "_" + name);
}

// Every task, one seed: the oracle stepped by hand gives the runner's log bit for bit, and the
// log saved and reloaded re-scores identically.
class EveryTask : public ::testing::TestWithParam<const char*> {};

TEST_P(EveryTask, HandSteppingEqualsTheRunnerAndTheReloadedLogRescores) {
  const script::EpisodeSpec spec = sample_task(GetParam(), 3);
  std::unique_ptr<policy::Policy> oracle = policy::make_policy("oracle");
  const EpisodeSetup setup = setup_of(spec, "oracle");
  RunOptions options;
  options.horizon = 0;  // the script's
  const ScoredEpisode run = run_task_episode(spec, *oracle, setup, options);
  ASSERT_GT(run.log.steps.size(), 1u);

  Episode by_hand(spec, oracle->spec(), setup, options);
  step_by_hand(by_hand, *oracle);
  EXPECT_TRUE(identical(by_hand.log(), run.log)) << GetParam();
  EXPECT_EQ(scored_json(by_hand.log(), by_hand.metrics()), scored_json(run.log, run.metrics));

  const std::filesystem::path path = temp_file(std::string(spec.task) + ".hlog");
  save_episode_log(run.log, path);
  const EpisodeLog back = load_episode_log(path);
  std::filesystem::remove(path);
  EXPECT_TRUE(identical(back, run.log));
  const ScenarioContract contract = contract_from_episode(spec, ScriptDriver(spec).graph(), by_hand.model());
  EXPECT_EQ(scored_json(back, compute_metrics(contract, back, options.constants)),
            scored_json(run.log, run.metrics));
}

INSTANTIATE_TEST_SUITE_P(Tasks, EveryTask, ::testing::ValuesIn(kTasks));

// The log holds what the robot was told: the action of each executed step and the servo
// targets it produced; the human's skeleton pose and the lids.
TEST(Episode, LogHoldsActionsTargetsAndTheSkeleton) {
  const script::EpisodeSpec spec = sample_task("tasks/C3_box_retrieval.yaml", 0);
  std::unique_ptr<policy::Policy> oracle = policy::make_policy("oracle");
  RunOptions options;
  options.horizon = 4.0;
  Episode episode(spec, oracle->spec(), setup_of(spec, "oracle"), options);
  run_episode(episode, *oracle);
  const EpisodeLog& log = episode.log();
  EXPECT_EQ(log.action_space, oracle->spec().action_space);
  ASSERT_EQ(log.steps.size(), 81u);
  EXPECT_TRUE(log.steps[0].action.empty());  // the reset state: nothing executed yet
  for (size_t k = 1; k < log.steps.size(); ++k) {
    const StepRecord& s = log.steps[k];
    const model::Robot& robot = episode.model().robot;
    EXPECT_EQ(log.robot, robot.name);
    ASSERT_EQ(s.action.size(), static_cast<size_t>(policy::action_dim(log.action_space, robot))) << k;
    EXPECT_EQ(s.joint_target.size(), robot.dof());
    EXPECT_EQ(s.joint_vel.size(), robot.dof());
    EXPECT_DOUBLE_EQ(s.gripper_target, s.action.back() * robot.gripper.max_width());
    EXPECT_EQ(s.lid_angles.size(), log.object_names.size());
    EXPECT_DOUBLE_EQ(s.finger_pos[0] + s.finger_pos[1], s.gripper_width);
  }
  // The person moves: the root and the joint rotations change over the episode.
  const human::SkeletonPose& first = log.steps[0].human_pose;
  const human::SkeletonPose& last = log.steps.back().human_pose;
  double turned = 0;
  for (size_t j = 1; j < first.local.size(); ++j) turned += first.local[j].angularDistance(last.local[j]);
  EXPECT_GT(turned, 0.05);
  EXPECT_FALSE(first.X_WP.translation.isZero());
}

// Under a fixed latency the steps where the policy thinks hold the previous command: no action.
TEST(Episode, HeldStepsLogNoAction) {
  const script::EpisodeSpec spec = sample_task("tasks/I1_point_pick.yaml", 0);
  std::unique_ptr<policy::Policy> noop = policy::make_policy("noop");
  RunOptions options;
  options.horizon = 1.0;
  options.latency = parse_latency("fixed:100");
  Episode episode(spec, noop->spec(), setup_of(spec, "noop"), options);
  run_episode(episode, *noop);
  const EpisodeLog& log = episode.log();
  ASSERT_EQ(log.steps.size(), 21u);
  EXPECT_TRUE(log.steps[1].action.empty());
  EXPECT_TRUE(log.steps[2].action.empty());
  EXPECT_FALSE(log.steps[3].action.empty());
}

// Observers see the start, every step as it is logged (step 0 included) and the end.
TEST(Episode, ObserversSeeEveryStep) {
  struct Counter : EpisodeObserver {
    int starts = 0, steps = 0, ends = 0;
    double last_time = -1;
    void on_start(const Episode& e) override {
      ++starts;
      EXPECT_TRUE(e.log().steps.empty());
    }
    void on_step(const Episode& e, const StepRecord& s) override {
      ++steps;
      EXPECT_EQ(&s, &e.log().steps.back());
      last_time = s.time;
    }
    void on_end(const Episode& e) override {
      ++ends;
      EXPECT_TRUE(e.done());
    }
  };
  const script::EpisodeSpec spec = sample_task("tasks/I1_point_pick.yaml", 0);
  std::unique_ptr<policy::Policy> noop = policy::make_policy("noop");
  RunOptions options;
  options.horizon = 2.0;
  Episode episode(spec, noop->spec(), setup_of(spec, "noop"), options);
  Counter counter;
  episode.add_observer(counter);
  const std::filesystem::path path = temp_file("observed.hlog");
  LogFileWriter writer(path);
  episode.add_observer(writer);
  run_episode(episode, *noop);
  EXPECT_EQ(counter.starts, 1);
  EXPECT_EQ(counter.steps, 41);
  EXPECT_EQ(counter.ends, 1);
  EXPECT_NEAR(counter.last_time, 2.0, 1e-9);  // 400 steps of 5 ms
  EXPECT_TRUE(identical(load_episode_log(path), episode.log()));
  std::filesystem::remove(path);
}

// A copy made mid-way and stepped on with the same actions gives the same log, bit for bit;
// so does a snapshot restored into the episode.
TEST(Episode, SnapshotContinuesIdentically) {
  const script::EpisodeSpec spec = sample_task("tasks/C1_handover_h2r.yaml", 0);
  std::unique_ptr<policy::Policy> oracle = policy::make_policy("oracle");
  RunOptions options;
  options.horizon = 0;
  Episode episode(spec, oracle->spec(), setup_of(spec, "oracle"), options);
  run_episode(episode, *oracle, [](const Episode& e) { return e.data().time() >= 6.0 - 1e-9; });
  ASSERT_FALSE(episode.done());
  const size_t mid = episode.log().steps.size();
  Episode copy(episode);
  const EpisodeSnapshot snapshot = episode.snapshot();
  EXPECT_NEAR(snapshot.time(), 6.0, 1e-9);
  // The original goes on with the oracle (its state continues: no reset).
  policy::Observation obs = episode.observe();
  while (!episode.done()) obs = episode.step(oracle->act(obs)).observation;
  ASSERT_GT(episode.log().steps.size(), mid + 20);
  // The copy, and the restored original, replay the same actions (a held step: hold()).
  const EpisodeLog full = episode.log();
  episode.restore(snapshot);
  EXPECT_EQ(episode.log().steps.size(), mid);
  for (Episode* e : {&copy, &episode}) {
    for (size_t k = mid; k < full.steps.size(); ++k) {
      const policy::Action& action = full.steps[k].action;
      if (action.empty()) {
        e->hold();
      } else {
        e->step(action);
      }
    }
    EXPECT_TRUE(e->done());
    EXPECT_TRUE(identical(e->log(), full));
  }
}

TEST(Episode, SnapshotOfAnotherSpecIsRefused) {
  std::unique_ptr<policy::Policy> noop = policy::make_policy("noop");
  RunOptions options;
  options.horizon = 1.0;
  const script::EpisodeSpec a = sample_task("tasks/I1_point_pick.yaml", 0);
  const script::EpisodeSpec b = sample_task("tasks/I1_point_pick.yaml", 1);
  Episode first(a, noop->spec(), setup_of(a, "noop"), options);
  Episode second(b, noop->spec(), setup_of(b, "noop"), options);
  first.reset();
  second.reset();
  try {
    second.restore(first.snapshot());
    FAIL();
  } catch (const core::InputError& e) {
    EXPECT_EQ(std::string(e.what()), "Episode::restore: expected a snapshot of spec " +
                                         script::spec_hash(b) + ", got a snapshot of spec " +
                                         script::spec_hash(a));
  }
}

TEST(Episode, BadStepsAreClearErrors) {
  const script::EpisodeSpec spec = sample_task("tasks/I1_point_pick.yaml", 0);
  std::unique_ptr<policy::Policy> noop = policy::make_policy("noop");
  RunOptions options;
  options.horizon = 0.1;
  Episode episode(spec, noop->spec(), setup_of(spec, "noop"), options);
  const auto message = [&](const auto& call) {
    try {
      call();
    } catch (const core::InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const policy::Action still(7, 0.0);
  EXPECT_EQ(message([&] { episode.step(still); }),
            "Episode::step: expected an episode started by reset(), got an episode never reset");
  episode.reset();
  EXPECT_EQ(message([&] { episode.step(policy::Action(3, 0.0)); }),
            "Episode::step action: wrong_shape: action 0: expected 7 values (ee_delta), got 3");
  EXPECT_EQ(message([&] { episode.step(policy::Action{0, 0, 0, 0, 0, 0, 2.0}); }),
            "Episode::step action: out_of_range: action 0 value 6: 2 is outside [0, 1]");
  policy::ActionChunk joints{policy::ActionSpace::kJointPos, {policy::Action(8, 0.0)}};
  EXPECT_EQ(message([&] { episode.step(joints); }),
            "Episode::step chunk: expected ee_delta actions (the episode's action space), got "
            "joint_pos actions");
  EXPECT_EQ(message([&] { episode.step(policy::ActionChunk{policy::ActionSpace::kEeDelta, {}}); }),
            "Episode::step chunk: expected at least one action, got an empty chunk");
  episode.step(still);
  const StepResult last = episode.step(still);
  EXPECT_TRUE(last.done);
  EXPECT_EQ(last.info, "horizon");
  EXPECT_EQ(message([&] { episode.step(still); }),
            "Episode::step: expected a running episode (reset() starts it again), got an "
            "episode that ended at 0.10 s (ok: horizon)");
  EXPECT_EQ(message([&] { episode.hold(); }),
            "Episode::hold: expected a running episode (reset() starts it again), got an "
            "episode that ended at 0.10 s (ok: horizon)");
  // reset() starts it again.
  episode.reset();
  EXPECT_FALSE(episode.step(still).done);
}

// A frame rendered from the log alone (pose_from_step on a fresh Data) equals the live render
// at that step.
TEST(Episode, LogAloneRerendersTheLiveFrame) {
  const script::EpisodeSpec spec = sample_task("tasks/C3_box_retrieval.yaml", 0);
  std::unique_ptr<policy::Policy> oracle = policy::make_policy("oracle");
  RunOptions options;
  options.horizon = 0;
  Episode episode(spec, oracle->spec(), setup_of(spec, "oracle"), options);
  run_episode(episode, *oracle, [](const Episode& e) { return e.data().time() >= 7.0 - 1e-9; });
  const model::Model& model = episode.model();
  auto renderer = render::make_renderer(render::Backend::kOsmesa, *model.m(), 160, 120);
  render::Image live;
  ASSERT_TRUE(renderer->render(model, episode.data(), model.agentview_camera, live));

  const std::filesystem::path path = temp_file("frame.hlog");
  save_episode_log(episode.log(), path);
  const EpisodeLog log = load_episode_log(path);
  std::filesystem::remove(path);
  sim::Data data = sim::make_data(model);
  pose_from_step(model, log, log.steps.back(), data);
  render::Image replayed;
  ASSERT_TRUE(renderer->render(model, data, model.agentview_camera, replayed));
  EXPECT_EQ(replayed.rgb, live.rgb);
  // An earlier step differs (the frame is the step's, not any).
  pose_from_step(model, log, log.steps[log.steps.size() / 2], data);
  renderer->render(model, data, model.agentview_camera, replayed);
  EXPECT_NE(replayed.rgb, live.rgb);
}

// An episode in a scene that has run other episodes (eval/run.h keeps one per worker) gives a
// fresh episode's log and metrics bit for bit, and the scene's renderers, made once, render
// what a fresh episode's render.
TEST(EpisodeScene, EpisodesInOneSceneEqualFreshOnes) {
  const script::EpisodeSpec spec = sample_task("tasks/C1_handover_h2r.yaml", 3);
  RunOptions options;
  options.horizon = 0;
  EpisodeScene scene(spec);
  EXPECT_EQ(script::spec_hash(scene.spec()), script::spec_hash(spec));
  for (const char* name : {"noop", "oracle"}) {  // the oracle in a scene noop has run
    std::unique_ptr<policy::Policy> policy = policy::make_policy(name);
    const ScoredEpisode fresh = run_task_episode(spec, *policy, setup_of(spec, name), options);
    const ScoredEpisode in_scene = run_task_episode(scene, *policy, setup_of(spec, name), options);
    ASSERT_GT(fresh.log.steps.size(), 1u);
    EXPECT_TRUE(identical(in_scene.log, fresh.log)) << name;
    EXPECT_EQ(scored_json(in_scene.log, in_scene.metrics), scored_json(fresh.log, fresh.metrics)) << name;
  }
  policy::PolicySpec cameras;
  cameras.cameras = {{"agentview", 64, 48}, {"wrist", 64, 48}};
  const sim::Data* scene_data = nullptr;
  for (int round = 0; round < 2; ++round) {
    Episode fresh(spec, cameras, setup_of(spec, "cameras"), options);
    Episode in_scene(scene, cameras, setup_of(spec, "cameras"), options);
    // The scene's one Data, not a new one per episode.
    if (scene_data != nullptr) {
      EXPECT_EQ(&in_scene.data(), scene_data);
    }
    scene_data = &in_scene.data();
    EXPECT_NE(&fresh.data(), scene_data);
    fresh.reset();
    in_scene.reset();
    for (int i = 0; i < 10 * (round + 1); ++i) {
      fresh.hold();
      in_scene.hold();
    }
    const policy::Observation a = fresh.observe();
    const policy::Observation b = in_scene.observe();
    ASSERT_EQ(a.images.size(), 2u);
    ASSERT_EQ(b.images.size(), 2u);
    for (size_t i = 0; i < a.images.size(); ++i) EXPECT_EQ(a.images[i].pixels, b.images[i].pixels) << i;
    EXPECT_TRUE(identical(in_scene.log(), fresh.log()));
  }
}

}  // namespace
}  // namespace hribench::eval

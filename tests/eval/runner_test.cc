#include "eval/runner.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <limits>

#include "core/errors.h"
#include "eval/metrics.h"
#include "eval/parallel.h"
#include "eval/robot_motion.h"
#include "eval/script_driver.h"
#include "human/skeleton.h"
#include "model/model.h"
#include "policy/builtin.h"
#include "render/gl_context.h"
#include "script/check.h"
#include "script/sample.h"
#include "sim/control.h"
#include "sim/data.h"
#include "support/mujoco_fixture.h"

namespace hribench::eval {
namespace {

TEST(Latency, ParsesTheThreeModes) {
  EXPECT_EQ(parse_latency("none").mode, LatencyMode::kNone);
  EXPECT_EQ(parse_latency("measured").mode, LatencyMode::kMeasured);
  const Latency fixed = parse_latency("fixed:200");
  EXPECT_EQ(fixed.mode, LatencyMode::kFixed);
  EXPECT_DOUBLE_EQ(fixed.fixed_seconds, 0.2);
  EXPECT_EQ(to_string(fixed), "fixed:200");
  EXPECT_DOUBLE_EQ(parse_latency("fixed:60000").fixed_seconds, 60.0);
  for (const char* bad : {"fixed:", "fixed:-5", "fixed:abc", "fixed:nan", "fixed:inf", "fixed:-inf",
                          "fixed:60000.5", "fixed:1e30", "fixed:5ms"}) {
    try {
      parse_latency(bad);
      FAIL() << bad;
    } catch (const core::InputError& e) {
      EXPECT_EQ(std::string(e.what()),
                std::string("--latency: expected fixed:MS with MS milliseconds in [0, 60000], got '") +
                    bad + "'");
    }
  }
  for (const char* bad : {"slow", "", "fixed"}) {
    try {
      parse_latency(bad);
      FAIL() << bad;
    } catch (const core::InputError& e) {
      EXPECT_EQ(std::string(e.what()),
                std::string("--latency: expected none, fixed:MS (milliseconds >= 0) or measured, "
                            "got '") + bad + "'");
    }
  }
}

// The human steps 0.2 m to the side at `shift_time` (the cue) and the driver logs the event.
class SideStepDriver : public ScenarioDriver {
 public:
  explicit SideStepDriver(double shift_time) : shift_time_(shift_time) {}
  std::vector<std::string> predicate_names() const override { return {"success"}; }
  void reset(const model::Model& model, sim::Data&) override {
    start_ = model.human_start;
    logged_ = false;
  }
  void drive(const model::Model& model, sim::Data& data) override {
    if (data.time() + 1e-9 < shift_time_) return;
    human::SkeletonPose pose = start_;
    pose.X_WP.translation.y() += 0.2;
    sim::set_human_pose(model, data, pose);
  }
  void observe(const model::Model&, const sim::Data& data, std::vector<uint8_t>& predicates,
               std::vector<Event>& events) override {
    predicates.assign(1, 0);
    if (!logged_ && data.time() + 1e-9 >= shift_time_) {
      events.push_back({shift_time_, EventKind::kPhase, Actor::kHuman, "step.end", ""});
      logged_ = true;
    }
  }

 private:
  double shift_time_;
  human::SkeletonPose start_;
  bool logged_ = false;
};

// Reacts to the human's pelvis leaving y = 0: moves the TCP along +y at 0.2 m/s.
class FollowPolicy : public policy::Policy {
 public:
  policy::PolicySpec spec() const override {
    return {{}, true, policy::ActionSpace::kEeDelta, 1};
  }
  void reset(const policy::EpisodeInfo&) override {}
  policy::ActionChunk act(const policy::Observation& obs) override {
    const bool go = obs.state->human_joints_W[0].y() > 0.1;
    return {policy::ActionSpace::kEeDelta, {{0, go ? 0.01 : 0.0, 0, 0, 0, 0, 1.0}}};
  }
};

// Returns NaN from the third query on.
class BrokenPolicy : public policy::NoopPolicy {
 public:
  policy::ActionChunk act(const policy::Observation& obs) override {
    policy::ActionChunk chunk = NoopPolicy::act(obs);
    if (++calls_ >= 3) chunk.actions[0][2] = std::numeric_limits<double>::quiet_NaN();
    return chunk;
  }

 private:
  int calls_ = 0;
};

class RunnerTest : public testing::MujocoTest {
 protected:
  void SetUp() override {
    MujocoTest::SetUp();
    model_ = std::make_unique<model::Model>(model::build(model::SceneSpec::Default()));
    data_ = std::make_unique<sim::Data>(sim::make_data(*model_));
    Watch(data_->mj.get());
  }
  EpisodeSetup setup(const std::string& policy) const {
    return {"test_task", "instructor", "abc", 3, "stay", policy};
  }
  std::unique_ptr<model::Model> model_;
  std::unique_ptr<sim::Data> data_;
};

TEST_F(RunnerTest, NoopEpisodeIsCompleteStillAndDeterministic) {
  policy::NoopPolicy noop;
  StandingHumanDriver driver;
  RunOptions options;
  options.horizon = 1.0;
  const EpisodeLog log = run_episode(*model_, *data_, noop, driver, setup("noop"), options);
  EXPECT_EQ(log.status, core::EpisodeStatus::kOk) << log.status_reason;
  ASSERT_EQ(log.steps.size(), 21u);  // t = 0, 0.05, ..., 1.0
  EXPECT_NEAR(log.steps.back().time, 1.0, 1e-9);
  EXPECT_NO_THROW(check_episode_log(log, "log"));
  EXPECT_EQ(log.object_names.size(), model_->objects.size());
  EXPECT_EQ(log.steps[0].joint_pos.size(), 7u);
  // The human stands across the table: finite separation, no contact.
  EXPECT_TRUE(std::isfinite(log.steps.back().separation));
  EXPECT_GT(log.steps.back().separation, 0.3);
  // The held robot barely moves.
  const double drift = (log.steps.back().X_WT.translation - log.steps.front().X_WT.translation).norm();
  EXPECT_LT(drift, 0.005);
  EXPECT_GT(total_length(still_time(log, MetricConstants{})), 0.9);
  // Same spec, same actions: the same log, bit for bit; and it survives a save/reload.
  const EpisodeLog again = run_episode(*model_, *data_, noop, driver, setup("noop"), options);
  EXPECT_TRUE(identical(log, again));
  EXPECT_TRUE(identical(decode_episode_log(encode_episode_log(log), "m"), log));
}

TEST_F(RunnerTest, OneAndTwoThreadsGiveIdenticalLogs) {
  // Random policies (seeded per episode) so the episodes differ from each other.
  const auto run_all = [&](int threads) {
    std::vector<sim::Data> datas;
    for (int w = 0; w < threads; ++w) datas.push_back(sim::make_data(*model_));
    std::vector<EpisodeLog> logs(4);
    run_jobs(
        4, threads,
        [&](size_t job, int worker) {
          policy::RandomPolicy random(policy::ActionSpace::kEeDelta, 1, 0.3);
          StandingHumanDriver driver;
          RunOptions options;
          options.horizon = 0.5;
          EpisodeSetup s = setup("random");
          s.seed = job;
          logs[job] = run_episode(*model_, datas[static_cast<size_t>(worker)], random, driver, s, options);
          return make_result(logs[job], compute_metrics(ScenarioContract{}, logs[job]));
        },
        nullptr);
    for (const sim::Data& d : datas) ExpectNoWarnings(d.mj.get());
    return logs;
  };
  const std::vector<EpisodeLog> one = run_all(1);
  const std::vector<EpisodeLog> two = run_all(2);
  for (size_t i = 0; i < one.size(); ++i) EXPECT_TRUE(identical(one[i], two[i])) << i;
  EXPECT_FALSE(identical(one[0], one[1]));  // different seeds, different episodes
}

TEST_F(RunnerTest, BadActionEndsTheEpisodeAsPolicyError) {
  BrokenPolicy broken;
  StandingHumanDriver driver;
  RunOptions options;
  options.horizon = 2.0;
  const EpisodeLog log = run_episode(*model_, *data_, broken, driver, setup("broken"), options);
  EXPECT_EQ(log.status, core::EpisodeStatus::kPolicyError);
  EXPECT_EQ(log.status_reason, "non_finite: action 0 value 2: nan");
  EXPECT_EQ(log.steps.size(), 3u);  // t = 0, 0.05, 0.1; the third query failed
  const EpisodeMetrics m = compute_metrics(ScenarioContract{}, log);
  EXPECT_EQ(*m.primary_label, FailureLabel::kPolicyError);
}

TEST_F(RunnerTest, EndsOnceSuccessHasHeldHalfASecond) {
  // Success holds from t = 0.3 s on: the episode ends at 0.8 s, not at the horizon.
  class SuccessDriver : public StandingHumanDriver {
   public:
    void observe(const model::Model&, const sim::Data& data, std::vector<uint8_t>& predicates,
                 std::vector<Event>&) override {
      predicates.assign(1, data.time() >= 0.3 - 1e-9 ? 1 : 0);
    }
  } driver;
  policy::NoopPolicy noop;
  RunOptions options;
  options.horizon = 5.0;
  const EpisodeLog log = run_episode(*model_, *data_, noop, driver, setup("noop"), options);
  EXPECT_NEAR(log.steps.back().time, 0.8, 1e-9);
  const EpisodeMetrics m = compute_metrics(ScenarioContract{}, log);
  EXPECT_TRUE(m.success);
  EXPECT_NEAR(m.completion_time, 0.3, 1e-9);
}

// The human's right arm raised forward, its hand swept along +y at 1 m/s through the Panda's
// forearm (link 5): the hand comes from -y and shoves the robot ahead of it.
class HandSweepDriver : public ScenarioDriver {
 public:
  std::vector<std::string> predicate_names() const override { return {"success"}; }
  void reset(const model::Model& model, sim::Data& data) override {
    pose_ = human::SkeletonPose::Standing(model.skeleton, 0, 0, core::kPi);
    pose_.local[static_cast<size_t>(human::index(human::Joint::kRightShoulder))] =
        core::axis_angle(core::Vec3::UnitY(), -core::kPi / 2);
    sim::forward(model, data);
    const mjData& d = *data.mj;
    const auto link5_body = static_cast<size_t>(model.link_body[5]);
    const core::Vec3 link5(d.xpos[3 * link5_body], d.xpos[3 * link5_body + 1], d.xpos[3 * link5_body + 2]);
    size_t hand = 0;
    for (size_t i = 0; i < model.human_capsules.size(); ++i) {
      if (model.human_capsules[i].name == "right_hand") hand = i;
    }
    const human::BodyCapsule& capsule = model.human_capsules[hand];
    const auto X_WJ = human::forward_kinematics(model.skeleton, pose_);
    const core::Vec3 hand_mid =
        X_WJ[static_cast<size_t>(human::index(capsule.joint))] * core::Vec3(0.5 * (capsule.from + capsule.to));
    start_ = pose_.X_WP.translation + (link5 + core::Vec3(-0.12, 0, 0) - hand_mid);
    Place(model, data);
  }
  void drive(const model::Model& model, sim::Data& data) override { Place(model, data); }
  void observe(const model::Model&, const sim::Data&, std::vector<uint8_t>& predicates,
               std::vector<Event>&) override {
    predicates.assign(1, 0);
  }

 private:
  void Place(const model::Model& model, sim::Data& data) {
    human::SkeletonPose pose = pose_;
    pose.X_WP.translation = start_ + core::Vec3(0, -0.6 + 1.0 * data.time(), 0);
    sim::set_human_pose(model, data, pose);
  }
  human::SkeletonPose pose_;
  core::Vec3 start_ = core::Vec3::Zero();
};

TEST_F(RunnerTest, RobotShovedByThePenetratingHumanMovesAwayFromIt) {
  // In the first 50 ms after the hand enters the robot (negative separation), the robot's
  // closest point is shoved along +y, straight away from the human: its speed toward the human
  // is negative and almost its whole speed. (Normalising by |point_human - point_robot| instead
  // of the signed distance flips this sign, so a shove would count as an approach and a push
  // into the human as a retreat.)
  policy::NoopPolicy noop;
  HandSweepDriver driver;
  RunOptions options;
  options.horizon = 0.8;
  options.control_dt = model::kTimestep;  // a control step per physics step
  const EpisodeLog log = run_episode(*model_, *data_, noop, driver, setup("noop"), options);
  ASSERT_EQ(log.status, core::EpisodeStatus::kOk) << log.status_reason;
  std::optional<double> entered;
  int shoved = 0;
  for (const StepRecord& s : log.steps) {
    if (!entered && s.separation < 0) entered = s.time;
    if (!entered || s.time > *entered + 0.05 || s.closest_point_speed < 0.05) continue;
    ASSERT_LT(s.separation, 0.0) << "t = " << s.time;
    ++shoved;
    EXPECT_LT(s.approach_speed, -0.9 * s.closest_point_speed)
        << "t = " << s.time << ", d = " << s.separation;
  }
  // More than half of the physics steps of those 50 ms (10 at 5 ms).
  EXPECT_GT(shoved, 0.025 / model::kTimestep);
}

// Asks for the given cameras (or the privileged track) and keeps what it observes.
class WatchingPolicy : public policy::NoopPolicy {
 public:
  std::vector<policy::CameraRequest> cameras;
  bool privileged = false;
  std::vector<policy::Observation> seen;
  policy::EpisodeInfo info;
  policy::PolicySpec spec() const override {
    policy::PolicySpec s = NoopPolicy::spec();
    s.cameras = cameras;
    s.privileged = privileged;
    return s;
  }
  void reset(const policy::EpisodeInfo& i) override {
    NoopPolicy::reset(i);
    info = i;
  }
  policy::ActionChunk act(const policy::Observation& observation) override {
    seen.push_back(observation);
    return NoopPolicy::act(observation);
  }
};

TEST_F(RunnerTest, CamerasAreRenderedAtTheRequestedSizesInRequestOrder) {
  WatchingPolicy watcher;
  watcher.cameras = {{"wrist", 16, 12}, {"agentview", 40, 30}};
  StandingHumanDriver driver;
  RunOptions options;
  options.horizon = 0.2;
  const EpisodeLog log = run_episode(*model_, *data_, watcher, driver, setup("cam"), options);
  ASSERT_EQ(log.status, core::EpisodeStatus::kOk) << log.status_reason;
  ASSERT_EQ(watcher.seen.size(), 4u);
  for (const policy::Observation& obs : watcher.seen) {
    ASSERT_EQ(obs.images.size(), 2u);
    EXPECT_EQ(obs.images[0].camera, "wrist");
    EXPECT_EQ(obs.images[0].width, 16);
    EXPECT_EQ(obs.images[0].height, 12);
    EXPECT_EQ(obs.images[0].pixels.size(), 16u * 12u * 3u);
    EXPECT_EQ(obs.images[1].camera, "agentview");
    ASSERT_EQ(obs.images[1].pixels.size(), 40u * 30u * 3u);
    // A real picture of the scene: not one flat colour.
    const auto& px = obs.images[1].pixels;
    EXPECT_NE(std::count(px.begin(), px.end(), px[0]), static_cast<long>(px.size()));
    EXPECT_FALSE(obs.state.has_value());
    EXPECT_TRUE(obs.events.empty());
  }
}

TEST_F(RunnerTest, CamerasOfOneSizeShareARendererAndKeepTheirViews) {
  // Two cameras of one size are drawn by one renderer (Episode), each from its own camera:
  // the images are those of episodes that ask for each camera alone.
  const auto seen_with = [&](std::vector<policy::CameraRequest> cameras) {
    WatchingPolicy watcher;
    watcher.cameras = std::move(cameras);
    StandingHumanDriver driver;
    RunOptions options;
    options.horizon = 0.1;
    run_episode(*model_, *data_, watcher, driver, setup("cam"), options);
    return watcher.seen;
  };
  const auto both = seen_with({{"wrist", 24, 24}, {"agentview", 24, 24}});
  const auto wrist = seen_with({{"wrist", 24, 24}});
  const auto agentview = seen_with({{"agentview", 24, 24}});
  ASSERT_EQ(both.size(), 2u);
  ASSERT_EQ(wrist.size(), 2u);
  ASSERT_EQ(agentview.size(), 2u);
  for (size_t k = 0; k < both.size(); ++k) {
    ASSERT_EQ(both[k].images.size(), 2u);
    EXPECT_NE(both[k].images[0].pixels, both[k].images[1].pixels);
    EXPECT_EQ(both[k].images[0].pixels, wrist[k].images[0].pixels) << k;
    EXPECT_EQ(both[k].images[1].pixels, agentview[k].images[0].pixels) << k;
  }
}

TEST_F(RunnerTest, CamerasTheRunnerCannotRenderAreRefused) {
  WatchingPolicy watcher;
  watcher.cameras = {{"agentview", 32, 32}};
  StandingHumanDriver driver;
  RunOptions options;
  options.render_backend = render::Backend::kNone;
  try {
    run_episode(*model_, *data_, watcher, driver, setup("cam"), options);
    FAIL();
  } catch (const core::InputError& e) {
    EXPECT_EQ(std::string(e.what()), "policy cam: expected a renderer for its cameras (osmesa or egl), "
                                     "got render back end none");
  }
  watcher.cameras = {{"ceiling", 32, 32}};
  EXPECT_THROW(run_episode(*model_, *data_, watcher, driver, setup("cam"), RunOptions{}),
               core::InputError);
}

TEST_F(RunnerTest, OnlyPrivilegedPoliciesSeeTheScenarioEvents) {
  for (const bool privileged : {false, true}) {
    WatchingPolicy watcher;
    watcher.privileged = privileged;
    SideStepDriver driver(0.5);
    RunOptions options;
    options.horizon = 1.0;
    const EpisodeLog log = run_episode(*model_, *data_, watcher, driver, setup("watch"), options);
    ASSERT_EQ(log.status, core::EpisodeStatus::kOk) << log.status_reason;
    EXPECT_EQ(watcher.info.episode, nullptr);  // this driver has no script
    for (const policy::Observation& obs : watcher.seen) {
      if (!privileged || obs.time + 1e-9 < 0.5) {
        EXPECT_TRUE(obs.events.empty()) << obs.time;
        continue;
      }
      ASSERT_EQ(obs.events.size(), 1u) << obs.time;
      EXPECT_EQ(obs.events[0].name, "step.end");
      EXPECT_EQ(obs.events[0].kind, "phase");
      EXPECT_DOUBLE_EQ(obs.events[0].time, 0.5);
    }
  }
}

TEST_F(RunnerTest, PrivilegedPoliciesGetTheSampledEpisodeOfAScriptDriver) {
  const script::EpisodeSpec spec =
      script::sample(script::load_scenario("tests/data/scripts/good/stop_go.yaml"), 1);
  const model::Model model = model::build(scene_spec_from_episode(spec));
  sim::Data data = sim::make_data(model);  // checked for warnings at the end (not watched: freed before TearDown)
  for (const bool privileged : {false, true}) {
    WatchingPolicy watcher;
    watcher.privileged = privileged;
    ScriptDriver driver(spec);
    RunOptions options;
    options.horizon = 8.0;
    const EpisodeLog log = run_episode(model, data, watcher, driver, setup("watch"), options);
    ASSERT_EQ(log.status, core::EpisodeStatus::kOk) << log.status_reason;
    if (!privileged) {
      EXPECT_EQ(watcher.info.episode, nullptr);
      continue;
    }
    ASSERT_NE(watcher.info.episode, nullptr);
    EXPECT_EQ(script::spec_hash(*watcher.info.episode), script::spec_hash(spec));
    // The last observation lists the log's events up to its time, cues included.
    const policy::Observation& last = watcher.seen.back();
    size_t expected = 0;
    for (const Event& event : log.events) expected += event.time <= last.time + 1e-9;
    ASSERT_EQ(last.events.size(), expected);
    EXPECT_TRUE(std::any_of(last.events.begin(), last.events.end(),
                            [](const policy::ScriptEvent& e) { return e.kind == "cue"; }));
  }
  ExpectNoWarnings(data.mj.get());
}

TEST_F(RunnerTest, FixedLatencyShiftsTheResponseByItsDuration) {
  // The human side-steps just before the 1.0 s query (the queries of a 200 ms policy come
  // every 0.25 s, so 1.0 s is a query time in both modes).
  const double shift = 0.975;
  ScenarioContract contract;
  sim::reset(*model_, *data_);
  const core::Vec3 goal = sim::tcp_pose(*model_, *data_).translation + core::Vec3(0, 1.0, 0);
  contract.cues.push_back({"follow", "step.end", CueKind::kGo, 1.0, goal});
  const auto response = [&](const std::string& latency) {
    FollowPolicy follow;
    SideStepDriver driver(shift);
    RunOptions options;
    options.horizon = 2.0;
    options.latency = parse_latency(latency);
    const EpisodeLog log = run_episode(*model_, *data_, follow, driver, setup("follow"), options);
    EXPECT_EQ(log.status, core::EpisodeStatus::kOk) << log.status_reason;
    const EpisodeMetrics m = compute_metrics(contract, log);
    EXPECT_TRUE(m.cues.at(0).responded) << latency;
    return *m.response_latency;
  };
  const double none = response("none");
  const double fixed = response("fixed:200");
  RecordProperty("rsp_none", std::to_string(none));
  RecordProperty("rsp_fixed200", std::to_string(fixed));
  EXPECT_LT(none, 0.1);
  EXPECT_NEAR(fixed - none, 0.2, 0.026);
}

// Chunks of four actions told apart by their x step (0.001 .. 0.004 m), two executed per query.
class FourActionChunks : public policy::NoopPolicy {
 public:
  explicit FourActionChunks(bool execute_while_thinking) : execute_while_thinking_(execute_while_thinking) {}
  policy::PolicySpec spec() const override {
    policy::PolicySpec s = NoopPolicy::spec();
    s.replan_every = 2;
    s.execute_while_thinking = execute_while_thinking_;
    return s;
  }
  policy::ActionChunk act(const policy::Observation&) override {
    policy::ActionChunk chunk{policy::ActionSpace::kEeDelta, {}};
    for (int i = 1; i <= 4; ++i) chunk.actions.push_back({0.001 * i, 0, 0, 0, 0, 0, 1.0});
    return chunk;
  }

 private:
  bool execute_while_thinking_;
};

TEST_F(RunnerTest, WhileThinkingTheRobotHoldsOrExecutesThePreviousChunksRest) {
  // fixed:100 = two control steps of thinking after each query.
  const auto executed = [&](bool execute_while_thinking) {
    FourActionChunks policy(execute_while_thinking);
    StandingHumanDriver driver;
    RunOptions options;
    options.horizon = 0.5;
    options.latency = parse_latency("fixed:100");
    const EpisodeLog log = run_episode(*model_, *data_, policy, driver, setup("chunks"), options);
    EXPECT_EQ(log.status, core::EpisodeStatus::kOk) << log.status_reason;
    std::vector<int> order;  // per step: 0 held, else the action's index in its chunk (1..4)
    for (size_t k = 1; k < log.steps.size(); ++k) {
      const policy::Action& a = log.steps[k].action;
      order.push_back(a.empty() ? 0 : static_cast<int>(std::lround(a[0] / 0.001)));
    }
    return order;
  };
  EXPECT_EQ(executed(false), (std::vector<int>{0, 0, 1, 2, 0, 0, 1, 2, 0, 0}));
  EXPECT_EQ(executed(true), (std::vector<int>{0, 0, 1, 2, 3, 4, 1, 2, 3, 4}));
}

}  // namespace
}  // namespace hribench::eval

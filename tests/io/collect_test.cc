// Tests of the collector (io/collect.h): float32 actions inside the limits, the feature names,
// a recorder that changes nothing in the episode and records each frame with the action
// executed after it, bad options refused before anything is written, a write failure mid-run
// (the episode discarded, those before it kept) followed by --resume (nothing duplicated),
// --keep all (failures kept and labelled) and --force (the dataset replaced).

#include "io/collect.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include <nlohmann/json.hpp>

#include "eval/runner.h"
#include "gen/pool.h"
#include "io/hdf5.h"
#include "model/robot.h"
#include "policy/registry.h"
#include "support/test_files.h"

namespace hribench::io {
namespace {

namespace fs = std::filesystem;
using ::hribench::testing::error_of;

std::string temp_dir(const std::string& name) { return ::hribench::testing::temp_dir("collect", name); }

const model::Robot& panda() { return model::robot_by_name("panda"); }

script::EpisodeSpec first_adapt_episode(const std::string& task) {
  return gen::pool_episodes(gen::read_manifest(gen::released_pool()), gen::Split::kAdapt, {task}).front();
}

// A small collect: 2 tasks, 1 episode each, 32x32 images.
CollectRequest small_request(const std::string& out, const std::string& format) {
  CollectRequest r;
  r.tasks = "handover_r2h,stop_go";
  r.episodes = 1;
  r.size = 32;
  r.format = format;
  r.out = out;
  return r;
}

nlohmann::json read_json(const fs::path& path) { return nlohmann::json::parse(::hribench::testing::read_text(path)); }

TEST(Float32Action, RoundsToTheNearestFloatInsideTheLimits) {
  const policy::ActionLimits limits = policy::action_limits(panda());
  // 0.05 (the translation bound) is not a float; its nearest float is above it.
  ASSERT_GT(static_cast<double>(static_cast<float>(0.05)), 0.05);
  const std::vector<float> a =
      float32_action({0.05, -0.05, 0.01, 0.25, -0.1, 0.0, 1.0}, policy::ActionSpace::kEeDelta, limits);
  EXPECT_LE(static_cast<double>(a[0]), 0.05);
  EXPECT_GE(static_cast<double>(a[1]), -0.05);
  EXPECT_EQ(a[0], std::nextafter(static_cast<float>(0.05), 0.0f));
  EXPECT_EQ(a[2], static_cast<float>(0.01));  // inside: the nearest float
  EXPECT_EQ(a[3], 0.25f);
  EXPECT_EQ(a[6], 1.0f);
  // Joint targets at the upper limit of joint 4 (a negative bound).
  policy::Action joints(limits.q_max.begin(), limits.q_max.end());
  joints.push_back(0.5);
  const std::vector<float> j = float32_action(joints, policy::ActionSpace::kJointPos, limits);
  for (size_t i = 0; i < limits.q_max.size(); ++i) EXPECT_LE(static_cast<double>(j[i]), limits.q_max[i]) << i;
  // Out of range stays out of range (the episode refuses it, as without the wrapper).
  EXPECT_GT(static_cast<double>(float32_action({0.2, 0, 0, 0, 0, 0, 1}, policy::ActionSpace::kEeDelta, limits)[0]), 0.05);
}

TEST(FeatureNames, NameEveryDimensionAsGroupDotPart) {
  const std::vector<std::string> state = state_names(panda());
  ASSERT_EQ(state.size(), 2 * panda().dof() + 9);
  EXPECT_EQ(state.front(), "joint_pos." + panda().joints.front().name);
  EXPECT_EQ(state[panda().dof()], "joint_vel." + panda().joints.front().name);
  EXPECT_EQ(state[2 * panda().dof()], "gripper.opening");
  EXPECT_EQ(state.back(), "tcp_quat.z");
  EXPECT_EQ(action_names(policy::ActionSpace::kEeDelta, panda()),
            (std::vector<std::string>{"ee_delta.dx", "ee_delta.dy", "ee_delta.dz", "ee_delta.drx", "ee_delta.dry",
                                      "ee_delta.drz", "gripper.opening"}));
  EXPECT_EQ(action_names(policy::ActionSpace::kJointPos, panda()).size(), panda().dof() + 1);
}

// Keeps copies of what it receives.
struct RecordedFrame {
  int64_t index = 0;
  std::vector<float> state, action;
  std::vector<std::vector<uint8_t>> images;
  std::string human_act;
  std::vector<std::string> events;
  bool done = false;
  std::vector<double> sim_state;
};
class CopySink : public EpisodeSink {
 public:
  void add(const Frame& f) override {
    RecordedFrame r{f.index, f.state, f.action, {}, f.human_act, f.events, f.done, f.sim_state};
    for (const render::Image* image : f.images) r.images.push_back(image->rgb);
    frames.push_back(std::move(r));
  }
  std::vector<RecordedFrame> frames;
};

TEST(FrameRecorder, ChangesNothingAndRecordsEachStepWithTheActionExecutedAfterIt) {
  const script::EpisodeSpec spec = first_adapt_episode("point_pick");
  eval::RunOptions options;
  options.horizon = 2.0;  // 41 steps
  Float32Actions policy(policy::make_policy("oracle"));
  const eval::EpisodeSetup setup = eval::setup_of(spec, "oracle");
  eval::Episode plain(spec, policy.spec(), setup, options);
  const eval::EpisodeLog expected = eval::run_episode(plain, policy);

  eval::Episode recorded(spec, policy.spec(), setup, options);
  const EpisodeHeader header = episode_header(spec, "I1", "oracle", recorded.model().robot,
                                              policy::ActionSpace::kEeDelta, {"agentview", "wrist"}, 32, 0.05);
  CopySink sink;
  FrameRecorder recorder(recorded, header, sink, render::Backend::kOsmesa);
  recorded.add_observer(recorder);
  const eval::EpisodeLog& log = eval::run_episode(recorded, policy);
  EXPECT_TRUE(eval::identical(log, expected));

  ASSERT_EQ(sink.frames.size(), log.steps.size());
  EXPECT_EQ(recorder.frames(), static_cast<int64_t>(log.steps.size()));
  for (size_t k = 0; k < sink.frames.size(); ++k) {
    const RecordedFrame& f = sink.frames[k];
    EXPECT_EQ(f.index, static_cast<int64_t>(k));
    ASSERT_EQ(f.state.size(), header.state_names.size());
    EXPECT_EQ(f.state[0], static_cast<float>(log.steps[k].joint_pos[0]));
    ASSERT_EQ(f.images.size(), 2u);
    EXPECT_EQ(f.images[0].size(), 32u * 32u * 3u);
    EXPECT_EQ(f.done, k + 1 == sink.frames.size());
    EXPECT_EQ(f.sim_state.front(), log.steps[k].time);
    if (k + 1 < sink.frames.size()) {
      // Exactly the executed action (float32 by the wrapper).
      ASSERT_EQ(f.action.size(), log.steps[k + 1].action.size());
      for (size_t j = 0; j < f.action.size(); ++j) EXPECT_EQ(static_cast<double>(f.action[j]), log.steps[k + 1].action[j]);
    }
  }
  // The last frame holds: no motion, the gripper command in force.
  const RecordedFrame& last = sink.frames.back();
  EXPECT_EQ(last.action[0], 0.0f);
  EXPECT_EQ(static_cast<double>(last.action[6]),
            static_cast<double>(static_cast<float>(log.steps.back().gripper_target / panda().gripper.max_width())));
  // Two cameras, two different pictures.
  EXPECT_NE(sink.frames[0].images[0], sink.frames[0].images[1]);
}

TEST(FrameRecorder, RecordsTheServoTargetsInTheJointSpace) {
  const script::EpisodeSpec spec = first_adapt_episode("point_pick");
  eval::RunOptions options;
  options.horizon = 0.5;
  Float32Actions policy(policy::make_policy("oracle"));
  eval::Episode episode(spec, policy.spec(), eval::setup_of(spec, "oracle"), options);
  const EpisodeHeader header = episode_header(spec, "I1", "oracle", episode.model().robot,
                                              policy::ActionSpace::kJointPos, {"wrist"}, 16, 0.05);
  CopySink sink;
  FrameRecorder recorder(episode, header, sink, render::Backend::kOsmesa);
  episode.add_observer(recorder);
  const eval::EpisodeLog& log = eval::run_episode(episode, policy);
  ASSERT_EQ(sink.frames.size(), log.steps.size());
  ASSERT_EQ(sink.frames[0].action.size(), panda().dof() + 1);
  for (size_t j = 0; j < panda().dof(); ++j) {
    EXPECT_NEAR(sink.frames[3].action[j], log.steps[4].joint_target[j], 1e-6) << j;
  }
}

TEST(Collect, RefusesBadOptionsBeforeWritingAnything) {
  const std::string dir = temp_dir("options");
  const auto message = [&](auto change) {
    CollectRequest r = small_request(dir, "act-hdf5");
    change(r);
    return error_of([&] { collect(r); });
  };
  EXPECT_EQ(message([](CollectRequest& r) { r.split = "train"; }),
            "--split: expected adapt, eval or test, got 'train'");
  EXPECT_EQ(message([](CollectRequest& r) { r.format = "zarr"; }),
            "--format: expected one of lerobot, lerobot-v3, act-hdf5, robomimic, got 'zarr'");
  EXPECT_NE(message([](CollectRequest& r) { r.policy = "nobody"; }).find("'nobody'"), std::string::npos);
  EXPECT_EQ(message([](CollectRequest& r) { r.cameras = "agentview,top"; }).substr(0, 34),
            "--cameras: expected one of agentvi");
  EXPECT_NE(message([](CollectRequest& r) { r.cameras = "agentview,top"; }).find("got 'top'"), std::string::npos);
  EXPECT_EQ(message([](CollectRequest& r) { r.cameras = "wrist,wrist"; }),
            "--cameras: expected each camera once, got 'wrist' twice");
  EXPECT_EQ(message([](CollectRequest& r) { r.keep = "failures"; }), "--keep: expected success or all, got 'failures'");
  EXPECT_EQ(message([](CollectRequest& r) { r.action_space = "ee_delta"; r.policy = "noop?space=joint_pos"; }),
            "--action-space: expected the policy's own (joint_pos) or joint_pos (the servo targets), got 'ee_delta'");
  EXPECT_EQ(message([](CollectRequest& r) { r.resume = r.force = true; }), "--resume: cannot be combined with --force");
  EXPECT_EQ(message([](CollectRequest& r) { r.threads = 0; }), "--threads: expected a positive number, got 0");
  EXPECT_EQ(message([](CollectRequest& r) { r.out = ""; }), "--out: expected an output folder, got none");
  EXPECT_FALSE(fs::exists(dir));
  // A folder holding something else, and another collect.
  fs::create_directories(dir);
  std::ofstream(dir + "/notes.txt") << "mine\n";
  EXPECT_EQ(message([](CollectRequest&) {}),
            "--out: " + dir + " holds files that are not a hribench collect (no hribench/collect.json), e.g. "
            "'notes.txt'; choose an empty or new folder");
  EXPECT_EQ(message([](CollectRequest& r) { r.force = true; }).substr(0, 6), "--out:");
  EXPECT_TRUE(fs::exists(dir + "/notes.txt"));  // --force never removes what is not a collect
  fs::remove(dir + "/notes.txt");
  fs::create_directories(dir + "/hribench");
  nlohmann::json state = {{"options", {{"size", 64}}}, {"episodes", nlohmann::json::array()}};
  std::ofstream(collect_state_path(dir)) << state.dump();
  EXPECT_EQ(message([](CollectRequest&) {}),
            "--out: " + dir + " already holds a dataset; use --resume to continue it or --force to replace it");
  const std::string other = message([](CollectRequest& r) { r.resume = true; });
  EXPECT_EQ(other.find("--resume: " + dir + " holds a dataset with other options ("), 0u) << other;
  EXPECT_NE(other.find("size: 64 in the dataset, 32 asked"), std::string::npos) << other;
  EXPECT_NE(other.find("; use --force to replace it"), std::string::npos) << other;
}

// Wraps a real writer; the sinks of `failing_task`'s episodes throw at their 5th frame.
class FailingWriter : public DatasetWriter {
 public:
  FailingWriter(std::unique_ptr<DatasetWriter> inner, std::string failing_task)
      : inner_(std::move(inner)), failing_task_(std::move(failing_task)) {}
  std::unique_ptr<EpisodeSink> begin_episode(const EpisodeHeader& header) override {
    return std::make_unique<Sink>(inner_->begin_episode(header), header.task == failing_task_);
  }
  void commit(std::unique_ptr<EpisodeSink> sink, const EpisodeOutcome& outcome) override {
    inner_->commit(std::move(static_cast<Sink&>(*sink).inner), outcome);
  }
  void discard(std::unique_ptr<EpisodeSink> sink) override {
    inner_->discard(std::move(static_cast<Sink&>(*sink).inner));
  }
  void finish() override { inner_->finish(); }
  void resume(const std::vector<EpisodeHeader>& committed) override { inner_->resume(committed); }

 private:
  struct Sink : EpisodeSink {
    Sink(std::unique_ptr<EpisodeSink> s, bool f) : inner(std::move(s)), fails(f) {}
    void add(const Frame& frame) override {
      if (fails && frame.index == 4) throw core::InputError::Message("disk", "No space left on device");
      inner->add(frame);
    }
    std::unique_ptr<EpisodeSink> inner;
    bool fails;
  };
  std::unique_ptr<DatasetWriter> inner_;
  std::string failing_task_;
};

TEST(Collect, AWriteFailureKeepsTheEpisodesBeforeItAndResumeDuplicatesNothing) {
  const std::string dir = temp_dir("failure");
  CollectRequest request = small_request(dir, "act-hdf5");
  request.threads = 2;
  const std::string message = error_of([&] {
    collect(request, nullptr, [](const fs::path& d) {
      return std::make_unique<FailingWriter>(make_dataset_writer("act-hdf5", d), "stop_go");
    });
  });
  const uint64_t seed = first_adapt_episode("stop_go").seed;
  EXPECT_EQ(message, dir + ": cannot write episode 1 (stop_go seed " + std::to_string(seed) +
                         "): disk: No space left on device; it is discarded; the 1 episodes before it are in the "
                         "dataset; continue with --resume");
  EXPECT_TRUE(fs::exists(act_episode_path(dir, "handover_r2h", 0)));
  EXPECT_FALSE(fs::exists(act_episode_path(dir, "stop_go", 0)));
  // No temporary file is left behind.
  for (const fs::directory_entry& e : fs::recursive_directory_iterator(dir)) {
    EXPECT_EQ(e.path().string().find(".tmp"), std::string::npos) << e.path();
  }
  const nlohmann::json state = read_json(collect_state_path(dir));
  ASSERT_EQ(state.at("episodes").size(), 1u);
  EXPECT_EQ(state.at("episodes")[0].at("task"), "handover_r2h");
  EXPECT_FALSE(state.at("finished").get<bool>());
  const auto first_written = fs::last_write_time(act_episode_path(dir, "handover_r2h", 0));

  // Resume: only the missing episode runs.
  CollectRequest resume = request;
  resume.resume = true;
  const CollectSummary summary = collect(resume);
  EXPECT_EQ(summary.resumed, 1u);
  EXPECT_EQ(summary.kept, 2u);
  EXPECT_EQ(fs::last_write_time(act_episode_path(dir, "handover_r2h", 0)), first_written);
  EXPECT_TRUE(fs::exists(act_episode_path(dir, "stop_go", 0)));
  EXPECT_FALSE(fs::exists(act_episode_path(dir, "handover_r2h", 1)));
  const nlohmann::json resumed = read_json(collect_state_path(dir));
  ASSERT_EQ(resumed.at("episodes").size(), 2u);
  EXPECT_EQ(resumed.at("episodes")[1].at("task"), "stop_go");
  EXPECT_EQ(resumed.at("episodes")[1].at("index"), 1);
  EXPECT_TRUE(resumed.at("finished").get<bool>());
  // A finished collect resumed again does nothing.
  EXPECT_EQ(collect(resume).resumed, 2u);
  EXPECT_EQ(fs::last_write_time(act_episode_path(dir, "handover_r2h", 0)), first_written);
}

// A policy that holds still for `acts` control steps, then fails: the episode ends with a
// policy error after `acts` steps.
void register_failing_policy(const std::string& name, int acts) {
  policy::register_policy({name, "fails", [acts](policy::PolicyRef) -> std::unique_ptr<policy::Policy> {
                             struct Fails : policy::Policy {
                               explicit Fails(int n) : acts(n) {}
                               policy::PolicySpec spec() const override { return {}; }
                               void reset(const policy::EpisodeInfo&) override { done = 0; }
                               policy::ActionChunk act(const policy::Observation&) override {
                                 if (done++ >= acts) throw policy::PolicyError(policy::PolicyErrorKind::kFailed, "test");
                                 return {policy::ActionSpace::kEeDelta, {{0, 0, 0, 0, 0, 0, 1}}};
                               }
                               int acts;
                               int done = 0;
                             };
                             return std::make_unique<Fails>(acts);
                           }});
}

TEST(Collect, KeepsOnlySuccessesUnlessAskedForAllWhichLabelsFailures) {
  register_failing_policy("test_fails", 3);
  CollectRequest r = small_request(temp_dir("keep_success"), "robomimic");
  r.policy = "test_fails";
  const CollectSummary none = collect(r);
  EXPECT_EQ(none.episodes, 2u);
  EXPECT_EQ(none.kept, 0u);
  EXPECT_EQ(read_robomimic_episodes(r.out).size(), 0u);
  const nlohmann::json state = read_json(collect_state_path(r.out));
  ASSERT_EQ(state.at("episodes").size(), 2u);
  EXPECT_FALSE(state.at("episodes")[0].at("kept").get<bool>());
  EXPECT_EQ(state.at("episodes")[0].at("status"), "policy_error");

  r.out = temp_dir("keep_all");
  r.keep = "all";
  EXPECT_EQ(collect(r).kept, 2u);
  const nlohmann::json all = read_json(collect_state_path(r.out));
  EXPECT_TRUE(all.at("episodes")[0].at("kept").get<bool>());
  EXPECT_FALSE(all.at("episodes")[0].at("labels").empty());
  EXPECT_EQ(all.at("episodes")[0].at("frames"), 4);
  const std::vector<RecordedEpisode> kept = read_robomimic_episodes(r.out);
  ASSERT_EQ(kept.size(), 2u);
  EXPECT_EQ(kept[0].actions.size(), 3u);

  // --force replaces the dataset: kept only successes now, none.
  r.keep = "success";
  EXPECT_NE(error_of([&] { collect(r); }).find("already holds a dataset"), std::string::npos);
  r.force = true;
  EXPECT_EQ(collect(r).kept, 0u);
  EXPECT_EQ(read_robomimic_episodes(r.out).size(), 0u);
  EXPECT_EQ(read_json(collect_state_path(r.out)).at("options").at("keep"), "success");
  r.force = false;

  // An episode that failed before its first action shows nothing: never kept.
  register_failing_policy("test_fails_at_once", 0);
  r.out = temp_dir("keep_none");
  r.policy = "test_fails_at_once";
  EXPECT_EQ(collect(r).kept, 0u);
}

}  // namespace
}  // namespace hribench::io

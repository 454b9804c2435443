// The files of an episode (eval/episode_files.h): stems that are file names, the log of a stem
// or a .hlog path, and the errors for a run without logs and an unknown stem.

#include "eval/episode_files.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "support/test_files.h"

namespace hribench::eval {
namespace {

namespace fs = std::filesystem;
using ::hribench::testing::error_of;

TEST(EpisodeFiles, StemIsAFileName) {
  EXPECT_EQ(episode_stem("point_pick", "noop", 3, "0123456789abcdef"), "point_pick__noop__3__0123456789ab");
  EXPECT_EQ(episode_stem("point_pick", "openpi://host:8000", 0, "ab"), "point_pick__openpi___host_8000__0__ab");
  EpisodeResult r;
  r.task = "stop_go";
  r.policy = "oracle";
  r.seed = 7;
  r.spec_hash = "ffffffffffffffffff";
  EXPECT_EQ(episode_stem(r), "stop_go__oracle__7__ffffffffffff");
  EXPECT_EQ(log_file("RUN", "S"), fs::path("RUN/logs/S.hlog"));
  EXPECT_EQ(video_file("RUN", "S"), fs::path("RUN/videos/S.mp4"));
  EXPECT_EQ(replay_file("RUN", "S"), fs::path("RUN/replay/S.html"));
}

TEST(EpisodeFiles, FindsALogByStemOrPathAndNamesSomeThatExist) {
  const fs::path run = ::hribench::testing::temp_dir("episode_files", "run");
  EXPECT_EQ(error_of([&] { find_episode_log(run, "x", "EPISODE"); }),
            run.string() + ": holds no episode logs (logs/*.hlog); run eval with --save-logs to keep them");
  fs::create_directories(run / "logs");
  for (const char* stem : {"d", "a", "c", "b"}) std::ofstream(log_file(run, stem)) << "log";
  std::ofstream(run / "logs" / "notes.txt") << "not a log";
  EXPECT_EQ(saved_log_stems(run), (std::vector<std::string>{"a", "b", "c", "d"}));
  EXPECT_EQ(find_episode_log(run, "c", "EPISODE"), log_file(run, "c"));
  EXPECT_EQ(find_episode_log(run, log_file(run, "b").string(), "EPISODE"), log_file(run, "b"));
  EXPECT_EQ(find_episode_log(run, "b.hlog", "EPISODE"), log_file(run, "b"));
  EXPECT_EQ(error_of([&] { find_episode_log(run, "point_pick__x", "--episode"); }),
            "--episode: expected an episode of " + run.string() +
                " (a log stem, e.g. a, b, c, ... 4 in all; or a .hlog file), got 'point_pick__x'");
  fs::remove_all(run);
}

TEST(EpisodeFiles, TheFirstFailuresOfEachTaskAndPolicyThatHaveLogs) {
  const fs::path run = ::hribench::testing::temp_dir("episode_files", "failures");
  std::vector<EpisodeResult> episodes;
  const auto add = [&](const std::string& task, const std::string& policy, uint64_t seed, bool success, bool logged) {
    EpisodeResult r;
    r.task = task;
    r.policy = policy;
    r.seed = seed;
    r.spec_hash = "hash" + std::to_string(seed);
    r.metrics.success = success;
    episodes.push_back(r);
    if (logged) {
      fs::create_directories(run / "logs");
      std::ofstream(log_file(run, episode_stem(r))) << "log";
    }
  };
  EXPECT_EQ(error_of([&] { first_failed_logged_stems(run, episodes, 1); }),
            run.string() + ": holds no episode logs (logs/*.hlog); run eval with --save-logs to keep them");
  add("stop_go", "blind", 0, true, true);     // a success: never chosen
  add("stop_go", "blind", 1, false, false);   // a failure without a log: passed over
  add("stop_go", "blind", 2, false, true);    // the first failure with a log
  add("stop_go", "blind", 3, false, true);    // the second
  add("stop_go", "noop", 0, false, true);     // another policy: a group of its own
  add("co_lift", "blind", 0, false, true);    // another task: a group of its own
  EXPECT_EQ(first_failed_logged_stems(run, episodes, 1),
            (std::vector<std::string>{"stop_go__blind__2__hash2", "stop_go__noop__0__hash0", "co_lift__blind__0__hash0"}));
  EXPECT_EQ(first_failed_logged_stems(run, episodes, 2),
            (std::vector<std::string>{"stop_go__blind__2__hash2", "stop_go__blind__3__hash3", "stop_go__noop__0__hash0",
                                      "co_lift__blind__0__hash0"}));
  fs::remove_all(run);
}

}  // namespace
}  // namespace hribench::eval

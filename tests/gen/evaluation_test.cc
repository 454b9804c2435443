#include "gen/evaluation.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "script/sample.h"
#include "support/logged_run.h"
#include "support/test_files.h"

namespace hribench::gen {
namespace {

namespace fs = std::filesystem;
using testing::error_of;
using testing::temp_dir;

// A one-second noop run of I1 (two seeds) with its logs saved, made once for the suite.
const fs::path& logged_run() {
  static const fs::path run = testing::make_logged_run("evaluation", "I1", "noop", 2, 5, 1);
  return run;
}

std::string first_stem() {
  std::vector<std::string> stems;
  for (const auto& entry : fs::directory_iterator(logged_run() / "logs"))
    stems.push_back(entry.path().stem().string());
  std::sort(stems.begin(), stems.end());
  return stems.front();
}

TEST(LoadLoggedEpisode, FindsTheLogByStemOrPathAndRebuildsTheSpecItRan) {
  const LoggedEpisode by_stem = load_logged_episode(logged_run(), first_stem());
  EXPECT_EQ(by_stem.log.task, "point_pick");
  EXPECT_EQ(script::spec_hash(by_stem.spec), by_stem.log.spec_hash);
  EXPECT_EQ(by_stem.spec.seed, by_stem.log.seed);
  EXPECT_FALSE(by_stem.log.steps.empty());
  const LoggedEpisode by_path = load_logged_episode(logged_run(), by_stem.log_file.string());
  EXPECT_EQ(by_path.log.spec_hash, by_stem.log.spec_hash);
}

TEST(LoadLoggedEpisode, NamesWhatIsMissing) {
  const fs::path empty = temp_dir("evaluation", "not_a_run");
  fs::create_directories(empty);
  EXPECT_EQ(error_of([&] { load_logged_episode(empty, "x"); }),
            empty.string() + ": expected a run folder of hribench eval (with options.json), got no options.json");
  const fs::path no_logs = temp_dir("evaluation", "no_logs");
  fs::create_directories(no_logs);
  fs::copy_file(logged_run() / "options.json", no_logs / "options.json");
  EXPECT_EQ(error_of([&] { load_logged_episode(no_logs, "x"); }),
            no_logs.string() + ": the run saved no episode logs (run eval with --save-logs)");
  const std::string unknown = error_of([&] { load_logged_episode(logged_run(), "point_pick__noop__99"); });
  EXPECT_EQ(unknown.rfind("episode: expected the stem of a log of the run (point_pick__noop__5__", 0), 0u) << unknown;
  EXPECT_NE(unknown.find("got 'point_pick__noop__99'"), std::string::npos) << unknown;
}

TEST(LoadLoggedEpisode, RefusesALogTheRunDidNotMake) {
  // The run's tasks give seeds 5 and 6; a log of seed 5 under another task list matches nothing.
  const fs::path other = temp_dir("evaluation", "other");
  fs::create_directories(other);
  std::ofstream(other / "options.json") << R"({"tasks": ["tasks/C3_box_retrieval.yaml"]})";
  const LoggedEpisode logged = load_logged_episode(logged_run(), first_stem());
  const std::string message = error_of([&] { load_logged_episode(other, logged.log_file.string()); });
  EXPECT_NE(message.find("expected an episode of the run's tasks or pool"), std::string::npos) << message;
  EXPECT_NE(message.find("task point_pick, seed 5, spec hash " + logged.log.spec_hash + " (none matches)"),
            std::string::npos) << message;
}

}  // namespace
}  // namespace hribench::gen

// Tests of `hribench bench`: a tiny run writes valid JSON with every expected key (timings are
// never asserted, only that they are positive numbers), `--backend none` skips rendering, and
// bad flags are one clear line.

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "model/model.h"
#include "support/run_command.h"

namespace hribench::cli {
namespace {

using ::hribench::testing::count_lines;
using ::hribench::testing::run_hribench;

// Runs bench with `flags`, writing JSON to a file named after `name` and this process (tests
// may run in parallel), and returns the parsed file (discarded if it is not valid JSON).
nlohmann::json run_bench_json(const std::string& name, const std::string& flags) {
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("hribench_bench_" + name + "_" + std::to_string(getpid()) + ".json"))
                               .string();
  std::remove(path.c_str());
  const auto r = run_hribench("bench --json " + path + " " + flags);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("cost ours/raw"), std::string::npos) << r.output;
  std::ifstream file(path);
  nlohmann::json j = nlohmann::json::parse(file, nullptr, /*allow_exceptions=*/false);
  std::remove(path.c_str());
  return j;
}

void expect_positive(const nlohmann::json& j, const char* key) {
  ASSERT_TRUE(j.contains(key)) << key << " in " << j.dump();
  ASSERT_TRUE(j[key].is_number()) << key;
  EXPECT_GT(j[key].get<double>(), 0) << key;
}

TEST(BenchCommandTest, TinyRunWritesJsonWithEveryKey) {
  const nlohmann::json j = run_bench_json("tiny", "--seconds 0.05 --threads 2");
  ASSERT_FALSE(j.is_discarded()) << "not valid JSON";
  EXPECT_EQ(j["mujoco_version"], "2.2.2");
  EXPECT_EQ(j["backend"], "osmesa");
  ASSERT_TRUE(j["gl_renderer"].is_string());
  EXPECT_FALSE(j["gl_renderer"].get<std::string>().empty());
  EXPECT_NE(j["gl_renderer"], "none");
  for (const char* key : {"hribench_version", "git_hash"}) EXPECT_TRUE(j[key].is_string()) << key;
  EXPECT_DOUBLE_EQ(j["timestep"].get<double>(), model::kTimestep);
  ASSERT_EQ(j["physics"].size(), 2u);
  EXPECT_EQ(j["physics"][0]["threads"], 1);
  EXPECT_EQ(j["physics"][1]["threads"], 2);
  for (const auto& row : j["physics"]) {
    for (const char* key : {"steps_per_second", "raw_steps_per_second", "realtime_factor",
                            "raw_realtime_factor", "cost_ratio"}) {
      expect_positive(row, key);
    }
    EXPECT_EQ(row["mujoco_warnings"], 0);
  }
  ASSERT_EQ(j["render"].size(), 4u);
  for (const auto& row : j["render"]) {
    EXPECT_TRUE(row["camera"] == "agentview" || row["camera"] == "wrist") << row.dump();
    EXPECT_TRUE(row["width"] == 128 || row["width"] == 224) << row.dump();
    EXPECT_EQ(row["width"], row["height"]);
    for (const char* key : {"fps", "raw_fps", "cost_ratio"}) expect_positive(row, key);
  }
  EXPECT_EQ(j["render_settings"]["shadows"], false);
  expect_positive(j, "render_mujoco_defaults_fps_agentview_224");
}

TEST(BenchCommandTest, NoneBackendSkipsRendering) {
  const nlohmann::json j = run_bench_json("none", "--seconds 0.02 --threads 1 --backend none");
  ASSERT_FALSE(j.is_discarded()) << "not valid JSON";
  EXPECT_EQ(j["gl_renderer"], "none");
  EXPECT_TRUE(j["render"].empty());
  EXPECT_EQ(j["physics"].size(), 1u);
}

TEST(BenchCommandTest, BadFlagsAreOneLine) {
  for (const auto& [args, message] :
       {std::pair<std::string, std::string>{
            "bench --seconds 0", "--seconds: expected a duration in (0, 3600] s, got 0"},
        {"bench --threads -1", "--threads: expected 1..256 (0: all cores), got -1"},
        {"bench --json /nonexistent-dir/b.json",
         "--json: cannot write '/nonexistent-dir/b.json'"}}) {
    const auto r = run_hribench(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.output;
    EXPECT_EQ(count_lines(r.output), 1) << r.output;
    EXPECT_EQ(r.output, "hribench: error: " + message + "\n") << args;
  }
}

}  // namespace
}  // namespace hribench::cli

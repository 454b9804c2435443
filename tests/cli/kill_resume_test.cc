// Nothing lost, nothing duplicated (docs/hardening.md "Crash-safe outputs"): `eval`,
// `generate` and `collect` are killed with SIGKILL at spread moments and resumed; the final
// outputs equal an uninterrupted run's byte for byte.

#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "support/run_command.h"
#include "support/test_files.h"

extern char** environ;

namespace hribench::cli {
namespace {

namespace fs = std::filesystem;
using ::hribench::testing::count_lines;
using ::hribench::testing::read_text;
using ::hribench::testing::run_hribench;

// Starts `hribench ARGS` (a shell line) and SIGKILLs it after `ms` milliseconds (or lets it end
// first). Returns whether it was killed.
bool run_and_kill_after(const std::string& args, int ms) {
  const std::string line = std::string("exec ") + HRIBENCH_BINARY + " " + args + " >/dev/null 2>&1";
  const char* argv[] = {"/bin/sh", "-c", line.c_str(), nullptr};
  pid_t pid = 0;
  if (posix_spawn(&pid, "/bin/sh", nullptr, nullptr, const_cast<char* const*>(argv), environ) != 0) return false;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(ms);
  int status = 0;
  while (std::chrono::steady_clock::now() < deadline) {
    if (waitpid(pid, &status, WNOHANG) == pid) return false;  // finished before the moment
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  kill(pid, SIGKILL);
  waitpid(pid, &status, 0);
  return WIFSIGNALED(status);
}

// Kill moments spread over a run of about `run_ms`: early (options being written), middle
// (episodes finishing), late (results being written).
std::vector<int> moments(int run_ms) {
  std::vector<int> ms;
  for (int k = 0; k < 5; ++k) ms.push_back(20 + (run_ms * (2 * k + 1)) / 10 + 37 * k % 50);
  return ms;
}

int elapsed_ms(const std::function<void()>& f) {
  const auto start = std::chrono::steady_clock::now();
  f();
  return static_cast<int>(
      std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - start).count());
}

TEST(KillAndResume, EvalEndsWithTheUninterruptedRunsResults) {
  const std::string root = ::hribench::testing::temp_dir("kill", "eval");
  const std::string run = "eval --tasks I4 --policy noop,reactive --episodes 2 --seed 5 --horizon 2 --threads 2 --out ";
  int run_ms = 0;
  run_ms = elapsed_ms([&] { ASSERT_EQ(run_hribench(run + root + "/reference").exit_code, 0); });
  const std::string reference = read_text(fs::path(root) / "reference" / "results.json");
  int killed = 0;
  for (const int ms : moments(run_ms)) {
    const std::string dir = root + "/killed_" + std::to_string(ms);
    killed += run_and_kill_after(run + dir, ms);
    const auto resumed = run_hribench(run + dir + " --resume");
    ASSERT_EQ(resumed.exit_code, 0) << "killed after " << ms << " ms: " << resumed.output;
    EXPECT_EQ(read_text(fs::path(dir) / "results.json"), reference) << "killed after " << ms << " ms";
    EXPECT_EQ(count_lines(read_text(fs::path(dir) / "episodes.jsonl")), 4) << "killed after " << ms << " ms";
    for (const auto& entry : fs::directory_iterator(dir)) {
      EXPECT_NE(entry.path().extension(), ".tmp") << entry.path();
    }
  }
  EXPECT_GE(killed, 3) << "most runs must really be killed (run took " << run_ms << " ms)";
  fs::remove_all(root);
}

TEST(KillAndResume, GenerateEndsWithTheUninterruptedPool) {
  const std::string root = ::hribench::testing::temp_dir("kill", "generate");
  const std::string run = "generate --tasks I1,I4 --candidates 6 --adapt 2 --eval 1 --test 1 --seed 3 "
                          "--executable-by none --threads 2 --quiet --out ";
  int run_ms = 0;
  run_ms = elapsed_ms([&] { ASSERT_EQ(run_hribench(run + root + "/reference").exit_code, 0); });
  const fs::path reference = fs::path(root) / "reference";
  int killed = 0;
  for (const int ms : moments(run_ms)) {
    const std::string dir = root + "/killed_" + std::to_string(ms);
    killed += run_and_kill_after(run + dir, ms);
    const auto resumed = run_hribench(run + dir + (fs::exists(dir) ? " --resume" : ""));
    ASSERT_EQ(resumed.exit_code, 0) << "killed after " << ms << " ms: " << resumed.output;
    for (const char* file : {"manifest.json", "report.json", "report.md"}) {
      EXPECT_EQ(read_text(fs::path(dir) / file), read_text(reference / file)) << file << ", killed after " << ms << " ms";
    }
  }
  EXPECT_GE(killed, 3) << "most runs must really be killed (run took " << run_ms << " ms)";
  fs::remove_all(root);
}

// Every file under `dir` by its path relative to it, with its bytes.
std::map<std::string, std::string> files_under(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    if (entry.is_regular_file()) files[fs::relative(entry.path(), dir).string()] = read_text(entry.path());
  }
  return files;
}

TEST(KillAndResume, CollectEndsWithTheUninterruptedDataset) {
  const std::string root = ::hribench::testing::temp_dir("kill", "collect");
  const std::string run = "collect --tasks C2,X3 --episodes 1 --size 16 --cameras wrist --format lerobot "
                          "--threads 2 --out ";
  int run_ms = 0;
  run_ms = elapsed_ms([&] { ASSERT_EQ(run_hribench(run + root + "/reference").exit_code, 0); });
  const std::map<std::string, std::string> reference = files_under(fs::path(root) / "reference");
  ASSERT_GT(reference.size(), 10u);  // meta, parquet, mp4 and log files
  int killed = 0;
  for (const int ms : moments(run_ms)) {
    const std::string dir = root + "/killed_" + std::to_string(ms);
    killed += run_and_kill_after(run + dir, ms);
    const auto resumed = run_hribench(run + dir + (fs::exists(dir) ? " --resume" : ""));
    ASSERT_EQ(resumed.exit_code, 0) << "killed after " << ms << " ms: " << resumed.output;
    const std::map<std::string, std::string> files = files_under(dir);
    for (const auto& [path, bytes] : reference) {
      const auto found = files.find(path);
      ASSERT_NE(found, files.end()) << path << " missing, killed after " << ms << " ms";
      EXPECT_TRUE(found->second == bytes) << path << " differs, killed after " << ms << " ms";
    }
    for (const auto& [path, bytes] : files) {
      EXPECT_TRUE(reference.count(path)) << path << " is extra, killed after " << ms << " ms";
    }
  }
  EXPECT_GE(killed, 3) << "most runs must really be killed (run took " << run_ms << " ms)";
  fs::remove_all(root);
}

}  // namespace
}  // namespace hribench::cli

// Nothing lost, nothing duplicated (docs/hardening.md "Crash-safe outputs"): `eval`,
// `generate` and `collect` are killed with SIGKILL at spread moments and resumed; the final
// outputs equal an uninterrupted run's byte for byte.

#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
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

// Runs `run ROOT/reference` whole, then `run DIR` killed at each of moments() of that run and
// resumed (`--resume` where the killed run left DIR), and calls check(DIR, reference, what) on
// each. Most runs must really be killed. The moments follow the shorter of two whole runs: one
// run can take twice as long as the next on a machine busy with other tests, and moments past
// the end of the killed runs kill nothing.
void kill_and_resume(const std::string& run, const std::string& root,
                     const std::function<void(const fs::path&, const fs::path&, const std::string&)>& check) {
  const fs::path reference = fs::path(root) / "reference";
  const fs::path timing = fs::path(root) / "timing";
  const int run_ms = std::min(
      elapsed_ms([&] { ASSERT_EQ(run_hribench(run + reference.string()).exit_code, 0); }),
      elapsed_ms([&] { ASSERT_EQ(run_hribench(run + timing.string()).exit_code, 0); }));
  int killed = 0;
  for (const int ms : moments(run_ms)) {
    const std::string dir = root + "/killed_" + std::to_string(ms);
    const std::string what = "killed after " + std::to_string(ms) + " ms";
    killed += run_and_kill_after(run + dir, ms);
    const auto resumed = run_hribench(run + dir + (fs::exists(dir) ? " --resume" : ""));
    ASSERT_EQ(resumed.exit_code, 0) << what << ": " << resumed.output;
    check(dir, reference, what);
  }
  EXPECT_GE(killed, 3) << "most runs must really be killed (run took " << run_ms << " ms)";
  fs::remove_all(root);
}

TEST(KillAndResume, EvalEndsWithTheUninterruptedRunsResults) {
  kill_and_resume("eval --tasks I4 --policy noop,reactive --episodes 2 --seed 5 --horizon 2 --threads 2 --out ",
                  ::hribench::testing::temp_dir("kill", "eval"),
                  [](const fs::path& dir, const fs::path& reference, const std::string& what) {
                    EXPECT_EQ(read_text(dir / "results.json"), read_text(reference / "results.json")) << what;
                    EXPECT_EQ(count_lines(read_text(dir / "episodes.jsonl")), 4) << what;
                    for (const auto& entry : fs::directory_iterator(dir)) {
                      EXPECT_NE(entry.path().extension(), ".tmp") << entry.path();
                    }
                  });
}

TEST(KillAndResume, GenerateEndsWithTheUninterruptedPool) {
  kill_and_resume("generate --tasks I1,I4 --candidates 12 --adapt 2 --eval 1 --test 1 --seed 3 "
                  "--executable-by none --threads 2 --quiet --out ",
                  ::hribench::testing::temp_dir("kill", "generate"),
                  [](const fs::path& dir, const fs::path& reference, const std::string& what) {
                    for (const char* file : {"manifest.json", "report.json", "report.md"}) {
                      EXPECT_EQ(read_text(dir / file), read_text(reference / file)) << file << ", " << what;
                    }
                  });
}

TEST(KillAndResume, CollectEndsWithTheUninterruptedDataset) {
  kill_and_resume("collect --tasks C2,X3 --episodes 1 --size 64 --cameras wrist --format lerobot --threads 2 --out ",
                  ::hribench::testing::temp_dir("kill", "collect"),
                  [](const fs::path& dir, const fs::path& reference, const std::string& what) {
                    SCOPED_TRACE(what);
                    // meta, parquet, mp4 and log files
                    EXPECT_GT(::hribench::testing::expect_same_files(dir, reference), 10u);
                  });
}

}  // namespace
}  // namespace hribench::cli

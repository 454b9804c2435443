// Runs over MPI ranks (eval/ranks.h, docs/scale.md "MPI"): `mpirun --oversubscribe -np 3` on
// this machine gives the single process's evaluation, generation and collect byte for byte, a
// run refused by rank 0 ends every rank, and a rank that dies loses only the episodes it had in
// flight, which --resume runs again (eval and collect).

#include "eval/ranks.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>
#include <string>
#include <thread>

#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>

#include "support/run_command.h"
#include "support/test_files.h"

extern char** environ;

namespace hribench::eval {
namespace {

namespace fs = std::filesystem;
using ::hribench::testing::read_text;
using ::hribench::testing::run_hribench;
using ::hribench::testing::run_shell;

// mpirun on one machine, as root if need be (CI), without a remote-login agent (none is
// needed on one machine; Open MPI refuses to start when ssh is missing unless told so).
const std::string kMpirun =
    "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_plm_rsh_agent=false "
    "mpirun --oversubscribe --bind-to none -np 3 ";

const std::string kEval =
    "eval --tasks I1,I4,X1 --policy noop,reactive --episodes 3 --seed 2 --horizon 4 --threads 2 --out ";

std::string lines_sorted(const fs::path& file) {
  std::istringstream in(read_text(file));
  std::multiset<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.insert(line);
  std::string out;
  for (const std::string& line : lines) out += line + "\n";
  return out;
}

TEST(Ranks, OutsideMpirunThereIsOneRankAndMpiIsNotStarted) {
  const Ranks ranks = mpi_ranks();
  EXPECT_EQ(ranks.rank, 0);
  EXPECT_EQ(ranks.size, 1);
  EXPECT_FALSE(ranks.distributed());
  int initialized = 1;
  MPI_Initialized(&initialized);
  EXPECT_EQ(initialized, 0);
}

TEST(Ranks, ThreeRanksWriteTheSingleProcessRunByteForByte) {
  const fs::path root = ::hribench::testing::temp_dir("ranks", "equal");
  const auto one = run_hribench(kEval + (root / "one").string() + " --save-logs");
  ASSERT_EQ(one.exit_code, 0) << one.output;
  const auto three = run_shell(kMpirun + HRIBENCH_BINARY + " " + kEval + (root / "three").string() + " --save-logs");
  ASSERT_EQ(three.exit_code, 0) << three.output;
  for (const char* file : {"options.json", "results.json", "summary.md", "summary.csv"}) {
    EXPECT_EQ(read_text(root / "three" / file), read_text(root / "one" / file)) << file;
  }
  // The journal holds the same episodes (in completion order).
  EXPECT_EQ(lines_sorted(root / "three" / "episodes.jsonl"), lines_sorted(root / "one" / "episodes.jsonl"));
  size_t logs = 0;
  for (const auto& entry : fs::directory_iterator(root / "one" / "logs")) {
    ++logs;
    const fs::path other = root / "three" / "logs" / entry.path().filename();
    ASSERT_TRUE(fs::exists(other)) << other;
    EXPECT_EQ(read_text(other), read_text(entry.path())) << entry.path().filename();
  }
  EXPECT_EQ(logs, 18u);
  // Rank 0 alone reports.
  EXPECT_NE(three.output.find("# HRIBench results"), std::string::npos) << three.output;
  EXPECT_EQ(three.output.find("# HRIBench results"), three.output.rfind("# HRIBench results")) << three.output;
  fs::remove_all(root);
}

// Every file under `expected` is under `got` with the same bytes (`by_lines`: a journal in
// completion order, compared as sorted lines), and `got` holds no other file; returns how many.
size_t expect_same_files(const fs::path& got, const fs::path& expected, const std::string& by_lines = "") {
  size_t files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(expected)) {
    if (!entry.is_regular_file()) continue;
    ++files;
    const fs::path relative = fs::relative(entry.path(), expected);
    const fs::path other = got / relative;
    if (!fs::exists(other)) {
      ADD_FAILURE() << other << " is missing";
    } else if (relative == by_lines) {
      EXPECT_EQ(lines_sorted(other), lines_sorted(entry.path()));
    } else {
      EXPECT_EQ(read_text(other), read_text(entry.path())) << relative;
    }
  }
  size_t extra = 0;
  for (const auto& entry : fs::recursive_directory_iterator(got)) extra += entry.is_regular_file();
  EXPECT_EQ(extra, files) << got << " holds other files than " << expected;
  return files;
}

TEST(Ranks, ThreeRanksGenerateTheSingleProcessPoolByteForByte) {
  const fs::path root = ::hribench::testing::temp_dir("ranks", "generate");
  const std::string generate =
      "generate --tasks I1,I4 --candidates 8 --adapt 2 --eval 1 --test 1 --seed 3 --executable-by none --threads 2 "
      "--quiet --out ";
  const auto one = run_hribench(generate + (root / "one").string());
  ASSERT_EQ(one.exit_code, 0) << one.output;
  const auto three = run_shell(kMpirun + HRIBENCH_BINARY + " " + generate + (root / "three").string());
  ASSERT_EQ(three.exit_code, 0) << three.output;
  // options, candidates (in completion order), manifest, reports, episodes
  EXPECT_GE(expect_same_files(root / "three", root / "one", "candidates.jsonl"), 5u);
  fs::remove_all(root);
}

// Frames of at least 64 px: x264 encodes smaller ones differently from one process to the next
// (docs/datasets.md "Reproducible bytes").
const std::string kCollect =
    "collect --tasks C2,X3 --episodes 3 --size 64 --cameras wrist --format lerobot-v3 --threads 1 --out ";

TEST(Ranks, ThreeRanksCollectTheSingleProcessDatasetByteForByte) {
  const fs::path root = ::hribench::testing::temp_dir("ranks", "collect");
  const auto one = run_hribench(kCollect + (root / "one").string());
  ASSERT_EQ(one.exit_code, 0) << one.output;
  const auto three = run_shell(kMpirun + HRIBENCH_BINARY + " " + kCollect + (root / "three").string());
  ASSERT_EQ(three.exit_code, 0) << three.output;
  // The dataset's meta, parquet and mp4 files, collect.json and the logs; nothing left over
  // (the episodes the other ranks stored for rank 0 are gone once committed).
  EXPECT_GE(expect_same_files(root / "three", root / "one"), 12u);
  EXPECT_NE(three.output.find("6 episodes, 6 in the dataset at " + (root / "three").string()), std::string::npos)
      << three.output;
  fs::remove_all(root);
}

TEST(Ranks, ARefusedRunEndsEveryRank) {
  const fs::path root = ::hribench::testing::temp_dir("ranks", "refused");
  fs::create_directories(root / "run");
  std::ofstream(root / "run" / "episodes.jsonl") << "";
  // The folder holds a run: rank 0 refuses it, and the waiting ranks end too (no hang).
  const auto refused = run_shell("timeout 60 env " + kMpirun + HRIBENCH_BINARY + " " + kEval + (root / "run").string());
  EXPECT_NE(refused.exit_code, 0);
  EXPECT_NE(refused.exit_code, 124) << "mpirun hung: " << refused.output;
  EXPECT_NE(refused.output.find("already holds a run; use --resume to continue it or --force to replace it"),
            std::string::npos)
      << refused.output;
  fs::remove_all(root);
}

// The process of rank `rank` among the children of mpirun `parent`, or -1.
pid_t rank_process(pid_t parent, int rank) {
  for (const auto& entry : fs::directory_iterator("/proc")) {
    const std::string name = entry.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::ifstream stat(entry.path() / "stat");
    std::string pid, comm, state;
    pid_t ppid = 0;
    if (!(stat >> pid >> comm >> state >> ppid) || ppid != parent) continue;
    std::ifstream environment(entry.path() / "environ", std::ios::binary);
    const std::string env((std::istreambuf_iterator<char>(environment)), std::istreambuf_iterator<char>());
    if (env.find("OMPI_COMM_WORLD_RANK=" + std::to_string(rank) + '\0') != std::string::npos) return std::stoi(name);
  }
  return -1;
}

// Runs `command` + `dir` under mpirun, kills rank 1 with SIGKILL once finished(dir) >= 2 (its
// episodes in flight are lost; mpirun ends the rest), checks that mpirun failed with fewer than
// `all` finished, and resumes with --resume; returns the resume's exit code and output.
::hribench::testing::CommandResult kill_rank_1_and_resume(const std::string& command, const fs::path& dir, int all,
                                                          const std::function<int(const fs::path&)>& finished) {
  const std::string line = "exec env " + kMpirun + HRIBENCH_BINARY + " " + command + dir.string() + " >/dev/null 2>&1";
  const char* argv[] = {"/bin/sh", "-c", line.c_str(), nullptr};
  pid_t mpirun = 0;
  EXPECT_EQ(posix_spawn(&mpirun, "/bin/sh", nullptr, nullptr, const_cast<char* const*>(argv), environ), 0);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  bool killed = false;
  int status = 0;
  while (std::chrono::steady_clock::now() < deadline) {
    if (waitpid(mpirun, &status, WNOHANG) == mpirun) break;
    if (!killed && finished(dir) >= 2) {
      const pid_t rank1 = rank_process(mpirun, 1);
      if (rank1 > 0) killed = kill(rank1, SIGKILL) == 0;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  if (!killed) waitpid(mpirun, &status, 0);
  EXPECT_TRUE(killed) << "the run ended before rank 1 could be killed";
  EXPECT_FALSE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "mpirun reported success after a rank died";
  const int written = finished(dir);
  EXPECT_GE(written, 2);
  EXPECT_LT(written, all);
  return run_shell(kMpirun + HRIBENCH_BINARY + " " + command + dir.string() + " --resume");
}

TEST(Ranks, ARankThatDiesLosesOnlyItsEpisodesInFlightAndAResumeRedoesThem) {
  const fs::path root = ::hribench::testing::temp_dir("ranks", "death");
  ASSERT_EQ(run_hribench(kEval + (root / "whole").string()).exit_code, 0);
  const fs::path dir = root / "killed";
  const auto resumed = kill_rank_1_and_resume(kEval, dir, 18, [](const fs::path& d) {
    const fs::path lines = d / "episodes.jsonl";
    return fs::exists(lines) ? ::hribench::testing::count_lines(read_text(lines)) : 0;
  });
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_EQ(read_text(dir / "results.json"), read_text(root / "whole" / "results.json"));
  EXPECT_EQ(lines_sorted(dir / "episodes.jsonl"), lines_sorted(root / "whole" / "episodes.jsonl"));
  fs::remove_all(root);
}

TEST(Ranks, ACollectWhoseRankDiesIsResumedToTheUninterruptedDataset) {
  const fs::path root = ::hribench::testing::temp_dir("ranks", "collect_death");
  ASSERT_EQ(run_hribench(kCollect + (root / "whole").string()).exit_code, 0);
  const fs::path dir = root / "killed";
  const auto resumed = kill_rank_1_and_resume(kCollect, dir, 6, [](const fs::path& d) {
    const fs::path state = d / "hribench" / "collect.json";  // one "key" per finished episode
    if (!fs::exists(state)) return 0;
    const std::string text = read_text(state);
    int episodes = 0;
    for (size_t at = text.find("\"key\""); at != std::string::npos; at = text.find("\"key\"", at + 1)) ++episodes;
    return episodes;
  });
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  expect_same_files(dir, root / "whole");
  fs::remove_all(root);
}

}  // namespace
}  // namespace hribench::eval

// `hribench generate --tasks LIST|all --candidates N --seed S --out DIR [--robot NAME] [--threads N]
// [--executable-by POLICY|none] [--adapt N --eval N --test N] [--resume] [--shard i/N]`: the
// generation pipeline of gen/generate.h. Writes the pool folder (gen/pool.h) and prints the
// report table; a shard judges its share of the candidates, and `hribench merge` makes the pool.

#include <cstdio>
#include <memory>
#include <string>

#include "cli/command.h"
#include "eval/ranks.h"
#include "eval/shard.h"
#include "gen/generate.h"
#include "gen/pool.h"
#include "model/robot.h"

namespace hribench::cli {
namespace {

struct GenerateArgs {
  std::string tasks = "all";
  size_t candidates = 150;
  uint64_t seed = 0;
  int threads = 1;
  std::string executable_by = "oracle";
  std::string robot{model::kDefaultRobot};
  gen::SplitSizes splits;
  std::string out;
  bool resume = false;
  bool quiet = false;
  std::string shard;  // "i/N", or empty: the whole generation
};

int run_generate(const GenerateArgs& a) {
  gen::GenerateOptions o;
  o.scripts = gen::resolve_task_scripts(a.tasks);
  o.candidates = a.candidates;
  o.seed = a.seed;
  o.robot = a.robot;
  o.threads = a.threads;
  o.splits = a.splits;
  o.filters.executable_by = a.executable_by;
  o.out = a.out;
  o.resume = a.resume;
  o.progress = !a.quiet;
  if (!a.shard.empty()) o.shard = eval::parse_shard(a.shard, "--shard");
  const gen::GenerationReport report = gen::generate(o);
  if (eval::mpi_ranks().rank != 0) return 0;  // under mpirun, rank 0 reports (eval/ranks.h)
  if (o.shard) {
    std::printf("hribench generate: shard %s of the candidates judged in %s; combine the %d folders with "
                "hribench merge OUT SHARD_DIR...\n",
                eval::to_string(*o.shard).c_str(), a.out.c_str(), o.shard->count);
    return 0;
  }
  std::fputs(gen::report_markdown(report).c_str(), stdout);
  return 0;
}

HRIB_REGISTER_COMMAND(
    "generate", "Sample, filter and split candidate episodes into a versioned episode pool",
    [](CLI::App& app) -> std::function<int()> {
      auto a = std::make_shared<GenerateArgs>();
      app.add_option("--tasks", a->tasks, "Task names, files, or all (comma-separated)");
      app.add_option("--candidates", a->candidates, "Candidates per task")->check(kNonNegativeWhole);
      app.add_option("--seed", a->seed, "Generation seed (candidate seeds derive from it)")
          ->check(kNonNegativeWhole);
      app.add_option("--robot", a->robot, "The robot the episodes are sampled for (docs/robots.md)");
      app.add_option("--threads", a->threads, "Worker threads");
      app.add_option("--executable-by", a->executable_by,
                     "Policy that must solve each candidate (the executability filter), or none: no "
                     "rollout filter (neither executable nor at_rest)");
      app.add_option("--adapt", a->splits.adapt, "Episodes per task in the adapt split")
          ->check(kNonNegativeWhole);
      app.add_option("--eval", a->splits.eval, "Episodes per task in the eval split")
          ->check(kNonNegativeWhole);
      app.add_option("--test", a->splits.test, "Episodes per task in the hidden test split")
          ->check(kNonNegativeWhole);
      app.add_option("--out", a->out, "Pool folder")->required();
      app.add_flag("--resume", a->resume, "Continue an interrupted generation in --out (same options)");
      app.add_flag("--quiet", a->quiet, "No progress line");
      app.add_option("--shard", a->shard,
                     "Judge only shard i of N (i/N, 0 <= i < N: every N-th candidate); combine the N "
                     "folders with hribench merge (docs/scale.md)");
      app.footer([] { return "Tasks: " + gen::task_list_text() + "."; });
      return [a] { return run_generate(*a); };
    });

}  // namespace
}  // namespace hribench::cli

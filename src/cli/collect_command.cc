// `hribench collect --pool pool/v8 --split adapt --policy oracle --cameras agentview,wrist
// --size 224 --format lerobot|lerobot-v3|act-hdf5|robomimic --out DIR [...]`: rolls the policy out on the
// split's episodes, renders the cameras at every control step and writes a training dataset
// (io/collect.h, docs/datasets.md), with a progress line. --dry-run renders every frame and
// writes nothing (the cost of the rollouts and rendering alone). --shard i/N records every N-th
// episode for `hribench merge`; under `mpirun -np N` rank 0 hands the episodes out to the other
// ranks and writes the dataset (docs/scale.md).

#include <cstdio>
#include <memory>
#include <string>

#include "cli/command.h"
#include "eval/ranks.h"
#include "io/collect.h"

namespace hribench::cli {
namespace {

int run_collect(const io::CollectRequest& r) {
  bool progressed = false;
  const io::CollectSummary s = io::collect(r, [&](const io::CollectProgress& p) {
    std::fprintf(stderr, "\rhribench collect: %zu/%zu episodes (%zu resumed), %zu kept, %.1f frames/s, ETA %.0f s ",
                 p.done, p.total, p.resumed, p.kept, p.frames_per_second, p.eta);
    std::fflush(stderr);
    progressed = true;
  });
  if (eval::mpi_ranks().rank != 0) return 0;  // under mpirun, rank 0 reports (eval/ranks.h)
  if (progressed) std::fprintf(stderr, "\n");
  if (!progressed && s.resumed == s.episodes) {
    std::fprintf(stderr, "hribench collect: nothing to resume: all %zu episodes of %s are finished\n", s.episodes,
                 r.out.c_str());
  }
  std::printf("%zu episodes, %zu in the dataset%s; %lld frames in %.1f s (%.1f frames/s)\n", s.episodes, s.kept,
              r.dry_run ? " (dry run: nothing written)" : (" at " + r.out).c_str(),
              static_cast<long long>(s.frames), s.seconds,
              s.seconds > 0 ? static_cast<double>(s.frames) / s.seconds : 0.0);
  return 0;
}

HRIB_REGISTER_COMMAND(
    "collect", "Roll a policy out on a pool's split and write a training dataset (LeRobot, ACT or robomimic)",
    [](CLI::App& app) -> std::function<int()> {
      auto r = std::make_shared<io::CollectRequest>();
      app.add_option("--pool", r->pool, "The episode pool (hribench generate)");
      app.add_option("--split", r->split, "The pool's split: adapt, eval or test");
      app.add_option("--policy", r->policy, "The policy whose actions are recorded");
      app.add_option("--cameras", r->cameras, "Cameras recorded at every control step (comma-separated)");
      app.add_option("--size", r->size, "Image side, pixels (square images)");
      std::string formats;
      for (const std::string& f : io::dataset_format_names()) formats += (formats.empty() ? "" : ", ") + f;
      app.add_option("--format", r->format, "Dataset format: " + formats + " (docs/datasets.md)");
      app.add_option("--out", r->out, "Output folder");
      app.add_option("--tasks", r->tasks, "Task names, ids, or all (comma-separated)");
      app.add_option("--episodes", r->episodes, "The first N episodes of the split per task (0: all)")
          ->check(kNonNegativeWhole);
      app.add_option("--threads", r->threads, "Worker threads (episodes run in parallel)");
      app.add_flag("--resume", r->resume, "Continue the collect in --out (same options)");
      app.add_flag("--force", r->force, "Replace the collect in --out");
      app.add_option("--keep", r->keep, "Episodes kept: success, or all (failures labelled)");
      app.add_option("--action-space", r->action_space,
                     "Recorded actions: the policy's own (default) or joint_pos (the servo targets)");
      app.add_option("--backend", r->backend, "GL back end of the cameras: osmesa or egl");
      app.add_flag("--dry-run", r->dry_run, "Render every frame, write nothing (throughput of the rollouts alone)");
      app.add_option("--shard", r->shard,
                     "i/N: record every N-th episode from the i-th, for hribench merge (docs/scale.md)");
      return [r] { return run_collect(*r); };
    });

}  // namespace
}  // namespace hribench::cli

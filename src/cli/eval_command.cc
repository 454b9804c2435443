// `hribench eval --tasks LIST|all --policy LIST --out DIR [...]`: runs every (task, policy,
// seed) episode, scores it, appends it to DIR/episodes.jsonl as it finishes (so --resume loses
// nothing), and writes DIR/results.json, summary.md, summary.csv and report.html (docs/report.md)
// at the end.
// DIR/options.json records the options that change results; another run's folder is refused
// unless --resume (same options; or more --episodes, which extends the run with the next
// seeds) or --force, and an episode pool's folder is refused outright.
// With --pool DIR [--split eval|adapt|test] the episodes are those of a generated pool's split
// (gen/pool.h: re-sampled from the manifest's seeds and checked against its hashes) instead of
// sampled seeds; the results' options name the pool and its version.
// With --save-logs each episode's log is written to DIR/logs/TASK__POLICY__SEED__HASH.hlog
// (eval/episode_log.h; by an observer of the episode, atomically: temporary name + rename).
// With --video failures|all each failed (or every) episode's video is written to
// DIR/videos/TASK__POLICY__SEED__HASH.mp4 by the worker right after the episode, from its log
// (io/episode_video.h, docs/videos.md); --video-cameras agentview,wrist puts the wrist camera
// beside agentview. Videos do not change results and are not among the run's options.
// With --shard i/N only every N-th job runs and the options record the shard; `hribench merge`
// combines the N folders (eval/shard.h, docs/scale.md). Under `mpirun -np N` rank 0 hands the
// episodes out to the other ranks' threads and writes everything (eval/ranks.h).
// The run itself is the library's (gen/evaluation.h, eval/run.h), shared with Python's
// hribench.evaluate: one instance of each policy per worker thread, reset for every episode.
// A remote policy that cannot connect for remote::kMaxConnectFailures episodes in a row stops
// the run (exit 1); those episodes are not written, so --resume runs them again.

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "cli/command.h"
#include "core/errors.h"
#include "eval/episode_files.h"
#include "eval/ranks.h"
#include "eval/report.h"
#include "eval/run.h"
#include "gen/evaluation.h"
#include "gen/pool.h"
#include "io/episode_video.h"
#include "policy/registry.h"
#include "remote/remote.h"

namespace hribench::cli {
namespace {

struct VideoRequest {
  std::string which = "none";  // --video: none, failures or all
  std::string cameras = "agentview";
};

// Sets settings.after_episode to write the videos --video asks for.
void ask_for_videos(const VideoRequest& video, const eval::RunPlan& plan, eval::RunSettings& settings) {
  if (video.which == "none") return;
  if (video.which != "failures" && video.which != "all") {
    throw core::InputError("--video", "none, failures or all", "'" + video.which + "'");
  }
  io::EpisodeVideoOptions options;
  options.cameras = io::video_cameras(video.cameras, plan.by_task.front().front(), "--video-cameras");
  options.backend = settings.run_options.render_backend;
  const std::filesystem::path out = settings.out;
  const bool all = video.which == "all";
  settings.after_episode = [out, options, all](const script::EpisodeSpec& spec, const eval::EpisodeLog& log,
                                               const eval::EpisodeResult& result, const std::string& stem) {
    if (!all && result.metrics.success) return;
    std::filesystem::create_directories(eval::video_file(out, stem).parent_path());
    io::write_episode_video(spec, log, eval::video_file(out, stem), options);
  };
}

int run_eval(const gen::EvalRequest& o, const VideoRequest& video) {
  const eval::PolicyMaker make = [](const std::string& reference) { return policy::make_policy(reference); };
  eval::RunSettings settings;
  const eval::RunPlan plan = gen::plan_evaluation(o, make, settings);
  ask_for_videos(video, plan, settings);
  // A remote policy that cannot connect for several episodes in a row stops the run.
  settings.unreachable = [](const eval::EpisodeResult& r) { return remote::is_connect_failure(r.status_reason); };
  settings.max_unreachable = remote::kMaxConnectFailures;
  bool progressed = false;
  eval::RunResults run;
  try {
    run = eval::run_plan(plan, settings, make, [&](const eval::RunProgress& p) {
      // A one-line progress indicator.
      std::fprintf(stderr, "\rhribench eval: %zu/%zu episodes (%zu resumed), %.2f ep/s, ETA %.0f s ", p.done,
                   p.total, p.resumed, p.rate, p.eta);
      std::fflush(stderr);
      progressed = true;
    });
  } catch (const eval::RunStopped& stopped) {
    std::fprintf(stderr, "\nhribench eval: stopped: %s\n", stopped.what());
    return 1;
  }
  if (eval::mpi_ranks().rank != 0) return 0;  // under mpirun, rank 0 reports (eval/ranks.h)
  if (progressed) {
    std::fprintf(stderr, "\n");
  } else {
    std::fprintf(stderr, "hribench eval: nothing to resume: all %zu episodes of %s are finished\n",
                 run.episodes.size(), o.out.c_str());
  }
  if (o.horizon > 0) {
    for (const std::string& task : gen::tasks_ended_before_a_cue(plan, run.episodes, o.horizon)) {
      std::fprintf(stderr,
                   "hribench eval: warning: --horizon %g s ends every %s episode before its first cue; its "
                   "scores say nothing about responding to the person\n",
                   o.horizon, task.c_str());
    }
  }
  std::fputs(eval::summary_markdown(run, eval::SummaryFor::kTerminal).c_str(), stdout);
  std::fprintf(stdout,
               "\nThe metric constants and per-episode results: %s/summary.md, %s/results.json; the report "
               "page: %s/report.html\n",
               o.out.c_str(), o.out.c_str(), o.out.c_str());
  return 0;
}

HRIB_REGISTER_COMMAND(
    "eval", "Run policies on tasks and score the episodes",
    [](CLI::App& app) -> std::function<int()> {
      auto o = std::make_shared<gen::EvalRequest>();
      app.add_option("--tasks", o->tasks, "Task names, files, or all (comma-separated; default all)");
      app.add_option("--policy", o->policies, "Policy references (comma-separated)")->required();
      CLI::Option* episodes =
          app.add_option("--episodes", o->episodes, "Episodes per task and policy (seeds S..S+N-1)");
      CLI::Option* seed = app.add_option("--seed", o->seed, "First seed")->check(kNonNegativeWhole);
      app.add_option("--pool", o->pool, "Evaluate the episodes of this generated pool (hribench generate)");
      app.add_option("--split", o->split, "The pool's split: eval (default), adapt or test");
      app.add_option("--threads", o->threads, "Worker threads");
      app.add_option("--latency", o->latency, "none | fixed:MS | measured");
      app.add_option("--horizon", o->horizon, "Episode length in seconds (default: the script's)");
      app.add_option("--out", o->out, "Output folder")->required();
      app.add_flag("--resume", o->resume, "Continue the run in --out (same options)");
      app.add_flag("--force", o->force, "Replace the run in --out");
      app.add_option("--shard", o->shard,
                     "Run only shard i of N (i/N, 0 <= i < N: every N-th episode); combine the N folders "
                     "with hribench merge (docs/scale.md)");
      app.add_flag("--save-logs", o->save_logs,
                   "Write each episode's log to DIR/logs/*.hlog (hribench's binary episode log)");
      auto video = std::make_shared<VideoRequest>();
      app.add_option("--video", video->which,
                     "Write episode videos to DIR/videos/*.mp4: none, failures or all (docs/videos.md)")
          ->capture_default_str();
      app.add_option("--video-cameras", video->cameras, "agentview, or agentview,wrist side by side")
          ->capture_default_str();
      app.footer([] {
        std::string policies;
        for (const std::string& name : policy::policy_names()) policies += (policies.empty() ? "" : ", ") + name;
        return "Tasks: " + gen::task_list_text() + ".\nPolicies: " + policies +
               " (docs/policies.md; options as NAME?key=value&key=value).";
      });
      return [o, video, episodes, seed] {
        o->sampling_flags = episodes->count() > 0 || seed->count() > 0;
        return run_eval(*o, *video);
      };
    });

}  // namespace
}  // namespace hribench::cli

#pragma once
// The files a run keeps about one episode (docs/report.md), all named by the episode's stem
// TASK__POLICY__SEED__HASH (the policy reference with characters a file name should not hold,
// e.g. "openpi://host:8000", replaced by '_'; HASH = the spec hash's first 12 characters):
//   RUN/logs/STEM.hlog     its log (eval --save-logs, eval/episode_log.h)
//   RUN/videos/STEM.mp4    its video (eval --video, hribench video)
//   RUN/replay/STEM.html   its 3D replay page (hribench replay-html)

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "eval/aggregate.h"

namespace hribench::eval {

std::string episode_stem(std::string_view task, std::string_view policy, uint64_t seed,
                         std::string_view spec_hash);
std::string episode_stem(const EpisodeResult& episode);

std::filesystem::path log_file(const std::filesystem::path& run, std::string_view stem);
std::filesystem::path video_file(const std::filesystem::path& run, std::string_view stem);
std::filesystem::path replay_file(const std::filesystem::path& run, std::string_view stem);

// The stems of RUN/logs/*.hlog, sorted (empty when there is no logs/ folder).
std::vector<std::string> saved_log_stems(const std::filesystem::path& run);

// The failed episodes (metrics.success false) of `run` that have a saved log: the stems of
// the first `per_task_and_policy` (>= 1) of each task and policy, in the order of `episodes`
// (the run's results.json, eval::load_run). What `hribench video RUN --failures N` and
// `hribench replay-html RUN --failures N` make, e.g. a few failures of each baseline for the
// main command's report (scripts/main.sh). Throws core::InputError when `run` holds no logs.
std::vector<std::string> first_failed_logged_stems(const std::filesystem::path& run,
                                                   const std::vector<EpisodeResult>& episodes,
                                                   int per_task_and_policy);

// The log of an episode of `run`: `episode` is the path of a .hlog file, or a stem of
// RUN/logs. Throws core::InputError (where = `where`, e.g. "EPISODE" or "--episode") when
// `run` holds no logs ("... run eval with --save-logs ...") or the stem is not one of them
// (a few that are named).
std::filesystem::path find_episode_log(const std::filesystem::path& run, std::string_view episode,
                                       std::string_view where);

}  // namespace hribench::eval

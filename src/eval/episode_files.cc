#include "eval/episode_files.h"

#include <algorithm>
#include <cctype>
#include <map>
#include <system_error>
#include <utility>

#include <fmt/format.h>

#include "core/errors.h"

namespace hribench::eval {

namespace fs = std::filesystem;

std::string episode_stem(std::string_view task, std::string_view policy, uint64_t seed,
                         std::string_view spec_hash) {
  std::string stem = fmt::format("{}__{}__{}__{}", task, policy, seed, spec_hash.substr(0, 12));
  for (char& c : stem) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-' && c != '.') c = '_';
  }
  return stem;
}

std::string episode_stem(const EpisodeResult& episode) {
  return episode_stem(episode.task, episode.policy, episode.seed, episode.spec_hash);
}

fs::path log_file(const fs::path& run, std::string_view stem) {
  return run / "logs" / (std::string(stem) + ".hlog");
}
fs::path video_file(const fs::path& run, std::string_view stem) {
  return run / "videos" / (std::string(stem) + ".mp4");
}
fs::path replay_file(const fs::path& run, std::string_view stem) {
  return run / "replay" / (std::string(stem) + ".html");
}

std::vector<std::string> saved_log_stems(const fs::path& run) {
  std::vector<std::string> stems;
  std::error_code ec;
  if (!fs::is_directory(run / "logs", ec)) return stems;
  for (const fs::directory_entry& entry : fs::directory_iterator(run / "logs", ec)) {
    if (entry.path().extension() == ".hlog") stems.push_back(entry.path().stem().string());
  }
  std::sort(stems.begin(), stems.end());
  return stems;
}

namespace {

std::vector<std::string> saved_log_stems_or_throw(const fs::path& run) {
  std::vector<std::string> stems = saved_log_stems(run);
  if (stems.empty()) {
    throw core::InputError::Message(
        run.string(), "holds no episode logs (logs/*.hlog); run eval with --save-logs to keep them");
  }
  return stems;
}

}  // namespace

std::vector<std::string> first_failed_logged_stems(const fs::path& run,
                                                   const std::vector<EpisodeResult>& episodes,
                                                   int per_task_and_policy) {
  const std::vector<std::string> logged = saved_log_stems_or_throw(run);
  std::vector<std::string> stems;
  std::map<std::pair<std::string, std::string>, int> taken;  // (task, policy) -> stems chosen
  for (const EpisodeResult& episode : episodes) {
    if (episode.metrics.success) continue;
    int& count = taken[{episode.task, episode.policy}];
    if (count >= per_task_and_policy) continue;
    const std::string stem = episode_stem(episode);
    if (!std::binary_search(logged.begin(), logged.end(), stem)) continue;
    stems.push_back(stem);
    ++count;
  }
  return stems;
}

fs::path find_episode_log(const fs::path& run, std::string_view episode, std::string_view where) {
  const fs::path given(episode);
  std::error_code ec;
  if (given.extension() == ".hlog" && fs::is_regular_file(given, ec)) return given;
  const std::vector<std::string> stems = saved_log_stems_or_throw(run);
  const std::string stem = given.extension() == ".hlog" ? given.stem().string() : std::string(episode);
  if (std::find(stems.begin(), stems.end(), stem) != stems.end()) return log_file(run, stem);
  std::string some;
  for (size_t i = 0; i < stems.size() && i < 3; ++i) some += (i ? ", " : "") + stems[i];
  throw core::InputError(std::string(where),
                         fmt::format("an episode of {} (a log stem, e.g. {}{}; or a .hlog file)", run.string(), some,
                                     stems.size() > 3 ? fmt::format(", ... {} in all", stems.size()) : ""),
                         "'" + std::string(episode) + "'");
}

}  // namespace hribench::eval

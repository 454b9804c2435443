// `hribench merge OUT SHARD_DIR...`: combines the folders of a sharded eval (`eval --shard i/N`,
// one per shard, each finished) into OUT, exactly as one `eval` without --shard would have
// written it: options.json without the shard, episodes.jsonl and results.json in job order,
// summary.md and summary.csv, and the shards' logs/ (eval/shard.h, docs/scale.md). The folders
// of a sharded `generate` become the pool one `generate` writes (gen::merge_generation), those of
// a sharded `collect` the dataset one `collect` writes (io::merge_collect). Shards
// that disagree (options, code, constants, a missing or repeated shard, an unfinished one) are
// refused in one line; OUT must be new.

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "cli/command.h"
#include "core/errors.h"
#include "core/files.h"
#include "core/json.h"
#include "eval/report.h"
#include "eval/shard.h"
#include "gen/generate.h"
#include "io/collect.h"

namespace hribench::cli {
namespace {

namespace fs = std::filesystem;

int run_merge(const std::string& out, const std::vector<std::string>& dirs) {
  if (io::holds_collect(dirs.front())) {
    const io::CollectSummary s = io::merge_collect(out, dirs);
    std::fprintf(stderr, "hribench merge: %zu collect shards -> the dataset %s\n", dirs.size(), out.c_str());
    std::printf("%zu episodes, %zu in the dataset at %s\n", s.episodes, s.kept, out.c_str());
    return 0;
  }
  if (gen::holds_generation(dirs.front())) {
    const gen::GenerationReport report = gen::merge_generation(out, dirs);
    std::fprintf(stderr, "hribench merge: %zu generation shards -> the pool %s\n", dirs.size(), out.c_str());
    std::fputs(gen::report_markdown(report).c_str(), stdout);
    return 0;
  }
  std::error_code ec;
  if (fs::exists(out, ec) && (!fs::is_directory(out, ec) || !fs::is_empty(out, ec))) {
    throw core::InputError("OUT", "a new or empty folder for the merged run", "'" + out + "'");
  }
  std::vector<eval::ShardRun> shards;
  for (const std::string& dir : dirs) {
    if (!fs::is_regular_file(fs::path(dir) / "results.json")) {
      throw core::InputError::Message(dir, "holds no finished run (no results.json); finish it with eval --resume");
    }
    const fs::path options = fs::path(dir) / "options.json";
    if (!fs::is_regular_file(options)) throw core::InputError::Message(dir, "holds no options.json");
    shards.push_back({dir, core::read_json_file(options.string()), eval::load_run(dir)});
  }
  const eval::RunResults merged = eval::merge_shards(shards);

  fs::create_directories(out);
  core::write_file_atomically(fs::path(out) / "options.json", eval::merged_options(shards.front().options).dump(2) + "\n");
  std::string lines;
  for (const eval::EpisodeResult& r : merged.episodes) lines += eval::episode_to_json(r).dump() + "\n";
  core::write_file_atomically(fs::path(out) / "episodes.jsonl", lines);
  for (const eval::ShardRun& shard : shards) {
    const fs::path logs = fs::path(shard.dir) / "logs";
    if (!fs::is_directory(logs)) continue;
    fs::create_directories(fs::path(out) / "logs");
    for (const fs::directory_entry& log : fs::directory_iterator(logs)) {
      fs::copy_file(log.path(), fs::path(out) / "logs" / log.path().filename(), fs::copy_options::overwrite_existing);
    }
  }
  eval::write_run(out, merged);
  std::fprintf(stderr, "hribench merge: %zu shards, %zu episodes -> %s\n", shards.size(), merged.episodes.size(),
               out.c_str());
  std::fputs(eval::summary_markdown(merged, eval::SummaryFor::kTerminal).c_str(), stdout);
  return 0;
}

HRIB_REGISTER_COMMAND("merge", "Combine the folders of a sharded eval, generate or collect (--shard i/N) into one run, pool or dataset",
                      [](CLI::App& app) -> std::function<int()> {
                        auto out = std::make_shared<std::string>();
                        auto dirs = std::make_shared<std::vector<std::string>>();
                        app.add_option("OUT", *out, "Folder for the merged run, pool or dataset (new or empty)")->required();
                        app.add_option("SHARD_DIR", *dirs, "The shards' run folders, one per shard")->required();
                        return [out, dirs] { return run_merge(*out, *dirs); };
                      });

}  // namespace
}  // namespace hribench::cli

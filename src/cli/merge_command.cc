// `hribench merge OUT SHARD_DIR...`: combines the folders of a sharded eval (`eval --shard i/N`,
// one per shard, each finished) into OUT, exactly as one `eval` without --shard would have
// written it: options.json without the shard, episodes.jsonl and results.json in job order,
// summary.md and summary.csv, and the shards' logs/ (eval/shard.h, docs/scale.md). The folders
// of a sharded `generate` become the pool one `generate` writes (gen::merge_generation), those of
// a sharded `collect` the dataset one `collect` writes (io::merge_collect). Shards
// that disagree (options, code, constants, a missing or repeated shard, an unfinished one) are
// refused in one line; OUT must be new or empty. The merge is written into a staging folder
// beside OUT (.NAME.merging) and renamed to OUT once complete, so a merge that fails after its
// checks (a stored episode that cannot be read, a full disk) leaves OUT as it was, never half a
// run, pool or dataset (docs/scale.md).

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>

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

// The merged folder's kind, as the first shard shows it.
enum class Merged { kRun, kPool, kDataset };

Merged merged_kind(const std::string& first_shard) {
  if (io::holds_collect(first_shard)) return Merged::kDataset;
  if (gen::holds_generation(first_shard)) return Merged::kPool;
  return Merged::kRun;
}

const char* to_string(Merged kind) {
  switch (kind) {
    case Merged::kRun: return "run";
    case Merged::kPool: return "pool";
    case Merged::kDataset: return "dataset";
  }
  return "run";
}

// A sharded eval's folders merged into `out`, a new folder.
eval::RunResults merge_runs(const fs::path& out, const std::vector<std::string>& dirs) {
  std::vector<eval::ShardRun> shards;
  for (const std::string& dir : dirs) {
    if (!fs::is_regular_file(fs::path(dir) / "results.json")) {
      throw core::InputError::Message(dir, "holds no finished run (no results.json); finish it with eval --resume");
    }
    const fs::path options = fs::path(dir) / "options.json";
    if (!fs::is_regular_file(options)) throw core::InputError::Message(dir, "holds no options.json");
    shards.push_back({dir, core::read_json_file(options.string()), eval::load_run(dir)});
  }
  eval::RunResults merged = eval::merge_shards(shards);

  fs::create_directories(out);
  core::write_file_atomically(out / "options.json", eval::merged_options(shards.front().options).dump(2) + "\n");
  std::string lines;
  for (const eval::EpisodeResult& r : merged.episodes) lines += eval::episode_to_json(r).dump() + "\n";
  core::write_file_atomically(out / "episodes.jsonl", lines);
  for (const eval::ShardRun& shard : shards) {
    const fs::path logs = fs::path(shard.dir) / "logs";
    if (!fs::is_directory(logs)) continue;
    fs::create_directories(out / "logs");
    for (const fs::directory_entry& log : fs::directory_iterator(logs)) {
      fs::copy_file(log.path(), out / "logs" / log.path().filename(), fs::copy_options::overwrite_existing);
    }
  }
  eval::write_run(out.string(), merged);
  return merged;
}

int run_merge(const std::string& out, const std::vector<std::string>& dirs) {
  const Merged kind = merged_kind(dirs.front());
  std::error_code ec;
  if (fs::exists(out, ec) && (!fs::is_directory(out, ec) || !fs::is_empty(out, ec))) {
    throw core::InputError("OUT", std::string("a new or empty folder for the merged ") + to_string(kind), "'" + out + "'");
  }
  fs::path target = fs::absolute(out).lexically_normal();
  if (!target.has_filename()) target = target.parent_path();  // OUT given as "dir/"
  const fs::path staging = target.parent_path() / ("." + target.filename().string() + ".merging");
  fs::remove_all(staging, ec);  // left by a merge that was killed
  std::string note;     // stderr
  std::string printed;  // stdout
  try {
    switch (kind) {
      case Merged::kDataset: {
        const io::CollectSummary s = io::merge_collect(staging, dirs);
        note = fmt::format("{} collect shards -> the dataset {}", dirs.size(), out);
        printed = fmt::format("{} episodes, {} in the dataset at {}\n", s.episodes, s.kept, out);
        break;
      }
      case Merged::kPool:
        note = fmt::format("{} generation shards -> the pool {}", dirs.size(), out);
        printed = gen::report_markdown(gen::merge_generation(staging.string(), dirs));
        break;
      case Merged::kRun: {
        const eval::RunResults merged = merge_runs(staging, dirs);
        note = fmt::format("{} shards, {} episodes -> {}", dirs.size(), merged.episodes.size(), out);
        printed = eval::summary_markdown(merged, eval::SummaryFor::kTerminal);
        break;
      }
    }
    if (fs::exists(target, ec)) fs::remove(target);  // empty, as checked above
    fs::rename(staging, target);
  } catch (...) {
    fs::remove_all(staging, ec);
    throw;
  }
  std::fprintf(stderr, "hribench merge: %s\n", note.c_str());
  std::fputs(printed.c_str(), stdout);
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

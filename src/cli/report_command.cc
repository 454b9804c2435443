// `hribench report DIR... [--by role|task] [--format md|csv|json|html] [--episode STEM] [--force]`: one headline table
// comparing the runs in the given folders (or results.json files), each labelled by its path,
// by role group and overall or by task; as Markdown, or every estimate with its interval as CSV
// or JSON (for programs). Runs that cannot be compared without a
// word — another horizon, other seeds, pool, split, latency, HRIBench version or tasks — are
// refused with the first difference named, or with --force compared with every difference
// printed as a warning. A policy in two runs (two checkpoints behind one name, say) is a warning:
// its rows are told apart by the run's path.
// --format html (re)writes the report page of one run, RUN/report.html (eval/report_html.h,
// docs/report.md), with the timeline of --episode STEM (default: the first failed episode with
// a saved log), linking the videos and replay pages the folder holds now.

#include <array>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "cli/command.h"
#include "core/errors.h"
#include "eval/report.h"
#include "eval/report_html.h"

namespace hribench::cli {
namespace {

// The run options that change what a number means; a run without one of them ran with the default.
constexpr std::array<const char*, 8> kComparedOptions = {"horizon", "episodes", "seed",  "pool",
                                                         "pool_version", "split", "latency", "tasks"};

struct Comparison {
  std::vector<std::string> differences;  // the runs measured different things
  std::vector<std::string> notes;        // worth a word, not a refusal
};

Comparison compare_runs(const std::vector<std::pair<std::string, eval::RunResults>>& runs) {
  Comparison c;
  if (runs.empty()) return c;
  const auto& [first_name, first] = runs.front();
  const auto option = [](const eval::RunResults& run, const char* key) {
    return run.info.options.contains(key) ? run.info.options.at(key).dump() : std::string("(not set)");
  };
  std::map<std::string, std::string> policy_run;  // policy -> the run it was first seen in
  for (const auto& [name, run] : runs) {
    for (const char* key : kComparedOptions) {
      if (option(run, key) != option(first, key)) {
        c.differences.push_back(fmt::format("{} has {} {}, {} has {}", name, key, option(run, key), first_name,
                                       option(first, key)));
      }
    }
    if (run.info.hribench_version != first.info.hribench_version) {
      c.differences.push_back(fmt::format("{} was made by HRIBench {}, {} by {}", name, run.info.hribench_version,
                                     first_name, first.info.hribench_version));
    }
    std::set<std::string> policies;
    for (const eval::EpisodeResult& e : run.episodes) policies.insert(e.policy);
    for (const std::string& policy : policies) {
      const auto [it, fresh] = policy_run.emplace(policy, name);
      if (!fresh) c.notes.push_back(fmt::format("policy {} is in {} and in {}", policy, it->second, name));
    }
  }
  return c;
}

struct ReportOptions {
  std::vector<std::string> dirs;
  std::string by = "role";
  std::string format = "md";
  std::string episode;
  bool force = false;
};

int run_report(const ReportOptions& o) {
  if (o.by != "role" && o.by != "task") throw core::InputError("--by", "role or task", "'" + o.by + "'");
  if (o.format != "md" && o.format != "csv" && o.format != "json" && o.format != "html") {
    throw core::InputError("--format", "md, csv, json or html", "'" + o.format + "'");
  }
  if (!o.episode.empty() && o.format != "html") {
    throw core::InputError("--episode", "--format html (the report page's timeline)", "--format " + o.format);
  }
  if (o.format == "html") {
    if (o.dirs.size() != 1) {
      throw core::InputError("--format html", "one run folder", fmt::format("{} runs", o.dirs.size()));
    }
    const std::filesystem::path dir = std::filesystem::is_directory(o.dirs.front())
                                          ? std::filesystem::path(o.dirs.front())
                                          : std::filesystem::path(o.dirs.front()).parent_path();
    const std::filesystem::path page = eval::write_report_html(dir, eval::load_run(o.dirs.front()), o.episode);
    std::printf("wrote %s\n", page.c_str());
    return 0;
  }
  const eval::CompareBy by = o.by == "task" ? eval::CompareBy::kTask : eval::CompareBy::kRole;
  const std::vector<std::string>& dirs = o.dirs;
  const bool force = o.force;
  std::vector<std::pair<std::string, eval::RunResults>> runs;
  runs.reserve(dirs.size());
  for (const std::string& dir : dirs) runs.emplace_back(dir, eval::load_run(dir));
  Comparison c = compare_runs(runs);
  if (!c.differences.empty() && !force) {
    throw core::InputError::Message(
        "report", "the runs differ: " + c.differences.front() +
                      (c.differences.size() > 1 ? fmt::format(" (and {} more)", c.differences.size() - 1) : "") +
                      "; use --force to compare them anyway");
  }
  c.notes.insert(c.notes.begin(), c.differences.begin(), c.differences.end());
  for (const std::string& note : c.notes) std::fprintf(stderr, "hribench report: warning: %s\n", note.c_str());
  if (o.format == "csv") {
    std::fputs(eval::compare_csv(runs, by).c_str(), stdout);
  } else if (o.format == "json") {
    std::fputs((eval::compare_json(runs, by).dump(2) + "\n").c_str(), stdout);
  } else {
    std::fputs(eval::compare_markdown(runs, by).c_str(), stdout);
  }
  return 0;
}

HRIB_REGISTER_COMMAND("report", "Compare the results of runs (folders written by eval)",
                      [](CLI::App& app) -> std::function<int()> {
                        auto o = std::make_shared<ReportOptions>();
                        app.add_option("dirs", o->dirs, "Run folders or results.json files")->required();
                        app.add_option("--by", o->by, "Rows by role group (and overall) or by task: role | task");
                        app.add_option("--format", o->format,
                                       "md (a table), csv or json (every estimate with its interval), or html "
                                       "(writes RUN/report.html, one run)");
                        app.add_option("--episode", o->episode,
                                       "With --format html: the episode whose timeline the page draws (a log "
                                       "stem of RUN/logs; default: the first failed one with a saved log)");
                        app.add_flag("--force", o->force,
                                     "Compare runs that differ in horizon, seeds, pool, split, latency, "
                                     "version or tasks (each difference is a warning)");
                        return [o] { return run_report(*o); };
                      });

}  // namespace
}  // namespace hribench::cli

#pragma once
// Results of a run (issue 5 "Reports"): results.json (provenance, metric constants, one entry
// per episode), summary.md and summary.csv (the headline table — Role group | Policy | CSR |
// CT | Rsp | TSync | OC | Safety — the component table, per-task tables and failure counts),
// and a table comparing several runs (`hribench report runs/A runs/B`).
//
// Each episode names its robot (a robot description, model/robot.h); the provenance lists the
// run's robots (derived from its episodes when written, not read back).
// Episodes serialize one by one (episode_to_json) so a runner can append them to a JSON-lines
// file as they finish; results.json holds them all. Doubles are written with round-trip
// precision, so reloaded results re-aggregate identically.

#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "eval/aggregate.h"
#include "eval/constants.h"

namespace hribench::eval {

inline constexpr int kResultsFormatVersion = 1;

// Provenance of a run (docs/design.md).
struct RunInfo {
  std::string hribench_version;
  std::string git_hash;
  std::string mujoco_version;
  std::string renderer;           // GL_RENDERER string, or "none"
  nlohmann::json options = nlohmann::json::object();  // the run's options (CLI flags)
  MetricConstants constants;
};
// This build's versions (core/version.h, mj_versionString) with the given renderer/options.
RunInfo current_run_info(std::string renderer, nlohmann::json options,
                         const MetricConstants& constants = {});

struct RunResults {
  RunInfo info;
  std::vector<EpisodeResult> episodes;
};

nlohmann::json episode_to_json(const EpisodeResult& episode);
// Throws core::InputError (where = `where`, e.g. "results.json: episodes[3]") on a missing or
// mistyped field or an unknown label/status.
EpisodeResult episode_from_json(const nlohmann::json& json, const std::string& where);

// JSON lines, one episode per line, for results written as each episode finishes (--resume).
// append_episode_line writes one line and flushes; throws core::InputError if it cannot.
void append_episode_line(const std::filesystem::path& path, const EpisodeResult& episode);
// The episodes of such a file, in order. A last line without its newline (a run killed while
// writing it) is dropped; any other bad line is a core::InputError at "FILE:LINE".
std::vector<EpisodeResult> load_episode_lines(const std::filesystem::path& path);

// The aggregates (docs/metrics.md "Aggregation") as results.json holds them: {"task": [...],
// "role": [...], "overall": [...]}, one object per (group, policy) with each estimate as
// {value, low, high, n} (null when not applicable), rsp_median, safety, critical_contacts and
// failures (primary label -> episodes). Derived from the episodes: written, never read back.
nlohmann::json aggregates_to_json(const RunResults& run);
nlohmann::json results_to_json(const RunResults& run);
RunResults results_from_json(const nlohmann::json& json, const std::string& where);

// Writes DIR/results.json, DIR/summary.md, DIR/summary.csv and DIR/report.html (DIR is
// created; the report links the episode files DIR holds, eval/report_html.h). Throws
// core::InputError if a file cannot be written or a saved log is corrupt.
void write_run(const std::filesystem::path& dir, const RunResults& run);
// Reads DIR/results.json (or the file itself when given a file). Throws core::InputError.
RunResults load_run(const std::filesystem::path& path);

// The documents themselves. The terminal's summary leaves out the metric constants table
// (it is in summary.md and results.json).
enum class SummaryFor { kFile, kTerminal };
std::string summary_markdown(const RunResults& run, SummaryFor audience = SummaryFor::kFile);
std::string summary_csv(const RunResults& run);
// One headline table over several runs (label = a name per run, e.g. its folder), by role
// group and overall (or by task), followed by a note if their metric constants differ.
enum class CompareBy { kRole, kTask };
std::string compare_markdown(const std::vector<std::pair<std::string, RunResults>>& runs,
                             CompareBy by = CompareBy::kRole);
// The same rows with every estimate and its interval: CSV (summary.csv's columns after a `run`
// column) and JSON (aggregates_to_json's objects with `run` and `level` added).
std::string compare_csv(const std::vector<std::pair<std::string, RunResults>>& runs, CompareBy by);
nlohmann::json compare_json(const std::vector<std::pair<std::string, RunResults>>& runs, CompareBy by);

}  // namespace hribench::eval

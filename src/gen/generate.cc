#include "gen/generate.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <thread>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/files.h"
#include "core/paths.h"
#include "core/version.h"
#include "eval/ranks.h"
#include "policy/registry.h"
#include "script/check.h"
#include "script/sample.h"

namespace hribench::gen {
namespace {

namespace fs = std::filesystem;

// Runs judge(job) for jobs 0..n-1 on `threads` threads; done(job, record) is serialised.
// The first exception stops new jobs and is rethrown after the running ones finish.
void run_parallel(size_t n, int threads, const std::function<CandidateRecord(size_t)>& judge,
                  const std::function<void(size_t, const CandidateRecord&)>& done) {
  std::atomic<size_t> next{0};
  std::atomic<bool> stop{false};
  std::mutex mutex;
  std::exception_ptr error;
  const auto worker = [&] {
    while (!stop) {
      const size_t job = next++;
      if (job >= n) return;
      try {
        const CandidateRecord record = judge(job);
        const std::lock_guard<std::mutex> lock(mutex);
        done(job, record);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(mutex);
        if (!error) error = std::current_exception();
        stop = true;
      }
    }
  };
  std::vector<std::thread> pool;
  const size_t count = std::min(static_cast<size_t>(threads), std::max<size_t>(n, 1));
  for (size_t i = 1; i < count; ++i) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
  if (error) std::rethrow_exception(error);
}

std::string key(const std::string& task, size_t index) { return task + "#" + std::to_string(index); }

// Candidate lines already in the file (a torn last line is dropped).
std::vector<CandidateRecord> load_candidates(const fs::path& path) {
  std::vector<CandidateRecord> records;
  std::ifstream in(path);
  std::string line;
  size_t number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty()) continue;
    try {
      records.push_back(candidate_from_json(
          core::parse_json(line, path.string()), path.string() + ":" + std::to_string(number)));
    } catch (const core::InputError&) {
      if (in.peek() == std::char_traits<char>::eof()) break;  // torn by an interruption
      throw;
    }
  }
  return records;
}

// What options.json holds: the generator options, and for a shard the shard, the job count
// and the code that judges (a merge refuses shards judged by other code).
core::Json options_json(const GenerateOptions& o, const core::Json& generator, size_t jobs) {
  if (!o.shard) return generator;
  core::Json options = generator;
  options["shard"] = eval::to_string(*o.shard);
  options["shard_of_jobs"] = jobs;
  options["code"] = core::code_identity();
  return options;
}

// Refuses an OUT holding another pool; returns the candidates judged before (resume).
// `generator`: what options.json must hold (options_json).
std::vector<CandidateRecord> prepare_out(const GenerateOptions& o, const core::Json& generator) {
  const fs::path dir = o.out;
  const fs::path options_file = dir / "options.json";
  const fs::path lines_file = dir / "candidates.jsonl";
  if (fs::exists(dir) && !fs::is_directory(dir)) {
    throw core::InputError("--out", "a folder for the pool", "'" + o.out + "', a file");
  }
  if (fs::exists(dir / "episodes.jsonl") || fs::exists(dir / "results.json")) {
    throw core::InputError::Message(
        o.out, "holds an evaluation run (episodes.jsonl / results.json), not a pool; choose another --out");
  }
  // A finished generation resumed with its own options (a run killed after writing its
  // manifest) redoes nothing and writes the same files again; any other pool is refused.
  const bool own_options = fs::exists(options_file) && core::read_json_file(options_file.string()) == generator;
  if (fs::exists(dir / "manifest.json") && !(o.resume && own_options)) {
    throw core::InputError::Message(o.out, "already holds a pool (manifest.json); choose another --out");
  }
  std::vector<CandidateRecord> finished;
  const bool has_run = fs::exists(options_file) || fs::exists(lines_file);
  if (has_run) {
    if (!o.resume) {
      throw core::InputError::Message(
          o.out, "holds an unfinished generation; use --resume to continue it (same options)");
    }
    if (!own_options) {
      throw core::InputError::Message(o.out, "holds a generation with other options; choose another --out");
    }
    if (fs::exists(lines_file)) finished = load_candidates(lines_file);
    std::string text;
    for (const CandidateRecord& r : finished) text += core::canonical_json(to_json(r)) + "\n";
    core::write_file_atomically(lines_file, text);
    return finished;
  }
  fs::create_directories(dir);
  core::write_file_atomically(options_file, core::pretty_json(generator) + "\n");
  return finished;
}

}  // namespace

core::Json to_json(const CandidateRecord& r) {
  return {{"task", r.task},
          {"candidate", r.index},
          {"seed", r.seed},
          {"hash", r.hash},
          {"failed", r.failed ? core::Json(std::string(to_string(*r.failed))) : core::Json(nullptr)},
          {"reason", r.reason}};
}

CandidateRecord candidate_from_json(const core::Json& json, std::string_view source) {
  const std::string where(source);
  CandidateRecord r;
  r.task = core::json_string(core::json_member(json, "task", where), where + " (task)");
  const core::Json& index = core::json_member(json, "candidate", where);
  const core::Json& seed = core::json_member(json, "seed", where);
  if (!index.is_number_unsigned() || !seed.is_number_unsigned()) {
    throw core::InputError(where, "unsigned candidate and seed", index.dump() + ", " + seed.dump());
  }
  r.index = index.get<size_t>();
  r.seed = seed.get<uint64_t>();
  r.hash = core::json_string(core::json_member(json, "hash", where), where + " (hash)");
  const core::Json& failed = core::json_member(json, "failed", where);
  if (!failed.is_null()) {
    r.failed = filter_from_name(core::json_string(failed, where + " (failed)"));
    if (!r.failed) throw core::InputError(where + " (failed)", "a filter name", failed.dump());
  }
  r.reason = core::json_string(core::json_member(json, "reason", where), where + " (reason)");
  return r;
}

core::Json generator_json(const GenerateOptions& o, const std::vector<std::string>& task_names) {
  core::Json tasks = core::Json::array();
  for (size_t i = 0; i < o.scripts.size(); ++i) {
    tasks.push_back({{"task", task_names.at(i)}, {"script", o.scripts[i]}});
  }
  return {{"pool_version", kPoolVersion},
          {"seed", o.seed},
          {"robot", o.robot},
          {"candidates_per_task", o.candidates},
          {"splits", {{"adapt", o.splits.adapt}, {"eval", o.splits.eval}, {"test", o.splits.test}}},
          {"executable_by", o.filters.executable_by},
          {"tasks", tasks}};
}

CandidateRecord judge_candidate(const script::Scenario& scenario, const std::string& task, size_t index,
                                uint64_t seed, std::string_view robot, const FilterOptions& filters) {
  CandidateRecord r;
  r.task = task;
  r.index = index;
  r.seed = candidate_seed(seed, task, index);
  const script::EpisodeSpec spec = script::sample(scenario, r.seed, robot);
  r.hash = script::spec_hash(spec);
  const Verdict verdict = validate_candidate(spec, filters);
  r.failed = verdict.failed;
  r.reason = verdict.reason;
  return r;
}

core::Json to_json(const GenerationReport& report) {
  const auto row = [](const TaskReport& t) {
    core::Json passed = core::Json::object();
    core::Json examples = core::Json::object();
    for (size_t k = 0; k < kNumFilters; ++k) {
      passed[std::string(to_string(kFilters[k]))] = t.passed[k];
      if (!t.example[k].empty()) examples[std::string(to_string(kFilters[k]))] = t.example[k];
    }
    return core::Json{{"task", t.task},           {"script", t.script},
                      {"candidates", t.candidates}, {"passed", passed},
                      {"validated", t.validated},   {"yield", t.yield()},
                      {"first_rejection", examples}};
  };
  core::Json tasks = core::Json::array();
  for (const TaskReport& t : report.tasks) tasks.push_back(row(t));
  core::Json filters = core::Json::array();
  for (const Filter f : kFilters) filters.push_back(std::string(to_string(f)));
  const core::Json constants = {
      {"reach_joint_margin_rad", kReachJointMargin},
      {"reach_position_tolerance_m", kReachPositionTolerance},
      {"reach_rotation_tolerance_rad", kReachRotationTolerance},
      {"place_clearance_m", kPlaceClearance},
      {"penetration_tolerance_m", kPenetrationTolerance},
      {"hand_table_tolerance_m", kHandTableTolerance},
      {"forearm_table_tolerance", "capsule radius"},
      {"plan_fps", kPlanFps},
      {"cue_region_radius_m", kCueRegionRadius},
      {"label_still_speed_mps", kLabelStillSpeed},
      {"image_margin", kImageMargin},
      {"cue_image_size_px", kCueImageSize},
      {"min_cue_hand_px", kMinCueHandPixels},
      {"min_key_object_px", kMinKeyObjectPixels},
      {"min_pointed_separation_px", kMinPointedSeparationPixels},
      {"at_rest_policy", std::string(kAtRestPolicy)}};
  return {{"generator", report.generator}, {"filters", filters}, {"constants", constants},
          {"tasks", tasks},                {"total", row(report.total)}};
}

std::string report_markdown(const GenerationReport& report) {
  std::ostringstream md;
  md << "# Generation report (pool version " << kPoolVersion << ")\n\n";
  md << "Candidates left after each filter (in pipeline order), validated episodes and yield.\n"
     << "Seed " << report.generator.value("seed", core::Json(0)).dump() << ", "
     << report.generator.value("candidates_per_task", core::Json(0)).dump()
     << " candidates per task, executable by `"
     << report.generator.value("executable_by", core::Json("")).get<std::string>() << "`"
     << (report.generator.value("executable_by", core::Json("")) == "none"
             ? std::string(" (no rollout: neither executable nor at_rest run)")
             : fmt::format(", the person never touching the robot at rest (`{}`)", kAtRestPolicy))
     << ".\n\n";
  md << "| task | candidates |";
  for (const Filter f : kFilters) md << ' ' << to_string(f) << " |";
  md << " validated | yield |\n|---|---:|";
  for (size_t k = 0; k < kNumFilters; ++k) md << "---:|";
  md << "---:|---:|\n";
  const auto row = [&](const TaskReport& t) {
    md << "| " << t.task << " | " << t.candidates << " |";
    for (size_t k = 0; k < kNumFilters; ++k) md << ' ' << t.passed[k] << " |";
    md << ' ' << t.validated << " | " << fmt::format("{:.1f} %", 100 * t.yield()) << " |\n";
  };
  for (const TaskReport& t : report.tasks) row(t);
  row(report.total);
  md << "\nFirst rejection of each filter, per task:\n\n";
  for (const TaskReport& t : report.tasks) {
    for (size_t k = 0; k < kNumFilters; ++k) {
      if (!t.example[k].empty()) md << "- " << t.task << ", " << to_string(kFilters[k]) << ": " << t.example[k] << "\n";
    }
  }
  return md.str();
}

GenerationReport generate(const GenerateOptions& o) {
  // Bad options first, before anything is written.
  if (o.scripts.empty()) throw core::InputError("--tasks", "at least one task", "none");
  if (o.threads <= 0) throw core::InputError("--threads", "a positive number", std::to_string(o.threads));
  try {
    model::robot_by_name(o.robot);
  } catch (const core::InputError& e) {
    throw core::InputError("--robot", e.expected(), e.got());
  }
  if (o.splits.adapt == 0 || o.splits.eval == 0) {
    throw core::InputError("--splits", "adapt and eval sizes > 0",
                           std::to_string(o.splits.adapt) + " and " + std::to_string(o.splits.eval));
  }
  if (o.candidates < o.splits.total()) {
    throw core::InputError::Message(
        "--candidates",
        fmt::format("{} per task cannot fill the splits ({} adapt + {} eval + {} test = {}): {} missing",
                    o.candidates, o.splits.adapt, o.splits.eval, o.splits.test, o.splits.total(),
                    o.splits.total() - o.candidates));
  }
  if (o.filters.executable_by != "none") policy::make_policy(o.filters.executable_by);
  std::vector<script::Scenario> scenarios;
  std::vector<std::string> names;
  for (const std::string& file : o.scripts) {
    scenarios.push_back(script::load_scenario(core::resolve_data_path(file).string()));
    names.push_back(scenarios.back().task);
  }
  for (size_t i = 0; i < names.size(); ++i) {
    for (size_t j = 0; j < i; ++j) {
      if (names[i] == names[j]) {
        throw core::InputError::Message("--tasks", "task '" + names[i] + "' is given twice");
      }
    }
  }
  const core::Json generator = generator_json(o, names);
  // Every (task, candidate) of the generation (a shard's: every N-th), and how to judge one.
  std::vector<std::pair<size_t, size_t>> jobs;
  for (size_t t = 0; t < names.size(); ++t) {
    for (size_t i = 0; i < o.candidates; ++i) {
      if (!o.shard || o.shard->owns(t * o.candidates + i)) jobs.emplace_back(t, i);
    }
  }
  const auto judge = [&](size_t job) {
    const auto [t, i] = jobs[job];
    return judge_candidate(scenarios[t], names[t], i, o.seed, o.robot, o.filters);
  };
  // Under mpirun the ranks other than 0 only judge the candidates rank 0 hands them
  // (eval/ranks.h), and return no report.
  const eval::Ranks ranks = eval::mpi_ranks();
  if (ranks.distributed() && ranks.rank != 0) {
    eval::serve_jobs(o.threads, [&](size_t job, int) { return core::canonical_json(to_json(judge(job))); });
    return GenerationReport{};
  }
  eval::ReleaseWorkersOnError release(o.threads);
  const std::vector<CandidateRecord> finished =
      prepare_out(o, options_json(o, generator, names.size() * o.candidates));

  // Judge every candidate not judged before; append each as it finishes.
  std::map<std::string, CandidateRecord> by_key;
  for (const CandidateRecord& r : finished) by_key.emplace(key(r.task, r.index), r);
  std::vector<size_t> todo;  // into jobs
  for (size_t j = 0; j < jobs.size(); ++j) {
    if (by_key.count(key(names[jobs[j].first], jobs[j].second)) == 0) todo.push_back(j);
  }
  const fs::path lines_file = fs::path(o.out) / "candidates.jsonl";
  std::ofstream lines(lines_file, std::ios::app | std::ios::binary);
  const auto start = std::chrono::steady_clock::now();
  size_t done = 0, validated = 0;
  for (const CandidateRecord& r : finished) validated += r.failed ? 0 : 1;
  const size_t all = o.shard ? eval::shard_share(names.size() * o.candidates, *o.shard) : names.size() * o.candidates;
  const auto judged = [&](const CandidateRecord& r) {
    lines << core::canonical_json(to_json(r)) << "\n" << std::flush;
    by_key.emplace(key(r.task, r.index), r);
    ++done;
    validated += r.failed ? 0 : 1;
    if (!o.progress) return;
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double rate = elapsed > 0 ? static_cast<double>(done) / elapsed : 0;
    const double eta = rate > 0 ? static_cast<double>(todo.size() - done) / rate : 0;
    std::fprintf(stderr, "\rhribench generate: %zu/%zu candidates (%zu resumed), %zu validated, %.2f/s, ETA %.0f s ",
                 done + finished.size(), all, finished.size(), validated, rate, eta);
    std::fflush(stderr);
  };
  if (ranks.distributed()) {
    release.disarm();
    eval::hand_out_jobs(todo, o.threads, [] { return false; }, [&](size_t job, std::string_view line) {
      const auto [t, i] = jobs[todo[job]];
      const std::string where = fmt::format("candidate {} of {}", i, names[t]);
      judged(candidate_from_json(core::parse_json(line, where), where));
    });
  } else {
    run_parallel(todo.size(), o.threads, [&](size_t job) { return judge(todo[job]); },
                 [&](size_t, const CandidateRecord& r) { judged(r); });
  }
  lines.close();
  if (o.progress && !todo.empty()) std::fprintf(stderr, "\n");

  // The report, in (task, candidate) order.
  GenerationReport report;
  report.generator = generator;
  if (o.shard) return report;  // a shard's candidates are split with the others' (merge_generation)
  report.total.task = "all";
  std::vector<std::vector<const CandidateRecord*>> valid(names.size());
  for (size_t t = 0; t < names.size(); ++t) {
    TaskReport row;
    row.task = names[t];
    row.script = o.scripts[t];
    for (size_t i = 0; i < o.candidates; ++i) {
      const CandidateRecord& r = by_key.at(key(names[t], i));
      ++row.candidates;
      const size_t failed_at = r.failed ? static_cast<size_t>(*r.failed) : kNumFilters;
      for (size_t k = 0; k < failed_at; ++k) ++row.passed[k];
      if (r.failed && row.example[failed_at].empty()) {
        row.example[failed_at] = fmt::format("candidate {}: {}", i, r.reason);
      }
      if (!r.failed) valid[t].push_back(&r);
    }
    row.validated = valid[t].size();
    report.total.candidates += row.candidates;
    report.total.validated += row.validated;
    for (size_t k = 0; k < kNumFilters; ++k) report.total.passed[k] += row.passed[k];
    report.tasks.push_back(row);
  }
  std::string missing;
  for (const TaskReport& t : report.tasks) {
    if (t.validated < o.splits.total()) {
      missing += fmt::format("{}{} has {} validated of {} needed ({} missing)", missing.empty() ? "" : "; ",
                             t.task, t.validated, o.splits.total(), o.splits.total() - t.validated);
    }
  }
  if (!missing.empty()) {
    core::write_file_atomically(fs::path(o.out) / "report.md", report_markdown(report));
    throw core::InputError::Message("--candidates", "too few validated episodes to fill the splits: " +
                                                        missing + "; generate again with more candidates");
  }

  // Splits, episode files and the manifest.
  Manifest manifest;
  manifest.generator = generator;
  for (size_t t = 0; t < names.size(); ++t) {
    const std::vector<Split> splits = assign_splits(valid[t].size(), o.seed, names[t], o.splits);
    const fs::path dir = fs::path(o.out) / "episodes" / names[t];
    fs::create_directories(dir);
    for (size_t k = 0; k < valid[t].size(); ++k) {
      const CandidateRecord& r = *valid[t][k];
      const script::EpisodeSpec spec = script::sample(scenarios[t], r.seed, o.robot);
      // A resumed generation whose scripts changed since the interruption: refuse, not mix.
      if (script::spec_hash(spec) != r.hash) {
        throw core::InputError::Message(
            o.scripts[t], fmt::format("candidate {} (seed {}) samples another episode than when it was "
                                      "judged; the script changed since the generation began: "
                                      "generate again without --resume", r.index, r.seed));
      }
      core::write_file_atomically(dir / fmt::format("c{:04d}.json", r.index), script::spec_to_text(spec));
      manifest.episodes.push_back(PoolEntry{names[t], o.scripts[t], splits[k], r.index, r.seed, r.hash});
    }
  }
  core::write_file_atomically(fs::path(o.out) / "report.json", core::pretty_json(to_json(report)) + "\n");
  core::write_file_atomically(fs::path(o.out) / "report.md", report_markdown(report));
  core::write_file_atomically(fs::path(o.out) / "manifest.json", core::pretty_json(to_json(manifest)) + "\n");
  return report;
}

bool holds_generation(const std::string& dir) { return fs::is_regular_file(fs::path(dir) / "candidates.jsonl"); }

GenerationReport merge_generation(const std::string& out, const std::vector<std::string>& dirs) {
  std::vector<eval::ShardOptions> folders;
  for (const std::string& dir : dirs) {
    const fs::path options = fs::path(dir) / "options.json";
    if (!holds_generation(dir) || !fs::is_regular_file(options)) {
      throw core::InputError::Message(dir, "holds no generation (options.json and candidates.jsonl)");
    }
    folders.push_back({dir, core::read_json_file(options.string())});
  }
  const std::vector<size_t> order = eval::shard_order(folders);
  core::Json generator = eval::merged_options(folders[order.front()].options);
  generator.erase("code");

  // The options one generate would have run with.
  GenerateOptions o;
  const std::string where = folders[order.front()].dir + "/options.json";
  try {
    for (const core::Json& task : generator.at("tasks")) o.scripts.push_back(task.at("script").get<std::string>());
    o.candidates = generator.at("candidates_per_task").get<size_t>();
    o.seed = generator.at("seed").get<uint64_t>();
    o.robot = generator.at("robot").get<std::string>();
    o.splits = {generator.at("splits").at("adapt").get<size_t>(), generator.at("splits").at("eval").get<size_t>(),
                generator.at("splits").at("test").get<size_t>()};
    o.filters.executable_by = generator.at("executable_by").get<std::string>();
  } catch (const core::Json::exception&) {
    throw core::InputError(where, "the generator options of hribench generate", generator.dump());
  }
  std::vector<std::string> names;
  for (const core::Json& task : generator.at("tasks")) names.push_back(task.value("task", ""));
  if (generator_json(o, names) != generator) {
    throw core::InputError(where, fmt::format("a generation of pool version {}", kPoolVersion),
                           generator.value("pool_version", core::Json()).dump());
  }

  // Each shard holds exactly its candidates.
  const size_t jobs = names.size() * o.candidates;
  std::map<std::string, CandidateRecord> by_key;
  for (size_t i = 0; i < order.size(); ++i) {
    const std::string& dir = folders[order[i]].dir;
    const eval::Shard shard{static_cast<int>(i), static_cast<int>(order.size())};
    size_t held = 0;
    for (const CandidateRecord& r : load_candidates(fs::path(dir) / "candidates.jsonl")) {
      const auto task = std::find(names.begin(), names.end(), r.task);
      const size_t job = static_cast<size_t>(task - names.begin()) * o.candidates + r.index;
      if (task == names.end() || r.index >= o.candidates || !shard.owns(job) ||
          !by_key.emplace(key(r.task, r.index), r).second) {
        throw core::InputError::Message(dir, fmt::format("holds candidate {} of {}, which is not shard {}'s (or is there twice)",
                                                         r.index, r.task, eval::to_string(shard)));
      }
      ++held;
    }
    if (held != eval::shard_share(jobs, shard)) {
      throw core::InputError::Message(
          dir, fmt::format("holds {} of its {} candidates; finish it with generate --shard {} --resume", held,
                           eval::shard_share(jobs, shard), eval::to_string(shard)));
    }
  }

  // OUT as an interrupted generation with every candidate judged; generate splits it.
  fs::create_directories(out);
  core::write_file_atomically(fs::path(out) / "options.json", core::pretty_json(generator) + "\n");
  std::string lines;
  for (const std::string& task : names) {
    for (size_t i = 0; i < o.candidates; ++i) lines += core::canonical_json(to_json(by_key.at(key(task, i)))) + "\n";
  }
  core::write_file_atomically(fs::path(out) / "candidates.jsonl", lines);
  o.out = out;
  o.resume = true;
  o.progress = false;
  return generate(o);
}

}  // namespace hribench::gen

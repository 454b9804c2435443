#include "eval/report.h"

#include <fmt/format.h>
#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <map>
#include <optional>
#include <type_traits>

#include "core/errors.h"
#include "core/files.h"
#include "core/json.h"
#include "core/version.h"
#include "eval/report_html.h"
#include "model/robot.h"

namespace hribench::eval {
namespace {

using nlohmann::json;

json optional_json(const std::optional<double>& v) { return v ? json(*v) : json(nullptr); }

// Typed reads from a JSON object; every problem is a core::InputError at `where.key`.
class Fields {
 public:
  Fields(const json& j, std::string where) : j_(j), where_(std::move(where)) {
    if (!j_.is_object()) throw core::InputError(where_, "an object", j_.type_name());
  }
  const json& at(const std::string& key) const {
    const auto it = j_.find(key);
    if (it == j_.end()) throw core::InputError(where_ + "." + key, "a value", "nothing");
    return *it;
  }
  double number(const std::string& key) const {
    const json& v = at(key);
    if (!v.is_number()) throw core::InputError(where_ + "." + key, "a number", v.type_name());
    return v.get<double>();
  }
  std::optional<double> optional_number(const std::string& key) const {
    if (at(key).is_null()) return std::nullopt;
    return number(key);
  }
  bool boolean(const std::string& key) const {
    const json& v = at(key);
    if (!v.is_boolean()) throw core::InputError(where_ + "." + key, "true or false", v.type_name());
    return v.get<bool>();
  }
  std::string string(const std::string& key) const {
    const json& v = at(key);
    if (!v.is_string()) throw core::InputError(where_ + "." + key, "a string", v.type_name());
    return v.get<std::string>();
  }
  uint64_t unsigned_integer(const std::string& key) const {
    const json& v = at(key);
    if (!v.is_number_unsigned()) {
      throw core::InputError(where_ + "." + key, "a non-negative integer", v.dump());
    }
    return v.get<uint64_t>();
  }
  const json& array(const std::string& key) const {
    const json& v = at(key);
    if (!v.is_array()) throw core::InputError(where_ + "." + key, "an array", v.type_name());
    return v;
  }
  std::string where(const std::string& key) const { return where_ + "." + key; }

 private:
  const json& j_;
  std::string where_;
};

FailureLabel label_from_string(const std::string& name, const std::string& where) {
  for (int i = 0; i < kNumFailureLabels; ++i) {
    const auto label = static_cast<FailureLabel>(i);
    if (to_string(label) == name) return label;
  }
  throw core::InputError(where, "a failure label (invalid, policy_error, ..., timeout)",
                         "'" + name + "'");
}

// The robots of a run's episodes, sorted, each once (provenance: derived, not stored).
std::vector<std::string> run_robots(const RunResults& run) {
  std::vector<std::string> names;
  for (const EpisodeResult& r : run.episodes) names.push_back(r.robot);
  std::sort(names.begin(), names.end());
  names.erase(std::unique(names.begin(), names.end()), names.end());
  return names;
}

}  // namespace

RunInfo current_run_info(std::string renderer, nlohmann::json options,
                         const MetricConstants& constants) {
  return RunInfo{std::string(core::version()), std::string(core::git_hash()), mj_versionString(),
                 std::move(renderer), std::move(options), constants};
}

json episode_to_json(const EpisodeResult& r) {
  const EpisodeMetrics& m = r.metrics;
  json cues = json::array();
  for (const CueResult& c : m.cues) {
    cues.push_back({{"name", c.name}, {"cue_time", c.cue_time},
                    {"response_time", optional_json(c.response_time)},
                    {"responded", c.responded}, {"latency", c.latency}, {"premature", c.premature}});
  }
  json syncs = json::array();
  for (const SyncResult& s : m.syncs) {
    syncs.push_back({{"name", s.name}, {"human_time", s.human_time},
                     {"robot_time", optional_json(s.robot_time)}, {"score", s.score}});
  }
  json orders = json::array();
  for (const OrderResult& o : m.orders) {
    orders.push_back(
        {{"description", o.description}, {"applicable", o.applicable}, {"satisfied", o.satisfied}});
  }
  json labels = json::array();
  for (const FailureLabel l : m.labels) labels.push_back(std::string(to_string(l)));
  return json{
      {"task", r.task},
      {"task_id", r.task_id},
      {"variant", r.variant},
      {"role", r.role},
      {"policy", r.policy},
      {"robot", r.robot},
      {"spec_hash", r.spec_hash},
      {"seed", r.seed},
      {"status", std::string(core::to_string(r.status))},
      {"status_reason", r.status_reason},
      {"success", m.success},
      {"success_since", optional_json(m.success_since)},
      {"completion_time", m.completion_time},
      {"idle_ratio", optional_json(m.idle_ratio)},
      {"response_latency", optional_json(m.response_latency)},
      {"tsync", optional_json(m.tsync)},
      {"order_compliance", optional_json(m.order_compliance)},
      {"human_contact", m.human_contact},
      {"environment_collision", m.environment_collision},
      {"collision_free", m.collision_free},
      {"max_human_force", m.max_human_force},
      {"above_quasi_static", m.above_quasi_static},
      {"critical_contact", m.critical_contact},
      {"monitored_time", m.monitored_time},
      {"violation_time", m.violation_time},
      {"hcs", m.hcs},
      {"cir", optional_json(m.cir)},
      {"dsr", optional_json(m.dsr)},
      {"r_idle", optional_json(m.r_idle)},
      {"h_idle", optional_json(m.h_idle)},
      {"c_act", optional_json(m.c_act)},
      {"f_del", optional_json(m.f_del)},
      {"cues", cues},
      {"syncs", syncs},
      {"orders", orders},
      {"labels", labels},
      {"primary_label", m.primary_label ? json(std::string(to_string(*m.primary_label)))
                                        : json(nullptr)},
  };
}

EpisodeResult episode_from_json(const json& j, const std::string& where) {
  const Fields f(j, where);
  EpisodeResult r;
  r.task = f.string("task");
  // Results written before episodes named their task id and variant leave them empty.
  r.task_id = j.contains("task_id") ? f.string("task_id") : std::string();
  r.variant = j.contains("variant") ? f.string("variant") : std::string();
  r.role = f.string("role");
  r.policy = f.string("policy");
  // Results written before episodes named their robot are all the Panda's.
  r.robot = j.contains("robot") ? f.string("robot") : std::string(model::kDefaultRobot);
  r.spec_hash = f.string("spec_hash");
  r.seed = f.unsigned_integer("seed");
  r.status = core::episode_status_from_string(f.string("status"), f.where("status"));
  r.status_reason = f.string("status_reason");
  EpisodeMetrics& m = r.metrics;
  m.success = f.boolean("success");
  m.success_since = f.optional_number("success_since");
  m.completion_time = f.number("completion_time");
  m.idle_ratio = f.optional_number("idle_ratio");
  m.response_latency = f.optional_number("response_latency");
  m.tsync = f.optional_number("tsync");
  m.order_compliance = f.optional_number("order_compliance");
  m.human_contact = f.boolean("human_contact");
  m.environment_collision = f.boolean("environment_collision");
  m.collision_free = f.boolean("collision_free");
  m.max_human_force = f.number("max_human_force");
  m.above_quasi_static = f.boolean("above_quasi_static");
  m.critical_contact = f.boolean("critical_contact");
  m.monitored_time = f.number("monitored_time");
  m.violation_time = f.number("violation_time");
  m.hcs = f.number("hcs");
  m.cir = f.optional_number("cir");
  m.dsr = f.optional_number("dsr");
  m.r_idle = f.optional_number("r_idle");
  m.h_idle = f.optional_number("h_idle");
  m.c_act = f.optional_number("c_act");
  m.f_del = f.optional_number("f_del");
  const json& cues = f.array("cues");
  for (size_t i = 0; i < cues.size(); ++i) {
    const Fields c(cues[i], fmt::format("{}[{}]", f.where("cues"), i));
    // Results written before premature go cues were marked have none.
    m.cues.push_back({c.string("name"), c.number("cue_time"), c.optional_number("response_time"),
                      c.boolean("responded"), c.number("latency"),
                      cues[i].contains("premature") && c.boolean("premature")});
  }
  const json& syncs = f.array("syncs");
  for (size_t i = 0; i < syncs.size(); ++i) {
    const Fields s(syncs[i], fmt::format("{}[{}]", f.where("syncs"), i));
    m.syncs.push_back({s.string("name"), s.number("human_time"), s.optional_number("robot_time"),
                       s.number("score")});
  }
  const json& orders = f.array("orders");
  for (size_t i = 0; i < orders.size(); ++i) {
    const Fields o(orders[i], fmt::format("{}[{}]", f.where("orders"), i));
    m.orders.push_back({o.string("description"), o.boolean("applicable"), o.boolean("satisfied")});
  }
  const json& labels = f.array("labels");
  for (size_t i = 0; i < labels.size(); ++i) {
    const std::string w = fmt::format("{}[{}]", f.where("labels"), i);
    if (!labels[i].is_string()) throw core::InputError(w, "a string", labels[i].type_name());
    m.labels.push_back(label_from_string(labels[i].get<std::string>(), w));
  }
  if (!f.at("primary_label").is_null()) {
    m.primary_label = label_from_string(f.string("primary_label"), f.where("primary_label"));
  }
  return r;
}

void append_episode_line(const std::filesystem::path& path, const EpisodeResult& episode) {
  std::ofstream out(path, std::ios::binary | std::ios::app);
  out << episode_to_json(episode).dump() << '\n';
  out.flush();
  if (!out) throw core::InputError::Message(path.string(), "cannot append to the episode file");
}

std::vector<EpisodeResult> load_episode_lines(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw core::InputError::Message(path.string(), "cannot open the episode file");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::vector<EpisodeResult> episodes;
  size_t start = 0;
  int line = 0;
  while (start < text.size()) {
    const size_t end = text.find('\n', start);
    if (end == std::string::npos) break;  // an unfinished last line
    ++line;
    const std::string where = fmt::format("{}:{}", path.string(), line);
    const json j = core::parse_json(std::string_view(text).substr(start, end - start), path.string(),
                                    static_cast<size_t>(line));
    episodes.push_back(episode_from_json(j, where));
    start = end + 1;
  }
  return episodes;
}

namespace {

json estimate_json(const std::optional<Estimate>& e) {
  if (!e) return nullptr;
  return json{{"value", e->value}, {"low", e->low}, {"high", e->high}, {"n", e->n}};
}

json summary_json(const GroupSummary& s) {
  json j{{"group", s.group}, {"policy", s.policy}, {"episodes", s.episodes}};
  if (!s.task_id.empty()) j["task_id"] = s.task_id;
  const std::pair<const char*, const std::optional<Estimate>*> estimates[] = {
      {"csr", &s.csr},     {"ct", &s.ct},       {"ct_success", &s.ct_success}, {"ir", &s.ir},
      {"rsp", &s.rsp},     {"tsync", &s.tsync}, {"oc", &s.oc},                 {"cfr", &s.cfr},
      {"hcs", &s.hcs},     {"cir", &s.cir},     {"dsr", &s.dsr},               {"r_idle", &s.r_idle},
      {"h_idle", &s.h_idle}, {"c_act", &s.c_act}, {"f_del", &s.f_del}};
  for (const auto& [name, e] : estimates) j[name] = estimate_json(*e);
  j["rsp_median"] = optional_json(s.rsp_median);
  j["safety"] = optional_json(s.safety);
  j["critical_contacts"] = s.critical_contacts;
  j["failures"] = s.failures;  // primary label -> episodes
  return j;
}

}  // namespace

json aggregates_to_json(const RunResults& run) {
  json aggregates = json::object();
  for (const auto& [level, by] : {std::pair{"task", GroupBy::kTask}, std::pair{"role", GroupBy::kRole},
                                  std::pair{"overall", GroupBy::kOverall}}) {
    json rows = json::array();
    for (const GroupSummary& s : summarize(run.episodes, by, run.info.constants)) {
      rows.push_back(summary_json(s));
    }
    aggregates[level] = std::move(rows);
  }
  return aggregates;
}

json results_to_json(const RunResults& run) {
  json constants = json::object();
  visit_constants(run.info.constants, [&](const char* name, const auto& value, const char*) {
    constants[name] = value;
  });
  json episodes = json::array();
  for (const EpisodeResult& r : run.episodes) episodes.push_back(episode_to_json(r));
  return json{
      {"format", "hribench-results"},
      {"version", kResultsFormatVersion},
      {"provenance",
       {{"hribench_version", run.info.hribench_version},
        {"git_hash", run.info.git_hash},
        {"mujoco_version", run.info.mujoco_version},
        {"renderer", run.info.renderer},
        {"robots", run_robots(run)}}},
      {"options", run.info.options},
      {"metric_constants", constants},
      {"aggregates", aggregates_to_json(run)},
      {"episodes", episodes},
  };
}

namespace {

// What a metric constant read back from a results file may be: the aggregation divides by,
// indexes with and allocates for these, so a value outside is bad input, not a bug.
struct ConstantRange {
  double low;
  bool open_low;
  double high;
  const char* text;
};
ConstantRange constant_range(std::string_view name) {
  if (name == "confidence") return {0.0, true, 1.0 - 1e-12, "a level in (0, 1)"};
  if (name == "bootstrap_resamples") return {1.0, false, 1e6, "a whole count from 1 to 1000000"};
  return {0.0, false, 1e6, "a number in [0, 1e6]"};
}

}  // namespace

RunResults results_from_json(const json& j, const std::string& where) {
  const Fields f(j, where);
  if (f.string("format") != "hribench-results") {
    throw core::InputError(f.where("format"), "hribench-results", f.string("format"));
  }
  if (f.number("version") != kResultsFormatVersion) {
    throw core::InputError(f.where("version"), std::to_string(kResultsFormatVersion),
                           f.at("version").dump());
  }
  RunResults run;
  const Fields p(f.at("provenance"), f.where("provenance"));
  run.info.hribench_version = p.string("hribench_version");
  run.info.git_hash = p.string("git_hash");
  run.info.mujoco_version = p.string("mujoco_version");
  run.info.renderer = p.string("renderer");
  run.info.options = f.at("options");
  const Fields c(f.at("metric_constants"), f.where("metric_constants"));
  visit_constants(run.info.constants, [&](const char* name, auto& value, const char*) {
    using Value = std::remove_reference_t<decltype(value)>;
    if constexpr (std::is_same_v<Value, uint64_t>) {
      value = c.unsigned_integer(name);
    } else {
      const double x = c.number(name);
      const ConstantRange range = constant_range(name);
      const bool whole = !std::is_integral_v<Value> || x == std::floor(x);
      if (!whole || !(range.open_low ? x > range.low : x >= range.low) || !(x <= range.high)) {
        throw core::InputError(c.where(name), range.text, fmt::format("{}", x));
      }
      value = static_cast<Value>(x);
    }
  });
  const json& episodes = f.array("episodes");
  for (size_t i = 0; i < episodes.size(); ++i) {
    run.episodes.push_back(episode_from_json(episodes[i], fmt::format("{}[{}]", f.where("episodes"), i)));
  }
  return run;
}

namespace {

std::string cell(const std::optional<Estimate>& e) {
  if (!e) return "—";
  return fmt::format("{:.2f} [{:.2f}, {:.2f}]", e->value, e->low, e->high);
}

std::string cell(const std::optional<double>& v) { return v ? fmt::format("{:.2f}", *v) : "—"; }

std::string headline_row(const GroupSummary& s) {
  return fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} |\n", group_label(s), s.policy, cell(s.csr),
                     cell(s.ct), cell(s.rsp), cell(s.tsync), cell(s.oc), cell(s.safety));
}

std::string headline_header(std::string_view first_column) {
  return fmt::format(
      "| {} | Policy | CSR↑ | CT↓ (s) | Rsp↓ (s) | TSync↑ | OC↑ | Safety↑ |\n"
      "|---|---|---|---|---|---|---|---|\n",
      first_column);
}

std::vector<GroupSummary> roles_then_overall(const RunResults& run) {
  std::vector<GroupSummary> rows = summarize(run.episodes, GroupBy::kRole, run.info.constants);
  for (GroupSummary& s : summarize(run.episodes, GroupBy::kOverall, run.info.constants)) {
    rows.push_back(std::move(s));
  }
  return rows;
}

// The main failure labels of a group: its two most frequent primary labels ("premature 20,
// collision 6"), or "—" when no episode failed.
std::string main_failures(const GroupSummary& s) {
  std::vector<std::pair<std::string, int>> labels(s.failures.begin(), s.failures.end());
  std::stable_sort(labels.begin(), labels.end(),
                   [](const auto& a, const auto& b) { return a.second > b.second; });
  std::string text;
  for (size_t i = 0; i < labels.size() && i < 2; ++i) {
    text += fmt::format("{}{} {}", i ? ", " : "", labels[i].first, labels[i].second);
  }
  return text.empty() ? "—" : text;
}

// One row per task: CSR of each policy, critical contacts of each, and the main failure labels
// of each (the README's per-task table).
std::string task_table(const RunResults& run) {
  const std::vector<GroupSummary> rows = summarize(run.episodes, GroupBy::kTask, run.info.constants);
  std::vector<std::string> policies;
  std::vector<const GroupSummary*> tasks;  // the first policy's row of each task, in order
  for (const GroupSummary& s : rows) {
    if (std::find(policies.begin(), policies.end(), s.policy) == policies.end()) policies.push_back(s.policy);
    if (std::none_of(tasks.begin(), tasks.end(), [&](const GroupSummary* t) { return t->group == s.group; })) {
      tasks.push_back(&s);
    }
  }
  std::sort(tasks.begin(), tasks.end(), [&](const GroupSummary* a, const GroupSummary* b) {
    const auto position = [&](const GroupSummary* t) {
      return std::find_if(rows.begin(), rows.end(), [&](const GroupSummary& r) { return r.group == t->group; }) -
             rows.begin();
    };
    return position(a) < position(b);
  });
  std::string policy_list;
  for (const std::string& p : policies) policy_list += (policy_list.empty() ? "" : " / ") + p;
  std::string md = "| Task |";
  for (const std::string& p : policies) md += " " + p + " |";
  md += " critical contacts (" + policy_list + ") | main failure labels (" + policy_list + ") |\n|---|";
  for (size_t i = 0; i < policies.size(); ++i) md += "---:|";
  md += "---|---|\n";
  for (const GroupSummary* task : tasks) {
    std::string csr;
    std::string contacts;
    std::string failures;
    for (const std::string& p : policies) {
      const auto it = std::find_if(rows.begin(), rows.end(), [&](const GroupSummary& r) {
        return r.group == task->group && r.policy == p;
      });
      const bool present = it != rows.end();
      csr += " " + (present ? cell(it->csr ? std::optional<double>(it->csr->value) : std::nullopt) : "—") + " |";
      contacts += (contacts.empty() ? "" : " / ") + (present ? std::to_string(it->critical_contacts) : "—");
      failures += (failures.empty() ? "" : " / ") + (present ? main_failures(*it) : "—");
    }
    md += "| " + group_label(*task) + " |" + csr + " " + contacts + " | " + failures + " |\n";
  }
  return md;
}

}  // namespace

std::string summary_markdown(const RunResults& run, SummaryFor audience) {
  const std::vector<GroupSummary> rows = roles_then_overall(run);
  std::string md = "# HRIBench results\n\n";
  std::string robots;
  for (const std::string& name : run_robots(run)) robots += (robots.empty() ? "" : ", ") + name;
  md += fmt::format("HRIBench {} (git {}), MuJoCo {}, renderer: {}, robot: {}; {} episodes. Options: `{}`.\n\n",
                    run.info.hribench_version, run.info.git_hash, run.info.mujoco_version,
                    run.info.renderer, robots, run.episodes.size(), run.info.options.dump());
  md += "Rates (CSR, CFR, CIR, DSR) with Wilson 95 % intervals; other metrics: mean with "
        "bootstrap 95 % intervals over episodes; — = not applicable.\n\n";
  md += "## Headline\n\n";
  md += headline_header("Role group");
  for (const GroupSummary& s : rows) md += headline_row(s);
  md += "\n## Components\n\n";
  md += "| Role group | Policy | IR↓ | CFR↑ | HCS↑ | CIR↑ | DSR↑ | R-IDLE↓ | H-IDLE↓ | C-ACT↑ | "
        "F-DEL↓ (s) | Rsp median (s) | CT successes (s) |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const GroupSummary& s : rows) {
    md += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n", s.group,
                      s.policy, cell(s.ir), cell(s.cfr), cell(s.hcs), cell(s.cir), cell(s.dsr),
                      cell(s.r_idle), cell(s.h_idle), cell(s.c_act), cell(s.f_del),
                      cell(s.rsp_median), cell(s.ct_success));
  }
  md += "\n## Per task\n\n";
  md += "CSR per task and policy, episodes with a critical contact, and the two most frequent "
        "primary failure labels.\n\n";
  md += task_table(run);
  md += "\n";
  md += headline_header("Task");
  for (const GroupSummary& s : summarize(run.episodes, GroupBy::kTask, run.info.constants)) {
    md += headline_row(s);
  }
  // Failure modes: primary labels of failed episodes, columns for labels that occur.
  md += "\n## Failure modes (primary label of each failed episode)\n\n";
  std::vector<std::string> present;
  for (int i = 0; i < kNumFailureLabels; ++i) {
    const std::string name(to_string(static_cast<FailureLabel>(i)));
    for (const GroupSummary& s : rows) {
      if (s.failures.count(name) && std::find(present.begin(), present.end(), name) == present.end()) {
        present.push_back(name);
      }
    }
  }
  md += "| Role group | Policy | episodes |";
  for (const std::string& name : present) md += " " + name + " |";
  md += "\n|---|---|---|";
  for (size_t i = 0; i < present.size(); ++i) md += "---|";
  md += "\n";
  for (const GroupSummary& s : rows) {
    md += fmt::format("| {} | {} | {} |", s.group, s.policy, s.episodes);
    for (const std::string& name : present) {
      const auto it = s.failures.find(name);
      md += fmt::format(" {} |", it == s.failures.end() ? 0 : it->second);
    }
    md += "\n";
  }
  if (audience == SummaryFor::kTerminal) return md;
  md += "\n## Metric constants\n\n| constant | value | unit |\n|---|---|---|\n";
  for (const NamedConstant& c : constant_table(run.info.constants)) {
    md += fmt::format("| {} | {} | {} |\n", c.name, c.value, c.unit);
  }
  return md;
}

namespace {

constexpr std::pair<const char*, GroupBy> kLevels[] = {
    {"role", GroupBy::kRole}, {"task", GroupBy::kTask}, {"overall", GroupBy::kOverall}};

std::string csv_header() {
  std::string csv = "level,group,task_id,policy,episodes";
  for (const char* name : {"csr", "ct", "ct_success", "ir", "rsp", "tsync", "oc", "cfr", "hcs", "cir",
                           "dsr", "r_idle", "h_idle", "c_act", "f_del"}) {
    csv += fmt::format(",{0},{0}_low,{0}_high", name);
  }
  return csv + ",rsp_median,safety,critical_contacts\n";
}

std::string csv_row(const char* level, const GroupSummary& s) {
  const auto number = [](const std::optional<double>& v) { return v ? fmt::format("{}", *v) : ""; };
  std::string csv = fmt::format("{},{},{},{},{}", level, s.group, s.task_id, s.policy, s.episodes);
  for (const auto* e : {&s.csr, &s.ct, &s.ct_success, &s.ir, &s.rsp, &s.tsync, &s.oc, &s.cfr, &s.hcs,
                        &s.cir, &s.dsr, &s.r_idle, &s.h_idle, &s.c_act, &s.f_del}) {
    csv += *e ? fmt::format(",{},{},{}", (*e)->value, (*e)->low, (*e)->high) : std::string(",,,");
  }
  return csv + "," + number(s.rsp_median) + "," + number(s.safety) + "," +
         std::to_string(s.critical_contacts) + "\n";
}

// A comparison's rows of one run: role groups then overall, or tasks.
std::vector<GroupSummary> compared_rows(const RunResults& run, CompareBy by) {
  return by == CompareBy::kTask ? summarize(run.episodes, GroupBy::kTask, run.info.constants)
                                : roles_then_overall(run);
}

const char* level_of(const GroupSummary& s, CompareBy by) {
  if (by == CompareBy::kTask) return "task";
  return s.group == "overall" ? "overall" : "role";
}

}  // namespace

std::string summary_csv(const RunResults& run) {
  std::string csv = csv_header();
  for (const auto& [level, by] : kLevels) {
    for (const GroupSummary& s : summarize(run.episodes, by, run.info.constants)) csv += csv_row(level, s);
  }
  return csv;
}

std::string compare_markdown(const std::vector<std::pair<std::string, RunResults>>& runs, CompareBy by) {
  std::string md = fmt::format(
      "| Run | {} | Policy | CSR↑ | CT↓ (s) | Rsp↓ (s) | TSync↑ | OC↑ | Safety↑ |\n"
      "|---|---|---|---|---|---|---|---|---|\n",
      by == CompareBy::kTask ? "Task" : "Role group");
  for (const auto& [label, run] : runs) {
    for (const GroupSummary& s : compared_rows(run, by)) md += "| " + label + " " + headline_row(s);
  }
  // Runs scored with different constants are not comparable: say so.
  for (const auto& [label, run] : runs) {
    if (constant_table(run.info.constants) == constant_table(runs.front().second.info.constants)) {
      continue;
    }
    md += fmt::format("\nNote: run {} used different metric constants than run {}.\n", label,
                      runs.front().first);
  }
  return md;
}

std::string compare_csv(const std::vector<std::pair<std::string, RunResults>>& runs, CompareBy by) {
  std::string csv = "run," + csv_header();
  for (const auto& [label, run] : runs) {
    for (const GroupSummary& s : compared_rows(run, by)) csv += label + "," + csv_row(level_of(s, by), s);
  }
  return csv;
}

nlohmann::json compare_json(const std::vector<std::pair<std::string, RunResults>>& runs, CompareBy by) {
  json rows = json::array();
  for (const auto& [label, run] : runs) {
    for (const GroupSummary& s : compared_rows(run, by)) {
      json row = summary_json(s);
      row["run"] = label;
      row["level"] = level_of(s, by);
      rows.push_back(std::move(row));
    }
  }
  return rows;
}

void write_run(const std::filesystem::path& dir, const RunResults& run) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw core::InputError::Message(dir.string(), "cannot create the folder: " + ec.message());
  core::write_file_atomically(dir / "results.json", results_to_json(run).dump(2) + "\n");
  core::write_file_atomically(dir / "summary.md", summary_markdown(run));
  core::write_file_atomically(dir / "summary.csv", summary_csv(run));
  write_report_html(dir, run);
}

RunResults load_run(const std::filesystem::path& path) {
  const std::filesystem::path file =
      std::filesystem::is_directory(path) ? path / "results.json" : path;
  std::ifstream in(file, std::ios::binary);
  if (!in) throw core::InputError::Message(file.string(), "cannot open the results file");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return results_from_json(core::parse_json(text, file.string()), file.string());
}

}  // namespace hribench::eval

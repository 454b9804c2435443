#include "eval/report.h"

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "core/errors.h"
#include "eval/episode_builder.h"

namespace hribench::eval {
namespace {

using testing::EpisodeBuilder;

RunResults sample_run() {
  RunResults run;
  run.info = current_run_info("none", {{"latency", "fixed:200"}, {"episodes", 2}});
  ScenarioContract contract;
  contract.cues.push_back({"stop", "stop.stroke", CueKind::kStop, 1.0, std::nullopt});
  for (int i = 0; i < 4; ++i) {
    EpisodeBuilder b(5.0);
    b.move_x(0.0, 1.5 + 0.3 * i, 0.1).event(1.0, "stop.stroke");
    if (i % 2 == 0) b.predicate("success", 3.0, 5.0);
    b.separation(2.0, 3.0, 0.4 + 0.1 * i, 0.2, 0.2);
    EpisodeLog log = b.log();
    log.task = i < 2 ? "stop_go" : "intrusion_yield";
    log.role = i < 2 ? "instructor" : "intruder";
    log.seed = static_cast<uint64_t>(100 + i);
    run.episodes.push_back(make_result(log, compute_metrics(contract, log)));
    run.episodes.back().task_id = i < 2 ? "I4" : "X1";
    run.episodes.back().variant = i == 1 ? "late_stop" : "";
  }
  return run;
}

// A path unique to this process and test (parallel ctest runs never share one).
std::filesystem::path unique_temp_path(const std::string& name) {
  const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
  return std::filesystem::path(::testing::TempDir()) /
         ("hribench_eval_" + std::string(test->test_suite_name()) + "_" + test->name() + "_" +
          std::to_string(getpid()) + "_" + name);
}

TEST(Report, ProvenanceAndConstantsInResults) {
  const RunResults run = sample_run();
  const nlohmann::json j = results_to_json(run);
  EXPECT_EQ(j["provenance"]["mujoco_version"], mj_versionString());
  EXPECT_EQ(j["provenance"]["renderer"], "none");
  EXPECT_EQ(j["options"]["latency"], "fixed:200");
  EXPECT_EQ(j["metric_constants"]["moving_ee_speed"], 0.02);
  EXPECT_EQ(j["metric_constants"]["still_sustain"], 0.2);
  EXPECT_EQ(j["metric_constants"].size(), constant_table(MetricConstants{}).size());
  EXPECT_EQ(j["episodes"].size(), 4u);
  EXPECT_EQ(j["episodes"][1]["seed"], 101);
  EXPECT_EQ(j["episodes"][1]["primary_label"], "timeout");
  // Every episode names its robot; the provenance lists the run's robots.
  EXPECT_EQ(j["episodes"][1]["robot"], "panda");
  EXPECT_EQ(j["provenance"]["robots"], nlohmann::json::array({"panda"}));
  EXPECT_NE(summary_markdown(run).find("renderer: none, robot: panda; 4 episodes"), std::string::npos);
}

TEST(Report, EpisodesWithoutARobotAreThePandas) {
  nlohmann::json j = episode_to_json(sample_run().episodes[0]);
  j.erase("robot");
  EXPECT_EQ(episode_from_json(j, "e").robot, "panda");
  j["robot"] = 3;
  try {
    episode_from_json(j, "e");
    FAIL();
  } catch (const core::InputError& e) {
    EXPECT_STREQ(e.what(), "e.robot: expected a string, got number");
  }
}

TEST(Report, ResultsRoundTripReaggregateIdentically) {
  const RunResults run = sample_run();
  const RunResults back = results_from_json(nlohmann::json::parse(results_to_json(run).dump()), "r");
  EXPECT_EQ(results_to_json(back), results_to_json(run));
  EXPECT_EQ(summary_markdown(back), summary_markdown(run));
  EXPECT_EQ(summary_csv(back), summary_csv(run));
  ASSERT_EQ(back.episodes.size(), 4u);
  EXPECT_EQ(back.episodes[2].metrics.hcs, run.episodes[2].metrics.hcs);
  EXPECT_EQ(back.episodes[2].metrics.cues[0].response_time, run.episodes[2].metrics.cues[0].response_time);
}

TEST(Report, SummaryTables) {
  const std::string md = summary_markdown(sample_run());
  EXPECT_NE(md.find("| Role group | Policy | CSR↑ | CT↓ (s) | Rsp↓ (s) | TSync↑ | OC↑ | Safety↑ |"),
            std::string::npos);
  EXPECT_NE(md.find("| instructor | noop | 0.50 ["), std::string::npos);
  EXPECT_NE(md.find("| overall | noop | 0.50 ["), std::string::npos);
  EXPECT_NE(md.find("| IR↓ | CFR↑ | HCS↑ | CIR↑ | DSR↑ |"), std::string::npos);
  EXPECT_NE(md.find("| Task | Policy |"), std::string::npos);
  EXPECT_NE(md.find("| I4 stop_go | noop | 0.50 ["), std::string::npos) << md;
  // The README's per-task table: CSR per policy, critical contacts, main failure labels.
  EXPECT_NE(md.find("| Task | noop | critical contacts (noop) | main failure labels (noop) |"), std::string::npos)
      << md;
  EXPECT_NE(md.find("| I4 stop_go | 0.50 | 0 | timeout 1 |"), std::string::npos) << md;
  EXPECT_LT(md.find("| I4 stop_go | 0.50 |"), md.find("| X1 intrusion_yield | 0.50 |"));
  // The terminal's summary leaves the constants table to the file.
  const std::string terminal = summary_markdown(sample_run(), SummaryFor::kTerminal);
  EXPECT_EQ(terminal.find("| still_sustain |"), std::string::npos);
  EXPECT_EQ(md.rfind(terminal, 0), 0u);
  EXPECT_NE(md.find("| episodes | no_response | timeout |"), std::string::npos);  // priority order
  EXPECT_NE(md.find("| still_sustain | 0.2 | s |"), std::string::npos);
  const std::string csv = summary_csv(sample_run());
  // Header + 2 roles + 2 tasks + overall.
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 6);
  EXPECT_EQ(csv.rfind("level,group,task_id,policy,episodes,csr,csr_low,csr_high,ct,", 0), 0u);
  EXPECT_NE(csv.find("\noverall,overall,,noop,4,0.5,"), std::string::npos);
  EXPECT_NE(csv.find("\ntask,stop_go,I4,noop,2,0.5,"), std::string::npos) << csv;
}

TEST(Report, ResultsHoldVariantsTaskIdsAndAggregates) {
  const RunResults run = sample_run();
  const nlohmann::json j = results_to_json(run);
  EXPECT_EQ(j["episodes"][1]["variant"], "late_stop");
  EXPECT_EQ(j["episodes"][1]["task_id"], "I4");
  EXPECT_EQ(j["episodes"][0]["cues"][0]["premature"], false);
  const nlohmann::json& tasks = j["aggregates"]["task"];
  ASSERT_EQ(tasks.size(), 2u);
  EXPECT_EQ(tasks[0]["group"], "stop_go");
  EXPECT_EQ(tasks[0]["task_id"], "I4");
  EXPECT_EQ(tasks[0]["episodes"], 2);
  EXPECT_EQ(tasks[0]["csr"]["value"], 0.5);
  EXPECT_EQ(tasks[0]["csr"]["n"], 2);
  EXPECT_EQ(tasks[0]["failures"]["timeout"], 1);
  EXPECT_EQ(tasks[0]["critical_contacts"], 0);
  EXPECT_TRUE(tasks[0]["tsync"].is_null());
  EXPECT_EQ(j["aggregates"]["role"].size(), 2u);
  EXPECT_EQ(j["aggregates"]["overall"][0]["episodes"], 4);
  // Read back (aggregates are derived, not read), variant and task id survive; results
  // written before them read as empty.
  const RunResults back = results_from_json(j, "r");
  EXPECT_EQ(back.episodes[1].variant, "late_stop");
  EXPECT_EQ(back.episodes[1].task_id, "I4");
  nlohmann::json old = j["episodes"][1];
  old.erase("variant");
  old.erase("task_id");
  old["cues"][0].erase("premature");
  const EpisodeResult e = episode_from_json(old, "e");
  EXPECT_EQ(e.variant, "");
  EXPECT_EQ(e.task_id, "");
  EXPECT_FALSE(e.metrics.cues[0].premature);
}

TEST(Report, CompareRuns) {
  RunResults a = sample_run();
  RunResults b = sample_run();
  b.info.constants.still_sustain = 0.3;
  const std::string md = compare_markdown({{"runs/A", a}, {"runs/B", b}});
  EXPECT_NE(md.find("| runs/A | instructor | noop |"), std::string::npos);
  EXPECT_NE(md.find("| runs/B | overall | noop |"), std::string::npos);
  EXPECT_NE(md.find("Note: run runs/B used different metric constants than run runs/A."),
            std::string::npos);
  EXPECT_EQ(compare_markdown({{"A", a}, {"A2", a}}).find("Note:"), std::string::npos);
  // By task, and as CSV / JSON with every interval.
  EXPECT_NE(compare_markdown({{"A", a}}, CompareBy::kTask).find("| A | X1 intrusion_yield | noop |"),
            std::string::npos);
  const std::string csv = compare_csv({{"A", a}, {"B", b}}, CompareBy::kTask);
  EXPECT_EQ(csv.rfind("run,level,group,task_id,policy,episodes,csr,", 0), 0u);
  EXPECT_NE(csv.find("\nB,task,intrusion_yield,X1,noop,2,"), std::string::npos) << csv;
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 5);  // header + 2 runs x 2 tasks
  const nlohmann::json rows = compare_json({{"A", a}}, CompareBy::kRole);
  ASSERT_EQ(rows.size(), 3u);  // 2 roles + overall
  EXPECT_EQ(rows[2]["level"], "overall");
  EXPECT_EQ(rows[0]["run"], "A");
  EXPECT_EQ(rows[0]["csr"]["n"], 2);
}

TEST(Report, WriteAndLoadRun) {
  const auto dir = unique_temp_path("report");
  std::filesystem::remove_all(dir);
  const RunResults run = sample_run();
  write_run(dir, run);
  EXPECT_TRUE(std::filesystem::exists(dir / "summary.md"));
  EXPECT_TRUE(std::filesystem::exists(dir / "summary.csv"));
  EXPECT_EQ(results_to_json(load_run(dir)), results_to_json(run));
  std::ofstream(dir / "results.json") << "{\"format\": \"hribench-results\", ";
  try {
    load_run(dir);
    FAIL();
  } catch (const core::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("results.json:1:32: invalid JSON"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}

TEST(Report, EpisodeLinesSurviveAKilledWrite) {
  const auto path = unique_temp_path("lines.jsonl");
  std::filesystem::remove(path);
  const RunResults run = sample_run();
  for (const EpisodeResult& r : run.episodes) append_episode_line(path, r);
  // A run killed while writing the fifth line leaves half a line behind.
  std::ofstream(path, std::ios::app) << "{\"task\": \"stop_";
  const std::vector<EpisodeResult> back = load_episode_lines(path);
  ASSERT_EQ(back.size(), 4u);
  for (size_t i = 0; i < back.size(); ++i) {
    EXPECT_EQ(episode_to_json(back[i]), episode_to_json(run.episodes[i]));
  }
  // A broken line in the middle is an error naming the line.
  std::ofstream(path, std::ios::trunc) << episode_to_json(run.episodes[0]).dump() << "\nnot json\n";
  try {
    load_episode_lines(path);
    FAIL();
  } catch (const core::InputError& e) {
    EXPECT_EQ(e.where(), path.string() + ":2:2");  // line 2, column 2
  }
  std::filesystem::remove(path);
}

TEST(Report, BadEpisodeFieldsNameTheirPlace) {
  nlohmann::json j = episode_to_json(sample_run().episodes[0]);
  j["hcs"] = "high";
  try {
    episode_from_json(j, "results.json: episodes[0]");
    FAIL();
  } catch (const core::InputError& e) {
    EXPECT_STREQ(e.what(), "results.json: episodes[0].hcs: expected a number, got string");
  }
  j = episode_to_json(sample_run().episodes[1]);
  j["labels"][0] = "sleepy";
  try {
    episode_from_json(j, "e");
    FAIL();
  } catch (const core::InputError& e) {
    EXPECT_STREQ(e.what(),
                 "e.labels[0]: expected a failure label (invalid, policy_error, ..., timeout), got "
                 "'sleepy'");
  }
  j = episode_to_json(sample_run().episodes[1]);
  j.erase("task");
  EXPECT_THROW(episode_from_json(j, "e"), core::InputError);
}

// metric_constants read back from a results file are checked against their ranges: these
// values used to abort `report` (0 resamples), cast 1e300 to int, or index out of bounds.
TEST(Report, MetricConstantsOutOfRangeAreInputErrors) {
  const nlohmann::json good = results_to_json(sample_run());
  const auto error_of = [&](const char* name, const nlohmann::json& value) {
    nlohmann::json j = good;
    j["metric_constants"][name] = value;
    try {
      results_from_json(j, "r.json");
    } catch (const core::InputError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_EQ(error_of("bootstrap_resamples", 0),
            "r.json.metric_constants.bootstrap_resamples: expected a whole count from 1 to 1000000, got 0");
  EXPECT_EQ(error_of("bootstrap_resamples", 1e300),
            "r.json.metric_constants.bootstrap_resamples: expected a whole count from 1 to 1000000, got 1e+300");
  EXPECT_EQ(error_of("bootstrap_resamples", 2.5),
            "r.json.metric_constants.bootstrap_resamples: expected a whole count from 1 to 1000000, got 2.5");
  EXPECT_EQ(error_of("confidence", 3), "r.json.metric_constants.confidence: expected a level in (0, 1), got 3");
  EXPECT_EQ(error_of("moving_ee_speed", -1),
            "r.json.metric_constants.moving_ee_speed: expected a number in [0, 1e6], got -1");
  EXPECT_EQ(error_of("bootstrap_seed", -3),
            "r.json.metric_constants.bootstrap_seed: expected a non-negative integer, got -3");
  EXPECT_EQ(error_of("confidence", 0.9), "(no error)");
}

}  // namespace
}  // namespace hribench::eval

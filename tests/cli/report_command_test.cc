// Tests of `hribench report`: runs that measured different things (another horizon here) are
// refused with the difference named, compared with --force and a warning; a policy in two runs
// is a warning.

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "support/run_command.h"
#include "support/test_files.h"

namespace hribench::cli {
namespace {

namespace fs = std::filesystem;
using ::hribench::testing::count_lines;
using ::hribench::testing::run_hribench;

class ReportComparisonTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = ::hribench::testing::temp_dir("report", "runs");
    const std::string common = " --tasks I1 --policy noop --episodes 1 --out " + dir_;
    ASSERT_EQ(run_hribench("eval --horizon 0.5" + common + "/short").exit_code, 0);
    ASSERT_EQ(run_hribench("eval --horizon 1" + common + "/long").exit_code, 0);
    ASSERT_EQ(run_hribench("eval --horizon 0.5" + common + "/again").exit_code, 0);
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static inline std::string dir_;
};

TEST_F(ReportComparisonTest, RefusesRunsOfAnotherHorizon) {
  const auto r = run_hribench("report " + dir_ + "/short " + dir_ + "/long");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_NE(r.output.find("report: the runs differ: " + dir_ + "/long has horizon 1.0, " + dir_ +
                          "/short has 0.5; use --force to compare them anyway"),
            std::string::npos) << r.output;
}

TEST_F(ReportComparisonTest, ForceComparesWithAWarning) {
  const auto r = run_hribench("report --force " + dir_ + "/short " + dir_ + "/long");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("hribench report: warning: " + dir_ + "/long has horizon 1.0"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("| Run |"), std::string::npos) << r.output;
}

TEST_F(ReportComparisonTest, SamePolicyInTwoRunsIsAWarning) {
  const auto r = run_hribench("report " + dir_ + "/short " + dir_ + "/again");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("warning: policy noop is in " + dir_ + "/short and in " + dir_ + "/again"),
            std::string::npos) << r.output;
}

TEST_F(ReportComparisonTest, ByTaskAsCsvAndJson) {
  const auto md = run_hribench("report --by task " + dir_ + "/short");
  ASSERT_EQ(md.exit_code, 0) << md.output;
  EXPECT_NE(md.output.find("| Run | Task | Policy |"), std::string::npos) << md.output;
  EXPECT_NE(md.output.find("| " + dir_ + "/short | I1 point_pick | noop |"), std::string::npos) << md.output;
  const auto csv = run_hribench("report --by task --format csv " + dir_ + "/short");
  ASSERT_EQ(csv.exit_code, 0) << csv.output;
  EXPECT_EQ(csv.output.rfind("run,level,group,task_id,policy,episodes,csr,csr_low,csr_high,", 0), 0u) << csv.output;
  EXPECT_NE(csv.output.find("\n" + dir_ + "/short,task,point_pick,I1,noop,1,0,"), std::string::npos) << csv.output;
  const auto json = run_hribench("report --format json " + dir_ + "/short");
  ASSERT_EQ(json.exit_code, 0) << json.output;
  const nlohmann::json rows = nlohmann::json::parse(json.output);
  ASSERT_EQ(rows.size(), 2u);  // instructor + overall
  EXPECT_EQ(rows[0]["level"], "role");
  EXPECT_EQ(rows[1]["group"], "overall");
  EXPECT_EQ(rows[1]["csr"]["n"], 1);
  const auto bad = run_hribench("report --format xlsx " + dir_ + "/short");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_EQ(count_lines(bad.output), 1) << bad.output;
  EXPECT_NE(bad.output.find("--format: expected md, csv, json or html, got 'xlsx'"), std::string::npos) << bad.output;
}

// --format html rewrites one run's report page (eval writes it too); its timeline needs logs.
TEST_F(ReportComparisonTest, HtmlRewritesTheRunsReportPage) {
  const fs::path page = fs::path(dir_) / "short" / "report.html";
  ASSERT_TRUE(fs::is_regular_file(page));  // by eval
  fs::remove(page);
  const auto html = run_hribench("report --format html " + dir_ + "/short");
  EXPECT_EQ(html.exit_code, 0) << html.output;
  EXPECT_EQ(html.output, "wrote " + page.string() + "\n");
  EXPECT_NE(::hribench::testing::read_text(page).find("No timeline: no episode of this run has a saved log"),
            std::string::npos);
  const auto two = run_hribench("report --format html " + dir_ + "/short " + dir_ + "/again");
  EXPECT_EQ(two.output, "hribench: error: --format html: expected one run folder, got 2 runs\n");
  const auto episode = run_hribench("report --episode x " + dir_ + "/short");
  EXPECT_EQ(episode.output,
            "hribench: error: --episode: expected --format html (the report page's timeline), got --format md\n");
  const auto unknown = run_hribench("report --format html --episode x " + dir_ + "/short");
  EXPECT_EQ(unknown.output, "hribench: error: " + dir_ +
                                "/short: holds no episode logs (logs/*.hlog); run eval with --save-logs to keep them\n");
}

}  // namespace
}  // namespace hribench::cli

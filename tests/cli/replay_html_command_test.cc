// Tests of `hribench replay-html`: the page of a saved log goes to RUN/replay/STEM.html (or
// --out); a run without logs, an unknown episode, a corrupt log and a data root without
// three.js are one clear line each.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "support/run_command.h"
#include "support/test_files.h"

namespace hribench::cli {
namespace {

namespace fs = std::filesystem;
using ::hribench::testing::count_lines;
using ::hribench::testing::run_hribench;

class ReplayHtmlCommandTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = ::hribench::testing::temp_dir("replay_html", "runs");
    const std::string common = " --tasks I1 --policy noop --episodes 1 --horizon 1 --out " + dir_;
    ASSERT_EQ(run_hribench("eval --save-logs" + common + "/logged").exit_code, 0);
    ASSERT_EQ(run_hribench("eval" + common + "/bare").exit_code, 0);
    for (const fs::directory_entry& e : fs::directory_iterator(dir_ + "/logged/logs")) stem_ = e.path().stem().string();
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static inline std::string dir_;
  static inline std::string stem_;
};

TEST_F(ReplayHtmlCommandTest, WritesThePageBesideTheReport) {
  const auto r = run_hribench("replay-html " + dir_ + "/logged " + stem_);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  const fs::path page = fs::path(dir_) / "logged" / "replay" / (stem_ + ".html");
  EXPECT_NE(r.output.find("wrote " + page.string() + " ("), std::string::npos) << r.output;
  EXPECT_TRUE(fs::is_regular_file(page));
  // The report links it once rewritten.
  EXPECT_EQ(run_hribench("report " + dir_ + "/logged --format html").exit_code, 0);
  EXPECT_NE(::hribench::testing::read_text(fs::path(dir_) / "logged" / "report.html")
                .find("<a href=\"replay/" + stem_ + ".html\">3D replay</a>"),
            std::string::npos);
  // A .hlog path and --out.
  const auto out = run_hribench("replay-html " + dir_ + "/logged " + dir_ + "/logged/logs/" + stem_ +
                                ".hlog --out " + dir_ + "/elsewhere/page.html");
  EXPECT_EQ(out.exit_code, 0) << out.output;
  EXPECT_TRUE(fs::is_regular_file(fs::path(dir_) / "elsewhere" / "page.html"));
}

// --failures 1: the page of the run's one episode (noop fails I1), where EPISODE would put it.
TEST_F(ReplayHtmlCommandTest, FailuresWritesThePagesOfTheFirstFailures) {
  const fs::path page = fs::path(dir_) / "logged" / "replay" / (stem_ + ".html");
  fs::remove(page);
  const auto r = run_hribench("replay-html " + dir_ + "/logged --failures 1");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("wrote " + page.string() + " ("), std::string::npos) << r.output;
  EXPECT_EQ(count_lines(r.output), 1) << r.output;
  EXPECT_TRUE(fs::is_regular_file(page));
  const auto bare = run_hribench("replay-html " + dir_ + "/bare --failures 1");
  EXPECT_EQ(bare.exit_code, 2);
  EXPECT_EQ(bare.output, "hribench: error: " + dir_ +
                             "/bare: holds no episode logs (logs/*.hlog); run eval with --save-logs to keep them\n");
}

TEST_F(ReplayHtmlCommandTest, ErrorsAreOneClearLine) {
  const auto bare = run_hribench("replay-html " + dir_ + "/bare " + stem_);
  EXPECT_EQ(bare.exit_code, 2);
  EXPECT_EQ(bare.output, "hribench: error: " + dir_ +
                             "/bare: holds no episode logs (logs/*.hlog); run eval with --save-logs to keep them\n");
  const auto unknown = run_hribench("replay-html " + dir_ + "/logged point_pick__nobody__0__x");
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_EQ(unknown.output, "hribench: error: EPISODE: expected an episode of " + dir_ + "/logged (a log stem, e.g. " +
                                stem_ + "; or a .hlog file), got 'point_pick__nobody__0__x'\n");
  // A data root without node_modules/three.
  const fs::path root = fs::path(dir_) / "root";
  fs::create_directories(root);
  fs::create_directory_symlink(fs::current_path() / "tasks", root / "tasks");
  const auto no_three = run_hribench("--root " + root.string() + " replay-html " + dir_ + "/logged " + stem_);
  EXPECT_EQ(no_three.exit_code, 2);
  EXPECT_EQ(no_three.output, "hribench: error: " + root.string() +
                                 "/node_modules/three/build/three.core.js: expected three.js (the npm package three "
                                 "pinned in package.json), got no such file: run scripts/install-deps.sh\n");
  // A log with one byte of its payload changed.
  const fs::path broken = fs::path(dir_) / "logged" / "logs" / "broken.hlog";
  std::string bytes = ::hribench::testing::read_text(fs::path(dir_) / "logged" / "logs" / (stem_ + ".hlog"));
  bytes[bytes.size() / 2] = static_cast<char>(bytes[bytes.size() / 2] ^ 0x5a);
  std::ofstream(broken, std::ios::binary) << bytes;
  const auto corrupt = run_hribench("replay-html " + dir_ + "/logged broken");
  EXPECT_EQ(corrupt.exit_code, 2);
  EXPECT_EQ(count_lines(corrupt.output), 1) << corrupt.output;
  EXPECT_EQ(corrupt.output, "hribench: error: " + broken.string() + ": corrupt episode log (checksum mismatch)\n");
  fs::remove(broken);
}

}  // namespace
}  // namespace hribench::cli

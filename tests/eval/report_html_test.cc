// The report page (eval/report_html.h): one bar per (group, policy) and one dot per episode with
// the metric, links only to files that exist, the timeline of the chosen episode (the first
// failed one with a saved log by default) or one sentence saying why there is none, and the
// errors for an unknown episode and a corrupt log.

#include "eval/report_html.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "eval/episode_builder.h"
#include "eval/episode_files.h"
#include "support/test_files.h"

namespace hribench::eval {
namespace {

namespace fs = std::filesystem;
using ::hribench::testing::error_of;
using testing::EpisodeBuilder;

struct SampleRun {
  RunResults run;
  std::vector<EpisodeLog> logs;  // aligned with run.episodes
};

// Two tasks x (oracle succeeds, noop fails), with a human act, a cue and a robot act.
SampleRun sample_run() {
  SampleRun s;
  s.run.info = current_run_info("none", {{"episodes", 1}});
  ScenarioContract contract;
  contract.cues.push_back({"stop", "stop.stroke", CueKind::kStop, 1.0, std::nullopt});
  for (int i = 0; i < 4; ++i) {
    const bool oracle = i % 2 == 0;
    EpisodeBuilder b(5.0);
    b.move_x(0.0, oracle ? 1.2 : 3.0, 0.1)
        .event(0.5, "stop.start", EventKind::kActStart)
        .event(1.0, "stop.stroke", EventKind::kCue)
        .event(2.0, "stop.end", EventKind::kActEnd)
        .event(2.5, "place.start", EventKind::kActStart, Actor::kRobot)
        .event(4.0, "place.end", EventKind::kActEnd, Actor::kRobot)
        .separation(0.0, 5.0, 0.6 - 0.1 * i, 0.2, 0.2);
    if (oracle) b.predicate("success", 3.0, 5.0);
    EpisodeLog log = b.log();
    log.task = i < 2 ? "stop_go" : "intrusion_yield";
    log.role = i < 2 ? "instructor" : "intruder";
    log.policy = oracle ? "oracle" : "noop";
    log.spec_hash = "0123456789abcdef";
    log.seed = 0;
    s.run.episodes.push_back(make_result(log, compute_metrics(contract, log)));
    s.run.episodes.back().task_id = i < 2 ? "I4" : "X1";
    s.logs.push_back(std::move(log));
  }
  return s;
}

// Occurrences of `needle` inside the element that starts with `open` (up to its </svg>).
int count_in(const std::string& html, const std::string& open, const std::string& needle) {
  const size_t from = html.find(open);
  if (from == std::string::npos) return -1;
  const size_t to = html.find("</svg>", from);
  int n = 0;
  for (size_t at = html.find(needle, from); at < to; at = html.find(needle, at + 1)) ++n;
  return n;
}

int count(const std::string& html, const std::string& needle) {
  int n = 0;
  for (size_t at = html.find(needle); at != std::string::npos; at = html.find(needle, at + 1)) ++n;
  return n;
}

TEST(ReportHtml, ABarPerGroupAndPolicyAndADotPerEpisode) {
  const SampleRun s = sample_run();
  const std::string html = report_html(s.run, std::vector<EpisodeFiles>(4), nullptr);
  EXPECT_EQ(count_in(html, "<svg id=\"csr-by-task\"", "class=\"bar\""), 4);
  EXPECT_EQ(count_in(html, "<svg id=\"csr-by-role\"", "class=\"bar\""), 4);
  EXPECT_EQ(count_in(html, "<svg id=\"csr-by-task\"", "data-group=\"I4 stop_go\""), 2);
  // The oracle succeeds (no label, a success segment); noop's failures have one label.
  EXPECT_EQ(count_in(html, "<svg id=\"failures\"", "class=\"bar\""), 1);
  EXPECT_EQ(count_in(html, "<svg id=\"failures\"", "class=\"success\""), 1);
  int with_rsp = 0;
  for (const EpisodeResult& e : s.run.episodes) with_rsp += e.metrics.response_latency ? 1 : 0;
  EXPECT_GT(with_rsp, 0);
  EXPECT_EQ(count_in(html, "<svg id=\"rsp\"", "class=\"dot\""), with_rsp);
  EXPECT_EQ(count(html, "<tr class=\"episode "), 4);
  EXPECT_EQ(count(html, "<tr class=\"episode failure\""), 2);
  // Self-contained: no script, nothing fetched.
  EXPECT_EQ(count(html, "<script"), 0);
  EXPECT_EQ(count(html, "src="), 0);
  EXPECT_EQ(count(html, "http://") - count(html, "xmlns=\"http://www.w3.org/2000/svg\""), 0);
}

TEST(ReportHtml, LinksOnlyToFilesThatExistAndSaysWhyThereIsNoTimeline) {
  const SampleRun s = sample_run();
  std::vector<EpisodeFiles> files(4);
  files[1].video = true;
  files[2].replay = true;
  const std::string html = report_html(s.run, files, nullptr);
  EXPECT_EQ(count(html, "<a href="), 2);
  EXPECT_EQ(count(html, "<a href=\"videos/" + episode_stem(s.run.episodes[1]) + ".mp4\">video</a>"), 1);
  EXPECT_EQ(count(html, "<a href=\"replay/" + episode_stem(s.run.episodes[2]) + ".html\">3D replay</a>"), 1);
  EXPECT_EQ(count(html, "<p class=\"no-timeline\">No timeline: no episode of this run has a saved log (run eval "
                        "with --save-logs to keep them).</p>"),
            1);
  EXPECT_EQ(count(html, "<svg id=\"timeline\""), 0);
}

TEST(ReportHtml, TimelineLanesOfTheEpisode) {
  const SampleRun s = sample_run();
  const ReportTimeline timeline{"stem", "--episode", s.logs[1]};
  const std::string html = report_html(s.run, std::vector<EpisodeFiles>(4), &timeline);
  EXPECT_EQ(count_in(html, "<svg id=\"timeline\"", "class=\"act human\""), 1);
  EXPECT_EQ(count_in(html, "<svg id=\"timeline\"", "class=\"act robot\""), 1);
  EXPECT_EQ(count_in(html, "<svg id=\"timeline\"", "class=\"goal robot\""), 1);
  EXPECT_EQ(count_in(html, "<svg id=\"timeline\"", "class=\"cue\""), 1);
  EXPECT_EQ(count_in(html, "<svg id=\"timeline\"", "class=\"separation\""), 1);
  EXPECT_EQ(count_in(html, "<svg id=\"timeline\"", "class=\"protective\""), 1);
  EXPECT_EQ(count_in(html, "<svg id=\"timeline\"", "class=\"force-human\""), 1);
  EXPECT_NE(html.find("<p><b>stem</b> (--episode): stop_go seed 0, policy noop"), std::string::npos);
}

TEST(ReportHtml, WriteChoosesTheFirstFailedEpisodeWithALog) {
  const SampleRun s = sample_run();
  const fs::path dir = ::hribench::testing::temp_dir("report_html", "run");
  const auto save = [&](size_t i) { save_episode_log(s.logs[i], log_file(dir, episode_stem(s.run.episodes[i]))); };
  const auto timeline_of = [&](std::string_view episode = {}) {
    const std::string html = ::hribench::testing::read_text(write_report_html(dir, s.run, episode));
    const size_t at = html.find("<p><b>");
    return at == std::string::npos ? std::string("none") : html.substr(at + 6, html.find(')', at) - at - 5);
  };
  fs::create_directories(dir);
  EXPECT_EQ(timeline_of(), "none");
  fs::create_directories(dir / "logs");
  save(0);
  save(2);
  EXPECT_EQ(timeline_of(), episode_stem(s.run.episodes[0]) +
                               "</b> (no episode failed: the first episode with a saved log)");
  save(3);
  EXPECT_EQ(timeline_of(), episode_stem(s.run.episodes[3]) + "</b> (the first failed episode with a saved log)");
  EXPECT_EQ(timeline_of(episode_stem(s.run.episodes[2])), episode_stem(s.run.episodes[2]) + "</b> (--episode)");
  EXPECT_EQ(error_of([&] { write_report_html(dir, s.run, "nope"); }),
            "--episode: expected an episode of " + dir.string() + " (a log stem, e.g. " +
                episode_stem(s.run.episodes[3]) + ", " + episode_stem(s.run.episodes[2]) + ", " +
                episode_stem(s.run.episodes[0]) + "; or a .hlog file), got 'nope'");
  const fs::path broken = log_file(dir, episode_stem(s.run.episodes[3]));
  std::ofstream(broken, std::ios::trunc) << "not a log";
  EXPECT_EQ(error_of([&] { write_report_html(dir, s.run); }),
            broken.string() + ": expected an HRIBench episode log (starting with HRIBLOG), got a file of another kind");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hribench::eval

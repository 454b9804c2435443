#pragma once
// RUN/report.html (docs/report.md): the results of a run as one self-contained page that opens
// from disk and reaches nothing on the network. Sections: the headline table with intervals;
// CSR per task and per role group of every policy as bar charts with their intervals; the
// primary failure labels per policy; the distributions of Rsp and TSync over episodes; one row
// per episode with its labels and links to its video (RUN/videos/STEM.mp4) and 3D replay
// (RUN/replay/STEM.html), each only when the file exists; and the timeline of one chosen
// episode from its saved log: human acts and cues, robot acts and contacts, separation d(t)
// against the protective distance S_p(t) (docs/metrics.md, HCS), contact forces.
//
// The charts are SVG written here, by our code (no plotting library): the page is the same
// bytes for the same run and files, needs no script, and its charts are plain elements a test
// can count (every bar is a <rect class="bar" data-policy="..." data-group="..."> inside an
// <svg id="csr-by-task">, <svg id="csr-by-role"> or <svg id="failures">; every dot of a
// distribution a <circle class="dot"> inside <svg id="rsp"> or <svg id="tsync">).

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "eval/episode_log.h"
#include "eval/report.h"

namespace hribench::eval {

// Which files of an episode exist (eval/episode_files.h); links are made to those only.
struct EpisodeFiles {
  bool log = false;
  bool video = false;
  bool replay = false;
};

// The episode whose timeline the report draws: its stem, its log and why it was chosen
// ("the first failed episode with a saved log", "--episode").
struct ReportTimeline {
  std::string stem;
  std::string chosen_because;
  EpisodeLog log;
};

// The page. `files` is aligned with run.episodes; `timeline` null: no episode has a saved log
// (the section says so in one sentence).
std::string report_html(const RunResults& run, const std::vector<EpisodeFiles>& files,
                        const ReportTimeline* timeline);

// Writes DIR/report.html for the run whose folder is `dir` (atomically) and returns its path:
// the episodes' files as they exist now; the timeline of `episode` (a log stem of DIR/logs or
// a .hlog file) or, when empty, of the first failed episode that has a saved log (else the
// first episode that has one; none: no timeline). Throws core::InputError for an episode that
// is not found (eval/episode_files.h), a corrupt log (eval/episode_log.h) or a file that
// cannot be written.
std::filesystem::path write_report_html(const std::filesystem::path& dir, const RunResults& run,
                                        std::string_view episode = {});

}  // namespace hribench::eval

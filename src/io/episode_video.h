#pragma once
// An episode's video from its log alone (docs/videos.md): the agentview camera, optionally a
// second camera side by side, and under them a band of text at every control step: simulated
// time, the person's current act and motion phase, the latest cue and the robot's response to
// it, the separation d(t) against the protective distance S_p(t), and the robot's contacts as
// they happen. Frame k is the log's step k, posed by eval::pose_from_step on a Data of its own
// and shown at k * control_dt: the episode itself is never touched, so `hribench eval --video`
// (in the worker, after the episode) and `hribench video RUN EPISODE` (from a saved log) make
// the same file.

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "eval/constants.h"
#include "eval/episode_log.h"
#include "eval/metrics.h"
#include "io/video.h"
#include "render/gl_context.h"
#include "render/renderer.h"
#include "script/scenario.h"

namespace hribench::io {

struct EpisodeVideoOptions {
  std::vector<std::string> cameras = {"agentview"};  // side by side, left to right (1 or 2)
  int panel_width = 320;   // pixels of each camera's picture (even)
  int panel_height = 240;
  render::Backend backend = render::Backend::kOsmesa;
  int crf = 23;            // the encoder's (VideoSettings; the frame rate is 1 / control_dt)
};

// Height of a band row (pixels) and the band's rows.
inline constexpr int kBandRowHeight = 20;
inline constexpr int kBandRows = 2;

// The band under frame `step` of the log: row 1 time, person, cue, response; row 2 separation
// against S_p (red background when closer than S_p) and contacts (red when one touches the
// person). `metrics` gives the responses (compute_metrics of the same log).
std::vector<render::BandRow> video_band(const eval::EpisodeLog& log, size_t step,
                                        const eval::EpisodeMetrics& metrics,
                                        const eval::MetricConstants& constants);

// The cameras of a list "agentview" or "agentview,wrist" (a flag's value; where = the flag),
// checked against the scene of `spec` (its model built): one or two cameras the model has.
std::vector<std::string> video_cameras(const std::string& list, const script::EpisodeSpec& spec,
                                       std::string_view where);

// Writes the video of `log`, an episode of `spec` (rebuilt: its scene model and contract, the
// metrics recomputed), to `path` (mp4, written whole). Throws core::InputError for a camera the
// model lacks (the cameras named), more than two cameras, a log that does not belong to the
// spec (its hash), an empty log, a renderer that cannot start (the none back end included) or
// a file that cannot be written.
void write_episode_video(const script::EpisodeSpec& spec, const eval::EpisodeLog& log,
                         const std::filesystem::path& path, const EpisodeVideoOptions& options,
                         const eval::MetricConstants& constants = {});

}  // namespace hribench::io

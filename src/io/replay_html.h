#pragma once
// The 3D replay page of an episode (docs/report.md): one HTML file, made from the episode's
// saved log alone (no policy re-run), that plays the episode in the browser with three.js —
// the robot's links, the person's capsules, the objects with the box lid, the table and floor —
// with a timeline scrubber, play/pause and speed, event markers on the timeline, contact points
// highlighted, the separation d(t) colour-coded against the protective distance S_p(t)
// (docs/metrics.md, HCS), and an orbit camera (drag: turn, wheel: zoom, shift-drag: pan).
//
// The page opens from disk and reaches nothing on the network: three.js (the npm package
// `three`, node_modules/three/build/three.{core,module}.js under the data root, core/paths.h) is
// inlined as text and loaded as modules from blob: URLs (a file:// page may not import other
// files), with its comments and blank lines left out. Every body that carries a visible geom is
// a three.js group posed at every control step (20 Hz, no subsampling) from the model re-posed
// by eval::pose_from_step: positions in millimetres and quaternions in 1/32767 as int16, in
// base64. A 30 s episode's page is about 1.5 MB (1.1 MB of it three.js).
//
// For tests and scripts the page sets window.hribenchReplay = {ready, seek(t), time(),
// duration(), frames(), endEffectorPosition(), contactPoints(), setVisible(category, on), play(),
// pause()}:
// seek shows the step nearest t (s) and draws it before returning; endEffectorPosition() is
// the world position [x, y, z] (m) of the TCP as drawn (the hand body's pose and the TCP
// site's offset: the log's X_WT within the quantisation, < 1 mm); contactPoints() the world
// positions [[x, y, z], ...] of the robot's contacts highlighted at the shown step;
// categories are "robot", "human", "object" and "scene".

#include <filesystem>
#include <string>
#include <string_view>

#include "eval/constants.h"
#include "eval/episode_log.h"
#include "model/model.h"

namespace hribench::io {

// The model the logged episode ran in: its task's script (the data root's tasks/, by the
// log's task name) sampled with the log's seed and built. Throws core::InputError when no
// script of tasks/ has that task, or the sample's spec hash is not the log's (the script
// changed since the run).
model::Model model_of_log(const eval::EpisodeLog& log);

// three.js as the page inlines it, from `root`/node_modules/three/build. Throws
// core::InputError (where = the missing file) when it is not there: "run
// scripts/install-deps.sh".
struct ThreeJs {
  std::string core;    // three.core.js
  std::string module;  // three.module.js (imports './three.core.js')
};
ThreeJs load_three_js(const std::filesystem::path& root);

// The page of `log` (recorded in `model`); `constants` give S_p.
std::string replay_html(const model::Model& model, const eval::EpisodeLog& log, const ThreeJs& three,
                        const eval::MetricConstants& constants);

// `hribench replay-html RUN EPISODE [--out FILE]`: the page of an episode of the run in `run`
// (EPISODE: a log stem of RUN/logs or a .hlog file, eval/episode_files.h), written to `out`,
// by default RUN/replay/STEM.html; the run's metric constants when RUN/results.json exists,
// else the defaults. Returns the path written. Throws core::InputError for a run without
// logs, an unknown episode, a corrupt log, a missing three.js or a file that cannot be
// written.
std::filesystem::path write_replay_html(const std::filesystem::path& run, std::string_view episode,
                                        const std::filesystem::path& out = {});

}  // namespace hribench::io

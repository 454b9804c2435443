// `hribench video RUN EPISODE|--failures N [--out FILE] [--cameras agentview[,wrist]] [--size WxH]`:
// the video of a saved episode (eval --save-logs) from its log alone, without running the policy
// again (io/episode_video.h, docs/videos.md). EPISODE is the log's stem (RUN/logs/STEM.hlog) or
// its path; --failures N makes the videos of the first N failed episodes of each task and policy
// (cli/episode_choice.h), one after the other. A video goes to RUN/videos/STEM.mp4 unless --out
// names another file.

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "cli/command.h"
#include "cli/episode_choice.h"
#include "core/errors.h"
#include "eval/episode_files.h"
#include "gen/evaluation.h"
#include "io/episode_video.h"

namespace hribench::cli {
namespace {

struct VideoOptions {
  std::string run;
  EpisodeChoice episodes;
  std::string out;
  std::string cameras = "agentview";
  std::string size = "320x240";
  std::string backend = "osmesa";
};

// "320x240" -> panel width and height.
void parse_panel_size(const std::string& size, io::EpisodeVideoOptions& options) {
  int width = 0;
  int height = 0;
  char x = 0;
  char extra = 0;
  if (std::sscanf(size.c_str(), "%d%c%d%c", &width, &x, &height, &extra) != 3 || x != 'x' ||
      width <= 0 || height <= 0 || width % 2 != 0 || height % 2 != 0 || width > render::kMaxImageSide ||
      height > render::kMaxImageSide) {
    throw core::InputError("--size", "WIDTHxHEIGHT of each camera, even numbers of pixels (e.g. 320x240)",
                           "'" + size + "'");
  }
  options.panel_width = width;
  options.panel_height = height;
}

int run_video(const VideoOptions& o) {
  io::EpisodeVideoOptions options;
  parse_panel_size(o.size, options);
  options.backend = render::parse_backend(o.backend);
  const std::vector<std::string> chosen = chosen_episodes(o.run, o.episodes, o.out);
  if (chosen.empty()) std::printf("hribench video: %s has no failed episode with a saved log\n", o.run.c_str());
  for (const std::string& name : chosen) {
    const gen::LoggedEpisode episode = gen::load_logged_episode(o.run, name);
    options.cameras = io::video_cameras(o.cameras, episode.spec, "--cameras");
    const std::filesystem::path out =
        o.out.empty() ? eval::video_file(o.run, episode.log_file.stem().string())
                      : std::filesystem::path(o.out);
    if (out.has_parent_path()) std::filesystem::create_directories(out.parent_path());
    io::write_episode_video(episode.spec, episode.log, out, options);
    std::printf("hribench video: wrote %s (%zu frames)\n", out.c_str(), episode.log.steps.size());
  }
  return 0;
}

HRIB_REGISTER_COMMAND(
    "video", "Make an episode's video from its saved log (docs/videos.md)",
    [](CLI::App& app) -> std::function<int()> {
      auto o = std::make_shared<VideoOptions>();
      app.add_option("run", o->run, "The run folder (hribench eval --save-logs --out RUN)")->required();
      add_episode_choice(app, o->episodes);
      app.add_option("--out", o->out, "The mp4 to write (default RUN/videos/STEM.mp4)");
      app.add_option("--cameras", o->cameras, "agentview, or agentview,wrist side by side")
          ->capture_default_str();
      app.add_option("--size", o->size, "Each camera's picture, WIDTHxHEIGHT")->capture_default_str();
      app.add_option("--backend", o->backend, "osmesa (CPU) or egl (GPU)")->capture_default_str();
      return [o] { return run_video(*o); };
    });

}  // namespace
}  // namespace hribench::cli

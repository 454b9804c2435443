// `hribench replay-html RUN EPISODE|--failures N [--out FILE]`: the 3D replay page of an episode
// of a run made with --save-logs (io/replay_html.h, docs/report.md), from its log alone: EPISODE
// is a log stem of RUN/logs (TASK__POLICY__SEED__HASH) or the path of a .hlog file; --failures N
// makes the pages of the first N failed episodes of each task and policy (cli/episode_choice.h).
// A page goes to RUN/replay/STEM.html (where RUN/report.html links it) unless --out names
// another file.

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "cli/command.h"
#include "cli/episode_choice.h"
#include "io/replay_html.h"

namespace hribench::cli {
namespace {

struct ReplayOptions {
  std::string run;
  EpisodeChoice episodes;
  std::string out;
};

HRIB_REGISTER_COMMAND("replay-html", "Write the 3D replay page of an episode from its saved log",
                      [](CLI::App& app) -> std::function<int()> {
                        auto o = std::make_shared<ReplayOptions>();
                        app.add_option("run", o->run, "The run's folder (eval --save-logs)")->required();
                        add_episode_choice(app, o->episodes);
                        app.add_option("--out", o->out, "The page to write (default RUN/replay/STEM.html)");
                        return [o] {
                          const std::vector<std::string> chosen = chosen_episodes(o->run, o->episodes, o->out);
                          if (chosen.empty()) std::printf("%s has no failed episode with a saved log\n", o->run.c_str());
                          for (const std::string& episode : chosen) {
                            const std::filesystem::path page = io::write_replay_html(o->run, episode, o->out);
                            std::printf("wrote %s (%.1f MB)\n", page.c_str(),
                                        static_cast<double>(std::filesystem::file_size(page)) / 1e6);
                          }
                          return 0;
                        };
                      });

}  // namespace
}  // namespace hribench::cli

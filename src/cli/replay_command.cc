// `hribench replay --dataset DIR [--episodes N]`: re-executes every recorded episode's actions
// of a collect's dataset on its spec and compares the log with the one the collect saved, bit
// for bit (io/replay.h, docs/datasets.md "Replay"). Exit 1 when any differs.

#include <cstdio>
#include <memory>
#include <string>

#include "cli/command.h"
#include "io/replay.h"

namespace hribench::cli {
namespace {

struct ReplayOptions {
  std::string dataset;
  size_t episodes = 0;
};

HRIB_REGISTER_COMMAND(
    "replay", "Re-execute a collected dataset's actions and check that they reproduce its episodes bit for bit",
    [](CLI::App& app) -> std::function<int()> {
      auto o = std::make_shared<ReplayOptions>();
      app.add_option("--dataset", o->dataset, "A folder written by hribench collect")->required();
      app.add_option("--episodes", o->episodes, "The first N episodes only (0: all)")->check(kNonNegativeWhole);
      return [o] {
        const io::ReplayReport report = io::replay_dataset(o->dataset, o->episodes);
        for (const std::string& d : report.differing) std::printf("differs: %s\n", d.c_str());
        std::printf("%zu episodes replayed, %zu identical to the collect's logs\n", report.episodes, report.identical);
        return report.differing.empty() ? 0 : 1;
      };
    });

}  // namespace
}  // namespace hribench::cli

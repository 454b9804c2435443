// `hribench report DIR...`: one headline table comparing the runs in the given folders (or
// results.json files), each labelled by its path.

#include <cstdio>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "cli/command.h"
#include "eval/report.h"

namespace hribench::cli {
namespace {

int run_report(const std::vector<std::string>& dirs) {
  std::vector<std::pair<std::string, eval::RunResults>> runs;
  runs.reserve(dirs.size());
  for (const std::string& dir : dirs) runs.emplace_back(dir, eval::load_run(dir));
  std::fputs(eval::compare_markdown(runs).c_str(), stdout);
  return 0;
}

HRIB_REGISTER_COMMAND("report", "Compare the results of runs (folders written by eval)",
                      [](CLI::App& app) -> std::function<int()> {
                        auto dirs = std::make_shared<std::vector<std::string>>();
                        app.add_option("dirs", *dirs, "Run folders or results.json files")
                            ->required();
                        return [dirs] { return run_report(*dirs); };
                      });

}  // namespace
}  // namespace hribench::cli

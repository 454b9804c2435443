// `hribench check FILE...`: validates scenario scripts before any physics and prints every
// problem, one per line ("file:line:col (key.path): expected X, got Y"). Exit 0 when every file
// is clean, 1 when any has a problem.

#include <cstdio>
#include <string>
#include <vector>

#include "cli/command.h"
#include "script/check.h"

namespace hribench::cli {
namespace {

int run_check(const std::vector<std::string>& files, bool quiet) {
  size_t total = 0;
  size_t bad_files = 0;
  for (const std::string& file : files) {
    const std::vector<script::Problem> problems = script::check(file);
    for (const script::Problem& p : problems) std::printf("%s\n", p.text().c_str());
    total += problems.size();
    if (!problems.empty()) ++bad_files;
    if (problems.empty() && !quiet) std::printf("%s: ok\n", file.c_str());
  }
  if (total > 0) {
    std::fprintf(stderr, "hribench check: %zu problem(s) in %zu of %zu file(s)\n", total, bad_files,
                 files.size());
    return 1;
  }
  return 0;
}

HRIB_REGISTER_COMMAND("check", "Validate scenario scripts and print every problem",
                      [](CLI::App& app) -> std::function<int()> {
                        auto files = std::make_shared<std::vector<std::string>>();
                        auto quiet = std::make_shared<bool>(false);
                        app.add_option("files", *files, "scenario scripts (.yaml)")->required();
                        app.add_flag("-q,--quiet", *quiet, "print nothing for clean files");
                        return [files, quiet] { return run_check(*files, *quiet); };
                      });

}  // namespace
}  // namespace hribench::cli

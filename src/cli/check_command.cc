// `hribench check FILE...`: validates scenario scripts before any physics and prints every
// problem, one per line ("file:line:col (key.path): expected X, got Y"). Exit 0 when every file
// is clean, 1 when any has a problem. With --sample SEED, each clean script is also sampled and
// its EpisodeSpec printed as JSON, followed by a line "sha256 HASH".

#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cli/command.h"
#include "core/paths.h"
#include "script/check.h"
#include "script/sample.h"

namespace hribench::cli {
namespace {

int run_check(const std::vector<std::string>& files, bool quiet, const std::optional<uint64_t>& seed) {
  size_t total = 0;
  size_t bad_files = 0;
  for (const std::string& name : files) {
    const std::string file = core::resolve_data_path(name).string();
    const std::vector<script::Problem> problems = script::check(file);
    for (const script::Problem& p : problems) std::printf("%s\n", p.text().c_str());
    total += problems.size();
    if (!problems.empty()) ++bad_files;
    if (problems.empty() && !quiet) std::printf("%s: ok\n", file.c_str());
    if (problems.empty() && seed.has_value()) {
      const script::EpisodeSpec spec = script::sample(script::load_scenario(file), *seed);
      std::printf("%ssha256 %s\n", script::spec_to_text(spec).c_str(), script::spec_hash(spec).c_str());
    }
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
                        auto seed = std::make_shared<std::optional<uint64_t>>();
                        app.add_option("files", *files, "scenario scripts (.yaml)")->required();
                        app.add_flag("-q,--quiet", *quiet, "print nothing for clean files");
                        app.add_option("--sample", *seed, "also print the EpisodeSpec drawn with this seed");
                        return [files, quiet, seed] { return run_check(*files, *quiet, *seed); };
                      });

}  // namespace
}  // namespace hribench::cli

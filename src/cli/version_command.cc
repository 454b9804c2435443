// `hribench version`: the provenance a result file records (HRIBench version, git hash,
// MuJoCo version).

#include <mujoco/mujoco.h>

#include <cstdio>

#include "cli/command.h"
#include "core/version.h"

namespace hribench::cli {
namespace {

HRIB_REGISTER_COMMAND("version", "Print HRIBench, git and MuJoCo versions",
                      [](CLI::App&) -> std::function<int()> {
                        return [] {
                          std::printf("hribench %.*s (git %.*s), MuJoCo %s\n",
                                      static_cast<int>(core::version().size()),
                                      core::version().data(),
                                      static_cast<int>(core::git_hash().size()),
                                      core::git_hash().data(), mj_versionString());
                          return 0;
                        };
                      });

}  // namespace
}  // namespace hribench::cli

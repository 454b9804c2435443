#pragma once
// Where HRIBench finds its data: the folder that holds tasks/ (the scenario scripts) and pool/
// (the released episode pools), so that commands work from any working directory
// (docs/getting-started.md, "Running from anywhere").
//
// The data root is, in this order:
//   1. the one set with set_data_root (the global `--root DIR` option of `hribench`);
//   2. the environment variable HRIBENCH_ROOT;
//   3. the current directory, if it has a tasks/ folder;
//   4. the source tree this binary was built from (compiled in), if it has a tasks/ folder;
//   5. the current directory.
//
// A relative path the user names (`--pool pool/v8`, `--task tasks/I1_point_pick.yaml`) is taken
// from the current directory when it exists there, else from the data root
// (resolve_data_path). Names recorded in outputs (manifests, options) stay as written, so a run
// records the same options whatever folder it was started from.

#include <filesystem>
#include <string>

namespace hribench::core {

// Overrides the data root for this process (an empty path clears the override). Throws
// core::InputError (where "--root") when `root` is not a folder.
void set_data_root(const std::filesystem::path& root);

// The data root (see above); never empty.
std::filesystem::path data_root();

// `path` as given when it is absolute or exists from the current directory; else
// data_root() / path when that exists; else `path` unchanged (so an error names what the user
// wrote).
std::filesystem::path resolve_data_path(const std::filesystem::path& path);

}  // namespace hribench::core

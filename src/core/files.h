#pragma once
// Files written whole: every result, summary, manifest, report and log a command writes goes to
// a temporary name beside its path and is renamed over it once complete, so a reader (or a run
// killed mid-write) finds the old file or the new one, never part of one (docs/hardening.md).

#include <filesystem>
#include <string_view>

namespace hribench::core {

// Writes `bytes` to PATH.tmp, then renames it over `path`. Throws core::InputError
// ("PATH: cannot write the file: REASON") if either step fails; the temporary is removed.
void write_file_atomically(const std::filesystem::path& path, std::string_view bytes);

}  // namespace hribench::core

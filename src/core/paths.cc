#include "core/paths.h"

#include <cstdlib>
#include <mutex>
#include <optional>

#include "core/errors.h"

namespace hribench::core {
namespace {

namespace fs = std::filesystem;

std::mutex& root_mutex() {
  static std::mutex mutex;
  return mutex;
}

std::optional<fs::path>& root_override() {
  static std::optional<fs::path> root;
  return root;
}

bool has_tasks(const fs::path& dir) {
  std::error_code ec;
  return fs::is_directory(dir / "tasks", ec);
}

}  // namespace

void set_data_root(const std::filesystem::path& root) {
  std::lock_guard<std::mutex> lock(root_mutex());
  if (root.empty()) {
    root_override().reset();
    return;
  }
  std::error_code ec;
  if (!fs::is_directory(root, ec)) {
    throw InputError("--root", "a folder holding tasks/ and pool/", "'" + root.string() + "'");
  }
  root_override() = fs::absolute(root, ec);
}

std::filesystem::path data_root() {
  {
    std::lock_guard<std::mutex> lock(root_mutex());
    if (root_override()) return *root_override();
  }
  if (const char* env = std::getenv("HRIBENCH_ROOT"); env != nullptr && *env != '\0') {
    std::error_code ec;
    if (!fs::is_directory(env, ec)) {
      throw InputError("HRIBENCH_ROOT", "a folder holding tasks/ and pool/", std::string("'") + env + "'");
    }
    return env;
  }
  const fs::path cwd = fs::current_path();
  if (has_tasks(cwd)) return cwd;
#ifdef HRIBENCH_SOURCE_ROOT
  if (has_tasks(HRIBENCH_SOURCE_ROOT)) return HRIBENCH_SOURCE_ROOT;
#endif
  return cwd;
}

std::filesystem::path resolve_data_path(const std::filesystem::path& path) {
  std::error_code ec;
  if (path.empty() || path.is_absolute() || fs::exists(path, ec)) return path;
  const fs::path under_root = data_root() / path;
  if (fs::exists(under_root, ec)) return under_root;
  return path;
}

}  // namespace hribench::core

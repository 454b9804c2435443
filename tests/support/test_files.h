#pragma once
// Helpers shared by tests that write and read files or check input-error messages.

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "core/errors.h"

namespace hribench::testing {

// The whole file as bytes ("" when it cannot be read).
inline std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// Every file under `dir` by its path relative to it, with its bytes.
inline std::map<std::string, std::string> files_under(const std::filesystem::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(dir)) {
    if (entry.is_regular_file()) files[std::filesystem::relative(entry.path(), dir).string()] = read_text(entry.path());
  }
  return files;
}

// Expects the files under `got` to be those under `expected`, byte for byte: each differing,
// missing or extra file is a failure naming it. Returns how many files `expected` holds.
inline size_t expect_same_files(const std::filesystem::path& got, const std::filesystem::path& expected) {
  const std::map<std::string, std::string> want = files_under(expected);
  const std::map<std::string, std::string> have = files_under(got);
  for (const auto& [path, bytes] : want) {
    const auto found = have.find(path);
    if (found == have.end()) {
      ADD_FAILURE() << path << " is missing";
    } else {
      EXPECT_TRUE(found->second == bytes) << path << " differs";
    }
  }
  for (const auto& [path, bytes] : have) EXPECT_TRUE(want.count(path) > 0) << path << " is extra";
  return want.size();
}

// A fresh, empty folder path under the test temp dir, unique per prefix, name and process.
inline std::string temp_dir(const std::string& prefix, const std::string& name) {
  const std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) /
                                    ("hribench_" + prefix + "_" + name + "_" + std::to_string(getpid()));
  std::filesystem::remove_all(dir);
  return dir.string();
}

// The message of the core::InputError `f` throws, "(no error)" when it throws none.
template <typename F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const core::InputError& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace hribench::testing

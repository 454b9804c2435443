#pragma once
// Reads Parquet files with two independent real readers, hyparquet and DuckDB, through
// tests/datasets/read_parquet.mjs run by the machine's Node.js (docs/datasets.md). The npm
// packages come from scripts/install-deps.sh; without them the calling test fails and says so.

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "support/run_command.h"

namespace hribench::testing {

// {FILE: {"hyparquet": {"schema", "num_rows", "rows"}, "duckdb": {"types", "rows",
// "metadata"}}} for each file, or a null json after a test failure naming what is missing.
inline nlohmann::json read_with_real_readers(const std::vector<std::string>& files) {
  const std::filesystem::path root = HRIBENCH_SOURCE_DIR;
  if (std::system("command -v node >/dev/null 2>&1") != 0 ||
      !std::filesystem::exists(root / "node_modules/hyparquet/package.json") ||
      !std::filesystem::exists(root / "node_modules/@duckdb/node-api/package.json")) {
    ADD_FAILURE() << "Node.js or the npm packages hyparquet and @duckdb/node-api are missing: "
                     "run scripts/install-deps.sh (it installs them from package-lock.json)";
    return nullptr;
  }
  const std::string json_path =
      (std::filesystem::path(::testing::TempDir()) / ("hribench_parquet_readers_" +
                                                      std::to_string(getpid()) + ".json")).string();
  std::string command = "cd '" + root.string() + "' && node tests/datasets/read_parquet.mjs";
  for (const std::string& file : files) command += " '" + file + "'";
  const CommandResult result = run_shell("(" + command + " > '" + json_path + "')");
  if (result.exit_code != 0) {
    ADD_FAILURE() << command << " failed:\n" << result.output;
    return nullptr;
  }
  std::ifstream in(json_path);
  nlohmann::json read = nlohmann::json::parse(in);
  std::filesystem::remove(json_path);
  return read;
}

}  // namespace hribench::testing

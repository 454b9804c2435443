#pragma once
// Reads Parquet files with two independent real readers, hyparquet and DuckDB, through
// tests/datasets/read_parquet.mjs run by the machine's Node.js (docs/datasets.md). The npm
// packages come from scripts/install-deps.sh; without them the calling test fails and says so.

#include <gtest/gtest.h>

#include <filesystem>
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
  std::string command = "cd '" + root.string() + "' && node tests/datasets/read_parquet.mjs";
  for (const std::string& file : files) command += " '" + file + "'";
  CommandResult result;
  {
    const std::string line = command + " 2>&1";
    FILE* pipe = popen(line.c_str(), "r");
    if (pipe == nullptr) {
      ADD_FAILURE() << "cannot run " << command;
      return nullptr;
    }
    char buffer[65536];
    size_t n = 0;
    while ((n = fread(buffer, 1, sizeof(buffer), pipe)) > 0) result.output.append(buffer, n);
    result.exit_code = pclose(pipe);
  }
  if (result.exit_code != 0) {
    ADD_FAILURE() << command << " failed:\n" << result.output;
    return nullptr;
  }
  return nlohmann::json::parse(result.output);
}

}  // namespace hribench::testing

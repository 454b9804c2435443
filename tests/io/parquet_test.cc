#include "io/parquet.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "support/parquet_readers.h"
#include "support/test_files.h"

namespace hribench::io {
namespace {

using hribench::testing::error_of;
using hribench::testing::temp_dir;

// Seven rows of every column type this writer writes, lists of fixed and of varying length
// (an empty one included), strings with non-ASCII text.
ParquetTable every_type() {
  ParquetTable table;
  ParquetColumn index = make_column("index", ParquetType::kInt64);
  ParquetColumn time = make_column("timestamp", ParquetType::kFloat32);
  ParquetColumn reward = make_column("reward", ParquetType::kFloat64);
  ParquetColumn done = make_column("next.done", ParquetType::kBool);
  ParquetColumn task = make_column("task", ParquetType::kString);
  ParquetColumn state = make_column("observation.state", ParquetType::kFloat32, true);
  ParquetColumn tasks = make_column("tasks", ParquetType::kString, true);
  ParquetColumn counts = make_column("count", ParquetType::kInt64, true);
  for (int r = 0; r < 7; ++r) {
    index.int64s.push_back(int64_t{1} << (5 * r));
    time.float32s.push_back(static_cast<float>(r) / 20.0f);
    reward.float64s.push_back(r * 0.1 - 0.25);
    done.bools.push_back(r % 3 == 2);
    task.strings.push_back(r == 4 ? "" : "hand över " + std::to_string(r));
    for (int k = 0; k < 3; ++k) state.float32s.push_back(static_cast<float>(r) + 0.5f * k);
    state.list_lengths.push_back(3);
    const int n = r % 3;  // 0, 1 or 2 strings
    for (int k = 0; k < n; ++k) tasks.strings.push_back("t" + std::to_string(r) + std::to_string(k));
    tasks.list_lengths.push_back(n);
    counts.int64s.push_back(r * 10);
    counts.list_lengths.push_back(1);
  }
  table.columns = {index, time, reward, done, task, state, tasks, counts};
  table.metadata = {{"pandas", R"({"index_columns": ["task"]})"}, {"note", "ü"}};
  return table;
}

void expect_equal(const ParquetTable& a, const ParquetTable& b) {
  ASSERT_EQ(a.columns.size(), b.columns.size());
  for (size_t c = 0; c < a.columns.size(); ++c) {
    SCOPED_TRACE(a.columns[c].name);
    EXPECT_EQ(a.columns[c].name, b.columns[c].name);
    EXPECT_EQ(a.columns[c].type, b.columns[c].type);
    EXPECT_EQ(a.columns[c].list, b.columns[c].list);
    EXPECT_EQ(a.columns[c].int64s, b.columns[c].int64s);
    EXPECT_EQ(a.columns[c].float32s, b.columns[c].float32s);
    EXPECT_EQ(a.columns[c].float64s, b.columns[c].float64s);
    EXPECT_EQ(a.columns[c].bools, b.columns[c].bools);
    EXPECT_EQ(a.columns[c].strings, b.columns[c].strings);
    EXPECT_EQ(a.columns[c].list_lengths, b.columns[c].list_lengths);
  }
  EXPECT_EQ(a.metadata, b.metadata);
}

// Row r of `column` as the JSON a reader gives (numbers, booleans, strings, arrays).
nlohmann::json json_cell(const ParquetColumn& column, int64_t row) {
  int64_t first = row;
  int64_t count = 1;
  if (column.list) {
    first = 0;
    for (int64_t r = 0; r < row; ++r) first += column.list_lengths[static_cast<size_t>(r)];
    count = column.list_lengths[static_cast<size_t>(row)];
  }
  nlohmann::json values = nlohmann::json::array();
  for (int64_t i = first; i < first + count; ++i) {
    const auto k = static_cast<size_t>(i);
    switch (column.type) {
      case ParquetType::kInt64:
        values.push_back(column.int64s[k]);
        break;
      case ParquetType::kFloat32:
        values.push_back(static_cast<double>(column.float32s[k]));
        break;
      case ParquetType::kFloat64:
        values.push_back(column.float64s[k]);
        break;
      case ParquetType::kBool:
        values.push_back(static_cast<bool>(column.bools[k]));
        break;
      case ParquetType::kString:
        values.push_back(column.strings[k]);
        break;
    }
  }
  return column.list ? values : values[0];
}

TEST(Parquet, OwnReaderReadsBackEveryTypeOverSeveralRowGroups) {
  const std::string dir = temp_dir("parquet", "own");
  std::filesystem::create_directories(dir);
  const ParquetTable table = every_type();
  for (int64_t rows_per_group : {1, 3, 7, 100}) {
    write_parquet(dir + "/t.parquet", table, rows_per_group);
    expect_equal(table, read_parquet(dir + "/t.parquet"));
  }
  EXPECT_FALSE(std::filesystem::exists(dir + "/t.parquet.tmp"));
  std::filesystem::remove_all(dir);
}

TEST(Parquet, HyparquetAndDuckDBReadEveryTypeValueAndTheMetadata) {
  const std::string dir = temp_dir("parquet", "readers");
  std::filesystem::create_directories(dir);
  const ParquetTable table = every_type();
  write_parquet(dir + "/one_group.parquet", table);
  write_parquet(dir + "/three_groups.parquet", table, 3);
  ParquetTable empty = table;
  for (ParquetColumn& c : empty.columns) c = make_column(c.name, c.type, c.list);
  write_parquet(dir + "/empty.parquet", empty);
  const nlohmann::json read = hribench::testing::read_with_real_readers(
      {dir + "/one_group.parquet", dir + "/three_groups.parquet", dir + "/empty.parquet"});
  ASSERT_FALSE(read.is_null());
  for (const std::string name : {"one_group", "three_groups"}) {
    SCOPED_TRACE(name);
    const nlohmann::json& file = read.at(dir + "/" + name + ".parquet");
    const nlohmann::json& hyparquet = file.at("hyparquet");
    const nlohmann::json& duckdb = file.at("duckdb");
    ASSERT_EQ(hyparquet.at("num_rows"), table.rows());
    ASSERT_EQ(hyparquet.at("rows").size(), 7u);
    ASSERT_EQ(duckdb.at("rows").size(), 7u);
    for (const ParquetColumn& column : table.columns) {
      for (int64_t r = 0; r < table.rows(); ++r) {
        SCOPED_TRACE(column.name + " row " + std::to_string(r));
        EXPECT_EQ(hyparquet.at("rows")[static_cast<size_t>(r)].at(column.name), json_cell(column, r));
        EXPECT_EQ(duckdb.at("rows")[static_cast<size_t>(r)].at(column.name), json_cell(column, r));
      }
    }
    const nlohmann::json types = {{"index", "BIGINT"},         {"timestamp", "FLOAT"},
                                  {"reward", "DOUBLE"},        {"next.done", "BOOLEAN"},
                                  {"task", "VARCHAR"},         {"observation.state", "FLOAT[]"},
                                  {"tasks", "VARCHAR[]"},      {"count", "BIGINT[]"}};
    EXPECT_EQ(duckdb.at("types"), types);
    EXPECT_EQ(duckdb.at("metadata").at("pandas"), R"({"index_columns": ["task"]})");
    EXPECT_EQ(duckdb.at("metadata").at("note"), "ü");
    // The schema hyparquet decodes from the Thrift footer: the LIST and STRING annotations.
    const nlohmann::json& schema = hyparquet.at("schema");
    ASSERT_EQ(schema.size(), 1u + 5u + 3u * 3u);
    EXPECT_EQ(schema[5]["logical_type"], "STRING");
    EXPECT_EQ(schema[6]["name"], "observation.state");
    EXPECT_EQ(schema[6]["converted_type"], "LIST");
    EXPECT_EQ(schema[6]["logical_type"], "LIST");
    EXPECT_EQ(schema[7]["repetition_type"], "REPEATED");
    EXPECT_EQ(schema[8]["type"], "FLOAT");
    EXPECT_EQ(schema[8]["repetition_type"], "REQUIRED");
  }
  EXPECT_EQ(read.at(dir + "/empty.parquet").at("duckdb").at("rows").size(), 0u);
  EXPECT_EQ(read.at(dir + "/empty.parquet").at("hyparquet").at("num_rows"), 0);
  std::filesystem::remove_all(dir);
}

TEST(Parquet, BadTablesAreInputErrorsAndNothingIsWritten) {
  const std::string dir = temp_dir("parquet", "errors");
  std::filesystem::create_directories(dir);
  const std::string path = dir + "/t.parquet";
  ParquetTable table = every_type();
  table.columns[1].float32s.pop_back();
  EXPECT_EQ(error_of([&] { write_parquet(path, table); }),
            path + ": column timestamp: expected 7 rows, got 6");
  table = every_type();
  table.columns[2].name = "index";
  EXPECT_EQ(error_of([&] { write_parquet(path, table); }),
            path + ": column 2: expected a unique, non-empty name, got 'index'");
  table = every_type();
  table.columns[5].list_lengths[0] = 2;
  EXPECT_EQ(error_of([&] { write_parquet(path, table); }),
            path + ": column observation.state: expected list lengths adding up to its 21 "
                   "values, got 20");
  EXPECT_EQ(error_of([&] { write_parquet(path, every_type(), 0); }),
            path + ": expected at least 1 row per row group, got 0");
  EXPECT_FALSE(std::filesystem::exists(path));
  std::ofstream(path) << "not parquet at all";
  EXPECT_EQ(error_of([&] { read_parquet(path); }),
            path + ": expected a Parquet file (PAR1 at both ends), got 18 bytes without it");
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace hribench::io

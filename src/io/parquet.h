#pragma once
// A small Apache Parquet writer and the reader of exactly what it writes (docs/datasets.md):
// Debian has no Arrow/Parquet library, and LeRobot datasets are Parquet tables. Files follow the
// format specification (github.com/apache/parquet-format): the footer and page headers in the
// Thrift compact protocol, data page v1, PLAIN values, no compression, one page per column
// chunk, one or more row groups, key-value metadata. Column types:
//   int64, float32, float64, bool     REQUIRED INT64 / FLOAT / DOUBLE / BOOLEAN
//   string                            REQUIRED BYTE_ARRAY, logical type STRING (UTF-8)
//   list of any of them               the standard 3-level LIST
//                                     (required group NAME (LIST) {
//                                        repeated group list { required T element; } })
//                                     with RLE-encoded repetition and definition levels
// A list column holds one list per row, of any length (0 included); a fixed-size list (a
// feature vector) is one whose rows all have the same length.

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace hribench::io {

enum class ParquetType { kInt64, kFloat32, kFloat64, kBool, kString };

// One column: its values in the vector of its type (the others stay empty). A list column also
// has one length per row in `list_lengths`, its values are the rows' lists one after the other.
struct ParquetColumn {
  std::string name;
  ParquetType type = ParquetType::kInt64;
  bool list = false;
  std::vector<int64_t> int64s;
  std::vector<float> float32s;
  std::vector<double> float64s;
  std::vector<bool> bools;
  std::vector<std::string> strings;
  std::vector<int64_t> list_lengths;  // list columns only: the number of values of each row

  // Number of values in the column's vector of its type.
  int64_t values() const;
  // Number of rows: list_lengths.size() for a list column, else values().
  int64_t rows() const;
};

// An empty column of that name and type.
ParquetColumn make_column(std::string name, ParquetType type, bool list = false);

struct ParquetTable {
  std::vector<ParquetColumn> columns;
  // The file's key-value metadata (e.g. "pandas" for a pandas index, docs/datasets.md).
  std::vector<std::pair<std::string, std::string>> metadata;

  // Number of rows (every column has it; 0 without columns).
  int64_t rows() const;
  // The column called `name`, nullptr when there is none.
  const ParquetColumn* find(const std::string& name) const;
};

// Writes `table` to `path` (to PATH.tmp, then renamed over it), `rows_per_group` rows per row
// group (>= 1; the last group holds the rest). Throws core::InputError for columns of different
// row counts, duplicate or empty names, list lengths that do not add up to the values, or a file
// that cannot be written (where the path).
void write_parquet(const std::filesystem::path& path, const ParquetTable& table,
                   int64_t rows_per_group = 65536);

// The table of a file written by write_parquet (every row group, the key-value metadata).
// Throws core::InputError (where the path) for a file that is not Parquet or uses features this
// writer does not write (compression, other encodings, optional values, nested types).
ParquetTable read_parquet(const std::filesystem::path& path);

}  // namespace hribench::io

#include "io/parquet.h"

#include <cstring>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "core/errors.h"
#include "core/files.h"

namespace hribench::io {
namespace {

// parquet.thrift's enum values (github.com/apache/parquet-format, src/main/thrift).
constexpr int32_t kTypeBoolean = 0;
constexpr int32_t kTypeInt64 = 2;
constexpr int32_t kTypeFloat = 4;
constexpr int32_t kTypeDouble = 5;
constexpr int32_t kTypeByteArray = 6;
constexpr int32_t kRequired = 0;
constexpr int32_t kRepeated = 2;
constexpr int32_t kConvertedUtf8 = 0;
constexpr int32_t kConvertedList = 3;
constexpr int32_t kEncodingPlain = 0;
constexpr int32_t kEncodingRle = 3;
constexpr int32_t kCodecUncompressed = 0;
constexpr int32_t kPageData = 0;

// Thrift compact protocol type ids.
constexpr uint8_t kCompactTrue = 1;
constexpr uint8_t kCompactFalse = 2;
constexpr uint8_t kCompactI32 = 5;
constexpr uint8_t kCompactI64 = 6;
constexpr uint8_t kCompactBinary = 8;
constexpr uint8_t kCompactList = 9;
constexpr uint8_t kCompactStruct = 12;

const char kMagic[] = "PAR1";

int32_t physical_type(ParquetType type) {
  switch (type) {
    case ParquetType::kInt64:
      return kTypeInt64;
    case ParquetType::kFloat32:
      return kTypeFloat;
    case ParquetType::kFloat64:
      return kTypeDouble;
    case ParquetType::kBool:
      return kTypeBoolean;
    case ParquetType::kString:
      return kTypeByteArray;
  }
  return kTypeInt64;
}

void put_varint(std::string& out, uint64_t value) {
  while (value >= 0x80) {
    out.push_back(static_cast<char>((value & 0x7F) | 0x80));
    value >>= 7;
  }
  out.push_back(static_cast<char>(value));
}

uint64_t zigzag(int64_t value) {
  return (static_cast<uint64_t>(value) << 1) ^ static_cast<uint64_t>(value >> 63);
}

template <typename T>
void put_le(std::string& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));  // the machine is little-endian (x86-64, arm64)
  out.append(bytes, sizeof(T));
}

// Thrift compact protocol, the subset parquet.thrift's structs need.
class CompactWriter {
 public:
  std::string out;

  void i32(int16_t id, int32_t value) {
    field(id, kCompactI32);
    put_varint(out, zigzag(value));
  }
  void i64(int16_t id, int64_t value) {
    field(id, kCompactI64);
    put_varint(out, zigzag(value));
  }
  void binary(int16_t id, const std::string& value) {
    field(id, kCompactBinary);
    binary_element(value);
  }
  void begin_struct(int16_t id) {
    field(id, kCompactStruct);
    begin_struct_element();
  }
  // A struct that is an element of a list (no field header).
  void begin_struct_element() {
    stack_.push_back(last_);
    last_ = 0;
  }
  void end_struct() {
    out.push_back(0);
    last_ = stack_.back();
    stack_.pop_back();
  }
  void list(int16_t id, uint8_t element_type, size_t size) {
    field(id, kCompactList);
    if (size < 15) {
      out.push_back(static_cast<char>((size << 4) | element_type));
    } else {
      out.push_back(static_cast<char>(0xF0 | element_type));
      put_varint(out, size);
    }
  }
  void i32_element(int32_t value) { put_varint(out, zigzag(value)); }
  void binary_element(const std::string& value) {
    put_varint(out, value.size());
    out += value;
  }
  // Ends the top-level struct.
  void stop() { out.push_back(0); }

 private:
  void field(int16_t id, uint8_t type) {
    const int delta = id - last_;
    if (delta > 0 && delta <= 15) {
      out.push_back(static_cast<char>((delta << 4) | type));
    } else {
      out.push_back(static_cast<char>(type));
      put_varint(out, zigzag(id));
    }
    last_ = id;
  }
  int16_t last_ = 0;
  std::vector<int16_t> stack_;
};

// RLE/bit-packed hybrid encoding of levels of bit width 1 (values 0 and 1), as RLE runs.
std::string encode_levels(const std::vector<uint8_t>& levels) {
  std::string runs;
  size_t i = 0;
  while (i < levels.size()) {
    size_t j = i;
    while (j < levels.size() && levels[j] == levels[i]) ++j;
    put_varint(runs, static_cast<uint64_t>(j - i) << 1);
    runs.push_back(static_cast<char>(levels[i]));
    i = j;
  }
  std::string out;
  put_le<uint32_t>(out, static_cast<uint32_t>(runs.size()));
  return out + runs;
}

void plain_values(std::string& out, const ParquetColumn& column, int64_t begin, int64_t end) {
  const auto b = static_cast<size_t>(begin);
  const auto e = static_cast<size_t>(end);
  switch (column.type) {
    case ParquetType::kInt64:
      for (size_t i = b; i < e; ++i) put_le<int64_t>(out, column.int64s[i]);
      break;
    case ParquetType::kFloat32:
      for (size_t i = b; i < e; ++i) put_le<float>(out, column.float32s[i]);
      break;
    case ParquetType::kFloat64:
      for (size_t i = b; i < e; ++i) put_le<double>(out, column.float64s[i]);
      break;
    case ParquetType::kBool: {
      uint8_t byte = 0;
      for (size_t i = b; i < e; ++i) {
        if (column.bools[i]) byte = static_cast<uint8_t>(byte | (1u << ((i - b) % 8)));
        if ((i - b) % 8 == 7 || i + 1 == e) {
          out.push_back(static_cast<char>(byte));
          byte = 0;
        }
      }
      break;
    }
    case ParquetType::kString:
      for (size_t i = b; i < e; ++i) {
        put_le<uint32_t>(out, static_cast<uint32_t>(column.strings[i].size()));
        out += column.strings[i];
      }
      break;
  }
}

void schema_leaf(CompactWriter& w, const std::string& name, ParquetType type) {
  w.begin_struct_element();
  w.i32(1, physical_type(type));
  w.i32(3, kRequired);
  w.binary(4, name);
  if (type == ParquetType::kString) {
    w.i32(6, kConvertedUtf8);
    w.begin_struct(10);  // LogicalType union: STRING (field 1, an empty struct)
    w.begin_struct(1);
    w.end_struct();
    w.end_struct();
  }
  w.end_struct();
}

struct ChunkInfo {
  int64_t offset = 0;  // of the page header in the file
  int64_t size = 0;    // page header and page
  int64_t num_values = 0;
};

}  // namespace

ParquetColumn make_column(std::string name, ParquetType type, bool list) {
  ParquetColumn column;
  column.name = std::move(name);
  column.type = type;
  column.list = list;
  return column;
}

int64_t ParquetColumn::values() const {
  switch (type) {
    case ParquetType::kInt64:
      return static_cast<int64_t>(int64s.size());
    case ParquetType::kFloat32:
      return static_cast<int64_t>(float32s.size());
    case ParquetType::kFloat64:
      return static_cast<int64_t>(float64s.size());
    case ParquetType::kBool:
      return static_cast<int64_t>(bools.size());
    case ParquetType::kString:
      return static_cast<int64_t>(strings.size());
  }
  return 0;
}

int64_t ParquetColumn::rows() const {
  return list ? static_cast<int64_t>(list_lengths.size()) : values();
}

int64_t ParquetTable::rows() const { return columns.empty() ? 0 : columns.front().rows(); }

const ParquetColumn* ParquetTable::find(const std::string& name) const {
  for (const ParquetColumn& column : columns) {
    if (column.name == name) return &column;
  }
  return nullptr;
}

void write_parquet(const std::filesystem::path& path, const ParquetTable& table,
                   int64_t rows_per_group) {
  const std::string where = path.string();
  if (rows_per_group < 1) {
    throw core::InputError(where, "at least 1 row per row group", std::to_string(rows_per_group));
  }
  const int64_t rows = table.rows();
  std::set<std::string> names;
  std::vector<std::vector<int64_t>> list_starts(table.columns.size());  // value offset per row
  for (size_t c = 0; c < table.columns.size(); ++c) {
    const ParquetColumn& column = table.columns[c];
    if (column.name.empty() || !names.insert(column.name).second) {
      throw core::InputError(where + ": column " + std::to_string(c), "a unique, non-empty name",
                             "'" + column.name + "'");
    }
    if (column.rows() != rows) {
      throw core::InputError(where + ": column " + column.name, std::to_string(rows) + " rows",
                             std::to_string(column.rows()));
    }
    if (column.list) {
      int64_t total = 0;
      list_starts[c].reserve(column.list_lengths.size() + 1);
      for (int64_t length : column.list_lengths) {
        if (length < 0) {
          throw core::InputError(where + ": column " + column.name, "list lengths >= 0",
                                 std::to_string(length));
        }
        list_starts[c].push_back(total);
        total += length;
      }
      list_starts[c].push_back(total);
      if (total != column.values()) {
        throw core::InputError(where + ": column " + column.name,
                               "list lengths adding up to its " +
                                   std::to_string(column.values()) + " values",
                               std::to_string(total));
      }
    }
  }

  std::string file(kMagic, 4);
  struct RowGroupInfo {
    int64_t rows = 0;
    std::vector<ChunkInfo> chunks;
  };
  std::vector<RowGroupInfo> groups;
  for (int64_t first = 0; first < rows || (first == 0 && groups.empty()); first += rows_per_group) {
    const int64_t last = std::min(rows, first + rows_per_group);
    RowGroupInfo group;
    group.rows = last - first;
    for (size_t c = 0; c < table.columns.size(); ++c) {
      const ParquetColumn& column = table.columns[c];
      std::string page;
      int64_t num_values = group.rows;
      if (column.list) {
        std::vector<uint8_t> repetition;
        std::vector<uint8_t> definition;
        for (int64_t r = first; r < last; ++r) {
          const int64_t length = column.list_lengths[static_cast<size_t>(r)];
          if (length == 0) {  // an empty list: one level pair, no value
            repetition.push_back(0);
            definition.push_back(0);
          }
          for (int64_t k = 0; k < length; ++k) {
            repetition.push_back(k == 0 ? 0 : 1);
            definition.push_back(1);
          }
        }
        num_values = static_cast<int64_t>(repetition.size());
        page = encode_levels(repetition) + encode_levels(definition);
        plain_values(page, column, list_starts[c][static_cast<size_t>(first)],
                     list_starts[c][static_cast<size_t>(last)]);
      } else {
        plain_values(page, column, first, last);
      }
      CompactWriter header;
      header.i32(1, kPageData);
      header.i32(2, static_cast<int32_t>(page.size()));
      header.i32(3, static_cast<int32_t>(page.size()));
      header.begin_struct(5);  // DataPageHeader
      header.i32(1, static_cast<int32_t>(num_values));
      header.i32(2, kEncodingPlain);
      header.i32(3, kEncodingRle);
      header.i32(4, kEncodingRle);
      header.end_struct();
      header.stop();
      ChunkInfo chunk;
      chunk.offset = static_cast<int64_t>(file.size());
      chunk.size = static_cast<int64_t>(header.out.size() + page.size());
      chunk.num_values = num_values;
      file += header.out;
      file += page;
      group.chunks.push_back(chunk);
    }
    groups.push_back(std::move(group));
    if (rows == 0) break;
  }

  CompactWriter meta;
  meta.i32(1, 1);  // version
  int64_t schema_size = 1;
  for (const ParquetColumn& column : table.columns) schema_size += column.list ? 3 : 1;
  meta.list(2, kCompactStruct, static_cast<size_t>(schema_size));
  meta.begin_struct_element();  // the root
  meta.binary(4, "schema");
  meta.i32(5, static_cast<int32_t>(table.columns.size()));
  meta.end_struct();
  for (const ParquetColumn& column : table.columns) {
    if (!column.list) {
      schema_leaf(meta, column.name, column.type);
      continue;
    }
    meta.begin_struct_element();
    meta.i32(3, kRequired);
    meta.binary(4, column.name);
    meta.i32(5, 1);
    meta.i32(6, kConvertedList);
    meta.begin_struct(10);  // LogicalType union: LIST (field 3, an empty struct)
    meta.begin_struct(3);
    meta.end_struct();
    meta.end_struct();
    meta.end_struct();
    meta.begin_struct_element();
    meta.i32(3, kRepeated);
    meta.binary(4, "list");
    meta.i32(5, 1);
    meta.end_struct();
    schema_leaf(meta, "element", column.type);
  }
  meta.i64(3, rows);
  meta.list(4, kCompactStruct, groups.size());
  for (const RowGroupInfo& group : groups) {
    meta.begin_struct_element();
    meta.list(1, kCompactStruct, group.chunks.size());
    int64_t group_bytes = 0;
    for (size_t c = 0; c < group.chunks.size(); ++c) {
      const ParquetColumn& column = table.columns[c];
      const ChunkInfo& chunk = group.chunks[c];
      group_bytes += chunk.size;
      meta.begin_struct_element();
      meta.i64(2, chunk.offset);
      meta.begin_struct(3);  // ColumnMetaData
      meta.i32(1, physical_type(column.type));
      meta.list(2, kCompactI32, 2);
      meta.i32_element(kEncodingPlain);
      meta.i32_element(kEncodingRle);
      if (column.list) {
        meta.list(3, kCompactBinary, 3);
        meta.binary_element(column.name);
        meta.binary_element("list");
        meta.binary_element("element");
      } else {
        meta.list(3, kCompactBinary, 1);
        meta.binary_element(column.name);
      }
      meta.i32(4, kCodecUncompressed);
      meta.i64(5, chunk.num_values);
      meta.i64(6, chunk.size);
      meta.i64(7, chunk.size);
      meta.i64(9, chunk.offset);
      meta.end_struct();
      meta.end_struct();
    }
    meta.i64(2, group_bytes);
    meta.i64(3, group.rows);
    meta.i64(5, group.chunks.empty() ? 4 : group.chunks.front().offset);
    meta.i64(6, group_bytes);
    meta.end_struct();
  }
  if (!table.metadata.empty()) {
    meta.list(5, kCompactStruct, table.metadata.size());
    for (const auto& [key, value] : table.metadata) {
      meta.begin_struct_element();
      meta.binary(1, key);
      meta.binary(2, value);
      meta.end_struct();
    }
  }
  meta.binary(6, "hribench parquet writer (docs/datasets.md)");
  meta.stop();
  file += meta.out;
  put_le<uint32_t>(file, static_cast<uint32_t>(meta.out.size()));
  file.append(kMagic, 4);
  core::write_file_atomically(path, file);
}

// ---------------------------------------------------------------------------------------------
// Reading.

namespace {

// A decoded Thrift compact value: a struct (fields by id), a list, an integer, a binary or a bool.
struct Thrift {
  int64_t integer = 0;
  std::string binary;
  std::vector<Thrift> list;
  std::map<int16_t, Thrift> fields;

  const Thrift* field(int16_t id) const {
    const auto it = fields.find(id);
    return it == fields.end() ? nullptr : &it->second;
  }
};

class Reader {
 public:
  Reader(const std::string& bytes, size_t position, std::string where)
      : bytes_(bytes), position_(position), where_(std::move(where)) {}

  size_t position() const { return position_; }

  Thrift read_struct() {
    Thrift result;
    int16_t last = 0;
    while (true) {
      const uint8_t header = byte();
      if (header == 0) return result;
      const uint8_t type = header & 0x0F;
      const int delta = header >> 4;
      const auto id = static_cast<int16_t>(delta != 0 ? last + delta : unzigzag(varint()));
      last = id;
      result.fields[id] = read_value(type);
    }
  }

  uint64_t varint() {
    uint64_t value = 0;
    for (int shift = 0; shift < 64; shift += 7) {
      const uint8_t b = byte();
      value |= static_cast<uint64_t>(b & 0x7F) << shift;
      if ((b & 0x80) == 0) return value;
    }
    fail("a varint of at most 10 bytes");
  }

  uint8_t byte() {
    if (position_ >= bytes_.size()) fail("more bytes (the file is truncated)");
    return static_cast<uint8_t>(bytes_[position_++]);
  }

  std::string take(uint64_t n) {
    if (n > bytes_.size() - position_) fail("more bytes (the file is truncated)");
    std::string out = bytes_.substr(position_, n);
    position_ += n;
    return out;
  }

  [[noreturn]] void fail(const std::string& expected) const {
    throw core::InputError(where_ + ": byte " + std::to_string(position_), expected,
                           "something else");
  }

 private:
  static int64_t unzigzag(uint64_t value) {
    return static_cast<int64_t>(value >> 1) ^ -static_cast<int64_t>(value & 1);
  }

  Thrift read_value(uint8_t type) {
    Thrift value;
    switch (type) {
      case kCompactTrue:
        value.integer = 1;
        break;
      case kCompactFalse:
        value.integer = 0;
        break;
      case 3:  // byte
        value.integer = static_cast<int8_t>(byte());
        break;
      case 4:  // i16
      case kCompactI32:
      case kCompactI64:
        value.integer = unzigzag(varint());
        break;
      case 7:  // double
        take(8);
        break;
      case kCompactBinary:
        value.binary = take(varint());
        break;
      case kCompactList:
      case 10: {  // set
        const uint8_t header = byte();
        uint64_t size = header >> 4;
        if (size == 15) size = varint();
        const uint8_t element = header & 0x0F;
        for (uint64_t i = 0; i < size; ++i) {
          if (element == kCompactTrue || element == kCompactFalse) {
            Thrift item;
            item.integer = byte() == kCompactTrue ? 1 : 0;
            value.list.push_back(std::move(item));
          } else {
            value.list.push_back(read_value(element));
          }
        }
        break;
      }
      case kCompactStruct:
        value = read_struct();
        break;
      default:
        fail("a Thrift compact type this reader knows (not a map)");
    }
    return value;
  }

  const std::string& bytes_;
  size_t position_;
  std::string where_;
};

int64_t integer_of(const Thrift& node, int16_t id, const std::string& where, const char* what) {
  const Thrift* field = node.field(id);
  if (field == nullptr) {
    throw core::InputError(where, std::string("the field ") + what, "none");
  }
  return field->integer;
}

// RLE/bit-packed hybrid levels of bit width 1, `count` of them, after their 4-byte length.
std::vector<uint8_t> decode_levels(Reader& reader, size_t count) {
  uint32_t length = 0;
  const std::string prefix = reader.take(4);
  std::memcpy(&length, prefix.data(), 4);
  const size_t end = reader.position() + length;
  std::vector<uint8_t> levels;
  levels.reserve(count);
  while (reader.position() < end && levels.size() < count) {
    const uint64_t header = reader.varint();
    if ((header & 1) == 0) {
      const uint8_t value = reader.byte();
      levels.insert(levels.end(), header >> 1, value);
    } else {
      const uint64_t bytes = header >> 1;  // groups of 8 values, one byte per group at width 1
      for (uint64_t g = 0; g < bytes; ++g) {
        const uint8_t b = reader.byte();
        for (int bit = 0; bit < 8; ++bit) levels.push_back(static_cast<uint8_t>((b >> bit) & 1));
      }
    }
  }
  if (levels.size() < count) reader.fail(std::to_string(count) + " levels");
  levels.resize(count);
  if (reader.position() != end) reader.fail("levels ending where their length says");
  return levels;
}

void read_plain(Reader& reader, ParquetColumn& column, size_t count) {
  switch (column.type) {
    case ParquetType::kInt64: {
      const std::string bytes = reader.take(count * 8);
      const size_t at = column.int64s.size();
      column.int64s.resize(at + count);
      std::memcpy(column.int64s.data() + at, bytes.data(), bytes.size());
      break;
    }
    case ParquetType::kFloat32: {
      const std::string bytes = reader.take(count * 4);
      const size_t at = column.float32s.size();
      column.float32s.resize(at + count);
      std::memcpy(column.float32s.data() + at, bytes.data(), bytes.size());
      break;
    }
    case ParquetType::kFloat64: {
      const std::string bytes = reader.take(count * 8);
      const size_t at = column.float64s.size();
      column.float64s.resize(at + count);
      std::memcpy(column.float64s.data() + at, bytes.data(), bytes.size());
      break;
    }
    case ParquetType::kBool: {
      const std::string bytes = reader.take((count + 7) / 8);
      for (size_t i = 0; i < count; ++i) {
        column.bools.push_back(((static_cast<uint8_t>(bytes[i / 8]) >> (i % 8)) & 1) != 0);
      }
      break;
    }
    case ParquetType::kString:
      for (size_t i = 0; i < count; ++i) {
        uint32_t length = 0;
        const std::string prefix = reader.take(4);
        std::memcpy(&length, prefix.data(), 4);
        column.strings.push_back(reader.take(length));
      }
      break;
  }
}

ParquetType type_of(int64_t physical, const std::string& where) {
  switch (physical) {
    case kTypeInt64:
      return ParquetType::kInt64;
    case kTypeFloat:
      return ParquetType::kFloat32;
    case kTypeDouble:
      return ParquetType::kFloat64;
    case kTypeBoolean:
      return ParquetType::kBool;
    case kTypeByteArray:
      return ParquetType::kString;
    default:
      throw core::InputError(where, "a column of INT64, FLOAT, DOUBLE, BOOLEAN or BYTE_ARRAY",
                             "physical type " + std::to_string(physical));
  }
}

}  // namespace

ParquetTable read_parquet(const std::filesystem::path& path) {
  const std::string where = path.string();
  std::ifstream in(path, std::ios::binary);
  if (!in) throw core::InputError::Message(where, "cannot open the file");
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string bytes = buffer.str();
  if (bytes.size() < 12 || bytes.compare(0, 4, kMagic) != 0 ||
      bytes.compare(bytes.size() - 4, 4, kMagic) != 0) {
    throw core::InputError(where, "a Parquet file (PAR1 at both ends)",
                           std::to_string(bytes.size()) + " bytes without it");
  }
  uint32_t footer_length = 0;
  std::memcpy(&footer_length, bytes.data() + bytes.size() - 8, 4);
  if (footer_length > bytes.size() - 12) {
    throw core::InputError(where, "a footer inside the file",
                           std::to_string(footer_length) + " bytes");
  }
  Reader footer(bytes, bytes.size() - 8 - footer_length, where);
  const Thrift meta = footer.read_struct();

  ParquetTable table;
  const Thrift* schema = meta.field(2);
  if (schema == nullptr || schema->list.empty()) {
    throw core::InputError(where, "a schema", "none");
  }
  size_t s = 1;
  while (s < schema->list.size()) {
    const Thrift& element = schema->list[s];
    ParquetColumn column;
    column.name = element.field(4) != nullptr ? element.field(4)->binary : "";
    const std::string column_where = where + ": column " + column.name;
    if (element.field(5) != nullptr) {  // a group: LIST, then the repeated group, then the leaf
      if (s + 2 >= schema->list.size() || element.field(5)->integer != 1 ||
          schema->list[s + 1].field(3) == nullptr ||
          schema->list[s + 1].field(3)->integer != kRepeated) {
        throw core::InputError(column_where, "a 3-level LIST of a required leaf",
                               "another nested type");
      }
      column.list = true;
      s += 2;
    }
    const Thrift& leaf = schema->list[s];
    if (integer_of(leaf, 3, column_where, "repetition_type") != kRequired) {
      throw core::InputError(column_where, "REQUIRED values", "optional or repeated ones");
    }
    column.type = type_of(integer_of(leaf, 1, column_where, "type"), column_where);
    table.columns.push_back(std::move(column));
    ++s;
  }

  if (const Thrift* groups = meta.field(4)) {
    for (const Thrift& group : groups->list) {
      const Thrift* chunks = group.field(1);
      if (chunks == nullptr || chunks->list.size() != table.columns.size()) {
        throw core::InputError(where, std::to_string(table.columns.size()) +
                                          " column chunks per row group", "another count");
      }
      for (size_t c = 0; c < table.columns.size(); ++c) {
        ParquetColumn& column = table.columns[c];
        const std::string column_where = where + ": column " + column.name;
        const Thrift* chunk_meta = chunks->list[c].field(3);
        if (chunk_meta == nullptr) throw core::InputError(column_where, "column metadata", "none");
        if (integer_of(*chunk_meta, 4, column_where, "codec") != kCodecUncompressed) {
          throw core::InputError(column_where, "an uncompressed column",
                                 "codec " + std::to_string(chunk_meta->field(4)->integer));
        }
        const int64_t total = integer_of(*chunk_meta, 5, column_where, "num_values");
        const int64_t offset = integer_of(*chunk_meta, 9, column_where, "data_page_offset");
        if (offset < 4 || static_cast<uint64_t>(offset) >= bytes.size()) {
          throw core::InputError(column_where, "a data page inside the file",
                                 "offset " + std::to_string(offset));
        }
        Reader page(bytes, static_cast<size_t>(offset), column_where);
        int64_t done = 0;
        while (done < total) {
          const Thrift header = page.read_struct();
          const Thrift* data = header.field(5);
          if (integer_of(header, 1, column_where, "page type") != kPageData || data == nullptr ||
              integer_of(*data, 2, column_where, "encoding") != kEncodingPlain) {
            throw core::InputError(column_where, "PLAIN data pages (v1)", "another page");
          }
          const auto count = static_cast<size_t>(integer_of(*data, 1, column_where, "num_values"));
          const size_t page_end =
              page.position() + static_cast<size_t>(integer_of(header, 3, column_where, "size"));
          if (column.list) {
            const std::vector<uint8_t> repetition = decode_levels(page, count);
            const std::vector<uint8_t> definition = decode_levels(page, count);
            size_t present = 0;
            for (size_t i = 0; i < count; ++i) {
              if (repetition[i] == 0) column.list_lengths.push_back(0);
              if (definition[i] == 1) {
                ++column.list_lengths.back();
                ++present;
              }
            }
            read_plain(page, column, present);
          } else {
            read_plain(page, column, count);
          }
          if (page.position() != page_end) page.fail("a page ending where its header says");
          done += static_cast<int64_t>(count);
        }
      }
    }
  }
  if (const Thrift* key_values = meta.field(5)) {
    for (const Thrift& kv : key_values->list) {
      table.metadata.emplace_back(kv.field(1) != nullptr ? kv.field(1)->binary : "",
                                  kv.field(2) != nullptr ? kv.field(2)->binary : "");
    }
  }
  const int64_t rows = integer_of(meta, 3, where, "num_rows");
  for (const ParquetColumn& column : table.columns) {
    if (column.rows() != rows) {
      throw core::InputError(where + ": column " + column.name, std::to_string(rows) + " rows",
                             std::to_string(column.rows()));
    }
  }
  return table;
}

}  // namespace hribench::io

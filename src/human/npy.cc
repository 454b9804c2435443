#include "human/npy.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>
#include <fstream>
#include <memory>
#include <optional>
#include <sstream>

#include <fmt/format.h>
#include <zip.h>
#include <zlib.h>

#include "core/errors.h"

namespace hribench::human {
namespace {

[[noreturn]] void fail_at(std::string_view where, size_t byte, std::string expected, std::string got) {
  throw core::InputError(fmt::format("{}: byte {}", where, byte), std::move(expected), std::move(got));
}

std::string read_file(const std::filesystem::path& path, std::string_view what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw core::InputError::Message(path.string(), fmt::format("cannot open the {} file", what));
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

uint64_t le(std::string_view b, size_t at, int n) {
  uint64_t v = 0;
  for (int i = n - 1; i >= 0; --i) v = (v << 8) | static_cast<uint8_t>(b[at + static_cast<size_t>(i)]);
  return v;
}

void put_le(std::string& out, uint64_t v, int n) {
  for (int i = 0; i < n; ++i) out += static_cast<char>((v >> (8 * i)) & 0xff);
}

// The Python dict literal of an .npy header: {'descr': '<f4', 'fortran_order': False,
// 'shape': (2, 3), }.
struct Header {
  std::optional<std::string> descr;
  std::optional<bool> fortran_order;
  std::optional<std::vector<size_t>> shape;
};

class HeaderParser {
 public:
  HeaderParser(std::string_view text, size_t base, std::string_view where)
      : s_(text), base_(base), where_(where) {}

  Header parse() {
    Header h;
    skip();
    expect('{', "'{' opening the header dict");
    while (true) {
      skip();
      if (peek() == '}') break;
      const std::string key = string("a quoted key");
      skip();
      expect(':', "':' after a key");
      skip();
      if (key == "descr") {
        h.descr = string("a quoted dtype string for 'descr'");
      } else if (key == "fortran_order") {
        if (s_.substr(i_, 4) == "True") {
          h.fortran_order = true;
          i_ += 4;
        } else if (s_.substr(i_, 5) == "False") {
          h.fortran_order = false;
          i_ += 5;
        } else {
          fail("True or False for 'fortran_order'");
        }
      } else if (key == "shape") {
        h.shape = tuple();
      } else {
        fail(fmt::format("only the keys descr, fortran_order, shape (not '{}')", key));
      }
      skip();
      if (peek() == ',') ++i_;
    }
    return h;
  }

 private:
  [[noreturn]] void fail(std::string expected) const {
    fail_at(where_, base_ + i_, std::move(expected),
            i_ < s_.size() ? fmt::format("'{}'", s_[i_]) : "the end of the header");
  }
  char peek() const { return i_ < s_.size() ? s_[i_] : '\0'; }
  void skip() {
    while (i_ < s_.size() && (s_[i_] == ' ' || s_[i_] == '\n' || s_[i_] == '\t')) ++i_;
  }
  void expect(char c, std::string what) {
    if (peek() != c) fail(std::move(what));
    ++i_;
  }
  std::string string(std::string what) {
    const char q = peek();
    if (q != '\'' && q != '"') fail(std::move(what));
    const size_t end = s_.find(q, i_ + 1);
    if (end == std::string_view::npos) fail("a closing quote");
    std::string v(s_.substr(i_ + 1, end - i_ - 1));
    i_ = end + 1;
    return v;
  }
  std::vector<size_t> tuple() {
    expect('(', "a shape tuple '(...)'");
    std::vector<size_t> dims;
    while (true) {
      skip();
      if (peek() == ')') {
        ++i_;
        return dims;
      }
      if (peek() < '0' || peek() > '9') fail("a non-negative integer in the shape");
      uint64_t v = 0;
      while (peek() >= '0' && peek() <= '9') {
        v = v * 10 + static_cast<uint64_t>(peek() - '0');
        if (v > (uint64_t{1} << 40)) fail("a shape dimension below 2^40");
        ++i_;
      }
      while (peek() == 'L') ++i_;  // Python 2 long suffix
      dims.push_back(static_cast<size_t>(v));
      skip();
      if (peek() == ',') ++i_;
      else if (peek() != ')') fail("',' or ')' in the shape");
    }
  }

  std::string_view s_;
  size_t base_;
  std::string_view where_;
  size_t i_ = 0;
};

}  // namespace

size_t NpyArray::size() const {
  size_t n = 1;
  for (const size_t d : shape) n *= d;
  return n;
}

NpyArray parse_npy_layout(std::string_view b, std::string_view where) {
  static constexpr std::string_view kMagic = "\x93NUMPY";
  if (b.size() < 10 || b.substr(0, 6) != kMagic) {
    fail_at(where, 0, "the .npy magic \\x93NUMPY", b.size() < 10 ? fmt::format("{} bytes", b.size()) : "other bytes");
  }
  const int major = static_cast<uint8_t>(b[6]);
  if (major < 1 || major > 3) fail_at(where, 6, "format version 1, 2 or 3", std::to_string(major));
  const size_t len_size = major == 1 ? 2 : 4;
  if (b.size() < 8 + len_size) fail_at(where, 8, "the header length", "end of data");
  const size_t header_len = le(b, 8, static_cast<int>(len_size));
  const size_t header_start = 8 + len_size;
  if (header_start + header_len > b.size()) {
    fail_at(where, header_start, fmt::format("a header of {} bytes", header_len),
            fmt::format("{} bytes (truncated)", b.size() - header_start));
  }
  const Header h = HeaderParser(b.substr(header_start, header_len), header_start, where).parse();
  if (!h.descr || !h.fortran_order || !h.shape) {
    fail_at(where, header_start, "a header with descr, fortran_order and shape", "a key missing");
  }
  NpyArray a;
  a.descr = *h.descr;
  a.shape = *h.shape;
  if (a.descr == "|O" || a.descr == "O" || a.descr == "<O" || a.descr == ">O") {
    fail_at(where, header_start, "a numeric array", "dtype 'O' (pickled Python objects, refused)");
  }
  if (*h.fortran_order) fail_at(where, header_start, "C order (fortran_order False)", "fortran_order True");
  a.data_offset = header_start + header_len;
  return a;
}

NpyArray parse_npy(std::string_view b, std::string_view where) {
  NpyArray a = parse_npy_layout(b, where);
  const size_t header_start = 8 + (static_cast<uint8_t>(b[6]) == 1 ? 2 : 4);
  const std::string& d = a.descr;
  const bool ok_type = d.size() == 3 && (d[0] == '<' || d[0] == '>' || d[0] == '=' || d[0] == '|') &&
                       ((d[1] == 'f' && (d[2] == '4' || d[2] == '8')) || (d[1] == 'i' && (d[2] == '4' || d[2] == '8')));
  if (!ok_type) {
    fail_at(where, header_start, "dtype float32, float64, int32 or int64 ('<f4', '<f8', '<i4', '<i8')",
            fmt::format("'{}'", d));
  }
  a.item_size = static_cast<size_t>(d[2] - '0');
  const size_t available = b.size() - a.data_offset;
  size_t n = 1;
  for (const size_t dim : a.shape) {
    if (dim != 0 && n > available / dim) {
      fail_at(where, a.data_offset, "data for the shape in the header", fmt::format("only {} bytes", available));
    }
    n *= dim;
  }
  if (n * a.item_size != available) {
    fail_at(where, a.data_offset, fmt::format("{} bytes of data ({} values)", n * a.item_size, n),
            fmt::format("{} bytes{}", available, available < n * a.item_size ? " (truncated)" : ""));
  }
  const bool swap = (d[0] == '>') == (std::endian::native == std::endian::little);
  a.values.resize(n);
  std::array<char, 8> raw{};
  for (size_t i = 0; i < n; ++i) {
    std::memcpy(raw.data(), b.data() + a.data_offset + i * a.item_size, a.item_size);
    if (swap && d[0] != '=' && d[0] != '|') std::reverse(raw.begin(), raw.begin() + static_cast<long>(a.item_size));
    if (d[1] == 'f' && a.item_size == 4) {
      float f;
      std::memcpy(&f, raw.data(), 4);
      a.values[i] = static_cast<double>(f);
    } else if (d[1] == 'f') {
      std::memcpy(&a.values[i], raw.data(), 8);
    } else if (a.item_size == 4) {
      int32_t v;
      std::memcpy(&v, raw.data(), 4);
      a.values[i] = v;
    } else {
      int64_t v;
      std::memcpy(&v, raw.data(), 8);
      a.values[i] = static_cast<double>(v);
    }
  }
  return a;
}

NpyArray read_npy(const std::filesystem::path& path) {
  return parse_npy(read_file(path, ".npy"), path.string());
}

std::string npy_header(std::string_view descr, const std::vector<size_t>& shape) {
  std::string dims;
  for (const size_t d : shape) dims += fmt::format("{}, ", d);
  if (shape.size() > 1) dims.resize(dims.size() - 2);
  else if (shape.size() == 1) dims.pop_back();
  std::string header =
      fmt::format("{{'descr': '{}', 'fortran_order': False, 'shape': ({}), }}", descr, dims);
  while ((10 + header.size() + 1) % 64 != 0) header += ' ';
  header += '\n';
  std::string out = "\x93NUMPY";
  out += '\x01';
  out += '\x00';
  put_le(out, header.size(), 2);
  out += header;
  return out;
}

std::string format_npy(const std::vector<size_t>& shape, const std::vector<double>& values, NpyType type) {
  size_t n = 1;
  for (const size_t d : shape) n *= d;
  if (n != values.size()) throw std::logic_error("format_npy: shape does not match values");
  std::string out = npy_header(type == NpyType::kFloat32 ? "<f4" : "<f8", shape);
  for (const double v : values) {
    if (type == NpyType::kFloat32) {
      const auto f = static_cast<float>(v);
      uint32_t bits;
      std::memcpy(&bits, &f, 4);
      put_le(out, bits, 4);
    } else {
      uint64_t bits;
      std::memcpy(&bits, &v, 8);
      put_le(out, bits, 8);
    }
  }
  return out;
}

// ---- zip archives, read through libzip -------------------------------------------------------

namespace {

// An archive open on `bytes` (which must outlive it), closed when it goes out of scope.
struct ZipDeleter {
  void operator()(zip_t* archive) const { zip_discard(archive); }
};
using ZipArchive = std::unique_ptr<zip_t, ZipDeleter>;

ZipArchive open_zip(std::string_view bytes, std::string_view where) {
  zip_error_t error;
  zip_error_init(&error);
  zip_source_t* source = zip_source_buffer_create(bytes.data(), bytes.size(), 0, &error);
  zip_t* archive = source == nullptr ? nullptr : zip_open_from_source(source, ZIP_RDONLY | ZIP_CHECKCONS, &error);
  if (archive == nullptr) {
    if (source != nullptr) zip_source_free(source);
    const std::string reason = zip_error_strerror(&error);
    zip_error_fini(&error);
    throw core::InputError(std::string(where), "a zip archive (npz)", reason);
  }
  zip_error_fini(&error);
  return ZipArchive(archive);
}

// The largest member we decompress, and DEFLATE's best ratio (258 bytes from 2 bits, and some):
// a declared size beyond either is refused before anything is allocated.
constexpr uint64_t kMaxMemberBytes = uint64_t{2} << 30;  // 2 GiB
constexpr uint64_t kMaxDeflateRatio = 1100;

}  // namespace

NpzArchive::NpzArchive(std::string bytes, std::string where) : bytes_(std::move(bytes)), where_(std::move(where)) {
  const ZipArchive archive = open_zip(bytes_, where_);
  const zip_int64_t entries = zip_get_num_entries(archive.get(), 0);
  for (zip_int64_t i = 0; i < entries; ++i) {
    const char* name = zip_get_name(archive.get(), static_cast<zip_uint64_t>(i), ZIP_FL_ENC_RAW);
    if (name == nullptr) {
      throw core::InputError(where_, fmt::format("a name for zip member {}", i), zip_strerror(archive.get()));
    }
    std::string key = name;
    if (key.size() > 4 && key.ends_with(".npy")) key.resize(key.size() - 4);
    members_[key] = static_cast<uint64_t>(i);
  }
}

NpzArchive NpzArchive::Read(const std::filesystem::path& path) {
  return NpzArchive(read_file(path, ".npz"), path.string());
}

std::vector<std::string> NpzArchive::keys() const {
  std::vector<std::string> k;
  for (const auto& [name, index] : members_) k.push_back(name);
  return k;
}

bool NpzArchive::contains(std::string_view key) const { return members_.find(key) != members_.end(); }

NpyArray NpzArchive::array(std::string_view key) const {
  const auto it = members_.find(key);
  if (it == members_.end()) {
    std::string list;
    for (const auto& [name, index] : members_) list += (list.empty() ? "" : ", ") + name;
    throw core::InputError(fmt::format("{}[{}]", where_, key), fmt::format("an array '{}'", key),
                           fmt::format("keys {}", list.empty() ? "(none)" : list));
  }
  const std::string where = fmt::format("{}[{}.npy]", where_, key);
  const ZipArchive archive = open_zip(bytes_, where_);
  zip_stat_t stat;
  zip_stat_init(&stat);
  if (zip_stat_index(archive.get(), it->second, 0, &stat) != 0) {
    throw core::InputError(where, "a readable zip member", zip_strerror(archive.get()));
  }
  // The declared size is checked before it is trusted: libzip stops at it while reading, and
  // only what DEFLATE could have produced from the stored bytes is reserved.
  const bool sized = (stat.valid & ZIP_STAT_SIZE) && (stat.valid & ZIP_STAT_COMP_SIZE);
  if (!sized || stat.size > kMaxMemberBytes || stat.size > stat.comp_size * kMaxDeflateRatio + 1024) {
    throw core::InputError(where, fmt::format("a member of at most {} bytes that its {} stored bytes can hold",
                                              kMaxMemberBytes, sized ? stat.comp_size : 0),
                           sized ? fmt::format("{} bytes declared", stat.size) : "no size");
  }
  zip_file_t* file = zip_fopen_index(archive.get(), it->second, 0);
  if (file == nullptr) throw core::InputError(where, "a readable zip member", zip_strerror(archive.get()));
  std::string content(static_cast<size_t>(stat.size), '\0');
  const zip_int64_t read = zip_fread(file, content.data(), stat.size);
  // One byte more than declared must not be there; the CRC is checked by libzip at the end.
  char extra = 0;
  const zip_int64_t more = read == static_cast<zip_int64_t>(stat.size) ? zip_fread(file, &extra, 1) : 0;
  std::string reason = read < 0 || more < 0 ? zip_file_strerror(file) : "";
  zip_fclose(file);
  if (!reason.empty()) throw core::InputError(where, "an intact zip member", reason);
  if (read != static_cast<zip_int64_t>(stat.size) || more != 0) {
    throw core::InputError(where, fmt::format("{} decompressed bytes", stat.size),
                           more != 0 ? "more" : fmt::format("{}", read));
  }
  return parse_npy(content, where);
}

std::string format_npz(const std::map<std::string, std::string>& members) {
  std::string out;
  std::string directory;
  for (const auto& member : members) {
    const std::string file = member.first + ".npy";
    const std::string& content = member.second;
    const auto crc = static_cast<uint32_t>(
        ::crc32(::crc32(0L, Z_NULL, 0), reinterpret_cast<const Bytef*>(content.data()), static_cast<uInt>(content.size())));
    const size_t offset = out.size();
    // Fields shared by the local header and the directory entry: no flags, stored, DOS time 0
    // and date 1980-01-01, CRC, sizes, name length, no extra field.
    const std::array<std::pair<uint64_t, int>, 9> shared = {{{0, 2}, {0, 2}, {0, 2}, {0x21, 2}, {crc, 4},
                                                            {content.size(), 4}, {content.size(), 4},
                                                            {file.size(), 2}, {0, 2}}};
    put_le(out, 0x04034b50u, 4);
    put_le(out, 20, 2);  // version needed
    for (const auto& [value, bytes] : shared) put_le(out, value, bytes);
    out += file;
    out += content;
    put_le(directory, 0x02014b50u, 4);
    put_le(directory, 20, 2);  // version made by
    put_le(directory, 20, 2);  // version needed
    for (const auto& [value, bytes] : shared) put_le(directory, value, bytes);
    put_le(directory, 0, 2);  // comment length
    put_le(directory, 0, 2);  // disk number
    put_le(directory, 0, 2);  // internal attributes
    put_le(directory, 0, 4);  // external attributes
    put_le(directory, offset, 4);
    directory += file;
  }
  const size_t cd_offset = out.size();
  out += directory;
  put_le(out, 0x06054b50u, 4);
  put_le(out, 0, 2);
  put_le(out, 0, 2);
  put_le(out, members.size(), 2);
  put_le(out, members.size(), 2);
  put_le(out, directory.size(), 4);
  put_le(out, cd_offset, 4);
  put_le(out, 0, 2);
  return out;
}

}  // namespace hribench::human

#include "human/npy.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>
#include <fstream>
#include <optional>
#include <sstream>

#include <fmt/format.h>

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

NpyArray parse_npy(std::string_view b, std::string_view where) {
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
  const std::string& d = a.descr;
  if (d == "|O" || d == "O" || d == "<O" || d == ">O") {
    fail_at(where, header_start, "a numeric array", "dtype 'O' (pickled Python objects, refused)");
  }
  const bool ok_type = d.size() == 3 && (d[0] == '<' || d[0] == '>' || d[0] == '=' || d[0] == '|') &&
                       ((d[1] == 'f' && (d[2] == '4' || d[2] == '8')) || (d[1] == 'i' && (d[2] == '4' || d[2] == '8')));
  if (!ok_type) {
    fail_at(where, header_start, "dtype float32, float64, int32 or int64 ('<f4', '<f8', '<i4', '<i8')",
            fmt::format("'{}'", d));
  }
  if (*h.fortran_order) fail_at(where, header_start, "C order (fortran_order False)", "fortran_order True");
  a.item_size = static_cast<size_t>(d[2] - '0');
  a.data_offset = header_start + header_len;
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

std::string format_npy(const std::vector<size_t>& shape, const std::vector<double>& values, NpyType type) {
  size_t n = 1;
  for (const size_t d : shape) n *= d;
  if (n != values.size()) throw std::logic_error("format_npy: shape does not match values");
  std::string dims;
  for (const size_t d : shape) dims += fmt::format("{}, ", d);
  if (shape.size() > 1) dims.resize(dims.size() - 2);
  else if (shape.size() == 1) dims.pop_back();
  std::string header = fmt::format("{{'descr': '{}', 'fortran_order': False, 'shape': ({}), }}",
                                   type == NpyType::kFloat32 ? "<f4" : "<f8", dims);
  while ((10 + header.size() + 1) % 64 != 0) header += ' ';
  header += '\n';
  std::string out = "\x93NUMPY";
  out += '\x01';
  out += '\x00';
  put_le(out, header.size(), 2);
  out += header;
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

// ---- CRC-32 and raw DEFLATE -------------------------------------------------------------------

uint32_t crc32(std::string_view bytes) {
  static const std::array<uint32_t, 256> table = [] {
    std::array<uint32_t, 256> t{};
    for (uint32_t i = 0; i < 256; ++i) {
      uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  uint32_t c = 0xFFFFFFFFu;
  for (const char ch : bytes) c = table[(c ^ static_cast<uint8_t>(ch)) & 0xff] ^ (c >> 8);
  return c ^ 0xFFFFFFFFu;
}

namespace {

// Canonical Huffman code: counts per length and symbols in code order (RFC 1951 §3.2.2).
struct Huffman {
  std::array<int, 16> count{};
  std::vector<int> symbol;
};

class Inflater {
 public:
  Inflater(std::string_view in, size_t expected, std::string_view where)
      : in_(in), expected_(expected), where_(where) {}

  std::string run() {
    out_.reserve(expected_);
    int last = 0;
    do {
      last = bits(1);
      const int type = bits(2);
      if (type == 0) stored();
      else if (type == 1) fixed();
      else if (type == 2) dynamic();
      else fail("a block type 0, 1 or 2", "type 3");
    } while (!last);
    return std::move(out_);
  }

 private:
  [[noreturn]] void fail(std::string expected, std::string got) const {
    fail_at(where_, pos_, std::move(expected), std::move(got));
  }
  int bits(int need) {
    uint32_t v = bitbuf_;
    while (bitcnt_ < need) {
      if (pos_ >= in_.size()) fail("more compressed data", "the end of the stream");
      v |= static_cast<uint32_t>(static_cast<uint8_t>(in_[pos_++])) << bitcnt_;
      bitcnt_ += 8;
    }
    bitbuf_ = v >> need;
    bitcnt_ -= need;
    return static_cast<int>(v & ((1u << need) - 1));
  }
  void emit(char c) {
    if (out_.size() >= expected_) fail(fmt::format("at most {} decompressed bytes", expected_), "more");
    out_ += c;
  }
  void stored() {
    bitbuf_ = 0;
    bitcnt_ = 0;
    if (pos_ + 4 > in_.size()) fail("a stored block length", "the end of the stream");
    const auto len = static_cast<size_t>(le(in_, pos_, 2));
    const auto nlen = static_cast<size_t>(le(in_, pos_ + 2, 2));
    if (len != (~nlen & 0xffff)) fail("a stored block length and its complement", "a mismatch");
    pos_ += 4;
    if (pos_ + len > in_.size()) fail(fmt::format("{} stored bytes", len), "the end of the stream");
    for (size_t i = 0; i < len; ++i) emit(in_[pos_ + i]);
    pos_ += len;
  }
  Huffman build(const int* lengths, int n) const {
    Huffman h;
    h.symbol.assign(static_cast<size_t>(n), 0);
    for (int s = 0; s < n; ++s) h.count[static_cast<size_t>(lengths[s])]++;
    int left = 1;
    for (size_t len = 1; len < 16; ++len) {
      left = left * 2 - h.count[len];
      if (left < 0) fail("a valid Huffman code", "an over-subscribed code");
    }
    std::array<int, 16> offs{};
    for (size_t len = 1; len < 15; ++len) offs[len + 1] = offs[len] + h.count[len];
    for (int s = 0; s < n; ++s) {
      if (lengths[s] != 0) h.symbol[static_cast<size_t>(offs[static_cast<size_t>(lengths[s])]++)] = s;
    }
    h.count[0] = 0;
    return h;
  }
  int decode(const Huffman& h) {
    int code = 0, first = 0, index = 0;
    for (size_t len = 1; len < 16; ++len) {
      code |= bits(1);
      const int count = h.count[len];
      if (code - count < first) return h.symbol[static_cast<size_t>(index + (code - first))];
      index += count;
      first += count;
      first <<= 1;
      code <<= 1;
    }
    fail("a valid Huffman code", "an unused code");
  }
  void codes(const Huffman& lencode, const Huffman& distcode) {
    static constexpr std::array<int, 29> kLenBase = {3, 4, 5, 6, 7, 8, 9, 10, 11, 13, 15, 17, 19, 23, 27,
                                                      31, 35, 43, 51, 59, 67, 83, 99, 115, 131, 163, 195, 227, 258};
    static constexpr std::array<int, 29> kLenExtra = {0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2,
                                                       2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0};
    static constexpr std::array<int, 30> kDistBase = {1, 2, 3, 4, 5, 7, 9, 13, 17, 25, 33, 49, 65, 97, 129,
                                                       193, 257, 385, 513, 769, 1025, 1537, 2049, 3073, 4097,
                                                       6145, 8193, 12289, 16385, 24577};
    static constexpr std::array<int, 30> kDistExtra = {0, 0, 0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6,
                                                        6, 7, 7, 8, 8, 9, 9, 10, 10, 11, 11, 12, 12, 13, 13};
    while (true) {
      int sym = decode(lencode);
      if (sym < 256) {
        emit(static_cast<char>(sym));
      } else if (sym == 256) {
        return;
      } else {
        sym -= 257;
        if (sym >= 29) fail("a length code below 286", std::to_string(sym + 257));
        const auto si = static_cast<size_t>(sym);
        const int len = kLenBase[si] + bits(kLenExtra[si]);
        const int dsym = decode(distcode);
        if (dsym >= 30) fail("a distance code below 30", std::to_string(dsym));
        const auto di = static_cast<size_t>(dsym);
        const auto dist = static_cast<size_t>(kDistBase[di] + bits(kDistExtra[di]));
        if (dist > out_.size()) fail("a distance within the output so far", fmt::format("{} > {}", dist, out_.size()));
        for (int k = 0; k < len; ++k) emit(out_[out_.size() - dist]);
      }
    }
  }
  void fixed() {
    std::array<int, 288> lengths{};
    for (size_t s = 0; s < 288; ++s) lengths[s] = s < 144 ? 8 : s < 256 ? 9 : s < 280 ? 7 : 8;
    std::array<int, 30> dist{};
    dist.fill(5);
    codes(build(lengths.data(), 288), build(dist.data(), 30));
  }
  void dynamic() {
    static constexpr std::array<size_t, 19> kOrder = {16, 17, 18, 0, 8, 7, 9, 6, 10, 5, 11, 4, 12, 3, 13, 2, 14, 1, 15};
    const int nlen = bits(5) + 257;
    const int ndist = bits(5) + 1;
    const int ncode = bits(4) + 4;
    if (nlen > 286 || ndist > 30) fail("at most 286 length and 30 distance codes", fmt::format("{} and {}", nlen, ndist));
    std::array<int, 320> lengths{};
    for (size_t i = 0; i < static_cast<size_t>(ncode); ++i) lengths[kOrder[i]] = bits(3);
    const Huffman lencode = build(lengths.data(), 19);
    lengths.fill(0);
    int index = 0;
    while (index < nlen + ndist) {
      int sym = decode(lencode);
      if (sym < 16) {
        lengths[static_cast<size_t>(index++)] = sym;
        continue;
      }
      int len = 0;
      if (sym == 16) {
        if (index == 0) fail("a previous length to repeat", "none");
        len = lengths[static_cast<size_t>(index - 1)];
        sym = 3 + bits(2);
      } else if (sym == 17) {
        sym = 3 + bits(3);
      } else {
        sym = 11 + bits(7);
      }
      if (index + sym > nlen + ndist) fail("code lengths within the declared count", "too many");
      while (sym-- > 0) lengths[static_cast<size_t>(index++)] = len;
    }
    if (lengths[256] == 0) fail("an end-of-block code", "none");
    const Huffman lit = build(lengths.data(), nlen);
    const Huffman dist = build(lengths.data() + nlen, ndist);
    codes(lit, dist);
  }

  std::string_view in_;
  size_t expected_;
  std::string_view where_;
  size_t pos_ = 0;
  uint32_t bitbuf_ = 0;
  int bitcnt_ = 0;
  std::string out_;
};

}  // namespace

std::string inflate_raw(std::string_view compressed, size_t expected_size, std::string_view where) {
  return Inflater(compressed, expected_size, where).run();
}

// ---- zip archives ---------------------------------------------------------------------------

NpzArchive::NpzArchive(std::string bytes, std::string where) : bytes_(std::move(bytes)), where_(std::move(where)) {
  const std::string_view b = bytes_;
  if (b.size() < 22 || b.substr(0, 2) != "PK") {
    fail_at(where_, 0, "a zip archive (npz) starting with 'PK'",
            b.size() < 22 ? fmt::format("{} bytes", b.size()) : "other bytes");
  }
  // End of central directory: the last "PK\5\6" within the final 64 KiB + 22 bytes.
  size_t eocd = std::string_view::npos;
  const size_t lowest = b.size() > 22 + 65535 ? b.size() - 22 - 65535 : 0;
  for (size_t i = b.size() - 22 + 1; i-- > lowest;) {
    if (le(b, i, 4) == 0x06054b50u) {
      eocd = i;
      break;
    }
  }
  if (eocd == std::string_view::npos) fail_at(where_, b.size(), "a zip end-of-central-directory record", "none");
  uint64_t entries = le(b, eocd + 10, 2);
  uint64_t cd_size = le(b, eocd + 12, 4);
  uint64_t cd_offset = le(b, eocd + 16, 4);
  if ((entries == 0xffff || cd_offset == 0xffffffffu) && eocd >= 20 && le(b, eocd - 20, 4) == 0x07064b50u) {
    const uint64_t rec = le(b, eocd - 20 + 8, 8);
    if (rec + 56 > b.size() || le(b, static_cast<size_t>(rec), 4) != 0x06064b50u) {
      fail_at(where_, eocd - 20, "a zip64 end-of-central-directory record", "a bad locator");
    }
    entries = le(b, static_cast<size_t>(rec) + 32, 8);
    cd_size = le(b, static_cast<size_t>(rec) + 40, 8);
    cd_offset = le(b, static_cast<size_t>(rec) + 48, 8);
  }
  if (cd_offset + cd_size > b.size()) fail_at(where_, eocd, "a central directory inside the file", "an offset past the end");
  size_t at = static_cast<size_t>(cd_offset);
  for (uint64_t e = 0; e < entries; ++e) {
    if (at + 46 > b.size() || le(b, at, 4) != 0x02014b50u) fail_at(where_, at, "a central directory entry", "other bytes");
    Member m;
    m.method = static_cast<uint16_t>(le(b, at + 10, 2));
    m.crc = static_cast<uint32_t>(le(b, at + 16, 4));
    m.compressed_size = le(b, at + 20, 4);
    m.size = le(b, at + 24, 4);
    const size_t name_len = le(b, at + 28, 2);
    const size_t extra_len = le(b, at + 30, 2);
    const size_t comment_len = le(b, at + 32, 2);
    m.local_header = le(b, at + 42, 4);
    if (at + 46 + name_len + extra_len + comment_len > b.size()) fail_at(where_, at, "a complete central directory entry", "the end of the file");
    const std::string name(b.substr(at + 46, name_len));
    // Zip64 extra field: the 32-bit fields that are 0xffffffff, in order.
    size_t x = at + 46 + name_len;
    const size_t x_end = x + extra_len;
    while (x + 4 <= x_end) {
      const uint64_t id = le(b, x, 2);
      const size_t len = le(b, x + 2, 2);
      if (id == 1) {
        size_t f = x + 4;
        if (m.size == 0xffffffffu && f + 8 <= x + 4 + len) { m.size = le(b, f, 8); f += 8; }
        if (m.compressed_size == 0xffffffffu && f + 8 <= x + 4 + len) { m.compressed_size = le(b, f, 8); f += 8; }
        if (m.local_header == 0xffffffffu && f + 8 <= x + 4 + len) m.local_header = le(b, f, 8);
      }
      x += 4 + len;
    }
    std::string key = name;
    if (key.size() > 4 && key.ends_with(".npy")) key.resize(key.size() - 4);
    members_[key] = m;
    at += 46 + name_len + extra_len + comment_len;
  }
}

NpzArchive NpzArchive::Read(const std::filesystem::path& path) {
  return NpzArchive(read_file(path, ".npz"), path.string());
}

std::vector<std::string> NpzArchive::keys() const {
  std::vector<std::string> k;
  for (const auto& [name, m] : members_) k.push_back(name);
  return k;
}

bool NpzArchive::contains(std::string_view key) const { return members_.find(key) != members_.end(); }

NpyArray NpzArchive::array(std::string_view key) const {
  const auto it = members_.find(key);
  if (it == members_.end()) {
    std::string list;
    for (const auto& [name, m] : members_) list += (list.empty() ? "" : ", ") + name;
    throw core::InputError(fmt::format("{}[{}]", where_, key), fmt::format("an array '{}'", key),
                           fmt::format("keys {}", list.empty() ? "(none)" : list));
  }
  const Member& m = it->second;
  const std::string where = fmt::format("{}[{}.npy]", where_, key);
  const std::string_view b = bytes_;
  const auto lh = static_cast<size_t>(m.local_header);
  if (lh + 30 > b.size() || le(b, lh, 4) != 0x04034b50u) fail_at(where_, lh, fmt::format("the local header of '{}'", key), "other bytes");
  const size_t data = lh + 30 + le(b, lh + 26, 2) + le(b, lh + 28, 2);
  if (data + m.compressed_size > b.size()) {
    fail_at(where_, data, fmt::format("{} bytes of '{}'", m.compressed_size, key), "the end of the file (truncated)");
  }
  const std::string_view raw = b.substr(data, static_cast<size_t>(m.compressed_size));
  std::string content;
  if (m.method == 0) {
    content = std::string(raw);
  } else if (m.method == 8) {
    content = inflate_raw(raw, static_cast<size_t>(m.size), where);
  } else {
    fail_at(where_, lh, fmt::format("compression method 0 (stored) or 8 (deflate) for '{}'", key), std::to_string(m.method));
  }
  if (content.size() != m.size) {
    fail_at(where, content.size(), fmt::format("{} decompressed bytes", m.size), std::to_string(content.size()));
  }
  if (crc32(content) != m.crc) fail_at(where_, data, fmt::format("member '{}' matching its CRC-32", key), "a mismatch (corrupted data)");
  return parse_npy(content, where);
}

std::string format_npz(const std::map<std::string, std::string>& members) {
  std::string out;
  std::string directory;
  for (const auto& [name, content] : members) {
    const std::string file = name + ".npy";
    const uint32_t crc = crc32(content);
    const size_t offset = out.size();
    // Fields shared by the local header and the directory entry: no flags, stored, DOS time 0
    // and date 1980-01-01, CRC, sizes, name length, no extra field.
    const auto shared = [&](std::string& to) {
      for (const auto& [value, bytes] : {std::pair<uint64_t, int>{0, 2}, {0, 2}, {0, 2}, {0x21, 2}, {crc, 4},
                                         {content.size(), 4}, {content.size(), 4}, {file.size(), 2}, {0, 2}}) {
        put_le(to, value, bytes);
      }
    };
    put_le(out, 0x04034b50u, 4);
    put_le(out, 20, 2);  // version needed
    shared(out);
    out += file;
    out += content;
    put_le(directory, 0x02014b50u, 4);
    put_le(directory, 20, 2);  // version made by
    put_le(directory, 20, 2);  // version needed
    shared(directory);
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

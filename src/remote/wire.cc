#include "remote/wire.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>

#include <fmt/format.h>
#include <msgpack.hpp>

#include "core/errors.h"
#include "human/npy.h"

namespace hribench::remote {
namespace {

// numpy half -> double (IEEE binary16).
double half_to_double(uint16_t h) {
  const int exponent = (h >> 10) & 0x1f;
  const int mantissa = h & 0x3ff;
  const double sign = (h & 0x8000) != 0 ? -1.0 : 1.0;
  if (exponent == 0) return sign * std::ldexp(mantissa, -24);
  if (exponent == 31) return mantissa == 0 ? sign * std::numeric_limits<double>::infinity() : std::numeric_limits<double>::quiet_NaN();
  return sign * std::ldexp(mantissa + 1024, exponent - 25);
}

template <class T>
T load(const char* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return v;
}

using Packer = msgpack::packer<msgpack::sbuffer>;

void pack_bin(Packer& pk, std::string_view bytes) {
  pk.pack_bin(static_cast<uint32_t>(bytes.size()));
  pk.pack_bin_body(bytes.data(), static_cast<uint32_t>(bytes.size()));
}

void pack_str(Packer& pk, std::string_view text) {
  pk.pack_str(static_cast<uint32_t>(text.size()));
  pk.pack_str_body(text.data(), static_cast<uint32_t>(text.size()));
}

void pack_array(Packer& pk, const NdArray& a, ArrayCodec codec) {
  if (codec == ArrayCodec::kGr00t) {
    pk.pack_map(2);
    pack_str(pk, "__ndarray_class__");
    pk.pack_true();
    pack_str(pk, "as_npy");
    const std::string npy = to_npy(a);
    pack_bin(pk, npy);
    return;
  }
  // openpi msgpack_numpy: the marker keys are Python bytes, i.e. msgpack bin.
  pk.pack_map(4);
  pack_bin(pk, "__ndarray__");
  pk.pack_true();
  pack_bin(pk, "data");
  pack_bin(pk, a.data);
  pack_bin(pk, "dtype");
  pack_str(pk, a.dtype);
  pack_bin(pk, "shape");
  pk.pack_array(static_cast<uint32_t>(a.shape.size()));
  for (const size_t d : a.shape) pk.pack_uint64(d);
}

void pack_value(Packer& pk, const Value& value, ArrayCodec codec) {
  std::visit(
      [&](const auto& x) {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, std::monostate>) {
          pk.pack_nil();
        } else if constexpr (std::is_same_v<T, bool>) {
          if (x) pk.pack_true();
          else pk.pack_false();
        } else if constexpr (std::is_same_v<T, int64_t>) {
          pk.pack_int64(x);
        } else if constexpr (std::is_same_v<T, double>) {
          pk.pack_double(x);
        } else if constexpr (std::is_same_v<T, std::string>) {
          pack_str(pk, x);
        } else if constexpr (std::is_same_v<T, Bin>) {
          pack_bin(pk, x.bytes);
        } else if constexpr (std::is_same_v<T, List>) {
          pk.pack_array(static_cast<uint32_t>(x.size()));
          for (const Value& item : x) pack_value(pk, item, codec);
        } else if constexpr (std::is_same_v<T, Map>) {
          pk.pack_map(static_cast<uint32_t>(x.size()));
          for (const auto& [key, item] : x) {
            pack_str(pk, key);
            pack_value(pk, item, codec);
          }
        } else {
          pack_array(pk, x, codec);
        }
      },
      value.v);
}

std::string raw(const msgpack::object& o) {
  if (o.type == msgpack::type::STR) return std::string(o.via.str.ptr, o.via.str.size);
  if (o.type == msgpack::type::BIN) return std::string(o.via.bin.ptr, o.via.bin.size);
  throw WireError("not msgpack of the protocol: a map key that is not a string");
}

const msgpack::object* member(const msgpack::object& map, std::string_view key) {
  for (uint32_t i = 0; i < map.via.map.size; ++i) {
    const msgpack::object& k = map.via.map.ptr[i].key;
    if ((k.type == msgpack::type::STR || k.type == msgpack::type::BIN) && raw(k) == key) {
      return &map.via.map.ptr[i].val;
    }
  }
  return nullptr;
}

constexpr size_t kMaxDepth = 64;         // nesting of lists and maps in a reply
constexpr size_t kMaxEntries = 1 << 16;  // entries of one list or map in a reply

Value convert(const msgpack::object& o, int depth);

NdArray openpi_array(const msgpack::object& o) {
  const msgpack::object* data = member(o, "data");
  const msgpack::object* dtype = member(o, "dtype");
  const msgpack::object* shape = member(o, "shape");
  if (data == nullptr || dtype == nullptr || shape == nullptr || shape->type != msgpack::type::ARRAY ||
      (data->type != msgpack::type::BIN && data->type != msgpack::type::STR) ||
      (dtype->type != msgpack::type::STR && dtype->type != msgpack::type::BIN)) {
    throw WireError("malformed msgpack-numpy array (needs data: bin, dtype: str, shape: list)");
  }
  NdArray a;
  a.data = raw(*data);
  a.dtype = raw(*dtype);
  for (uint32_t i = 0; i < shape->via.array.size; ++i) {
    const msgpack::object& d = shape->via.array.ptr[i];
    if (d.type != msgpack::type::POSITIVE_INTEGER) throw WireError("malformed msgpack-numpy array: shape");
    a.shape.push_back(static_cast<size_t>(d.via.u64));
  }
  if (!a.data_matches_shape()) {
    throw WireError(fmt::format("malformed msgpack-numpy array: {} bytes of data for dtype {} shape of {} values",
                                a.data.size(), a.dtype, a.size()));
  }
  return a;
}

Value convert(const msgpack::object& o, int depth) {
  if (depth > static_cast<int>(kMaxDepth)) {
    throw WireError(fmt::format("not msgpack of the protocol: nested deeper than {}", kMaxDepth));
  }
  switch (o.type) {
    case msgpack::type::NIL:
      return {};
    case msgpack::type::BOOLEAN:
      return Value(o.via.boolean);
    case msgpack::type::POSITIVE_INTEGER:
      if (o.via.u64 > static_cast<uint64_t>(INT64_MAX)) return Value(static_cast<double>(o.via.u64));
      return Value(static_cast<int64_t>(o.via.u64));
    case msgpack::type::NEGATIVE_INTEGER:
      return Value(o.via.i64);
    case msgpack::type::FLOAT32:
    case msgpack::type::FLOAT64:
      return Value(o.via.f64);
    case msgpack::type::STR:
      return Value(raw(o));
    case msgpack::type::BIN:
      return Value(Bin{raw(o)});
    case msgpack::type::ARRAY: {
      List list;
      list.reserve(o.via.array.size);
      for (uint32_t i = 0; i < o.via.array.size; ++i) list.push_back(convert(o.via.array.ptr[i], depth + 1));
      return Value(std::move(list));
    }
    case msgpack::type::MAP: {
      if (member(o, "__ndarray__") != nullptr) return Value(openpi_array(o));
      if (member(o, "__npgeneric__") != nullptr) {
        const msgpack::object* data = member(o, "data");
        if (data == nullptr) throw WireError("malformed msgpack-numpy scalar (no data)");
        return convert(*data, depth + 1);
      }
      if (member(o, "__ndarray_class__") != nullptr) {
        const msgpack::object* npy = member(o, "as_npy");
        if (npy == nullptr || (npy->type != msgpack::type::BIN && npy->type != msgpack::type::STR)) {
          throw WireError("malformed GR00T array (needs as_npy: bin)");
        }
        return Value(from_npy(raw(*npy), "as_npy"));
      }
      Map map;
      map.reserve(o.via.map.size);
      for (uint32_t i = 0; i < o.via.map.size; ++i) {
        map.emplace_back(raw(o.via.map.ptr[i].key), convert(o.via.map.ptr[i].val, depth + 1));
      }
      return Value(std::move(map));
    }
    default:
      throw WireError("not msgpack of the protocol: an extension type");
  }
}

}  // namespace

size_t NdArray::size() const {
  size_t n = 1;
  for (const size_t d : shape) n *= d;
  return n;
}

size_t NdArray::item_size() const {
  if (dtype.size() < 3) return 0;
  size_t n = 0;
  for (size_t i = 2; i < dtype.size(); ++i) {
    if (dtype[i] < '0' || dtype[i] > '9') return 0;
    n = n * 10 + static_cast<size_t>(dtype[i] - '0');
    if (n > 64) return 0;
  }
  return n;
}

bool NdArray::data_matches_shape() const {
  const size_t item = item_size();
  if (item == 0) return false;
  if (std::find(shape.begin(), shape.end(), size_t{0}) != shape.end()) return data.empty();
  size_t bytes = item;
  for (const size_t d : shape) {
    if (bytes > data.size() / d) return false;
    bytes *= d;
  }
  return bytes == data.size();
}

std::vector<double> NdArray::to_doubles(std::string_view where) const {
  const char order = dtype.empty() ? '?' : dtype[0];
  const char kind = dtype.size() > 1 ? dtype[1] : '?';
  const size_t n = item_size();
  const bool known = (order == '<' || order == '|' || order == '=') &&
                     ((kind == 'f' && (n == 2 || n == 4 || n == 8)) ||
                      ((kind == 'i' || kind == 'u') && (n == 1 || n == 2 || n == 4 || n == 8)) ||
                      (kind == 'b' && n == 1));
  if (!known) {
    throw WireError(fmt::format("{}: dtype '{}' is not a little-endian number (float16/32/64, int, uint, bool)",
                                where, dtype));
  }
  if (!data_matches_shape()) {
    throw WireError(fmt::format("{}: {} bytes of data for {} values of {}", where, data.size(), size(), dtype));
  }
  std::vector<double> out(size());
  const char* p = data.data();
  for (size_t i = 0; i < out.size(); ++i, p += n) {
    if (kind == 'f') {
      out[i] = n == 2 ? half_to_double(load<uint16_t>(p)) : n == 4 ? static_cast<double>(load<float>(p)) : load<double>(p);
    } else if (kind == 'i') {
      out[i] = n == 1 ? load<int8_t>(p) : n == 2 ? load<int16_t>(p) : n == 4 ? load<int32_t>(p)
                                                                        : static_cast<double>(load<int64_t>(p));
    } else {
      out[i] = n == 1 ? load<uint8_t>(p) : n == 2 ? load<uint16_t>(p) : n == 4 ? load<uint32_t>(p)
                                                                         : static_cast<double>(load<uint64_t>(p));
    }
  }
  return out;
}

NdArray NdArray::from_doubles(const std::vector<double>& values, std::vector<size_t> shape, std::string_view dtype) {
  NdArray a;
  a.dtype = std::string(dtype);
  a.shape = std::move(shape);
  HRIB_CHECK(a.size() == values.size());
  HRIB_CHECK(dtype == "<f8" || dtype == "<f4");
  static_assert(std::endian::native == std::endian::little, "the wire is little-endian");
  if (dtype == "<f8") {
    a.data.assign(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(double));
  } else {
    a.data.resize(values.size() * sizeof(float));
    for (size_t i = 0; i < values.size(); ++i) {
      const auto f = static_cast<float>(values[i]);
      std::memcpy(a.data.data() + i * sizeof(float), &f, sizeof(float));
    }
  }
  return a;
}

NdArray NdArray::from_bytes(const uint8_t* bytes, std::vector<size_t> shape) {
  NdArray a;
  a.dtype = "|u1";
  a.shape = std::move(shape);
  a.data.assign(reinterpret_cast<const char*>(bytes), a.size());
  return a;
}

std::string_view Value::kind() const {
  static constexpr std::string_view kNames[] = {"nil", "bool", "int", "float", "str",
                                                "bin", "list", "map", "ndarray"};
  return kNames[v.index()];
}

namespace {
[[noreturn]] void wrong_kind(std::string_view where, std::string_view expected, const Value& got) {
  throw WireError(fmt::format("{}: expected {}, got {}", where, expected, got.kind()));
}
}  // namespace

const std::string& Value::str(std::string_view where) const {
  if (const auto* s = std::get_if<std::string>(&v)) return *s;
  wrong_kind(where, "str", *this);
}

double Value::number(std::string_view where) const {
  if (const auto* d = std::get_if<double>(&v)) return *d;
  if (const auto* i = std::get_if<int64_t>(&v)) return static_cast<double>(*i);
  wrong_kind(where, "a number", *this);
}

const List& Value::list(std::string_view where) const {
  if (const auto* l = std::get_if<List>(&v)) return *l;
  wrong_kind(where, "list", *this);
}

const Map& Value::map(std::string_view where) const {
  if (const auto* m = std::get_if<Map>(&v)) return *m;
  wrong_kind(where, "map", *this);
}

const NdArray& Value::array(std::string_view where) const {
  if (const auto* a = std::get_if<NdArray>(&v)) return *a;
  wrong_kind(where, "ndarray", *this);
}

const Value* find(const Map& m, std::string_view key) {
  for (const auto& [k, value] : m) {
    if (k == key) return &value;
  }
  return nullptr;
}

const Value& at(const Map& m, std::string_view key, std::string_view where) {
  if (const Value* value = find(m, key)) return *value;
  std::string keys;
  for (const auto& entry : m) keys += (keys.empty() ? "" : ", ") + entry.first;
  throw WireError(fmt::format("{}: no key '{}' (keys: {})", where, key, keys.empty() ? "none" : keys));
}

std::string pack(const Value& value, ArrayCodec codec) {
  msgpack::sbuffer buffer(1 << 16);
  Packer pk(&buffer);
  pack_value(pk, value, codec);
  return std::string(buffer.data(), buffer.size());
}

Value unpack(std::string_view bytes) {
  try {
    size_t offset = 0;
    // msgpack-c allocates a container's declared count before reading it: bound the counts (no
    // reply of the protocols has a list or map of more entries) and the nesting.
    const msgpack::unpack_limit limit(kMaxEntries, kMaxEntries, bytes.size(), bytes.size(), bytes.size(),
                                      kMaxDepth);
    const msgpack::object_handle handle =
        msgpack::unpack(bytes.data(), bytes.size(), offset, nullptr, nullptr, limit);
    if (offset != bytes.size()) {
      throw WireError(fmt::format("not msgpack: {} bytes after the first object", bytes.size() - offset));
    }
    return convert(handle.get(), 0);
  } catch (const msgpack::unpack_error& e) {
    throw WireError(fmt::format("not msgpack: {}", e.what()));
  }
}

std::string to_npy(const NdArray& array) {
  std::string out = human::npy_header(array.dtype, array.shape);
  out += array.data;
  return out;
}

NdArray from_npy(std::string_view bytes, std::string_view where) {
  human::NpyArray layout;
  try {
    layout = human::parse_npy_layout(bytes, where);
  } catch (const core::InputError& e) {  // a server's bytes, not the user's file: a WireError
    throw WireError(e.what());
  }
  NdArray a;
  a.dtype = layout.descr;
  a.shape = layout.shape;
  a.data = std::string(bytes.substr(layout.data_offset));
  if (!a.data_matches_shape()) {
    throw WireError(fmt::format("{}: {} bytes of data for dtype '{}' and {} values", where, a.data.size(),
                                a.dtype, a.size()));
  }
  return a;
}

}  // namespace hribench::remote

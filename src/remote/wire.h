#pragma once
// The messages of the remote-policy protocols (docs/remote-policies.md): a msgpack value tree
// with numpy arrays, packed and unpacked in the two array forms in use:
//   openpi  (msgpack-numpy): {b"__ndarray__": True, b"data": bin, b"dtype": "<f4", b"shape": [..]}
//           with the four marker keys as msgpack bin; numpy scalars as {b"__npgeneric__": True,
//           b"data": item, b"dtype": ".."};
//   GR00T   (MsgSerializer): {"__ndarray_class__": True, "as_npy": bin (a whole .npy v1.0 file)}.
// Unpacking recognises both forms whatever the codec. Arrays keep their raw little-endian bytes
// and numpy dtype string; values are read by that string, never assumed float32.
// Everything unpacked is untrusted: malformed input throws WireError (one line).

#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

namespace hribench::remote {

// Bad bytes from the other side (not msgpack, a malformed array, a missing key, ...).
class WireError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A numpy array: dtype string as numpy writes it ("|u1", "<f4", "<f8", "<i8", "|b1", ...),
// shape, and the C-order raw bytes.
struct NdArray {
  std::string dtype;
  std::vector<size_t> shape;
  std::string data;

  size_t size() const;       // product of shape (1 for a 0-d array)
  size_t item_size() const;  // bytes per value, from dtype
  // True when data holds exactly size() values of item_size() bytes (a shape whose product
  // overflows never does).
  bool data_matches_shape() const;
  // The values as doubles, by dtype: little-endian or byte-order-free float16/32/64, signed and
  // unsigned integers of 1/2/4/8 bytes and bool. Throws WireError (naming `where`) for another
  // dtype, a big-endian one, or data of the wrong size.
  std::vector<double> to_doubles(std::string_view where) const;

  static NdArray from_doubles(const std::vector<double>& values, std::vector<size_t> shape,
                              std::string_view dtype);  // dtype "<f8" or "<f4"
  static NdArray from_bytes(const uint8_t* bytes, std::vector<size_t> shape);  // "|u1"
};

struct Bin {
  std::string bytes;
};

struct Value;
using List = std::vector<Value>;
using Map = std::vector<std::pair<std::string, Value>>;  // insertion order kept

struct Value {
  std::variant<std::monostate, bool, int64_t, double, std::string, Bin, List, Map, NdArray> v;

  Value() = default;
  Value(bool b) : v(b) {}                  // NOLINT: implicit on purpose (literal maps)
  Value(int i) : v(int64_t{i}) {}          // NOLINT
  Value(int64_t i) : v(i) {}               // NOLINT
  Value(double d) : v(d) {}                // NOLINT
  Value(std::string s) : v(std::move(s)) {}  // NOLINT
  Value(const char* s) : v(std::string(s)) {}  // NOLINT
  Value(Bin b) : v(std::move(b)) {}        // NOLINT
  Value(List l) : v(std::move(l)) {}       // NOLINT
  Value(Map m) : v(std::move(m)) {}        // NOLINT
  Value(NdArray a) : v(std::move(a)) {}    // NOLINT

  bool is_nil() const { return std::holds_alternative<std::monostate>(v); }
  // The kind held, for messages: "nil", "bool", "int", "float", "str", "bin", "list", "map",
  // "ndarray".
  std::string_view kind() const;
  // Typed access; throws WireError "WHERE: expected KIND, got KIND" otherwise.
  const std::string& str(std::string_view where) const;
  double number(std::string_view where) const;  // int or float
  const List& list(std::string_view where) const;
  const Map& map(std::string_view where) const;
  const NdArray& array(std::string_view where) const;
};

// The entry `key` of map `m`, or nullptr.
const Value* find(const Map& m, std::string_view key);
// The entry `key` of map `m`; throws WireError naming `where` and the keys present.
const Value& at(const Map& m, std::string_view key, std::string_view where);

enum class ArrayCodec { kOpenpi, kGr00t };

// msgpack bytes of `value`, arrays in `codec`'s form.
std::string pack(const Value& value, ArrayCodec codec);
// Parses msgpack bytes (either array form); throws WireError "not msgpack: ..." for bytes that
// are not one complete msgpack object, or for a malformed array.
Value unpack(std::string_view bytes);

// .npy v1.0 bytes of `array` (header padded to a multiple of 64 bytes, as numpy writes it), and
// back (versions 1.0-3.0, C order; raw bytes kept; bytes that are no such file: WireError).
std::string to_npy(const NdArray& array);
NdArray from_npy(std::string_view bytes, std::string_view where);

}  // namespace hribench::remote

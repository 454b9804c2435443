#pragma once
// NumPy array files: .npy (format versions 1.0, 2.0, 3.0) and .npz (a zip archive of .npy
// members, stored or DEFLATE-compressed as np.savez / np.savez_compressed write them, zip64
// included), read through libzip (Debian's libzip-dev). Only numeric arrays are decoded: little- or big-endian float32,
// float64, int32 and int64 become doubles. Object arrays ('|O', pickled Python objects) are
// refused when read, and an npz member is only decoded when asked for, so an archive whose
// other members are pickled or strings still reads. Errors are core::InputError naming the
// file, the member ("file.npz[poses.npy]") and the byte offset.

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace hribench::human {

// A decoded numeric array, C order.
struct NpyArray {
  std::vector<size_t> shape;   // () for a scalar
  std::string descr;           // dtype as written, e.g. "<f4"
  std::vector<double> values;  // product(shape) values
  size_t data_offset = 0;      // byte offset of values[0] in the .npy bytes
  size_t item_size = 0;        // bytes per value in the file
  size_t size() const;         // product of shape (1 for a scalar)
};

// Decodes .npy bytes; `where` names the source in errors ("FILE" or "FILE[member]").
NpyArray parse_npy(std::string_view bytes, std::string_view where);
// The header only (any dtype but 'O', C order): shape, descr and data_offset are set; values
// and item_size are left empty. For readers that keep the raw bytes (remote/wire.h).
NpyArray parse_npy_layout(std::string_view bytes, std::string_view where);
NpyArray read_npy(const std::filesystem::path& path);

// .npy bytes (version 1.0, header padded to 64 bytes) of `values` with `shape`, as little-endian
// float32 ("<f4") or float64 ("<f8").
enum class NpyType { kFloat32, kFloat64 };
// The magic, version 1.0, length and header of an array of numpy dtype `descr` ("|u1", "<f4")
// and `shape`, padded to a multiple of 64 bytes; the raw C-order data follows it.
std::string npy_header(std::string_view descr, const std::vector<size_t>& shape);
std::string format_npy(const std::vector<size_t>& shape, const std::vector<double>& values,
                       NpyType type);

// An npz archive: member names -> raw (decompressed on demand) .npy bytes.
class NpzArchive {
 public:
  // Reads the zip central directory (libzip, with its consistency checks); throws
  // core::InputError if `bytes` is not a zip archive.
  NpzArchive(std::string bytes, std::string where);
  static NpzArchive Read(const std::filesystem::path& path);

  // Array keys ("poses" for member "poses.npy"), sorted.
  std::vector<std::string> keys() const;
  bool contains(std::string_view key) const;
  // Decompresses, checks the CRC and decodes one member. Throws core::InputError (missing key,
  // corrupt member, unsupported dtype, a declared size above 2 GiB or above what DEFLATE can
  // produce from the member's stored bytes, checked before anything is allocated).
  NpyArray array(std::string_view key) const;

 private:
  std::string bytes_;
  std::string where_;
  std::map<std::string, uint64_t, std::less<>> members_;  // key -> zip entry index
};

// Zip bytes of stored (uncompressed) members, as np.savez writes them: name -> .npy bytes.
std::string format_npz(const std::map<std::string, std::string>& members);

}  // namespace hribench::human

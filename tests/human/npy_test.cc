#include "human/npy.h"

#include <gtest/gtest.h>

#include <cstring>

#include "core/errors.h"

namespace hribench::human {
namespace {

TEST(NpyTest, FormatThenParseKeepsShapeAndValues) {
  const std::vector<double> v = {1.5, -2.25, 3e-3, 4, 5, 6};
  for (const NpyType type : {NpyType::kFloat32, NpyType::kFloat64}) {
    const std::string bytes = format_npy({2, 3}, v, type);
    EXPECT_EQ((bytes.size() - v.size() * (type == NpyType::kFloat32 ? 4 : 8)) % 64, 0u);  // aligned header
    const NpyArray a = parse_npy(bytes, "a.npy");
    EXPECT_EQ(a.shape, (std::vector<size_t>{2, 3}));
    EXPECT_EQ(a.descr, type == NpyType::kFloat32 ? "<f4" : "<f8");
    ASSERT_EQ(a.values.size(), 6u);
    for (size_t i = 0; i < v.size(); ++i) EXPECT_NEAR(a.values[i], v[i], 1e-7);
  }
  const NpyArray scalar = parse_npy(format_npy({}, {60.0}, NpyType::kFloat64), "s.npy");
  EXPECT_TRUE(scalar.shape.empty());
  EXPECT_EQ(scalar.values, std::vector<double>{60.0});
}

TEST(NpyTest, ReadsBigEndianVersionTwoAndIntegers) {
  // Version 2.0 header (4-byte length), big-endian float64 [1.0, -2.0].
  std::string header = "{'descr': '>f8', 'fortran_order': False, 'shape': (2,), }";
  while ((12 + header.size() + 1) % 64 != 0) header += ' ';
  header += '\n';
  std::string bytes = std::string("\x93NUMPY\x02\x00", 8);
  const auto len = static_cast<uint32_t>(header.size());
  bytes += std::string(reinterpret_cast<const char*>(&len), 4);
  bytes += header;
  bytes += std::string("\x3f\xf0\x00\x00\x00\x00\x00\x00\xc0\x00\x00\x00\x00\x00\x00\x00", 16);
  const NpyArray a = parse_npy(bytes, "be.npy");
  EXPECT_EQ(a.values, (std::vector<double>{1.0, -2.0}));
  // int64 little-endian.
  std::string h2 = "{'descr': '<i8', 'fortran_order': False, 'shape': (1,), }";
  while ((10 + h2.size() + 1) % 64 != 0) h2 += ' ';
  h2 += '\n';
  std::string b2 = std::string("\x93NUMPY\x01\x00", 8);
  b2 += static_cast<char>(h2.size());
  b2 += '\0';
  b2 += h2;
  const int64_t seven = -7;
  b2 += std::string(reinterpret_cast<const char*>(&seven), 8);
  EXPECT_EQ(parse_npy(b2, "i.npy").values, std::vector<double>{-7.0});
}

TEST(NpyTest, NpzArchiveReadsDeflatedMembersAndSkipsOthers) {
  // Written by Python's zipfile the way np.savez_compressed does (DEFLATE, zip64 local headers,
  // dynamic Huffman blocks), with a '<U7' string member that is never decoded.
  const NpzArchive npz = NpzArchive::Read("tests/data/motion/hy_motion_like.npz");
  EXPECT_EQ(npz.keys(), (std::vector<std::string>{"Rh", "betas", "gender", "poses", "trans"}));
  const NpyArray poses = npz.array("poses");
  EXPECT_EQ(poses.shape, (std::vector<size_t>{3, 156}));
  EXPECT_NEAR(poses.values[156 + 16 * 3 + 2], 1.5707963267948966, 1e-15);
  EXPECT_EQ(npz.array("trans").values[1], 0.95);
  EXPECT_THROW(npz.array("gender"), core::InputError);  // a string array, not numeric
  // Stored archive with a pickled member: the numeric members still read.
  const NpzArchive amass = NpzArchive::Read("tests/data/motion/amass_like.npz");
  EXPECT_TRUE(amass.contains("marker_labels"));
  EXPECT_EQ(amass.array("mocap_framerate").values, std::vector<double>{60.0});
}

TEST(NpyTest, FormatNpzThenReadBack) {
  const std::string bytes = format_npz({{"a", format_npy({2}, {1, 2}, NpyType::kFloat64)},
                                        {"b", format_npy({1}, {3}, NpyType::kFloat32)}});
  const NpzArchive npz(bytes, "x.npz");
  EXPECT_EQ(npz.keys(), (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(npz.array("a").values, (std::vector<double>{1, 2}));
  EXPECT_EQ(npz.array("b").values, (std::vector<double>{3}));
}

// Little-endian field of `n` bytes at `at`.
void patch(std::string& bytes, size_t at, uint64_t value, int n) {
  for (int i = 0; i < n; ++i) bytes[at + static_cast<size_t>(i)] = static_cast<char>((value >> (8 * i)) & 0xff);
}

core::InputError npz_error(const std::string& bytes, const char* key) {
  try {
    const NpzArchive npz(bytes, "x.npz");
    npz.array(key);
  } catch (const core::InputError& e) {
    return e;
  }
  return core::InputError("(no error)", "", "");
}

// Archives that made our own zip reader read out of bounds or reserve 4 GiB (issue 22), now
// read by libzip: each is one InputError.
TEST(NpyTest, MalformedZipsAreInputErrors) {
  const std::string good = format_npz({{"a", format_npy({2}, {1, 2}, NpyType::kFloat64)}});
  const size_t entry = good.size() - 22 - (46 + 5);  // the one central directory entry
  ASSERT_EQ(good.substr(entry, 4), "PK\x01\x02");
  // A declared size of 4 GiB in both headers of a stored member of 144 bytes: refused before
  // anything is allocated.
  std::string huge = good;
  patch(huge, 22, 0xfffffffeu, 4);
  patch(huge, entry + 24, 0xfffffffeu, 4);
  const core::InputError size_error = npz_error(huge, "a");
  EXPECT_EQ(size_error.where(), "x.npz[a.npy]");
  EXPECT_EQ(size_error.expected(), "a member of at most 2147483648 bytes that its 144 stored bytes can hold");
  EXPECT_EQ(size_error.got(), "4294967294 bytes declared");
  // An extra field longer than the entry.
  std::string extra = good;
  patch(extra, entry + 30, 0xffff, 2);
  EXPECT_EQ(npz_error(extra, "a").where(), "x.npz");
  EXPECT_EQ(npz_error(extra, "a").expected(), "a zip archive (npz)");
  EXPECT_EQ(npz_error(extra, "a").got(), "Zip archive inconsistent");
  // A zip64 end-of-directory locator whose record lies far past the end of the file.
  std::string zip64 = good;
  patch(zip64, zip64.size() - 22 + 10, 0xffff, 2);
  std::string locator = "PK\x06\x07";
  locator += std::string(16, '\0');
  patch(locator, 8, uint64_t{1} << 60, 8);
  zip64.insert(zip64.size() - 22, locator);
  EXPECT_EQ(npz_error(zip64, "a").where(), "x.npz");
  EXPECT_EQ(npz_error(zip64, "a").expected(), "a zip archive (npz)");
  EXPECT_EQ(npz_error(zip64, "a").got(), "Zip archive inconsistent");
}

}  // namespace
}  // namespace hribench::human

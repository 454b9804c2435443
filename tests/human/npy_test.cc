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

TEST(NpyTest, Crc32MatchesTheStandardCheckValue) {
  EXPECT_EQ(crc32("123456789"), 0xCBF43926u);
  EXPECT_EQ(crc32(""), 0u);
}

TEST(NpyTest, InflatesStoredFixedAndDynamicBlocks) {
  // Raw deflate (zlib wbits -15, level 9) of "hello hello hello hello": a fixed-Huffman block with a match.
  const std::string fixed("\xcb\x48\xcd\xc9\xc9\x57\xc8\x40\x27\x01", 10);
  EXPECT_EQ(inflate_raw(fixed, 100, "f"), "hello hello hello hello");
  // A stored block: BFINAL=1 BTYPE=00, LEN=3, NLEN=~3, "abc".
  const std::string stored("\x01\x03\x00\xfc\xff" "abc", 8);
  EXPECT_EQ(inflate_raw(stored, 3, "s"), "abc");
  // The output is bounded by the declared size.
  EXPECT_THROW(inflate_raw(stored, 2, "s"), core::InputError);
  // Truncated stream: a clear error with the byte offset.
  try {
    inflate_raw(fixed.substr(0, 4), 100, "t.npz[x.npy]");
    FAIL() << "no error";
  } catch (const core::InputError& e) {
    EXPECT_EQ(e.where(), "t.npz[x.npy]: byte 4");
    EXPECT_EQ(e.got(), "the end of the stream");
  }
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

}  // namespace
}  // namespace hribench::human

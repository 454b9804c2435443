// The msgpack forms of the remote protocols: openpi's msgpack-numpy bytes exactly as openpi's
// packer writes them (marker keys as bin), GR00T's npy-in-msgpack, decoding by dtype string,
// and the one-line errors for bytes that are not msgpack or arrays that do not add up.

#include "remote/wire.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>

#include "human/npy.h"

namespace hribench::remote {
namespace {

std::string hex(const std::string& bytes) {
  std::string out;
  for (const unsigned char c : bytes) out += "0123456789abcdef"[c >> 4], out += "0123456789abcdef"[c & 15];
  return out;
}

std::string hex_of_text(const std::string& text) { return hex(text); }

TEST(Wire, OpenpiArrayBytesAreThoseOfOpenpisPacker) {
  // protocols: np.array([1, 2], float32) packs as
  // 84 c4 0b "__ndarray__" c3 c4 04 "data" c4 08 0000803f00000040 c4 05 "dtype" a3 "<f4" c4 05 "shape" 91 02
  const std::string packed = pack(Value(NdArray::from_doubles({1, 2}, {2}, "<f4")), ArrayCodec::kOpenpi);
  const std::string expected = "84c40b" + hex_of_text("__ndarray__") + "c3c404" + hex_of_text("data") +
                               "c4080000803f00000040c405" + hex_of_text("dtype") + "a3" + hex_of_text("<f4") +
                               "c405" + hex_of_text("shape") + "9102";
  EXPECT_EQ(hex(packed), expected);
}

TEST(Wire, AnImageNeedsBin32) {
  std::vector<uint8_t> pixels(224 * 224 * 3, 7);
  const std::string packed = pack(Value(NdArray::from_bytes(pixels.data(), {224, 224, 3})), ArrayCodec::kOpenpi);
  const size_t at = packed.find(std::string("\xc6\x00\x02\x4c\x00", 5));  // bin32, 150528 bytes
  EXPECT_NE(at, std::string::npos);
  const Value back = unpack(packed);
  EXPECT_EQ(back.array("image").data, std::string(pixels.begin(), pixels.end()));
  EXPECT_EQ(back.array("image").dtype, "|u1");
}

TEST(Wire, RepliesAreDecodedByTheirDtype) {
  const auto decoded = [](const std::string& dtype, const std::string& raw) {
    NdArray a;
    a.dtype = dtype;
    a.shape = {raw.size() / a.item_size()};
    a.data = raw;
    return unpack(pack(Value(a), ArrayCodec::kOpenpi)).array("a").to_doubles("a");
  };
  EXPECT_EQ(decoded("<f8", std::string("\x00\x00\x00\x00\x00\x00\xf0\x3f", 8)), std::vector<double>{1.0});
  EXPECT_EQ(decoded("<f2", std::string("\x00\x3c\x00\xc0", 4)), (std::vector<double>{1.0, -2.0}));
  EXPECT_EQ(decoded("<i8", std::string("\xfe\xff\xff\xff\xff\xff\xff\xff", 8)), std::vector<double>{-2.0});
  EXPECT_EQ(decoded("|u1", std::string("\xff", 1)), std::vector<double>{255.0});
  EXPECT_EQ(decoded("|b1", std::string("\x01", 1)), std::vector<double>{1.0});
  NdArray big;
  big.dtype = ">f4";
  big.shape = {1};
  big.data = std::string(4, '\0');
  try {
    big.to_doubles("actions");
    FAIL();
  } catch (const WireError& e) {
    EXPECT_NE(std::string(e.what()).find("actions: dtype '>f4'"), std::string::npos) << e.what();
  }
}

// The WireError message of unpacking `bytes`, or "(no error)".
std::string unpack_error(const std::string& bytes) {
  try {
    unpack(bytes);
  } catch (const WireError& e) {
    return std::string(e.what());
  }
  return std::string("(no error)");
}

TEST(Wire, BadBytesAreOneLineWireErrors) {
  EXPECT_EQ(unpack_error("\xc1 not msgpack").rfind("not msgpack", 0), 0u) << unpack_error("\xc1 not msgpack");
  EXPECT_EQ(unpack_error(std::string("\x92\x01", 2)).rfind("not msgpack", 0), 0u);  // truncated
  EXPECT_NE(unpack_error(std::string("\x01\x02", 2)).find("1 bytes after"), std::string::npos);
  // An array whose data does not match dtype and shape.
  NdArray a = NdArray::from_doubles({1, 2}, {2}, "<f4");
  a.shape = {3};
  EXPECT_NE(unpack_error(pack(Value(a), ArrayCodec::kOpenpi)).find("malformed msgpack-numpy array"), std::string::npos);
}

// Found by fuzz/remote_reply_fuzz.cc: a list or map declaring 2^32 entries in 5 bytes made
// msgpack-c allocate 64 GiB before reading them; a shape whose product overflows to the data's
// size passed as an array of 2^64 values.
TEST(Wire, DeclaredSizesAreBoundedBeforeAnythingIsAllocated) {
  EXPECT_EQ(unpack_error(std::string("\xdd\xff\xff\xff\xff", 5)).rfind("not msgpack", 0), 0u);  // array32
  EXPECT_EQ(unpack_error(std::string("\xdf\xff\xff\xff\xff", 5)).rfind("not msgpack", 0), 0u);  // map32
  std::string deep(70, '\x91');  // [[[...]]] 70 deep
  deep += '\xc0';
  EXPECT_EQ(unpack_error(deep).rfind("not msgpack", 0), 0u) << unpack_error(deep);
  NdArray wraps;
  wraps.dtype = "<f4";
  wraps.shape = {size_t{1} << 62, 4};  // 2^64 values of 4 bytes: 0 bytes modulo 2^64
  EXPECT_FALSE(wraps.data_matches_shape());
  EXPECT_NE(unpack_error(pack(Value(wraps), ArrayCodec::kOpenpi)).find("malformed msgpack-numpy array"), std::string::npos);
  wraps.shape = {0, 4};
  EXPECT_TRUE(wraps.data_matches_shape());
}

// Found by fuzz/remote_reply_fuzz.cc: NPY bytes that are no NPY file (inside a GR00T reply or
// alone) escaped as the file reader's InputError instead of the wire's WireError.
TEST(Wire, BadNpyBytesAreWireErrors) {
  for (const std::string& bytes : {std::string(), std::string("\x93NUMPY\x01\x00\xff\xff{", 11),
                                   std::string("not an npy file")}) {
    try {
      from_npy(bytes, "reply.actions");
      FAIL() << "no error for " << bytes.size() << " bytes";
    } catch (const WireError& e) {
      EXPECT_EQ(std::string(e.what()).rfind("reply.actions", 0), 0u) << e.what();
    }
  }
}

TEST(Wire, Gr00tArraysAreWholeNpyFiles) {
  const NdArray a = NdArray::from_doubles({1, 2, 3, 4, 5, 6}, {2, 3}, "<f4");
  const std::string packed = pack(Value(Map{{"x", a}}), ArrayCodec::kGr00t);
  EXPECT_NE(packed.find("__ndarray_class__"), std::string::npos);
  EXPECT_NE(packed.find("as_npy"), std::string::npos);
  const std::string npy = to_npy(a);
  EXPECT_EQ((npy.size() - a.data.size()) % 64, 0u);  // header padded as numpy pads it
  EXPECT_EQ(npy.substr(0, 8), std::string("\x93NUMPY\x01\x00", 8));
  const human::NpyArray read = human::parse_npy(npy, "x.npy");  // the project's reader agrees
  EXPECT_EQ(read.values, (std::vector<double>{1, 2, 3, 4, 5, 6}));
  const Value back = unpack(packed);
  const NdArray& b = back.map("m").front().second.array("x");
  EXPECT_EQ(b.dtype, "<f4");
  EXPECT_EQ(b.shape, (std::vector<size_t>{2, 3}));
  EXPECT_EQ(b.data, a.data);
}

TEST(Wire, MapsListsAndScalarsRoundTrip) {
  const Value v = Map{{"endpoint", "get_action"}, {"n", 3}, {"x", 0.5}, {"ok", true},
                      {"language", List{List{"pick"}}}, {"none", Value()}};
  const Value back = unpack(pack(v, ArrayCodec::kGr00t));
  const Map& m = back.map("m");
  EXPECT_EQ(at(m, "endpoint", "m").str("endpoint"), "get_action");
  EXPECT_EQ(at(m, "n", "m").number("n"), 3);
  EXPECT_EQ(at(m, "x", "m").number("x"), 0.5);
  EXPECT_EQ(at(m, "language", "m").list("l")[0].list("l")[0].str("l"), "pick");
  EXPECT_TRUE(at(m, "none", "m").is_nil());
  try {
    at(m, "missing", "reply");
    FAIL();
  } catch (const WireError& e) {
    EXPECT_NE(std::string(e.what()).find("reply: no key 'missing' (keys: endpoint, n, x, ok, language, none)"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace hribench::remote

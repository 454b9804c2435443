#pragma once
// Content hashes. SHA-256 (FIPS 180-4) identifies an EpisodeSpec by the bytes of its canonical
// JSON, so two machines that sampled the same episode agree on its hash.

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

namespace hribench::core {

using Sha256Digest = std::array<uint8_t, 32>;

// SHA-256 of a byte string.
Sha256Digest sha256(std::string_view bytes);
// Lower-case hexadecimal form (64 characters) of a digest, and of the hash of `bytes`.
std::string to_hex(const Sha256Digest& digest);
std::string sha256_hex(std::string_view bytes);

}  // namespace hribench::core

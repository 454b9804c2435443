#pragma once
// Seeded, splittable random numbers. Everything random in HRIBench is drawn from an Rng at
// `sample(seed)` (docs/design.md). The generator and every distribution are written here (not
// std::*_distribution, whose output differs between standard libraries), so a seed gives the
// same numbers on every platform.
//
// Splitting: rng.split("human") gives a child stream that depends only on the parent's key and
// the name — not on how many numbers were drawn before — so adding a draw in one part of a
// scenario does not shift the draws of another.

#include <cstdint>
#include <span>
#include <string_view>

namespace hribench::core {

class Rng {
 public:
  explicit Rng(uint64_t seed);

  // A child stream named `stream` (independent of this stream's position).
  Rng split(std::string_view stream) const;
  Rng split(uint64_t index) const;

  uint64_t next_u64();
  // Uniform in [0, 1) with 53 random bits.
  double uniform();
  // Uniform in [lo, hi). Requires lo <= hi.
  double uniform(double lo, double hi);
  // Uniform integer in [lo, hi], inclusive, unbiased. Requires lo <= hi.
  int64_t uniform_int(int64_t lo, int64_t hi);
  // Normal(mean, stddev), Box–Muller. Requires stddev >= 0.
  double normal(double mean, double stddev);
  // Index i with probability weights[i] / sum. Requires a non-empty span of finite weights
  // >= 0 with a positive sum.
  size_t weighted_index(std::span<const double> weights);

  uint64_t key() const { return key_; }

 private:
  uint64_t key_;    // identity of the stream, used by split()
  uint64_t s_[4];   // xoshiro256** state
};

// 64-bit FNV-1a of a byte string (stream names, quick content keys).
uint64_t fnv1a64(std::string_view bytes, uint64_t basis = 0xcbf29ce484222325ULL);

}  // namespace hribench::core

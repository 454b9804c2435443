#include "core/bisection.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>

#include "core/rng.h"

namespace hribench::core {
namespace {

// A deterministic rounding-sized wobble of f at x (as a long computation's rounding is): up to
// `amplitude`, a different value at every double.
double wobble(double x, double amplitude) {
  uint64_t bits = 0;
  std::memcpy(&bits, &x, sizeof bits);
  bits ^= bits >> 29;
  bits *= 0xbf58476d1ce4e5b9ULL;
  bits ^= bits >> 32;
  return amplitude * (static_cast<double>(bits % 2001) / 1000.0 - 1.0);
}

struct Case {
  std::function<double(double)> f;
  Crossing crossing;
  double lo;
  double hi;
};

// Smooth monotone crossings of the kinds the lean's bisections meet: a nearly straight one, a
// bent one, one with a kink (a clamp), one steep, one shallow; each with a wobble of 1e-15
// (lengths in metres rounded through a pose).
std::vector<Case> cases(Rng& rng) {
  std::vector<Case> out;
  for (int i = 0; i < 400; ++i) {
    const double root = rng.uniform(0.01, 1.2);
    const double slope = std::pow(10.0, rng.uniform(-2, 1));
    const double bend = rng.uniform(0, 2);
    const double noise = rng.uniform(0, 1) < 0.5 ? 1e-15 : 0;
    const int kind = i % 4;
    const auto g = [=](double x) {
      const double d = x - root;
      switch (kind) {
        case 0:
          return slope * d + noise * wobble(x, 1);
        case 1:
          return slope * (d + bend * d * d * d) + wobble(x, noise);
        case 2:
          return slope * std::sin(std::clamp(d, -1.0, 0.5)) + wobble(x, noise);
        default:
          return slope * (std::exp(bend * d) - 1) + wobble(x, noise);
      }
    };
    const bool rising = i % 3 != 0;
    out.push_back({rising ? std::function<double(double)>(g)
                          : std::function<double(double)>([g](double x) { return -g(x); }),
                   rising ? Crossing::kRising : Crossing::kFalling, 0, rng.uniform(root + 0.01, 1.25)});
  }
  return out;
}

TEST(BisectionTest, BracketedIsPlainBisectionToTheBitWithAThirdOfTheJudgements) {
  Rng rng(7);
  long plain_calls = 0;
  long bracketed_calls = 0;
  for (const Case& c : cases(rng)) {
    for (const int steps : {30, 40}) {  // the lean's bisections
      const Bracket plain = bisect(c.lo, c.hi, steps, c.crossing, [&](double x) {
        ++plain_calls;
        return c.f(x);
      });
      const Bracket fast =
          bisect_bracketed(c.lo, c.f(c.lo), c.hi, c.f(c.hi), steps, c.crossing, [&](double x) {
            ++bracketed_calls;
            return c.f(x);
          });
      ASSERT_EQ(fast.lo, plain.lo) << "steps " << steps << ", [" << c.lo << ", " << c.hi << "]";
      ASSERT_EQ(fast.hi, plain.hi);
    }
  }
  EXPECT_LT(bracketed_calls * 3, plain_calls) << bracketed_calls << " of " << plain_calls;
}

TEST(BisectionTest, AFlatOrNotFiniteFunctionIsJudgedAtEveryMidpoint) {
  for (const double flat : {0.0, std::nan("")}) {
    int calls = 0;
    const auto f = [&](double x) {
      ++calls;
      return x < 0.3 ? flat : 1.0;
    };
    const Bracket plain = bisect(0, 1, 30, Crossing::kRising, f);
    calls = 0;
    const Bracket fast = bisect_bracketed(0, flat, 1, 1.0, 30, Crossing::kRising, f);
    EXPECT_EQ(fast.lo, plain.lo);
    EXPECT_EQ(fast.hi, plain.hi);
    EXPECT_GE(calls, 30) << "value " << flat;
  }
}

TEST(BisectionTest, ACrossingWithinRoundingOfAMidpointIsJudgedAsPlainBisectionDoes) {
  // f rises through zero in a staircase of rounding-sized steps: which side a midpoint near the
  // crossing lands on is the wobble's, and the bracketed search must judge those midpoints.
  Rng rng(11);
  for (int i = 0; i < 200; ++i) {
    const double root = rng.uniform(0.1, 0.9);
    const auto f = [root](double x) { return 0.5 * (x - root) + wobble(x, 1e-14); };
    const Bracket plain = bisect(0, 1, 60, Crossing::kRising, f);
    const Bracket fast = bisect_bracketed(0, f(0), 1, f(1), 60, Crossing::kRising, f);
    ASSERT_EQ(fast.lo, plain.lo) << root;
    ASSERT_EQ(fast.hi, plain.hi) << root;
  }
}

}  // namespace
}  // namespace hribench::core

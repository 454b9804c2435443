#pragma once
// Bisection to the bit, judging fewer midpoints (docs/performance.md, "A leaning person's
// pose"). The person's lean is found by bisections whose every midpoint costs a pose; what
// they return is part of the released pool's episodes, so it must not move by one bit.

#include <algorithm>
#include <cmath>
#include <limits>

namespace hribench::core {

// What `steps` halvings leave of an interval: the last lo and hi.
struct Bracket {
  double lo = 0;
  double hi = 0;
};

// Which way a bisected function crosses zero: a midpoint where f > 0 replaces `hi` where it
// rises, `lo` where it falls (so `lo` always holds the side of f(lo), `hi` that of f(hi)).
enum class Crossing { kRising, kFalling };

// `steps` halvings of [lo, hi], each judging f at the midpoint (plain bisection).
template <class F>
Bracket bisect(double lo, double hi, int steps, Crossing crossing, F f) {
  for (int i = 0; i < steps; ++i) {
    const double mid = 0.5 * (lo + hi);
    const bool past = (f(mid) > 0) == (crossing == Crossing::kRising);
    (past ? hi : lo) = mid;
  }
  return {lo, hi};
}

// How far (in f's unit, metres for the lean) a computed f may be from the true value, with a
// wide margin: lengths under a few metres through a few hundred operations round by about
// 1e-15.
inline constexpr double kBisectionRounding = 1e-12;
// The most secant steps bisect_bracketed takes (a smooth crossing takes well under ten).
inline constexpr int kMaxSecantSteps = 16;

// The same halvings, to the bit, where f is monotone between the crossing and every midpoint
// farther from it than kBisectionRounding over f's slope there. `f_lo`, `f_hi` are f at lo and
// hi, on the two sides of the crossing as the caller judged them. First a safeguarded secant
// (regula falsi with the Illinois step) brackets the crossing between two judged points a, b;
// then the halvings run, and a midpoint left of a or right of b by more than kBisectionRounding
// over the bracket's slope is placed on a's or b's side without judging f; the others are
// judged as plain bisection judges them. Where the slope cannot be told (f flat, or not
// finite) every midpoint is judged; so are those near a crossing the secant did not close in on
// within kMaxSecantSteps.
template <class F>
Bracket bisect_bracketed(double lo, double f_lo, double hi, double f_hi, int steps,
                         Crossing crossing, F f) {
  const bool rising = crossing == Crossing::kRising;
  const auto past = [rising](double v) { return (v > 0) == rising; };
  // The bracket: a judged on lo's side, b on hi's, with their values; fa_s, fb_s are the values
  // the secant uses (Illinois halves the one that stays).
  double a = lo;
  double b = hi;
  double fa = f_lo;
  double fb = f_hi;
  double fa_s = fa;
  double fb_s = fb;
  const auto margin = [&] {
    const double slope = std::abs(fb - fa) / (b - a);
    return slope > 0 && std::isfinite(slope) ? kBisectionRounding / slope
                                             : std::numeric_limits<double>::infinity();
  };
  int kept = 0;  // +1: a stayed last time, -1: b stayed
  for (int i = 0; i < kMaxSecantSteps; ++i) {
    // A step lands at least half the margin inside the bracket, so that a secant closing in on
    // the crossing from one side also closes the other side on it.
    const double step = 0.5 * margin();
    if (!(b - a > 2 * step)) break;
    double x = b - fb_s * (b - a) / (fb_s - fa_s);
    if (!std::isfinite(x)) x = 0.5 * (a + b);
    x = std::clamp(x, a + step, b - step);
    const double fx = f(x);
    if (past(fx)) {
      b = x;
      fb = fb_s = fx;
      if (kept == 1) fa_s *= 0.5;
      kept = 1;
    } else {
      a = x;
      fa = fa_s = fx;
      if (kept == -1) fb_s *= 0.5;
      kept = -1;
    }
  }
  const double sure = margin();
  for (int i = 0; i < steps; ++i) {
    const double mid = 0.5 * (lo + hi);
    bool is_past;
    if (mid < a - sure) {
      is_past = false;
    } else if (mid > b + sure) {
      is_past = true;
    } else {
      is_past = past(f(mid));
    }
    (is_past ? hi : lo) = mid;
  }
  return {lo, hi};
}

}  // namespace hribench::core

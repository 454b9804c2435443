#include "eval/constants.h"

#include <cmath>
#include <numbers>

#include "core/errors.h"

namespace hribench::eval {

double normal_quantile(double p) {
  HRIB_CHECK(p > 0 && p < 1) << "normal_quantile(" << p << ")";
  // Newton's method on the upper tail q = 1 - p = erfc(z / sqrt 2) / 2, from z = 0: it
  // converges in a few steps and keeps the tail's precision for p near 1.
  const double q = 1 - p;
  double z = 0;
  for (int i = 0; i < 100; ++i) {
    const double f = 0.5 * std::erfc(z / std::sqrt(2.0)) - q;
    const double slope = -std::exp(-z * z / 2) / std::sqrt(2 * std::numbers::pi);
    const double next = z - f / slope;
    if (next == z) break;
    z = next;
  }
  return z;
}

std::vector<NamedConstant> constant_table(const MetricConstants& constants) {
  std::vector<NamedConstant> table;
  visit_constants(constants, [&](const char* name, const auto& value, const char* unit) {
    table.push_back({name, static_cast<double>(value), unit});
  });
  return table;
}

}  // namespace hribench::eval

#include "eval/constants.h"

namespace hribench::eval {

std::vector<NamedConstant> constant_table(const MetricConstants& constants) {
  std::vector<NamedConstant> table;
  visit_constants(constants, [&](const char* name, const auto& value, const char* unit) {
    table.push_back({name, static_cast<double>(value), unit});
  });
  return table;
}

}  // namespace hribench::eval

#include "script/scenario.h"

#include "core/errors.h"

namespace hribench::script {

double Num::value() const {
  HRIB_CHECK(expr.kind == Expr::Kind::kNumber) << "unresolved number " << to_source(expr) << " at " << where.text;
  return expr.number;
}

const std::string& Text::value() const {
  HRIB_CHECK(expr.kind == Expr::Kind::kString) << "unresolved word " << to_source(expr) << " at " << where.text;
  return expr.text;
}

}  // namespace hribench::script

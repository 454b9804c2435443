// The expression language (U, N, choice, $var, templates) and the predicate language.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/errors.h"
#include "script/expr.h"
#include "script/predicate.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const hribench::script::Expr e = hribench::script::parse_expr(text);
    hribench::script::parse_expr(hribench::script::to_source(e));  // what it prints reads back
  } catch (const hribench::script::ExprError&) {
  }
  try {
    hribench::script::bind_predicate(text, {"cup", "bin", "box", "table"});
  } catch (const hribench::core::InputError&) {
  }
  return 0;
}

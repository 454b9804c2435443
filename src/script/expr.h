#pragma once
// Values written in a scenario script: literals, `$var` references, string templates and the
// distributions U, Uint, N and choice. Every random value of a script is an Expr until
// sample() resolves it with a seeded core::Rng into a literal.
//
// Grammar of one scalar:
//   U(a, b)                      uniform real in [a, b), a < b
//   Uint(a, b)                   uniform integer in [a, b] (both integers), a < b
//   N(mu, sigma)                 normal, sigma > 0
//   N(mu, sigma, clip=[lo, hi])  normal clipped to [lo, hi], lo < hi
//   choice([x, y, ...])          equal weights, 1..64 items (numbers, words or $vars)
//   choice([x, y], [w1, w2])     weighted choice, weights >= 0 with a positive sum
//   $name                        the value of var `name` (one draw per episode)
//   text with $name inside       a string template, e.g. human.$hand -> human.right
//   a number                     finite, |x| <= kMaxMagnitude
//   anything else                a string literal

#include <cstdint>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "core/rng.h"

namespace hribench::script {

inline constexpr double kMaxMagnitude = 1e6;  // larger numbers are typos, refused

struct Expr {
  enum class Kind { kNumber, kString, kVar, kTemplate, kUniform, kUniformInt, kNormal, kChoice };
  Kind kind = Kind::kNumber;
  double number = 0;            // kNumber
  std::string text;             // kString: value; kVar: var name; kTemplate: the raw text
  double a = 0, b = 0;          // kUniform/kUniformInt: bounds; kNormal: mu, sigma
  bool clipped = false;         // kNormal
  double lo = 0, hi = 0;        // kNormal clip bounds
  std::vector<Expr> items;      // kChoice
  std::vector<double> weights;  // kChoice; empty = equal weights

  static Expr Number(double x);
  static Expr String(std::string s);
  bool is_literal() const { return kind == Kind::kNumber || kind == Kind::kString; }
  bool operator==(const Expr&) const = default;
};

// Tokens shared by the expression and predicate parsers. Words: [A-Za-z_$][A-Za-z0-9_.$]*;
// numbers: decimal only (no hex, no nan/inf); strings: '...' or "..."; punctuation: ( ) [ ] ,
// = < >. `pos` is the byte offset in the text.
struct Token {
  enum class Kind { kWord, kNumber, kString, kPunct, kEnd };
  Kind kind = Kind::kEnd;
  std::string text;
  double number = 0;
  size_t pos = 0;
};
// Throws ExprError on a character that starts no token or a number out of range.
std::vector<Token> tokenize(std::string_view text);

// Thrown by parse_expr: what was expected and what was found (the caller adds the location).
struct ExprError {
  std::string expected;
  std::string got;
};

// Parses one scalar (quoted or not: quote expressions inside YAML flow collections, where a
// comma would otherwise split them). Throws ExprError.
Expr parse_expr(std::string_view text);
// The source form, parseable again: "U(0.5, 3)", "choice([left, right])", "$hand", "1.25".
std::string to_source(const Expr& expr);

// The var names an expression refers to (in order of appearance, duplicates kept).
std::vector<std::string> var_refs(const Expr& expr);
// The names referred to as $name inside a text (templates, predicates).
std::vector<std::string> template_refs(std::string_view text);

// The value of a resolved expression.
using Value = std::variant<double, std::string>;
struct VarTable {
  std::vector<std::string> names;
  std::vector<Value> values;
  const Value* find(std::string_view name) const;
};

// Draws the expression (vars looked up in `vars`). Throws ExprError for an unknown var.
Value draw(const Expr& expr, core::Rng& rng, const VarTable& vars);
// Replaces every $name in `text` by the var's value (numbers in their shortest exact form).
std::string substitute(std::string_view text, const VarTable& vars);
// Shortest decimal text that reads back to exactly `x`.
std::string format_number(double x);

// Smallest and largest value a numeric expression can take (infinite for unclipped N);
// vars are looked up recursively in `defs` (names/exprs in parallel), unknown vars give
// [-inf, inf].
struct Range {
  double lo, hi;
};
Range value_range(const Expr& expr, const std::vector<std::string>& def_names,
                  const std::vector<Expr>& defs, int depth = 0);
// The string values an expression can take: literal strings and choices of them (recursing
// into vars). `complete` is false when some value is not known before sampling (templates).
struct StringSet {
  std::vector<std::string> values;
  bool complete = true;
};
StringSet string_values(const Expr& expr, const std::vector<std::string>& def_names,
                        const std::vector<Expr>& defs, int depth = 0);
// "number" or "string" for a value, and what an Expr yields: "number", "string", "mixed",
// "unknown" (depends on an unknown var).
std::string expr_type(const Expr& expr, const std::vector<std::string>& def_names,
                      const std::vector<Expr>& defs, int depth = 0);

}  // namespace hribench::script

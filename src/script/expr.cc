#include "script/expr.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>

#include "core/errors.h"
#include "core/limits.h"

namespace hribench::script {
namespace {

constexpr int kMaxVarDepth = 16;
constexpr size_t kMaxChoiceItems = 64;
constexpr double kInf = std::numeric_limits<double>::infinity();

bool word_start(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || c == '_' || c == '$';
}
bool word_char(char c) { return word_start(c) || (c >= '0' && c <= '9') || c == '.'; }
bool digit(char c) { return c >= '0' && c <= '9'; }

// Length of a decimal number at text[i] (sign, digits, fraction, exponent), 0 if none.
size_t number_length(std::string_view text, size_t i) {
  size_t k = i;
  if (k < text.size() && (text[k] == '-' || text[k] == '+')) ++k;
  size_t mantissa = 0;
  while (k < text.size() && digit(text[k])) ++k, ++mantissa;
  if (k < text.size() && text[k] == '.') {
    ++k;
    while (k < text.size() && digit(text[k])) ++k, ++mantissa;
  }
  if (mantissa == 0) return 0;
  if (k < text.size() && (text[k] == 'e' || text[k] == 'E')) {
    size_t e = k + 1;
    if (e < text.size() && (text[e] == '-' || text[e] == '+')) ++e;
    size_t exp_digits = 0;
    while (e < text.size() && digit(text[e])) ++e, ++exp_digits;
    if (exp_digits > 0) k = e;
  }
  return k - i;
}

double parse_number(std::string_view text) {
  double x = 0;
  const char* begin = text.data();
  if (!text.empty() && text[0] == '+') ++begin;
  const auto [end, ec] = std::from_chars(begin, text.data() + text.size(), x);
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(x) ||
      std::fabs(x) > kMaxMagnitude) {
    throw ExprError{"a number within +-1e6", "'" + std::string(text) + "'"};
  }
  return x;
}

std::string quote(std::string_view text) { return "'" + std::string(text) + "'"; }

// Recursive-descent parser over tokens.
class Parser {
 public:
  explicit Parser(std::string_view text) : text_(text), tokens_(tokenize(text)) {}

  Expr parse_all() {
    Expr e = parse_value();
    if (peek().kind != Token::Kind::kEnd) {
      throw ExprError{"the end of the expression", "'" + peek().text + "' after it"};
    }
    return e;
  }

 private:
  const Token& peek() const { return tokens_[i_]; }
  const Token& next() { return tokens_[i_ < tokens_.size() - 1 ? i_++ : i_]; }
  bool is_punct(const char* p) const {
    return peek().kind == Token::Kind::kPunct && peek().text == p;
  }
  void expect(const char* p, const char* context) {
    if (!is_punct(p)) {
      const std::string got = peek().kind == Token::Kind::kEnd ? "the end" : quote(peek().text);
      throw ExprError{std::string("'") + p + "' " + context +
                          " (inside {...} or [...] flow collections, quote the expression)",
                      got};
    }
    next();
  }
  double parse_signed_number(const char* what) {
    if (peek().kind != Token::Kind::kNumber) {
      throw ExprError{std::string("a number for ") + what,
                      peek().kind == Token::Kind::kEnd ? "the end" : quote(peek().text)};
    }
    return next().number;
  }

  Expr parse_value() {
    const Token& t = peek();
    if (t.kind == Token::Kind::kNumber) return Expr::Number(next().number);
    if (t.kind == Token::Kind::kString) return Expr::String(next().text);
    if (t.kind == Token::Kind::kWord) {
      const std::string word = next().text;
      if (is_punct("(")) return parse_call(word);
      if (word[0] == '$' && word.find('$', 1) == std::string::npos &&
          word.find('.') == std::string::npos) {
        if (word.size() == 1) throw ExprError{"a var name after '$'", "'$'"};
        Expr e;
        e.kind = Expr::Kind::kVar;
        e.text = word.substr(1);
        return e;
      }
      if (word.find('$') != std::string::npos) {
        for (const std::string& ref : template_refs(word)) {
          if (ref.empty()) throw ExprError{"a var name after '$'", quote(word)};
        }
        Expr e;
        e.kind = Expr::Kind::kTemplate;
        e.text = word;
        return e;
      }
      return Expr::String(word);
    }
    throw ExprError{"a value", t.kind == Token::Kind::kEnd ? "nothing" : quote(t.text)};
  }

  // A call's arguments may hold calls (choice([choice([...])])): the nesting is bounded here,
  // where the parser recurses (core::kMaxNestingDepth, docs/hardening.md).
  Expr parse_call(const std::string& name) {
    if (calls_open_ == core::kMaxNestingDepth) {
      throw ExprError{"calls nested at most " + std::to_string(core::kMaxNestingDepth) + " deep",
                      "deeper nesting"};
    }
    ++calls_open_;
    Expr e = parse_call_body(name);
    --calls_open_;
    return e;
  }
  Expr parse_call_body(const std::string& name) {
    expect("(", "after the function name");
    Expr e;
    if (name == "U" || name == "Uint") {
      e.kind = name == "U" ? Expr::Kind::kUniform : Expr::Kind::kUniformInt;
      e.a = parse_signed_number("the lower bound");
      expect(",", "between the bounds");
      e.b = parse_signed_number("the upper bound");
      expect(")", "to close the call");
      if (!(e.a < e.b)) {
        throw ExprError{name + "(a, b) with a < b", name + "(" + format_number(e.a) + ", " +
                                                       format_number(e.b) + ")"};
      }
      if (e.kind == Expr::Kind::kUniformInt &&
          (std::floor(e.a) != e.a || std::floor(e.b) != e.b)) {
        throw ExprError{"Uint(a, b) with integer bounds",
                        "Uint(" + format_number(e.a) + ", " + format_number(e.b) + ")"};
      }
      return e;
    }
    if (name == "N") {
      e.kind = Expr::Kind::kNormal;
      e.a = parse_signed_number("the mean");
      expect(",", "between mean and sigma");
      e.b = parse_signed_number("sigma");
      if (is_punct(",")) {
        next();
        if (!(peek().kind == Token::Kind::kWord && peek().text == "clip")) {
          throw ExprError{"clip=[lo, hi] as N's third argument", quote(peek().text)};
        }
        next();
        expect("=", "after clip");
        expect("[", "to open the clip range");
        e.clipped = true;
        e.lo = parse_signed_number("the clip lower bound");
        expect(",", "between the clip bounds");
        e.hi = parse_signed_number("the clip upper bound");
        expect("]", "to close the clip range");
      }
      expect(")", "to close the call");
      if (!(e.b > 0)) {
        throw ExprError{"N(mu, sigma) with sigma > 0", "sigma " + format_number(e.b)};
      }
      if (e.clipped && !(e.lo < e.hi)) {
        throw ExprError{"clip=[lo, hi] with lo < hi",
                        "[" + format_number(e.lo) + ", " + format_number(e.hi) + "]"};
      }
      return e;
    }
    if (name == "choice") {
      e.kind = Expr::Kind::kChoice;
      expect("[", "to open the list of choices");
      while (!is_punct("]")) {
        if (peek().kind == Token::Kind::kEnd) throw ExprError{"']' to close the choices", "the end"};
        e.items.push_back(parse_value());
        if (!is_punct("]")) expect(",", "between choices");
      }
      next();
      if (e.items.empty()) throw ExprError{"at least one choice", "choice([])"};
      if (e.items.size() > kMaxChoiceItems) {
        throw ExprError{"at most 64 choices", std::to_string(e.items.size())};
      }
      if (is_punct(",")) {
        next();
        expect("[", "to open the list of weights");
        double sum = 0;
        while (!is_punct("]")) {
          const double w = parse_signed_number("a weight");
          if (w < 0) throw ExprError{"weights >= 0", format_number(w)};
          e.weights.push_back(w);
          sum += w;
          if (!is_punct("]")) expect(",", "between weights");
        }
        next();
        if (e.weights.size() != e.items.size()) {
          throw ExprError{"one weight per choice (" + std::to_string(e.items.size()) + ")",
                          std::to_string(e.weights.size()) + " weights"};
        }
        if (!(sum > 0)) throw ExprError{"weights with a positive sum", "all zero"};
      }
      expect(")", "to close the call");
      return e;
    }
    throw ExprError{"U, Uint, N or choice", quote(name + "(...)")};
  }

  std::string_view text_;
  std::vector<Token> tokens_;
  int calls_open_ = 0;
  size_t i_ = 0;
};

}  // namespace

Expr Expr::Number(double x) {
  Expr e;
  e.kind = Kind::kNumber;
  e.number = x;
  return e;
}

Expr Expr::String(std::string s) {
  Expr e;
  e.kind = Kind::kString;
  e.text = std::move(s);
  return e;
}

std::vector<Token> tokenize(std::string_view text) {
  std::vector<Token> tokens;
  size_t i = 0;
  while (i < text.size()) {
    const char c = text[i];
    if (c == ' ' || c == '\t' || c == '\n' || c == '\r') {
      ++i;
      continue;
    }
    Token t;
    t.pos = i;
    const size_t num = number_length(text, i);
    // A sign starts a number only when no word or value precedes it directly.
    if (num > 0 && !(i > 0 && word_char(text[i - 1]))) {
      t.kind = Token::Kind::kNumber;
      t.text = std::string(text.substr(i, num));
      t.number = parse_number(t.text);
      i += num;
      if (i < text.size() && word_start(text[i])) {
        throw ExprError{"a number", quote(std::string(text.substr(t.pos, i - t.pos + 1)) + "...")};
      }
    } else if (word_start(c)) {
      t.kind = Token::Kind::kWord;
      size_t k = i;
      while (k < text.size() && word_char(text[k])) ++k;
      t.text = std::string(text.substr(i, k - i));
      i = k;
    } else if (c == '\'' || c == '"') {
      const size_t end = text.find(c, i + 1);
      if (end == std::string_view::npos) throw ExprError{"a closing quote", "the end"};
      t.kind = Token::Kind::kString;
      t.text = std::string(text.substr(i + 1, end - i - 1));
      i = end + 1;
    } else if (std::string_view("()[],=<>").find(c) != std::string_view::npos) {
      t.kind = Token::Kind::kPunct;
      t.text = std::string(1, c);
      ++i;
    } else {
      throw ExprError{"a value, name or one of ( ) [ ] , = < >", quote(std::string(1, c))};
    }
    tokens.push_back(std::move(t));
  }
  Token end;
  end.pos = text.size();
  tokens.push_back(end);
  return tokens;
}

Expr parse_expr(std::string_view text) {
  // A whole-text number or a text without calls is read directly (so free text such as an
  // object colour "light blue" stays one string).
  size_t first = 0;
  while (first < text.size() && text[first] == ' ') ++first;
  size_t last = text.size();
  while (last > first && text[last - 1] == ' ') --last;
  const std::string_view body = text.substr(first, last - first);
  if (!body.empty() && number_length(body, 0) == body.size()) return Expr::Number(parse_number(body));
  const size_t paren = body.find('(');
  if (paren == std::string_view::npos) {
    if (body.find('$') == std::string_view::npos) return Expr::String(std::string(body));
    // $var or template: must be one word.
    return Parser(body).parse_all();
  }
  std::string_view head = body.substr(0, paren);
  while (!head.empty() && head.back() == ' ') head.remove_suffix(1);
  if (head == "U" || head == "Uint" || head == "N" || head == "choice") {
    return Parser(body).parse_all();
  }
  if (body.find('$') != std::string_view::npos) {
    Expr e;
    e.kind = Expr::Kind::kTemplate;
    e.text = std::string(body);
    return e;
  }
  return Expr::String(std::string(body));
}

std::string format_number(double x) {
  char buf[64];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, x);
  HRIB_CHECK(ec == std::errc()) << "to_chars failed";
  return std::string(buf, end);
}

std::string to_source(const Expr& e) {
  switch (e.kind) {
    case Expr::Kind::kNumber:
      return format_number(e.number);
    case Expr::Kind::kString: {
      // Words read back as themselves; anything else is quoted.
      const bool word = !e.text.empty() && word_start(e.text[0]) &&
                        std::all_of(e.text.begin(), e.text.end(), word_char) &&
                        e.text.find('$') == std::string::npos;
      return word ? e.text : "'" + e.text + "'";
    }
    case Expr::Kind::kVar:
      return "$" + e.text;
    case Expr::Kind::kTemplate:
      return e.text;
    case Expr::Kind::kUniform:
      return "U(" + format_number(e.a) + ", " + format_number(e.b) + ")";
    case Expr::Kind::kUniformInt:
      return "Uint(" + format_number(e.a) + ", " + format_number(e.b) + ")";
    case Expr::Kind::kNormal: {
      std::string s = "N(" + format_number(e.a) + ", " + format_number(e.b);
      if (e.clipped) s += ", clip=[" + format_number(e.lo) + ", " + format_number(e.hi) + "]";
      return s + ")";
    }
    case Expr::Kind::kChoice: {
      std::string s = "choice([";
      for (size_t i = 0; i < e.items.size(); ++i) s += (i ? ", " : "") + to_source(e.items[i]);
      s += "]";
      if (!e.weights.empty()) {
        s += ", [";
        for (size_t i = 0; i < e.weights.size(); ++i) s += (i ? ", " : "") + format_number(e.weights[i]);
        s += "]";
      }
      return s + ")";
    }
  }
  return "";
}

std::vector<std::string> template_refs(std::string_view text) {
  std::vector<std::string> refs;
  for (size_t i = text.find('$'); i != std::string_view::npos; i = text.find('$', i + 1)) {
    size_t k = i + 1;
    while (k < text.size() && (word_start(text[k]) || digit(text[k])) && text[k] != '$') ++k;
    refs.emplace_back(text.substr(i + 1, k - i - 1));
  }
  return refs;
}

std::vector<std::string> var_refs(const Expr& e) {
  std::vector<std::string> refs;
  if (e.kind == Expr::Kind::kVar) refs.push_back(e.text);
  if (e.kind == Expr::Kind::kTemplate) refs = template_refs(e.text);
  for (const Expr& item : e.items) {
    for (std::string& r : var_refs(item)) refs.push_back(std::move(r));
  }
  return refs;
}

const Value* VarTable::find(std::string_view name) const {
  for (size_t i = 0; i < names.size(); ++i) {
    if (names[i] == name) return &values[i];
  }
  return nullptr;
}

std::string substitute(std::string_view text, const VarTable& vars) {
  std::string out;
  size_t i = 0;
  while (i < text.size()) {
    if (text[i] != '$') {
      out.push_back(text[i++]);
      continue;
    }
    size_t k = i + 1;
    while (k < text.size() && (word_start(text[k]) || digit(text[k])) && text[k] != '$') ++k;
    const std::string name(text.substr(i + 1, k - i - 1));
    const Value* v = vars.find(name);
    if (v == nullptr) throw ExprError{"a defined var", "$" + name};
    out += std::holds_alternative<double>(*v) ? format_number(std::get<double>(*v))
                                              : std::get<std::string>(*v);
    i = k;
  }
  return out;
}

Value draw(const Expr& e, core::Rng& rng, const VarTable& vars) {
  switch (e.kind) {
    case Expr::Kind::kNumber:
      return e.number;
    case Expr::Kind::kString:
      return e.text;
    case Expr::Kind::kVar: {
      const Value* v = vars.find(e.text);
      if (v == nullptr) throw ExprError{"a defined var", "$" + e.text};
      return *v;
    }
    case Expr::Kind::kTemplate:
      return substitute(e.text, vars);
    case Expr::Kind::kUniform:
      return rng.uniform(e.a, e.b);
    case Expr::Kind::kUniformInt:
      return static_cast<double>(
          rng.uniform_int(static_cast<int64_t>(e.a), static_cast<int64_t>(e.b)));
    case Expr::Kind::kNormal: {
      if (!e.clipped) return rng.normal(e.a, e.b);
      // Rejection keeps the shape inside the clip range; clamp only after 100 misses.
      for (int attempt = 0; attempt < 100; ++attempt) {
        const double x = rng.normal(e.a, e.b);
        if (x >= e.lo && x <= e.hi) return x;
      }
      return std::clamp(e.a, e.lo, e.hi);
    }
    case Expr::Kind::kChoice: {
      size_t index = 0;
      if (e.weights.empty()) {
        index = static_cast<size_t>(rng.uniform_int(0, static_cast<int64_t>(e.items.size()) - 1));
      } else {
        index = rng.weighted_index(e.weights);
      }
      return draw(e.items[index], rng, vars);
    }
  }
  return 0.0;
}

namespace {
const Expr* find_def(std::string_view name, const std::vector<std::string>& names,
                     const std::vector<Expr>& defs) {
  for (size_t i = 0; i < names.size(); ++i) {
    if (names[i] == name) return &defs[i];
  }
  return nullptr;
}
}  // namespace

Range value_range(const Expr& e, const std::vector<std::string>& names,
                  const std::vector<Expr>& defs, int depth) {
  switch (e.kind) {
    case Expr::Kind::kNumber:
      return {e.number, e.number};
    case Expr::Kind::kUniform:
    case Expr::Kind::kUniformInt:
      return {e.a, e.b};
    case Expr::Kind::kNormal:
      return e.clipped ? Range{e.lo, e.hi} : Range{-kInf, kInf};
    case Expr::Kind::kVar: {
      const Expr* def = find_def(e.text, names, defs);
      if (def == nullptr || depth > kMaxVarDepth) return {-kInf, kInf};
      return value_range(*def, names, defs, depth + 1);
    }
    case Expr::Kind::kChoice: {
      Range r{kInf, -kInf};
      for (size_t i = 0; i < e.items.size(); ++i) {
        if (!e.weights.empty() && e.weights[i] == 0) continue;
        const Range item = value_range(e.items[i], names, defs, depth + 1);
        r.lo = std::min(r.lo, item.lo);
        r.hi = std::max(r.hi, item.hi);
      }
      return r;
    }
    default:
      return {-kInf, kInf};
  }
}

StringSet string_values(const Expr& e, const std::vector<std::string>& names,
                        const std::vector<Expr>& defs, int depth) {
  StringSet set;
  if (e.kind == Expr::Kind::kString) {
    set.values.push_back(e.text);
  } else if (e.kind == Expr::Kind::kVar) {
    const Expr* def = find_def(e.text, names, defs);
    if (def == nullptr || depth > kMaxVarDepth) {
      set.complete = false;
    } else {
      set = string_values(*def, names, defs, depth + 1);
    }
  } else if (e.kind == Expr::Kind::kChoice) {
    for (const Expr& item : e.items) {
      StringSet sub = string_values(item, names, defs, depth + 1);
      set.complete = set.complete && sub.complete;
      for (std::string& v : sub.values) {
        if (std::find(set.values.begin(), set.values.end(), v) == set.values.end()) {
          set.values.push_back(std::move(v));
        }
      }
    }
  } else if (e.kind == Expr::Kind::kTemplate) {
    // Expand templates whose vars are string choices (human.$hand -> human.left, human.right).
    std::vector<std::string> partial = {""};
    const std::string& t = e.text;
    size_t i = 0;
    while (i < t.size()) {
      if (t[i] != '$') {
        for (std::string& p : partial) p.push_back(t[i]);
        ++i;
        continue;
      }
      size_t k = i + 1;
      while (k < t.size() && (word_start(t[k]) || digit(t[k])) && t[k] != '$') ++k;
      Expr ref;
      ref.kind = Expr::Kind::kVar;
      ref.text = t.substr(i + 1, k - i - 1);
      const StringSet sub = string_values(ref, names, defs, depth + 1);
      if (!sub.complete || sub.values.empty() || partial.size() * sub.values.size() > 256) {
        set.complete = false;
        return set;
      }
      std::vector<std::string> next;
      for (const std::string& p : partial) {
        for (const std::string& v : sub.values) next.push_back(p + v);
      }
      partial = std::move(next);
      i = k;
    }
    set.values = std::move(partial);
  } else {
    set.complete = false;
  }
  return set;
}

std::string expr_type(const Expr& e, const std::vector<std::string>& names,
                      const std::vector<Expr>& defs, int depth) {
  switch (e.kind) {
    case Expr::Kind::kNumber:
    case Expr::Kind::kUniform:
    case Expr::Kind::kUniformInt:
    case Expr::Kind::kNormal:
      return "number";
    case Expr::Kind::kString:
    case Expr::Kind::kTemplate:
      return "string";
    case Expr::Kind::kVar: {
      const Expr* def = find_def(e.text, names, defs);
      if (def == nullptr || depth > kMaxVarDepth) return "unknown";
      return expr_type(*def, names, defs, depth + 1);
    }
    case Expr::Kind::kChoice: {
      std::string type;
      for (const Expr& item : e.items) {
        const std::string t = expr_type(item, names, defs, depth + 1);
        if (t == "unknown") return t;
        if (type.empty()) type = t;
        if (t != type) return "mixed";
      }
      return type;
    }
  }
  return "unknown";
}

}  // namespace hribench::script

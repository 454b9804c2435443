#include "core/json.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include "core/errors.h"
#include "core/limits.h"

namespace hribench::core {
namespace {

// Every number finite, recursively; `path` names the offending member.
void require_finite(const Json& value, const std::string& path) {
  if (value.is_number_float() && !std::isfinite(value.get<double>())) {
    throw InputError(path.empty() ? "(root)" : path, "a finite number", "NaN or infinity");
  }
  if (value.is_object()) {
    for (auto it = value.begin(); it != value.end(); ++it) {
      require_finite(it.value(), path.empty() ? it.key() : path + "." + it.key());
    }
  } else if (value.is_array()) {
    for (size_t i = 0; i < value.size(); ++i) {
      require_finite(value[i], path + "[" + std::to_string(i) + "]");
    }
  }
}

// Builds the DOM as nlohmann's own parser does, but refuses nesting deeper than
// kMaxNestingDepth (the DOM, its destructor and every reader recurse once per level) and keeps
// the position and reason of a failure, so that every error, a number out of double range
// (1e400) included, becomes an InputError with a location.
class BoundedDomBuilder {
 public:
  explicit BoundedDomBuilder(Json& root) : dom_(root, /*allow_exceptions=*/false) {}

  bool null() { return dom_.null(); }
  bool boolean(bool v) { return dom_.boolean(v); }
  bool number_integer(Json::number_integer_t v) { return dom_.number_integer(v); }
  bool number_unsigned(Json::number_unsigned_t v) { return dom_.number_unsigned(v); }
  bool number_float(Json::number_float_t v, const Json::string_t& s) { return dom_.number_float(v, s); }
  bool string(Json::string_t& v) { return dom_.string(v); }
  bool binary(Json::binary_t& v) { return dom_.binary(v); }
  bool key(Json::string_t& v) { return dom_.key(v); }
  bool start_object(std::size_t n) { return deeper() && dom_.start_object(n); }
  bool end_object() {
    --depth_;
    return dom_.end_object();
  }
  bool start_array(std::size_t n) { return deeper() && dom_.start_array(n); }
  bool end_array() {
    --depth_;
    return dom_.end_array();
  }
  template <class Exception>
  bool parse_error(std::size_t position, const std::string& token, const Exception& e) {
    failed_at_ = position;
    token_ = token;
    reason_ = e.what();
    number_overflow_ = e.id == 406;
    return false;
  }

  bool too_deep() const { return too_deep_; }
  bool number_overflow() const { return number_overflow_; }
  size_t failed_at() const { return failed_at_; }  // characters read when the parser failed
  const std::string& token() const { return token_; }
  const std::string& reason() const { return reason_; }

 private:
  bool deeper() {
    if (++depth_ <= kMaxNestingDepth) return true;
    too_deep_ = true;
    return false;
  }
  nlohmann::detail::json_sax_dom_parser<Json> dom_;
  int depth_ = 0;
  bool too_deep_ = false;
  bool number_overflow_ = false;
  size_t failed_at_ = 0;
  std::string token_;
  std::string reason_;
};

// Byte offset of the bracket that opens nesting level kMaxNestingDepth + 1 (strings skipped).
size_t too_deep_offset(std::string_view text) {
  int depth = 0;
  bool in_string = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\') ++i;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxNestingDepth) return i;
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return text.size();
}

// 1-based line and column of byte `offset` in `text`.
std::string line_col(std::string_view text, size_t offset, size_t first_line) {
  size_t line = first_line, col = 1;
  for (size_t i = 0; i < offset && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      col = 1;
    } else {
      ++col;
    }
  }
  return std::to_string(line) + ":" + std::to_string(col);
}

}  // namespace

std::string canonical_json(const Json& value) {
  require_finite(value, "");
  return value.dump();
}

std::string pretty_json(const Json& value) {
  require_finite(value, "");
  return value.dump(2);
}

Json parse_json(std::string_view text, std::string_view source, size_t first_line) {
  Json root;
  BoundedDomBuilder builder(root);
  if (Json::sax_parse(text.begin(), text.end(), &builder)) return root;
  const std::string where = std::string(source) + ":";
  if (builder.too_deep()) {
    throw InputError(where + line_col(text, too_deep_offset(text), first_line),
                     "nesting at most " + std::to_string(kMaxNestingDepth) + " deep", "deeper nesting");
  }
  const size_t offset = builder.failed_at() > 0 ? builder.failed_at() - 1 : 0;
  if (builder.number_overflow()) {  // located at the number's first character
    std::string token = builder.token();
    const size_t start = builder.failed_at() >= token.size() ? builder.failed_at() - token.size() : 0;
    if (token.size() > 40) token = token.substr(0, 37) + "...";
    throw InputError(where + line_col(text, start, first_line), "a number within the range of a double",
                     "'" + token + "'");
  }
  throw InputError::Message(where + line_col(text, offset, first_line), "invalid JSON (" + builder.reason() + ")");
}

Json read_json_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError::Message(path, "cannot open file");
  std::ostringstream text;
  text << in.rdbuf();
  return parse_json(text.str(), path);
}

std::string json_kind(const Json& value) {
  if (value.is_object()) return "object";
  if (value.is_array()) return "array";
  if (value.is_string()) return "string";
  if (value.is_number()) return "number";
  if (value.is_boolean()) return "boolean";
  return "null";
}

const Json& json_member(const Json& object, std::string_view key, std::string_view path) {
  if (!object.is_object()) throw InputError(std::string(path), "an object", json_kind(object));
  const auto it = object.find(key);
  if (it == object.end()) {
    throw InputError(std::string(path), "a member '" + std::string(key) + "'", "none");
  }
  return *it;
}

double json_number(const Json& value, std::string_view path) {
  if (!value.is_number()) throw InputError(std::string(path), "a number", json_kind(value));
  const double x = value.get<double>();
  if (!std::isfinite(x)) throw InputError(std::string(path), "a finite number", "NaN or infinity");
  return x;
}

std::string json_string(const Json& value, std::string_view path) {
  if (!value.is_string()) throw InputError(std::string(path), "a string", json_kind(value));
  return value.get<std::string>();
}

bool json_bool(const Json& value, std::string_view path) {
  if (!value.is_boolean()) throw InputError(std::string(path), "a boolean", json_kind(value));
  return value.get<bool>();
}

}  // namespace hribench::core

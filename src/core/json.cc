#include "core/json.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include "core/errors.h"

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

// 1-based line and column of byte `offset` in `text`.
std::string line_col(std::string_view text, size_t offset) {
  size_t line = 1, col = 1;
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

Json parse_json(std::string_view text, std::string_view source) {
  try {
    return Json::parse(text.begin(), text.end());
  } catch (const Json::parse_error& e) {
    const size_t offset = e.byte > 0 ? e.byte - 1 : 0;
    throw InputError::Message(std::string(source) + ":" + line_col(text, offset),
                              "invalid JSON (" + std::string(e.what()) + ")");
  }
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

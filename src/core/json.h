#pragma once
// JSON helpers on nlohmann::json: canonical text (the bytes a content hash is taken of),
// parsing with file:line:col errors, and typed member access that throws core::InputError.
//
// Doubles round-trip exactly: nlohmann writes the shortest decimal that reads back to the same
// double. NaN and infinities have no JSON form and are refused (InputError), never written as
// null.

#include <nlohmann/json.hpp>

#include <string>
#include <string_view>

namespace hribench::core {

using Json = nlohmann::json;  // objects keep their keys sorted (std::map)

// Compact text with sorted keys, no spaces. Throws InputError (where = key path) when a number
// is NaN or infinite.
std::string canonical_json(const Json& value);
// Indented text for people (same content as canonical_json).
std::string pretty_json(const Json& value);

// Parses `text`; every error is an InputError with where "SOURCE:line:col": bad syntax, a number
// beyond the range of a double (1e400), nesting deeper than kMaxNestingDepth (core/limits.h).
// Every reader of outside JSON parses through here. `first_line` numbers the first line of
// `text` (a line of a JSON-lines file).
Json parse_json(std::string_view text, std::string_view source, size_t first_line = 1);
// Reads and parses a file. Throws InputError when it cannot be opened or parsed.
Json read_json_file(const std::string& path);

// Typed access for readers: `path` names the object for error messages ("spec.acts[2]").
const Json& json_member(const Json& object, std::string_view key, std::string_view path);
double json_number(const Json& value, std::string_view path);   // finite number
std::string json_string(const Json& value, std::string_view path);
bool json_bool(const Json& value, std::string_view path);

// "object", "array", "string", "number", "boolean" or "null".
std::string json_kind(const Json& value);

}  // namespace hribench::core

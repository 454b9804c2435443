#pragma once
// Loading YAML for people-written files (scenario scripts, configs) with exact locations.
//
// yaml-cpp 0.7 accepts things a benchmark must not: duplicate keys (the last silently wins),
// tabs in indentation, arbitrary bytes. parse_yaml() refuses them and reports EVERY problem it
// finds as a core::InputError whose where() is "FILE:LINE:COL (key.path)", 1-based, so a
// validator can print them all. Numbers are left as scalars: typed readers decide (and refuse
// NaN, infinities and absurd magnitudes).

#include <yaml-cpp/yaml.h>

#include <string>
#include <string_view>
#include <vector>

#include "core/errors.h"
#include "core/limits.h"

namespace hribench::core {

inline constexpr size_t kMaxYamlBytes = 4u << 20;     // 4 MiB of text
inline constexpr size_t kMaxYamlNodes = 200000;       // nodes visited (alias bombs)

struct YamlDocument {
  std::string file;  // as given; used in every location
  YAML::Node root;   // IsNull() when the text could not be parsed at all
};

// Parses `text` (named `file` in messages). Appends every problem to `problems`: bytes that
// are not UTF-8 or are control characters, tabs in indentation, syntax errors, duplicate or
// non-scalar mapping keys, nesting deeper than core::kMaxNestingDepth (core/limits.h), more than
// kMaxYamlNodes nodes. When the bytes or the indentation are bad the text is not handed to
// yaml-cpp, and when the tree is too deep or too large (a cyclic alias is infinitely deep) it is
// not handed on: root is null in both cases, so a reader that walks the tree never recurses
// past the limit.
YamlDocument parse_yaml(std::string_view text, std::string file,
                        std::vector<InputError>& problems);
// Reads `path` and parses it; "cannot open file" is a problem too.
YamlDocument load_yaml_file(const std::string& path, std::vector<InputError>& problems);
// Throwing form: the first problem, if any.
YamlDocument parse_yaml(std::string_view text, std::string file);

// "FILE:LINE:COL (key.path)" with 1-based line and column; "(key.path)" left out when empty.
std::string yaml_where(std::string_view file, const YAML::Mark& mark, std::string_view key_path);
// True when the node is a quoted scalar ("..." or '...'), i.e. a string no matter how it reads.
bool yaml_quoted(const YAML::Node& node);
// What a node is, for "got ..." in messages: "a mapping", "a sequence", "null", "'text'".
std::string yaml_kind(const YAML::Node& node);

}  // namespace hribench::core

#include "core/yaml.h"

#include <fstream>
#include <map>
#include <sstream>

namespace hribench::core {
namespace {

std::string loc(std::string_view file, size_t line, size_t col) {
  return std::string(file) + ":" + std::to_string(line) + ":" + std::to_string(col);
}

// Length of the UTF-8 sequence at text[i], or 0 when it is not valid (overlong forms,
// surrogates, code points past U+10FFFF and truncated sequences are all invalid).
size_t utf8_length(std::string_view text, size_t i) {
  const auto byte = [&](size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char b0 = byte(i);
  if (b0 < 0x80) return 1;
  size_t n = 0;
  uint32_t cp = 0;
  if ((b0 & 0xE0) == 0xC0) {
    n = 2;
    cp = b0 & 0x1Fu;
  } else if ((b0 & 0xF0) == 0xE0) {
    n = 3;
    cp = b0 & 0x0Fu;
  } else if ((b0 & 0xF8) == 0xF0) {
    n = 4;
    cp = b0 & 0x07u;
  } else {
    return 0;
  }
  if (i + n > text.size()) return 0;
  for (size_t k = 1; k < n; ++k) {
    if ((byte(i + k) & 0xC0) != 0x80) return 0;
    cp = (cp << 6) | (byte(i + k) & 0x3Fu);
  }
  static constexpr uint32_t kMin[] = {0, 0, 0x80, 0x800, 0x10000};
  if (cp < kMin[n] || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return 0;
  return n;
}

// Byte-level checks: UTF-8, control characters, tabs in indentation. Returns false when the
// text must not be parsed.
bool check_bytes(std::string_view text, const std::string& file, std::vector<InputError>& out) {
  bool ok = true;
  size_t line = 1, col = 1;
  bool in_indent = true;
  size_t reported = 0;
  for (size_t i = 0; i < text.size();) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    const size_t n = utf8_length(text, i);
    if (n == 0) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "0x%02X", c);
      out.push_back(InputError(loc(file, line, col), "UTF-8 text", "the byte " + std::string(hex)));
      return false;  // one is enough: the rest of the file cannot be trusted
    }
    if (c == '\n') {
      ++line;
      col = 1;
      in_indent = true;
      ++i;
      continue;
    }
    if (c == '\t' && in_indent) {
      if (reported++ < 10) {
        out.push_back(InputError(loc(file, line, col), "spaces for indentation", "a tab"));
      }
      ok = false;
    } else if (c < 0x20 && c != '\t' && c != '\r') {
      out.push_back(InputError(loc(file, line, col), "printable text",
                               "the control character " + std::to_string(c)));
      return false;
    }
    if (c != ' ' && c != '\t') in_indent = false;
    i += n;
    ++col;
  }
  return ok;
}

// Walks the tree: duplicate and non-scalar keys, depth, node count.
struct TreeCheck {
  const std::string& file;
  std::vector<InputError>& out;
  size_t nodes = 0;
  bool stopped = false;

  void visit(const YAML::Node& node, const std::string& path, int depth) {
    if (stopped) return;
    if (++nodes > kMaxYamlNodes) {
      out.push_back(InputError(yaml_where(file, node.Mark(), path),
                               "at most " + std::to_string(kMaxYamlNodes) + " nodes",
                               "more (nested aliases?)"));
      stopped = true;
      return;
    }
    if ((node.IsMap() || node.IsSequence()) && depth >= kMaxNestingDepth) {
      out.push_back(InputError(yaml_where(file, node.Mark(), path),
                               "nesting at most " + std::to_string(kMaxNestingDepth) + " deep",
                               "deeper nesting"));
      stopped = true;
      return;
    }
    if (node.IsMap()) {
      std::map<std::string, YAML::Mark> seen;
      for (auto it = node.begin(); it != node.end(); ++it) {
        if (!it->first.IsScalar()) {
          out.push_back(InputError(yaml_where(file, it->first.Mark(), path), "a plain key",
                                   yaml_kind(it->first)));
          continue;
        }
        const std::string key = it->first.Scalar();
        const std::string child = path.empty() ? key : path + "." + key;
        const auto [first, inserted] = seen.emplace(key, it->first.Mark());
        if (!inserted) {
          out.push_back(InputError(yaml_where(file, it->first.Mark(), child),
                                   "each key once in a mapping",
                                   "'" + key + "' again (first at line " +
                                       std::to_string(first->second.line + 1) + ")"));
        }
        visit(it->second, child, depth + 1);
      }
    } else if (node.IsSequence()) {
      for (size_t i = 0; i < node.size(); ++i) {
        visit(node[i], path + "[" + std::to_string(i) + "]", depth + 1);
      }
    }
  }
};

}  // namespace

std::string yaml_where(std::string_view file, const YAML::Mark& mark, std::string_view key_path) {
  std::string where = loc(file, static_cast<size_t>(mark.line + 1), static_cast<size_t>(mark.column + 1));
  if (!key_path.empty()) where += " (" + std::string(key_path) + ")";
  return where;
}

bool yaml_quoted(const YAML::Node& node) { return node.IsScalar() && node.Tag() == "!"; }

std::string yaml_kind(const YAML::Node& node) {
  if (node.IsMap()) return "a mapping";
  if (node.IsSequence()) return "a sequence";
  if (node.IsScalar()) {
    std::string text = node.Scalar();
    if (text.size() > 40) text = text.substr(0, 37) + "...";
    return "'" + text + "'";
  }
  return "nothing (null)";
}

YamlDocument parse_yaml(std::string_view text, std::string file,
                        std::vector<InputError>& problems) {
  YamlDocument doc{std::move(file), YAML::Node()};
  if (text.size() > kMaxYamlBytes) {
    problems.push_back(InputError(doc.file, "at most " + std::to_string(kMaxYamlBytes) + " bytes",
                                  std::to_string(text.size()) + " bytes"));
    return doc;
  }
  if (!check_bytes(text, doc.file, problems)) return doc;
  try {
    doc.root = YAML::Load(std::string(text));
  } catch (const YAML::Exception& e) {
    // yaml-cpp's messages start with "yaml-cpp: error at line ..."; keep only the reason.
    problems.push_back(InputError::Message(
        loc(doc.file, static_cast<size_t>(e.mark.line + 1), static_cast<size_t>(e.mark.column + 1)),
        "invalid YAML: " + e.msg));
    doc.root = YAML::Node();
    return doc;
  }
  TreeCheck check{doc.file, problems};
  check.visit(doc.root, "", 0);
  if (check.stopped) doc.root = YAML::Node();  // too deep or too large to walk
  return doc;
}

YamlDocument load_yaml_file(const std::string& path, std::vector<InputError>& problems) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    problems.push_back(InputError::Message(path, "cannot open file"));
    return {path, YAML::Node()};
  }
  std::ostringstream text;
  text << in.rdbuf();
  return parse_yaml(text.str(), path, problems);
}

YamlDocument parse_yaml(std::string_view text, std::string file) {
  std::vector<InputError> problems;
  YamlDocument doc = parse_yaml(text, std::move(file), problems);
  if (!problems.empty()) throw problems.front();
  return doc;
}

}  // namespace hribench::core

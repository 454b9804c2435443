#include "script/schema_io.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <type_traits>

#include "core/yaml.h"

namespace hribench::script {
namespace {

template <class T>
struct IsOptional : std::false_type {};
template <class T>
struct IsOptional<std::optional<T>> : std::true_type {};
template <class T>
struct IsVector : std::false_type {};
template <class T>
struct IsVector<std::vector<T>> : std::true_type {};
template <class T>
struct IsNamed : std::false_type {};
template <class T>
struct IsNamed<std::vector<Entry<T>>> : std::true_type {};

struct KeyCollector {
  std::vector<std::string> keys;
  template <class T>
  void req(const char* key, T&, const char*) { keys.emplace_back(key); }
  template <class T>
  void opt(const char* key, T&, const char*) { keys.emplace_back(key); }
  template <class T>
  void rest(T&, const char*) {}
};

template <class T>
concept Visitable = requires(T& t, KeyCollector& v) { t.visit(v); };

bool is_name(const std::string& s) {
  if (s.empty() || s.size() > 64) return false;
  if (!((s[0] >= 'a' && s[0] <= 'z') || (s[0] >= 'A' && s[0] <= 'Z') || s[0] == '_')) return false;
  return std::all_of(s.begin(), s.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
  });
}

std::string join(const std::vector<std::string>& items) {
  std::string s;
  for (size_t i = 0; i < items.size(); ++i) s += (i ? ", " : "") + items[i];
  return s;
}

bool looks_non_finite(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](char c) {
    return static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c);
  });
  for (const char* word : {".nan", "nan", ".inf", "-.inf", "+.inf", "inf", "-inf", "infinity"}) {
    if (text == word) return true;
  }
  return false;
}

// ---------------------------------------------------------------------------------------------
// YAML -> structs, collecting every problem.
class YamlIn {
 public:
  YamlIn(std::string file, std::vector<core::InputError>& problems,
         std::map<std::string, std::string>& locations)
      : file_(std::move(file)), problems_(problems), locations_(locations) {}

  template <class T>
  void req(const char* key, T& member, const char*) {
    field(key, member, true);
  }
  template <class T>
  void opt(const char* key, T& member, const char*) {
    field(key, member, false);
  }
  template <class T>
  void rest(Named<T>& member, const char*) {
    frame_->has_rest = true;
    for (auto it = frame_->node.begin(); it != frame_->node.end(); ++it) {
      if (!it->first.IsScalar()) continue;
      const std::string key = it->first.Scalar();
      if (std::find(frame_->known.begin(), frame_->known.end(), key) != frame_->known.end()) continue;
      Entry<T> entry;
      entry.name = key;
      entry.where.text = where(it->first, child(key));
      locations_[child(key)] = entry.where.text;
      read(it->second, child(key), entry.value);
      member.push_back(std::move(entry));
    }
  }

  template <class T>
  void read_root(const YAML::Node& node, T& out) {
    read(node, "", out);
  }

 private:
  struct Frame {
    YAML::Node node;
    std::string path;
    std::vector<std::string> known;
    bool has_rest = false;
  };

  std::string child(const std::string& key) const {
    return frame_->path.empty() ? key : frame_->path + "." + key;
  }
  std::string where(const YAML::Node& n, const std::string& path) const {
    return core::yaml_where(file_, n.Mark(), path);
  }
  void problem(const YAML::Node& n, const std::string& path, std::string expected, std::string got) {
    problems_.push_back(core::InputError(where(n, path), std::move(expected), std::move(got)));
  }

  template <class T>
  void field(const char* key, T& member, bool required) {
    frame_->known.emplace_back(key);
    const YAML::Node n = frame_->node[key];
    if (!n.IsDefined()) {
      if (required) problem(frame_->node, frame_->path, std::string("a key '") + key + "'", "none");
      return;
    }
    locations_[child(key)] = where(n, child(key));
    read(n, child(key), member);
  }

  bool scalar(const YAML::Node& n, const std::string& path, const std::string& expected) {
    if (n.IsScalar()) return true;
    problem(n, path, expected, core::yaml_kind(n));
    return false;
  }

  bool parse(const YAML::Node& n, const std::string& path, Expr& out) {
    try {
      out = parse_expr(n.Scalar());
      return true;
    } catch (const ExprError& e) {
      problem(n, path, e.expected, e.got);
      return false;
    }
  }

  // Scalars.
  void read(const YAML::Node& n, const std::string& path, std::string& out) {
    if (scalar(n, path, "a word or text")) out = n.Scalar();
  }
  void read(const YAML::Node& n, const std::string& path, bool& out) {
    if (!scalar(n, path, "true or false")) return;
    if (n.Scalar() == "true") {
      out = true;
    } else if (n.Scalar() == "false") {
      out = false;
    } else {
      problem(n, path, "true or false", "'" + n.Scalar() + "'");
    }
  }
  void read(const YAML::Node& n, const std::string& path, double& out) {
    if (!scalar(n, path, "a number")) return;
    Expr e;
    if (!parse(n, path, e)) return;
    if (e.kind != Expr::Kind::kNumber) {
      problem(n, path, looks_non_finite(n.Scalar()) ? "a finite number" : "a number",
              "'" + n.Scalar() + "'");
      return;
    }
    out = e.number;
  }
  void read(const YAML::Node& n, const std::string& path, int& out) {
    double x = 0;
    const size_t before = problems_.size();
    read(n, path, x);
    if (problems_.size() != before) return;
    if (std::floor(x) != x) {
      problem(n, path, "an integer", "'" + n.Scalar() + "'");
      return;
    }
    out = static_cast<int>(x);
  }
  void read(const YAML::Node& n, const std::string& path, uint64_t& out) {
    if (!scalar(n, path, "an unsigned integer")) return;
    const std::string& s = n.Scalar();
    if (s.empty() || s.size() > 20 || !std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; })) {
      problem(n, path, "an unsigned integer", "'" + s + "'");
      return;
    }
    out = std::stoull(s);
  }
  void read(const YAML::Node& n, const std::string& path, Num& out) {
    out.where.text = where(n, path);
    out.bad = true;
    if (!scalar(n, path, "a number or a distribution")) return;
    Expr e;
    if (!parse(n, path, e)) return;
    const auto numeric = [](const Expr& x) {
      return x.kind == Expr::Kind::kNumber || x.kind == Expr::Kind::kUniform ||
             x.kind == Expr::Kind::kUniformInt || x.kind == Expr::Kind::kNormal ||
             x.kind == Expr::Kind::kVar;
    };
    bool ok = numeric(e);
    if (e.kind == Expr::Kind::kChoice) ok = std::all_of(e.items.begin(), e.items.end(), numeric);
    if (!ok) {
      problem(n, path,
              looks_non_finite(n.Scalar()) ? "a finite number"
                                           : "a number or a distribution (U, Uint, N, choice of numbers)",
              "'" + n.Scalar() + "'");
      return;
    }
    out.expr = std::move(e);
    out.bad = false;
  }
  void read(const YAML::Node& n, const std::string& path, Text& out) {
    out.where.text = where(n, path);
    out.bad = true;
    if (!scalar(n, path, "a word, $var or choice([...])")) return;
    Expr e;
    if (!parse(n, path, e)) return;
    if (e.kind == Expr::Kind::kNumber) e = Expr::String(n.Scalar());
    const auto textual = [](const Expr& x) {
      return x.kind == Expr::Kind::kString || x.kind == Expr::Kind::kVar ||
             x.kind == Expr::Kind::kTemplate;
    };
    bool ok = textual(e);
    if (e.kind == Expr::Kind::kChoice) ok = std::all_of(e.items.begin(), e.items.end(), textual);
    if (!ok) {
      problem(n, path, "a word, $var or choice([...]) of words", "'" + n.Scalar() + "'");
      return;
    }
    out.expr = std::move(e);
    out.bad = false;
  }
  void read(const YAML::Node& n, const std::string& path, Any& out) {
    out.where.text = where(n, path);
    out.bad = !scalar(n, path, "a value, $var or distribution") || !parse(n, path, out.expr);
  }
  void read(const YAML::Node& n, const std::string& path, Pred& out) {
    out.where.text = where(n, path);
    if (scalar(n, path, "a predicate such as in(item, bin)")) out.source = n.Scalar();
  }
  void read(const YAML::Node& n, const std::string& path, ValueTree& out) {
    out.where.text = where(n, path);
    if (n.IsScalar()) {
      out.kind = ValueTree::Kind::kScalar;
      read(n, path, out.scalar);
    } else if (n.IsSequence()) {
      out.kind = ValueTree::Kind::kList;
      out.items.resize(n.size());
      for (size_t i = 0; i < n.size(); ++i) read(n[i], path + "[" + std::to_string(i) + "]", out.items[i]);
    } else if (n.IsMap()) {
      out.kind = ValueTree::Kind::kMap;
      for (auto it = n.begin(); it != n.end(); ++it) {
        if (!it->first.IsScalar()) continue;
        // Keys in name order (the canonical order, as JSON objects keep it).
        const std::string key = it->first.Scalar();
        const size_t at = static_cast<size_t>(
            std::lower_bound(out.keys.begin(), out.keys.end(), key) - out.keys.begin());
        out.keys.insert(out.keys.begin() + static_cast<std::ptrdiff_t>(at), key);
        ValueTree item;
        read(it->second, path + "." + key, item);
        out.items.insert(out.items.begin() + static_cast<std::ptrdiff_t>(at), std::move(item));
      }
    } else {
      problem(n, path, "a value", core::yaml_kind(n));
    }
  }

  // Containers.
  template <class T>
  void read(const YAML::Node& n, const std::string& path, std::optional<T>& out) {
    out.emplace();
    read(n, path, *out);
  }
  template <class T>
  void read(const YAML::Node& n, const std::string& path, std::vector<T>& out) {
    if constexpr (std::is_same_v<T, Pred>) {
      if (n.IsScalar()) {  // a single predicate stands for a list of one
        out.emplace_back();
        read(n, path, out.back());
        return;
      }
    }
    if (!n.IsSequence()) {
      problem(n, path, "a sequence [...]", core::yaml_kind(n));
      return;
    }
    out.resize(n.size());
    for (size_t i = 0; i < n.size(); ++i) read(n[i], path + "[" + std::to_string(i) + "]", out[i]);
  }
  template <class T>
  void read(const YAML::Node& n, const std::string& path, Named<T>& out) {
    if (!n.IsMap()) {
      problem(n, path, "a mapping of names", core::yaml_kind(n));
      return;
    }
    for (auto it = n.begin(); it != n.end(); ++it) {
      if (!it->first.IsScalar()) continue;  // reported by core::parse_yaml
      const std::string key = it->first.Scalar();
      const std::string sub = path.empty() ? key : path + "." + key;
      if (!is_name(key)) {
        problem(it->first, sub, "a name of letters, digits and _ (not starting with a digit)", "'" + key + "'");
        continue;
      }
      Entry<T> entry;
      entry.name = key;
      entry.where.text = where(it->first, sub);
      locations_[sub] = entry.where.text;
      read(it->second, sub, entry.value);
      out.push_back(std::move(entry));
    }
  }
  template <Visitable T>
  void read(const YAML::Node& n, const std::string& path, T& out) {
    if (!n.IsMap()) {
      problem(n, path, std::string("a mapping (") + T::kSchemaName + ")", core::yaml_kind(n));
      return;
    }
    Frame frame{n, path, {}, false};
    Frame* saved = frame_;
    frame_ = &frame;
    out.visit(*this);
    frame_ = saved;
    if (frame.has_rest) return;
    for (auto it = n.begin(); it != n.end(); ++it) {
      if (!it->first.IsScalar()) continue;
      const std::string key = it->first.Scalar();
      if (std::find(frame.known.begin(), frame.known.end(), key) == frame.known.end()) {
        const std::string sub = path.empty() ? key : path + "." + key;
        problem(it->first, sub, std::string("a key of ") + T::kSchemaName + " (" + join(frame.known) + ")",
                "unknown key '" + key + "'");
      }
    }
  }

  std::string file_;
  std::vector<core::InputError>& problems_;
  std::map<std::string, std::string>& locations_;
  Frame* frame_ = nullptr;
};

// ---------------------------------------------------------------------------------------------
// structs -> JSON.
class JsonOut {
 public:
  core::Json* out = nullptr;

  template <class T>
  void req(const char* key, T& member, const char*) {
    (*out)[key] = write(member);
  }
  template <class T>
  void opt(const char* key, T& member, const char*) {
    if constexpr (IsOptional<T>::value) {
      if (!member.has_value()) return;
    }
    (*out)[key] = write(member);
  }
  template <class T>
  void rest(Named<T>& member, const char*) {
    for (Entry<T>& e : member) (*out)[e.name] = write(e.value);
  }

  static core::Json write(const std::string& s) { return s; }
  static core::Json write(bool b) { return b; }
  static core::Json write(double x) { return x; }
  static core::Json write(int x) { return x; }
  static core::Json write(uint64_t x) { return x; }
  static core::Json write(const Param& p) {
    if (p.expr.kind == Expr::Kind::kNumber) return p.expr.number;
    if (p.expr.kind == Expr::Kind::kString) return p.expr.text;
    return to_source(p.expr);
  }
  static core::Json write(const Pred& p) { return p.source; }
  static core::Json write(const ValueTree& t) {
    if (t.kind == ValueTree::Kind::kScalar) return write(t.scalar);
    if (t.kind == ValueTree::Kind::kList) {
      core::Json a = core::Json::array();
      for (const ValueTree& item : t.items) a.push_back(write(item));
      return a;
    }
    core::Json o = core::Json::object();
    for (size_t i = 0; i < t.items.size(); ++i) o[t.keys[i]] = write(t.items[i]);
    return o;
  }
  template <class T>
  static core::Json write(const std::optional<T>& o) {
    return write(*o);
  }
  template <class T>
  static core::Json write(const std::vector<T>& v) {
    core::Json a = core::Json::array();
    for (const T& item : v) a.push_back(write(item));
    return a;
  }
  // Named entries: an array (file order) of {"name": ..., fields...} or {"name", "value"}.
  template <class T>
  static core::Json write(const Named<T>& v) {
    core::Json a = core::Json::array();
    for (const Entry<T>& e : v) {
      core::Json item;
      if constexpr (Visitable<T>) {
        item = write(e.value);
      } else {
        item["value"] = write(e.value);
      }
      item["name"] = e.name;
      a.push_back(std::move(item));
    }
    return a;
  }
  template <Visitable T>
  static core::Json write(const T& s) {
    core::Json o = core::Json::object();
    JsonOut v;
    v.out = &o;
    const_cast<T&>(s).visit(v);  // visit is non-const only to share one function with readers
    return o;
  }
};

// ---------------------------------------------------------------------------------------------
// JSON -> structs (episode specs written by JsonOut); throws on the first problem.
class JsonIn {
 public:
  const core::Json* in = nullptr;
  std::string path;
  std::string source;

  template <class T>
  void req(const char* key, T& member, const char*) {
    const auto it = in->find(key);
    if (it == in->end()) throw core::InputError(loc(path), std::string("a member '") + key + "'", "none");
    read(*it, sub(key), member);
  }
  template <class T>
  void opt(const char* key, T& member, const char*) {
    const auto it = in->find(key);
    if (it == in->end()) return;
    read(*it, sub(key), member);
  }
  template <class T>
  void rest(Named<T>& member, const char*) {
    KeyCollector known;
    Motion probe;
    probe.visit(known);
    for (auto it = in->begin(); it != in->end(); ++it) {
      if (std::find(known.keys.begin(), known.keys.end(), it.key()) != known.keys.end()) continue;
      Entry<T> e;
      e.name = it.key();
      read(it.value(), sub(it.key()), e.value);
      member.push_back(std::move(e));
    }
  }

  std::string sub(const std::string& key) const { return path.empty() ? key : path + "." + key; }
  std::string loc(const std::string& p) const { return source + (p.empty() ? "" : " (" + p + ")"); }

  void read(const core::Json& j, const std::string& p, std::string& out) { out = core::json_string(j, loc(p)); }
  void read(const core::Json& j, const std::string& p, bool& out) { out = core::json_bool(j, loc(p)); }
  void read(const core::Json& j, const std::string& p, double& out) { out = core::json_number(j, loc(p)); }
  void read(const core::Json& j, const std::string& p, int& out) {
    if (!j.is_number_integer()) throw core::InputError(loc(p), "an integer", core::json_kind(j));
    out = j.get<int>();
  }
  void read(const core::Json& j, const std::string& p, uint64_t& out) {
    if (!j.is_number_unsigned() && !(j.is_number_integer() && j.get<int64_t>() >= 0)) {
      throw core::InputError(loc(p), "an unsigned integer", core::json_kind(j));
    }
    out = j.get<uint64_t>();
  }
  void read(const core::Json& j, const std::string& p, Param& out) {
    out.where.text = loc(p);
    if (j.is_number()) {
      out.expr = Expr::Number(core::json_number(j, loc(p)));
    } else {
      out.expr = Expr::String(core::json_string(j, loc(p)));
    }
  }
  void read(const core::Json& j, const std::string& p, Num& out) {
    read(j, p, static_cast<Param&>(out));
    if (out.expr.kind != Expr::Kind::kNumber) {
      try {
        out.expr = parse_expr(out.expr.text);
      } catch (const ExprError& e) {
        throw core::InputError(loc(p), e.expected, e.got);
      }
      if (out.expr.kind == Expr::Kind::kString || out.expr.kind == Expr::Kind::kTemplate) {
        throw core::InputError(loc(p), "a number or a distribution", "'" + out.expr.text + "'");
      }
    }
  }
  void read(const core::Json& j, const std::string& p, Text& out) {
    read(j, p, static_cast<Param&>(out));
    if (out.expr.kind == Expr::Kind::kNumber) throw core::InputError(loc(p), "a string", "a number");
  }
  void read(const core::Json& j, const std::string& p, Any& out) { read(j, p, static_cast<Param&>(out)); }
  void read(const core::Json& j, const std::string& p, Pred& out) {
    out.where.text = loc(p);
    out.source = core::json_string(j, loc(p));
  }
  void read(const core::Json& j, const std::string& p, ValueTree& out) {
    out.where.text = loc(p);
    if (j.is_array()) {
      out.kind = ValueTree::Kind::kList;
      out.items.resize(j.size());
      for (size_t i = 0; i < j.size(); ++i) read(j[i], p + "[" + std::to_string(i) + "]", out.items[i]);
    } else if (j.is_object()) {
      out.kind = ValueTree::Kind::kMap;
      for (auto it = j.begin(); it != j.end(); ++it) {
        out.keys.push_back(it.key());
        out.items.emplace_back();
        read(it.value(), p + "." + it.key(), out.items.back());
      }
    } else {
      out.kind = ValueTree::Kind::kScalar;
      read(j, p, out.scalar);
    }
  }
  template <class T>
  void read(const core::Json& j, const std::string& p, std::optional<T>& out) {
    out.emplace();
    read(j, p, *out);
  }
  template <class T>
  void read(const core::Json& j, const std::string& p, std::vector<T>& out) {
    if (!j.is_array()) throw core::InputError(loc(p), "an array", core::json_kind(j));
    out.resize(j.size());
    for (size_t i = 0; i < j.size(); ++i) read(j[i], p + "[" + std::to_string(i) + "]", out[i]);
  }
  template <class T>
  void read(const core::Json& j, const std::string& p, Named<T>& out) {
    if (!j.is_array()) throw core::InputError(loc(p), "an array of named entries", core::json_kind(j));
    for (size_t i = 0; i < j.size(); ++i) {
      const std::string ip = p + "[" + std::to_string(i) + "]";
      Entry<T> e;
      e.name = core::json_string(core::json_member(j[i], "name", loc(ip)), loc(ip + ".name"));
      if constexpr (Visitable<T>) {
        core::Json rest = j[i];
        rest.erase("name");
        read(rest, ip, e.value);
      } else {
        read(core::json_member(j[i], "value", loc(ip)), ip + ".value", e.value);
      }
      out.push_back(std::move(e));
    }
  }
  template <Visitable T>
  void read(const core::Json& j, const std::string& p, T& out) {
    if (!j.is_object()) throw core::InputError(loc(p), "an object", core::json_kind(j));
    JsonIn v{&j, p, source};
    out.visit(v);
    KeyCollector known;
    out.visit(known);
    if (std::is_same_v<T, Motion>) return;
    for (auto it = j.begin(); it != j.end(); ++it) {
      if (std::find(known.keys.begin(), known.keys.end(), it.key()) == known.keys.end()) {
        throw core::InputError(loc(sub(p.empty() ? it.key() : p + "." + it.key())),
                               std::string("a member of ") + T::kSchemaName, "'" + it.key() + "'");
      }
    }
  }
};

// ---------------------------------------------------------------------------------------------
// structs -> Markdown key tables.
class DocOut {
 public:
  std::string text;
  std::vector<std::string> done;

  template <Visitable T>
  void document() {
    if (std::find(done.begin(), done.end(), T::kSchemaName) != done.end()) return;
    done.emplace_back(T::kSchemaName);
    rows_.clear();
    pending_.clear();
    T probe;
    probe.visit(*this);
    text += std::string("### `") + T::kSchemaName + "`\n\n| key | kind | | meaning |\n|---|---|---|---|\n";
    for (const std::string& row : rows_) text += row;
    text += "\n";
    const std::vector<void (*)(DocOut&)> next = pending_;
    for (auto f : next) f(*this);
  }

  template <class T>
  void req(const char* key, T&, const char* doc) {
    row(key, kind_name<T>(), "required", doc);
  }
  template <class T>
  void opt(const char* key, T&, const char* doc) {
    row(key, kind_name<T>(), "optional", doc);
  }
  template <class T>
  void rest(T&, const char* doc) {
    row("*other*", "value", "per primitive", doc);
  }

 private:
  void row(const char* key, const std::string& kind, const char* need, const char* doc) {
    std::string escaped = doc;
    for (size_t i = escaped.find('|'); i != std::string::npos; i = escaped.find('|', i + 2)) {
      escaped.replace(i, 1, "\\|");
    }
    rows_.push_back(std::string("| `") + key + "` | " + kind + " | " + need + " | " + escaped + " |\n");
  }

  template <class T>
  std::string kind_name() {
    if constexpr (IsOptional<T>::value) {
      return kind_name<typename T::value_type>();
    } else if constexpr (IsNamed<T>::value) {
      using E = typename T::value_type;
      return "mapping NAME: " + kind_name<decltype(E::value)>();
    } else if constexpr (IsVector<T>::value) {
      return "list of " + kind_name<typename T::value_type>();
    } else if constexpr (Visitable<T>) {
      pending_.push_back([](DocOut& d) { d.document<T>(); });
      return std::string("[") + T::kSchemaName + "](#" + T::kSchemaName + ")";
    } else if constexpr (std::is_same_v<T, Num>) {
      return "number";
    } else if constexpr (std::is_same_v<T, Text>) {
      return "word";
    } else if constexpr (std::is_same_v<T, Any>) {
      return "value";
    } else if constexpr (std::is_same_v<T, Pred>) {
      return "predicate";
    } else if constexpr (std::is_same_v<T, ValueTree>) {
      return "value";
    } else if constexpr (std::is_same_v<T, bool>) {
      return "true/false";
    } else if constexpr (std::is_same_v<T, std::string>) {
      return "text";
    } else {
      return "number";
    }
  }

  std::vector<std::string> rows_;
  std::vector<void (*)(DocOut&)> pending_;
};

}  // namespace

Scenario parse_scenario(std::string_view text, const std::string& file,
                        std::vector<core::InputError>& problems) {
  Scenario scenario;
  scenario.file = file;
  const core::YamlDocument doc = core::parse_yaml(text, file, problems);
  if (!doc.root.IsDefined() || doc.root.IsNull()) {
    if (problems.empty()) problems.push_back(core::InputError(file + ":1:1", "a scenario script", "an empty file"));
    return scenario;
  }
  YamlIn reader(file, problems, scenario.locations);
  reader.read_root(doc.root, scenario);
  return scenario;
}

Scenario read_scenario(const std::string& path, std::vector<core::InputError>& problems) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    problems.push_back(core::InputError::Message(path, "cannot open file"));
    Scenario s;
    s.file = path;
    return s;
  }
  std::ostringstream text;
  text << in.rdbuf();
  return parse_scenario(text.str(), path, problems);
}

core::Json to_json(const EpisodeSpec& spec) { return JsonOut::write(spec); }
core::Json to_json(const Scenario& scenario) { return JsonOut::write(scenario); }

EpisodeSpec episode_from_json(const core::Json& json, std::string_view source) {
  EpisodeSpec spec;
  JsonIn reader{&json, "", std::string(source)};
  reader.read(json, "", spec);
  return spec;
}

std::string schema_reference_markdown() {
  DocOut doc;
  doc.document<Scenario>();
  return doc.text;
}

}  // namespace hribench::script

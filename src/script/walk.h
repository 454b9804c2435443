#pragma once
// walk_params(s, f): calls f on every value inside a scenario struct, in visit order:
//   f(Param&, ParamType)  for Num (kNumber), Text (kWord), Any and motion parameters (kAny)
//   f(Pred&)              for every predicate
// Used by the validator (reference checks) and by sample() (drawing every value).

#include <optional>
#include <vector>

#include "script/scenario.h"

namespace hribench::script {

enum class ParamType { kNumber, kWord, kAny };

template <class F>
class ParamWalker {
 public:
  explicit ParamWalker(F& f) : f_(f) {}
  template <class T>
  void req(const char*, T& member, const char*) { walk(member); }
  template <class T>
  void opt(const char*, T& member, const char*) { walk(member); }
  template <class T>
  void rest(T& member, const char*) { walk(member); }

  void walk(Num& p) { f_(static_cast<Param&>(p), ParamType::kNumber); }
  void walk(Text& p) { f_(static_cast<Param&>(p), ParamType::kWord); }
  void walk(Any& p) { f_(static_cast<Param&>(p), ParamType::kAny); }
  void walk(Pred& p) { f_(p); }
  void walk(ValueTree& t) {
    if (t.kind == ValueTree::Kind::kScalar) {
      walk(t.scalar);
    } else {
      for (ValueTree& item : t.items) walk(item);
    }
  }
  template <class T>
  void walk(std::optional<T>& o) {
    if (o.has_value()) walk(*o);
  }
  template <class T>
  void walk(std::vector<T>& v) {
    for (T& item : v) walk(item);
  }
  template <class T>
  void walk(Entry<T>& e) { walk(e.value); }
  template <class T>
    requires requires(T& t, ParamWalker& w) { t.visit(w); }
  void walk(T& s) { s.visit(*this); }
  // Plain members (names, events, flags) hold no values.
  void walk(std::string&) {}
  void walk(bool&) {}
  void walk(double&) {}
  void walk(int&) {}
  void walk(uint64_t&) {}

 private:
  F& f_;
};

template <class T, class F>
void walk_params(T& s, F& f) {
  ParamWalker<F> walker(f);
  walker.walk(s);
}

}  // namespace hribench::script

#include "script/predicate.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/errors.h"
#include "script/expr.h"

namespace hribench::script {
namespace {

using Kind = Arg::Kind;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Argument kinds accepted at one position, as a bit mask of Arg::Kind.
constexpr unsigned bit(Kind k) { return 1u << static_cast<unsigned>(k); }
constexpr unsigned kObj = bit(Kind::kObject);
constexpr unsigned kNum = bit(Kind::kNumber);
constexpr unsigned kRob = bit(Kind::kRobot);
constexpr unsigned kHands = bit(Kind::kHand) | bit(Kind::kAnyHand);
constexpr unsigned kPoint = kObj | kRob | bit(Kind::kHand);

struct Signature {
  const char* name;
  Atom atom;
  std::vector<unsigned> args;
  const char* usage;
};

const std::vector<Signature>& signatures() {
  static const std::vector<Signature> table = {
      {"grasped", Atom::kGrasped, {kRob, kObj}, "grasped(robot, OBJECT)"},
      {"held", Atom::kHeld, {kHands, kObj}, "held(human.left|right|any, OBJECT)"},
      {"held_for", Atom::kHeldFor, {kRob | kHands, kObj, kNum},
       "held_for(robot|human.H, OBJECT, SECONDS)"},
      {"in", Atom::kIn, {kObj, kObj}, "in(OBJECT, CONTAINER)"},
      {"on", Atom::kOn, {kObj, kObj | bit(Kind::kTable)}, "on(OBJECT, SURFACE|table)"},
      {"near", Atom::kNear, {kPoint, kPoint, kNum}, "near(A, B, METRES)"},
      {"moved", Atom::kMoved, {kObj, kNum}, "moved(OBJECT, METRES)"},
      {"dropped", Atom::kDropped, {kObj}, "dropped(OBJECT)"},
      {"at_home", Atom::kAtHome, {kRob}, "at_home(robot)"},
      {"still", Atom::kStill, {kRob}, "still(robot)"},
      {"clear", Atom::kClear, {kObj}, "clear(OBJECT)"},
      {"open", Atom::kOpen, {kObj, kNum}, "open(BOX, DEGREES)"},
      {"tilt", Atom::kTilt, {kObj}, "tilt(OBJECT) < DEGREES"},
  };
  return table;
}

std::string list_names(const std::vector<std::string>& names) {
  std::string s;
  for (size_t i = 0; i < names.size(); ++i) s += (i ? ", " : "") + names[i];
  return s;
}

std::string kinds_text(unsigned mask) {
  std::vector<std::string> parts;
  if (mask & kObj) parts.push_back("a scene object");
  if (mask & kRob) parts.push_back("robot");
  if (mask & bit(Kind::kHand)) parts.push_back(mask & bit(Kind::kAnyHand) ? "human.left|right|any" : "human.left|right");
  if (mask & bit(Kind::kTable)) parts.push_back("table");
  if (mask & kNum) parts.push_back("a number");
  std::string s;
  for (size_t i = 0; i < parts.size(); ++i) s += (i ? (i + 1 == parts.size() ? " or " : ", ") : "") + parts[i];
  return s;
}

class PredicateParser {
 public:
  PredicateParser(std::string_view source, const std::vector<std::string>& objects)
      : objects_(objects) {
    try {
      tokens_ = tokenize(source);
    } catch (const ExprError& e) {
      throw core::InputError("", e.expected, e.got);
    }
  }

  BoundPredicate parse(std::string_view source) {
    BoundPredicate out;
    out.source = std::string(source);
    if (peek().kind == Token::Kind::kEnd) throw core::InputError("", "a predicate", "nothing");
    out.root = parse_or(0);
    if (peek().kind != Token::Kind::kEnd) {
      throw core::InputError("", "'and', 'or' or the end of the predicate", "'" + peek().text + "'");
    }
    out.slots = slots_;
    return out;
  }

 private:
  const Token& peek() const { return tokens_[i_]; }
  const Token& next() { return tokens_[i_ < tokens_.size() - 1 ? i_++ : i_]; }
  bool is_word(const char* w) const { return peek().kind == Token::Kind::kWord && peek().text == w; }
  bool is_punct(const char* p) const { return peek().kind == Token::Kind::kPunct && peek().text == p; }
  std::string got() const {
    return peek().kind == Token::Kind::kEnd ? "the end" : "'" + peek().text + "'";
  }
  void expect(const char* p) {
    if (!is_punct(p)) throw core::InputError("", std::string("'") + p + "'", got());
    next();
  }
  void count_node(int depth) {
    if (++nodes_ > kMaxPredicateNodes || depth > 16) {
      throw core::InputError("", "a predicate of at most 64 terms, nested at most 16 deep",
                             "a larger one");
    }
  }

  Predicate parse_or(int depth) { return parse_chain(depth, "or", Atom::kOr, &PredicateParser::parse_and); }
  Predicate parse_and(int depth) { return parse_chain(depth, "and", Atom::kAnd, &PredicateParser::parse_unary); }

  // operand (WORD operand)*: one node with every operand as a child, or the single operand.
  Predicate parse_chain(int depth, const char* word, Atom atom, Predicate (PredicateParser::*operand)(int)) {
    count_node(depth);
    Predicate first = (this->*operand)(depth + 1);
    if (!is_word(word)) return first;
    Predicate p;
    p.atom = atom;
    p.children.push_back(std::move(first));
    while (is_word(word)) {
      next();
      p.children.push_back((this->*operand)(depth + 1));
    }
    return p;
  }

  Predicate parse_unary(int depth) {
    count_node(depth);
    if (is_word("not")) {
      next();
      Predicate p;
      p.atom = Atom::kNot;
      p.children.push_back(parse_unary(depth + 1));
      return p;
    }
    if (is_word("ever")) {
      next();
      Predicate p;
      p.atom = Atom::kEver;
      expect("(");
      p.children.push_back(parse_or(depth + 1));
      expect(")");
      p.slot = slots_++;
      return p;
    }
    if (is_punct("(")) {
      next();
      Predicate p = parse_or(depth + 1);
      expect(")");
      return p;
    }
    return parse_atom();
  }

  Arg parse_arg(const Signature& sig, size_t position) {
    const unsigned mask = sig.args[position];
    const std::string where_text = "argument " + std::to_string(position + 1) + " of " + sig.usage;
    const Token t = next();
    Arg arg;
    if (t.kind == Token::Kind::kNumber) {
      arg.kind = Kind::kNumber;
      arg.number = t.number;
    } else if (t.kind == Token::Kind::kWord && t.text == "robot") {
      arg.kind = Kind::kRobot;
    } else if (t.kind == Token::Kind::kWord && t.text == "table") {
      arg.kind = Kind::kTable;
    } else if (t.kind == Token::Kind::kWord && t.text.rfind("human.", 0) == 0) {
      const std::string side = t.text.substr(6);
      if (side == "left" || side == "right") {
        arg.kind = Kind::kHand;
        arg.index = side == "left" ? kLeftHand : kRightHand;
      } else if (side == "any") {
        arg.kind = Kind::kAnyHand;
      } else {
        throw core::InputError("", "human.left, human.right or human.any as " + where_text,
                               "'" + t.text + "'");
      }
    } else if (t.kind == Token::Kind::kWord) {
      const auto it = std::find(objects_.begin(), objects_.end(), t.text);
      if (it == objects_.end()) {
        throw core::InputError("", kinds_text(mask) + " as " + where_text +
                                       (mask & kObj ? " (scene objects: " + list_names(objects_) + ")" : ""),
                               "'" + t.text + "'");
      }
      arg.kind = Kind::kObject;
      arg.index = static_cast<int>(it - objects_.begin());
    } else {
      throw core::InputError("", kinds_text(mask) + " as " + where_text,
                             t.kind == Token::Kind::kEnd ? "the end" : "'" + t.text + "'");
    }
    if ((mask & bit(arg.kind)) == 0) {
      throw core::InputError("", kinds_text(mask) + " as " + where_text, "'" + t.text + "'");
    }
    if (arg.kind == Kind::kNumber && arg.number < 0) {
      throw core::InputError("", "a number >= 0 as " + where_text, "'" + t.text + "'");
    }
    return arg;
  }

  Predicate parse_atom() {
    if (peek().kind != Token::Kind::kWord) throw core::InputError("", "a predicate", got());
    const std::string name = next().text;
    const auto& table = signatures();
    const auto sig = std::find_if(table.begin(), table.end(),
                                  [&](const Signature& s) { return name == s.name; });
    if (sig == table.end()) {
      throw core::InputError("", "a predicate (" + list_names(predicate_names()) + ")", "'" + name + "'");
    }
    Predicate p;
    p.atom = sig->atom;
    expect("(");
    while (!is_punct(")")) {
      if (p.args.size() == sig->args.size()) {
        throw core::InputError("", std::to_string(sig->args.size()) + " argument(s): " + sig->usage,
                               "more");
      }
      p.args.push_back(parse_arg(*sig, p.args.size()));
      if (!is_punct(")")) expect(",");
    }
    next();
    if (p.args.size() != sig->args.size()) {
      throw core::InputError("", std::to_string(sig->args.size()) + " argument(s): " + sig->usage,
                             std::to_string(p.args.size()));
    }
    if (p.atom == Atom::kTilt) {
      if (!is_punct("<") && !is_punct(">")) {
        throw core::InputError("", "tilt(OBJECT) < DEGREES or tilt(OBJECT) > DEGREES", got());
      }
      p.compare = next().text[0];
      if (peek().kind != Token::Kind::kNumber) throw core::InputError("", "a number of degrees", got());
      p.threshold = next().number;
    } else if (is_punct("<") || is_punct(">")) {
      throw core::InputError("", "a comparison only after tilt(...)", "'" + peek().text + "' after " + name);
    }
    if (p.atom == Atom::kHeldFor || p.atom == Atom::kDropped || p.atom == Atom::kStill) {
      p.slot = slots_++;
    }
    return p;
  }

  const std::vector<std::string>& objects_;
  std::vector<Token> tokens_;
  size_t i_ = 0;
  size_t slots_ = 0;
  size_t nodes_ = 0;
};

// Helpers on the snapshot.
const ObjectState& object(const WorldSnapshot& w, const Arg& a) {
  HRIB_CHECK(a.index >= 0 && static_cast<size_t>(a.index) < w.objects.size())
      << "snapshot has " << w.objects.size() << " objects, predicate wants index " << a.index;
  return w.objects[static_cast<size_t>(a.index)];
}
bool is_grasped(const ObjectState& o) { return o.left_finger_contact && o.right_finger_contact; }
bool held_by_hand(const WorldSnapshot& w, int hand, int index) {
  return w.hands[static_cast<size_t>(hand)].held_object == index;
}
bool held_by_human(const WorldSnapshot& w, int index) {
  return held_by_hand(w, kLeftHand, index) || held_by_hand(w, kRightHand, index);
}
bool free_object(const WorldSnapshot& w, const Arg& a) {
  return !is_grasped(object(w, a)) && !held_by_human(w, a.index);
}
// Half height of an object's box along world z.
double half_height(const ObjectState& o) {
  const core::Mat3 r = o.X_WO.rotation.toRotationMatrix();
  return std::abs(r(2, 0)) * o.half_extents.x() + std::abs(r(2, 1)) * o.half_extents.y() +
         std::abs(r(2, 2)) * o.half_extents.z();
}
core::Vec3 point_of(const WorldSnapshot& w, const Arg& a) {
  if (a.kind == Kind::kRobot) return w.X_WT.translation;
  if (a.kind == Kind::kHand) return w.hands[static_cast<size_t>(a.index)].p_W;
  return object(w, a).X_WO.translation;
}
// Holds for `duration` seconds, tracked in memory slot `slot`.
bool sustained(bool now, double duration, double time, size_t slot, PredicateMemory& m) {
  if (!now) {
    m.since[slot] = kNaN;
    return false;
  }
  if (std::isnan(m.since[slot])) m.since[slot] = time;
  return time - m.since[slot] >= duration - 1e-9;
}

bool eval(const Predicate& p, const WorldSnapshot& w, PredicateMemory& m) {
  switch (p.atom) {
    case Atom::kNot:
      return !eval(p.children[0], w, m);
    case Atom::kEver:
      if (eval(p.children[0], w, m)) m.latched[p.slot] = 1;
      return m.latched[p.slot] != 0;
    case Atom::kAnd: {
      bool all = true;  // every child is evaluated so memories stay up to date
      for (const Predicate& c : p.children) all = eval(c, w, m) && all;
      return all;
    }
    case Atom::kOr: {
      bool any = false;
      for (const Predicate& c : p.children) any = eval(c, w, m) || any;
      return any;
    }
    case Atom::kGrasped:
      return is_grasped(object(w, p.args[1]));
    case Atom::kHeld: {
      const Arg& h = p.args[0];
      return h.kind == Kind::kAnyHand ? held_by_human(w, p.args[1].index)
                                      : held_by_hand(w, h.index, p.args[1].index);
    }
    case Atom::kHeldFor: {
      const Arg& a = p.args[0];
      const int o = p.args[1].index;
      bool now = false;
      if (a.kind == Kind::kRobot) now = is_grasped(object(w, p.args[1]));
      if (a.kind == Kind::kHand) now = held_by_hand(w, a.index, o);
      if (a.kind == Kind::kAnyHand) now = held_by_human(w, o);
      return sustained(now, p.args[2].number, w.time, p.slot, m);
    }
    case Atom::kIn: {
      const ObjectState& o = object(w, p.args[0]);
      const ObjectState& c = object(w, p.args[1]);
      const core::Vec3 q = c.X_WO.inverse() * o.X_WO.translation;
      const core::Vec3& h = c.half_extents;
      const double sx = std::max(h.x() - kInMargin, 0.5 * h.x());
      const double sy = std::max(h.y() - kInMargin, 0.5 * h.y());
      return std::abs(q.x()) <= sx && std::abs(q.y()) <= sy && q.z() >= -h.z() - kInMargin &&
             q.z() <= h.z() + kInTopMargin && free_object(w, p.args[0]);
    }
    case Atom::kOn: {
      const ObjectState& o = object(w, p.args[0]);
      const double bottom = o.X_WO.translation.z() - half_height(o);
      bool footprint = true;
      double top = w.table_height;
      if (p.args[1].kind == Kind::kObject) {
        const ObjectState& s = object(w, p.args[1]);
        top = s.X_WO.translation.z() + half_height(s);
        const core::Vec3 q = s.X_WO.inverse() * o.X_WO.translation;
        footprint = std::abs(q.x()) <= s.half_extents.x() + kInMargin &&
                    std::abs(q.y()) <= s.half_extents.y() + kInMargin;
      }
      return footprint && std::abs(bottom - top) <= kOnGap && o.v_WO.norm() < kRestSpeed &&
             free_object(w, p.args[0]);
    }
    case Atom::kNear:
      return (point_of(w, p.args[0]) - point_of(w, p.args[1])).norm() <= p.args[2].number;
    case Atom::kMoved: {
      const ObjectState& o = object(w, p.args[0]);
      return (o.X_WO.translation - o.p_WO_initial).norm() > p.args[1].number;
    }
    case Atom::kDropped: {
      const ObjectState& o = object(w, p.args[0]);
      const bool falling = o.v_WO.z() < -kDropSpeed || o.X_WO.translation.z() < w.table_height - kDropBelow;
      if (falling && free_object(w, p.args[0])) m.latched[p.slot] = 1;
      return m.latched[p.slot] != 0;
    }
    case Atom::kAtHome:
      return w.home_distance <= kHomeTolerance;
    case Atom::kStill: {
      const bool now = w.v_WT.norm() < kStillSpeed && std::abs(w.gripper_speed) < kStillSpeed;
      return sustained(now, kStillFor, w.time, p.slot, m);
    }
    case Atom::kClear: {
      const ObjectState& o = object(w, p.args[0]);
      const core::Vec3& c = o.X_WO.translation;
      for (const HandState& hand : w.hands) {
        const core::Vec3 d = hand.p_W - c;
        if (std::hypot(d.x(), d.y()) < kClearRadius && std::abs(d.z()) < kClearHeight) return false;
      }
      for (size_t j = 0; j < w.objects.size(); ++j) {
        if (static_cast<int>(j) == p.args[0].index) continue;
        const core::Vec3 q = o.X_WO.inverse() * w.objects[j].X_WO.translation;
        if (std::abs(q.x()) <= o.half_extents.x() && std::abs(q.y()) <= o.half_extents.y() &&
            q.z() > 0 && q.z() < kClearHeight) {
          return false;
        }
      }
      return true;
    }
    case Atom::kOpen:
      return object(w, p.args[0]).lid_deg >= p.args[1].number;
    case Atom::kTilt: {
      const core::Mat3 r = object(w, p.args[0]).X_WO.rotation.toRotationMatrix();
      const double deg = core::rad_to_deg(std::acos(std::clamp(r(2, 2), -1.0, 1.0)));
      return p.compare == '<' ? deg < p.threshold : deg > p.threshold;
    }
  }
  return false;
}

}  // namespace

BoundPredicate bind_predicate(std::string_view source, const std::vector<std::string>& objects) {
  PredicateParser parser(source, objects);
  return parser.parse(source);
}

PredicateMemory make_memory(const BoundPredicate& predicate) {
  PredicateMemory m;
  m.since.assign(predicate.slots, kNaN);
  m.latched.assign(predicate.slots, 0);
  return m;
}

bool evaluate(const BoundPredicate& predicate, const WorldSnapshot& world, PredicateMemory& memory) {
  HRIB_CHECK(memory.since.size() == predicate.slots) << "memory not made for this predicate";
  return eval(predicate.root, world, memory);
}

std::optional<HoldingAtom> holding_atom(const Predicate& predicate) {
  if (predicate.atom != Atom::kGrasped && predicate.atom != Atom::kHeld && predicate.atom != Atom::kHeldFor) {
    return std::nullopt;
  }
  // (Bound: the holder is the first argument, the object the second.)
  HRIB_CHECK(predicate.args.size() >= 2 && predicate.args[1].kind == Kind::kObject) << static_cast<int>(predicate.atom);
  return HoldingAtom{predicate.atom, predicate.args[0], predicate.args[1].index};
}

std::vector<std::string> predicate_names() {
  std::vector<std::string> names;
  for (const Signature& s : signatures()) names.emplace_back(s.name);
  names.emplace_back("ever");
  names.emplace_back("not");
  names.emplace_back("and");
  names.emplace_back("or");
  return names;
}

}  // namespace hribench::script

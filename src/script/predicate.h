#pragma once
// The one predicate library of HRIBench: used by human triggers (when/unless/until), robot
// goals, success conditions and the metrics. A predicate is parsed from the script's text,
// bound to the scene's object names (type-checked), then evaluated on WorldSnapshots.
//
// Grammar:  pred := or;  or := and ('or' and)*;  and := unary ('and' unary)*;
//           unary := 'not' unary | 'ever' '(' pred ')' | '(' pred ')' | atom;
//           atom := NAME '(' args ')' [('<'|'>') NUMBER]
// Arguments are words (object names, robot, human.left|right|any, table) or numbers.
//
// Atoms (o, c, s: scene objects; A, B: robot | human.left | human.right | an object):
//   grasped(robot, o)        both finger pads touch o
//   held(human.H, o)         hand H (left|right|any) holds o
//   held_for(A, o, s)        grasped (A = robot) / held (A = human.H) continuously for >= s seconds
//   in(o, c)                 o's centre inside c's box (shrunk by kInMargin sideways, up to
//                            kInTopMargin above its top), o not grasped or held
//   on(o, s)                 o's bottom within kOnGap of s's top (s = table: of the table top),
//                            o's centre above s's footprint (+kInMargin), o slower than kRestSpeed,
//                            not grasped or held
//   near(A, B, d)            distance between A and B (TCP, palm centre, object centre) <= d
//   moved(o, d)              o's centre is more than d from where it started
//   dropped(o)               latched: once o, neither grasped nor held, fell faster than
//                            kDropSpeed or below the table top by kDropBelow
//   at_home(robot)           TCP within kHomeTolerance of its home
//   still(robot)             TCP slower than kStillSpeed and gripper slower than kStillSpeed,
//                            for kStillFor seconds (docs/metrics.md "still")
//   clear(o)                 no palm within kClearRadius of o's centre (horizontally, and
//                            |dz| < kClearHeight), no other object on o's footprint
//   open(o, deg)             o's lid open at least deg degrees
//   tilt(o) < deg            angle between o's z axis and world z, degrees ('<' or '>')
// and one operator over time:
//   ever(P)                  latched: P held at some control step of the episode so far (its
//                            child is evaluated at every step, so P's own memories stay current)

#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "script/world.h"

namespace hribench::script {

// Tolerances (documented in docs/scenario-scripts.md).
inline constexpr double kInMargin = 0.01;        // m
inline constexpr double kInTopMargin = 0.02;     // m
inline constexpr double kOnGap = 0.02;           // m
inline constexpr double kRestSpeed = 0.05;       // m/s
inline constexpr double kDropSpeed = 1.0;        // m/s downward
inline constexpr double kDropBelow = 0.05;       // m below the table top
inline constexpr double kHomeTolerance = 0.03;   // m
inline constexpr double kStillSpeed = 0.01;      // m/s
inline constexpr double kStillFor = 0.2;         // s
inline constexpr double kClearRadius = 0.12;     // m
inline constexpr double kClearHeight = 0.30;     // m
inline constexpr size_t kMaxPredicateNodes = 64;

enum class Atom {
  kGrasped, kHeld, kHeldFor, kIn, kOn, kNear, kMoved, kDropped, kAtHome, kStill, kClear,
  kOpen, kTilt, kEver, kNot, kAnd, kOr
};

// One argument after binding.
struct Arg {
  enum class Kind { kRobot, kHand, kAnyHand, kObject, kTable, kNumber };
  Kind kind = Kind::kNumber;
  int index = 0;      // kHand: Hand; kObject: object index
  double number = 0;  // kNumber
};

struct Predicate {
  Atom atom = Atom::kAnd;
  std::vector<Arg> args;
  std::vector<Predicate> children;  // not, ever: 1; and/or: >= 2
  char compare = 0;                 // tilt: '<' or '>'
  double threshold = 0;             // tilt: degrees
  size_t slot = 0;                  // memory slot (held_for, dropped, still, ever)
};

// A predicate, bound, with the source text it came from.
struct BoundPredicate {
  std::string source;
  Predicate root;
  size_t slots = 0;  // memory slots needed
};

// Parses and type-checks `source` against the scene's object names. Throws InputError with
// an empty where() (the caller knows the location) describing the first problem.
BoundPredicate bind_predicate(std::string_view source, const std::vector<std::string>& objects);

// Who holds which object, as a predicate says it: the typed reading of a single atom
// grasped(robot, o), held(human.H, o) or held_for(A, o, s), for code that asks about logged
// predicates (their names are predicate text: bind them with bind_predicate) instead of
// building or matching their text.
struct HoldingAtom {
  Atom atom = Atom::kGrasped;  // kGrasped | kHeld | kHeldFor
  Arg holder;                  // Arg::Kind::kRobot, kHand (index: Hand) or kAnyHand
  int object = 0;              // index into the object names the predicate was bound against

  // Whether it says that the robot grasps object `o` (grasped(robot, o)).
  bool robot_grasps(int o) const { return atom == Atom::kGrasped && object == o; }
  // Whether it says that a human hand (one, or any) holds object `o` (held(human.H, o)).
  bool human_holds(int o) const { return atom == Atom::kHeld && object == o; }
};
// The holding atom `predicate` is, nullopt for any other predicate, also for a holding atom
// within not/and/or ("held(human.any, cup) and not grasped(robot, cup)").
std::optional<HoldingAtom> holding_atom(const Predicate& predicate);

// What a predicate remembers between steps (one per bound predicate and per episode).
struct PredicateMemory {
  std::vector<double> since;   // held_for/still: time the condition began; NaN = not holding
  std::vector<char> latched;   // dropped, ever
};
PredicateMemory make_memory(const BoundPredicate& predicate);

// Evaluates at world.time, updating `memory`. Call once per control step, in time order.
bool evaluate(const BoundPredicate& predicate, const WorldSnapshot& world, PredicateMemory& memory);

// Names of all atoms, for docs and messages.
std::vector<std::string> predicate_names();

}  // namespace hribench::script

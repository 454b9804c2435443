#pragma once
// The catalog of procedural human motion primitives: for each primitive its named phases (the
// events a script can refer to, e.g. `point.stroke`, `offer.hold_stable`) and its parameters
// (name, kind, unit, default, valid range). The script layer validates `motion:` blocks against
// it; the generator (human/motion.h) reads the same table to fill defaults and check ranges.
//
// Conventions for every primitive:
// - Points are in the world frame W, metres. A point parameter may be written in a script as a
//   scene object (the compiler passes the object's centre).
// - Hand targets are the PALM CENTRE (hand_points(...).palm, human/labels.h), not the wrist:
//   the wrist sits Skeleton::palm_distance (about 9 cm) behind it. Pointing targets are hit by
//   the ray shoulder -> index fingertip.
// - Times are seconds from the start of the primitive's plan; the first named phase starts at
//   `onset`. Durations of 0 are allowed where the range says so (the phase is then empty), so a
//   chain of acts can skip a lowering or retraction.
// - A phase with `waits` set can be held open by the runtime: it lasts at least its nominal
//   duration and ends when its signal arrives (human/motion.h, MotionPlan). Its signal has the
//   phase's own name (e.g. the signal "hold_stable" ends offer's hold_stable phase).

#include <string_view>
#include <vector>

namespace hribench::human {

enum class ParamKind {
  kNumber,  // a real number with a unit and an inclusive range [min, max]
  kSide,    // "left" | "right"
  kChoice,  // one of `choices`
  kPoint,   // a world point [x, y, z] in m (or a scene object: its centre)
  kPoints,  // a list of world points (via-points of a hand path), possibly empty
  kZone,    // {center: [x, y, z], radius: r}: a ball in W; min/max bound the radius (m)
  kObject,  // the name of a scene object (labels which object a hand holds)
};
std::string_view to_string(ParamKind kind);  // "number", "side", ...

struct ParamInfo {
  std::string_view name;
  ParamKind kind = ParamKind::kNumber;
  std::string_view unit;        // "s", "m", "m/s", "deg", "1" (dimensionless), "" (non-number)
  bool required = false;        // the script must give it
  bool has_default = false;     // for kNumber/kSide/kChoice: default_value/default_choice apply
  double default_value = 0;     // kNumber
  double min = 0;               // kNumber: valid range (inclusive); kZone: radius range
  double max = 0;
  std::string_view default_choice;         // kSide / kChoice
  std::vector<std::string_view> choices;   // kSide: {left, right}; kChoice: the options
  std::string_view doc;         // one line for `hribench check` messages and the docs
};

struct PhaseInfo {
  std::string_view name;
  bool waits = false;           // can be held open until its signal (reactive phase)
  std::string_view doc;
};

struct PrimitiveInfo {
  std::string_view name;
  std::string_view summary;
  bool uses_hand = false;            // has a `hand` parameter (the active hand)
  std::vector<PhaseInfo> phases;     // in time order
  std::vector<ParamInfo> params;     // every accepted parameter; anything else is an error

  const ParamInfo* param(std::string_view name) const;  // nullptr if not accepted
  const PhaseInfo* phase(std::string_view name) const;  // nullptr if no such phase
};

// All primitives, in a fixed order: idle, walk_to, reach, retract, point, go, stop, give_me,
// cancel, your_turn, offer, receive, pick, place, move_object, hold_lid, lift, carry, lower,
// intrude, withdraw, release_retract.
const std::vector<PrimitiveInfo>& primitive_catalog();
// The primitive with this name, or nullptr.
const PrimitiveInfo* find_primitive(std::string_view name);

}  // namespace hribench::human

#include "human/primitives.h"

namespace hribench::human {
namespace {

// Parameter builders (keep the table below readable).
ParamInfo num(std::string_view name, std::string_view unit, double def, double lo, double hi,
              std::string_view doc) {
  ParamInfo p;
  p.name = name;
  p.kind = ParamKind::kNumber;
  p.unit = unit;
  p.has_default = true;
  p.default_value = def;
  p.min = lo;
  p.max = hi;
  p.doc = doc;
  return p;
}
// A number without a default: absent means "not used".
ParamInfo optional_num(std::string_view name, std::string_view unit, double lo, double hi,
                       std::string_view doc) {
  ParamInfo p = num(name, unit, 0, lo, hi, doc);
  p.has_default = false;
  return p;
}
// A non-number parameter.
ParamInfo of_kind(std::string_view name, ParamKind kind, std::string_view unit, bool required,
                  std::string_view doc) {
  ParamInfo p;
  p.name = name;
  p.kind = kind;
  p.unit = unit;
  p.required = required;
  p.doc = doc;
  return p;
}
ParamInfo point(std::string_view name, bool required, std::string_view doc) {
  return of_kind(name, ParamKind::kPoint, "m", required, doc);
}
ParamInfo choice(std::string_view name, std::vector<std::string_view> options,
                 std::string_view def, std::string_view doc) {
  ParamInfo p;
  p.name = name;
  p.kind = ParamKind::kChoice;
  p.has_default = true;
  p.default_choice = def;
  p.choices = std::move(options);
  p.doc = doc;
  return p;
}
ParamInfo hand() {
  ParamInfo p = choice("hand", {"left", "right"}, "right", "the active hand");
  p.kind = ParamKind::kSide;
  return p;
}
ParamInfo zone() {
  ParamInfo p = of_kind("zone", ParamKind::kZone, "m", true,
                        "ball the palm centre is brought to (centre in W, radius 0.005-0.5 m)");
  p.min = 0.005;
  p.max = 0.5;
  return p;
}
ParamInfo object(std::string_view doc) { return of_kind("object", ParamKind::kObject, "", false, doc); }
ParamInfo via() {
  return of_kind("via", ParamKind::kPoints, "m", false,
                 "via-points (W) the palm passes through on the main movement");
}
ParamInfo onset() { return num("onset", "s", 0, 0, 600, "wait before the first phase"); }
ParamInfo swivel() {
  return num("swivel", "deg", 20, -20, 80,
             "elbow swivel about the shoulder-wrist axis: 0 = elbow down, + = elbow out");
}
ParamInfo tremor() {
  return num("tremor", "m", 0, 0, 0.005, "hand tremor amplitude (8-12 Hz), per axis");
}
ParamInfo decel(double def) {
  return num("decel", "1", def, 0.5, 0.8,
             "fraction of the main movement spent decelerating (0.5 = symmetric min-jerk)");
}
ParamInfo palm(std::vector<std::string_view> options, std::string_view def) {
  return choice("palm", std::move(options), def, "palm facing at the target");
}
ParamInfo grasp() {
  return choice("grasp_type", {"side", "top"}, "side",
                "side: palm facing the body's midline, fingers forward; top: palm down");
}

// Phase builders.
PhaseInfo ph(std::string_view name, std::string_view doc) { return {name, false, doc}; }
PhaseInfo wait_ph(std::string_view name, std::string_view doc) { return {name, true, doc}; }

std::vector<PrimitiveInfo> build_catalog() {
  std::vector<PrimitiveInfo> c;
  c.push_back({"idle", "stand, breathing, with a slow weight shift", false,
               {ph("idle", "standing")},
               {onset(), num("duration", "s", 3, 0.1, 600, "how long to stand"),
                num("breath_period", "s", 4, 2, 8, "one breath"),
                num("breath", "deg", 1.5, 0, 4, "chest extension per breath"),
                num("sway", "m", 0.015, 0, 0.05, "lateral pelvis sway (weight shift)"),
                num("sway_period", "s", 6, 2, 20, "one weight shift left-right-left")}});
  c.push_back({"walk_to", "turn, walk to a floor point, turn to a heading", false,
               {ph("turn", "turn toward the goal"), ph("walk", "walk"),
                ph("face", "turn to the final heading")},
               {onset(), point("to", true, "goal of the pelvis on the floor (z ignored)"),
                num("speed", "m/s", 1.2, 0.3, 2.0, "peak walking speed"),
                num("step_length", "m", 0.65, 0.4, 0.9, "length of one step"),
                num("turn", "s", 0.6, 0, 2, "duration of each turn"),
                optional_num("yaw_deg", "deg", -360, 360,
                             "final heading about +z (default: the walking direction)")}});
  c.push_back({"reach", "move the palm to a point and stay", true,
               {ph("reach", "min-jerk transport of the palm"),
                wait_ph("hold", "palm at the target")},
               {onset(), hand(), point("target", true, "palm centre at the end"),
                num("duration", "s", 0.9, 0.3, 3, "reach duration"),
                num("dwell", "s", 0, 0, 60, "minimum hold"),
                palm({"down", "medial", "up"}, "medial"), swivel(), via(), decel(0.5),
                tremor()}});
  c.push_back({"retract", "bring the hand back to the side", true,
               {ph("retract", "min-jerk return to the hanging arm")},
               {onset(), hand(), num("duration", "s", 0.8, 0.2, 3, "retract duration"),
                tremor()}});
  c.push_back({"point", "deictic point: the ray shoulder -> index fingertip hits the target", true,
               {ph("prep", "arm lifts, elbow flexes"),
                ph("stroke", "index moves onto the ray (asymmetric min-jerk)"),
                wait_ph("hold", "post-stroke hold on the ray"),
                ph("retract", "arm returns to the side")},
               {onset(), hand(), point("target", true, "the point the ray passes through"),
                num("prep", "s", 0.25, 0.05, 1.5, "preparation"),
                num("stroke", "s", 0.6, 0.2, 2, "stroke"),
                num("hold", "s", 1.5, 0, 60, "post-stroke hold (dwell)"),
                num("retract", "s", 0.7, 0, 2.5, "retraction"),
                num("extension", "1", 0.85, 0.5, 0.92,
                    "shoulder-wrist distance / (upper arm + forearm)"),
                swivel(), via(), decel(0.6), tremor()}});
  c.push_back({"go", "go gesture: wave or beckon toward the robot", true,
               {ph("raise", "hand comes up"), ph("gesture", "oscillation"),
                ph("lower", "hand goes down")},
               {onset(), hand(), choice("style", {"wave", "beckon"}, "beckon", "form of the gesture"),
                num("raise", "s", 0.5, 0.2, 2, "raise"), num("gesture", "s", 1.2, 0.3, 5, "gesture"),
                num("cycles", "1", 2, 1, 8, "oscillations during the gesture"),
                num("amplitude", "deg", 25, 5, 45, "oscillation amplitude"),
                num("lower", "s", 0.5, 0, 2, "lower"), swivel(), tremor()}});
  c.push_back({"stop", "stop gesture: palm out toward the robot, fingers up", true,
               {ph("raise", "palm comes up"), wait_ph("hold", "palm held out"),
                ph("lower", "hand goes down")},
               {onset(), hand(), num("raise", "s", 0.45, 0.2, 2, "raise"),
                num("hold", "s", 1.5, 0, 60, "hold"), num("lower", "s", 0.6, 0, 2, "lower"),
                num("extension", "1", 0.75, 0.5, 0.92, "shoulder-palm reach / arm length"),
                num("height", "m", 0.05, -0.25, 0.25, "palm height above the shoulder"),
                swivel(), tremor()}});
  c.push_back({"give_me", "give-me gesture: open palm up, fingers beckon", true,
               {ph("raise", "open palm comes up"), ph("gesture", "finger beckons"),
                ph("lower", "hand goes down (0 s: stays for a following receive)")},
               {onset(), hand(),
                point("target", false, "where the palm is presented (default: in front of the waist)"),
                num("raise", "s", 0.5, 0.2, 2, "raise"), num("gesture", "s", 1.0, 0.3, 5, "gesture"),
                num("cycles", "1", 2, 1, 6, "beckons"),
                num("amplitude", "deg", 15, 5, 40, "wrist flexion per beckon"),
                num("lower", "s", 0.5, 0, 2, "lower"), swivel(), tremor()}});
  c.push_back({"cancel", "cancel gesture: arms crossed, or a wave-off", true,
               {ph("raise", "arms come up"), ph("gesture", "arms crossed / waving off"),
                ph("lower", "arms go down")},
               {onset(), hand(),
                choice("style", {"arms_crossed", "wave_off"}, "arms_crossed", "form of the gesture"),
                num("raise", "s", 0.6, 0.2, 2, "raise"), num("gesture", "s", 1.5, 0.3, 60, "gesture"),
                num("cycles", "1", 2, 1, 6, "wave-off sweeps"),
                num("amplitude", "deg", 30, 10, 50, "wave-off sweep amplitude"),
                num("lower", "s", 0.6, 0, 2, "lower"), swivel(), tremor()}});
  c.push_back({"your_turn", "your-turn gesture: open palm up sweeping toward the robot", true,
               {ph("raise", "hand comes up near the body"),
                ph("gesture", "palm-up sweep toward the target"), ph("hold", "presenting"),
                ph("lower", "hand goes down")},
               {onset(), hand(),
                point("target", false, "what is indicated (default: straight ahead, the robot)"),
                num("raise", "s", 0.5, 0.2, 2, "raise"), num("gesture", "s", 0.8, 0.3, 3, "sweep"),
                num("hold", "s", 0.6, 0, 60, "hold"), num("lower", "s", 0.6, 0, 2, "lower"),
                swivel(), tremor()}});
  c.push_back({"offer", "hand an object into a zone and hold it stable", true,
               {ph("reach", "transport into the zone"), ph("hold", "settling in the zone"),
                wait_ph("hold_stable", "held still until the robot has the object"),
                ph("release", "hand opens"), ph("retract", "hand returns to the side")},
               {onset(), hand(), zone(), object("the object in the hand"),
                num("duration", "s", 1.0, 0.4, 3, "reach"),
                num("settle", "s", 0.3, 0.05, 1, "settling (phase hold)"),
                num("hold", "s", 0.5, 0, 60, "minimum hold_stable"),
                num("release", "s", 0.3, 0.1, 1, "release"),
                num("retract", "s", 0.8, 0, 3, "retract"), palm({"up", "medial"}, "medial"),
                swivel(), via(), decel(0.55), tremor()}});
  c.push_back({"receive", "open hand to a zone, close on the object, pull back", true,
               {ph("reach", "open hand moves out (into the zone, or short of it by shift_by)"),
                ph("present", "the open hand held out where the reach ended"),
                ph("shift", "the open hand moves by shift_by into the zone"),
                wait_ph("open", "open hand waits until the object is in the palm"),
                ph("close", "hand closes on the object"), ph("retract", "pull back with it")},
               {onset(), hand(), zone(), object("the object received"),
                num("duration", "s", 1.0, 0.4, 3, "reach"),
                num("present", "s", 0, 0, 5, "held out before the shift"),
                num("shift", "s", 0, 0, 3, "the move into the zone (at least 0.2 s with shift_by)"),
                point("shift_by", false,
                      "offset (W, m) of the zone from where the hand is first held out: a receiving "
                      "hand that moves while the giver comes (absent: it reaches the zone directly)"),
                num("open", "s", 0.3, 0, 60, "minimum open wait"),
                num("close", "s", 0.3, 0.1, 1, "close"), num("retract", "s", 0.8, 0, 3, "retract"),
                palm({"up", "medial"}, "up"), swivel(), via(), decel(0.55), tremor()}});
  c.push_back({"pick", "reach an object, grasp it, lift it", true,
               {ph("reach", "transport to the grasp"), ph("grasp", "hand closes"),
                ph("lift", "object lifted")},
               {onset(), hand(), object("the object picked"),
                point("target", true, "palm centre at the grasp"), grasp(),
                num("duration", "s", 0.9, 0.3, 3, "reach"), num("grasp", "s", 0.35, 0.1, 1.5, "grasp"),
                num("lift", "s", 0.5, 0.2, 2, "lift"),
                num("lift_height", "m", 0.12, 0, 0.4, "lift height"), swivel(), via(), decel(0.6),
                tremor()}});
  c.push_back({"place", "put the held object down at a point and let go", true,
               {ph("transport", "carry to the target (descending at the end)"),
                ph("release", "hand opens"), ph("retract", "hand returns to the side")},
               {onset(), hand(), object("the object placed"),
                point("target", true, "palm centre at the release"), grasp(),
                num("duration", "s", 1.0, 0.3, 3, "transport"),
                num("approach_height", "m", 0.08, 0, 0.3, "descend from this height above"),
                num("release", "s", 0.3, 0.1, 1, "release"), num("retract", "s", 0.8, 0, 3, "retract"),
                swivel(), via(), decel(0.6), tremor()}});
  c.push_back({"move_object", "pick an object and place it elsewhere", true,
               {ph("reach", "transport to the grasp"), ph("grasp", "hand closes"),
                ph("transport", "carry to the new place"), ph("release", "hand opens"),
                ph("retract", "hand returns to the side")},
               {onset(), hand(), object("the object moved"),
                point("from", true, "palm centre at the grasp"),
                point("to", true, "palm centre at the release"), grasp(),
                num("duration", "s", 0.9, 0.3, 3, "reach"), num("grasp", "s", 0.35, 0.1, 1.5, "grasp"),
                num("transport", "s", 1.2, 0.4, 4, "transport"),
                num("lift_height", "m", 0.1, 0, 0.3, "clearance over the table"),
                num("release", "s", 0.3, 0.1, 1, "release"), num("retract", "s", 0.8, 0, 3, "retract"),
                swivel(), via(), decel(0.6), tremor()}});
  c.push_back({"hold_lid", "open a hinged lid, hold it open, close it", true,
               {ph("reach", "to the lid handle"), ph("grasp", "hand closes on the handle"),
                ph("open", "lid swings open"),
                wait_ph("hold", "lid held open (can close early)"),
                ph("close", "lid swings shut"), ph("release", "hand opens"),
                ph("retract", "hand returns to the side")},
               {onset(), hand(), object("the lid (or box)"),
                point("handle", true, "palm centre at the handle, lid closed"),
                point("hinge", true,
                      "a point on the hinge axis (horizontal, perpendicular to hinge->handle)"),
                num("open_deg", "deg", 100, 30, 130, "opening angle"),
                num("duration", "s", 0.9, 0.3, 3, "reach"), num("grasp", "s", 0.3, 0.1, 1.5, "grasp"),
                num("open", "s", 1.0, 0.4, 3, "open"), num("hold", "s", 6, 0, 60, "hold"),
                num("close", "s", 1.0, 0.4, 3, "close"), num("release", "s", 0.3, 0.1, 1, "release"),
                num("retract", "s", 0.8, 0, 3, "retract"), swivel(), tremor()}});
  c.push_back({"lift", "grasp a plank end (both hands) and lift it", true,
               {ph("reach", "hands to the plank end"), ph("grasp", "hands close"),
                ph("prep", "small preparatory dip (the lift cue)"), ph("lift", "plank end rises")},
               {onset(), hand(), object("the plank"),
                point("target", true, "grip point (between the palms) on the plank end"),
                num("grip_width", "m", 0.25, 0, 0.5, "distance between the palms (0: one hand)"),
                num("duration", "s", 1.0, 0.4, 3, "reach"), num("grasp", "s", 0.4, 0.1, 1.5, "grasp"),
                num("prep", "s", 0.4, 0, 1.5, "preparatory dip"),
                num("lift", "s", 1.2, 0.4, 4, "lift"), num("height", "m", 0.2, 0.02, 0.5, "lift height"),
                swivel(), tremor()}});
  c.push_back({"carry", "carry the held plank end to a new grip point (stepping)", true,
               {ph("carry", "body and hands move together")},
               {onset(), hand(), object("the plank"),
                point("to", true, "new position of the grip point"),
                num("duration", "s", 2.0, 0.5, 10, "carry"),
                num("grip_width", "m", 0.25, 0, 0.5, "distance between the palms (0: one hand)"),
                tremor()}});
  c.push_back({"lower", "lower the held plank end and let go", true,
               {ph("lower", "plank end descends"), ph("release", "hands open"),
                ph("retract", "hands return to the sides")},
               {onset(), hand(), object("the plank"),
                num("height", "m", 0.2, 0, 0.5, "how far the grip point descends"),
                num("grip_width", "m", 0.25, 0, 0.5, "distance between the palms (0: one hand)"),
                num("lower", "s", 1.2, 0.4, 4, "lower"), num("release", "s", 0.4, 0.1, 1, "release"),
                num("retract", "s", 0.8, 0, 3, "retract"), tremor()}});
  c.push_back({"intrude", "reach across the workspace, dwell, retract", true,
               {ph("reach", "fast reach into the workspace"), ph("dwell", "hand stays there"),
                ph("retract", "hand returns to the side")},
               {onset(), hand(), point("target", true, "palm centre inside the workspace"),
                num("duration", "s", 0.6, 0.2, 3, "reach (ISO 13855 assumes 2.0 m/s)"),
                num("dwell", "s", 2, 0, 60, "dwell"), num("retract", "s", 0.8, 0, 3, "retract"),
                palm({"down", "medial"}, "down"), swivel(), via(), decel(0.5), tremor()}});
  c.push_back({"withdraw", "pull the hand back quickly (keeps what it holds)", true,
               {ph("withdraw", "hand returns to the side")},
               {onset(), hand(), object("the object in the hand, if any"),
                num("duration", "s", 0.6, 0.2, 3, "withdraw"), tremor()}});
  c.push_back({"release_retract", "open the hand, then bring it back", true,
               {ph("release", "hand opens"), ph("retract", "hand returns to the side")},
               {onset(), hand(), object("the object let go"),
                num("release", "s", 0.3, 0.1, 1, "release"),
                num("retract", "s", 0.8, 0.2, 3, "retract"), tremor()}});
  return c;
}

}  // namespace

std::string_view to_string(ParamKind kind) {
  switch (kind) {
    case ParamKind::kNumber: return "number";
    case ParamKind::kSide: return "side";
    case ParamKind::kChoice: return "choice";
    case ParamKind::kPoint: return "point";
    case ParamKind::kPoints: return "points";
    case ParamKind::kZone: return "zone";
    case ParamKind::kObject: return "object";
  }
  return "unknown";
}

const ParamInfo* PrimitiveInfo::param(std::string_view param_name) const {
  for (const ParamInfo& p : params) {
    if (p.name == param_name) return &p;
  }
  return nullptr;
}

const PhaseInfo* PrimitiveInfo::phase(std::string_view phase_name) const {
  for (const PhaseInfo& p : phases) {
    if (p.name == phase_name) return &p;
  }
  return nullptr;
}

const std::vector<PrimitiveInfo>& primitive_catalog() {
  static const std::vector<PrimitiveInfo> catalog = build_catalog();
  return catalog;
}

const PrimitiveInfo* find_primitive(std::string_view name) {
  for (const PrimitiveInfo& p : primitive_catalog()) {
    if (p.name == name) return &p;
  }
  return nullptr;
}

}  // namespace hribench::human

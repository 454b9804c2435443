#pragma once
// The object catalogue (docs/scenario-scripts.md, "Scene and human"): every object kind and colour a
// script may name, written once. The validator checks scripts against it (script/check.h),
// the sampler spaces objects by the kinds' sizes (script/sample.cc), and the model builds and
// colours the bodies from it (model/objects.cc, model/model.h).

#include <array>
#include <string_view>
#include <vector>

#include "core/math.h"

namespace hribench::script {

// An object kind at scale 1 (a scene object's `size_scale` multiplies every length).
struct ObjectKindEntry {
  std::string_view name;
  // Half extents of the bounding box about the footprint's centre, m (z: half the height; the
  // box with its lid closed).
  core::Vec3 half_extents;
  bool round = false;  // the footprint is a disc of radius half_extents.x() (cup, bottle, plate)
};
// The kinds the model builds, in model::ObjectKind order. Scripts may also name a "platform",
// a fixed box sized by the script itself (kPlatformKind).
const std::vector<ObjectKindEntry>& catalogue_kinds();
inline constexpr std::string_view kPlatformKind = "platform";
// The entry named `name`, nullptr for an unknown kind (and for a platform).
const ObjectKindEntry* find_kind(std::string_view name);

// A colour: its name in scripts and its RGBA (components in [0, 1]).
struct ColourEntry {
  std::string_view name;
  std::array<float, 4> rgba;
};
// Every colour, in the order a scene's distractors draw them (script/sample.cc): appending
// keeps released episode specs, reordering or renaming changes them.
const std::vector<ColourEntry>& catalogue_colours();
// The entry named `name`, nullptr for an unknown colour.
const ColourEntry* find_colour(std::string_view name);

// Radius of the circle around an object's footprint at scale 1 (m), any yaw.
double footprint_radius(const ObjectKindEntry& kind);

}  // namespace hribench::script

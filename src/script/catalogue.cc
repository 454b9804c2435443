#include "script/catalogue.h"

#include <cmath>

namespace hribench::script {

const std::vector<ObjectKindEntry>& catalogue_kinds() {
  static const std::vector<ObjectKindEntry> kinds = {
      {"cube", {0.025, 0.025, 0.025}, false}, {"cup", {0.035, 0.035, 0.045}, true},
      {"bottle", {0.032, 0.032, 0.105}, true}, {"plate", {0.1, 0.1, 0.008}, true},
      {"bin", {0.12, 0.09, 0.05}, false},      {"tray", {0.15, 0.11, 0.0125}, false},
      {"box", {0.1, 0.08, 0.064}, false},      {"plank", {0.3, 0.03, 0.02}, false},
  };
  return kinds;
}

const ObjectKindEntry* find_kind(std::string_view name) {
  for (const ObjectKindEntry& kind : catalogue_kinds()) {
    if (kind.name == name) return &kind;
  }
  return nullptr;
}

const std::vector<ColourEntry>& catalogue_colours() {
  static const std::vector<ColourEntry> colours = {
      {"red", {0.85f, 0.12f, 0.12f, 1}},   {"green", {0.15f, 0.7f, 0.2f, 1}},
      {"blue", {0.15f, 0.3f, 0.85f, 1}},   {"yellow", {0.95f, 0.85f, 0.1f, 1}},
      {"orange", {0.95f, 0.5f, 0.1f, 1}},  {"purple", {0.55f, 0.2f, 0.7f, 1}},
      {"white", {0.95f, 0.95f, 0.95f, 1}}, {"black", {0.08f, 0.08f, 0.08f, 1}},
      {"gray", {0.5f, 0.5f, 0.5f, 1}},     {"brown", {0.5f, 0.3f, 0.15f, 1}},
      {"pink", {0.98f, 0.6f, 0.7f, 1}},    {"cyan", {0.1f, 0.8f, 0.85f, 1}},
  };
  return colours;
}

const ColourEntry* find_colour(std::string_view name) {
  for (const ColourEntry& colour : catalogue_colours()) {
    if (colour.name == name) return &colour;
  }
  return nullptr;
}

double footprint_radius(const ObjectKindEntry& kind) {
  return kind.round ? kind.half_extents.x() : std::hypot(kind.half_extents.x(), kind.half_extents.y());
}

}  // namespace hribench::script

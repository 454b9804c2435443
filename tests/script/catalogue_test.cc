#include "script/catalogue.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>

#include "script/check.h"

namespace hribench::script {
namespace {

// Every kind has a size (positive half extents) and a footprint radius that covers its
// footprint; names are unique; a platform is no catalogue kind (the script sizes it).
TEST(CatalogueTest, EveryKindHasASize) {
  std::set<std::string_view> names;
  for (const ObjectKindEntry& kind : catalogue_kinds()) {
    EXPECT_TRUE(names.insert(kind.name).second) << kind.name;
    EXPECT_GT(kind.half_extents.minCoeff(), 0.0) << kind.name;
    EXPECT_EQ(find_kind(kind.name), &kind);
    const double r = footprint_radius(kind);
    EXPECT_GE(r, std::max(kind.half_extents.x(), kind.half_extents.y())) << kind.name;
    if (kind.round) {
      EXPECT_EQ(kind.half_extents.x(), kind.half_extents.y()) << kind.name;
    }
  }
  EXPECT_EQ(catalogue_kinds().size(), 8u);
  EXPECT_EQ(find_kind(kPlatformKind), nullptr);
  EXPECT_EQ(find_kind("sphere"), nullptr);
  EXPECT_DOUBLE_EQ(footprint_radius(*find_kind("cup")), 0.035);
  EXPECT_DOUBLE_EQ(footprint_radius(*find_kind("cube")), std::hypot(0.025, 0.025));
}

// One spelling per colour: "gray" (the released scripts' and specs' spelling), never "grey".
TEST(CatalogueTest, EachColourHasOneSpelling) {
  std::set<std::string_view> names;
  for (const ColourEntry& colour : catalogue_colours()) {
    EXPECT_TRUE(names.insert(colour.name).second) << colour.name;
    for (const float c : colour.rgba) EXPECT_TRUE(c >= 0 && c <= 1) << colour.name;
    EXPECT_EQ(find_colour(colour.name), &colour);
  }
  EXPECT_NE(find_colour("gray"), nullptr);
  EXPECT_EQ(find_colour("grey"), nullptr);
  EXPECT_EQ(find_colour("mauve"), nullptr);
}

// The validator's lists are the catalogue's (plus the platform), in its order: distractor
// colours are drawn by index, so the order is part of every released episode spec.
TEST(CatalogueTest, TheValidatorsListsAreTheCatalogues) {
  const std::vector<std::string> colours = {"red", "green", "blue", "yellow", "orange", "purple",
                                            "white", "black", "gray", "brown", "pink", "cyan"};
  EXPECT_EQ(object_colors(), colours);
  const std::vector<std::string> kinds = {"cube", "cup", "bottle", "plate", "bin",
                                          "tray", "box", "plank", "platform"};
  EXPECT_EQ(object_kinds(), kinds);
}

}  // namespace
}  // namespace hribench::script

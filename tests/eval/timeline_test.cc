#include "eval/timeline.h"

#include <gtest/gtest.h>

namespace hribench::eval {
namespace {

TEST(Timeline, NormalizeMergesAndDropsEmpty) {
  EXPECT_EQ(normalized({{3, 4}, {0, 1}, {0.5, 2}, {5, 5}, {2, 2.5}}),
            (TimeSet{{0, 2.5}, {3, 4}}));
}

TEST(Timeline, SetOperations) {
  const TimeSet a{{0, 4}, {6, 10}};
  const TimeSet b{{3, 7}, {9, 12}};
  EXPECT_EQ(unite(a, b), (TimeSet{{0, 12}}));
  EXPECT_EQ(intersect(a, b), (TimeSet{{3, 4}, {6, 7}, {9, 10}}));
  EXPECT_EQ(subtract(a, b), (TimeSet{{0, 3}, {7, 9}}));
  EXPECT_EQ(subtract(b, a), (TimeSet{{4, 6}, {10, 12}}));
  EXPECT_DOUBLE_EQ(total_length(a), 8.0);
  EXPECT_TRUE(contains(a, 4.0));
  EXPECT_FALSE(contains(a, 5.0));
  EXPECT_TRUE(intersect(a, {}).empty());
  EXPECT_EQ(subtract(a, {}), a);
}

}  // namespace
}  // namespace hribench::eval

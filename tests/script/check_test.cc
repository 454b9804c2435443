#include "script/check.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace hribench::script {
namespace {

std::string all(const std::vector<Problem>& problems) {
  std::string s;
  for (const Problem& p : problems) s += p.text() + "\n";
  return s;
}

TEST(CheckTest, GoodExamplesAreClean) {
  for (const char* file : {"tests/data/scripts/good/handover_h2r.yaml"}) {
    const std::vector<Problem> problems = check(file);
    EXPECT_TRUE(problems.empty()) << file << "\n" << all(problems);
  }
}

}  // namespace
}  // namespace hribench::script

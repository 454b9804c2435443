// The C++ example of docs/episode.md, compiled and run; the doc shows the lines between the
// two "example" markers verbatim (EpisodeExample.DocShowsThisExample checks it).

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <memory>
#include <string>

#include "eval/task_episode.h"

// [example]
#include "eval/episode.h"
#include "policy/registry.h"
#include "script/check.h"
#include "script/sample.h"

using namespace hribench;

// Steps the oracle through an I1 episode by hand, one action per control step.
eval::EpisodeLog step_oracle_through_i1(uint64_t seed) {
  const script::EpisodeSpec spec =
      script::sample(script::load_scenario("tasks/I1_point_pick.yaml"), seed);
  std::unique_ptr<policy::Policy> oracle = policy::make_policy("oracle");
  eval::RunOptions options;
  options.horizon = 0;  // the script's horizon
  eval::Episode episode(spec, oracle->spec(), eval::setup_of(spec, "oracle"), options);
  episode.reset();
  oracle->reset(episode.info());
  policy::Observation observation = episode.observe();
  while (!episode.done()) {
    const policy::ActionChunk chunk = oracle->act(observation);
    observation = episode.step(chunk.actions.front()).observation;
  }
  const eval::EpisodeMetrics metrics = episode.metrics();
  std::printf("I1 seed %llu: success %d, CT %.2f s, %zu steps\n",
              static_cast<unsigned long long>(seed), metrics.success ? 1 : 0,
              metrics.completion_time, episode.log().steps.size());
  return episode.log();
}
// [example]

namespace hribench::eval {
namespace {

TEST(EpisodeExample, StepsTheOracleThroughI1LikeTheRunner) {
  const EpisodeLog log = step_oracle_through_i1(0);
  const script::EpisodeSpec spec = script::sample(script::load_scenario("tasks/I1_point_pick.yaml"), 0);
  std::unique_ptr<policy::Policy> oracle = policy::make_policy("oracle");
  RunOptions options;
  options.horizon = 0;
  const ScoredEpisode run = run_task_episode(spec, *oracle, setup_of(spec, "oracle"), options);
  EXPECT_TRUE(run.metrics.success);
  EXPECT_TRUE(identical(log, run.log));
}

// The lines between the markers in this file, and the C++ block of docs/episode.md.
std::string between_markers(const std::string& text, const std::string& marker) {
  const size_t a = text.find(marker);
  const size_t b = text.find(marker, a + marker.size());
  if (a == std::string::npos || b == std::string::npos) return "";
  const size_t from = text.find('\n', a) + 1;
  return text.substr(from, text.rfind('\n', b) + 1 - from);
}

std::string read(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

TEST(EpisodeExample, DocShowsThisExample) {
  const std::string example = between_markers(read("tests/eval/episode_example_test.cc"), "// [example]");
  ASSERT_FALSE(example.empty());
  const std::string doc = read("docs/episode.md");
  const std::string fence = "```cpp\n";
  const size_t at = doc.find(fence);
  ASSERT_NE(at, std::string::npos);
  const size_t end = doc.find("```\n", at + fence.size());
  EXPECT_EQ(doc.substr(at + fence.size(), end - at - fence.size()), example);
}

}  // namespace
}  // namespace hribench::eval

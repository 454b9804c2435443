#include "eval/task_episode.h"

#include <gtest/gtest.h>

#include "core/errors.h"
#include "eval/script_contract.h"
#include "eval/script_driver.h"
#include "model/model.h"
#include "policy/builtin.h"
#include "script/check.h"
#include "script/sample.h"
#include "sim/data.h"

namespace hribench::eval {
namespace {

EpisodeSetup setup_of(const script::EpisodeSpec& spec) {
  return {spec.task, spec.role, "hash", spec.seed, spec.instruction, "noop"};
}

TEST(TaskEpisode, RunsTheScriptsHorizonAndScoresAgainstTheEpisodesFullContract) {
  const script::EpisodeSpec spec =
      script::sample(script::load_scenario("tests/data/scripts/good/handover_h2r.yaml"), 2);
  policy::NoopPolicy noop;
  RunOptions options;
  options.horizon = 0;  // the script's
  const ScoredEpisode scored = run_task_episode(spec, noop, setup_of(spec), options);
  ASSERT_EQ(scored.log.status, core::EpisodeStatus::kOk) << scored.log.status_reason;
  EXPECT_NEAR(scored.log.horizon, spec.horizon, 1e-12);
  EXPECT_NEAR(scored.log.steps.back().time, spec.horizon, 1e-9);
  // The same as scoring by hand with contract_from_episode (goal positions, permits, waits).
  const model::Model model = model::build(scene_spec_from_episode(spec));
  const ScenarioContract contract = contract_from_episode(spec, ScriptDriver(spec).graph(), model);
  EXPECT_FALSE(contract.permitted_contacts.empty());
  const EpisodeMetrics by_hand = compute_metrics(contract, scored.log, options.constants);
  EXPECT_EQ(scored.metrics.success, by_hand.success);
  EXPECT_EQ(scored.metrics.primary_label, by_hand.primary_label);
  EXPECT_EQ(scored.metrics.idle_ratio, by_hand.idle_ratio);
  EXPECT_FALSE(scored.metrics.success);  // noop never takes the object
}

TEST(TaskEpisode, AShortHorizonIsKept) {
  const script::EpisodeSpec spec =
      script::sample(script::load_scenario("tests/data/scripts/good/stop_go.yaml"), 1);
  policy::NoopPolicy noop;
  RunOptions options;
  options.horizon = 1.0;
  const ScoredEpisode scored = run_task_episode(spec, noop, setup_of(spec), options);
  EXPECT_NEAR(scored.log.steps.back().time, 1.0, 1e-9);
}

TEST(TaskEpisode, ASceneTheModelCannotBuildIsInputError) {
  script::EpisodeSpec spec =
      script::sample(script::load_scenario("tests/data/scripts/good/stop_go.yaml"), 1);
  spec.scene.objects[0].value.kind = script::Text("teapot");
  policy::NoopPolicy noop;
  EXPECT_THROW(run_task_episode(spec, noop, setup_of(spec), RunOptions{}), core::InputError);
}

}  // namespace
}  // namespace hribench::eval

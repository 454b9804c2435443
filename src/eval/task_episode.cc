#include "eval/task_episode.h"

#include "eval/script_contract.h"
#include "eval/script_driver.h"
#include "model/model.h"
#include "sim/data.h"

namespace hribench::eval {

ScoredEpisode run_task_episode(const script::EpisodeSpec& spec, policy::Policy& policy,
                               const EpisodeSetup& setup, RunOptions options) {
  const model::Model model = model::build(scene_spec_from_episode(spec));
  sim::Data data = sim::make_data(model);
  ScriptDriver driver(spec);
  if (options.horizon <= 0) options.horizon = spec.horizon;
  ScoredEpisode scored;
  scored.log = run_episode(model, data, policy, driver, setup, options);
  const ScenarioContract contract = contract_from_episode(spec, driver.graph(), model);
  scored.metrics = compute_metrics(contract, scored.log, options.constants);
  return scored;
}

}  // namespace hribench::eval

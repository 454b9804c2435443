// Tests of eval/raw_replay.h: raw mj_step makes an episode's recorded physics steps bit for
// bit, from any step on (each step's state is recorded), and says at which step it did not
// when the model differs; RawAlongside makes them during a second run of the episode and says
// where the episode ran past its recording.

#include "eval/raw_replay.h"

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "eval/runner.h"
#include "eval/task_episode.h"
#include "policy/registry.h"
#include "script/check.h"
#include "script/sample.h"
#include "sim/data.h"
#include "support/mujoco_fixture.h"

namespace hribench::eval {
namespace {

class RawReplayTest : public ::hribench::testing::MujocoTest {};

// box_retrieval seed 0 under noop for 4 s: the person opens the box's lid, grasping it at
// about 3.1 s in the middle of a control step (sim::grasp_point runs mj_forward between two
// physics steps), and the hold's wrenches pull on the lid from then on.
const char* const kTask = "tasks/C3_box_retrieval.yaml";
constexpr double kHorizon = 4.0;

struct Recorded {
  RawRecording recording;
  std::unique_ptr<Episode> episode;
};

std::unique_ptr<Recorded> record(double horizon, EpisodeObserver* also = nullptr) {
  auto out = std::make_unique<Recorded>();
  const script::EpisodeSpec spec = script::sample(script::load_scenario(kTask), 0);
  std::unique_ptr<policy::Policy> noop = policy::make_policy("noop");
  RunOptions options;
  options.horizon = horizon;
  out->episode = std::make_unique<Episode>(spec, noop->spec(), setup_of(spec, "noop"), options);
  out->episode->add_observer(out->recording);
  if (also != nullptr) out->episode->add_observer(*also);
  run_episode(*out->episode, *noop);
  return out;
}

TEST_F(RawReplayTest, RawMjStepMakesTheEpisodesStepsBitForBitFromAnyStep) {
  const std::unique_ptr<Recorded> r = record(kHorizon);
  const mjModel* m = r->episode->model().m();
  EXPECT_EQ(r->recording.steps(), std::lround(kHorizon / m->opt.timestep));
  const sim::MjDataPtr raw(mj_makeData(m));
  Watch(raw.get());
  EXPECT_EQ(r->recording.replay(m, raw.get(), 0, r->recording.steps()), -1);
  // Each step starts from its recorded state: the second half alone, from a fresh mjData.
  mj_resetData(m, raw.get());
  EXPECT_EQ(r->recording.replay(m, raw.get(), r->recording.steps() / 2, r->recording.steps()), -1);
}

TEST_F(RawReplayTest, AnotherModelIsCaughtAtItsFirstStep) {
  const std::unique_ptr<Recorded> r = record(kHorizon);
  std::unique_ptr<mjModel, model::MjModelDeleter> other(mj_copyModel(nullptr, r->episode->model().m()));
  other->opt.gravity[2] = -9.80;  // the scene's is -9.81
  const sim::MjDataPtr raw(mj_makeData(other.get()));
  EXPECT_EQ(r->recording.replay(other.get(), raw.get(), 0, r->recording.steps()), 0);
  EXPECT_EQ(r->recording.replay(other.get(), raw.get(), 100, 200), 100);
}

TEST_F(RawReplayTest, AlongsideASecondRunRawMakesEveryStepAndIsTimedApart) {
  const std::unique_ptr<Recorded> first = record(kHorizon);
  const sim::MjDataPtr raw(mj_makeData(first->episode->model().m()));
  RawAlongside alongside(first->recording, raw.get());
  const std::unique_ptr<Recorded> second = record(kHorizon, &alongside);
  EXPECT_TRUE(identical(first->episode->log(), second->episode->log()));
  EXPECT_EQ(alongside.differs(), -1);
  EXPECT_GT(alongside.seconds(), 0);
  // A run longer than the recording: raw lacks the steps past it.
  const std::unique_ptr<Recorded> shorter = record(1.0);
  RawAlongside short_of_steps(shorter->recording, raw.get());
  record(2.0, &short_of_steps);
  EXPECT_EQ(short_of_steps.differs(), shorter->recording.steps());
}

}  // namespace
}  // namespace hribench::eval

// Tests of `hribench bench --episodes` (cli/episode_bench.h): a short run of two tasks writes
// a row per (task, policy) with the episode's step counts, positive rates and ratios, and the
// MuJoCo arena use within the model's capacity; the scaling rows with --threads 2; bad
// options are one clear line. Timings are never asserted beyond being positive.

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "model/model.h"
#include "model/robot.h"
#include "support/run_command.h"

namespace hribench::cli {
namespace {

using ::hribench::testing::count_lines;
using ::hribench::testing::run_hribench;

nlohmann::json run_episode_bench_json(const std::string& flags) {
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("hribench_episode_bench_" + std::to_string(getpid()) + ".json"))
                               .string();
  std::remove(path.c_str());
  const auto r = run_hribench("bench --episodes --json " + path + " " + flags);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("cost/raw"), std::string::npos) << r.output;
  std::ifstream file(path);
  nlohmann::json j = nlohmann::json::parse(file, nullptr, /*allow_exceptions=*/false);
  std::remove(path.c_str());
  return j;
}

TEST(EpisodeBenchTest, RowPerTaskAndPolicyWithRatiosAndArenaUse) {
  const nlohmann::json j =
      run_episode_bench_json("--tasks I1,C1 --policies noop,oracle --horizon 0.5 --threads 2");
  ASSERT_FALSE(j.is_discarded()) << "not valid JSON";
  EXPECT_EQ(j["mujoco_version"], "2.2.2");
  ASSERT_EQ(j["tasks"].size(), 4u);
  EXPECT_EQ(j["tasks"][0]["task"], "point_pick");
  EXPECT_EQ(j["tasks"][0]["policy"], "noop");
  EXPECT_EQ(j["tasks"][1]["policy"], "oracle");
  EXPECT_EQ(j["tasks"][2]["task"], "handover_h2r");
  for (const auto& row : j["tasks"]) {
    EXPECT_EQ(row["episodes"], 1);
    // 0.5 s at 20 Hz control, each control step 50 ms of physics steps (10 at 5 ms).
    EXPECT_DOUBLE_EQ(row["physics_steps_per_episode"].get<double>(), static_cast<double>(10 * std::lround(0.05 / model::kTimestep))) << row.dump();
    for (const char* key : {"seconds_per_episode", "setup_seconds_per_episode", "control_steps_per_second",
                            "physics_steps_per_second", "raw_physics_steps_per_second", "cost_ratio",
                            "run_cost_ratio"}) {
      ASSERT_TRUE(row[key].is_number()) << key;
      EXPECT_GT(row[key].get<double>(), 0) << key << " in " << row.dump();
    }
    EXPECT_GT(row["maxuse_efc"].get<int>(), 0);
    EXPECT_LE(row["maxuse_efc"].get<int>(), row["njmax"].get<int>());
    EXPECT_GT(row["maxuse_con"].get<int>(), 0);
    EXPECT_LE(row["maxuse_con"].get<int>(), row["nconmax"].get<int>());
    EXPECT_LE(row["maxuse_stack"].get<int>(), row["nstack"].get<int>());
    // Half a second: nobody has touched the person yet.
    EXPECT_EQ(row["max_human_force"].get<double>(), 0) << row.dump();
    EXPECT_EQ(row["critical_contacts"].get<int>(), 0) << row.dump();
  }
  ASSERT_EQ(j["scaling"].size(), 2u);
  EXPECT_EQ(j["scaling"][0]["threads"], 1);
  EXPECT_EQ(j["scaling"][1]["threads"], 2);
  for (const auto& row : j["scaling"]) {
    EXPECT_EQ(row["episodes"], 4);
    EXPECT_GT(row["episodes_per_second"].get<double>(), 0);
  }
}

TEST(EpisodeBenchTest, PhysicsCandidatesAreRowsComparedWithTheFirst) {
  // A candidate equal to the scene as built (50 solver iterations) gives the same episode
  // (differ 0); the implicit integrator changes the physics, so its log differs.
  const nlohmann::json j = run_episode_bench_json(
      "--tasks I1 --policies noop --horizon 0.3 --threads 1 "
      "--physics as-built,iterations=50,implicit+iterations=20,timestep=0.0025");
  ASSERT_FALSE(j.is_discarded()) << "not valid JSON";
  ASSERT_EQ(j["tasks"].size(), 4u);
  EXPECT_EQ(j["tasks"][0]["physics"], "as-built");
  EXPECT_EQ(j["tasks"][1]["physics"], "iterations=50");
  EXPECT_EQ(j["tasks"][1]["differ_from_first_physics"], 0);
  EXPECT_EQ(j["tasks"][2]["physics"], "implicit+iterations=20");
  EXPECT_EQ(j["tasks"][2]["differ_from_first_physics"], 1);
  // A 2.5 ms physics step: 20 steps per 50 ms control step instead of 10, a different episode.
  EXPECT_EQ(j["tasks"][3]["physics"], "timestep=0.0025");
  EXPECT_EQ(j["tasks"][3]["differ_from_first_physics"], 1);
  const double steps_as_built = j["tasks"][0]["physics_steps_per_episode"].get<double>();
  EXPECT_GT(steps_as_built, 0);
  EXPECT_EQ(2 * steps_as_built, j["tasks"][3]["physics_steps_per_episode"].get<double>());
}

TEST(EpisodeBenchTest, EulerKeepsTheOracleOnlyWithTheServoDampingAddedBack) {
  // point_pick's oracle picks the cube by finger contact. Under Euler with the servos' damping
  // only in the joints' damping, the arm crawls (docs/performance.md) and the episode times out;
  // euler-servo also adds the damping back unclamped, and the oracle succeeds again.
  const nlohmann::json j = run_episode_bench_json(
      "--tasks I1 --policies oracle --horizon 15 --threads 1 --physics implicit,euler,euler-servo");
  ASSERT_FALSE(j.is_discarded()) << "not valid JSON";
  ASSERT_EQ(j["tasks"].size(), 3u);
  EXPECT_EQ(j["tasks"][0]["successes"], 1);
  EXPECT_EQ(j["tasks"][1]["physics"], "euler");
  EXPECT_EQ(j["tasks"][1]["successes"], 0);
  EXPECT_EQ(j["tasks"][2]["physics"], "euler-servo");
  EXPECT_EQ(j["tasks"][2]["successes"], 1);
  EXPECT_EQ(j["tasks"][2]["differ_from_first_physics"], 1);
}

TEST(EpisodeBenchTest, GraspCandidatesChangeTheEpisodeAndTheArmatureAsBuiltDoesNot) {
  // point_pick's oracle closes the fingers on the cube before 8 s. The fingers' armature as
  // built (with MuJoCo's inertia-derived constants recomputed) replays the episode to the bit;
  // three times the armature, the noslip solver, another impedance ratio, or another time
  // constant or largest impedance of the grasp's contacts changes it.
  const double armature = model::robot_by_name("panda").gripper.finger_armature;
  const nlohmann::json j = run_episode_bench_json(fmt::format(
      "--tasks I1 --policies oracle --horizon 8 --threads 1 "
      "--physics as-built,finger-armature={},finger-armature={},noslip=3,impratio=30,grasp-timeconst=0.02,"
      "grasp-dmax=0.999",
      armature, 3 * armature));
  ASSERT_FALSE(j.is_discarded()) << "not valid JSON";
  ASSERT_EQ(j["tasks"].size(), 7u);
  EXPECT_EQ(j["tasks"][1]["differ_from_first_physics"], 0) << j["tasks"][1].dump();
  EXPECT_EQ(j["tasks"][2]["differ_from_first_physics"], 1) << j["tasks"][2].dump();
  EXPECT_EQ(j["tasks"][3]["physics"], "noslip=3");
  EXPECT_EQ(j["tasks"][3]["differ_from_first_physics"], 1) << j["tasks"][3].dump();
  EXPECT_EQ(j["tasks"][4]["physics"], "impratio=30");
  EXPECT_EQ(j["tasks"][4]["differ_from_first_physics"], 1) << j["tasks"][4].dump();
  EXPECT_EQ(j["tasks"][5]["physics"], "grasp-timeconst=0.02");
  EXPECT_EQ(j["tasks"][5]["differ_from_first_physics"], 1) << j["tasks"][5].dump();
  EXPECT_EQ(j["tasks"][6]["physics"], "grasp-dmax=0.999");
  EXPECT_EQ(j["tasks"][6]["differ_from_first_physics"], 1) << j["tasks"][6].dump();
}

TEST(EpisodeBenchTest, RowsGiveThePeakContactForceOnThePerson) {
  // X3 seed 0: blind reaches for the object the person is placing and meets the hand
  // (OracleBaselines: label contact), a force a physics candidate may change.
  const nlohmann::json j = run_episode_bench_json("--tasks X3 --policies blind,noop --threads 1");
  ASSERT_FALSE(j.is_discarded()) << "not valid JSON";
  ASSERT_EQ(j["tasks"].size(), 2u);
  EXPECT_GT(j["tasks"][0]["max_human_force"].get<double>(), 1.0) << j["tasks"][0].dump();
  EXPECT_EQ(j["tasks"][1]["max_human_force"].get<double>(), 0) << j["tasks"][1].dump();
}

TEST(EpisodeBenchTest, PoolV6sFeetlessForwardObservationAreCandidates) {
  // point_pick's scene has round-based objects on the table: taking their feet away removes
  // contacts and changes the episode. Observing with MuJoCo's forward pass (pools up to v6)
  // gives the next physics step its warm start and bias forces anew, which changes the episode
  // too; the raw mj_step beside it still makes every step as the episode did (the command
  // checks it). The last candidate is pool v6's physics.
  const nlohmann::json j = run_episode_bench_json(
      "--tasks I1 --policies noop --horizon 1 --threads 1 "
      "--physics as-built,no-base-feet,observe-forward,"
      "timestep=0.0025+finger-armature=0.1+no-base-feet+observe-forward");
  ASSERT_FALSE(j.is_discarded()) << "not valid JSON";
  ASSERT_EQ(j["tasks"].size(), 4u);
  EXPECT_EQ(j["tasks"][1]["physics"], "no-base-feet");
  EXPECT_EQ(j["tasks"][1]["differ_from_first_physics"], 1) << j["tasks"][1].dump();
  EXPECT_LT(j["tasks"][1]["maxuse_con"].get<int>(), j["tasks"][0]["maxuse_con"].get<int>());
  EXPECT_EQ(j["tasks"][2]["physics"], "observe-forward");
  EXPECT_EQ(j["tasks"][2]["differ_from_first_physics"], 1) << j["tasks"][2].dump();
  EXPECT_EQ(j["tasks"][2]["maxuse_con"], j["tasks"][0]["maxuse_con"]);
  EXPECT_EQ(j["tasks"][3]["differ_from_first_physics"], 1) << j["tasks"][3].dump();
  EXPECT_EQ(j["tasks"][3]["physics_steps_per_episode"].get<double>(),
            2 * j["tasks"][0]["physics_steps_per_episode"].get<double>())
      << j["tasks"][3].dump();
}

TEST(EpisodeBenchTest, PosingThePersonPerPhysicsStepIsACandidate) {
  // The person offers the object from the start: posed at every physics step, its pose differs
  // from the one made once per control step and interpolated between (as built), so the log
  // does; the physics steps are the same.
  const nlohmann::json j = run_episode_bench_json(
      "--tasks C1 --policies noop --horizon 4 --threads 1 --physics as-built,person-per-physics-step");
  ASSERT_FALSE(j.is_discarded()) << "not valid JSON";
  ASSERT_EQ(j["tasks"].size(), 2u);
  EXPECT_EQ(j["tasks"][1]["physics"], "person-per-physics-step");
  EXPECT_EQ(j["tasks"][1]["differ_from_first_physics"], 1) << j["tasks"][1].dump();
  EXPECT_EQ(j["tasks"][1]["physics_steps_per_episode"], j["tasks"][0]["physics_steps_per_episode"]);
}

TEST(EpisodeBenchTest, BadOptionsAreOneLine) {
  for (const auto& [args, message] :
       {std::pair<std::string, std::string>{"bench --episodes --seeds 0",
                                            "--seeds: expected a positive number of episodes per task, got 0"},
        {"bench --episodes --repeats 0", "--repeats: expected a positive number of runs per episode, got 0"},
        {"bench --episodes --horizon -2", "--horizon: expected a positive number of seconds, got -2"},
        {"bench --episodes --policies nope", "policy: expected one of blind, gr00t, noop, openpi, oracle, random, reactive, got 'nope'"},
        {"bench --episodes --tasks I1 --horizon 0.1 --threads 1 --physics rk4",
         "--physics: expected as-built, implicit, euler, euler-servo, timestep=S, iterations=N, tolerance=X, "
         "impratio=X, noslip=N, finger-armature=KG, grasp-timeconst=S, grasp-dmax=X, no-base-feet, observe-forward, "
         "person-per-physics-step, joined by '+', got 'rk4'"},
        {"bench --episodes --tasks I1 --horizon 0.1 --threads 1 --physics noslip=2.5",
         "--physics: expected as-built, implicit, euler, euler-servo, timestep=S, iterations=N, tolerance=X, "
         "impratio=X, noslip=N, finger-armature=KG, grasp-timeconst=S, grasp-dmax=X, no-base-feet, observe-forward, "
         "person-per-physics-step, joined by '+', got 'noslip=2.5'"},
        {"bench --episodes --tasks I1 --horizon 0.1 --threads 1 --physics grasp-dmax=1.5",
         "--physics: expected grasp-dmax below 1, got 'grasp-dmax=1.5'"},
        {"bench --episodes --tasks I1 --horizon 0.1 --threads 1 --physics timestep=0.003",
         "control_dt: expected a whole number of 3 ms physics steps, got 0.05 s"},
        {"bench --episodes --tasks I1 --horizon 0.1 --policies 'noop?cameras=wrist:64'",
         "policy noop: cameras: expected NAME:WIDTHxHEIGHT joined by '+' (e.g. agentview:224x224+wrist:224x224), "
         "sides in [1, 4096], got 'wrist:64'"},
        {"bench --episodes --tasks I1 --horizon 0.1 --threads 1 --policies 'noop?cameras=nope:32x32'",
         "policy noop?cameras=nope:32x32 camera: expected one of agentview, wrist, got 'nope'"}}) {
    const auto r = run_hribench(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.output;
    EXPECT_EQ(count_lines(r.output), 1) << r.output;
    EXPECT_EQ(r.output, "hribench: error: " + message + "\n") << args;
  }
}

}  // namespace
}  // namespace hribench::cli

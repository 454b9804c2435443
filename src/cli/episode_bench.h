#pragma once
// `hribench bench --episodes`: the cost of real task episodes (docs/performance.md). For every
// (task, policy) it runs sampled episodes of the task exactly as `hribench eval` does (the
// scene's model built, an eval::Episode, eval::run_episode, the metrics) and, in the same run,
// raw MuJoCo making the same physics steps on the SAME compiled mjModel: one untimed run of the
// episode records each physics step's state and inputs (eval::RawRecording), then every timed
// run has raw mj_step make the steps of each control step right after it, timed apart
// (eval::RawAlongside), and checked bit for bit against the episode's. It reports per task:
// wall seconds per episode (and of it, the setup: model build, Data, contract, renderers),
// control and physics steps per second, the cost ratio episode / raw mj_step (the median over
// episodes), the peak memory one worker adds, and the MuJoCo arena
// use (peak contacts, constraint rows and stack against the model's capacity). With --threads
// N > 1 it also runs the whole set of episodes on 1 and on N threads (episodes per second,
// peak memory per worker). Wall-clock figures are measurements, never results.
//
// --physics A,B,... measures physics candidates (a row per task, policy and candidate) without
// changing the benchmark's physics: each candidate is applied to the episode's compiled model
// (the episode and raw mj_step both run on it), and the rows of the later candidates count
// the episodes whose outcome (success, status, primary label) or log differs from the first
// candidate's. Candidates: as-built (the scene as built: euler-servo at 5 ms, pool v7); implicit (the
// implicit integrator with the arm servos' damping in the servos alone,
// model::servo_damping_in_servos: with timestep=0.002, pool v4's physics but for its lighter
// fingers); euler (Euler integrator with the arm servos' damping kv moved from the actuators'
// bias to the joints' damping, which Euler integrates implicitly); euler-servo (Euler
// integrator with model::servo_damping_in_joints: kv also in the joints' damping and added
// back unclamped, so the servos' force limits apply; as built); timestep=S (the physics step,
// s; the 50 ms control step must hold a whole number of them); iterations=N (solver
// iterations); tolerance=X (solver tolerance); impratio=X (the ratio of frictional to normal
// constraint impedance); noslip=N (iterations of MuJoCo's noslip solver, none as built);
// finger-armature=KG (the gripper fingers' armature, as built the robot description's
// finger_armature; MuJoCo's constants derived from the inertia are recomputed);
// grasp-timeconst=S and grasp-dmax=X (the contact time constant, solref[0], and the largest
// impedance, solimp[1], of every finger and object geom: the contacts that hold a grasp);
// no-base-feet (model::SceneSpec::base_feet off: no hidden square foot inside the cups' and
// bottles' round bases); observe-forward (the episode observes each control step's new state
// with MuJoCo's forward pass instead of its kinematics alone,
// eval::RunOptions::forward_after_control_step); person-per-physics-step (the person posed
// from the plans at every physics step, as released up to pool v7,
// eval::RunOptions::person_pose_per_physics_step); joined by '+' they combine
// (euler+iterations=20). Pool v6's physics: timestep=0.0025+finger-armature=0.1+no-base-feet+
// observe-forward.

#include <string>
#include <string_view>
#include <vector>

namespace hribench::cli {

// The --physics candidates (above), as the help and the error messages name them.
inline constexpr std::string_view kPhysicsCandidates =
    "as-built, implicit, euler, euler-servo, timestep=S, iterations=N, tolerance=X, impratio=X, "
    "noslip=N, finger-armature=KG, grasp-timeconst=S, grasp-dmax=X, no-base-feet, observe-forward, "
    "person-per-physics-step";

struct EpisodeBenchOptions {
  std::string tasks = "all";           // task ids or names (gen::resolve_task_scripts)
  std::vector<std::string> policies = {"noop", "oracle"};  // policy references
  int seeds = 1;                       // episodes per task: seeds seed .. seed + seeds - 1
  unsigned long long seed = 0;
  int repeats = 1;                     // timed runs of each episode (each with raw alongside)
  double horizon = -1;                 // s; -1: each script's own horizon
  int threads = 0;                     // > 1: the scaling rows (0: all cores)
  std::string json;                    // also write the figures as JSON to this file
  std::vector<std::string> physics = {"as-built"};  // physics candidates (see above)
};

// Runs the benchmark, prints its table, writes the JSON; returns the exit code. Throws
// core::InputError for bad options.
int run_episode_bench(const EpisodeBenchOptions& options);

}  // namespace hribench::cli

// eval: the Episode (eval/episode.h) stepped from Python with the GIL released around the
// physics, episode logs as numpy arrays (eval/episode_log.h), an episode's result as JSON
// (eval/report.h). The Gymnasium surface over these is python/hribench/env.py.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "bindings.h"
#include "core/errors.h"
#include "eval/episode.h"
#include "eval/episode_log.h"
#include "eval/report.h"
#include "eval/reward.h"
#include "policy/policy.h"
#include "script/scenario.h"

namespace py = pybind11;

namespace hribench::python {
namespace {

template <typename T>
py::array_t<T> zeros(std::vector<py::ssize_t> shape) {
  py::array_t<T> array(shape);
  std::fill(array.mutable_data(), array.mutable_data() + array.size(), T{});
  return array;
}

void put_pose(const core::Pose& pose, double* out) {
  for (int i = 0; i < 3; ++i) out[i] = pose.translation[i];
  core::quat_to_wxyz(pose.rotation, out + 3);
}

py::list events_to_python(const std::vector<eval::Event>& events, size_t from) {
  py::list list;
  for (size_t i = from; i < events.size(); ++i) {
    const eval::Event& e = events[i];
    py::dict d;
    d["time"] = e.time;
    d["kind"] = std::string(eval::to_string(e.kind));
    d["actor"] = std::string(eval::to_string(e.actor));
    d["name"] = e.name;
    d["detail"] = e.detail;
    list.append(d);
  }
  return list;
}

// The log as arrays, one row per control step (docs/python.md lists the keys).
py::dict log_to_python(const eval::EpisodeLog& log) {
  const auto n = static_cast<py::ssize_t>(log.steps.size());
  const auto dof = static_cast<py::ssize_t>(log.steps.empty() ? 0 : log.steps[0].joint_pos.size());
  py::ssize_t action_dim = 0;
  for (const eval::StepRecord& s : log.steps) action_dim = std::max(action_dim, static_cast<py::ssize_t>(s.action.size()));
  const auto objects = static_cast<py::ssize_t>(log.object_names.size());
  const auto predicates = static_cast<py::ssize_t>(log.predicate_names.size());
  auto time = zeros<double>({n});
  auto joint_pos = zeros<double>({n, dof});
  auto joint_vel = zeros<double>({n, dof});
  auto tcp = zeros<double>({n, 7});
  auto gripper = zeros<double>({n});
  auto actions = zeros<double>({n, action_dim});
  auto human = zeros<double>({n, human::kNumJoints, 3});
  auto object_poses = zeros<double>({n, objects, 7});
  auto separation = zeros<double>({n});
  auto approach = zeros<double>({n});
  auto predicate_values = zeros<uint8_t>({n, predicates});
  std::vector<int64_t> contact_step;
  std::vector<double> contact_force;
  std::vector<std::string> contact_part, contact_other, contact_region;
  for (py::ssize_t k = 0; k < n; ++k) {
    const eval::StepRecord& s = log.steps[static_cast<size_t>(k)];
    time.mutable_at(k) = s.time;
    for (py::ssize_t j = 0; j < dof && j < static_cast<py::ssize_t>(s.joint_pos.size()); ++j) {
      joint_pos.mutable_at(k, j) = s.joint_pos[static_cast<size_t>(j)];
      joint_vel.mutable_at(k, j) = s.joint_vel[static_cast<size_t>(j)];
    }
    put_pose(s.X_WT, tcp.mutable_data(k, 0));
    gripper.mutable_at(k) = s.gripper_width;
    for (py::ssize_t a = 0; a < action_dim; ++a) {
      actions.mutable_at(k, a) = a < static_cast<py::ssize_t>(s.action.size())
                                     ? s.action[static_cast<size_t>(a)]
                                     : std::numeric_limits<double>::quiet_NaN();
    }
    for (int j = 0; j < human::kNumJoints; ++j) {
      for (int c = 0; c < 3; ++c) human.mutable_at(k, j, c) = s.human_joints_W[static_cast<size_t>(j)][c];
    }
    for (py::ssize_t o = 0; o < objects && o < static_cast<py::ssize_t>(s.object_poses.size()); ++o) {
      put_pose(s.object_poses[static_cast<size_t>(o)], object_poses.mutable_data(k, o, 0));
    }
    separation.mutable_at(k) = s.separation;
    approach.mutable_at(k) = s.approach_speed;
    for (py::ssize_t p = 0; p < predicates && p < static_cast<py::ssize_t>(s.predicates.size()); ++p) {
      predicate_values.mutable_at(k, p) = s.predicates[static_cast<size_t>(p)];
    }
    for (const eval::Contact& c : s.contacts) {
      contact_step.push_back(k);
      contact_force.push_back(c.normal_force);
      contact_part.push_back(c.robot_part);
      contact_other.push_back(c.other);
      contact_region.push_back(c.region ? std::string(human::to_string(*c.region))
                                        : std::string(eval::to_string(c.other_kind)));
    }
  }
  py::dict d;
  d["task"] = log.task;
  d["role"] = log.role;
  d["spec_hash"] = log.spec_hash;
  d["seed"] = log.seed;
  d["policy"] = log.policy;
  d["robot"] = log.robot;
  d["horizon"] = log.horizon;
  d["control_dt"] = log.control_dt;
  d["action_space"] = std::string(policy::to_string(log.action_space));
  d["status"] = std::string(core::to_string(log.status));
  d["status_reason"] = log.status_reason;
  d["object_names"] = log.object_names;
  d["predicate_names"] = log.predicate_names;
  d["time"] = time;
  d["joint_pos"] = joint_pos;
  d["joint_vel"] = joint_vel;
  d["tcp_pose"] = tcp;
  d["gripper_width"] = gripper;
  d["actions"] = actions;
  d["human_joints"] = human;
  d["object_poses"] = object_poses;
  d["separation"] = separation;
  d["approach_speed"] = approach;
  d["predicates"] = predicate_values;
  py::dict contacts;
  contacts["step"] = py::array_t<int64_t>(static_cast<py::ssize_t>(contact_step.size()), contact_step.data());
  contacts["normal_force"] =
      py::array_t<double>(static_cast<py::ssize_t>(contact_force.size()), contact_force.data());
  contacts["robot_part"] = contact_part;
  contacts["other"] = contact_other;
  contacts["region"] = contact_region;
  d["contacts"] = contacts;
  d["events"] = events_to_python(log.events, 0);
  return d;
}

policy::Action action_from_python(const py::handle& action, const eval::Episode& episode) {
  policy::ActionChunk chunk = chunk_from_python(action, episode.policy_spec().action_space, "action");
  if (chunk.actions.size() != 1) {
    throw core::InputError("action", "one action (dim,)",
                           "a chunk of " + std::to_string(chunk.actions.size()) + " actions");
  }
  return std::move(chunk.actions[0]);
}

py::dict terms_dict(const eval::RewardTerms& r) {
  py::dict d;
  d["progress"] = r.progress;
  d["success"] = r.success;
  d["premature_motion"] = r.premature_motion;
  d["separation"] = r.separation;
  d["contact"] = r.contact;
  d["total"] = r.total();
  return d;
}

// The dense reward of the episode's latest step, term by term (eval/reward.h), with the
// script's weights.
py::dict dense_reward(const eval::Episode& e) {
  if (!e.contract() || !e.spec()) {
    throw core::InputError("reward", "an episode of a task (its contract)", "a bare episode");
  }
  if (e.log().steps.size() < 2) return terms_dict(eval::RewardTerms{});
  // The episode's last step pays the success term (eval/reward.h).
  const std::optional<eval::EpisodeMetrics> ended = e.done() ? std::optional(e.metrics()) : std::nullopt;
  return terms_dict(eval::dense_reward(*e.contract(), e.log(), e.log().steps.size() - 1,
                                       e.spec()->reward.value_or(script::RewardWeights{}),
                                       e.options().constants, ended ? &*ended : nullptr));
}

std::string result_json(const eval::Episode& episode) {
  return eval::episode_to_json(eval::make_result(episode.log(), episode.metrics())).dump();
}

}  // namespace

void bind_eval(py::module_& m) {
  py::class_<eval::Episode>(m, "Episode", "eval::Episode (docs/episode.md), stepped from Python.")
      .def(py::init([](const script::EpisodeSpec& spec, const policy::PolicySpec& policy_spec,
                       const std::string& policy_name, double horizon) {
             eval::RunOptions options;
             options.horizon = horizon;
             return std::make_unique<eval::Episode>(spec, policy_spec, eval::setup_of(spec, policy_name),
                                                    options);
           }),
           py::arg("spec"), py::arg("policy_spec"), py::arg("policy_name") = "python",
           py::arg("horizon") = 0.0)
      .def("reset", &eval::Episode::reset, py::call_guard<py::gil_scoped_release>())
      .def("observe",
           [](eval::Episode& e) {
             policy::Observation obs;
             {
               py::gil_scoped_release release;
               obs = e.observe();
             }
             return observation_to_python(std::move(obs));
           })
      // (observation, done, status, reason) after one action.
      .def("step",
           [](eval::Episode& e, const py::handle& action) {
             const policy::Action a = action_from_python(action, e);
             eval::StepResult r;
             {
               py::gil_scoped_release release;
               r = e.step(a);
             }
             return py::make_tuple(observation_to_python(std::move(r.observation)), r.done,
                                   std::string(core::to_string(r.status)), r.info);
           })
      // Steps the rows of `actions` (n, dim) with Episode::step in C++ (observations built and
      // dropped) until they run out or the episode ends; returns the steps taken. For replaying
      // a log's actions, and the C++ side of bench/python_overhead.py.
      .def("replay",
           [](eval::Episode& e, const py::handle& actions) {
             const policy::ActionChunk chunk =
                 chunk_from_python(actions, e.policy_spec().action_space, "actions");
             py::gil_scoped_release release;
             size_t taken = 0;
             for (const policy::Action& a : chunk.actions) {
               if (e.done()) break;
               e.step(a);
               ++taken;
             }
             return taken;
           })
      // One control step without an observation (action None: hold); returns done.
      .def("advance",
           [](eval::Episode& e, const py::handle& action) {
             if (action.is_none()) {
               py::gil_scoped_release release;
               return e.advance(nullptr);
             }
             const policy::Action a = action_from_python(action, e);
             policy::validate_chunk({e.policy_spec().action_space, {a}}, e.policy_spec().action_space,
                                    e.action_limits());
             py::gil_scoped_release release;
             return e.advance(&a);
           })
      .def("end",
           [](eval::Episode& e, const std::string& reason) { e.end(core::EpisodeStatus::kPolicyError, reason); })
      .def_property_readonly("done", &eval::Episode::done)
      .def_property_readonly("time", [](const eval::Episode& e) {
        return e.log().steps.empty() ? 0.0 : e.log().steps.back().time;
      })
      .def_property_readonly("num_steps", [](const eval::Episode& e) { return e.log().steps.size(); })
      .def_property_readonly("status", [](const eval::Episode& e) { return std::string(core::to_string(e.log().status)); })
      .def_property_readonly("status_reason", [](const eval::Episode& e) { return e.log().status_reason; })
      .def_property_readonly("policy_spec", &eval::Episode::policy_spec)
      .def("events", [](const eval::Episode& e, size_t from) { return events_to_python(e.log().events, from); },
           py::arg("start") = 0)
      .def_property_readonly("num_events", [](const eval::Episode& e) { return e.log().events.size(); })
      .def("dense_reward", &dense_reward, "The latest step's dense reward by term (eval/reward.h).")
      .def("result_json", &result_json, "The episode's result (metrics) as results.json writes it.")
      .def("info", [](const eval::Episode& e) { return episode_info_to_python(e.info()); })
      .def("action_limits",
           [](const eval::Episode& e) {
             const policy::ActionLimits l = e.action_limits();
             py::dict d;
             d["max_ee_translation"] = l.max_ee_translation;
             d["max_ee_rotation"] = l.max_ee_rotation;
             d["q_min"] = std::vector<double>(l.q_min.begin(), l.q_min.end());
             d["q_max"] = std::vector<double>(l.q_max.begin(), l.q_max.end());
             return d;
           })
      .def("log", [](const eval::Episode& e) { return log_to_python(e.log()); })
      .def("log_bytes",
           [](const eval::Episode& e) { return py::bytes(eval::encode_episode_log(e.log())); },
           "The log in the .hlog encoding (eval/episode_log.h): equal bytes, identical logs.");
  m.def("load_log", [](const std::string& path) { return log_to_python(eval::load_episode_log(path)); },
        py::arg("path"));
  m.def("load_results_json",
        [](const std::string& path) { return eval::results_to_json(eval::load_run(path)).dump(); },
        py::arg("path"), "DIR/results.json (or the file) read and checked, as JSON text.");
  m.def("log_bytes_of_file",
        [](const std::string& path) { return py::bytes(eval::encode_episode_log(eval::load_episode_log(path))); },
        py::arg("path"));
}

}  // namespace hribench::python

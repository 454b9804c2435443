#pragma once
// The compiled part of the Python module `hribench._hribench` (docs/python.md): one binding
// file per C++ layer it exposes, each adding that layer's names to the module. Thin: no logic
// the C++ API lacks; the Gymnasium shape of things is python/hribench/*.py.

#include <pybind11/pybind11.h>

#include <memory>
#include <string>

#include "policy/policy.h"

namespace hribench::python {

void bind_core(pybind11::module_& m);    // core.cc: errors (ValueError, CheckError), version
void bind_policy(pybind11::module_& m);  // policy.cc: PolicySpec, the C++ policies' names
void bind_eval(pybind11::module_& m);    // eval.cc: Episode, rewards, logs, results
void bind_gen(pybind11::module_& m);     // gen.cc: episodes of tasks and pools, evaluate

// policy.cc. An Observation as the dict Python policies and env.step return (docs/python.md):
// "time", "instruction", "joint_pos", "joint_vel", "gripper_width", "tcp_pos", "tcp_quat"
// (w, x, y, z), "images" {camera: uint8 (H, W, 3) viewing the rendered buffer, no copy},
// "state" {"human_joints" (22, 3), "objects" {name: (7,) position + wxyz}} when asked.
// Consumes the observation (its image buffers move into the arrays).
pybind11::dict observation_to_python(policy::Observation&& observation);
// An action (dim,) or a chunk (n, dim) of numbers as an ActionChunk in `space`. Throws
// core::InputError (where `where`) for anything else.
policy::ActionChunk chunk_from_python(const pybind11::handle& actions, policy::ActionSpace space,
                                      const std::string& where);
// A policy::Policy whose reset and act are Python callables (reset may be None), called with
// the GIL taken; a Python exception in them becomes a PolicyError(kFailed) "TYPE: message".
std::unique_ptr<policy::Policy> python_policy(policy::PolicySpec spec, pybind11::object reset,
                                              pybind11::object act);
// What a policy's reset(info) receives: EpisodeInfo's fields and the robot's gripper opening.
pybind11::dict episode_info_to_python(const policy::EpisodeInfo& info);

}  // namespace hribench::python

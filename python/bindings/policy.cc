// policy: what a policy declares (PolicySpec), sees (Observation as a dict of numpy arrays) and
// returns (an action or a chunk as an array), and Python objects as policy::Policy
// (docs/python.md).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "bindings.h"
#include "core/errors.h"
#include "model/robot.h"
#include "policy/policy.h"
#include "policy/registry.h"

namespace py = pybind11;

namespace hribench::python {
namespace {

py::array_t<double> vector_array(const double* values, size_t n) {
  py::array_t<double> array(static_cast<py::ssize_t>(n));
  std::copy(values, values + n, array.mutable_data());
  return array;
}

py::array_t<double> pose_array(const core::Pose& pose) {
  py::array_t<double> array(7);
  double* out = array.mutable_data();
  for (int i = 0; i < 3; ++i) out[i] = pose.translation[i];
  core::quat_to_wxyz(pose.rotation, out + 3);
  return array;
}

// An image's pixels as a uint8 (H, W, 3) array that owns the moved buffer (no copy).
py::array image_array(policy::Image&& image) {
  auto* pixels = new std::vector<uint8_t>(std::move(image.pixels));
  py::capsule owner(pixels, [](void* p) { delete static_cast<std::vector<uint8_t>*>(p); });
  return py::array_t<uint8_t>({image.height, image.width, 3}, pixels->data(), owner);
}

std::string python_error_message(const py::error_already_set& e) {
  return std::string(py::str(e.type().attr("__name__"))) + ": " + std::string(py::str(e.value()));
}

class PythonPolicy : public policy::Policy {
 public:
  PythonPolicy(policy::PolicySpec spec, py::object reset, py::object act)
      : spec_(std::move(spec)), reset_(std::move(reset)), act_(std::move(act)) {}
  ~PythonPolicy() override {
    py::gil_scoped_acquire gil;
    reset_ = py::object();
    act_ = py::object();
  }
  policy::PolicySpec spec() const override { return spec_; }
  void reset(const policy::EpisodeInfo& info) override {
    py::gil_scoped_acquire gil;
    if (reset_.is_none()) return;
    std::string failure;
    try {
      reset_(episode_info_to_python(info));
      return;
    } catch (py::error_already_set& e) {
      failure = python_error_message(e);
    }
    throw policy::PolicyError(policy::PolicyErrorKind::kFailed, failure);
  }
  policy::ActionChunk act(const policy::Observation& observation) override {
    policy::Observation copy = observation;  // the dict takes the image buffers
    py::gil_scoped_acquire gil;
    std::string failure;
    try {
      py::object actions = act_(observation_to_python(std::move(copy)));
      return chunk_from_python(actions, spec_.action_space, "act");
    } catch (py::error_already_set& e) {
      failure = python_error_message(e);
    } catch (const core::InputError& e) {
      failure = e.what();
    }
    throw policy::PolicyError(policy::PolicyErrorKind::kFailed, failure);
  }

 private:
  policy::PolicySpec spec_;
  py::object reset_;
  py::object act_;
};

}  // namespace

py::dict observation_to_python(policy::Observation&& observation) {
  py::dict obs;
  const policy::Proprioception& p = observation.proprio;
  obs["time"] = observation.time;
  obs["instruction"] = observation.instruction;
  obs["joint_pos"] = vector_array(p.joint_pos.data(), p.joint_pos.size());
  obs["joint_vel"] = vector_array(p.joint_vel.data(), p.joint_vel.size());
  obs["gripper_width"] = vector_array(&p.gripper_width, 1);
  const py::array_t<double> tcp = pose_array(p.X_WT);
  obs["tcp_pos"] = tcp[py::slice(0, 3, 1)];
  obs["tcp_quat"] = tcp[py::slice(3, 7, 1)];
  py::dict images;
  for (policy::Image& image : observation.images) {
    const std::string camera = image.camera;
    images[py::str(camera)] = image_array(std::move(image));
  }
  obs["images"] = images;
  if (observation.state) {
    py::array_t<double> joints({policy::kHumanKeypoints, 3});
    auto out = joints.mutable_unchecked<2>();
    for (int j = 0; j < policy::kHumanKeypoints; ++j) {
      for (int k = 0; k < 3; ++k) out(j, k) = observation.state->human_joints_W[static_cast<size_t>(j)][k];
    }
    py::dict objects;
    for (const policy::ObjectPose& object : observation.state->objects) {
      objects[py::str(object.name)] = pose_array(object.X_WO);
    }
    py::dict state;
    state["human_joints"] = joints;
    state["objects"] = objects;
    obs["state"] = state;
  }
  return obs;
}

policy::ActionChunk chunk_from_python(const py::handle& actions, policy::ActionSpace space,
                                      const std::string& where) {
  py::array_t<double, py::array::c_style | py::array::forcecast> array;
  try {
    array = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(actions);
  } catch (const py::error_already_set&) {
  }
  if (!array || (array.ndim() != 1 && array.ndim() != 2) || array.size() == 0) {
    throw core::InputError(where, "an action (dim,) or a chunk (n, dim) of numbers",
                           std::string(py::str(py::repr(actions))).substr(0, 80));
  }
  policy::ActionChunk chunk;
  chunk.space = space;
  const py::ssize_t rows = array.ndim() == 1 ? 1 : array.shape(0);
  const py::ssize_t cols = array.ndim() == 1 ? array.shape(0) : array.shape(1);
  const double* data = array.data();
  for (py::ssize_t r = 0; r < rows; ++r) {
    chunk.actions.emplace_back(data + r * cols, data + (r + 1) * cols);
  }
  return chunk;
}

std::unique_ptr<policy::Policy> python_policy(policy::PolicySpec spec, py::object reset,
                                              py::object act) {
  return std::make_unique<PythonPolicy>(std::move(spec), std::move(reset), std::move(act));
}

py::dict episode_info_to_python(const policy::EpisodeInfo& info) {
  py::dict d;
  d["task"] = info.task;
  d["instruction"] = info.instruction;
  d["seed"] = info.seed;
  d["horizon"] = info.horizon;
  d["control_dt"] = info.control_dt;
  d["robot"] = info.robot;
  d["gripper_max_width"] = model::robot_by_name(info.robot).gripper.max_width();  // m
  return d;
}

void bind_policy(py::module_& m) {
  py::class_<policy::PolicySpec>(m, "PolicySpec")
      .def(py::init([](const std::vector<std::tuple<std::string, int, int>>& cameras,
                       bool state_track, const std::string& action_space, int replan_every) {
             policy::PolicySpec spec;
             for (const auto& [name, height, width] : cameras) spec.cameras.push_back({name, width, height});
             spec.state_track = state_track;
             spec.action_space = policy::action_space_from_string(action_space, "action_space");
             if (replan_every < 1) {
               throw core::InputError("replan_every", "a positive number", std::to_string(replan_every));
             }
             spec.replan_every = replan_every;
             return spec;
           }),
           py::arg("cameras") = std::vector<std::tuple<std::string, int, int>>{},
           py::arg("state_track") = false, py::arg("action_space") = "ee_delta",
           py::arg("replan_every") = 1)
      .def_property_readonly("cameras",
                             [](const policy::PolicySpec& s) {
                               std::vector<std::tuple<std::string, int, int>> cameras;
                               for (const auto& c : s.cameras) cameras.emplace_back(c.name, c.height, c.width);
                               return cameras;
                             })
      .def_readonly("state_track", &policy::PolicySpec::state_track)
      .def_property_readonly("action_space",
                             [](const policy::PolicySpec& s) { return std::string(policy::to_string(s.action_space)); })
      .def_readonly("replan_every", &policy::PolicySpec::replan_every);
  m.def("policy_names", &policy::policy_names, "The C++ policies by name (policy/registry.h).");
  m.def("policy_spec", [](const std::string& reference) { return policy::make_policy(reference)->spec(); },
        py::arg("reference"), "The PolicySpec of a C++ policy reference, e.g. 'noop'.");
}

}  // namespace hribench::python

#pragma once
// Shared by the remote client tests: an observation as the runner would make it for a spec
// (proprioception of the Panda at home, grey images for each requested camera), and the message
// the runner's validation gives a chunk.

#include <string>

#include "policy/policy.h"

namespace hribench::remote::testing {

inline policy::Observation observation(const policy::PolicySpec& spec) {
  policy::Observation obs;
  obs.time = 0.25;
  obs.instruction = "hand me the cup";
  obs.proprio.joint_pos = model::robot_by_name("panda").home();
  obs.proprio.joint_vel = model::JointVector(7, 0.0);
  obs.proprio.gripper_width = 0.08;
  for (const policy::CameraRequest& c : spec.cameras) {
    policy::Image image;
    image.camera = c.name;
    image.width = c.width;
    image.height = c.height;
    image.pixels.assign(static_cast<size_t>(c.width * c.height * 3), 128);
    obs.images.push_back(image);
  }
  return obs;
}

// The PolicyError message validate_chunk gives `chunk` ("(no error)" if none).
inline std::string validation_error(const policy::ActionChunk& chunk, const policy::PolicySpec& spec) {
  try {
    policy::validate_chunk(chunk, spec.action_space, policy::action_limits(model::robot_by_name("panda")));
  } catch (const policy::PolicyError& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace hribench::remote::testing

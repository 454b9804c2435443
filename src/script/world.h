#pragma once
// The world as the script layer sees it: plain data, filled each control step by the
// simulation (sim comes after script in the layer order, so this header depends on nothing
// but core math). Predicates, triggers and the act-graph runtime read only this.
//
// Frames and units: world frame W (z up, x from the robot base toward the human), metres,
// seconds, m/s, degrees where named *_deg.

#include <array>
#include <vector>

#include "core/math.h"

namespace hribench::script {

// Index of a human hand in WorldSnapshot::hands.
enum Hand : int { kLeftHand = 0, kRightHand = 1 };

struct ObjectState {
  core::Pose X_WO;                                   // object frame = its bounding-box centre
  core::Vec3 v_WO = core::Vec3::Zero();              // linear velocity of the centre, m/s
  core::Vec3 half_extents = core::Vec3::Zero();      // half sizes of its box, in its own frame, m
  core::Vec3 p_WO_initial = core::Vec3::Zero();      // centre at the start of the episode
  double lid_deg = 0;                                // hinged lid opening (boxes), 0 = closed
  bool left_finger_contact = false;                  // robot finger pads touching it
  bool right_finger_contact = false;
};

struct HandState {
  core::Vec3 p_W = core::Vec3::Zero();  // palm centre
  int held_object = -1;                 // index into WorldSnapshot::objects, -1 = nothing
};

struct WorldSnapshot {
  double time = 0;                        // simulated seconds since the episode start
  // One entry per scene object, in the order of ActGraph::objects (the EpisodeSpec's scene
  // order, distractors last). The sim must fill every entry.
  std::vector<ObjectState> objects;
  core::Pose X_WT;                        // robot tool-centre point (between the finger pads)
  core::Vec3 v_WT = core::Vec3::Zero();   // TCP linear velocity, m/s
  double gripper_width = 0;               // finger opening, m
  double gripper_speed = 0;               // d(width)/dt, m/s
  double home_distance = 0;               // TCP distance from its home (start) position, m
  std::array<HandState, 2> hands;         // [kLeftHand], [kRightHand]
  double table_height = 0.75;             // table top z, m
};

}  // namespace hribench::script

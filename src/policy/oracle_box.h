#pragma once
// Geometry of the expert's box retrieval (C3 box_retrieval): where the robot waits while the
// person opens the hinged lid, how far the gripper may go into the box, how it enters and when
// it is out again. Pure functions of poses; every position is world frame (m), X_WB is the
// box body (footprint centre on the table, yaw about z; the hinge runs along the box's y axis
// on its +x wall). Used by policy/oracle_box.cc; not part of the policy interface.

#include "core/math.h"

namespace hribench::policy::oracle_box {

// The box's walls (model/objects.cc, kind box at scale 1): outer half extents, height.
inline constexpr double kHalfX = 0.10;
inline constexpr double kHalfY = 0.08;
inline constexpr double kWallHeight = 0.12;
inline constexpr double kWallThickness = 0.008;
inline constexpr double kClosedHalfHeight = 0.064;  // with the closed lid: its centre's height
// The Panda hand (model/panda.cc): housing bottom above the TCP, fingertips below it, the
// housing's half length along the fingers' opening direction.
inline constexpr double kHousingAboveTcp = 0.044;
inline constexpr double kHousingHalfWidth = 0.03;
// Reaching into the box the hand tilts about the hinge direction, its wrist toward the robot
// (away from the person's hand on the lid above the hinge), and grasps that much off the
// object's axis toward the robot (the fingers close on a chord).
inline constexpr double kTilt = 0.35;         // rad
inline constexpr double kGraspShift = 0.01;   // m
inline constexpr double kTipBelowTcp = 0.009;
// Clearances: the housing over the wall tops, the fingertips over them while moving sideways.
inline constexpr double kHousingClearance = 0.005;
inline constexpr double kTipClearance = 0.025;
// The waiting point lies this share of the `near` distance from the box origin; the last
// kCreepDistance of the way to it is crept at kCreepSpeed (below the metrics' response speed,
// so arriving near the box is not an early start of the reach into it).
inline constexpr double kWaitShare = 0.93;
inline constexpr double kCreepDistance = 0.03;
inline constexpr double kCreepSpeed = 0.012;  // m/s
// The hand holding the lid: from the wrist down to the lid's edge.
inline constexpr double kHandLength = 0.08;
// Leaving: the TCP this much beyond the act's distance from the box origin.
inline constexpr double kLeaveMargin = 0.04;
// Grip of an object inside the box: a faster squeeze than on the table (the lid window is short).
inline constexpr double kSqueezeRate = 0.06;  // m/s
inline constexpr double kGripTime = 0.25;     // s of full grip before checking
// Descending into the box (the fingers pre-shaped around the object).
inline constexpr double kDescentSpeed = 0.2;  // m/s

// The box's centre (of its bounding box with the lid closed): what near(robot, box, d) measures from.
core::Vec3 centre(const core::Pose& X_WB);
// Height of the box's wall tops (the rim), m.
double rim_z(const core::Pose& X_WB);
// Whether a point lies within the box's outer footprint and below its rim plus `above`.
bool inside(const core::Pose& X_WB, const core::Vec3& p_W, double above);
// The TCP height of a grasp inside the box: `grasp_z` (the object's own grasp height), raised
// until the hand housing stays above the rim.
double grasp_z(const core::Pose& X_WB, double grasp_z);
// The TCP height at which the open fingers pass over the rim.
double entry_z(const core::Pose& X_WB);
// Where the robot waits for the lid: beside the box on the side away from the person (`person`
// is e.g. the pelvis), toward the robot (-x of the box), within `near` (times kWaitShare) of
// the box's centre and above the rim.
core::Vec3 wait_point(const core::Pose& X_WB, const core::Vec3& person, double near);
// The TCP height straight above `tcp`'s horizontal position at which the TCP is farther than
// `distance` + kLeaveMargin from the box's centre, at least the entry height.
double exit_z(const core::Pose& X_WB, const core::Vec3& tcp, double distance);
// The horizontal position of a grasp on an object at `p_W` inside the box: kGraspShift toward
// the robot (-x of the box).
core::Vec3 grasp_point(const core::Pose& X_WB, const core::Vec3& p_W);
// The hand's yaw (about world z, from `X_home`'s orientation) that puts the fingers' opening
// direction (the TCP frame's y) along the hinge (the box's y): the housing, long that way, then
// clears the lid standing on the hinge side. In [-pi/2, pi/2).
double finger_yaw(const core::Pose& X_WB, const core::Pose& X_home);
// The hand's orientation in and over the box: finger_yaw, then tilted by kTilt.
core::Quat hand_rotation(const core::Pose& X_WB, const core::Pose& X_home);

}  // namespace hribench::policy::oracle_box

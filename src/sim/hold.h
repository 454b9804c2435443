#pragma once
// A human hand holding an object, and letting it go.
//
// Choice: the hold is a stiff 6-D spring-damper wrench applied through mjData.xfrc_applied at
// every physics step, pulling the object body to a fixed pose relative to the palm (the pose
// captured when the hold started), plus gravity compensation and velocity feed-forward of the
// moving palm. It is not a MuJoCo weld equality: in MuJoCo 2.2.2 eq_active lives only in
// mjModel (mjData.eq_active came in 3.x), and our Model is immutable and shared between
// threads. The object stays a dynamic body: it still collides with the robot, the table and
// other objects, so a robot can take it (handover) and a released object falls.
// Human hands do not collide with objects (a held object rests against the palm; the other
// human capsules do collide), see model/model.h.
//
// Spring: natural frequency 12 Hz, critically damped, scaled by the object's mass (linear) and
// largest principal inertia (angular).

#include <optional>

#include "human/skeleton.h"
#include "model/model.h"
#include "sim/data.h"

namespace hribench::sim {

// Starts holding `object` (index in model.objects) with hand `side`, keeping the object's
// current pose relative to the palm (the palm of the current human pose). Replaces whatever
// that hand held. Requires model.has_human and a valid object index (checked).
void grasp_by_human(const model::Model& model, Data& data, human::Side side, int object);
// As grasp_by_human, with a given pose of the object body in the palm frame (e.g.
// model.objects[i].X_palm_hold).
void grasp_by_human(const model::Model& model, Data& data, human::Side side, int object,
                    const core::Pose& X_palm_obj);
// Holds the lid of box `object` (a kBox) at the point of the lid nearest to the palm centre
// now: a 3-D spring-damper pulls that point of the lid toward the palm centre (the hinge
// decides the lid's orientation), plus the lid's weight; the spring force is limited to 3 N
// (about 4x the lid's weight) so a hand that leaves the lid's arc cannot drag the box. The
// hand should follow the lid's arc (lift the free edge); lifting the hand opens the lid.
void grasp_lid_by_human(const model::Model& model, Data& data, human::Side side, int object);
// Holds `object` (any kind without a lid, e.g. a plank's end) at the point of its bounding box
// nearest to the palm centre now: a 3-D spring-damper (12 Hz on 1/8 of the object's mass: a
// free rod's end moves like m / 4, shared by two hands; force limited to kPointHoldForceMax) pulls that point toward the palm centre; the object turns
// freely about it. Both hands may point-hold the same object (two grips across a plank's end
// keep it from rolling; its pitch is left to whoever holds the other end). Stored as a
// HoldState with `lid` set (a point hold) on an object without a lid body.
inline constexpr double kPointHoldForceMax = 150;  // N per hand
void grasp_point_by_human(const model::Model& model, Data& data, human::Side side, int object);
// Lets go: the object is free again (it falls unless something supports it).
void release_by_human(const model::Model& model, Data& data, human::Side side);
// Object index held by that hand (by any kind of hold), or nullopt.
std::optional<int> held_object(const Data& data, human::Side side);

// Pose of the palm frame in world for the current human pose (model.X_wrist_palm).
core::Pose palm_pose(const model::Model& model, Data& data, human::Side side);

// Writes the hold wrenches into mj->xfrc_applied (used by step(); allocation-free).
void apply_hold_wrenches(const model::Model& model, Data& data);

}  // namespace hribench::sim

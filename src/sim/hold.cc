#include "sim/hold.h"

#include "core/errors.h"

namespace hribench::sim {
namespace {

constexpr double kHoldFrequency = 2 * core::kPi * 12;  // rad/s, critically damped
constexpr double kLidForceMax = 3.0;  // N, spring force limit of a lid hold

// Point hold: a spring-damper from the grasped point of `body` to the palm centre, on the
// effective mass `mass` at that point, force limited to `force_max`, plus `weight` x the body's
// weight. The body's state is that of the last forward pass (one step old). Adds to
// xfrc_applied (two hands may hold one body).
void apply_point_wrench(const model::Model& model, Data& data, HoldState& h, int body,
                        double mass, double force_max, double weight, const core::Vec3& target) {
  const mjModel* m = model.m();
  mjData* d = data.mj.get();
  const double dt = m->opt.timestep;
  core::Vec3 v_target = core::Vec3::Zero();
  if (h.has_last_target) v_target = (target - h.X_W_last_target.translation) / dt;
  h.X_W_last_target.translation = target;
  h.has_last_target = true;
  const core::Vec3 origin(d->xpos[3 * body], d->xpos[3 * body + 1], d->xpos[3 * body + 2]);
  const core::Quat r = core::quat_from_wxyz(d->xquat + 4 * body).normalized();
  const core::Vec3 point = origin + r * h.p_lid_grasp;
  // Velocity of the grasped point (world frame, from cvel).
  mjtNum vel[6];
  mj_objectVelocity(m, d, mjOBJ_BODY, body, vel, 0);
  const core::Vec3 w(vel[0], vel[1], vel[2]);
  const core::Vec3 v_point = core::Vec3(vel[3], vel[4], vel[5]) + w.cross(point - origin);
  const double k = kHoldFrequency;
  core::Vec3 spring = mass * (k * k * (target - point) + 2 * k * (v_target - v_point));
  // A hand out of reach pulls with at most force_max (a lid hold cannot drag its box).
  if (spring.norm() > force_max) spring *= force_max / spring.norm();
  const core::Vec3 gravity(m->opt.gravity[0], m->opt.gravity[1], m->opt.gravity[2]);
  const core::Vec3 com(d->xipos[3 * body], d->xipos[3 * body + 1], d->xipos[3 * body + 2]);
  const core::Vec3 force = spring - weight * m->body_subtreemass[body] * gravity;
  const core::Vec3 torque = (point - com).cross(spring);
  mjtNum* xfrc = d->xfrc_applied + 6 * body;
  for (int i = 0; i < 3; ++i) {
    xfrc[i] += force[i];
    xfrc[3 + i] += torque[i];
  }
}

// The body a hold pulls on: the lid of a box, else the object.
int held_body(const model::ObjectInfo& o, const HoldState& h) {
  return h.lid && o.lid_body >= 0 ? o.lid_body : o.body;
}

// Starts a point hold of `body` (the lid or the object) at its box geom point nearest the palm
// (box_geom < 0: the object's bounding box in its body frame).
void grasp_point(const model::Model& model, Data& data, human::Side side, int object, int body,
                 int box_geom) {
  release_by_human(model, data, side);
  forward(model, data);
  const mjData* d = data.mj.get();
  const mjModel* m = model.m();
  core::Pose X_WL;
  X_WL.translation = core::Vec3(d->xpos[3 * body], d->xpos[3 * body + 1], d->xpos[3 * body + 2]);
  X_WL.rotation = core::quat_from_wxyz(d->xquat + 4 * body).normalized();
  const core::Vec3 palm_L = X_WL.inverse() * palm_pose(model, data, side).translation;
  core::Vec3 centre, half;
  if (box_geom >= 0) {
    centre = core::Vec3(m->geom_pos[3 * box_geom], m->geom_pos[3 * box_geom + 1], m->geom_pos[3 * box_geom + 2]);
    half = core::Vec3(m->geom_size[3 * box_geom], m->geom_size[3 * box_geom + 1], m->geom_size[3 * box_geom + 2]);
  } else {
    half = model.objects[static_cast<size_t>(object)].half_extents;
    centre = core::Vec3(0, 0, half.z());
  }
  HoldState& h = data.hold[static_cast<size_t>(side)];
  h.object = object;
  h.lid = true;
  h.p_lid_grasp = centre + (palm_L - centre).cwiseMax(-half).cwiseMin(half);
  h.has_last_target = false;
}

}  // namespace

core::Pose palm_pose(const model::Model& model, Data& data, human::Side side) {
  HRIB_CHECK(model.has_human) << "palm_pose without a human";
  pose_human(model, data);
  const auto wrist = static_cast<size_t>(human::index(human::wrist(side)));
  return data.X_WJ[wrist] * model.X_wrist_palm[static_cast<size_t>(side)];
}

void grasp_by_human(const model::Model& model, Data& data, human::Side side, int object,
                    const core::Pose& X_palm_obj) {
  HRIB_CHECK(model.has_human) << "grasp_by_human without a human";
  HRIB_CHECK(object >= 0 && static_cast<size_t>(object) < model.objects.size())
      << "object index " << object;
  release_by_human(model, data, side);
  // An object is held by one hand at a time (a box's lid hold is on another body).
  const bool has_lid = model.objects[static_cast<size_t>(object)].lid_body >= 0;
  for (HoldState& other : data.hold)
    if (other.object == object && (!other.lid || !has_lid)) other = HoldState{};
  HoldState& h = data.hold[static_cast<size_t>(side)];
  h.object = object;
  h.X_palm_obj = X_palm_obj;
  h.has_last_target = false;
}

void grasp_by_human(const model::Model& model, Data& data, human::Side side, int object) {
  HRIB_CHECK(object >= 0 && static_cast<size_t>(object) < model.objects.size())
      << "object index " << object;
  const model::ObjectInfo& o = model.objects[static_cast<size_t>(object)];
  const mjtNum* q = data.mj->qpos + o.qpos_adr;
  core::Pose X_WO;
  X_WO.translation = core::Vec3(q[0], q[1], q[2]);
  X_WO.rotation = core::quat_from_wxyz(q + 3).normalized();
  grasp_by_human(model, data, side, object, palm_pose(model, data, side).inverse() * X_WO);
}

void grasp_lid_by_human(const model::Model& model, Data& data, human::Side side, int object) {
  HRIB_CHECK(model.has_human) << "grasp_lid_by_human without a human";
  HRIB_CHECK(object >= 0 && static_cast<size_t>(object) < model.objects.size())
      << "object index " << object;
  const model::ObjectInfo& o = model.objects[static_cast<size_t>(object)];
  HRIB_CHECK(o.lid_body >= 0) << "object " << o.name << " has no lid";
  grasp_point(model, data, side, object, o.lid_body, model.m()->body_geomadr[o.lid_body]);
}

void grasp_point_by_human(const model::Model& model, Data& data, human::Side side, int object) {
  HRIB_CHECK(model.has_human) << "grasp_point_by_human without a human";
  HRIB_CHECK(object >= 0 && static_cast<size_t>(object) < model.objects.size())
      << "object index " << object;
  const model::ObjectInfo& o = model.objects[static_cast<size_t>(object)];
  HRIB_CHECK(o.lid_body < 0) << "object " << o.name << " has a lid (grasp_lid_by_human)";
  // A full hold of this object by the other hand ends (an object is held one way at a time).
  for (const human::Side other : {human::Side::kLeft, human::Side::kRight})
    if (data.hold[static_cast<size_t>(other)].object == object && !data.hold[static_cast<size_t>(other)].lid)
      release_by_human(model, data, other);
  grasp_point(model, data, side, object, o.body, -1);
}

void release_by_human(const model::Model& model, Data& data, human::Side side) {
  HoldState& h = data.hold[static_cast<size_t>(side)];
  if (h.object >= 0) {
    const model::ObjectInfo& o = model.objects[static_cast<size_t>(h.object)];
    mju_zero(data.mj->xfrc_applied + 6 * held_body(o, h), 6);
  }
  h = HoldState{};
}

std::optional<int> held_object(const Data& data, human::Side side) {
  const HoldState& h = data.hold[static_cast<size_t>(side)];
  if (h.object < 0) return std::nullopt;
  return h.object;
}

void apply_hold_wrenches(const model::Model& model, Data& data) {
  const mjModel* m = model.m();
  mjData* d = data.mj.get();
  const double w = kHoldFrequency;
  const double dt = m->opt.timestep;
  // Holds add up (two hands may point-hold one body): clear the held bodies first.
  for (const HoldState& h : data.hold)
    if (h.object >= 0) mju_zero(d->xfrc_applied + 6 * held_body(model.objects[static_cast<size_t>(h.object)], h), 6);
  for (const human::Side side : {human::Side::kLeft, human::Side::kRight}) {
    HoldState& h = data.hold[static_cast<size_t>(side)];
    if (h.object < 0) continue;
    const model::ObjectInfo& o = model.objects[static_cast<size_t>(h.object)];
    const core::Vec3 palm = palm_pose(model, data, side).translation;
    if (h.lid && o.lid_body >= 0) {
      // A lid: its mass at the free edge (a plate hinged at one edge: m / 3), its weight.
      apply_point_wrench(model, data, h, o.lid_body, m->body_mass[o.lid_body] / 3, kLidForceMax, 1.0, palm);
      continue;
    }
    if (h.lid) {
      apply_point_wrench(model, data, h, o.body, m->body_subtreemass[o.body] / 8, kPointHoldForceMax, 0.0, palm);
      continue;
    }
    const int body = o.body;
    const core::Pose X_WT = palm_pose(model, data, side) * h.X_palm_obj;
    // Target velocity from the palm's motion since the last step (feed-forward).
    core::Vec3 v_target = core::Vec3::Zero();
    core::Vec3 w_target = core::Vec3::Zero();
    if (h.has_last_target) {
      v_target = (X_WT.translation - h.X_W_last_target.translation) / dt;
      const Eigen::AngleAxisd dr(X_WT.rotation * h.X_W_last_target.rotation.conjugate());
      w_target = dr.axis() * dr.angle() / dt;
    }
    h.X_W_last_target = X_WT;
    h.has_last_target = true;
    // Current state of the free body (qpos: position, quaternion; qvel: world linear velocity
    // of the body origin, body-frame angular velocity).
    const mjtNum* q = d->qpos + o.qpos_adr;
    const mjtNum* qd = d->qvel + o.dof_adr;
    const core::Vec3 p(q[0], q[1], q[2]);
    const core::Quat r = core::quat_from_wxyz(q + 3).normalized();
    const core::Vec3 omega = r * core::Vec3(qd[3], qd[4], qd[5]);
    const core::Vec3 ipos(m->body_ipos[3 * body], m->body_ipos[3 * body + 1],
                          m->body_ipos[3 * body + 2]);
    const core::Vec3 com = p + r * ipos;
    const core::Vec3 v_com = core::Vec3(qd[0], qd[1], qd[2]) + omega.cross(r * ipos);
    const core::Vec3 com_target = X_WT * ipos;
    const core::Vec3 v_com_target = v_target + w_target.cross(X_WT.rotation * ipos);
    const double mass = m->body_subtreemass[body];
    const core::Vec3 gravity(m->opt.gravity[0], m->opt.gravity[1], m->opt.gravity[2]);
    const core::Vec3 force =
        mass * (w * w * (com_target - com) + 2 * w * (v_com_target - v_com) - gravity);
    // Rotational spring-damper with the body's inertia tensor in world.
    const Eigen::AngleAxisd err(X_WT.rotation * r.conjugate());
    const core::Mat3 R_inertia =
        (r * core::quat_from_wxyz(m->body_iquat + 4 * body)).toRotationMatrix();
    const core::Vec3 principal(m->body_inertia[3 * body], m->body_inertia[3 * body + 1],
                               m->body_inertia[3 * body + 2]);
    const core::Mat3 inertia = R_inertia * principal.asDiagonal() * R_inertia.transpose();
    const core::Vec3 torque =
        inertia * (w * w * (err.axis() * err.angle()) + 2 * w * (w_target - omega));
    mjtNum* xfrc = d->xfrc_applied + 6 * body;
    for (int k = 0; k < 3; ++k) {
      xfrc[k] += force[k];
      xfrc[3 + k] += torque[k];
    }
  }
}

}  // namespace hribench::sim

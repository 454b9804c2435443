#pragma once
// Math types for the whole project: Eigen vectors/quaternions and rigid poses.
// Units: metres, radians, seconds. World frame W: z up, x from the robot base toward the
// human, y to the robot's left. Naming: X_AB is the pose of frame B expressed in frame A, so
// X_AC = X_AB * X_BC and p_A = X_AB * p_B.

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace hribench::core {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;  // always unit norm where a rotation is meant

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double deg_to_rad(double deg) { return deg * kPi / 180.0; }
inline constexpr double rad_to_deg(double rad) { return rad * 180.0 / kPi; }

// A rigid transform X_AB: rotation R_AB and translation p_AB (origin of B in A).
struct Pose {
  Quat rotation = Quat::Identity();
  Vec3 translation = Vec3::Zero();

  static Pose Identity() { return {}; }
  Pose inverse() const {
    const Quat r_inv = rotation.conjugate();
    return {r_inv, -(r_inv * translation)};
  }
  Pose operator*(const Pose& other) const {
    return {(rotation * other.rotation).normalized(), rotation * other.translation + translation};
  }
  Vec3 operator*(const Vec3& p) const { return rotation * p + translation; }
};

// Quaternion from MuJoCo's (w, x, y, z) order and back.
inline Quat quat_from_wxyz(const double* wxyz) { return Quat(wxyz[0], wxyz[1], wxyz[2], wxyz[3]); }
inline void quat_to_wxyz(const Quat& q, double* wxyz) {
  wxyz[0] = q.w();
  wxyz[1] = q.x();
  wxyz[2] = q.y();
  wxyz[3] = q.z();
}

// Rotation about a unit axis.
inline Quat axis_angle(const Vec3& axis, double angle_rad) {
  return Quat(Eigen::AngleAxisd(angle_rad, axis.normalized()));
}

}  // namespace hribench::core

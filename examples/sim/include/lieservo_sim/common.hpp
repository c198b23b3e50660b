// lieservo_sim/common.hpp — shared types of the simulation module (examples/sim).
//
// Units: millimetres and radians inside; degrees only in reports and presets.
// Scene set-up errors (a negative radius, a non-convex polygon, a non-finite pose, ...) throw
// lieservo::sim::SceneError (derived from std::invalid_argument) with a message naming the
// offending parameter.  Set-up is not on a real-time path, so exceptions are fine there; the
// per-step functions never throw.
#pragma once

#include <stdexcept>
#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <lieservo/groups/se3.hpp>
#include <lieservo/groups/so3.hpp>

namespace lieservo::sim {

using SE3d = lieservo::SE3<double>;
using SO3d = lieservo::SO3<double>;
using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat3 = Eigen::Matrix3d;

/// A bad scene configuration, detected at set-up.
class SceneError : public std::invalid_argument {
 public:
  explicit SceneError(const std::string& what) : std::invalid_argument("lieservo_sim: " + what) {}
};

inline constexpr double kPi = lieservo::pi<double>();

/// Throws SceneError("<name> must be finite and > 0 (got v)") unless v is finite and > 0.
void requirePositive(double v, const char* name);
/// Throws SceneError unless v is finite and >= 0.
void requireNonNegative(double v, const char* name);
/// Throws SceneError unless the pose is finite with an orthonormal rotation.
void requireValidPose(const SE3d& X, const char* name);

/// Rotation matrix from the columns x, y, z (assumed orthonormal, right-handed).
inline Mat3 fromColumns(const Vec3& x, const Vec3& y, const Vec3& z) {
  Mat3 R;
  R.col(0) = x;
  R.col(1) = y;
  R.col(2) = z;
  return R;
}
inline SE3d makePose(const Mat3& R, const Vec3& t) { return SE3d(SO3d::fromMatrixUnchecked(R), t); }

// Degrees, Euler angles and the pose labels (x, y, z, α, β, γ) are the core's: deg2rad and
// rad2deg (lieservo/units.hpp), SO3::fromEulerXYZ / toEulerXYZ and SE3::fromEulerXYZ6 /
// toEulerXYZ6 (R = Rz(γ) Ry(β) Rx(α), the paper's labels).
using lieservo::deg2rad;
using lieservo::rad2deg;
/// The elementary rotations (Eigen's angle-axis).
inline Mat3 rotX(double a) { return Eigen::AngleAxisd(a, Vec3::UnitX()).toRotationMatrix(); }
inline Mat3 rotY(double a) { return Eigen::AngleAxisd(a, Vec3::UnitY()).toRotationMatrix(); }
inline Mat3 rotZ(double a) { return Eigen::AngleAxisd(a, Vec3::UnitZ()).toRotationMatrix(); }

}  // namespace lieservo::sim

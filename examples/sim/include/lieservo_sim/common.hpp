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
inline constexpr double deg(double d) { return d * kPi / 180.0; }
inline constexpr double toDeg(double r) { return r * 180.0 / kPi; }

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

/// Extrinsic-xyz Euler angles (α, β, γ) of R = Rz(γ) Ry(β) Rx(α) (the paper's pose labels).
inline Vec3 eulerXYZ(const Mat3& R) {
  const double b = -std::asin(std::max(-1.0, std::min(1.0, R(2, 0))));
  return Vec3(std::atan2(R(2, 1), R(2, 2)), b, std::atan2(R(1, 0), R(0, 0)));
}
inline Mat3 rotX(double a) { return Eigen::AngleAxisd(a, Vec3::UnitX()).toRotationMatrix(); }
inline Mat3 rotY(double a) { return Eigen::AngleAxisd(a, Vec3::UnitY()).toRotationMatrix(); }
inline Mat3 rotZ(double a) { return Eigen::AngleAxisd(a, Vec3::UnitZ()).toRotationMatrix(); }
/// R = Rz(γ) Ry(β) Rx(α).
inline Mat3 eulerToMatrix(double a, double b, double g) { return rotZ(g) * rotY(b) * rotX(a); }
/// X from (x, y, z, α, β, γ) with R = Rz(γ) Ry(β) Rx(α) (radians).
inline SE3d poseFromEuler6(const Vec6& e) { return makePose(eulerToMatrix(e[3], e[4], e[5]), e.head<3>()); }
inline Vec6 euler6(const SE3d& X) {
  Vec6 e;
  e.head<3>() = X.translation();
  e.tail<3>() = eulerXYZ(X.rotationMatrix());
  return e;
}

}  // namespace lieservo::sim

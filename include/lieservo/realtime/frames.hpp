// lieservo/realtime/frames.hpp — sensor-frame twists to a robot's base-frame command.
//
// Frames: {O} robot base, {E} end effector (pose T_OE, as the robot reports it), {S} tactile
// sensor (tip centre, z out of the tip), rigidly mounted: X_OS = X_OE X_ES, with the
// mounting transform X_ES = (R_ES, p_ES) (p_ES: the sensor origin in {E} coordinates).
//
// The controllers output a BODY twist of the sensor, ξ_s = [v_s; ω_s]: v_s is the velocity
// of the sensor origin and ω_s the angular velocity, both in {S} coordinates
// (X_OS⁻¹ dX_OS/dt = ξ_s^). A Cartesian-velocity robot interface (libfranka's, for one) takes
// the base twist [ṗ_OE; ω_O]: the velocity of the EE ORIGIN and the angular velocity, both in
// BASE coordinates (a "mixed" twist, not the spatial twist of Lie theory, which would be the
// velocity of the point at the base origin). The derivation:
//   ω_O   = R_OS ω_s,                    R_OS = R_OE R_ES
//   ṗ_OS  = R_OS v_s                     (sensor origin velocity, base coordinates)
//   p_OS  = p_OE + R_OE p_ES   ⇒   ṗ_OE = ṗ_OS − ω_O × (R_OE p_ES)
//                                       = R_OS v_s + (R_OE p_ES) × ω_O,
// i.e. [ṗ_OE; ω_O] = Ad(X_O'S) ξ_s with X_O'S = (R_OS, R_OE p_ES), the sensor pose seen from a
// frame at the EE origin with base orientation (Ad = [[C, r^C],[0, C]], SE3::Ad()). Only R_OE
// enters, not p_OE. The mounting offset matters: rotating about the tip centre (as the servo
// controllers ask) moves the EE origin by ω × (p_OE − p_OS).
//
// Units: rotations in radians. Translation units pass through unchanged; the library's
// twists are in mm/s and poses in mm, a robot's often in m/s and m — scale by
// `translation_scale` (e.g. 1e-3 for mm → m) where offered.
//
// The checks are the group classes' own (SO3::fromMatrix, SE3::fromMatrix); noexcept; no
// allocation.
#pragma once

#include <lieservo/groups/se3.hpp>
#include <lieservo/groups/so3.hpp>
#include <lieservo/status.hpp>

#include <Eigen/Core>
#include <cmath>

namespace lieservo::realtime {

using Matrix3 = Eigen::Matrix3d;               ///< a rotation
using Vector3 = Eigen::Vector3d;               ///< a point or a velocity
using Vector6 = Eigen::Matrix<double, 6, 1>;  ///< a twist [v; ω]
using Matrix4 = Eigen::Matrix4d;               ///< a homogeneous transform

/// Default tolerance of the orthonormality check on robot-supplied rotations (‖RᵀR − I‖_F).
constexpr double kRotationTolerance = 1e-6;

/// True when R passes SO3::fromMatrix's check with tolerance `tol`: finite, ‖RᵀR − I‖_F ≤ tol,
/// det R > 0.
inline bool isRotation(const Matrix3& R, double tol = kRotationTolerance) noexcept {
  SO3<double> C;
  return SO3<double>::fromMatrix(R, C, tol) == Status::ok;
}

/// A homogeneous 4×4 pose T_OE (the robot's end effector in its base frame) to a rotation
/// and a translation, checked by SE3::fromMatrix: non_finite_input, not_orthonormal (rotation
/// block, tolerance `tol`), invalid_argument (bottom row not (0 0 0 1) within `tol`); outputs
/// untouched unless ok. (A robot library's own layout, e.g. libfranka's column-major
/// O_T_EE array, is mapped to a Matrix4 by its adapter: examples/franka/franka_frames.hpp.)
inline Status poseFromHomogeneous(const Matrix4& T, Matrix3& R, Vector3& p, double tol = kRotationTolerance) noexcept {
  SE3<double> X;
  const Status s = SE3<double>::fromMatrix(T, X, tol);
  if (s != Status::ok) return s;
  R = X.rotationMatrix();
  p = X.translation();
  return Status::ok;
}

/// Rigid mounting of the sensor on the end effector: X_ES = (R_ES, p_ES).
struct SensorMount {
  Matrix3 R_es = Matrix3::Identity();  ///< sensor axes in {E}
  Vector3 p_es = Vector3::Zero();  ///< sensor origin in {E}, in the command's length unit

  /// non_finite_input, not_orthonormal (isRotation with `tol`), or ok.
  Status validate(double tol = kRotationTolerance) const noexcept {
    if (!R_es.allFinite() || !p_es.allFinite()) return Status::non_finite_input;
    if (!isRotation(R_es, tol)) return Status::not_orthonormal;
    return Status::ok;
  }
};

/// X_O'S = (R_OS, R_OE p_ES): the sensor pose from a frame at the EE origin with the base's
/// orientation, whose adjoint maps the sensor's body twist to the base twist (file comment).
inline SE3<double> eeOriginToSensor(const Matrix3& R_oe, const SensorMount& mount) noexcept {
  return SE3<double>(SO3<double>::fromMatrixUnchecked(R_oe * mount.R_es), R_oe * mount.p_es);
}

/// Sensor body twist ξ_s = [v_s; ω_s] → base twist [ṗ_OE; ω_O] = Ad(X_O'S) ξ_s, the EE-origin
/// velocity and the angular velocity in base coordinates, given R_OE and the mount. The
/// translation of ξ_s is multiplied by `translation_scale` first (mm → m: 1e-3); p_ES must
/// be in the OUTPUT length unit. Unchecked (see sensorTwistToBaseChecked).
inline Vector6 sensorTwistToBase(const Matrix3& R_oe, const SensorMount& mount, const Vector6& xi_s,
                                 double translation_scale = 1.0) noexcept {
  Vector6 xi = xi_s;
  xi.head<3>() *= translation_scale;
  return eeOriginToSensor(R_oe, mount).Ad() * xi;
}

/// Inverse of sensorTwistToBase: a base twist [ṗ_OE; ω_O] (e.g. the robot's last command) →
/// ξ_s = Ad(X_O'S)⁻¹ [ṗ_OE; ω_O] = Ad(X_O'S⁻¹) [ṗ_OE; ω_O], with the translation divided by
/// `translation_scale` at the end (m → mm: 1e-3).
inline Vector6 baseTwistToSensor(const Matrix3& R_oe, const SensorMount& mount, const Vector6& v_base,
                                 double translation_scale = 1.0) noexcept {
  Vector6 out = eeOriginToSensor(R_oe, mount).inverse().Ad() * v_base;
  out.head<3>() /= translation_scale;
  return out;
}

/// Checked conversion with the EE pose T_OE: Status from poseFromHomogeneous or
/// non_finite_input for ξ_s / invalid_argument for a non-positive scale; `out` untouched
/// unless ok. The mount is assumed validated (SensorMount::validate) by the caller.
inline Status sensorTwistToBaseChecked(const Matrix4& T_oe, const SensorMount& mount, const Vector6& xi_s,
                                       double translation_scale, Vector6& out) noexcept {
  if (!xi_s.allFinite() || !std::isfinite(translation_scale)) return Status::non_finite_input;
  if (!(translation_scale > 0)) return Status::invalid_argument;
  Matrix3 R;
  Vector3 p;
  const Status s = poseFromHomogeneous(T_oe, R, p);
  if (s != Status::ok) return s;
  out = sensorTwistToBase(R, mount, xi_s, translation_scale);
  return Status::ok;
}

/// Sensor pose in the base frame from the EE pose T_OE and the mount: X_OS = T_OE X_ES,
/// with the EE translation multiplied by `translation_scale` (m → mm: 1e3) and p_ES in the
/// output unit. Checked like poseFromHomogeneous; X_os untouched unless ok.
inline Status sensorPoseFromHomogeneous(const Matrix4& T_oe, const SensorMount& mount, double translation_scale,
                                        Matrix4& X_os) noexcept {
  if (!std::isfinite(translation_scale)) return Status::non_finite_input;
  if (!(translation_scale > 0)) return Status::invalid_argument;
  Matrix3 R;
  Vector3 p;
  const Status s = poseFromHomogeneous(T_oe, R, p);
  if (s != Status::ok) return s;
  const SE3<double> X_oe(SO3<double>::fromMatrixUnchecked(R), translation_scale * p);  // checked above
  const SE3<double> X_es(SO3<double>::fromMatrixUnchecked(mount.R_es), mount.p_es);
  X_os = (X_oe * X_es).matrix();
  return Status::ok;
}

}  // namespace lieservo::realtime

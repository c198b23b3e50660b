// lieservo/realtime/frames.hpp — sensor-frame twists to a robot's base-frame command.
//
// Frames: {O} robot base, {E} end effector (pose T_OE; libfranka's O_T_EE), {S} tactile
// sensor (tip centre, z out of the tip), rigidly mounted: X_OS = X_OE X_ES, with the
// mounting transform X_ES = (R_ES, p_ES) (p_ES: the sensor origin in {E} coordinates).
//
// The controllers output a BODY twist of the sensor, ξ_s = [v_s; ω_s]: v_s is the velocity
// of the sensor origin and ω_s the angular velocity, both in {S} coordinates
// (X_OS⁻¹ dX_OS/dt = ξ_s^). libfranka's CartesianVelocities O_dP_EE = [ṗ_OE; ω_O] is the
// velocity of the EE ORIGIN and the angular velocity, both in BASE coordinates (a "mixed"
// twist, not the spatial twist of Lie theory, which would be the velocity of the point at
// the base origin). The derivation:
//   ω_O   = R_OS ω_s,                    R_OS = R_OE R_ES
//   ṗ_OS  = R_OS v_s                     (sensor origin velocity, base coordinates)
//   p_OS  = p_OE + R_OE p_ES   ⇒   ṗ_OE = ṗ_OS − ω_O × (R_OE p_ES)
//                                       = R_OS v_s + (R_OE p_ES) × ω_O.
// Equivalently O_dP_EE = Ad(X_{O'S}) ξ_s with X_{O'S} = (R_OS, R_OE p_ES), the sensor pose
// seen from a frame at the EE origin with base orientation (Ad = [[C, r^C],[0, C]]).
// Note that only R_OE enters, not p_OE. The mounting offset matters: rotating about the tip
// centre (as the servo controllers ask) moves the EE origin by ω × (p_OE − p_OS).
//
// Units: rotations in radians. Translation units pass through unchanged; the library's
// twists are in mm/s and poses in mm, libfranka's in m/s and m — scale by
// `translation_scale` (e.g. 1e-3 for mm → m) where offered.
//
// Eigen + std only; noexcept; no allocation.
#pragma once

#include <lieservo/status.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

namespace lieservo::realtime {

using Matrix3 = Eigen::Matrix3d;
using Vector3 = Eigen::Vector3d;
using Vector6 = Eigen::Matrix<double, 6, 1>;
using Matrix4 = Eigen::Matrix4d;

/// Default tolerance of the orthonormality check on robot-supplied rotations.
constexpr double kRotationTolerance = 1e-6;

/// True when R is orthonormal with determinant +1 to within `tol` (max-abs of RᵀR − I).
inline bool isRotation(const Matrix3& R, double tol = kRotationTolerance) noexcept {
  if (!R.allFinite()) return false;
  const double err = (R.transpose() * R - Matrix3::Identity()).cwiseAbs().maxCoeff();
  return err <= tol && std::abs(R.determinant() - 1.0) <= 3 * tol;
}

/// A homogeneous 4×4 pose T_OE (the robot's end effector in its base frame) to a rotation
/// and a translation. Checks: finite, bottom row (0 0 0 1), rotation orthonormal (tol).
/// Errors: non_finite_input, invalid_argument (bottom row), not_orthonormal; outputs
/// untouched unless ok. (A robot library's own layout, e.g. libfranka's column-major
/// O_T_EE array, is mapped to a Matrix4 by its adapter: examples/franka/franka_frames.hpp.)
inline Status poseFromHomogeneous(const Matrix4& T, Matrix3& R, Vector3& p, double tol = kRotationTolerance) noexcept {
  if (!T.allFinite()) return Status::non_finite_input;
  if (std::abs(T(3, 0)) > tol || std::abs(T(3, 1)) > tol || std::abs(T(3, 2)) > tol || std::abs(T(3, 3) - 1.0) > tol)
    return Status::invalid_argument;
  const Matrix3 Rm = T.topLeftCorner<3, 3>();
  if (!isRotation(Rm, tol)) return Status::not_orthonormal;
  R = Rm;
  p = T.topRightCorner<3, 1>();
  return Status::ok;
}

/// Rigid mounting of the sensor on the end effector: X_ES = (R_ES, p_ES).
struct SensorMount {
  Matrix3 R_es = Matrix3::Identity();
  Vector3 p_es = Vector3::Zero();  ///< sensor origin in {E}, in the command's length unit

  Status validate(double tol = kRotationTolerance) const noexcept {
    if (!R_es.allFinite() || !p_es.allFinite()) return Status::non_finite_input;
    if (!isRotation(R_es, tol)) return Status::not_orthonormal;
    return Status::ok;
  }
};

/// Sensor body twist ξ_s = [v_s; ω_s] → [ṗ_OE; ω_O], the EE-origin velocity and angular
/// velocity in base coordinates (libfranka's O_dP_EE), given R_OE and the mount. The
/// translation of ξ_s is multiplied by `translation_scale` first (mm → m: 1e-3); p_ES must
/// be in the OUTPUT length unit. Unchecked (see sensorTwistToBaseChecked).
inline Vector6 sensorTwistToBase(const Matrix3& R_oe, const SensorMount& mount, const Vector6& xi_s,
                                 double translation_scale = 1.0) noexcept {
  const Matrix3 R_os = R_oe * mount.R_es;
  const Vector3 w_o = R_os * xi_s.tail<3>();
  const Vector3 r_o = R_oe * mount.p_es;  // EE origin → sensor origin, base coordinates
  Vector6 out;
  out.head<3>() = R_os * (translation_scale * xi_s.head<3>()) + r_o.cross(w_o);
  out.tail<3>() = w_o;
  return out;
}

/// Inverse of sensorTwistToBase: [ṗ_OE; ω_O] (e.g. libfranka's O_dP_EE_c) → ξ_s, with the
/// translation divided by `translation_scale` at the end (m → mm: 1e-3).
inline Vector6 baseTwistToSensor(const Matrix3& R_oe, const SensorMount& mount, const Vector6& v_base,
                                 double translation_scale = 1.0) noexcept {
  const Matrix3 R_os = R_oe * mount.R_es;
  const Vector3 w_o = v_base.tail<3>();
  const Vector3 r_o = R_oe * mount.p_es;
  const Vector3 p_dot_s = v_base.head<3>() - r_o.cross(w_o);  // sensor origin velocity, base
  Vector6 out;
  out.head<3>() = R_os.transpose() * p_dot_s / translation_scale;
  out.tail<3>() = R_os.transpose() * w_o;
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
  X_os.setIdentity();
  X_os.topLeftCorner<3, 3>() = R * mount.R_es;
  X_os.topRightCorner<3, 1>() = translation_scale * p + R * mount.p_es;
  return Status::ok;
}

}  // namespace lieservo::realtime

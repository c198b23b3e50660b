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
// Types and units: poses are SE3 throughout. A robot's pose T_OE is parsed once, checked
// (poseFromHomogeneous, or its adapter's parse of the robot library's layout), into an SE3 in
// the robot's length unit (libfranka: metres). The mount X_ES is one object in that same unit
// (SensorMount, built once from the library's mm with SensorMount::fromLibraryUnits). Rotations
// in radians. The library's twists are in mm/s and poses in mm: the functions below take a
// `translation_scale` for the one change of unit they make.
//
// noexcept; no allocation.
#pragma once
#include <lieservo/detail/options_push.hpp>

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

/// The one parse of a robot-supplied pose: a homogeneous 4×4 T_OE (the robot's end effector in
/// its base frame) to an SE3, checked by SE3::fromMatrix: non_finite_input, not_orthonormal
/// (rotation block, tolerance `tol`), invalid_argument (bottom row not (0 0 0 1) within `tol`);
/// X untouched unless ok. (A robot library's own layout, e.g. libfranka's column-major O_T_EE
/// array, is mapped by its adapter: examples/franka/franka_frames.hpp.)
inline Status poseFromHomogeneous(const Matrix4& T, SE3<double>& X, double tol = kRotationTolerance) noexcept {
  return SE3<double>::fromMatrix(T, X, tol);
}

/// Rigid mounting of the sensor on the end effector: X_ES, the sensor frame in {E}, with its
/// translation p_ES in the ROBOT's length unit, that of T_OE (metres for libfranka).
struct SensorMount {
  SE3<double> X_es{};  ///< X_ES = (R_ES, p_ES), p_ES in the robot's length unit

  /// The mount from X_ES in the library's length unit (mm) and `to_robot`, the factor to the
  /// robot's (mm → m: 1e-3).
  static SensorMount fromLibraryUnits(const SE3<double>& X_es_library, double to_robot) noexcept {
    return SensorMount{SE3<double>(X_es_library.so3(), to_robot * X_es_library.translation())};
  }

  /// non_finite_input, not_orthonormal (isRotation with `tol`), or ok.
  Status validate(double tol = kRotationTolerance) const noexcept {
    if (!X_es.allFinite()) return Status::non_finite_input;
    if (!isRotation(X_es.rotationMatrix(), tol)) return Status::not_orthonormal;
    return Status::ok;
  }
};

/// X_O'S = (R_OS, R_OE p_ES): the sensor pose from a frame at the EE origin with the base's
/// orientation, whose adjoint maps the sensor's body twist to the base twist (file comment).
inline SE3<double> eeOriginToSensor(const SE3<double>& T_oe, const SensorMount& mount) noexcept {
  return SE3<double>(T_oe.so3() * mount.X_es.so3(), T_oe.so3() * mount.X_es.translation());
}

/// Sensor body twist ξ_s = [v_s; ω_s] → base twist [ṗ_OE; ω_O] = Ad(X_O'S) ξ_s, the EE-origin
/// velocity and the angular velocity in base coordinates, given the EE pose T_OE (only its
/// rotation enters) and the mount. The translation of ξ_s is multiplied by
/// `translation_scale` first (library mm → robot m: 1e-3). Unchecked: T_OE and the mount come
/// checked from their parse and validate(); the pipeline checks the twist.
inline Vector6 sensorTwistToBase(const SE3<double>& T_oe, const SensorMount& mount, const Vector6& xi_s,
                                 double translation_scale = 1.0) noexcept {
  Vector6 xi = xi_s;
  xi.head<3>() *= translation_scale;
  return eeOriginToSensor(T_oe, mount).Ad() * xi;
}

/// Inverse of sensorTwistToBase: a base twist [ṗ_OE; ω_O] (e.g. the robot's last command) →
/// ξ_s = Ad(X_O'S⁻¹) [ṗ_OE; ω_O], with the translation divided by `translation_scale` at the
/// end (robot m → library mm: 1e-3).
inline Vector6 baseTwistToSensor(const SE3<double>& T_oe, const SensorMount& mount, const Vector6& v_base,
                                 double translation_scale = 1.0) noexcept {
  Vector6 out = eeOriginToSensor(T_oe, mount).inverse().Ad() * v_base;
  out.head<3>() /= translation_scale;
  return out;
}

/// The sensor's pose in the base frame, X_OS = T_OE X_ES, with its translation multiplied by
/// `translation_scale` (robot m → library mm: 1e3).
inline SE3<double> sensorPose(const SE3<double>& T_oe, const SensorMount& mount, double translation_scale = 1.0) noexcept {
  const SE3<double> X_os = T_oe * mount.X_es;
  return SE3<double>(X_os.so3(), translation_scale * X_os.translation());
}

}  // namespace lieservo::realtime

#include <lieservo/detail/options_pop.hpp>

// franka_frames.hpp — libfranka's pose layout to the robot-agnostic real-time layer.
//
// libfranka's documented Cartesian limits, and its pose layout: libfranka gives the end-effector
// pose as RobotState::O_T_EE, a std::array<double, 16> holding the homogeneous 4×4 T_OE
// column-major (element (r, c) at c*4 + r; metres). poseFromColumnMajor is the one parse of it
// into the SE3 that the core (include/lieservo/realtime) and the filter's side take. Header-only, Eigen + std only (no libfranka), so it is
// tested in CI (tests/franka) where libfranka is not installed.
#pragma once

#include <lieservo/realtime/frames.hpp>
#include <lieservo/realtime/velocity_smoother.hpp>
#include <lieservo/status.hpp>

#include <array>

namespace lieservo::franka_frames {

using realtime::Matrix4;
using realtime::SensorMount;
using realtime::Vector6;

/// libfranka's documented Cartesian limits for the end effector (m, rad, s): translation
/// 1.7 m/s, 13 m/s², 6500 m/s³; rotation 2.5 rad/s, 25 rad/s², 12500 rad/s³. Never command at
/// these: the adapter refuses smoother limits that are not within() them.
inline realtime::SmootherLimits<double> documentedCartesianLimits() noexcept {
  realtime::SmootherLimits<double> l;
  l.translation = {1.7, 13.0, 6500.0};
  l.rotation = {2.5, 25.0, 12500.0};
  return l;
}

/// O_T_EE as a homogeneous matrix (Eigen's default storage is column-major, as libfranka's).
inline Matrix4 homogeneous(const std::array<double, 16>& O_T_EE) noexcept {
  return Eigen::Map<const Matrix4>(O_T_EE.data());
}

/// A homogeneous matrix to libfranka's column-major array.
inline std::array<double, 16> toColumnMajor(const Matrix4& M) noexcept {
  std::array<double, 16> a{};
  Eigen::Map<Matrix4>(a.data()) = M;
  return a;
}

/// The one parse of O_T_EE: T_OE as an SE3 in metres, checked (realtime::poseFromHomogeneous);
/// T_oe untouched unless ok.
inline Status poseFromColumnMajor(const std::array<double, 16>& O_T_EE, SE3<double>& T_oe,
                                  double tol = realtime::kRotationTolerance) noexcept {
  return realtime::poseFromHomogeneous(homogeneous(O_T_EE), T_oe, tol);
}

}  // namespace lieservo::franka_frames

// lieservo_sim/simulated_arm.hpp — a kinematic arm implementing lieservo::robot::RobotInterface.
//
// The commanded twist u = [v (mm/s); ω (rad/s)] is a BODY twist in the current sensor frame
// {s} (the controllers' output, sec:servoing_controller).  The arm integrates it by RIGHT
// multiplication, X_ws ← X_ws · exp(u_k^ Δt), in `substeps` sub-steps of Δt = dt / substeps
// (the paper's 1 kHz libfranka loop under a ~25 Hz tactile loop).  Before each sub-step the
// commanded twist is limited (linear and angular speed caps, direction kept) and the applied
// twist moves towards it no faster than the acceleration limits allow.
#pragma once

#include <cstdint>

#include "common.hpp"
#include "robot_interface.hpp"  // examples/robot (include path set by CMake)

namespace lieservo::sim {

struct ArmLimits {
  double max_linear_speed = 250.0;       ///< mm/s
  double max_angular_speed = deg(90.0);  ///< rad/s
  double max_linear_accel = 1000.0;      ///< mm/s²
  double max_angular_accel = deg(360.0); ///< rad/s²
  int substeps = 8;                      ///< integration sub-steps per commandVelocity call

  void validate() const;  ///< throws SceneError
};

/// One integration step's applied twist: `target` capped at the speed limits (norms, direction
/// kept), reached from `applied` no faster than the acceleration limits allow over h seconds.
lieservo::robot::Twist limitTwist(const lieservo::robot::Twist& target, const lieservo::robot::Twist& applied,
                                  const ArmLimits& limits, double h);

class SimulatedArm final : public lieservo::robot::RobotInterface {
 public:
  using Twist = lieservo::robot::Twist;

  explicit SimulatedArm(const SE3d& X_ws0, const ArmLimits& limits = {});

  Status readPose(SE3d& X_ws) override;
  /// Integrates `twist_s` for dt seconds; Status::invalid_time_step for dt ≤ 0 / non-finite,
  /// Status::non_finite_input for a NaN twist (pose unchanged).
  Status commandVelocity(const Twist& twist_s, double dt) override;
  /// Teleports (a blocking move that has finished) and brings the arm to rest.
  Status moveTo(const SE3d& X_ws) override;
  void stop() override { velocity_.setZero(); }

  const SE3d& pose() const { return pose_; }
  const Twist& velocity() const { return velocity_; }  ///< applied body twist (after limits)
  const ArmLimits& limits() const { return limits_; }

 private:
  void substep(const Twist& target, double h);
  SE3d pose_;
  Twist velocity_ = Twist::Zero();
  ArmLimits limits_;
};

}  // namespace lieservo::sim

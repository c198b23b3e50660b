// examples/robot/robot_interface.hpp — the robot interface the examples share.
//
// Implemented by the simulated arm (examples/sim) and by the libfranka adapter
// (examples/franka). Poses are the *sensor* frame {s} (tip centre, z out of the tip)
// in the robot's work frame {w}; translation in mm, rotation in radians. Twists are
// body twists in the current sensor frame, ξ = [v; ω] (mm/s, rad/s), the same
// frame as the controllers' output (paper Section 3.3.2 (sec:servoing_controller)).
#pragma once

#include <lieservo/groups/se3.hpp>
#include <lieservo/status.hpp>

namespace lieservo::robot {

using SE3d = lieservo::SE3<double>;
using Twist = SE3d::Tangent;  // [v (mm/s); ω (rad/s)] in the sensor frame

class RobotInterface {
 public:
  virtual ~RobotInterface() = default;

  /// Current sensor pose X_ws (proprioception).
  virtual Status readPose(SE3d& X_ws) = 0;

  /// Command a sensor-frame velocity twist held for the next control period dt (s).
  /// Implementations limit velocity/acceleration; dt <= 0 → Status::invalid_time_step.
  virtual Status commandVelocity(const Twist& twist_s, double dt) = 0;

  /// Blocking position move of the sensor frame to X_ws (used by data collection).
  virtual Status moveTo(const SE3d& X_ws) = 0;

  /// Bring the robot to rest (ramp velocity to zero).
  virtual void stop() = 0;
};

}  // namespace lieservo::robot

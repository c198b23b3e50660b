// lieservo_sim/sensor_arm.hpp — a sensor of the MuJoCo world driven as a robot.
//
// The arm holding a TacTip is velocity-servoed and position-stiff: RobotInterface's commanded
// twist u = [v (mm/s); ω (rad/s)] is a BODY twist in the current sensor frame {s} (the
// controllers' output, Section 3.3.2 (sec:servoing_controller)): each call sets the twist the sensor moves
// with, and each World::step moves it by right multiplication, X_ws ← X_ws · exp(u h), with
// MuJoCo seeing that velocity. The twist applied is the commanded one capped at speed limits
// (norms, direction kept) and reached no faster than the acceleration limits allow: the
// paper's arm under its ~25 Hz tactile loop. The world is stepped by the caller.
#pragma once

#include "common.hpp"
#include "contact_model.hpp"
#include "mujoco_world.hpp"
#include "robot_interface.hpp"  // examples/robot (include path set by CMake)

namespace lieservo::sim {

struct ArmLimits {
  double max_linear_speed = 250.0;       ///< mm/s
  double max_angular_speed = deg2rad(90.0);  ///< rad/s
  double max_linear_accel = 1000.0;      ///< mm/s²
  double max_angular_accel = deg2rad(360.0); ///< rad/s²

  void validate() const;  ///< throws SceneError
};

/// One step's applied twist: `target` capped at the speed limits (norms, direction kept),
/// reached from `applied` no faster than the acceleration limits allow over h seconds.
lieservo::robot::Twist limitTwist(const lieservo::robot::Twist& target, const lieservo::robot::Twist& applied,
                                  const ArmLimits& limits, double h);

/// The tactile contact of the world's sensor `sensor`, from the engine's nearest surface point
/// (an object or a fixture) and the gel's deflection, through `contact` (its anchor is
/// released when nothing is in range; the state then says no contact, depth −1000 mm).
ContactState touchContact(const mujoco::World& world, int sensor, ContactModel& contact);

class MujocoSensorArm final : public lieservo::robot::RobotInterface {
 public:
  /// Throws SceneError for a sensor index the world does not have or bad limits.
  MujocoSensorArm(mujoco::World& world, int sensor, const ArmLimits& limits = {});

  Status readPose(SE3d& X_ws) override;
  /// The twist the sensor moves with from now on (World::step moves it), under the limits;
  /// dt is the time since the last command (for the acceleration limits). invalid_time_step
  /// for dt ≤ 0 or non-finite, non_finite_input for a NaN twist; the motion is unchanged then.
  Status commandVelocity(const SE3d::Tangent& twist_s, double dt) override;
  /// Teleports the sensor (a blocking move that has finished) and brings the arm to rest.
  Status moveTo(const SE3d& X_ws) override;
  void stop() override;
  SE3d pose() const { return world_->sensorPose(sensor_); }
  const SE3d::Tangent& appliedTwist() const { return applied_; }
  int sensor() const { return sensor_; }

 private:
  mujoco::World* world_;
  int sensor_;
  ArmLimits limits_;
  SE3d::Tangent applied_ = SE3d::Tangent::Zero();
};

}  // namespace lieservo::sim

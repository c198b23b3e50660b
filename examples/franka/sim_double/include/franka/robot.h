// franka/robot.h (lieservo's libfranka test double) — the part of libfranka's franka::Robot
// that the Franka adapter uses, with libfranka's declarations, backed by the simulated Panda
// of franka_sim/arm.h instead of a network connection to an arm.
#pragma once

#include <array>
#include <cstddef>
#include <functional>
#include <memory>
#include <string>

#include <franka/control_types.h>
#include <franka/duration.h>
#include <franka/exception.h>
#include <franka/lowpass_filter.h>
#include <franka/robot_state.h>

namespace franka_sim {
class Arm;
}

namespace franka {

class Robot {
 public:
  /// "Connects" to the simulated arm registered under franka_address (franka_sim::Arm);
  /// NetworkException when none is.
  explicit Robot(const std::string& franka_address, RealtimeConfig realtime_config = RealtimeConfig::kEnforce,
                 size_t log_size = 50);
  Robot(const Robot&) = delete;
  Robot& operator=(const Robot&) = delete;
  ~Robot() noexcept;

  /// Runs the Cartesian velocity motion generator at 1 kHz until it returns MotionFinished.
  /// Throws ControlException where libfranka's robot would stop with an error (a command over
  /// the documented Cartesian limits, a joint over its limits, an injected reflex) and
  /// std::invalid_argument for a non-finite command, as libfranka does.
  void control(std::function<CartesianVelocities(const RobotState&, franka::Duration)> motion_generator_callback,
               ControllerMode controller_mode = ControllerMode::kJointImpedance, bool limit_rate = false,
               double cutoff_frequency = kDefaultCutoffFrequency);

  RobotState readOnce();

  void setCollisionBehavior(const std::array<double, 7>& lower_torque_thresholds,
                            const std::array<double, 7>& upper_torque_thresholds,
                            const std::array<double, 6>& lower_force_thresholds,
                            const std::array<double, 6>& upper_force_thresholds);

  void automaticErrorRecovery();

 private:
  std::shared_ptr<franka_sim::Arm> arm_;
};

}  // namespace franka

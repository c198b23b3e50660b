// franka/control_types.h (lieservo's libfranka test double) — the Cartesian velocity command
// and the enumerations the Franka adapter uses, with libfranka's declarations.
#pragma once

#include <array>
#include <initializer_list>

namespace franka {

enum class ControllerMode { kJointImpedance, kCartesianImpedance };
enum class RealtimeConfig { kEnforce, kIgnore };

struct Finishable {
  bool motion_finished = false;
};

/// The end effector's twist in the base frame: [v (m/s); ω (rad/s)].
class CartesianVelocities : public Finishable {
 public:
  CartesianVelocities(const std::array<double, 6>& cartesian_velocities) noexcept
      : O_dP_EE(cartesian_velocities) {}
  std::array<double, 6> O_dP_EE{};  // NOLINT(readability-identifier-naming)
};

/// The last command of a motion: the robot stops the motion after it.
inline CartesianVelocities MotionFinished(CartesianVelocities command) noexcept {  // NOLINT
  command.motion_finished = true;
  return command;
}

}  // namespace franka

// franka/robot_state.h (lieservo's libfranka test double) — the fields of libfranka's
// franka::RobotState that the double fills (the Franka adapter reads O_T_EE).
#pragma once

#include <array>

#include <franka/duration.h>

namespace franka {

struct RobotState {
  std::array<double, 16> O_T_EE{};  ///< end effector in the base frame, column-major (m)  // NOLINT
  std::array<double, 7> q{};        ///< joint positions (rad)
  std::array<double, 7> dq{};       ///< joint velocities (rad/s)
  Duration time{};                  ///< since the robot started
};

}  // namespace franka

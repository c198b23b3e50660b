// The libfranka test double's joints under MuJoCo's dynamics, for the tests in tests/franka.
#pragma once

#include <algorithm>
#include <cmath>

#include <franka_sim/arm.h>

#include "lieservo_sim/panda_dynamics.hpp"

namespace lieservo_test {

namespace panda = lieservo::sim::panda;

/// The double's joints as the MuJoCo Panda moves them under its joint controller
/// (panda_dynamics.hpp): they lag the commands and yield to the contact's load.
class DynamicServo : public franka_sim::JointServo {
 public:
  explicit DynamicServo(const panda::Joints& q0) : arm_(q0) {}
  void step(const panda::Joints& dq_cmd, const Eigen::Vector3d& f, const Eigen::Vector3d& p, panda::Joints& q,
            panda::Joints& dq) override {
    arm_.setLoad(f, p);
    arm_.step(dq_cmd);
    q = arm_.q();
    dq = arm_.dq();
    for (int i = 0; i < panda::kJoints; ++i)
      max_torque_ratio = std::max(max_torque_ratio, std::abs(arm_.torques()[i]) / panda::torqueLimits()[i]);
    max_lag = std::max(max_lag, arm_.trackingError().cwiseAbs().maxCoeff());
  }
  void brake(panda::Joints& q, panda::Joints& dq) override {
    arm_.brake();
    q = arm_.q();
    dq = arm_.dq();
  }
  double max_torque_ratio = 0;  ///< max |τ_i| / τ_max,i over the cycles
  double max_lag = 0;           ///< rad: max |q_d − q| over the cycles

 private:
  panda::PandaDynamics arm_;
};

}  // namespace lieservo_test

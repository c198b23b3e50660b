// Kinematic arm (see lieservo_sim/simulated_arm.hpp).
#include "lieservo_sim/simulated_arm.hpp"

#include <algorithm>
#include <cmath>

namespace lieservo::sim {

void ArmLimits::validate() const {
  requirePositive(max_linear_speed, "ArmLimits.max_linear_speed");
  requirePositive(max_angular_speed, "ArmLimits.max_angular_speed");
  requirePositive(max_linear_accel, "ArmLimits.max_linear_accel");
  requirePositive(max_angular_accel, "ArmLimits.max_angular_accel");
  if (substeps < 1 || substeps > 1000) throw SceneError("ArmLimits.substeps must be in [1, 1000]");
}

SimulatedArm::SimulatedArm(const SE3d& X_ws0, const ArmLimits& limits) : pose_(X_ws0), limits_(limits) {
  limits_.validate();
  requireValidPose(X_ws0, "SimulatedArm initial pose");
}

Status SimulatedArm::readPose(SE3d& X_ws) {
  X_ws = pose_;
  return Status::ok;
}

static Vec3 capNorm(const Vec3& v, double cap) {
  const double n = v.norm();
  return n > cap ? Vec3(v * (cap / n)) : v;
}

lieservo::robot::Twist limitTwist(const lieservo::robot::Twist& target, const lieservo::robot::Twist& applied,
                                  const ArmLimits& limits, double h) {
  lieservo::robot::Twist cmd;
  cmd.head<3>() = capNorm(target.head<3>(), limits.max_linear_speed);
  cmd.tail<3>() = capNorm(target.tail<3>(), limits.max_angular_speed);
  lieservo::robot::Twist dv = cmd - applied;
  dv.head<3>() = capNorm(dv.head<3>(), limits.max_linear_accel * h);
  dv.tail<3>() = capNorm(dv.tail<3>(), limits.max_angular_accel * h);
  return applied + dv;
}

void SimulatedArm::substep(const Twist& target, double h) {
  velocity_ = limitTwist(target, velocity_, limits_, h);
  pose_ = pose_ * SE3d::exp(velocity_ * h);  // body twist: right multiplication
  pose_.normalize();
}

Status SimulatedArm::commandVelocity(const Twist& twist_s, double dt) {
  if (!(dt > 0) || !std::isfinite(dt)) return Status::invalid_time_step;
  if (!twist_s.allFinite()) return Status::non_finite_input;
  const double h = dt / limits_.substeps;
  for (int i = 0; i < limits_.substeps; ++i) substep(twist_s, h);
  return Status::ok;
}

Status SimulatedArm::moveTo(const SE3d& X_ws) {
  if (!X_ws.allFinite()) return Status::non_finite_input;
  pose_ = X_ws;
  velocity_.setZero();
  return Status::ok;
}

}  // namespace lieservo::sim

// A sensor of the MuJoCo world driven as a robot (see lieservo_sim/sensor_arm.hpp).
#include "lieservo_sim/sensor_arm.hpp"

#include <cmath>
#include <string>

namespace lieservo::sim {

ContactState touchContact(const mujoco::World& world, int sensor, ContactModel& contact) {
  const mujoco::TipGeometry g = world.tipGeometry(sensor);
  if (!g.valid) {
    contact.release();
    ContactState none;
    none.depth = -1e3;
    return none;
  }
  const SE3d X_wo = g.object >= 0 ? world.objectPose(g.object) : world.fixturePose(g.fixture);
  SurfacePoint sp;
  sp.point = X_wo.inverse() * g.point_w;
  sp.normal = X_wo.rotationMatrix().transpose() * g.normal_w;
  sp.signed_distance = contact.params().tip_radius - g.depth;
  return contact.update(world.sensorPose(sensor), X_wo, sp, world.gelDeflection(sensor));
}

void ArmLimits::validate() const {
  requirePositive(max_linear_speed, "ArmLimits.max_linear_speed");
  requirePositive(max_angular_speed, "ArmLimits.max_angular_speed");
  requirePositive(max_linear_accel, "ArmLimits.max_linear_accel");
  requirePositive(max_angular_accel, "ArmLimits.max_angular_accel");
}

namespace {
Vec3 capNorm(const Vec3& v, double cap) {
  const double n = v.norm();
  return n > cap ? Vec3(v * (cap / n)) : v;
}
}  // namespace

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

MujocoSensorArm::MujocoSensorArm(mujoco::World& world, int sensor, const ArmLimits& limits)
    : world_(&world), sensor_(sensor), limits_(limits) {
  if (sensor < 0 || sensor >= world.sensorCount()) throw SceneError("MujocoSensorArm: no sensor " + std::to_string(sensor));
  limits_.validate();
}

Status MujocoSensorArm::readPose(SE3d& X_ws) {
  X_ws = world_->sensorPose(sensor_);
  return Status::ok;
}

Status MujocoSensorArm::commandVelocity(const SE3d::Tangent& twist_s, double dt) {
  if (!(dt > 0) || !std::isfinite(dt)) return Status::invalid_time_step;
  if (!twist_s.allFinite()) return Status::non_finite_input;
  const SE3d::Tangent applied = limitTwist(twist_s, applied_, limits_, dt);
  // The world moves the sensor by X_ws ← X_ws · exp(u^ h) at each of its steps (body twist:
  // right multiplication) while this twist holds.
  const Status s = world_->setSensorTwist(sensor_, applied);
  if (s == Status::ok) applied_ = applied;
  return s;
}

void MujocoSensorArm::stop() {
  applied_.setZero();
  // A zero twist for the arm's own sensor: setSensorTwist refuses only a bad index or a non-finite twist.
  (void)world_->setSensorTwist(sensor_, applied_);
}

Status MujocoSensorArm::moveTo(const SE3d& X_ws) {
  const Status s = world_->setSensorPose(sensor_, X_ws);  // at rest there
  if (s == Status::ok) applied_.setZero();
  return s;
}

}  // namespace lieservo::sim

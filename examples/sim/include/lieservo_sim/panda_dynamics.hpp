// lieservo_sim/panda_dynamics.hpp — the Franka Emika Panda as a MuJoCo model: its joints
// move under torques, so the arm lags its commands and yields to loads, as the real one does.
//
// The model (pandaMjcf) is the chain of panda_kinematics.hpp (Franka's modified DH table, the
// same joint limits), one body per link with a capsule of the link's mass (Gaz et al.'s
// identified masses, IEEE RA-L 2019), the rotors' reflected inertia as joint armature, and
// the sensor and its mount (0.5 kg) on the flange. Each joint is driven by the robot's own
// joint controller, a PD law with velocity feedforward toward the trajectory that integrates
// the commanded joint velocities,
//     τ_i = kp_i (q_d,i − q_i) + kd_i (q̇_d,i − q̇_i),   q_d ← q_d + Δt q̇_d,
// within the Panda's joint torque limits (87 N·m joints 1–4, 12 N·m joints 5–7). The robot
// compensates gravity itself (libfranka's torques exclude it), so the model has none; inertia,
// Coriolis forces and external loads remain. MuJoCo steps it at 1 kHz with its implicit
// integrator. The gains, armature and link shapes are plausible values, not Franka's (the
// robot's internal controller is not published); docs/hardware.md says what follows from them.
//
// Units are libfranka's (metres, radians, newtons, seconds) in the base frame {O}.
#pragma once

#include <string>

#include <Eigen/Core>

#include "panda_kinematics.hpp"

struct mjModel_;
struct mjData_;

namespace lieservo::sim::panda {

/// The joint controller's gains: kp (N·m/rad) and kd (N·m·s/rad) per joint.
struct JointServoGains {
  Joints kp = (Joints() << 3000, 3000, 3000, 3000, 1000, 1000, 1000).finished();
  Joints kd = (Joints() << 80, 80, 80, 80, 20, 20, 20).finished();
};

/// The Panda's joint torque limits (N·m), Franka's datasheet.
inline const Joints& torqueLimits() {
  static const Joints tau = (Joints() << 87, 87, 87, 87, 12, 12, 12).finished();
  return tau;
}

/// The model's MJCF (metres, radians; 1 ms step, no gravity, no contacts of its own).
std::string pandaMjcf(const JointServoGains& gains = {});

/// The Panda's joints under its joint controller in MuJoCo, one 1 ms step at a time.
class PandaDynamics {
 public:
  /// At rest at q0 (throws std::invalid_argument outside the joint limits or on a gains error,
  /// std::runtime_error if MuJoCo cannot load the model).
  explicit PandaDynamics(const Joints& q0, const JointServoGains& gains = {});
  ~PandaDynamics();
  PandaDynamics(const PandaDynamics&) = delete;
  PandaDynamics& operator=(const PandaDynamics&) = delete;

  /// One 1 ms step toward the joint velocities dq_d (rad/s): the desired trajectory advances by
  /// dq_d Δt and the joint controller's torques, the load and the arm's dynamics move the joints.
  void step(const Joints& dq_d);
  /// The robot brakes where it is: at rest, the desired trajectory reset to the joints.
  void brake();
  /// A load on the arm, held until changed: force f (N, {O}) at the point p (m, {O}) of the
  /// flange's body (what a contact at the sensor's tip pushes back with). Zero by default;
  /// throws std::invalid_argument on a non-finite value (the load kept).
  void setLoad(const Eigen::Vector3d& f, const Eigen::Vector3d& p);

  Joints q() const;
  Joints dq() const;
  /// q_d − q (rad): how far the joints lag the desired trajectory.
  Joints trackingError() const;
  /// The joint controller's torques of the last step (N·m), after the torque limits.
  Joints torques() const;
  /// The flange pose in {O} from MuJoCo's own kinematics (equals flange(q())).
  Eigen::Matrix4d flangePose() const;
  static constexpr double kStep = 1e-3;  ///< s

 private:
  void applyLoad();

  mjModel_* m_ = nullptr;
  mjData_* d_ = nullptr;
  JointServoGains gains_;
  Joints q_d_;
  int flange_body_ = -1;
  Eigen::Vector3d load_f_ = Eigen::Vector3d::Zero(), load_p_ = Eigen::Vector3d::Zero();
};

}  // namespace lieservo::sim::panda

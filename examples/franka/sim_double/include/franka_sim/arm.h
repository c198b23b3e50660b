// franka_sim/arm.h — the simulated Panda behind lieservo's libfranka test double.
//
// A franka::Robot constructed with an address finds the Arm registered under it here. The
// arm follows each 1 kHz Cartesian velocity command by resolved rate (panda_kinematics.hpp:
// damped least squares, joint velocity limits) and stops with the error libfranka's robot
// would raise: a command over the documented Cartesian limits, a joint over its position
// limits or a joint velocity the command needs beyond its limit (after the inverse kinematics,
// as libfranka names them), an injected reflex. After
// an error the arm is at rest (dq = 0) until automaticErrorRecovery().
//
// What moves the joints is a JointServo: by default kinematic (the joints follow their velocity
// command exactly, no dynamics, no load); a dynamic one (the MuJoCo Panda of
// lieservo_sim/panda_dynamics.hpp under its joint controller, tests/franka/test_franka_tasks.cpp)
// lags the command and yields to the load set with setLoad. The cycles are paced at 1 kHz of
// wall-clock time, since the adapter's watchdog measures the age of commands on the steady
// clock. In lockstep mode (setLockstep) the cycles run only as a simulation releases them
// (advance), so that a simulated world and the arm share one clock.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>

#include <franka/control_types.h>
#include <franka/duration.h>
#include <franka/robot_state.h>
#include <lieservo_sim/panda_kinematics.hpp>

namespace franka_sim {

namespace panda = lieservo::sim::panda;

/// What the double saw over its motions (since construction or resetReport()).
struct ArmReport {
  std::uint64_t cycles = 0;             ///< 1 kHz callbacks run
  std::uint64_t motions = 0;            ///< control() calls that ended normally
  std::uint64_t errors = 0;             ///< control() calls that ended in an error
  std::string last_error;               ///< the last error's text ("" if none)
  double max_twist_error = 0;           ///< max ‖J dq − commanded twist‖ (m/s and rad/s mixed)
  std::uint64_t damped_cycles = 0;      ///< cycles where damping (a near singularity) changed the twist
  double min_manipulability = 1e9;      ///< over the cycles
  double min_joint_margin = 1e9;        ///< rad, over the cycles
  double max_speed = 0, max_angular_speed = 0;   ///< m/s, rad/s commanded
  double max_accel = 0, max_angular_accel = 0;   ///< m/s², rad/s² (differences over 1 ms)
  double max_jerk = 0, max_angular_jerk = 0;     ///< m/s³, rad/s³
  /// max ‖(J dq)_v − v‖ (m/s), J where the cycle started and dq the joint velocities the servo
  /// reached at its end: the flange's translation velocity achieved against the command (for
  /// the kinematic servo, the resolved rate's own error: 0 up to rounding).
  double max_achieved_error = 0;
};

/// The joints' response to the 1 kHz joint velocity commands of the resolved rate.
class JointServo {
 public:
  virtual ~JointServo() = default;
  /// One 1 ms cycle from (q, dq) toward the commanded joint velocities dq_cmd, under the load
  /// (force f, N, at point p, m, both in {O}); q and dq become the joints' state after it.
  virtual void step(const panda::Joints& dq_cmd, const Eigen::Vector3d& f, const Eigen::Vector3d& p,
                    panda::Joints& q, panda::Joints& dq) = 0;
  /// The robot brakes where it is (an error, or the end of a motion): q kept, dq = 0.
  virtual void brake(panda::Joints& q, panda::Joints& dq) = 0;
};

/// The default servo: q ← q + Δt dq_cmd, dq = dq_cmd; the load is ignored.
class KinematicServo : public JointServo {
 public:
  void step(const panda::Joints& dq_cmd, const Eigen::Vector3d&, const Eigen::Vector3d&, panda::Joints& q,
            panda::Joints& dq) override;
  void brake(panda::Joints&, panda::Joints& dq) override { dq.setZero(); }
};

class Arm {
 public:
  /// Registers an arm at q0 under `address` (replacing any other); remove() it after use. The
  /// servo's state must be q0 at rest (null: a KinematicServo).
  static std::shared_ptr<Arm> create(const std::string& address, const panda::Joints& q0 = panda::readyPose(),
                                     std::shared_ptr<JointServo> servo = nullptr);
  static void remove(const std::string& address);
  /// The arm registered under `address`, or null.
  static std::shared_ptr<Arm> find(const std::string& address);

  explicit Arm(const panda::Joints& q0, std::shared_ptr<JointServo> servo = nullptr);

  /// The load on the flange's body, held until changed: force f (N, {O}) at point p (m, {O}),
  /// what a contact at the sensor pushes back with. Only a dynamic servo feels it. Throws
  /// std::invalid_argument on a non-finite value (the load kept).
  void setLoad(const Eigen::Vector3d& f, const Eigen::Vector3d& p);
  /// The next 1 kHz cycle raises a ControlException with this text (a reflex).
  void injectReflex(const std::string& what);
  /// Lockstep with a simulation (off by default): control() runs a 1 kHz cycle only when
  /// advance() has released one, so that the arm and a simulated world share one clock.
  void setLockstep(bool on);
  /// Releases n cycles and waits until they have run or no control() call is running; the
  /// number of cycles run (0 while the robot is idle: the arm rests meanwhile).
  int advance(int n);
  /// Whether a control() call is running (a motion has started and not ended).
  bool inControl() const;

  panda::Joints joints() const;
  panda::Joints jointVelocities() const;
  bool faulted() const;
  ArmReport report() const;

  // franka::Robot's side.
  franka::RobotState readOnce() const;
  void control(const std::function<franka::CartesianVelocities(const franka::RobotState&, franka::Duration)>& cb);
  void recover();

 private:
  franka::RobotState stateLocked() const;
  [[noreturn]] void fail(const std::string& what);  // mutex_ held
  using Twist = Eigen::Matrix<double, 6, 1>;
  // One 1 ms cycle of a commanded base twist, mutex_ held: the motion generator's limits on
  // `v` (against the previous cycle's velocity and acceleration, updated), then the joints.
  void checkMotionLimits(const Twist& v, Twist& v_prev, Twist& a_prev);
  void stepJoints(const Twist& v);

  mutable std::mutex mutex_;
  panda::Joints q_, dq_ = panda::Joints::Zero();
  std::shared_ptr<JointServo> servo_;
  Eigen::Vector3d load_f_ = Eigen::Vector3d::Zero(), load_p_ = Eigen::Vector3d::Zero();
  std::uint64_t time_ms_ = 0;
  bool faulted_ = false, lockstep_ = false, in_control_ = false;
  int permits_ = 0, ran_ = 0;
  std::condition_variable cycle_cv_;
  std::string reflex_;
  ArmReport report_;
};

}  // namespace franka_sim

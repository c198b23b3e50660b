// examples/franka/franka_adapter.hpp — lieservo::robot::RobotInterface on a Franka arm
// through libfranka (built only when find_package(Franka) succeeds; see docs/hardware.md).
//
// Threads:
//   * the caller's (tactile) thread, at camera rate: commandVelocity() writes the sensor-frame
//     twist and a contact flag into a lock-free LatestValueChannel and returns at once;
//   * the adapter's control thread, inside franka::Robot::control() at 1 kHz: every callback
//     runs lieservo::realtime::CartesianVelocityPipeline (watchdog → sensor-to-base twist
//     through O_T_EE and the mount → jerk-limited smoother) and returns
//     franka::CartesianVelocities; it publishes O_T_EE through a second channel for readPose().
//   No locks, allocation or I/O inside the callback.
//
// Units at this interface are the library's: poses in mm and rad, twists in mm/s and rad/s,
// in the sensor frame. libfranka's are metres; the conversion is in the pipeline.
#pragma once

#include <lieservo/groups/se3.hpp>
#include <lieservo/realtime/velocity_pipeline.hpp>
#include <lieservo/status.hpp>

#include "robot_interface.hpp"

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

namespace franka {
class Robot;
}

namespace lieservo::franka_adapter {

using robot::SE3d;
using robot::Twist;

struct FrankaAdapterOptions {
  std::string robot_ip;                 ///< FCI address of the arm's control box
  /// Sensor frame in libfranka's EE frame, X_ES (mm, rad). Measure it from the CAD of the
  /// mount: origin at the TacTip's hemisphere centre, z out of the tip. If Desk's end-effector
  /// configuration already puts EE at the tip, this is the identity.
  SE3d X_ee_s = SE3d::identity();
  /// The robot base in the work frame {w}, X_wO (mm, rad): X_ws = X_wO · O_T_EE · X_ES.
  SE3d X_w_base = SE3d::identity();

  /// Base-frame limits of the commanded EE twist (SI). Defaults are conservative, far under
  /// libfranka's documented 1.7 m/s, 13 m/s², 6500 m/s³ / 2.5 rad/s, 25 rad/s², 12500 rad/s³.
  realtime::SmootherLimits<double> limits{};
  realtime::WatchdogOptions watchdog{};

  // moveTo(): a P servo on the SE(3) error, through the same smoother.
  double move_gain = 2.0;               ///< 1/s on the body-frame log error
  double move_speed_mm_s = 30.0;        ///< cap on the commanded speed (translation)
  double move_speed_rad_s = 0.3;        ///< cap on the commanded speed (rotation)
  double move_tolerance_mm = 0.1;
  double move_tolerance_rad = 0.002;
  double move_timeout_s = 60.0;

  // libfranka set-up.
  bool enforce_realtime = true;         ///< franka::RealtimeConfig::kEnforce (needs PREEMPT_RT)
  bool libfranka_rate_limiter = true;   ///< keep libfranka's own limiter on as a safety net
  double cutoff_frequency_hz = 100.0;   ///< libfranka's low-pass on commands (its default)
  /// Collision thresholds (setCollisionBehavior): torques (Nm, 7 joints), forces (N/Nm,
  /// x y z R P Y). Moderate defaults for slow contact work; tune for your set-up.
  std::array<double, 7> lower_torque{{20, 20, 18, 18, 16, 14, 12}};
  std::array<double, 7> upper_torque{{20, 20, 18, 18, 16, 14, 12}};
  std::array<double, 6> lower_force{{20, 20, 20, 25, 25, 25}};
  std::array<double, 6> upper_force{{20, 20, 20, 25, 25, 25}};
};

/// Diagnostics readable from any thread.
struct FrankaAdapterStats {
  bool running = false;
  bool faulted = false;
  realtime::WatchdogState watchdog = realtime::WatchdogState::waiting;
  std::uint64_t callbacks = 0;
  std::uint64_t lost_cycles = 0;       ///< sum of (period − 1 ms) over callbacks, in ms
  std::uint64_t pipeline_errors = 0;   ///< callbacks that fell back to stepStopping()
};

class FrankaAdapter final : public robot::RobotInterface {
 public:
  /// Connects to the robot and applies the collision behaviour. Throws std::runtime_error
  /// (set-up only) for bad options or libfranka connection errors.
  explicit FrankaAdapter(const FrankaAdapterOptions& options);
  ~FrankaAdapter() override;
  FrankaAdapter(const FrankaAdapter&) = delete;
  FrankaAdapter& operator=(const FrankaAdapter&) = delete;

  /// X_ws from the control loop's latest O_T_EE (or robot.readOnce() when idle).
  Status readPose(SE3d& X_ws) override;

  /// Queue a sensor-frame twist (mm/s, rad/s); starts the 1 kHz loop if needed. Never blocks
  /// on the robot. dt is the caller's period (only validated). No contact information: the
  /// contact-loss stop never triggers through this overload.
  Status commandVelocity(const Twist& twist_s, double dt) override;
  /// As above with the tactile thread's contact decision (contact-loss stop, watchdog.hpp).
  Status commandVelocity(const Twist& twist_s, double dt, bool in_contact);

  /// Blocking move of the sensor frame to X_ws (stops the velocity loop first).
  Status moveTo(const SE3d& X_ws) override;

  /// Ramp to zero inside the limits, finish the libfranka motion and join the loop.
  void stop() override;

  /// Clear a latched contact-loss stop (the loop keeps running at zero velocity meanwhile).
  void rearm();
  /// After a libfranka error (reflex, collision): franka::Robot::automaticErrorRecovery().
  Status recover();

  FrankaAdapterStats stats() const;
  /// The last libfranka exception text ("" if none); calls that met one returned
  /// Status::device_error.
  std::string lastError() const;

 private:
  void startVelocityLoop();
  void velocityLoop();
  void joinLoop();
  Status sensorPoseFromState(const std::array<double, 16>& O_T_EE, SE3d& X_ws) const;

  FrankaAdapterOptions options_;
  realtime::PipelineOptions pipeline_options_;
  std::unique_ptr<franka::Robot> robot_;
  std::mutex robot_mutex_;   // serialises non-real-time uses of robot_ (control/readOnce/recovery)
  std::mutex loop_mutex_;    // start/stop of the control thread

  realtime::LatestValueChannel<realtime::TwistCommand> commands_;  // tactile → 1 kHz
  realtime::LatestValueChannel<std::array<double, 16>> poses_;     // 1 kHz → readPose
  std::mutex pose_reader_mutex_;     // readPose() may be called from several threads
  std::mutex command_writer_mutex_;  // commandVelocity() may be called from several threads

  std::thread loop_;
  std::atomic<bool> running_{false};
  std::atomic<bool> stop_requested_{false};
  std::atomic<bool> rearm_requested_{false};
  std::atomic<bool> faulted_{false};
  std::atomic<int> watchdog_state_{0};
  std::atomic<std::uint64_t> callbacks_{0}, lost_cycles_{0}, pipeline_errors_{0};
  mutable std::mutex error_mutex_;
  std::string last_error_;
};

}  // namespace lieservo::franka_adapter

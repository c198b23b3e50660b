// examples/franka/tactile_run.hpp — the robot program's tactile thread, apart from its sensor and
// its robot: the approach until contact, then lieservo::TactileLoop once a frame (the filter and
// the controller; the same class the simulated tasks step), each accepted frame's twist sent to
// the robot. franka_servo_example runs it with the camera + GDN front end and the Franka
// adapter; tests/franka runs it with recorded frames and a recording robot, against the
// simulation's commands bit for bit. Eigen and lieservo only.
#pragma once

#include <atomic>
#include <chrono>
#include <string>

#include <lieservo/control/tactile_loop.hpp>
#include <lieservo/estimation/concentrated_gaussian.hpp>
#include <lieservo/groups/se3.hpp>
#include <lieservo/realtime/watchdog.hpp>

namespace lieservo::franka_example {

/// One tactile sample: the observation Gaussian of X_sf (feature in sensor), a contact
/// decision and the capture time.
struct TactileSample {
  ConcentratedGaussian<SE3<double>> observation;
  bool in_contact = false;
  double contact_statistic = 0;
  std::chrono::steady_clock::time_point stamp;
};

/// The tactile seam: replace the front end to use a different sensor or model.
class TactileFrontEnd {
 public:
  virtual ~TactileFrontEnd() = default;
  /// Blocks for the next frame. false: the sensor is gone (camera lost / model failure).
  virtual bool next(TactileSample& out, std::string& error) = 0;
};

/// What ends a run besides the task: its duration, and the approach's speed and reach.
struct RunSettings {
  double duration_s = 60;       ///< wall-clock time from the first frame
  double approach_speed = 5;    ///< mm/s along the sensor z until contact
  double approach_max_mm = 30;  ///< give up without contact after this far
};

/// The tactile thread. The first frame sets the clock (dt is the time between frames' capture
/// stamps). Until the front end reports contact, the sensor approaches along its z; at contact
/// the loop is reset (its filter initialises from that frame); after that every frame goes
/// through `loop` under its policy: an accepted step (initialised, commanded, gated) sends the
/// twist, terminated ends the run at the target, and a refusal ends the run (the robot's
/// watchdog and ramped stop then bring the arm to rest). `Robot` provides readPose(SE3&),
/// commandVelocity(twist, dt, in_contact) → Status, stats() (`faulted`, `watchdog`) and
/// lastError(), as FrankaAdapter does. Returns what ended the run.
template <class Robot, class Loop>
std::string runTactileLoop(const RunSettings& run, Robot& robot, TactileFrontEnd& sensor, Loop& loop,
                           const std::atomic<bool>& quit) {
  using clock = std::chrono::steady_clock;
  using SE3d = SE3<double>;
  SE3d X_ws;
  if (robot.readPose(X_ws) != Status::ok) return "cannot read the robot pose: " + robot.lastError();
  const Eigen::Vector3d approach_start = X_ws.translation();
  TactileSample sample;
  std::string error;
  if (!sensor.next(sample, error)) return "tactile front end failed: " + error;
  clock::time_point last = sample.stamp;
  const clock::time_point t_end = clock::now() + std::chrono::duration_cast<clock::duration>(
                                                     std::chrono::duration<double>(run.duration_s));
  bool touched = false;
  while (!quit.load()) {
    if (!sensor.next(sample, error)) return "tactile front end failed: " + error;  // the watchdog stops the arm
    const double dt = std::chrono::duration<double>(sample.stamp - last).count();
    last = sample.stamp;
    if (clock::now() > t_end) return "duration reached";
    if (robot.readPose(X_ws) != Status::ok) return "cannot read the robot pose: " + robot.lastError();
    const auto st = robot.stats();
    if (st.faulted) return "robot fault: " + robot.lastError();
    if (st.watchdog == realtime::WatchdogState::tripped_contact_loss) return "contact lost: stopped (watchdog)";

    typename SE3d::Tangent u = SE3d::Tangent::Zero();
    if (!touched) {
      // Approach along the sensor z (out of the tip, into the surface/object) until contact.
      if (!sample.in_contact) {
        if ((X_ws.translation() - approach_start).norm() > run.approach_max_mm) return "no contact within the approach distance";
        u[2] = run.approach_speed;
        if (robot.commandVelocity(u, dt, false) != Status::ok) return "command refused: " + robot.lastError();
        continue;
      }
      touched = true;
      loop.reset();  // the filter's next step initialises from this contact
    }
    if (const Status s = loop.step(X_ws, sample.observation, dt, u); s != Status::ok)
      return std::string("tactile loop refused the frame: ") + describe(s);
    if (loop.outcome() == LoopOutcome::terminated) return "target reached";
    if (robot.commandVelocity(u, dt, sample.in_contact) != Status::ok) return "command refused: " + robot.lastError();
  }
  return "interrupted";
}

}  // namespace lieservo::franka_example

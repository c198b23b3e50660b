// examples/franka/franka_adapter.cpp — see franka_adapter.hpp and docs/hardware.md.
//
// Built against libfranka where find_package(Franka) succeeds, and everywhere against the
// libfranka test double (examples/franka/sim_double), which is how CI runs it
// (tests/franka/test_franka_adapter_sim). Everything the 1 kHz callback computes is
// lieservo::realtime::CartesianVelocityPipeline (tested on its own in tests/realtime).
#include "franka_adapter.hpp"
#include "franka_frames.hpp"

#include <franka/control_types.h>
#include <franka/duration.h>
#include <franka/exception.h>
#include <franka/robot.h>
#include <franka/robot_state.h>

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace lieservo::franka_adapter {

namespace {

using realtime::ChannelStamp;
using realtime::TwistCommand;

std::array<double, 6> toArray(const Twist& t) {
  return {t[0], t[1], t[2], t[3], t[4], t[5]};
}

constexpr double kMetresPerMm = 1e-3;  // the library's lengths (mm) → libfranka's (m)
constexpr double kMmPerMetre = 1e3;

}  // namespace

FrankaAdapter::FrankaAdapter(const FrankaAdapterOptions& options) : options_(options) {
  if (!options_.X_ee_s.allFinite() || !options_.X_w_base.allFinite())
    throw std::runtime_error("FrankaAdapter: non-finite mount or base transform");
  if (!options_.limits.within(franka_frames::documentedCartesianLimits()))
    throw std::runtime_error("FrankaAdapter: limits exceed libfranka's documented Cartesian limits");
  if (!(options_.move_gain > 0) || !(options_.move_speed_mm_s > 0) || !(options_.move_speed_rad_s > 0) ||
      !(options_.move_tolerance_mm > 0) || !(options_.move_tolerance_rad > 0) || !(options_.move_timeout_s > 0))
    throw std::runtime_error("FrankaAdapter: move_* options must be > 0");

  pipeline_options_.limits = options_.limits;
  pipeline_options_.watchdog = options_.watchdog;
  // The one mount: X_ES in libfranka's metres, as O_T_EE is (the options give it in mm).
  pipeline_options_.mount = realtime::SensorMount::fromLibraryUnits(options_.X_ee_s, kMetresPerMm);
  pipeline_options_.twist_to_metres = kMetresPerMm;
  pipeline_options_.control_period_s = 1e-3;  // libfranka's command period
  realtime::CartesianVelocityPipeline probe;
  const Status s = probe.configure(pipeline_options_);
  if (s != Status::ok) throw std::runtime_error(std::string("FrankaAdapter: bad options: ") + describe(s));

  try {
    robot_ = std::make_unique<franka::Robot>(
        options_.robot_ip, options_.enforce_realtime ? franka::RealtimeConfig::kEnforce : franka::RealtimeConfig::kIgnore);
    robot_->setCollisionBehavior(options_.lower_torque, options_.upper_torque, options_.lower_force,
                                 options_.upper_force);
  } catch (const std::exception& e) {  // franka::Exception, and std::invalid_argument (NaN commands)
    throw std::runtime_error(std::string("FrankaAdapter: cannot set up the robot at ") + options_.robot_ip + ": " +
                             e.what());
  }
}

FrankaAdapter::~FrankaAdapter() { stop(); }

Status FrankaAdapter::sensorPoseFromState(const std::array<double, 16>& O_T_EE, SE3d& X_ws) const {
  SE3d T_oe;
  const Status s = franka_frames::poseFromColumnMajor(O_T_EE, T_oe);  // the one parse
  if (s != Status::ok) return s;
  X_ws = options_.X_w_base * realtime::sensorPose(T_oe, pipeline_options_.mount, kMmPerMetre);
  return Status::ok;
}

Status FrankaAdapter::readPose(SE3d& X_ws) {
  std::array<double, 16> O_T_EE{};
  if (running_.load(std::memory_order_acquire)) {
    std::lock_guard<std::mutex> reader(pose_reader_mutex_);
    if (poses_.read(O_T_EE)) return sensorPoseFromState(O_T_EE, X_ws);
  }
  std::unique_lock<std::mutex> lock(robot_mutex_, std::try_to_lock);
  if (!lock.owns_lock()) {  // the loop is starting or stopping: wait for its first state
    std::lock_guard<std::mutex> reader(pose_reader_mutex_);
    for (int i = 0; i < 100; ++i) {
      if (poses_.read(O_T_EE)) return sensorPoseFromState(O_T_EE, X_ws);
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return Status::not_initialised;
  }
  try {
    O_T_EE = robot_->readOnce().O_T_EE;
  } catch (const std::exception& e) {  // franka::Exception, and std::invalid_argument (NaN commands)
    std::lock_guard<std::mutex> g(error_mutex_);
    last_error_ = e.what();
    return Status::device_error;
  }
  return sensorPoseFromState(O_T_EE, X_ws);
}

Status FrankaAdapter::commandVelocity(const Twist& twist_s, double dt) {
  return commandVelocity(twist_s, dt, true);
}

Status FrankaAdapter::commandVelocity(const Twist& twist_s, double dt, bool in_contact) {
  if (!(dt > 0) || !std::isfinite(dt)) return Status::invalid_time_step;
  if (!twist_s.allFinite()) return Status::non_finite_input;
  if (faulted_.load()) return Status::not_initialised;  // call recover() first
  {
    std::lock_guard<std::mutex> g(command_writer_mutex_);
    TwistCommand c;
    c.twist_s = toArray(twist_s);
    c.in_contact = in_contact;
    commands_.write(c);
  }
  if (!running_.load(std::memory_order_acquire)) startVelocityLoop();
  return Status::ok;
}

void FrankaAdapter::startVelocityLoop() {
  std::lock_guard<std::mutex> g(loop_mutex_);
  if (running_.load() || faulted_.load()) return;
  joinLoop();
  stop_requested_.store(false);
  rearm_requested_.store(false);
  running_.store(true, std::memory_order_release);
  loop_ = std::thread([this] { velocityLoop(); });
}

void FrankaAdapter::velocityLoop() {
  std::lock_guard<std::mutex> robot_lock(robot_mutex_);
  realtime::CartesianVelocityPipeline pipeline;
  (void)pipeline.configure(pipeline_options_);  // validated in the constructor
  try {
    robot_->control(
        [&](const franka::RobotState& state, franka::Duration period) -> franka::CartesianVelocities {
          // --- 1 kHz, real-time: no locks, no allocation, no I/O ---------------------------
          poses_.write(state.O_T_EE);
          std::array<double, 6> out{};
          const std::uint64_t ms = period.toMSec();
          if (ms == 0) return franka::CartesianVelocities(out);  // first call: start from rest
          if (ms > 1) lost_cycles_.fetch_add(ms - 1, std::memory_order_relaxed);
          callbacks_.fetch_add(1, std::memory_order_relaxed);
          if (rearm_requested_.exchange(false, std::memory_order_acq_rel)) pipeline.rearm();
          const bool stopping = stop_requested_.load(std::memory_order_acquire);
          if (stopping) {
            (void)pipeline.stepStopping(out);
          } else if (SE3d T_oe; franka_frames::poseFromColumnMajor(state.O_T_EE, T_oe) != Status::ok ||
                                pipeline.step(T_oe, commands_, realtime::steadyNowNs(), out) != Status::ok) {
            pipeline_errors_.fetch_add(1, std::memory_order_relaxed);
            (void)pipeline.stepStopping(out);  // latched: needs rearm()
          }
          watchdog_state_.store(static_cast<int>(pipeline.watchdog().state()), std::memory_order_relaxed);
          franka::CartesianVelocities cmd(out);
          if (stopping && pipeline.stopped()) return franka::MotionFinished(cmd);
          return cmd;
        },
        franka::ControllerMode::kJointImpedance, options_.libfranka_rate_limiter, options_.cutoff_frequency_hz);
  } catch (const std::exception& e) {  // franka::Exception, and std::invalid_argument (NaN commands)
    faulted_.store(true);
    std::lock_guard<std::mutex> g(error_mutex_);
    last_error_ = e.what();
  }
  running_.store(false, std::memory_order_release);
}

void FrankaAdapter::joinLoop() {
  if (loop_.joinable()) loop_.join();
}

void FrankaAdapter::stop() {
  std::lock_guard<std::mutex> g(loop_mutex_);
  stop_requested_.store(true, std::memory_order_release);
  joinLoop();
}

void FrankaAdapter::rearm() { rearm_requested_.store(true, std::memory_order_release); }

Status FrankaAdapter::recover() {
  stop();
  std::lock_guard<std::mutex> robot_lock(robot_mutex_);
  try {
    robot_->automaticErrorRecovery();
  } catch (const std::exception& e) {  // franka::Exception, and std::invalid_argument (NaN commands)
    std::lock_guard<std::mutex> g(error_mutex_);
    last_error_ = e.what();
    return Status::device_error;
  }
  faulted_.store(false);
  return Status::ok;
}

Status FrankaAdapter::moveTo(const SE3d& X_ws_goal) {
  if (!X_ws_goal.allFinite()) return Status::non_finite_input;
  if (faulted_.load()) return Status::not_initialised;
  stop();  // ramp down and end any velocity motion first
  std::lock_guard<std::mutex> robot_lock(robot_mutex_);

  // The goal of the sensor frame in the base frame (mm).
  const SE3d X_os_goal = options_.X_w_base.inverse() * X_ws_goal;
  realtime::PipelineOptions po = pipeline_options_;
  po.watchdog.rearm_fresh_commands = 1;
  po.watchdog.stop_on_contact_loss = false;
  realtime::CartesianVelocityPipeline pipeline;
  if (pipeline.configure(po) != Status::ok) return Status::invalid_argument;
  const double gain = options_.move_gain, vmax = options_.move_speed_mm_s, wmax = options_.move_speed_rad_s;
  const double tol_p = options_.move_tolerance_mm, tol_r = options_.move_tolerance_rad;
  const double timeout = options_.move_timeout_s;
  std::uint64_t seq = 0;
  double t = 0;
  bool reached = false, failed = false;
  running_.store(true, std::memory_order_release);
  try {
    robot_->control(
        [&](const franka::RobotState& state, franka::Duration period) -> franka::CartesianVelocities {
          poses_.write(state.O_T_EE);
          std::array<double, 6> out{};
          if (period.toMSec() == 0) return franka::CartesianVelocities(out);
          t += period.toSec();
          // Body-frame error of the sensor, e = log(X_os⁻¹ X_os_goal) (eq. 18, eqn:local_tangent_space_error).
          SE3d T_oe;
          bool ok = franka_frames::poseFromColumnMajor(state.O_T_EE, T_oe) == Status::ok;  // the one parse
          Twist e = Twist::Zero();
          if (ok) {
            const SE3d X_os = realtime::sensorPose(T_oe, po.mount, kMmPerMetre);
            e = (X_os.inverse() * X_os_goal).log();
            ok = e.allFinite();
          }
          if (!ok) failed = true;
          const bool done = ok && e.head<3>().norm() < tol_p && e.tail<3>().norm() < tol_r;
          if (done) reached = true;
          if (!ok || reached || t > timeout) {
            (void)pipeline.stepStopping(out);
            franka::CartesianVelocities cmd(out);
            return pipeline.stopped() ? franka::MotionFinished(cmd) : cmd;
          }
          // P servo, speed-capped (direction kept), through the same watchdog/frames/smoother.
          Twist u = gain * e;
          const double sv = u.head<3>().norm() > vmax ? vmax / u.head<3>().norm() : 1.0;
          const double sw = u.tail<3>().norm() > wmax ? wmax / u.tail<3>().norm() : 1.0;
          u *= std::min(sv, sw);
          TwistCommand c;
          c.twist_s = toArray(u);
          c.in_contact = true;
          const std::int64_t now = realtime::steadyNowNs();
          if (pipeline.step(T_oe, c, ChannelStamp{++seq, now}, now, out) != Status::ok) {
            failed = true;
            (void)pipeline.stepStopping(out);
          }
          return franka::CartesianVelocities(out);
        },
        franka::ControllerMode::kJointImpedance, options_.libfranka_rate_limiter, options_.cutoff_frequency_hz);
  } catch (const std::exception& e) {  // franka::Exception, and std::invalid_argument (NaN commands)
    faulted_.store(true);
    running_.store(false, std::memory_order_release);
    std::lock_guard<std::mutex> g(error_mutex_);
    last_error_ = e.what();
    return Status::device_error;
  }
  running_.store(false, std::memory_order_release);
  if (failed) return Status::numerical_failure;
  return reached ? Status::ok : Status::not_converged;
}

FrankaAdapterStats FrankaAdapter::stats() const {
  FrankaAdapterStats s;
  s.running = running_.load();
  s.faulted = faulted_.load();
  s.watchdog = static_cast<realtime::WatchdogState>(watchdog_state_.load());
  s.callbacks = callbacks_.load();
  s.lost_cycles = lost_cycles_.load();
  s.pipeline_errors = pipeline_errors_.load();
  return s;
}

std::string FrankaAdapter::lastError() const {
  std::lock_guard<std::mutex> g(error_mutex_);
  return last_error_;
}

}  // namespace lieservo::franka_adapter

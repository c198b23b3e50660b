// lieservo/realtime/velocity_pipeline.hpp — the body of a 1 kHz Cartesian velocity callback.
//
// Everything a robot adapter's real-time callback does, without the robot library, so it
// is tested in CI: (1) take the latest tactile command (a sensor-frame body twist in the
// library's units, mm/s and rad/s, plus a contact flag) with its stamp, (2) let the
// CommandWatchdog decide whether it may pass, (3) convert it to the base twist (EE-origin
// velocity and angular velocity in base coordinates) through the current EE pose T_OE and the
// sensor mount (frames.hpp), (4) smooth it with the jerk-limited VelocitySmoother IN THE BASE
// FRAME, so the limits hold on exactly the signal the robot receives, and (5) output
// base_twist = [ṗ_OE (m/s); ω_O (rad/s)], what a Cartesian-velocity interface takes.
//
// A robot adapter (examples/franka) calls step() once per callback of the robot library; a fake robot in
// tests/realtime drives it at 1 kHz from a second thread.
#pragma once
#include <lieservo/detail/options_push.hpp>

#include <lieservo/configurable.hpp>
#include <lieservo/realtime/frames.hpp>
#include <lieservo/realtime/latest_value_channel.hpp>
#include <lieservo/realtime/velocity_smoother.hpp>
#include <lieservo/realtime/watchdog.hpp>
#include <lieservo/status.hpp>

#include <array>
#include <cmath>
#include <cstdint>

namespace lieservo::realtime {

/// The message from the tactile thread to the 1 kHz thread (trivially copyable).
struct TwistCommand {
  std::array<double, 6> twist_s{};  ///< sensor body twist [v (library length unit/s); ω (rad/s)]
  bool in_contact = false;          ///< the tactile thread's contact decision for this frame
};

/// The pipeline's limits, watchdog, sensor mount, units and command period.
struct PipelineOptions {
  SmootherLimits<double> limits{};   ///< base-frame limits, SI (m, rad); must be valid
  WatchdogOptions watchdog{};  ///< when commands may pass
  SensorMount mount{};               ///< X_ES in the robot's length unit (metres: SensorMount::fromLibraryUnits)
  double twist_to_metres = 1e-3;     ///< command translation unit → m (library mm → 1e-3)
  double control_period_s = 1e-3;    ///< the robot's command period (libfranka: 1 ms)

  /// ok, or the first reason: the limits' and the watchdog's validate(), the mount's
  /// (not_orthonormal, non_finite_input), non_finite_input (a NaN or infinite scale or period),
  /// invalid_argument (a scale ≤ 0), invalid_time_step (a period the smoother refuses).
  Status validate() const noexcept {
    if (const Status s = limits.validate(); s != Status::ok) return s;
    if (const Status s = watchdog.validate(); s != Status::ok) return s;
    if (const Status s = mount.validate(); s != Status::ok) return s;
    if (!std::isfinite(twist_to_metres) || !std::isfinite(control_period_s)) return Status::non_finite_input;
    if (!(twist_to_metres > 0)) return Status::invalid_argument;
    if (!VelocitySmoother<double>::validStep(control_period_s)) return Status::invalid_time_step;
    return Status::ok;
  }
};

/// The body of a 1 kHz Cartesian velocity callback: watchdog, sensor-to-base twist,
/// jerk-limited smoothing in the base frame (the header comment gives the steps).
class CartesianVelocityPipeline : public Configurable<CartesianVelocityPipeline> {
 public:
  using Options = PipelineOptions;  ///< limits, watchdog, mount, units, period

  CartesianVelocityPipeline() noexcept { (void)configure(Options{}); }
  /// Under `options`; invalid ones are kept as configurationStatus(), which step() returns
  /// until a configure() succeeds (Configurable).
  explicit CartesianVelocityPipeline(const Options& options) noexcept { configureOnConstruction(options); }

  /// The options' whole check (PipelineOptions::validate).
  static Status validate(const Options& o) noexcept { return o.validate(); }
  /// Validate and apply options; resets the smoother (to rest) and the watchdog. Not real-time
  /// safe to call while the loop runs (call it before starting the loop). Invalid options: the
  /// Status says why and nothing changes.
  Status configure(const Options& o) noexcept { return configureChecked(o); }
  const PipelineOptions& options() const noexcept { return options_; }  ///< the options in force

  /// One control cycle. `T_OE`: the robot's current EE pose in metres, as its one parse gave it
  /// (poseFromHomogeneous, or the adapter's); `cmd`/`stamp`: the latest command from the
  /// channel (stamp.sequence == 0: none yet); `now_ns`: the same clock as the stamps. On
  /// success writes the command to `base_twist`. Errors (state and output unchanged): a
  /// non-finite pose or a non-finite twist in an accepted command (non_finite_input). On an
  /// error the caller should call stepStopping() for this cycle instead.
  Status step(const SE3<double>& T_OE, const TwistCommand& cmd, const ChannelStamp& stamp, std::int64_t now_ns,
              std::array<double, 6>& base_twist) noexcept {
    if (const Status c = configurationStatus(); c != Status::ok) return c;
    if (!T_OE.allFinite()) return Status::non_finite_input;
    const Eigen::Map<const Vector6> xi(cmd.twist_s.data());
    if (stamp.sequence != 0 && !xi.allFinite()) return Status::non_finite_input;

    // The command's age: its stamp's distance from now, in double (no signed overflow for any
    // pair of stamps). A stamp from the future is as untrustworthy as an old one: one stamped
    // further ahead than the timeout does not pass.
    const double age_s =
        stamp.sequence == 0 ? 0.0 : 1e-9 * std::abs(static_cast<double>(now_ns) - static_cast<double>(stamp.time_ns));
    const Status ws = watchdog_.step(stamp.sequence, age_s, cmd.in_contact);
    if (ws != Status::ok) return ws;

    Vector6 target = Vector6::Zero();
    if (watchdog_.passCommands()) target = sensorTwistToBase(T_OE, options_.mount, xi, options_.twist_to_metres);
    return advance(target, base_twist);
  }

  /// Convenience: read the newest command from `channel` and step().
  Status step(const SE3<double>& T_OE, LatestValueChannel<TwistCommand>& channel, std::int64_t now_ns,
              std::array<double, 6>& base_twist) noexcept {
    TwistCommand cmd;
    ChannelStamp stamp;
    if (!channel.read(cmd, stamp)) stamp = ChannelStamp{};
    return step(T_OE, cmd, stamp, now_ns, base_twist);
  }

  /// A cycle that needs no pose: trips the watchdog (external) and ramps towards zero.
  /// Use on any error, or to stop. Always ok.
  Status stepStopping(std::array<double, 6>& base_twist) noexcept {
    watchdog_.trip();
    return advance(Vector6::Zero(), base_twist);
  }

  /// Request a stop (latched until rearm()); subsequent step()s ramp to zero.
  void requestStop() noexcept { watchdog_.trip(); }
  /// Clear a latched stop / contact loss; commands pass again after fresh ones arrive.
  void rearm() noexcept { watchdog_.rearm(); }

  /// Commands are not passing and the commanded velocity is exactly zero.
  bool stopped() const noexcept { return !watchdog_.passCommands() && smoother_.atRest(); }

  /// Re-synchronise with the robot's last commanded velocity/acceleration (e.g. after an
  /// error recovery the robot restarts from rest: pass zeros). Checked like
  /// VelocitySmoother::reset(v, a).
  Status resync(const Vector6& velocity, const Vector6& acceleration) noexcept {
    return smoother_.reset(velocity, acceleration);
  }

  const VelocitySmoother<double>& smoother() const noexcept { return smoother_; }  ///< the base-frame smoother
  const CommandWatchdog& watchdog() const noexcept { return watchdog_; }  ///< the command watchdog

 private:
  friend class Configurable<CartesianVelocityPipeline>;
  Status apply(const Options& o) noexcept {  // validated (Configurable)
    options_ = o;
    (void)smoother_.configure(o.limits);  // validated with o
    smoother_.reset();
    (void)watchdog_.configure(o.watchdog);  // validated with o
    return Status::ok;
  }

  Status advance(const Vector6& target, std::array<double, 6>& out) noexcept {
    const Status s = smoother_.step(target, options_.control_period_s);
    if (s != Status::ok) return s;
    Eigen::Map<Vector6>(out.data()) = smoother_.velocity();
    return Status::ok;
  }

  PipelineOptions options_{};
  VelocitySmoother<double> smoother_{};
  CommandWatchdog watchdog_{};
};

}  // namespace lieservo::realtime

#include <lieservo/detail/options_pop.hpp>

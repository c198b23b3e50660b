// lieservo/realtime/watchdog.hpp — command/contact watchdog for the 1 kHz loop.
//
// The watchdog decides, every control cycle, whether the latest tactile command may be
// passed on. When it may not, the caller feeds a zero target to the VelocitySmoother,
// which ramps the commanded twist to zero inside its jerk/acceleration limits; the ramp
// lasts at most VelocitySmoother::stoppingTimeBound() (≈ |v|/A + A/J + |a|/J; with the
// default Franka limits and 25 mm/s: 0.1 s + 0.01 s).
//
// Policy (WatchdogOptions):
//   * waiting      — start-up and after rearm(): commands are held back until
//                    `rearm_fresh_commands` consecutive fresh commands have arrived
//                    (fresh = a new sequence number whose age <= command_timeout_s).
//   * active       — commands pass. Trips to:
//       - tripped_timeout      if the latest command is older than command_timeout_s
//                              (tactile thread stalled, camera dropped, model too slow);
//                              re-arms by itself after `rearm_fresh_commands`
//                              consecutive fresh commands (the tactile loop is back).
//       - tripped_contact_loss if stop_on_contact_loss and a command reports no contact
//                              after one that reported contact (since the last arming).
//                              If latch_contact_loss (default) it stays tripped until the
//                              application calls rearm(); otherwise it re-arms like a
//                              timeout, but only on commands that report contact again.
//       - tripped_external     after trip() (stop request, fault); only rearm() clears it.
//   Contact is not required before the first contact (approach moves are allowed).
//
// Real-time contract: step() is noexcept, allocation-free, returns Status and leaves
// the state unchanged on bad input.
#pragma once
#include <lieservo/detail/options_push.hpp>

#include <lieservo/configurable.hpp>
#include <lieservo/status.hpp>

#include <cmath>
#include <cstdint>

namespace lieservo::realtime {

/// The watchdog's timeout, re-arming and contact-loss policy.
struct WatchdogOptions {
  double command_timeout_s = 0.2;   ///< max age of the latest command (camera ~30 Hz: ~6 frames)
  int rearm_fresh_commands = 3;     ///< consecutive fresh commands needed to (re)arm, >= 1
  bool stop_on_contact_loss = true;  ///< stop when a command reports lost contact (after a first contact)
  bool latch_contact_loss = true;   ///< contact-loss stop needs rearm()

  /// ok, non_finite_input (a NaN or infinite timeout) or invalid_argument (a timeout ≤ 0,
  /// fewer than one fresh command to rearm).
  Status validate() const noexcept {
    if (!std::isfinite(command_timeout_s)) return Status::non_finite_input;
    if (!(command_timeout_s > 0) || rearm_fresh_commands < 1) return Status::invalid_argument;
    return Status::ok;
  }
};

/// Where the watchdog is (the header comment gives the transitions).
enum class WatchdogState : int {
  waiting = 0,
  active,
  tripped_timeout,
  tripped_contact_loss,
  tripped_external,
};

/// A short phrase for a state, for logs and messages.
constexpr const char* describe(WatchdogState s) noexcept {
  switch (s) {
    case WatchdogState::waiting: return "waiting for fresh commands";
    case WatchdogState::active: return "active";
    case WatchdogState::tripped_timeout: return "stopped: command timeout";
    case WatchdogState::tripped_contact_loss: return "stopped: contact lost";
    case WatchdogState::tripped_external: return "stopped: stop requested";
  }
  return "unknown";
}

/// Decides every control cycle whether the latest tactile command may pass (the header
/// comment gives the states and the policy).
class CommandWatchdog : public Configurable<CommandWatchdog> {
 public:
  using Options = WatchdogOptions;  ///< when commands may pass

  CommandWatchdog() noexcept = default;
  /// `waiting` under `options`; invalid ones are kept as configurationStatus(), which step()
  /// returns until a configure() succeeds (Configurable).
  explicit CommandWatchdog(const Options& options) noexcept { configureOnConstruction(options); }

  /// The options' own check (WatchdogOptions::validate).
  static Status validate(const Options& options) noexcept { return options.validate(); }
  /// Invalid options → validate()'s Status (unchanged). Resets to `waiting`.
  Status configure(const Options& options) noexcept { return configureChecked(options); }
  const WatchdogOptions& options() const noexcept { return options_; }  ///< the options in force

  /// One control cycle. `sequence`: the latest command's sequence number (0 = none yet);
  /// `age_s`: its age in seconds (>= 0, ignored when sequence == 0); `in_contact`: the
  /// contact flag it carried. Non-finite age → non_finite_input; negative age →
  /// invalid_argument; state unchanged in both cases.
  Status step(std::uint64_t sequence, double age_s, bool in_contact) noexcept {
    if (const Status c = configurationStatus(); c != Status::ok) return c;
    if (sequence != 0) {
      if (!std::isfinite(age_s)) return Status::non_finite_input;
      if (age_s < 0) return Status::invalid_argument;
    }
    const bool have = sequence != 0;
    const bool timely = have && age_s <= options_.command_timeout_s;
    const bool is_new = have && sequence != last_sequence_;
    last_sequence_ = sequence;

    switch (state_) {
      case WatchdogState::active:
        if (!timely) {
          enterTripped(WatchdogState::tripped_timeout);
        } else if (options_.stop_on_contact_loss && contact_seen_ && !in_contact) {
          enterTripped(WatchdogState::tripped_contact_loss);
        } else if (in_contact) {
          contact_seen_ = true;
        }
        break;
      case WatchdogState::waiting:
      case WatchdogState::tripped_timeout:
        countFresh(timely, is_new, true);
        if (state_ == WatchdogState::active && in_contact) contact_seen_ = true;
        break;
      case WatchdogState::tripped_contact_loss:
        if (!options_.latch_contact_loss) countFresh(timely, is_new, in_contact);
        break;
      case WatchdogState::tripped_external:
        break;
    }
    return Status::ok;
  }

  /// True when the latest command may be passed to the robot.
  bool passCommands() const noexcept { return state_ == WatchdogState::active; }
  WatchdogState state() const noexcept { return state_; }  ///< the current state

  /// Stop request / fault: stop passing commands until rearm().
  void trip() noexcept { enterTripped(WatchdogState::tripped_external); }

  /// Clear every trip (and the contact history) and wait for fresh commands again.
  void rearm() noexcept {
    state_ = WatchdogState::waiting;
    fresh_count_ = 0;
    contact_seen_ = false;
  }

  /// Trips since configure() (for logging).
  std::uint64_t tripCount() const noexcept { return trips_; }

 private:
  friend class Configurable<CommandWatchdog>;
  Status apply(const Options& options) noexcept {  // validated (Configurable)
    options_ = options;
    rearm();
    return Status::ok;
  }
  void enterTripped(WatchdogState s) noexcept {
    if (state_ != s) ++trips_;
    state_ = s;
    fresh_count_ = 0;
  }

  // Count consecutive fresh commands (new and timely, and `ok`); a stale cycle resets it.
  void countFresh(bool timely, bool is_new, bool ok) noexcept {
    if (!timely || !ok) {
      fresh_count_ = 0;
      return;
    }
    if (is_new && ++fresh_count_ >= options_.rearm_fresh_commands) {
      state_ = WatchdogState::active;
      fresh_count_ = 0;
    }
  }

  WatchdogOptions options_{};
  WatchdogState state_ = WatchdogState::waiting;
  std::uint64_t last_sequence_ = 0;
  int fresh_count_ = 0;
  bool contact_seen_ = false;
  std::uint64_t trips_ = 0;
};

}  // namespace lieservo::realtime

#include <lieservo/detail/options_pop.hpp>

// Command watchdog: arming, timeout, contact loss (latched and not), external stop, and the
// ramp-down through the smoother.
#include <catch2/catch.hpp>

#include "limit_checker.hpp"

#include <lieservo/realtime/velocity_smoother.hpp>
#include <lieservo/realtime/watchdog.hpp>

#include <limits>

using lieservo::Status;
using namespace lieservo::realtime;

namespace {

struct Feed {
  CommandWatchdog& w;
  std::uint64_t seq = 0;
  // A new command (fresh sequence) with the given age and contact flag; the cycle must be accepted.
  void fresh(double age, bool contact) { REQUIRE(w.step(++seq, age, contact) == Status::ok); }
  // The same command seen again (no new sequence) at a later age.
  void again(double age, bool contact) { REQUIRE(w.step(seq, age, contact) == Status::ok); }
};

}  // namespace

TEST_CASE("watchdog: arms after N fresh commands, trips on timeout, re-arms by itself", "[realtime][watchdog]") {
  CommandWatchdog w;
  WatchdogOptions o;
  o.command_timeout_s = 0.1;
  o.rearm_fresh_commands = 3;
  REQUIRE(w.configure(o) == Status::ok);
  Feed f{w};
  CHECK(w.state() == WatchdogState::waiting);
  CHECK(w.step(0, 0.0, false) == Status::ok);  // nothing written yet
  CHECK_FALSE(w.passCommands());
  f.fresh(0.01, false);
  f.again(0.02, false);  // repeats do not count
  f.fresh(0.01, false);
  CHECK_FALSE(w.passCommands());
  f.fresh(0.01, false);
  CHECK(w.passCommands());

  // Stale: the same command ages past the timeout.
  f.again(0.05, false);
  CHECK(w.passCommands());
  f.again(0.1000001, false);
  CHECK(w.state() == WatchdogState::tripped_timeout);
  CHECK_FALSE(w.passCommands());
  // Two fresh, then a stale gap resets the count; then three fresh re-arm.
  f.fresh(0.01, false);
  f.fresh(0.01, false);
  f.again(0.5, false);
  f.fresh(0.01, false);
  CHECK_FALSE(w.passCommands());
  f.fresh(0.01, false);
  f.fresh(0.01, false);
  CHECK(w.passCommands());
  CHECK(w.tripCount() == 1);
}

TEST_CASE("watchdog: contact loss stops, latched until rearm()", "[realtime][watchdog]") {
  CommandWatchdog w;
  WatchdogOptions o;
  o.rearm_fresh_commands = 1;
  REQUIRE(w.configure(o) == Status::ok);
  Feed f{w};
  f.fresh(0.0, false);  // approach without contact is allowed
  CHECK(w.passCommands());
  f.fresh(0.0, false);
  CHECK(w.passCommands());
  f.fresh(0.0, true);  // touch
  CHECK(w.passCommands());
  f.fresh(0.0, false);  // lose it
  CHECK(w.state() == WatchdogState::tripped_contact_loss);
  for (int i = 0; i < 10; ++i) f.fresh(0.0, true);
  CHECK(w.state() == WatchdogState::tripped_contact_loss);  // latched
  w.rearm();
  CHECK(w.state() == WatchdogState::waiting);
  f.fresh(0.0, false);
  CHECK(w.passCommands());  // contact history cleared: approach again
}

TEST_CASE("watchdog: unlatched contact loss re-arms only on commands in contact", "[realtime][watchdog]") {
  CommandWatchdog w;
  WatchdogOptions o;
  o.rearm_fresh_commands = 2;
  o.latch_contact_loss = false;
  REQUIRE(w.configure(o) == Status::ok);
  Feed f{w};
  f.fresh(0.0, true);
  f.fresh(0.0, true);
  REQUIRE(w.passCommands());
  f.fresh(0.0, false);
  CHECK(w.state() == WatchdogState::tripped_contact_loss);
  f.fresh(0.0, false);
  f.fresh(0.0, false);
  CHECK_FALSE(w.passCommands());
  f.fresh(0.0, true);
  CHECK_FALSE(w.passCommands());
  f.fresh(0.0, true);
  CHECK(w.passCommands());
}

TEST_CASE("watchdog: contact-loss stop can be disabled, external trip needs rearm", "[realtime][watchdog]") {
  CommandWatchdog w;
  WatchdogOptions o;
  o.rearm_fresh_commands = 1;
  o.stop_on_contact_loss = false;
  REQUIRE(w.configure(o) == Status::ok);
  Feed f{w};
  f.fresh(0.0, true);
  f.fresh(0.0, false);
  CHECK(w.passCommands());
  w.trip();
  CHECK(w.state() == WatchdogState::tripped_external);
  for (int i = 0; i < 5; ++i) f.fresh(0.0, true);
  CHECK_FALSE(w.passCommands());
  w.rearm();
  f.fresh(0.0, true);
  CHECK(w.passCommands());
}

TEST_CASE("watchdog: bad input and options leave the state unchanged", "[realtime][watchdog]") {
  CommandWatchdog w;
  WatchdogOptions o;
  o.rearm_fresh_commands = 1;
  REQUIRE(w.configure(o) == Status::ok);
  CHECK(w.step(1, std::numeric_limits<double>::quiet_NaN(), true) == Status::non_finite_input);
  CHECK(w.step(1, -0.5, true) == Status::invalid_argument);
  CHECK(w.state() == WatchdogState::waiting);
  CHECK(w.step(1, 0.0, true) == Status::ok);  // sequence 1 still counts as new
  CHECK(w.passCommands());

  WatchdogOptions bad = o;
  bad.command_timeout_s = 0;
  CHECK(w.configure(bad) == Status::invalid_argument);
  bad = o;
  bad.rearm_fresh_commands = 0;
  CHECK(w.configure(bad) == Status::invalid_argument);
  CHECK(w.passCommands());  // untouched
  CHECK(w.options().rearm_fresh_commands == 1);
}

TEST_CASE("watchdog: a trip ramps the smoothed command to zero within the documented time", "[realtime][watchdog]") {
  // The 1 kHz loop: target = command if passCommands() else 0, through the smoother.
  CommandWatchdog w;
  WatchdogOptions o;
  o.command_timeout_s = 0.1;
  o.rearm_fresh_commands = 1;
  REQUIRE(w.configure(o) == Status::ok);
  VelocitySmoother<double> s;
  rt_test::LimitChecker check{s.limits(), 1e-3};
  rt_test::Twist cmd;
  cmd << 0.2, -0.1, 0.05, 0.3, 0.0, -0.5;
  const double dt = 1e-3;
  std::uint64_t seq = 0;
  double last_write = 0, t = 0;
  // Commands at 25 Hz for 1 s, then the tactile thread stalls.
  int k = 0;
  for (; k < 1000; ++k, t += dt) {
    if (t - last_write >= 0.04 || seq == 0) {
      ++seq;
      last_write = t;
    }
    REQUIRE(w.step(seq, t - last_write, true) == Status::ok);
    REQUIRE(s.step(w.passCommands() ? cmd : rt_test::Twist::Zero(), dt) == Status::ok);
    check.push(s.velocity());
  }
  REQUIRE(w.passCommands());
  REQUIRE((s.velocity() - cmd).norm() < 1e-12);
  const double bound = s.stoppingTimeBound(dt);
  double trip_time = -1, rest_time = -1;
  for (; k < 3000; ++k, t += dt) {
    REQUIRE(w.step(seq, t - last_write, true) == Status::ok);
    if (!w.passCommands() && trip_time < 0) trip_time = t;
    REQUIRE(s.step(w.passCommands() ? cmd : rt_test::Twist::Zero(), dt) == Status::ok);
    check.push(s.velocity());
    if (trip_time >= 0 && s.atRest() && rest_time < 0) rest_time = t;
  }
  CHECK(w.state() == WatchdogState::tripped_timeout);
  CHECK(trip_time - last_write == Approx(0.1).margin(1.5e-3));
  REQUIRE(rest_time > 0);
  CHECK(rest_time - trip_time <= bound);
  CHECK(check.worst_norm <= 1 + 1e-9);
}

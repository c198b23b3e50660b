// Jerk-limited velocity smoother: limits on every step, no overshoot, bounded settling,
// reversing targets, bad input.
#include <catch2/catch.hpp>

#include "limit_checker.hpp"
#include "test_support.hpp"

#include <lieservo/realtime/velocity_smoother.hpp>
#include <lieservo/sampling/random.hpp>

#include <cmath>
#include <limits>

using lieservo::sampling::uniform;
using lieservo::Status;
using lieservo::realtime::AxisLimits;
using lieservo::realtime::SmootherLimits;
using lieservo::realtime::VelocitySmoother;
using rt_test::clampedTarget;
using rt_test::LimitChecker;
using rt_test::Twist;

namespace {

constexpr double kDt = 1e-3;
constexpr double kTol = 1e-9;  // relative rounding allowance on the finite differences

SmootherLimits<double> limitSet(int which) {
  switch (which) {
    case 0: return SmootherLimits<double>{};                    // lieservo's Franka defaults
    case 1: {                                                   // fast, m-scale limits
      SmootherLimits<double> l;
      l.translation = {1.7, 13.0, 6500.0};
      l.rotation = {2.5, 25.0, 12500.0};
      return l;
    }
    default: {                                                  // slow, mm-scale limits
      SmootherLimits<double> l;
      l.translation = {25.0, 100.0, 2000.0};
      l.rotation = {0.3, 1.0, 30.0};
      return l;
    }
  }
}

Twist randomTwist(lieservo::sampling::Rng& rng, const SmootherLimits<double>& l, double scale) {
  Twist t;
  for (int i = 0; i < 6; ++i) t[i] = scale * uniform(rng, -1.0, 1.0) * (i < 3 ? l.translation.velocity : l.rotation.velocity);
  return t;
}

// One step; FAILs (without counting an assertion per step) unless ok.
void stepOrFail(VelocitySmoother<double>& s, const Twist& target, double dt) {
  if (s.step(target, dt) != Status::ok) FAIL("smoother step failed");
}

// Steps until the velocity equals the target exactly and the acceleration is zero; -1 if not
// within max_steps.
int stepsToSettle(VelocitySmoother<double>& s, const Twist& target, int max_steps, LimitChecker* check = nullptr) {
  for (int k = 1; k <= max_steps; ++k) {
    stepOrFail(s, target, kDt);
    if (check) check->push(s.velocity());
    // Landed: on the target (exactly, up to the rounding of the smoother's own velocity
    // clamp of the target) and with exactly zero acceleration.
    if ((s.velocity() - target).norm() <= 1e-15 * (1.0 + target.norm()) && s.acceleration().isZero(0)) return k;
  }
  return -1;
}

}  // namespace

TEST_CASE("smoother: within() compares every limit", "[realtime][smoother]") {
  const SmootherLimits<double> d{};
  CHECK(d.validate() == Status::ok);
  CHECK(d.within(d));
  CHECK(d.within(limitSet(1)));
  CHECK_FALSE(limitSet(1).within(d));
  for (int k = 0; k < 6; ++k) {  // one limit above the outer one's is enough to fail
    SmootherLimits<double> l = d;
    AxisLimits<double>& a = k < 3 ? l.translation : l.rotation;
    (k % 3 == 0 ? a.velocity : k % 3 == 1 ? a.acceleration : a.jerk) *= 1.01;
    CHECK_FALSE(l.within(d));
  }
}

TEST_CASE("smoother: seeded random targets never exceed velocity, acceleration or jerk", "[realtime][smoother]") {
  for (int which = 0; which < 3; ++which) {
    const auto L = limitSet(which);
    VelocitySmoother<double> s;
    REQUIRE(s.configure(L) == Status::ok);
    LimitChecker check{L, kDt};
    lieservo::sampling::Rng rng(1234u + static_cast<unsigned>(which));
    const long segments = lieservo::test::scaledCount(600, 60);
    for (long seg = 0; seg < segments; ++seg) {
      // Targets up to 3x the velocity limit (clamped inside), held 1..400 steps; every
      // 5th segment a full reversal of the current velocity.
      Twist target = seg % 5 == 4 ? Twist(-3.0 * s.velocity()) : randomTwist(rng, L, seg % 3 == 0 ? 3.0 : 1.0);
      const int hold = 1 + static_cast<int>(rng() % 400);
      for (int k = 0; k < hold; ++k) {
        stepOrFail(s, target, kDt);
        check.push(s.velocity());
      }
    }
    INFO("limit set " << which);
    CHECK(check.worst_norm <= 1.0 + kTol);
    CHECK(check.worst_axis <= 1.0 + kTol);   // per-axis (libfranka-style) follows from the norms
    CHECK(check.worst_norm >= 1.0 - 1e-6);   // and the limits are actually used
  }
}

TEST_CASE("smoother: step from rest is time-optimal in 1-D and never overshoots", "[realtime][smoother]") {
  const auto L = limitSet(0);
  VelocitySmoother<double> s;
  REQUIRE(s.configure(L) == Status::ok);
  const double V = L.translation.velocity, A = L.translation.acceleration, J = L.translation.jerk;
  for (double frac : {0.001, 0.01, 0.1, 0.5, 1.0}) {
    s.reset();
    Twist target = Twist::Zero();
    target[1] = frac * V;
    LimitChecker check{L, kDt};
    double peak = 0;
    int k = 0;
    for (; k < 5000; ++k) {
      stepOrFail(s, target, kDt);
      check.push(s.velocity());
      peak = std::max(peak, s.velocity()[1]);
      REQUIRE(s.velocity()[0] == 0.0);
      REQUIRE(s.velocity()[2] == 0.0);
      if (s.velocity()[1] == target[1] && s.acceleration()[1] == 0.0) break;
    }
    const double dv = target[1];
    // Continuous-time optimum: dv/A + A/J if the acceleration limit is reached, else 2√(dv/J).
    const double t_opt = dv >= A * A / J ? dv / A + A / J : 2.0 * std::sqrt(dv / J);
    INFO("fraction " << frac << " steps " << k);
    CHECK(k < 5000);
    CHECK(peak <= target[1] * (1 + 1e-12));  // no overshoot
    CHECK((k + 1) * kDt <= t_opt + 3 * kDt);  // within 3 steps of the optimum
    CHECK((k + 1) * kDt >= t_opt - 3 * kDt);
    CHECK(check.worst_norm <= 1 + kTol);
  }
}

TEST_CASE("smoother: vector step from rest goes straight, without overshoot", "[realtime][smoother]") {
  const auto L = limitSet(0);
  lieservo::sampling::Rng rng(99);
  VelocitySmoother<double> s;
  REQUIRE(s.configure(L) == Status::ok);
  const long trials = lieservo::test::scaledCount(100, 10);
  for (long trial = 0; trial < trials; ++trial) {
    s.reset();
    const Twist target = clampedTarget(randomTwist(rng, L, 1.0), L);
    LimitChecker check{L, kDt};
    double overshoot = 0, off_line = 0;
    for (int k = 0; k < 2000; ++k) {
      stepOrFail(s, target, kDt);
      check.push(s.velocity());
      for (int part = 0; part < 2; ++part) {
        const Eigen::Vector3d w = target.segment<3>(3 * part), v = s.velocity().segment<3>(3 * part);
        const double along = v.dot(w) / w.norm();
        overshoot = std::max(overshoot, along / w.norm() - 1);
        off_line = std::max(off_line, (v - along * w / w.norm()).norm() / w.norm());
      }
    }
    CHECK(overshoot <= 1e-12);  // no overshoot
    CHECK(off_line <= 1e-12);   // on the straight line
    CHECK((s.velocity() - target).norm() <= 1e-12);
    CHECK(check.worst_norm <= 1 + kTol);
  }
}

TEST_CASE("smoother: a huge target is clamped along its direction, not lost to an overflowing norm",
          "[realtime][smoother]") {
  // Targets whose norm overflows a double (1e200, 1e308 in two components): the smoother moves
  // towards the velocity limit along the target's direction, as for any target beyond it.
  const auto L = limitSet(0);
  for (const Eigen::Vector3d& dir : {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(1, 1, 0), Eigen::Vector3d(-1, 2, -3)}) {
    for (const double scale : {1e200, 1e308 / 3}) {
      VelocitySmoother<double> s;
      REQUIRE(s.configure(L) == Status::ok);
      Twist target = Twist::Zero();
      target.head<3>() = scale * dir;
      target.tail<3>() = scale * dir.reverse();
      LimitChecker check{L, kDt};
      for (int k = 0; k < 3000; ++k) {
        stepOrFail(s, target, kDt);
        check.push(s.velocity());
      }
      for (int part = 0; part < 2; ++part) {
        const Eigen::Vector3d u = (part == 0 ? dir : Eigen::Vector3d(dir.reverse())).normalized();
        const Eigen::Vector3d v = s.velocity().segment<3>(3 * part);
        const double V = part == 0 ? L.translation.velocity : L.rotation.velocity;
        INFO("scale " << scale << ", part " << part << ": velocity " << v.transpose());
        CHECK((v - V * u).norm() <= 1e-12 * V);  // at the limit, along the target
      }
      CHECK(check.worst_norm <= 1 + kTol);
    }
  }
}

TEST_CASE("smoother: reversing targets brake first, stay inside the limits and settle", "[realtime][smoother]") {
  for (int which = 0; which < 3; ++which) {
    const auto L = limitSet(which);
    VelocitySmoother<double> s;
    REQUIRE(s.configure(L) == Status::ok);
    LimitChecker check{L, kDt};
    Twist plus = Twist::Zero();
    plus[0] = L.translation.velocity;
    plus[5] = L.rotation.velocity;
    // Reverse at full speed, mid-acceleration and after settling.
    for (int hold : {3000, 40, 7, 1, 3000}) {
      for (int k = 0; k < hold; ++k) {
        stepOrFail(s, plus, kDt);
        check.push(s.velocity());
      }
      plus = -plus;
    }
    const int n = stepsToSettle(s, plus, 20000, &check);
    INFO("limit set " << which);
    CHECK(n > 0);
    CHECK(check.worst_norm <= 1 + kTol);
    CHECK(check.worst_axis <= 1 + kTol);
  }
}

TEST_CASE("smoother: settles within its bound from random moving states", "[realtime][smoother]") {
  for (int which = 0; which < 3; ++which) {
    const auto L = limitSet(which);
    VelocitySmoother<double> s;
    REQUIRE(s.configure(L) == Status::ok);
    lieservo::sampling::Rng rng(2024u + static_cast<unsigned>(which));
    LimitChecker check{L, kDt};
    const long trials = lieservo::test::scaledCount(300, 30);
    for (long trial = 0; trial < trials; ++trial) {
      const Twist t0 = randomTwist(rng, L, 1.0);
      const int pre = static_cast<int>(rng() % 200);
      for (int k = 0; k < pre; ++k) {
        stepOrFail(s, t0, kDt);
        check.push(s.velocity());
      }
      // Stopping: bounded by stoppingTimeBound().
      VelocitySmoother<double> stopper = s;
      LimitChecker stop_check = check;
      const double bound = stopper.stoppingTimeBound(kDt);
      const int n_stop = stepsToSettle(stopper, Twist::Zero(), 100000, &stop_check);
      CHECK(n_stop > 0);
      CHECK(n_stop * kDt <= bound);
      CHECK(stopper.atRest());
      CHECK(stop_check.worst_norm <= 1 + kTol);
      // A new random target: reached (exactly) in bounded time.
      const Twist target = clampedTarget(randomTwist(rng, L, 1.0), L);
      const int n = stepsToSettle(s, target, 100000, &check);
      CHECK(n > 0);
      const double t_max = L.translation.velocity * 2 / L.translation.acceleration +
                           L.rotation.velocity * 2 / L.rotation.acceleration +
                           4 * (L.translation.acceleration / L.translation.jerk + L.rotation.acceleration / L.rotation.jerk);
      CHECK(n * kDt <= t_max);
    }
    CHECK(check.worst_norm <= 1 + kTol);
  }
}

TEST_CASE("smoother: variable dt keeps acceleration and jerk exact, velocity within 1%", "[realtime][smoother]") {
  const auto L = limitSet(0);
  VelocitySmoother<double> s;
  REQUIRE(s.configure(L) == Status::ok);
  lieservo::sampling::Rng rng(5);
  Twist v_prev = Twist::Zero(), a_prev = Twist::Zero();
  double worst = 0, worst_v = 0;
  const long segments = lieservo::test::scaledCount(200, 20);
  for (long seg = 0; seg < segments; ++seg) {
    const Twist target = randomTwist(rng, L, 1.5);
    for (int k = 0; k < 100; ++k) {
      const double dt = uniform(rng, 0.5e-3, 3e-3);
      stepOrFail(s, target, dt);
      const Twist v = s.velocity(), a = (v - v_prev) / dt, j = (a - a_prev) / dt;
      worst = std::max({worst, a.head<3>().norm() / L.translation.acceleration, j.head<3>().norm() / L.translation.jerk,
                        a.tail<3>().norm() / L.rotation.acceleration, j.tail<3>().norm() / L.rotation.jerk});
      worst_v = std::max({worst_v, v.head<3>().norm() / L.translation.velocity, v.tail<3>().norm() / L.rotation.velocity});
      v_prev = v;
      a_prev = a;
    }
  }
  CHECK(worst <= 1 + 1e-8);    // acceleration and jerk: exact
  CHECK(worst_v <= 1.01);       // velocity: approximate when dt varies (documented)
}

TEST_CASE("smoother: bad input returns a Status and leaves the state unchanged", "[realtime][smoother]") {
  VelocitySmoother<double> s;
  Twist target = Twist::Constant(0.05);
  for (int k = 0; k < 20; ++k) stepOrFail(s, target, kDt);
  const Twist v0 = s.velocity(), a0 = s.acceleration();
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();

  // Outside [1e-6, 1] s too: a period whose products with the limits could overflow.
  for (double dt : {0.0, -1e-3, nan, inf, -inf, 1e-7, 2.0, 1e300}) {
    Twist out = Twist::Constant(7.0);
    CHECK(s.step(target, dt) == Status::invalid_time_step);
    CHECK(s.step(target, dt, out) == Status::invalid_time_step);
    CHECK(out == Twist::Constant(7.0));
  }
  Twist bad = target;
  bad[4] = nan;
  CHECK(s.step(bad, kDt) == Status::non_finite_input);
  bad[4] = inf;
  CHECK(s.step(bad, kDt) == Status::non_finite_input);
  CHECK(s.velocity() == v0);
  CHECK(s.acceleration() == a0);

  SmootherLimits<double> l{};
  const SmootherLimits<double> before = s.limits();
  l.translation.jerk = 0;
  CHECK(s.configure(l) == Status::invalid_argument);
  l = SmootherLimits<double>{};
  l.rotation.velocity = nan;
  CHECK(s.configure(l) == Status::non_finite_input);
  l = SmootherLimits<double>{};
  l.rotation.acceleration = -1;
  CHECK(s.configure(l) == Status::invalid_argument);
  // Beyond [1e-9, 1e9], or an acceleration ramp A/J over 1000 s (limits and periods near
  // 1.8e308 would turn the output into NaN).
  for (const double x : {1e10, std::numeric_limits<double>::max(), 1e-10}) {
    l = SmootherLimits<double>{};
    l.translation.velocity = x;
    CHECK(s.configure(l) == Status::invalid_argument);
  }
  l = SmootherLimits<double>{};
  l.translation.jerk = std::numeric_limits<double>::infinity();
  CHECK(s.configure(l) == Status::non_finite_input);
  l = SmootherLimits<double>{};
  l.rotation.acceleration = 1e4, l.rotation.jerk = 1;
  CHECK(s.configure(l) == Status::invalid_argument);
  l.rotation.jerk = 10;  // a ramp of 1000 s: the bound itself
  CHECK(s.configure(l) == Status::ok);
  CHECK(s.configure(before) == Status::ok);
  CHECK(s.limits().translation.jerk == before.translation.jerk);

  Twist too_fast = Twist::Zero();
  too_fast[0] = 2 * s.limits().translation.velocity;
  CHECK(s.reset(too_fast, Twist::Zero()) == Status::invalid_argument);
  // At the velocity limit and still accelerating outwards: braking would exceed it.
  Twist at_limit = Twist::Zero(), accel = Twist::Zero();
  at_limit[0] = s.limits().translation.velocity;
  accel[0] = s.limits().translation.acceleration;
  CHECK(s.reset(at_limit, accel) == Status::invalid_argument);
  bad = Twist::Zero();
  bad[2] = nan;
  CHECK(s.reset(bad, Twist::Zero()) == Status::non_finite_input);
  CHECK(s.velocity() == v0);
  CHECK(s.acceleration() == a0);

  // A valid resync is accepted and continues within the limits.
  Twist v1 = Twist::Zero();
  v1[1] = 0.1;
  CHECK(s.reset(v1, Twist::Zero()) == Status::ok);
  CHECK(s.velocity() == v1);
  s.reset();
  CHECK(s.atRest());
}

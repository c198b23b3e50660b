// MimoPid / SisoPid (eq. 19, eqn:ff_fb_pid_control): each term against hand-computed values with a
// variable time step, clipping, invalid input handling, and the per-step gain conversion.
#include <catch2/catch.hpp>

#include "control_test_util.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <lieservo/control/pid.hpp>

using lieservo::MimoPid;
using lieservo::SisoPid;
using lieservo::Status;
using Pid2 = MimoPid<double, 2>;
using V2 = Pid2::Vector;
using Approx = Catch::Detail::Approx;

namespace {
using lieservo::test::kInf;
const double kNaN = std::numeric_limits<double>::quiet_NaN();
}  // namespace

TEST_CASE("pid: proportional term alone", "[control][pid]") {
  Pid2 pid(Pid2::Options::diagonal(V2(2, 3), V2::Zero(), V2::Zero()));
  V2 u = V2::Zero();
  const double dts[] = {0.1, 0.02, 0.5};
  const V2 errors[] = {V2(1, -2), V2(0.5, 4), V2(-3, 0)};
  for (int k = 0; k < 3; ++k) {
    REQUIRE(pid.step(errors[k], V2::Zero(), dts[k], u) == Status::ok);
    CHECK(u[0] == Approx(2 * errors[k][0]));
    CHECK(u[1] == Approx(3 * errors[k][1]));
  }
}

TEST_CASE("pid: integral term alone, backward Euler with variable dt", "[control][pid]") {
  Pid2 pid(Pid2::Options::diagonal(V2::Zero(), V2(0.5, 2), V2::Zero()));
  // I_k = I_{k-1} + e_k dt_k: channel 0: 0.1, 0.5, 0.45; channel 1: -0.1, -0.1, 0.0
  const double dts[] = {0.1, 0.2, 0.05};
  const V2 errors[] = {V2(1, -1), V2(2, 0), V2(-1, 2)};
  const double i0[] = {0.1, 0.5, 0.45};
  const double i1[] = {-0.1, -0.1, 0.0};
  V2 u = V2::Zero();
  for (int k = 0; k < 3; ++k) {
    REQUIRE(pid.step(errors[k], V2::Zero(), dts[k], u) == Status::ok);
    CHECK(pid.integral()[0] == Approx(i0[k]));
    CHECK(pid.integral()[1] == Approx(i1[k]).margin(1e-15));
    CHECK(u[0] == Approx(0.5 * i0[k]));
    CHECK(u[1] == Approx(2 * i1[k]).margin(1e-15));
  }
}

TEST_CASE("pid: derivative of the smoothed error, variable dt, zero on the first step", "[control][pid]") {
  auto o = Pid2::Options::diagonal(V2::Zero(), V2::Zero(), V2(0.4, 1));
  o.smoothing = 0.5;
  Pid2 pid(o);
  // ē: 1, 2, 2.5, 1.25 (ē_k = 0.5 e_k + 0.5 ē_{k-1}, ē_0 = e_0); d = Δē/dt: 0, 5, 5, -2.5
  const double dts[] = {0.1, 0.2, 0.1, 0.5};
  const double e[] = {1, 3, 3, 0};
  const double ebar[] = {1, 2, 2.5, 1.25};
  const double d[] = {0, 5, 5, -2.5};
  V2 u = V2::Zero();
  for (int k = 0; k < 4; ++k) {
    REQUIRE(pid.step(V2(e[k], -e[k]), V2::Zero(), dts[k], u) == Status::ok);
    CHECK(pid.smoothedError()[0] == Approx(ebar[k]));
    CHECK(pid.derivative()[0] == Approx(d[k]).margin(1e-12));
    CHECK(u[0] == Approx(0.4 * d[k]).margin(1e-12));
    CHECK(u[1] == Approx(-1.0 * d[k]).margin(1e-12));
  }
  // reset → the next step is a first step again (derivative zero, ē = e)
  pid.reset();
  REQUIRE(pid.step(V2(7, 7), V2::Zero(), 0.1, u) == Status::ok);
  CHECK(u.isZero());
  CHECK(pid.smoothedError()[0] == 7);
}

TEST_CASE("pid: smoothing weight and time constant", "[control][pid]") {
  auto o = Pid2::Options::diagonal(V2::Zero(), V2::Zero(), V2(1, 1));
  o.smoothing = 0.25;  // weight of the newest sample
  Pid2 pid(o);
  V2 u = V2::Zero();
  REQUIRE(pid.step(V2(0, 0), V2::Zero(), 0.1, u) == Status::ok);
  REQUIRE(pid.step(V2(4, 4), V2::Zero(), 0.1, u) == Status::ok);
  CHECK(pid.smoothedError()[0] == Approx(1.0));  // 0.25·4 + 0.75·0
  CHECK(u[0] == Approx(10.0));                   // (1 − 0)/0.1

  o.smoothing_time_constant = 0.2;  // α = 1 − exp(−dt/τ)
  Pid2 pid2(o);
  REQUIRE(pid2.step(V2(0, 0), V2::Zero(), 0.05, u) == Status::ok);
  REQUIRE(pid2.step(V2(1, 1), V2::Zero(), 0.05, u) == Status::ok);
  const double a = 1 - std::exp(-0.05 / 0.2);
  CHECK(pid2.alpha(0.05) == Approx(a));
  CHECK(pid2.smoothedError()[0] == Approx(a));
  CHECK(u[0] == Approx(a / 0.05));
}

TEST_CASE("pid: the memoised smoothing weight follows dt and the options", "[control][pid]") {
  // update() computes 1 − exp(−dt/τ) once per distinct dt. A changed dt, and a configure() with
  // a new τ at an unchanged dt, must each give the fresh weight, exactly as alpha(dt) does.
  auto o = Pid2::Options::diagonal(V2::Zero(), V2::Zero(), V2::Zero());
  o.smoothing_time_constant = 0.2;
  Pid2 pid(o);
  V2 u;
  double expected = 0;
  const auto step = [&](double e, double dt) {
    const double a = pid.started() ? pid.alpha(dt) : 1.0;  // the first step takes e as it is
    expected = a * e + (1 - a) * expected;
    REQUIRE(pid.step(V2(e, -e), V2::Zero(), dt, u) == Status::ok);
    CHECK(pid.smoothedError()[0] == Approx(expected).epsilon(1e-14));  // a stale α is off by > 10 %
  };
  step(1.0, 0.05);
  step(2.0, 0.05);  // memo hit
  step(3.0, 0.01);  // new dt
  step(4.0, 0.05);  // back to the first dt
  o.smoothing_time_constant = 0.02;
  REQUIRE(pid.configure(o) == Status::ok);  // same dt, new τ: the memo must not be reused
  CHECK(pid.alpha(0.05) == Approx(1 - std::exp(-0.05 / 0.02)).epsilon(1e-15));
  step(5.0, 0.05);
  o.smoothing_time_constant = 0;  // back to the fixed per-step weight
  o.smoothing = 0.25;
  REQUIRE(pid.configure(o) == Status::ok);
  step(6.0, 0.05);
  CHECK(pid.alpha(0.05) == 0.25);
}

TEST_CASE("pid: feedforward passes through; zero error and zero feedforward give zero output",
          "[control][pid]") {
  auto o = Pid2::Options::diagonal(V2(1, 2), V2(3, 4), V2(5, 6));
  Pid2 pid(o);
  V2 u(9, 9);
  for (int k = 0; k < 50; ++k) {
    REQUIRE(pid.step(V2::Zero(), V2::Zero(), 0.01 * (1 + k % 3), u) == Status::ok);
    CHECK(u.isZero());
  }
  REQUIRE(pid.step(V2::Zero(), V2(1.5, -2), 0.01, u) == Status::ok);
  CHECK(u == V2(1.5, -2));
  CHECK(pid.lastTerms().feedforward == V2(1.5, -2));
}

TEST_CASE("pid: full gain matrices and the sum of terms", "[control][pid]") {
  Pid2::Options o;
  o.kp << 1, 2, 0, 1;
  o.ki << 0, 1, 1, 0;
  o.kd << 0.5, 0, 0, 0.5;
  o.smoothing = 1.0;  // no smoothing: d = Δe/dt
  Pid2 pid(o);
  V2 u = V2::Zero();
  REQUIRE(pid.step(V2(1, 1), V2(0.1, 0.2), 0.5, u) == Status::ok);
  // P = (3, 1); I = (0.5, 0.5) → Ki I = (0.5, 0.5); D = 0
  CHECK(u[0] == Approx(0.1 + 3 + 0.5));
  CHECK(u[1] == Approx(0.2 + 1 + 0.5));
  REQUIRE(pid.step(V2(2, 0), V2::Zero(), 0.25, u) == Status::ok);
  // P = (2, 0); I = (1.0, 0.5) → Ki I = (0.5, 1.0); d = (4, -4) → Kd d = (2, -2)
  CHECK(u[0] == Approx(2 + 0.5 + 2));
  CHECK(u[1] == Approx(0 + 1.0 - 2));
  const auto& t = pid.lastTerms();
  CHECK((t.proportional + t.integral + t.derivative + t.feedforward).isApprox(t.unclipped));
}

TEST_CASE("pid: integral clipping bounds wind-up; output clipping", "[control][pid]") {
  auto o = Pid2::Options::diagonal(V2::Zero(), V2(1, 1), V2::Zero());
  o.clipIntegral(-0.3, 0.3);
  o.output_min = V2(-kInf, -0.1);
  o.output_max = V2(kInf, 0.1);
  Pid2 pid(o);
  V2 u = V2::Zero();
  for (int k = 0; k < 1000; ++k) REQUIRE(pid.step(V2(1, 1), V2::Zero(), 0.1, u) == Status::ok);
  CHECK(pid.integral()[0] == Approx(0.3));  // bounded, not 100
  CHECK(u[0] == Approx(0.3));
  CHECK(u[1] == Approx(0.1));                          // output clip
  CHECK(pid.lastTerms().unclipped[1] == Approx(0.3));  // before the clip
  // recovery is immediate: one step of opposite error moves the integral off the bound
  REQUIRE(pid.step(V2(-1, -1), V2::Zero(), 0.1, u) == Status::ok);
  CHECK(pid.integral()[0] == Approx(0.2));
  // the output clip applies to the total, feedforward included
  REQUIRE(pid.step(V2::Zero(), V2(5, 5), 0.1, u) == Status::ok);
  CHECK(u[1] == Approx(0.1));
  CHECK(u[0] == Approx(5.2));
}

TEST_CASE("pid: invalid time step or non-finite input leaves state and output unchanged",
          "[control][pid]") {
  Pid2 pid(Pid2::Options::diagonal(V2(1, 1), V2(1, 1), V2(1, 1)));
  V2 u = V2::Zero();
  REQUIRE(pid.step(V2(1, 2), V2::Zero(), 0.1, u) == Status::ok);
  REQUIRE(pid.step(V2(2, 3), V2::Zero(), 0.1, u) == Status::ok);
  const V2 integral = pid.integral(), smoothed = pid.smoothedError(), deriv = pid.derivative();
  const long steps = pid.steps();
  const V2 u_before = u;
  for (double dt : {0.0, -0.1, kNaN, kInf, -kInf}) {
    CHECK(pid.step(V2(1, 1), V2::Zero(), dt, u) == Status::invalid_time_step);
  }
  CHECK(pid.step(V2(kNaN, 1), V2::Zero(), 0.1, u) == Status::non_finite_input);
  CHECK(pid.step(V2(1, kInf), V2::Zero(), 0.1, u) == Status::non_finite_input);
  CHECK(pid.step(V2(1, 1), V2(kNaN, 0), 0.1, u) == Status::non_finite_input);
  CHECK(u == u_before);
  CHECK(pid.integral() == integral);
  CHECK(pid.smoothedError() == smoothed);
  CHECK(pid.derivative() == deriv);
  CHECK(pid.steps() == steps);
}

TEST_CASE("pid: option validation", "[control][pid]") {
  Pid2::Options bad;
  bad.smoothing = 0.0;
  CHECK(Pid2::validate(bad) == Status::invalid_argument);
  bad = Pid2::Options{};
  bad.smoothing = 1.5;
  CHECK(Pid2::validate(bad) == Status::invalid_argument);
  bad = Pid2::Options{};
  bad.integral_min[1] = 1;
  bad.integral_max[1] = -1;
  CHECK(Pid2::validate(bad) == Status::invalid_argument);
  bad = Pid2::Options{};
  bad.output_max[0] = kNaN;
  CHECK(Pid2::validate(bad) == Status::non_finite_input);
  bad = Pid2::Options{};
  bad.kp(0, 1) = kInf;
  CHECK(Pid2::validate(bad) == Status::non_finite_input);
  bad = Pid2::Options{};
  bad.smoothing_time_constant = -1;
  CHECK(Pid2::validate(bad) == Status::invalid_argument);
  CHECK(Pid2::validate(Pid2::Options{}) == Status::ok);

  // a controller built with invalid options refuses to run; configure() leaves it unchanged
  Pid2 refused(bad);
  V2 u(1, 1);
  CHECK(refused.configurationStatus() == Status::invalid_argument);
  CHECK(refused.step(V2(1, 1), V2::Zero(), 0.1, u) == Status::invalid_argument);
  CHECK(u == V2(1, 1));
  Pid2 good(Pid2::Options::diagonal(V2(1, 1), V2::Zero(), V2::Zero()));
  CHECK(good.configure(bad) == Status::invalid_argument);
  CHECK(good.options().kp(0, 0) == 1);
  CHECK(good.configurationStatus() == Status::ok);  // a refused configure() changes nothing
  // configurationStatus(): why the constructor's options were refused, until a configure()
  // succeeds; a refused configure() does not change it either.
  Pid2::Options nan_gain;
  nan_gain.kp(0, 1) = kNaN;
  CHECK(refused.configure(nan_gain) == Status::non_finite_input);
  CHECK(refused.configurationStatus() == Status::invalid_argument);
  CHECK(refused.configure(Pid2::Options::diagonal(V2(1, 1), V2::Zero(), V2::Zero())) == Status::ok);
  CHECK(refused.configurationStatus() == Status::ok);
  CHECK(refused.step(V2(1, 1), V2::Zero(), 0.1, u) == Status::ok);
}

TEST_CASE("pid: SisoPid equals MimoPid<1>", "[control][pid]") {
  SisoPid<double>::Options so;
  so.kp = 0.9;
  so.ki = 6;
  so.kd = 0.045;
  so.integral_min = -0.05;
  so.integral_max = 0.05;
  so.output_min = -15;
  so.output_max = 15;
  SisoPid<double> siso(so);
  MimoPid<double, 1> mimo(SisoPid<double>::toMimo(so));
  double u = 0;
  MimoPid<double, 1>::Vector um = MimoPid<double, 1>::Vector::Zero();
  for (int k = 0; k < 40; ++k) {
    const double e = std::sin(0.3 * k) * 2;
    const double dt = 0.02 + 0.01 * (k % 4);
    REQUIRE(siso.step(e, 0.5, dt, u) == Status::ok);
    REQUIRE(mimo.step(MimoPid<double, 1>::Vector::Constant(e), MimoPid<double, 1>::Vector::Constant(0.5),
                        dt, um) == Status::ok);
    CHECK(u == um[0]);
  }
  const double before = u;
  CHECK(siso.step(1.0, 0.0, 0.0, u) == Status::invalid_time_step);
  CHECK(siso.step(kNaN, 0.0, 0.1, u) == Status::non_finite_input);
  CHECK(u == before);
}

namespace {
// A per-step PID as in earlier tactile-servoing code: Σe (clipped), Δē per step, no dt.
struct PerStepPid {
  double kp, ki, kd, alpha, ilo, ihi;
  double sum = 0, ebar = 0;
  bool started = false;
  double step(double e) {
    sum = std::min(ihi, std::max(ilo, sum + e));
    double d = 0;
    if (!started) {
      ebar = e;
      started = true;
    } else {
      const double prev = ebar;
      ebar = alpha * e + (1 - alpha) * ebar;
      d = ebar - prev;
    }
    return kp * e + ki * sum + kd * d;
  }
};
}  // namespace

TEST_CASE("pid: per-step gains convert as Ki/dt, Kd·dt, clip·dt (time-constant smoothing)",
          "[control][pid]") {
  const double T = 1.0 / 20.0;
  PerStepPid ref{0.9, 0.3, 0.9, 0.5, -10, 10};
  SisoPid<double>::Options o;
  o.kp = 0.9;
  o.ki = 0.3 / T;
  o.kd = 0.9 * T;
  o.integral_min = -10 * T;
  o.integral_max = 10 * T;
  o.smoothing_time_constant = -T / std::log(0.5);  // α(T) = 0.5
  SisoPid<double> pid(o);
  double max_integral = 0;
  for (int k = 0; k < 200; ++k) {
    const double e = 8 * std::sin(0.05 * k) + 3;  // drives the integral into its clip
    double u = 0;
    REQUIRE(pid.step(e, 0, T, u) == Status::ok);
    CHECK(u == Approx(ref.step(e)).epsilon(1e-12).margin(1e-12));
    max_integral = std::max(max_integral, std::abs(pid.integral()));
  }
  CHECK(max_integral == Approx(10 * T));  // the clip was active
}

TEST_CASE("detail::allFinite over one and several objects (the real-time paths' finiteness test)", "[control][pid]") {
  using V6 = Eigen::Matrix<double, 6, 1>;
  using M3 = Eigen::Matrix3d;
  const double big = std::numeric_limits<double>::max(), tiny = std::numeric_limits<double>::denorm_min();
  V6 a, b;
  a << big, -big, tiny, -tiny, 0.0, 1.0;
  b << 1.0, 2.0, 3.0, 4.0, 5.0, 6.0;
  M3 m = M3::Identity() * big;
  // x − x is exactly 0 for every finite x, so extremes do not overflow the test.
  CHECK(lieservo::detail::allFinite(a));
  CHECK(lieservo::detail::allFinite(a, b, a));
  CHECK(lieservo::detail::allFinite(m));
  for (double bad : {kInf, -kInf, std::numeric_limits<double>::quiet_NaN()}) {
    for (int i = 0; i < 6; ++i) {
      for (int which = 0; which < 3; ++which) {
        V6 x = a, y = b, z = a;
        (which == 0 ? x : which == 1 ? y : z)(i) = bad;
        INFO("bad value " << bad << " at " << i << " of object " << which);
        CHECK_FALSE(lieservo::detail::allFinite(x, y, z));
        if (which == 0) CHECK_FALSE(lieservo::detail::allFinite(x));
      }
    }
    M3 mb = m;
    mb(2, 1) = bad;
    CHECK_FALSE(lieservo::detail::allFinite(mb));
  }
}

// A clip range must hold a finite value: [+inf, +inf] (or [−inf, −inf]) passes min ≤ max but
// clips every output to infinity, so every update would fail.
TEST_CASE("pid: a clip range at +inf or -inf only is refused", "[control][pid]") {
  for (const double v : {kInf, -kInf}) {
    Pid2::Options o = Pid2::Options::diagonal(V2(1, 1), V2::Zero(), V2::Zero());
    o.clipOutput(v, v);
    CHECK(Pid2::validate(o) == Status::invalid_argument);
    o = Pid2::Options::diagonal(V2(1, 1), V2::Zero(), V2::Zero());
    o.integral_min[1] = v;
    o.integral_max[1] = v;
    CHECK(Pid2::validate(o) == Status::invalid_argument);
    Pid2 pid(o);
    V2 u(5, 5);
    CHECK(pid.step(V2(1, 1), V2::Zero(), 0.1, u) == Status::invalid_argument);
    CHECK(u == V2(5, 5));
  }
  // Half-open ranges stay valid.
  Pid2::Options o = Pid2::Options::diagonal(V2(1, 1), V2::Zero(), V2::Zero());
  o.clipOutput(-kInf, 3.0);
  CHECK(Pid2::validate(o) == Status::ok);
  o.clipOutput(-3.0, kInf);
  CHECK(Pid2::validate(o) == Status::ok);
}

// The 1 kHz callback body against a kinematic fake robot that integrates the base twist [ṗ_OE; ω_O].
#include <catch2/catch.hpp>

#include "limit_checker.hpp"

#include <lieservo/units.hpp>
#include <lieservo/realtime/velocity_pipeline.hpp>

#include <Eigen/Geometry>
#include <cstdint>
#include <limits>
#include <utility>

using lieservo::Status;
using namespace lieservo::realtime;
using SE3d = lieservo::SE3<double>;
using SO3d = lieservo::SO3<double>;

namespace {

// A perfect velocity-controlled arm: p += ṗ dt, R ← exp(ω dt) R (base-frame ω).
struct FakeArm {
  Matrix3 R = Eigen::AngleAxisd(lieservo::pi<double>(), Vector3::UnitX()).toRotationMatrix();  // pointing down
  Vector3 p = Vector3(0.4, 0.0, 0.3);
  void integrate(const std::array<double, 6>& v, double dt) {
    const Eigen::Map<const Vector6> x(v.data());
    p += dt * x.head<3>();
    const Vector3 w = x.tail<3>();
    if (w.norm() > 0) R = Eigen::AngleAxisd(dt * w.norm(), w.normalized()).toRotationMatrix() * R;
  }
  // The pose as a robot reports it, through the one parse (as an adapter does each cycle).
  SE3d T_OE() const {
    Matrix4 T = Matrix4::Identity();
    T.topLeftCorner<3, 3>() = R;
    T.topRightCorner<3, 1>() = p;
    SE3d X;
    REQUIRE(poseFromHomogeneous(T, X) == Status::ok);
    return X;
  }
};

PipelineOptions options() {
  PipelineOptions o;
  o.mount.X_es = SE3d(SO3d(), Vector3(0, 0, 0.12));  // tip centre 120 mm below the flange (m)
  o.watchdog.rearm_fresh_commands = 1;
  o.watchdog.command_timeout_s = 0.1;
  return o;
}

}  // namespace

TEST_CASE("pipeline: rotating about the tip centre keeps the tip in place", "[realtime][pipeline]") {
  CartesianVelocityPipeline pipe;
  REQUIRE(pipe.configure(options()) == Status::ok);
  FakeArm arm;
  const std::int64_t ms = 1000000;
  TwistCommand cmd;
  cmd.twist_s = {0, 0, 0, 0.2, -0.1, 0.0};  // pure rotation of the sensor (rad/s)
  cmd.in_contact = true;
  std::array<double, 6> out{};
  rt_test::LimitChecker check{pipe.options().limits, 1e-3};
  const Matrix4 X0 = sensorPose(arm.T_OE(), pipe.options().mount).matrix();
  std::uint64_t seq = 0;
  Matrix4 X_after_ramp;
  for (int k = 0; k < 2000; ++k) {
    if (k == 200) X_after_ramp = sensorPose(arm.T_OE(), pipe.options().mount).matrix();
    if (k % 33 == 0) ++seq;  // a fresh tactile command every 33 ms
    const ChannelStamp stamp{seq, static_cast<std::int64_t>((k - k % 33)) * ms};
    REQUIRE(pipe.step(arm.T_OE(), cmd, stamp, k * ms, out) == Status::ok);
    check.push(Eigen::Map<const Vector6>(out.data()));
    arm.integrate(out, 1e-3);
  }
  const Matrix4 X1 = sensorPose(arm.T_OE(), pipe.options().mount).matrix();
  // The EE moved a lot, the tip centre hardly: smoothing happens at the EE (so the limits
  // hold on the robot's signal), with separate linear and angular ramps, so during the
  // ~40 ms start-up ramp the rotation is not exactly about the tip (documented); after it,
  // the tip stays put.
  CHECK((arm.p - Vector3(0.4, 0.0, 0.3)).norm() > 0.03);
  CHECK((X1.topRightCorner<3, 1>() - X0.topRightCorner<3, 1>()).norm() < 1e-3);
  CHECK((X1.topRightCorner<3, 1>() - X_after_ramp.topRightCorner<3, 1>()).norm() < 2e-5);
  // Rotated by ~|ω| t about base axes: the sensor-frame angular velocity was honoured.
  const Eigen::AngleAxisd d(X0.topLeftCorner<3, 3>().transpose() * X1.topLeftCorner<3, 3>());
  CHECK((d.angle() * d.axis() - Vector3(0.2, -0.1, 0) * 2.0).norm() < 0.01);
  CHECK(check.worst_norm <= 1 + 1e-9);
}

TEST_CASE("pipeline: pressing along the sensor z moves the arm down in the base frame", "[realtime][pipeline]") {
  CartesianVelocityPipeline pipe;
  REQUIRE(pipe.configure(options()) == Status::ok);
  FakeArm arm;
  TwistCommand cmd;
  cmd.twist_s = {0, 0, 10, 0, 0, 0};  // 10 mm/s into the surface
  std::array<double, 6> out{};
  for (int k = 0; k < 1000; ++k) {
    const ChannelStamp stamp{static_cast<std::uint64_t>(k + 1), k * 1000000LL};
    REQUIRE(pipe.step(arm.T_OE(), cmd, stamp, k * 1000000LL, out) == Status::ok);
    arm.integrate(out, 1e-3);
  }
  CHECK(out[2] == Approx(-0.01).margin(1e-12));
  CHECK(arm.p.z() == Approx(0.3 - 0.01 * 1.0).margin(5e-4));  // ≈1 s at 10 mm/s, minus the ramp
}

TEST_CASE("pipeline: stale commands and stop requests ramp to zero, rearm resumes", "[realtime][pipeline]") {
  CartesianVelocityPipeline pipe;
  REQUIRE(pipe.configure(options()) == Status::ok);
  FakeArm arm;
  TwistCommand cmd;
  cmd.twist_s = {20, 0, 0, 0, 0, 0.3};
  cmd.in_contact = true;
  std::array<double, 6> out{};
  rt_test::LimitChecker check{pipe.options().limits, 1e-3};
  const ChannelStamp stamp{1, 0};  // written once at t = 0, never again
  int k = 0;
  for (; k < 300; ++k) {
    REQUIRE(pipe.step(arm.T_OE(), cmd, stamp, k * 1000000LL, out) == Status::ok);
    check.push(Eigen::Map<const Vector6>(out.data()));
    if (k == 50) CHECK(Eigen::Map<const Vector6>(out.data()).norm() > 0);
  }
  CHECK(pipe.watchdog().state() == WatchdogState::tripped_timeout);
  CHECK(pipe.stopped());
  CHECK(Eigen::Map<const Vector6>(out.data()).isZero(0));

  // Fresh commands again → moves; then a stop request ramps down and latches.
  for (; k < 600; ++k) {
    const ChannelStamp s{static_cast<std::uint64_t>(k), k * 1000000LL};
    REQUIRE(pipe.step(arm.T_OE(), cmd, s, k * 1000000LL, out) == Status::ok);
    check.push(Eigen::Map<const Vector6>(out.data()));
  }
  CHECK_FALSE(pipe.stopped());
  pipe.requestStop();
  for (; k < 900; ++k) {
    const ChannelStamp s{static_cast<std::uint64_t>(k), k * 1000000LL};
    REQUIRE(pipe.step(arm.T_OE(), cmd, s, k * 1000000LL, out) == Status::ok);
    check.push(Eigen::Map<const Vector6>(out.data()));
  }
  CHECK(pipe.stopped());
  pipe.rearm();
  const ChannelStamp s{100000, k * 1000000LL};
  REQUIRE(pipe.step(arm.T_OE(), cmd, s, k * 1000000LL, out) == Status::ok);
  CHECK_FALSE(pipe.stopped());
  CHECK(check.worst_norm <= 1 + 1e-9);
}

TEST_CASE("pipeline: a stamp from the future or at the clock's ends does not pass as fresh", "[realtime][pipeline]") {
  FakeArm arm;
  TwistCommand cmd;
  cmd.twist_s = {20, 0, 0, 0, 0, 0};
  cmd.in_contact = true;
  std::array<double, 6> out{};
  SECTION("moving, then a command stamped 10 s ahead and no more: the watchdog trips at once") {
    CartesianVelocityPipeline pipe;
    REQUIRE(pipe.configure(options()) == Status::ok);
    int k = 1;
    for (; k <= 50; ++k) {
      const ChannelStamp fresh{std::uint64_t(k), k * 1000000LL};
      REQUIRE(pipe.step(arm.T_OE(), cmd, fresh, k * 1000000LL, out) == Status::ok);
    }
    REQUIRE(Eigen::Map<const Vector6>(out.data()).norm() > 0);
    const ChannelStamp ahead{std::uint64_t(k), k * 1000000LL + 10000000000LL};
    REQUIRE(pipe.step(arm.T_OE(), cmd, ahead, k * 1000000LL, out) == Status::ok);
    CHECK(pipe.watchdog().state() == WatchdogState::tripped_timeout);
    for (int j = 1; j < 300; ++j) REQUIRE(pipe.step(arm.T_OE(), cmd, ahead, (k + j) * 1000000LL, out) == Status::ok);
    CHECK(pipe.stopped());
  }
  SECTION("stamp and clock at the ends of int64: no overflow (UBSan), the command does not pass") {
    for (const auto& [stamp_ns, now_ns] : {std::pair<std::int64_t, std::int64_t>{std::numeric_limits<std::int64_t>::max(),
                                                                                  std::numeric_limits<std::int64_t>::min()},
                                           {std::numeric_limits<std::int64_t>::min(), std::numeric_limits<std::int64_t>::max()}}) {
      CartesianVelocityPipeline pipe;
      REQUIRE(pipe.configure(options()) == Status::ok);
      REQUIRE(pipe.step(arm.T_OE(), cmd, ChannelStamp{12, stamp_ns}, now_ns, out) == Status::ok);
      CHECK_FALSE(pipe.watchdog().passCommands());
      CHECK(Eigen::Map<const Vector6>(out.data()).isZero(0));
    }
  }
  SECTION("a stamp a microsecond ahead (clock jitter) passes") {
    CartesianVelocityPipeline pipe;
    REQUIRE(pipe.configure(options()) == Status::ok);
    for (int k = 1; k < 50; ++k) {
      const std::int64_t now = k * 1000000LL;
      REQUIRE(pipe.step(arm.T_OE(), cmd, ChannelStamp{std::uint64_t(k), now + 1000}, now, out) == Status::ok);
    }
    CHECK_FALSE(pipe.stopped());
    CHECK(Eigen::Map<const Vector6>(out.data()).norm() > 0);
  }
}

TEST_CASE("pipeline: bad pose or command -> Status, output and state unchanged, stepStopping ramps", "[realtime][pipeline]") {
  CartesianVelocityPipeline pipe;
  REQUIRE(pipe.configure(options()) == Status::ok);
  FakeArm arm;
  TwistCommand cmd;
  cmd.twist_s = {5, 5, 0, 0, 0, 0};
  std::array<double, 6> out{};
  for (int k = 0; k < 100; ++k) {
    const ChannelStamp s{static_cast<std::uint64_t>(k + 1), k * 1000000LL};
    REQUIRE(pipe.step(arm.T_OE(), cmd, s, k * 1000000LL, out) == Status::ok);
  }
  const auto v_before = pipe.smoother().velocity();
  const std::array<double, 6> out_before = out;
  // A pose that did not come through the parse (a non-orthonormal one is the parse's to refuse:
  // test_frames).
  Matrix4 bad_pose = arm.T_OE().matrix();
  bad_pose(0, 0) = std::numeric_limits<double>::quiet_NaN();
  const ChannelStamp s{200, 100000000LL};
  CHECK(pipe.step(SE3d::fromMatrixUnchecked(bad_pose), cmd, s, 100000000LL, out) == Status::non_finite_input);
  bad_pose = arm.T_OE().matrix();
  bad_pose(1, 3) = std::numeric_limits<double>::infinity();
  CHECK(pipe.step(SE3d::fromMatrixUnchecked(bad_pose), cmd, s, 100000000LL, out) == Status::non_finite_input);
  TwistCommand bad_cmd = cmd;
  bad_cmd.twist_s[2] = std::numeric_limits<double>::infinity();
  CHECK(pipe.step(arm.T_OE(), bad_cmd, s, 100000000LL, out) == Status::non_finite_input);
  CHECK(out == out_before);
  CHECK(pipe.smoother().velocity() == v_before);
  CHECK(pipe.watchdog().passCommands());

  // The adapter's fallback for a bad cycle: stepStopping() ramps to rest without a pose.
  int n = 0;
  while (!pipe.stopped() && n < 2000) {
    REQUIRE(pipe.stepStopping(out) == Status::ok);
    ++n;
  }
  CHECK(pipe.stopped());
  CHECK(n < 2000);

  PipelineOptions o = options();
  Matrix4 skewed = o.mount.X_es.matrix();
  skewed(0, 0) = 0.5;
  o.mount.X_es = SE3d::fromMatrixUnchecked(skewed);
  CHECK(pipe.configure(o) == Status::not_orthonormal);
  for (const double period : {0.0, 2.0, 1e-7, std::numeric_limits<double>::max()}) {
    o = options();
    o.control_period_s = period;
    CHECK(pipe.configure(o) == (std::isfinite(period) ? Status::invalid_time_step : Status::non_finite_input));
  }
  o = options();
  o.limits.translation.velocity = -1;
  CHECK(pipe.configure(o) == Status::invalid_argument);
  CHECK(pipe.options().mount.X_es.translation().z() == 0.12);  // unchanged
}

TEST_CASE("pipeline, smoother, watchdog: options refused at construction are kept until a configure() succeeds",
          "[realtime][pipeline]") {
  // The lifecycle the filter and the controllers share (lieservo/configurable.hpp).
  SmootherLimits<double> bad_limits;
  bad_limits.translation.velocity = -1;
  VelocitySmoother<double> smoother(bad_limits);
  CHECK(smoother.configurationStatus() == Status::invalid_argument);
  CHECK(smoother.step(Vector6::Ones(), 1e-3) == Status::invalid_argument);
  CHECK(smoother.atRest());
  REQUIRE(smoother.configure(SmootherLimits<double>{}) == Status::ok);
  CHECK(smoother.step(Vector6::Ones(), 1e-3) == Status::ok);

  WatchdogOptions bad_watchdog;
  bad_watchdog.command_timeout_s = std::numeric_limits<double>::quiet_NaN();
  CommandWatchdog watchdog(bad_watchdog);
  CHECK(watchdog.configurationStatus() == Status::non_finite_input);
  CHECK(watchdog.step(1, 0.0, true) == Status::non_finite_input);
  CHECK(watchdog.state() == WatchdogState::waiting);
  REQUIRE(watchdog.configure(WatchdogOptions{}) == Status::ok);
  CHECK(watchdog.step(1, 0.0, true) == Status::ok);

  PipelineOptions bad = options();
  bad.control_period_s = 0;
  CartesianVelocityPipeline pipe(bad);
  CHECK(pipe.configurationStatus() == Status::invalid_time_step);
  TwistCommand cmd;
  cmd.twist_s = {1, 0, 0, 0, 0, 0};
  std::array<double, 6> out{};
  CHECK(pipe.step(SE3d(), cmd, ChannelStamp{1, 0}, 0, out) == Status::invalid_time_step);
  CHECK(out == std::array<double, 6>{});
  REQUIRE(pipe.configure(options()) == Status::ok);
  CHECK(pipe.configurationStatus() == Status::ok);
  CHECK(pipe.step(SE3d(), cmd, ChannelStamp{1, 0}, 0, out) == Status::ok);
}

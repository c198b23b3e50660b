// TactileServoController (Section 3.3.2, sec:servoing_controller): the servo error E = X_sf X_s'f⁻¹
// (eq. 20, eqn:se3_tactile_servo_error), e = log(E)^∨ (eq. 18, eqn:local_tangent_space_error), the
// feedforward mapping v = Ad(X_ss') u_s'2, genericity over the group, and the Status contract.
#include <catch2/catch.hpp>

#include "control_test_util.hpp"

#include <cmath>
#include <limits>

#include <lieservo/control/tactile_servo_controller.hpp>
#include <lieservo/groups/se2.hpp>
#include <lieservo/groups/se3.hpp>
#include <lieservo/groups/so2.hpp>
#include <lieservo/groups/so3.hpp>
#include <lieservo/units.hpp>

using namespace lieservo;
using SE3d_ = SE3<double>;
using V6 = SE3d_::Tangent;
using Servo = TactileServoController<SE3d_>;

namespace {
using lieservo::test::v6;
Servo::Options pOnly(double kp) {
  Servo::Options o;
  o.pid = Servo::Pid::Options::diagonal(V6::Constant(kp), V6::Zero(), V6::Zero());
  return o;
}
}  // namespace

TEST_CASE("servo: error is X_sf X_fs' and e = log(E)", "[control][servo]") {
  auto o = pOnly(2.0);
  o.reference = SE3d_::fromEulerXYZ6Degrees(v6(0, 0, 6, 0, 0, 0));  // X_fs': 6 mm deep
  Servo servo(o);
  // Sensor 4 mm deep, tilted 10° about x, sheared 1 mm in y: X_fs, so X_sf = X_fs⁻¹.
  const SE3d_ X_fs = SE3d_::fromEulerXYZ6Degrees(v6(0, 1, 4, 10, 0, 0));
  const SE3d_ X_sf = X_fs.inverse();
  V6 u = V6::Zero();
  REQUIRE(servo.step(X_sf, 0.01, u) == Status::ok);
  const SE3d_ E = X_fs.inverse() * o.reference;  // X_ss' = X_sf X_fs'
  CHECK(servo.poseError().isApprox(E, 1e-12));
  CHECK(servo.tangentError().isApprox(E.log(), 1e-12));
  CHECK(u.isApprox(2.0 * E.log(), 1e-12));
  // the error is the right perturbation taking the sensor to the reference:
  // X_fs exp(e^) = X_fs'
  CHECK((X_fs * SE3d_::exp(servo.tangentError())).isApprox(o.reference, 1e-9));
}

TEST_CASE("servo: at the reference the output is the feedforward, unchanged", "[control][servo]") {
  auto o = pOnly(5.0);
  o.reference = SE3d_::fromEulerXYZ6Degrees(v6(0, 0, 3, 0, 0, 0));
  o.feedforward = v6(0, 10, 0, 0, 0, 0);
  Servo servo(o);
  V6 u = V6::Zero();
  for (int k = 0; k < 5; ++k) {
    REQUIRE(servo.step(o.reference.inverse(), 0.05, u) == Status::ok);
    CHECK(u.isApprox(o.feedforward, 1e-12));
    CHECK(servo.tangentError().norm() < 1e-12);
  }
}

TEST_CASE("servo: zero error and zero feedforward give zero output", "[control][servo]") {
  Servo::Options o;
  o.pid = Servo::Pid::Options::diagonal(V6::Constant(5), V6::Constant(10), V6::Constant(0.025));
  o.reference = SE3d_::fromEulerXYZ6Degrees(v6(0, 0, 6, 0, 0, 0));
  Servo servo(o);
  V6 u = V6::Ones();
  for (int k = 0; k < 20; ++k) {
    REQUIRE(servo.step(o.reference.inverse(), 0.033, u) == Status::ok);
    CHECK(u.norm() < 1e-12);
  }
}

TEST_CASE("servo: feedforward is mapped by Ad(X_ss') when the sensor is not at the reference",
          "[control][servo]") {
  Servo::Options o;  // zero gains: output = feedforward term only
  o.reference = SE3d_::identity();
  o.feedforward = v6(0, 10, 0, 0, 0, 1);  // 10 mm/s along y', 1 rad/s about z' (reference frame)
  Servo servo(o);
  // Hand-built: X_ss' = (Rz(90°), r = (1, 0, 0)).  X_sf = X_ss' X_fs'⁻¹ = X_ss'.
  const SE3d_ X_ss(SO3<double>::fromEulerXYZ(0, 0, pi<double>() / 2), Eigen::Vector3d(1, 0, 0));
  V6 u = V6::Zero();
  REQUIRE(servo.step(X_ss, 0.01, u) == Status::ok);
  // ω = C ω' = (0, 0, 1); v = C v' + r × (C ω') = (−10, 0, 0) + (1,0,0)×(0,0,1) = (−10, −1, 0)
  CHECK(u.isApprox(v6(-10, -1, 0, 0, 0, 1), 1e-12));
  CHECK(servo.feedforwardInSensorFrame().isApprox(u, 1e-12));

  // Meaning: moving the sensor with u = Ad(X_ss') u_s'2 moves a frame rigidly attached at
  // the reference pose with body twist u_s'2.  Kinematic plant: X_ws ← X_ws exp(u dt).
  const SE3d_ X_ws = SE3d_::fromEulerXYZ6Degrees(v6(100, -20, 50, 30, -10, 45));
  const SE3d_ X_ws_ref = X_ws * X_ss;  // attached copy of {s'}
  const double dt = 0.02;
  const SE3d_ X_ws_next = X_ws * SE3d_::exp(dt * u);
  CHECK((X_ws_next * X_ss).isApprox(X_ws_ref * SE3d_::exp(dt * o.feedforward), 1e-9));
  CHECK(servo.referenceToSensorAdjoint().isApprox(X_ss.Ad(), 1e-12));
}

TEST_CASE("servo: invalid dt or non-finite pose leaves everything unchanged", "[control][servo]") {
  Servo::Options o;
  o.pid = Servo::Pid::Options::diagonal(V6::Constant(1), V6::Constant(1), V6::Constant(1));
  Servo servo(o);
  const SE3d_ X = SE3d_::fromEulerXYZ6Degrees(v6(1, 2, 3, 4, 5, 6));
  V6 u = V6::Zero();
  REQUIRE(servo.step(X, 0.1, u) == Status::ok);
  const V6 u0 = u, e0 = servo.tangentError(), i0 = servo.pid().integral();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CHECK(servo.step(SE3d_::identity(), 0.0, u) == Status::invalid_time_step);
  CHECK(servo.step(SE3d_::identity(), -1.0, u) == Status::invalid_time_step);
  CHECK(servo.step(SE3d_::identity(), nan, u) == Status::invalid_time_step);
  const SE3d_ bad(X.so3(), X.translation() + SE3d_::Vector3(0, nan, 0));
  CHECK(servo.step(bad, 0.1, u) == Status::non_finite_input);
  CHECK(u == u0);
  CHECK(servo.tangentError() == e0);
  CHECK(servo.pid().integral() == i0);
  CHECK(servo.setFeedforward(V6::Constant(nan)) == Status::non_finite_input);
  CHECK(servo.options().feedforward.isZero());

  // Finite pose and reference whose composition overflows: e = log(E) is not finite. The input
  // was valid, so this is the controller's numerical failure (reported by the PID's own check),
  // and again nothing changes.
  REQUIRE(servo.setReference(SE3d_(SE3d_::SO3Type(), SE3d_::Vector3(1e308, 0, 0))) == Status::ok);
  CHECK(servo.step(SE3d_(SE3d_::SO3Type(), SE3d_::Vector3(1e308, 0, 0)), 0.1, u) == Status::numerical_failure);
  CHECK(u == u0);
  CHECK(servo.tangentError() == e0);
  CHECK(servo.poseError().translation().allFinite());
  CHECK(servo.pid().integral() == i0);
}

TEST_CASE("servo: generic over the group (SE2, SO3, SO2)", "[control][servo]") {
  {
    using S = TactileServoController<SE2<double>>;
    S::Options o;
    o.pid = S::Pid::Options::diagonal(S::Tangent::Constant(3), S::Tangent::Zero(), S::Tangent::Zero());
    o.reference = SE2<double>::exp(S::Tangent(0.0, 2.0, 0.0));
    o.feedforward = S::Tangent(1.0, 0.0, 0.0);
    S servo(o);
    const SE2<double> X_sf = SE2<double>::exp(S::Tangent(0.5, -0.2, 0.3));
    S::Tangent u = S::Tangent::Zero();
    REQUIRE(servo.step(X_sf, 0.01, u) == Status::ok);
    const SE2<double> E = X_sf * o.reference;
    CHECK(u.isApprox(3 * E.log() + E.Ad() * o.feedforward, 1e-12));
  }
  {
    using S = TactileServoController<SO3<double>>;
    S::Options o;
    o.pid = S::Pid::Options::diagonal(S::Tangent::Constant(2), S::Tangent::Zero(), S::Tangent::Zero());
    S servo(o);
    const SO3<double> X_sf = SO3<double>::fromEulerXYZ(0.1, -0.2, 0.3);
    S::Tangent u = S::Tangent::Zero();
    REQUIRE(servo.step(X_sf, 0.01, u) == Status::ok);
    CHECK(u.isApprox(2 * X_sf.log(), 1e-12));
  }
  {
    using S = TactileServoController<SO2<double>>;
    S::Options o;
    o.pid = S::Pid::Options::diagonal(S::Tangent::Constant(2), S::Tangent::Zero(), S::Tangent::Zero());
    S servo(o);
    S::Tangent u = S::Tangent::Zero();
    REQUIRE(servo.step(SO2<double>::exp(S::Tangent::Constant(0.4)), 0.01, u) == Status::ok);
    CHECK(u[0] == Approx(0.8));
  }
}

// Poses with a non-orthonormal rotation block must be refused wherever a controller takes
// a pose, not only NaN/inf: the rotation would otherwise enter log() as if it were valid.
TEST_CASE("servo: non-orthonormal rotations are refused and change nothing", "[control][servo]") {
  auto scaled = [](const SE3d_& X, double f) {
    SE3d_::Matrix M = X.matrix();
    M.topLeftCorner<3, 3>() *= f;
    return SE3d_::fromMatrixUnchecked(M);
  };
  const SE3d_ good = SE3d_::exp(v6(0.1, -0.2, 3, 0.02, -0.01, 0.03));
  const SE3d_ bad = scaled(good, 1.01);
  Servo::Options o;
  o.pid = Servo::Pid::Options::diagonal(V6::Constant(0.5), V6::Zero(), V6::Zero());
  o.reference = SE3d_::exp(v6(0, 0, 3, 0, 0, 0));
  Servo servo(o);
  V6 u = V6::Zero();
  REQUIRE(servo.step(good, 0.05, u) == Status::ok);
  const V6 u_before = u;
  const V6 e_before = servo.tangentError();

  CHECK(servo.step(bad, 0.05, u) == Status::not_orthonormal);
  CHECK(u == u_before);
  CHECK(servo.tangentError() == e_before);

  const SE3d_ ref_before = servo.options().reference;
  CHECK(servo.setReference(bad) == Status::not_orthonormal);
  CHECK(servo.options().reference.matrix() == ref_before.matrix());

  // One bad input, one Status: the options' check says what setReference says.
  o.reference = bad;
  CHECK(Servo::validate(o) == Status::not_orthonormal);
  CHECK(servo.configure(o) == Status::not_orthonormal);
  CHECK(servo.options().reference.matrix() == ref_before.matrix());
  CHECK(Servo(o).step(good, 0.05, u) == Status::not_orthonormal);
  CHECK(u == u_before);
  o = servo.options();
  o.feedforward[2] = std::numeric_limits<double>::quiet_NaN();
  CHECK(Servo::validate(o) == Status::non_finite_input);
  CHECK(servo.setFeedforward(o.feedforward) == Status::non_finite_input);
}

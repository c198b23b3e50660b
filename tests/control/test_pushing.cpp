// PushingController (Section 3.3.3, sec:pushing_controller): target pose in the reference sensor frame
// (eq. 21, eqn:transformed_target_pose), bearing and distance (eq. 22, eqn:target_bearing_distance), bearing
// sign, the ρ* cut-off, termination, and the Status contract — on hand-built geometries.
#include <catch2/catch.hpp>

#include "control_test_util.hpp"

#include <cmath>
#include <limits>

#include <lieservo/control/presets.hpp>
#include <lieservo/control/pushing_controller.hpp>
#include <lieservo/groups/se3.hpp>
#include <lieservo/units.hpp>

using namespace lieservo;
using G = SE3<double>;
using V6 = G::Tangent;
using Push = PushingController<SE3d>;
using Eigen::Vector3d;

namespace {
using lieservo::test::v6;
G at(double x, double y, double z) { return G(SO3<double>(), Vector3d(x, y, z)); }

// Servo with zero gains and the paper's push feedforward; alignment P-only (kp) unless given.
Push::Options simple(double kp_align) {
  Push::Options o;
  o.servo.feedforward = v6(0, 0, 10, 0, 0, 0);
  o.alignment.kp = kp_align;
  o.alignment_cutoff = 120;
  o.termination_radius = 20;
  return o;
}
}  // namespace

TEST_CASE("pushing: bearing sign and distance with the sensor at the reference", "[control][pushing]") {
  Push push(simple(2.0));
  const G X_sf = push.options().servo.reference.inverse();  // at the reference: X_ss' = I
  V6 u = V6::Zero();
  // target ahead and to +y of the sensor
  REQUIRE(push.setTarget(at(0, 100, 300)) == Status::ok);
  REQUIRE(push.step(G::identity(), X_sf, 0.05, u) == Status::ok);
  const double theta = std::atan2(100.0, 300.0);
  CHECK(push.bearing() == Approx(theta));
  CHECK(push.distance() == Approx(std::hypot(100.0, 300.0)));
  CHECK(push.alignmentActive());
  CHECK(u[1] == Approx(-2.0 * theta));  // e = 0 − θ < 0 → slide towards −y
  CHECK(u[2] == Approx(10.0));           // feedforward push
  CHECK(u[0] == 0.0);
  CHECK(u.tail<3>().isZero());
  // mirrored target → mirrored command
  push.reset();
  REQUIRE(push.setTarget(at(0, -100, 300)) == Status::ok);
  REQUIRE(push.step(G::identity(), X_sf, 0.05, u) == Status::ok);
  CHECK(push.bearing() == Approx(-theta));
  CHECK(u[1] == Approx(2.0 * theta));
}

TEST_CASE("pushing: the paper's start geometry with the Table 8 preset", "[control][pushing]") {
  // Work frame: the table is the work yz-plane; the right-angle-mounted sensor points along
  // work +y (z_s = y_w), with y_s = z_w and x_s = −x_w.  Sensor at (y, z) = (−250, 100) mm,
  // target at (0, 375) mm (Section 5.6, sec:single_arm_object_pushing_exp), both at the same height x.
  Eigen::Matrix3d C;
  C << -1, 0, 0,  //
      0, 0, 1,    //
      0, 1, 0;
  const G X_ws(SO3<double>::fromMatrixUnchecked(C), Vector3d(45, -250, 100));
  auto o = pushingPreset<double>(PushingConfiguration::single_arm);
  o.target = at(45, 0, 375);
  Push push(o);
  const G X_sf = o.servo.reference.inverse();
  V6 u = V6::Zero();
  REQUIRE(push.step(X_ws, X_sf, 0.05, u) == Status::ok);
  CHECK(rad2deg(push.bearing()) == Approx(rad2deg(std::atan2(275.0, 250.0))));  // 47.7°
  CHECK(push.distance() == Approx(std::hypot(275.0, 250.0)));                    // 371.7 mm
  CHECK(push.alignmentActive());
  CHECK(u[1] == Approx(-15.0));  // 0.9 mm/s/deg · 47.7° = 43 mm/s, clipped to 15 mm/s
  CHECK(u[2] == Approx(10.0));
  CHECK_FALSE(push.terminated());
}

TEST_CASE("pushing: alignment is zeroed inside rho*", "[control][pushing]") {
  Push push(simple(2.0));
  const G X_sf = push.options().servo.reference.inverse();
  V6 u = V6::Zero();
  REQUIRE(push.setTarget(at(0, 50, 100)) == Status::ok);  // r = 111.8 < 120
  REQUIRE(push.step(G::identity(), X_sf, 0.05, u) == Status::ok);
  CHECK_FALSE(push.alignmentActive());
  CHECK(push.alignment().steps() == 0);  // PID 2 is held, not stepped
  CHECK(u.isApprox(v6(0, 0, 10, 0, 0, 0)));
  CHECK(push.alignmentVelocity().isZero());

  REQUIRE(push.setTarget(at(0, 1, 119)) == Status::ok);
  REQUIRE(push.step(G::identity(), X_sf, 0.05, u) == Status::ok);
  CHECK_FALSE(push.alignmentActive());
  REQUIRE(push.setTarget(at(0, 1, 121)) == Status::ok);
  REQUIRE(push.step(G::identity(), X_sf, 0.05, u) == Status::ok);
  CHECK(push.alignmentActive());
  CHECK(u[1] == Approx(-2.0 * std::atan2(1.0, 121.0)));
}

TEST_CASE("pushing: target is taken into the reference frame and the alignment mapped by Ad(X_ss')",
          "[control][pushing]") {
  Push push(simple(3.0));
  // Sensor off the reference: X_ss' = rotation 20° about x, 2 mm along y.
  const G X_ss = G::fromEulerXYZ6Degrees(v6(0, 2, 0, 20, 0, 0));
  const G X_sf = X_ss * push.options().servo.reference.inverse();
  const G X_ws = G::fromEulerXYZ6Degrees(v6(10, 20, 30, 0, 0, 30));
  const G X_wt = X_ws * at(5, 150, 400);
  REQUIRE(push.setTarget(X_wt) == Status::ok);
  V6 u = V6::Zero();
  REQUIRE(push.step(X_ws, X_sf, 0.05, u) == Status::ok);
  const G X_srt = X_ss.inverse() * X_ws.inverse() * X_wt;  // eq. 21 (eqn:transformed_target_pose)
  CHECK(push.targetInReference().isApprox(X_srt, 1e-9));
  const double y = X_srt.translation()[1], z = X_srt.translation()[2];
  CHECK(push.bearing() == Approx(std::atan2(y, z)));
  CHECK(push.distance() == Approx(std::hypot(y, z)));
  const V6 align_ref = v6(0, -3.0 * std::atan2(y, z), 0, 0, 0, 0);
  CHECK(push.alignmentVelocity().isApprox(X_ss.Ad() * align_ref, 1e-12));
  CHECK(u.isApprox(push.servoVelocity() + X_ss.Ad() * align_ref, 1e-12));
  CHECK(push.servoVelocity().isApprox(X_ss.Ad() * v6(0, 0, 10, 0, 0, 0), 1e-12));
}

TEST_CASE("pushing: termination within the tip radius (latched)", "[control][pushing]") {
  V6 u = V6::Zero();
  {
    Push push(simple(1.0));  // default: distance in the sensor's y–z plane
    const G X_sf = push.options().servo.reference.inverse();
    REQUIRE(push.setTarget(at(30, 5, 10)) == Status::ok);  // yz distance 11.2 < 20, 3-D 32
    REQUIRE(push.step(G::identity(), X_sf, 0.05, u) == Status::ok);
    CHECK(push.terminated());
    CHECK(u.isZero());
    CHECK(push.terminationDistance() == Approx(std::hypot(5.0, 10.0)));
    // latched: moving away does not restart the push
    REQUIRE(push.step(at(0, 0, -500), X_sf, 0.05, u) == Status::ok);
    CHECK(push.terminated());
    CHECK(u.isZero());
    REQUIRE(push.setTarget(at(0, 0, 400)) == Status::ok);  // a new target clears the latch
    REQUIRE(push.step(G::identity(), X_sf, 0.05, u) == Status::ok);
    CHECK_FALSE(push.terminated());
    CHECK(u[2] == Approx(10.0));
  }
  {
    auto o = simple(1.0);
    o.termination_distance = TerminationDistance::euclidean;
    Push push(o);
    const G X_sf = push.options().servo.reference.inverse();
    REQUIRE(push.setTarget(at(30, 5, 10)) == Status::ok);
    REQUIRE(push.step(G::identity(), X_sf, 0.05, u) == Status::ok);
    CHECK_FALSE(push.terminated());
    CHECK(push.terminationDistance() == Approx(std::sqrt(30.0 * 30 + 5 * 5 + 10 * 10)));
    REQUIRE(push.setTarget(at(3, 5, 10)) == Status::ok);
    REQUIRE(push.step(G::identity(), X_sf, 0.05, u) == Status::ok);
    CHECK(push.terminated());
  }
}

TEST_CASE("pushing: invalid input leaves everything unchanged", "[control][pushing]") {
  auto o = pushingPreset<double>(PushingConfiguration::dual_arm_leader);
  o.target = at(0, 200, 400);
  Push push(o);
  const G X_sf = G::fromEulerXYZ6Degrees(v6(1, 0, 0, 3, 0, 0)).inverse();
  V6 u = V6::Zero();
  REQUIRE(push.step(G::identity(), X_sf, 0.05, u) == Status::ok);
  const V6 u0 = u;
  const double b0 = push.bearing(), i0 = push.alignment().integral();
  const V6 si0 = push.servo().pid().integral();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CHECK(push.step(G::identity(), X_sf, 0.0, u) == Status::invalid_time_step);
  CHECK(push.step(G::identity(), X_sf, nan, u) == Status::invalid_time_step);
  const G bad(G::SO3Type(), G::Vector3(nan, 0, 0));
  CHECK(push.step(G::identity(), bad, 0.05, u) == Status::non_finite_input);
  CHECK(push.step(bad, X_sf, 0.05, u) == Status::non_finite_input);
  // A rotation block scaled by 1.01: finite, but not a rotation.
  G::Matrix M = X_sf.matrix();
  M.topLeftCorner<3, 3>() *= 1.01;
  const G skewed = G::fromMatrixUnchecked(M);
  CHECK(push.step(G::identity(), skewed, 0.05, u) == Status::not_orthonormal);
  CHECK(push.step(skewed, X_sf, 0.05, u) == Status::not_orthonormal);
  CHECK(u == u0);
  CHECK(push.bearing() == b0);
  CHECK(push.alignment().integral() == i0);
  CHECK(push.servo().pid().integral() == si0);
}

TEST_CASE("pushing: a non-orthonormal target or reference is refused and changes nothing",
          "[control][pushing]") {
  auto o = pushingPreset<double>(PushingConfiguration::single_arm);
  o.target = at(0, 200, 400);
  Push push(o);
  G::Matrix M = at(0, 100, 300).matrix();
  M(0, 1) += 0.02;  // shear the rotation block
  const G skewed = G::fromMatrixUnchecked(M);
  CHECK(push.setTarget(skewed) == Status::not_orthonormal);
  CHECK(push.options().target.matrix() == o.target.matrix());
  CHECK(push.setReference(skewed) == Status::not_orthonormal);
  CHECK(push.options().servo.reference.matrix() == o.servo.reference.matrix());
  auto bad = o;
  bad.target = skewed;
  CHECK(Push::validate(bad) == Status::not_orthonormal);  // as setTarget
  CHECK(push.configure(bad) == Status::not_orthonormal);
  CHECK(push.options().target.matrix() == o.target.matrix());
}

TEST_CASE("pushing: wrapAngle", "[control][pushing]") {
  const double p = pi<double>();
  CHECK(Push::wrapAngle(0.5) == Approx(0.5));
  CHECK(Push::wrapAngle(2 * p + 0.25) == Approx(0.25));
  CHECK(Push::wrapAngle(-p) == Approx(p));
  CHECK(Push::wrapAngle(-1.5 * p) == Approx(0.5 * p));
}

TEST_CASE("pushing: a TerminationDistance outside the enum is refused", "[control][pushing]") {
  Push::Options o = simple(2.0);
  o.termination_distance = static_cast<TerminationDistance>(7);
  CHECK(Push::validate(o) == Status::invalid_argument);
  Push push;
  CHECK(push.configure(o) == Status::invalid_argument);
  CHECK(push.options().termination_distance == TerminationDistance::sensor_yz_plane);
}

TEST_CASE("pushing: a numerical failure after the alignment PID stepped leaves both PIDs as they were",
          "[control][pushing]") {
  // The servo's feedforward and the alignment's output are each finite and large along y of the
  // reference frame; their sum overflows. The alignment PID has stepped by then.
  Push::Options o = simple(1e308);
  o.servo.feedforward = v6(0, -1.7e308, 0, 0, 0, 0);
  Push push(o);
  REQUIRE(push.configurationStatus() == Status::ok);
  const G X_sf = push.options().servo.reference.inverse();
  V6 u = V6::Zero();
  REQUIRE(push.setTarget(at(0, 0, 300)) == Status::ok);  // straight ahead: θ = 0, u_y = 0
  REQUIRE(push.step(G::identity(), X_sf, 0.05, u) == Status::ok);
  REQUIRE(push.alignment().steps() == 1);
  const double smoothed = push.alignment().smoothedError();
  const long servo_steps = push.servo().pid().steps();
  REQUIRE(push.setTarget(at(0, 300, 0)) == Status::ok);  // θ = 90°: u_y = −1.57e308
  const V6 u_before = u;
  CHECK(push.step(G::identity(), X_sf, 0.05, u) == Status::numerical_failure);
  CHECK(push.alignment().steps() == 1);
  CHECK(push.alignment().smoothedError() == smoothed);
  CHECK(push.servo().pid().steps() == servo_steps);
  CHECK(u == u_before);
}

// Kinematic arm: body-twist integration by right multiplication, limits, bad inputs.
#include <catch2/catch.hpp>

#include "lieservo_sim/simulated_arm.hpp"

using namespace lieservo::sim;

namespace {
ArmLimits fastLimits() {
  ArmLimits l;
  l.max_linear_accel = 1e9;
  l.max_angular_accel = 1e9;
  l.substeps = 10;
  return l;
}
}  // namespace

TEST_CASE("arm: a constant body twist integrates as X0 exp(u t) (right multiplication)", "[sim][arm]") {
  const SE3d X0 = makePose(eulerToMatrix(0.4, -0.3, 1.2), Vec3(100, -50, 20));
  SimulatedArm arm(X0, fastLimits());
  Vec6 u;
  u << 10, -5, 2, 0.1, 0.2, -0.3;
  for (int k = 0; k < 20; ++k) REQUIRE(arm.commandVelocity(u, 0.05) == lieservo::Status::ok);
  const SE3d expected = X0 * SE3d::exp(u * 1.0);
  SE3d X;
  arm.readPose(X);
  CHECK((X.translation() - expected.translation()).norm() == Approx(0).margin(1e-6));
  CHECK((X.rotationMatrix() - expected.rotationMatrix()).norm() == Approx(0).margin(1e-9));
  // Left multiplication would differ:
  const SE3d left = SE3d::exp(u * 1.0) * X0;
  CHECK((X.translation() - left.translation()).norm() > 1.0);
}

TEST_CASE("arm: speed and acceleration limits", "[sim][arm]") {
  ArmLimits l;
  l.max_linear_speed = 100;
  l.max_linear_accel = 500;
  SimulatedArm arm(SE3d::identity(), l);
  Vec6 u = Vec6::Zero();
  u[0] = 1000;
  arm.commandVelocity(u, 0.05);
  CHECK(arm.velocity().head<3>().norm() == Approx(25).epsilon(1e-9));  // 500 mm/s² × 0.05 s
  for (int k = 0; k < 20; ++k) arm.commandVelocity(u, 0.05);
  CHECK(arm.velocity().head<3>().norm() == Approx(100));
  arm.stop();
  CHECK(arm.velocity().norm() == 0);
}

TEST_CASE("arm: invalid commands leave the pose unchanged", "[sim][arm]") {
  SimulatedArm arm(SE3d::identity());
  Vec6 u = Vec6::Ones();
  CHECK(arm.commandVelocity(u, 0.0) == lieservo::Status::invalid_time_step);
  CHECK(arm.commandVelocity(u, -1.0) == lieservo::Status::invalid_time_step);
  u[2] = std::nan("");
  CHECK(arm.commandVelocity(u, 0.05) == lieservo::Status::non_finite_input);
  CHECK(arm.pose().translation().norm() == 0);
  const SE3d target = makePose(rotZ(0.5), Vec3(1, 2, 3));
  CHECK(arm.moveTo(target) == lieservo::Status::ok);
  CHECK((arm.pose().translation() - Vec3(1, 2, 3)).norm() == 0);
}

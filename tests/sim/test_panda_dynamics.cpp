// The simulated Panda's dynamics (examples/sim panda_dynamics.hpp): MuJoCo's model of the arm
// against the kinematic chain it is built from, its joint controller's tracking in free motion,
// its static stiffness against the joint-space statics of a load, braking, and bad input.
// Bounds written before the first run.
#include <catch2/catch.hpp>

#include <cmath>
#include <stdexcept>

#include <lieservo/sampling/random.hpp>
#include <lieservo_sim/panda_dynamics.hpp>

#include "test_support.hpp"

using namespace lieservo::sim::panda;

namespace {

constexpr double kPi = 3.14159265358979323846;

Eigen::Matrix3d hat(const Eigen::Vector3d& r) {
  Eigen::Matrix3d R;
  R << 0, -r.z(), r.y(), r.z(), 0, -r.x(), -r.y(), r.x(), 0;
  return R;
}

}  // namespace

TEST_CASE("panda dynamics: MuJoCo's model has the kinematic chain's flange", "[sim][robot][panda]") {
  // 200 seeded configurations inside the limits: MuJoCo's flange pose equals flange(q) to 1e-12
  // (rotation entries and metres).
  lieservo::sampling::Rng rng(20261128);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double worst = 0;
  for (int n = 0; n < 200; ++n) {
    Joints q;
    for (int i = 0; i < kJoints; ++i) q[i] = lowerLimits()[i] + u(rng) * (upperLimits()[i] - lowerLimits()[i]);
    const PandaDynamics arm(q);
    worst = std::max(worst, (arm.flangePose() - flange(q)).cwiseAbs().maxCoeff());
  }
  INFO("worst entry difference " << worst);
  CHECK(worst <= 1e-12);
}

TEST_CASE("panda dynamics: the joint controller tracks a smooth motion and settles", "[sim][robot][panda]") {
  // From the ready pose, every joint commanded q̇_d = 0.3 sin(2π t / 2 s) rad/s for 2 s, then
  // rest for 0.5 s. Bounds: |q_d − q| ≤ 2e-3 rad throughout (the PD law lags by the inertia's
  // torque over kp: about 1e-3 rad at the shoulder), torques inside the limits; after the rest,
  // |q_d − q| and |q̇| ≤ 1e-6 (no gravity, no load: q_d is an equilibrium).
  PandaDynamics arm(readyPose());
  double max_lag = 0, max_torque = 0;
  for (int k = 0; k < 2000; ++k) {
    const double t = k * PandaDynamics::kStep;
    arm.step(Joints::Constant(0.3 * std::sin(2 * kPi * t / 2.0)));
    max_lag = std::max(max_lag, arm.trackingError().cwiseAbs().maxCoeff());
    max_torque = std::max(max_torque, (arm.torques().cwiseAbs().array() / torqueLimits().array()).maxCoeff());
  }
  for (int k = 0; k < 500; ++k) arm.step(Joints::Zero());
  INFO("max lag " << max_lag << " rad, max torque " << max_torque << " of the limits");
  CHECK(max_lag <= 2e-3);
  CHECK(max_torque < 1.0);
  CHECK(arm.trackingError().cwiseAbs().maxCoeff() <= 1e-6);
  CHECK(arm.dq().cwiseAbs().maxCoeff() <= 1e-6);
  CHECK(arm.q().allFinite());
}

TEST_CASE("panda dynamics: a load deflects the joints by the controller's stiffness", "[sim][robot][panda]") {
  // 10 N along x, y and z of {O} at the sensor's tip (100 mm beyond the flange along its z),
  // held for 1 s with no motion commanded: at equilibrium kp (q_d − q) balances the load's joint
  // torques J_pᵀ f (J_p the tip point's translational Jacobian), so q − q_d = kp⁻¹ J_pᵀ f within
  // 1 % of its norm (J_p taken at the ready pose; the deflection changes it by ~1e-3).
  const JointServoGains gains;
  const Jacobian J = jacobian(readyPose());
  const Eigen::Matrix4d F = flange(readyPose());
  const Eigen::Vector3d r = F.topLeftCorner<3, 3>() * Eigen::Vector3d(0, 0, 0.1);
  const Eigen::Matrix<double, 3, kJoints> Jp = J.topRows<3>() - hat(r) * J.bottomRows<3>();
  const Eigen::Vector3d tip = F.topRightCorner<3, 1>() + r;
  for (int axis = 0; axis < 3; ++axis) {
    PandaDynamics arm(readyPose());
    const Eigen::Vector3d f = 10.0 * Eigen::Vector3d::Unit(axis);
    arm.setLoad(f, tip);
    for (int k = 0; k < 1000; ++k) arm.step(Joints::Zero());
    const Joints expected = (Jp.transpose() * f).cwiseQuotient(gains.kp);
    const Joints deflection = -arm.trackingError();
    INFO("axis " << axis << ": deflection " << deflection.transpose() << ", statics " << expected.transpose());
    CHECK((deflection - expected).norm() <= 0.01 * expected.norm());
    CHECK(arm.dq().cwiseAbs().maxCoeff() <= 1e-6);
  }
}

TEST_CASE("panda dynamics: brake, and bad input refused with the state kept", "[sim][robot][panda]") {
  PandaDynamics arm(readyPose()), twin(readyPose());
  for (int k = 0; k < 100; ++k) {
    arm.step(Joints::Constant(0.2));
    twin.step(Joints::Constant(0.2));
  }
  REQUIRE(arm.dq().norm() > 0.1);
  // Braking: at rest where it is, the desired trajectory there too.
  const Joints q_before = arm.q();
  arm.brake();
  CHECK(arm.q() == q_before);
  CHECK(arm.dq() == Joints::Zero());
  CHECK(arm.trackingError() == Joints::Zero());
  twin.brake();
  // A non-finite load is refused and changes nothing: the twins stay bitwise equal.
  const double nan = std::nan("");
  CHECK_THROWS_AS(arm.setLoad(Eigen::Vector3d(nan, 0, 0), Eigen::Vector3d::Zero()), std::invalid_argument);
  CHECK_THROWS_AS(arm.setLoad(Eigen::Vector3d::Zero(), Eigen::Vector3d(0, HUGE_VAL, 0)), std::invalid_argument);
  for (int k = 0; k < 100; ++k) {
    arm.step(Joints::Constant(-0.1));
    twin.step(Joints::Constant(-0.1));
  }
  CHECK(arm.q() == twin.q());
  CHECK(arm.dq() == twin.dq());
  // A start outside the joint limits, or gains that are not a stable PD law.
  Joints outside = readyPose();
  outside[3] = 0.1;  // joint 4's upper limit is −0.0698 rad
  CHECK_THROWS_AS(PandaDynamics(outside), std::invalid_argument);
  CHECK_THROWS_AS(PandaDynamics(Joints::Constant(nan)), std::invalid_argument);
  JointServoGains bad;
  bad.kp[2] = 0;
  CHECK_THROWS_AS(PandaDynamics(readyPose(), bad), std::invalid_argument);
  bad = JointServoGains{};
  bad.kd[6] = -1;
  CHECK_THROWS_AS(PandaDynamics(readyPose(), bad), std::invalid_argument);
}

// No heap allocation per control step: counting (tests/support/allocation_counter.hpp) is
// switched on only around the controller steps.
#include <catch2/catch.hpp>

#include <cmath>
#include <new>

#include "allocation_counter.hpp"

#include <lieservo/control.hpp>
#include <lieservo/groups/se2.hpp>
#include <lieservo/groups/so2.hpp>
#include <lieservo/groups/so3.hpp>
#include <lieservo/units.hpp>

using AllocationWindow = lieservo::test::AllocationCounter;

using namespace lieservo;
using G = SE3<double>;
using V6 = G::Tangent;

TEST_CASE("no allocation: the counter works", "[control][alloc]") {
  long n = 0;
  {
    AllocationWindow w;
    void* volatile p = ::operator new(16);  // an explicit call: not elided
    ::operator delete(p);
    n = w.count();
  }
  CHECK(n == 1);
}

TEST_CASE("no allocation per step: PIDs and servo controllers on every group", "[control][alloc]") {
  const int steps = 5000;
  MimoPid<double, 6> mimo(paperMimoPid<double>(paper::kStabiliser));
  SisoPid<double> siso(paperAlignmentPid<double>(true));
  TactileServoController<G> servo(surfaceFollowingPreset<double>());
  TactileServoController<SE2<double>> servo2;
  TactileServoController<SO3<double>> servo3;
  TactileServoController<SO2<double>> servo1;
  int failures = 0;
  long allocations = 0;
  {
    AllocationWindow w;
    for (int k = 0; k < steps; ++k) {
      const double t = 0.001 * k;
      V6 e = V6::Zero();
      for (int i = 0; i < 6; ++i) e[i] = std::sin(t + i);
      V6 u = V6::Zero();
      failures += mimo.step(e, V6::Zero(), 0.001, u) != Status::ok;
      double uy = 0;
      failures += siso.step(e[0], 0.0, 0.001, uy) != Status::ok;
      failures += servo.step(G::exp(0.1 * e), 0.001, u) != Status::ok;
      SE2<double>::Tangent u2 = SE2<double>::Tangent::Zero();
      failures += servo2.step(SE2<double>::exp(e.head<3>()), 0.001, u2) != Status::ok;
      SO3<double>::Tangent u3 = SO3<double>::Tangent::Zero();
      failures += servo3.step(SO3<double>::exp(0.5 * e.tail<3>()), 0.001, u3) != Status::ok;
      SO2<double>::Tangent u1 = SO2<double>::Tangent::Zero();
      failures += servo1.step(SO2<double>::exp(e.head<1>()), 0.001, u1) != Status::ok;
      // failing steps must not allocate either
      failures += servo.step(G::exp(e), -1.0, u) == Status::ok;
    }
    allocations = w.count();
  }
  CHECK(failures == 0);
  CHECK(allocations == 0);
}

TEST_CASE("no allocation per step: pushing and dual-arm pushing with filters", "[control][alloc]") {
  const int steps = 3000;
  auto po = pushingPreset<double>(PushingConfiguration::single_arm);
  po.target = G(SO3<double>(), Eigen::Vector3d(0, 200, 600));
  PushingController<SE3d> push(po);
  auto dopts = dualArmPushingPreset<double>(true);
  dopts.leader.target = G(SO3<double>(), Eigen::Vector3d(0, 100, 1e4));
  DualArmPushing<SE3d> dual(dopts, DiscriminativeBayesFilter<G>(), DiscriminativeBayesFilter<G>());
  auto copts = centralisedDualArmPushingPreset<double>(true);
  copts.arms = dopts;
  copts.opposition_gain = 100;  // the opposition term runs too (the presets leave it at 0)
  CentralisedDualArmPushing<SE3d> central(copts, DiscriminativeBayesFilter<G>(), DiscriminativeBayesFilter<G>());
  const G X_ofF(SO3<double>::fromEulerXYZ(pi<double>(), 0, 0), Eigen::Vector3d(0, 0, 60));
  G X_wsL = dopts.leader.servo.reference, X_wsF = X_ofF * dopts.follower.reference, X_wo;
  G::Jacobian cov = G::Jacobian::Identity() * 0.01;
  int failures = 0;
  long allocations = 0;
  {
    AllocationWindow w;
    for (int k = 0; k < steps; ++k) {
      V6 n = V6::Zero();
      for (int i = 0; i < 6; ++i) n[i] = 0.01 * std::sin(0.7 * k + i);
      V6 u = V6::Zero();
      // pushing: alternate far (alignment active) and near (cut-off) geometries
      const G X_ws = G(SO3<double>(), Eigen::Vector3d(0, 0, (k % 2) ? 0.0 : 550.0));
      failures += push.step(X_ws, G::exp(n) * po.servo.reference.inverse(), 0.02, u) != Status::ok;
      DualArmPushing<SE3d>::ArmInput inL{X_wsL, {G::exp(n) * X_wsL.inverse() * X_wo, cov}};
      DualArmPushing<SE3d>::ArmInput inF{X_wsF, {G::exp(-n) * X_wsF.inverse() * X_wo * X_ofF, cov}};
      DualArmPushing<SE3d>::ArmOutput outL, outF;
      failures += dual.step(inL, inF, 0.02, outL, outF) != Status::ok;
      failures += central.step(inL, inF, 0.02, outL, outF) != Status::ok;
      X_wsL = X_wsL * G::exp(0.02 * outL.velocity);
      X_wsF = X_wsF * G::exp(0.02 * outF.velocity);
      X_wo = X_wo * G::exp(0.02 * (V6() << 0, 0, 10, 0, 0, 0).finished());
    }
    // termination path
    auto near = po;
    near.target = G(SO3<double>(), Eigen::Vector3d(0, 1, 5));
    failures += push.configure(near) != Status::ok;
    failures += push.setTarget(near.target) != Status::ok;
    V6 u = V6::Zero();
    failures += push.step(G::identity(), po.servo.reference.inverse(), 0.02, u) != Status::ok;
    failures += !push.terminated();
    allocations = w.count();
  }
  CHECK(failures == 0);
  CHECK(allocations == 0);
}

TEST_CASE("no allocation per step: the tactile loop, commanded, gated and refused", "[control][alloc][loop]") {
  TactileLoop<PushingController<SE3d>>::Options o;
  o.filter.gating = true;
  o.controller = pushingPreset<double>(PushingConfiguration::single_arm);
  o.controller.target = G(SO3<double>(), Eigen::Vector3d(0, 200, 600));
  TactileLoop<PushingController<SE3d>> loop(o);
  TactileLoop<TactileServoController<G>> servo_loop({{}, surfaceFollowingPreset<double>()});
  ConcentratedGaussian<G> obs(o.controller.servo.reference.inverse(), G::Jacobian::Identity() * 0.01);
  int failures = 0, gated = 0;
  long allocations = 0;
  {
    AllocationWindow w;
    for (int k = 0; k < 3000; ++k) {
      V6 n = V6::Zero();
      for (int i = 0; i < 6; ++i) n[i] = 0.01 * std::sin(0.7 * k + i);
      if (k % 100 == 50) n[1] += 30;  // the gate rejects it
      const ConcentratedGaussian<G> g(G::exp(n) * obs.mean, obs.covariance);
      V6 u = V6::Zero();
      failures += loop.step(G(), g, 0.02, u) != Status::ok;
      gated += loop.outcome() == LoopOutcome::gated;
      failures += servo_loop.step(G(), g, 0.02, u) != Status::ok;
      failures += loop.step(G(), g, -1.0, u) == Status::ok;  // refused steps must not allocate either
    }
    allocations = w.count();
  }
  CHECK(failures == 0);
  CHECK(gated == 30);
  CHECK(allocations == 0);
}

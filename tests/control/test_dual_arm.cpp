// DualArmPushing (Section 3.3.4, sec:single_dual_arm_controllers, Section 5.7 (sec:dual_arm_object_pushing_exp)):
// equivalence with hand-wired filters and controllers, a closed loop with both filters
// pushing a rigid object (tall-object references), termination, and the Status contract.
#include <catch2/catch.hpp>

#include "control_test_util.hpp"

#include <cmath>
#include <limits>

#include <lieservo/control/dual_arm.hpp>
#include <lieservo/units.hpp>

using namespace lieservo;
using G = SE3<double>;
using V6 = G::Tangent;
using M6 = G::Jacobian;
using Filter = DiscriminativeBayesFilter<G>;
using Dual = DualArmPushing<SE3d>;

namespace {
using lieservo::test::v6;

// Observation covariance: 0.2 mm and 0.5° standard deviations.
M6 obsCov() {
  V6 s = v6(0.2, 0.2, 0.2, deg2rad(0.5), deg2rad(0.5), deg2rad(0.5));
  return M6(s.cwiseProduct(s).asDiagonal());
}

// A deterministic, pseudo-random perturbation of a pose (observation "noise").
G perturb(const G& X, int k, double scale) {
  V6 n = V6::Zero();
  for (int i = 0; i < 6; ++i) n[i] = std::sin(1.7 * k + 2.3 * i) * (i < 3 ? 0.1 : deg2rad(0.2)) * scale;
  return G::exp(n) * X;
}

// Rigid object pushed along its leader-face normal.  Leader face {fL} at the object origin,
// z into the object; follower face {fF} on the opposite side (width 60 mm), z into the object.
struct Scene {
  G X_wo = G::identity();
  G X_ofL = G::identity();
  G X_ofF = G(SO3<double>::fromEulerXYZ(pi<double>(), 0, 0), Eigen::Vector3d(0, 0, 60));
  G X_wsL, X_wsF;
  Scene(const Dual::Options& o) {
    // start both sensors off their references
    X_wsL = X_wo * X_ofL * o.leader.servo.reference * G::exp(-v6(1.5, 0, 0, deg2rad(4), 0, 0));
    X_wsF = X_wo * X_ofF * o.follower.reference * G::exp(-v6(-1, 0, 1.5, deg2rad(-3), 0, 0));
  }
  G featureL() const { return X_wsL.inverse() * X_wo * X_ofL; }
  G featureF() const { return X_wsF.inverse() * X_wo * X_ofF; }
  void advance(const V6& uL, const V6& uF, double dt, double push_speed) {
    X_wsL = X_wsL * G::exp(dt * uL);
    X_wsF = X_wsF * G::exp(dt * uF);
    X_wo = X_wo * G::exp(dt * v6(0, 0, push_speed, 0, 0, 0));
  }
};
// The pose with its rotation scaled by 1.01: not orthonormal.
G skewed(const G& X) {
  G::Matrix M = X.matrix();
  M.topLeftCorner<3, 3>() *= 1.01;
  return G::fromMatrixUnchecked(M);
}

// Three good steps of either dual-arm controller, pushing the scene along.
template <class Controller>
void warmUp(Controller& c, Scene& scene, Dual::ArmOutput& outL, Dual::ArmOutput& outF) {
  for (int k = 0; k < 3; ++k) {
    Dual::ArmInput inL{scene.X_wsL, {scene.featureL(), obsCov()}};
    Dual::ArmInput inF{scene.X_wsF, {scene.featureF(), obsCov()}};
    REQUIRE(c.step(inL, inF, 0.05, outL, outF) == Status::ok);
    scene.advance(outL.velocity, outF.velocity, 0.05, 10);
  }
}
}  // namespace

TEST_CASE("dual arm: equals two hand-wired filter + controller pairs", "[control][dual_arm]") {
  auto o = dualArmPushingPreset<double>(false);
  o.leader.target = G(SO3<double>(), Eigen::Vector3d(0, 150, 900));
  Dual dual(o, Filter(), Filter());
  REQUIRE(dual.configurationStatus() == Status::ok);
  Filter fL, fF;
  PushingController<SE3d> leader(o.leader);
  TactileServoController<G> follower(o.follower);
  Scene scene(o);
  const double dt = 1.0 / 30.0;
  for (int k = 0; k < 150; ++k) {
    Dual::ArmInput inL{scene.X_wsL, {perturb(scene.featureL(), k, 1), obsCov()}};
    Dual::ArmInput inF{scene.X_wsF, {perturb(scene.featureF(), k + 7, 1), obsCov()}};
    Dual::ArmOutput outL, outF;
    REQUIRE(dual.step(inL, inF, dt, outL, outF) == Status::ok);
    // by hand
    REQUIRE(fL.step(inL.sensor_pose, inL.observation) == Status::ok);  // k = 0: initialisation
    REQUIRE(fF.step(inF.sensor_pose, inF.observation) == Status::ok);
    V6 uL = V6::Zero(), uF = V6::Zero();
    REQUIRE(leader.step(inL.sensor_pose, fL.filtered().mean, dt, uL) == Status::ok);
    REQUIRE(follower.step(fF.filtered().mean, dt, uF) == Status::ok);
    CHECK(outL.velocity == uL);
    CHECK(outF.velocity == uF);
    CHECK(outL.feature_in_sensor.isApprox(fL.filtered().mean, 0));
    scene.advance(uL, uF, dt, 10.0);
  }
}

TEST_CASE("dual arm: closed loop with filters converges to the tall-object references",
          "[control][dual_arm]") {
  for (double rate : {30.0, 250.0}) {
    auto o = dualArmPushingPreset<double>(true);
    CHECK(o.leader.servo.reference.isApprox(G::fromEulerXYZ6Degrees(v6(0.5, 0, 0, 0, 0, 0)), 1e-15));
    CHECK(o.follower.reference.isApprox(G::fromEulerXYZ6Degrees(v6(-0.5, 0, 3, 0, 0, 0)), 1e-15));
    o.leader.target = G(SO3<double>(), Eigen::Vector3d(0, 0, 1e5));  // straight ahead
    Dual dual(o, Filter(), Filter());
    Scene scene(o);
    const double dt = 1.0 / rate;
    const long n = static_cast<long>(20.0 * rate);
    Dual::ArmOutput outL, outF;
    for (long k = 0; k < n; ++k) {
      Dual::ArmInput inL{scene.X_wsL, {perturb(scene.featureL(), int(k), 0.2), obsCov()}};
      Dual::ArmInput inF{scene.X_wsF, {perturb(scene.featureF(), int(k) + 3, 0.2), obsCov()}};
      REQUIRE(dual.step(inL, inF, dt, outL, outF) == Status::ok);
      scene.advance(outL.velocity, outF.velocity, dt, 10.0);
    }
    // controlled channels: leader x, α (Table 8 PID 1); follower x, z, α (Table 9)
    const V6 eL = (scene.featureL() * o.leader.servo.reference).log();
    const V6 eF = (scene.featureF() * o.follower.reference).log();
    INFO("rate " << rate << " Hz, leader e = " << eL.transpose() << ", follower e = " << eF.transpose());
    CHECK(std::abs(eL[0]) < 0.1);
    CHECK(std::abs(eL[3]) < deg2rad(0.3));
    CHECK(std::abs(eF[0]) < 0.1);
    CHECK(std::abs(eF[2]) < 0.1);
    CHECK(std::abs(eF[3]) < deg2rad(0.3));
    CHECK_FALSE(dual.terminated());
  }
}

TEST_CASE("dual arm: termination stops both arms", "[control][dual_arm]") {
  auto o = dualArmPushingPreset<double>(false);
  Scene scene(o);
  o.leader.target = scene.X_wsL * G(SO3<double>(), Eigen::Vector3d(0, 3, 10));  // within 20 mm
  Dual dual(o, Filter(), Filter());
  Dual::ArmInput inL{scene.X_wsL, {scene.featureL(), obsCov()}};
  Dual::ArmInput inF{scene.X_wsF, {scene.featureF(), obsCov()}};
  Dual::ArmOutput outL, outF;
  outF.velocity.setOnes();
  REQUIRE(dual.step(inL, inF, 0.05, outL, outF) == Status::ok);
  CHECK(dual.terminated());
  CHECK(outL.velocity.isZero());
  CHECK(outF.velocity.isZero());
}

TEST_CASE("dual arm: failures leave filters, controllers and outputs unchanged", "[control][dual_arm]") {
  auto o = dualArmPushingPreset<double>(false);
  o.leader.target = G(SO3<double>(), Eigen::Vector3d(0, 100, 800));
  Dual dual(o, Filter(), Filter());
  Scene scene(o);
  Dual::ArmOutput outL, outF;
  warmUp(dual, scene, outL, outF);
  const V6 uL0 = outL.velocity, uF0 = outF.velocity;
  const G filL0 = dual.leaderFilter().filtered().mean, filF0 = dual.followerFilter().filtered().mean;
  const V6 iL0 = dual.leader().servo().pid().integral(), iF0 = dual.follower().pid().integral();
  Dual::ArmInput inL{scene.X_wsL, {scene.featureL(), obsCov()}};
  Dual::ArmInput inF{scene.X_wsF, {scene.featureF(), obsCov()}};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CHECK(dual.step(inL, inF, 0.0, outL, outF) == Status::invalid_time_step);
  CHECK(dual.step(inL, inF, nan, outL, outF) == Status::invalid_time_step);
  // the follower's observation is bad: the leader filter already stepped must be rolled back
  Dual::ArmInput badF = inF;
  badF.observation.covariance(2, 2) = nan;
  CHECK(dual.step(inL, badF, 0.05, outL, outF) != Status::ok);
  CHECK(outL.velocity == uL0);
  CHECK(outF.velocity == uF0);
  CHECK(dual.leaderFilter().filtered().mean.isApprox(filL0, 0));
  CHECK(dual.followerFilter().filtered().mean.isApprox(filF0, 0));
  CHECK(dual.leader().servo().pid().integral() == iL0);
  CHECK(dual.follower().pid().integral() == iF0);
  // a non-orthonormal sensor pose is refused the same way
  Dual::ArmInput skewedL = inL;
  skewedL.sensor_pose = skewed(inL.sensor_pose);
  CHECK(dual.step(skewedL, inF, 0.05, outL, outF) == Status::not_orthonormal);
  CHECK(outL.velocity == uL0);
  CHECK(dual.leaderFilter().filtered().mean.isApprox(filL0, 0));
  CHECK(dual.setReferences(skewedL.sensor_pose, o.follower.reference) == Status::not_orthonormal);
  CHECK(dual.leader().options().servo.reference.matrix() == o.leader.servo.reference.matrix());
  // and the next good step works
  CHECK(dual.step(inL, inF, 0.05, outL, outF) == Status::ok);
  // reset() clears both filters: the next step initialises them again
  dual.reset();
  CHECK(!dual.leaderFilter().initialised());
  CHECK(!dual.followerFilter().initialised());
  CHECK(dual.step(inL, inF, 0.05, outL, outF) == Status::ok);
  CHECK(dual.leaderFilter().diagnostics().corrections == 1);
}

// ---- CentralisedDualArmPushing (Section 3.3.4, sec:single_dual_arm_controllers: the centralised
// alternative): the decentralised twists plus the follower's feedforward from both poses.
#include <lieservo/control/centralised_dual_arm.hpp>

namespace {
using Central = CentralisedDualArmPushing<SE3d>;

// The expected centralised feedforward, written out from the header's formulas.
V6 expectedFeedforward(const G& X_wL, const G& X_wF, const V6& uL, double k, double vmax) {
  const Eigen::Matrix3d R_FL = X_wF.rotationMatrix().transpose() * X_wL.rotationMatrix();
  Eigen::Vector3d v(k * R_FL(0, 2), k * R_FL(1, 2), 0);
  if (v.norm() > vmax) v *= vmax / v.norm();
  V6 u = V6::Zero();
  u.head<3>() = v + R_FL.col(2) * uL[2];
  return u;
}
}  // namespace

TEST_CASE("centralised dual arm: the decentralised twists plus the push and the opposition velocity",
          "[control][dual_arm][centralised]") {
  auto o = centralisedDualArmPushingPreset<double>(false);
  o.arms.leader.target = G(SO3<double>(), Eigen::Vector3d(0, 150, 900));
  Central central(o, Filter(), Filter());
  Dual dual(o.arms, Filter(), Filter());
  REQUIRE(central.configurationStatus() == Status::ok);
  Scene scene(o.arms);
  // The follower turned 8° about its x axis off the opposite pose: the opposition term acts
  // (and is clipped at 20 mm/s for a gain of 400 mm/s per rad: 28 mm/s).
  scene.X_wsF = scene.X_wsF * G(SO3<double>::fromEulerXYZ(deg2rad(8), deg2rad(3), 0), Eigen::Vector3d::Zero());
  for (double gain : {100.0, 400.0}) {
    o.opposition_gain = gain;
    REQUIRE(central.configure(o) == Status::ok);
    const double dt = 0.05;
    for (int k = 0; k < 40; ++k) {
      Dual::ArmInput inL{scene.X_wsL, {perturb(scene.featureL(), k, 1), obsCov()}};
      Dual::ArmInput inF{scene.X_wsF, {perturb(scene.featureF(), k + 7, 1), obsCov()}};
      Dual::ArmOutput cL, cF, dL, dF;
      REQUIRE(central.step(inL, inF, dt, cL, cF) == Status::ok);
      REQUIRE(dual.step(inL, inF, dt, dL, dF) == Status::ok);
      CHECK(cL.velocity == dL.velocity);
      const V6 ff = expectedFeedforward(inL.sensor_pose, inF.sensor_pose, dL.velocity, gain, o.max_opposition_speed);
      CHECK((cF.velocity - (dF.velocity + ff)).norm() < 1e-12 * (1 + ff.norm()));
      CHECK((central.followerFeedforward() - ff).norm() < 1e-12 * (1 + ff.norm()));
      const Eigen::Matrix3d R_FL = inF.sensor_pose.rotationMatrix().transpose() * inL.sensor_pose.rotationMatrix();
      const Eigen::Vector3d v_op = central.followerFeedforward().head<3>() - R_FL.col(2) * dL.velocity[2];
      CHECK(v_op.norm() <= o.max_opposition_speed + 1e-12);
      if (k == 0) CHECK(v_op.norm() > 0.5 * std::min(o.max_opposition_speed, gain * deg2rad(8)));  // it acts
      scene.advance(cL.velocity, dF.velocity, dt, 10.0);
    }
  }
}

TEST_CASE("centralised dual arm: an enormous opposition gain is clipped, not overflowed to zero",
          "[control][dual_arm][centralised]") {
  auto o = centralisedDualArmPushingPreset<double>(false);
  o.arms.leader.target = G(SO3<double>(), Eigen::Vector3d(0, 150, 900));
  o.opposition_gain = 1e200;  // k_op |a| overflows to +inf for any misalignment
  Central central(o, Filter(), Filter());
  REQUIRE(central.configurationStatus() == Status::ok);
  Scene scene(o.arms);
  scene.X_wsF = scene.X_wsF * G(SO3<double>::fromEulerXYZ(deg2rad(8), deg2rad(3), 0), Eigen::Vector3d::Zero());
  Dual::ArmInput inL{scene.X_wsL, {scene.featureL(), obsCov()}};
  Dual::ArmInput inF{scene.X_wsF, {scene.featureF(), obsCov()}};
  Dual::ArmOutput outL, outF;
  REQUIRE(central.step(inL, inF, 0.05, outL, outF) == Status::ok);
  const Eigen::Matrix3d R_FL = inF.sensor_pose.rotationMatrix().transpose() * inL.sensor_pose.rotationMatrix();
  const Eigen::Vector3d v_op = central.followerFeedforward().head<3>() - R_FL.col(2) * outL.velocity[2];
  CHECK(std::abs(v_op.norm() - o.max_opposition_speed) < 1e-9);
  CHECK(outF.velocity.allFinite());
}

TEST_CASE("centralised dual arm: round an arc, the follower turns its axis back against the leader's",
          "[control][dual_arm][centralised]") {
  // Kinematic check of the opposition term alone (no feedback, no push): the follower rides a
  // circle of radius 80 mm about the object's centre with its axis on the centre (what its
  // servo does on a round object); the leader stands at angle 0 facing the centre. Started
  // 25° round, the follower's own opposition velocity takes it back to 180° opposition.
  auto o = centralisedDualArmPushingPreset<double>(false);
  o.opposition_gain = 100;  // the term at a gain a caller sets (the presets leave it at 0)
  o.arms.follower.pid = MimoPid<double, 6>::Options::diagonal(V6::Zero(), V6::Zero(), V6::Zero());
  o.arms.leader.servo.pid = MimoPid<double, 6>::Options::diagonal(V6::Zero(), V6::Zero(), V6::Zero());
  o.arms.leader.servo.feedforward.setZero();
  o.arms.leader.alignment_cutoff = 1e9;  // the leader stands still
  o.arms.leader.target = G(SO3<double>(), Eigen::Vector3d(0, 0, 1e4));
  Central central(o, Filter(), Filter());
  REQUIRE(central.configurationStatus() == Status::ok);
  const double rho = 80;
  // x_s down (−z_w), z_s towards the centre; positions in the x–y plane.
  auto onCircle = [&](double phi) {
    const Eigen::Vector3d p(rho * std::cos(phi), rho * std::sin(phi), 0), z = -p.normalized();
    Eigen::Matrix3d R;
    R.col(0) = -Eigen::Vector3d::UnitZ();
    R.col(2) = z;
    R.col(1) = R.col(2).cross(R.col(0));
    return G(SO3<double>::fromMatrixUnchecked(R), p);
  };
  const G X_wL = onCircle(pi<double>());
  double phi = deg2rad(25);
  for (int k = 0; k < 400; ++k) {
    const G X_wF = onCircle(phi);
    Dual::ArmInput inL{X_wL, {G::identity(), obsCov()}};
    Dual::ArmInput inF{X_wF, {G::identity(), obsCov()}};
    Dual::ArmOutput outL, outF;
    REQUIRE(central.step(inL, inF, 0.05, outL, outF) == Status::ok);
    // Ride the circle with the tangential part of the commanded velocity.
    const Eigen::Vector3d v_w = X_wF.rotationMatrix() * outF.velocity.head<3>();
    const Eigen::Vector3d t(-std::sin(phi), std::cos(phi), 0);
    phi += 0.05 * v_w.dot(t) / rho;
  }
  CHECK(std::abs(phi) < deg2rad(0.5));
}

TEST_CASE("centralised dual arm: refusals and failures leave everything unchanged; termination stops both",
          "[control][dual_arm][centralised]") {
  auto o = centralisedDualArmPushingPreset<double>(false);
  o.arms.leader.target = G(SO3<double>(), Eigen::Vector3d(0, 100, 800));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  // A NaN or infinite value: non_finite_input; a finite one out of range: invalid_argument.
  for (double bad : {-1.0, nan, std::numeric_limits<double>::infinity()}) {
    const Status expected = std::isfinite(bad) ? Status::invalid_argument : Status::non_finite_input;
    auto b = o;
    b.opposition_gain = bad;
    CHECK(Central::validate(b) == expected);
    b = o;
    b.max_opposition_speed = bad;
    CHECK(Central::validate(b) == expected);
  }
  auto badArms = o;
  badArms.arms.follower.feedforward[0] = nan;
  CHECK(Central::validate(badArms) == Status::non_finite_input);
  Central central(o, Filter(), Filter());
  auto b = o;
  b.opposition_gain = -1;
  CHECK(central.configure(b) == Status::invalid_argument);
  CHECK(central.options().opposition_gain == o.opposition_gain);
  Central unconfigured(b, Filter(), Filter());
  CHECK(unconfigured.configurationStatus() == Status::invalid_argument);

  Scene scene(o.arms);
  Dual::ArmOutput outL, outF;
  warmUp(central, scene, outL, outF);
  const V6 uL0 = outL.velocity, uF0 = outF.velocity, ff0 = central.followerFeedforward();
  const G filL0 = central.arms().leaderFilter().filtered().mean;
  const V6 iF0 = central.follower().pid().integral();
  Dual::ArmInput inL{scene.X_wsL, {scene.featureL(), obsCov()}};
  Dual::ArmInput inF{scene.X_wsF, {scene.featureF(), obsCov()}};
  CHECK(central.step(inL, inF, 0.0, outL, outF) == Status::invalid_time_step);
  Dual::ArmInput badF = inF;
  badF.observation.covariance(2, 2) = nan;
  CHECK(central.step(inL, badF, 0.05, outL, outF) != Status::ok);
  Dual::ArmInput skewedF = inF;
  skewedF.sensor_pose = skewed(inF.sensor_pose);
  CHECK(central.step(inL, skewedF, 0.05, outL, outF) == Status::not_orthonormal);
  CHECK(outL.velocity == uL0);
  CHECK(outF.velocity == uF0);
  CHECK(central.followerFeedforward() == ff0);
  CHECK(central.arms().leaderFilter().filtered().mean.isApprox(filL0, 0));
  CHECK(central.follower().pid().integral() == iF0);
  CHECK(central.step(inL, inF, 0.05, outL, outF) == Status::ok);

  // Termination: both arms stop, the feedforward too.
  auto near = o;
  near.arms.leader.target = scene.X_wsL * G(SO3<double>(), Eigen::Vector3d(0, 3, 10));
  Central stop(near, Filter(), Filter());
  outF.velocity.setOnes();
  REQUIRE(stop.step(inL, inF, 0.05, outL, outF) == Status::ok);
  CHECK(stop.terminated());
  CHECK(outL.velocity.isZero());
  CHECK(outF.velocity.isZero());
  // reset() clears the filters and the feedforward
  central.reset();
  CHECK(!central.arms().leaderFilter().initialised());
  CHECK(central.followerFeedforward().isZero());
}

// TactileLoop (control/tactile_loop.hpp): the paper's loop, filter then controller, under one
// policy: it equals the hand-wired pair bit for bit, says what each step did, and on every
// refusal leaves the filter, the controller and the caller's twist exactly as they were.
#include <catch2/catch.hpp>

#include "control_test_util.hpp"

#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <type_traits>
#include <utility>

#include <lieservo/control/presets.hpp>
#include <lieservo/control/tactile_loop.hpp>
#include <lieservo/groups/se2.hpp>
#include <lieservo/groups/so3.hpp>
#include <lieservo/sampling/random.hpp>
#include <lieservo/units.hpp>

using namespace lieservo;
using G = SE3<double>;
using V6 = G::Tangent;
using Gaussian = ConcentratedGaussian<G>;
using Filter = DiscriminativeBayesFilter<G>;
using ServoLoop = TactileLoop<TactileServoController<G>>;
using PushLoop = TactileLoop<PushingController<SE3d>>;

static_assert(noexcept(std::declval<ServoLoop&>().step(std::declval<const G&>(), std::declval<const Gaussian&>(), 0.05,
                                                       std::declval<V6&>())));
static_assert(noexcept(std::declval<PushLoop&>().step(std::declval<const G&>(), std::declval<const Gaussian&>(), 0.05,
                                                      std::declval<V6&>())));
static_assert(std::is_same_v<ServoLoop::Group, G> && std::is_same_v<PushLoop::Group, G>);

namespace {
using lieservo::test::v6;

// A slow servo's frames: the sensor moves 0.5 mm and 0.1° a frame; the feature sits ~3 mm deep
// in front of it, observed with the paper's order of noise; frame `outlier` is 30 mm off.
struct Frames {
  sampling::Rng rng{20261202};
  G X_wf = G(SO3<double>::exp(Eigen::Vector3d(0.05, -0.02, 0.1)), Eigen::Vector3d(0, 0, 3));
  long k = 0;
  long outlier = -1;

  void next(G& X_ws, Gaussian& obs) {
    V6 motion = v6(0.5, 0, 0, 0, 0, deg2rad(0.1));
    X_ws = G::exp(double(k) * motion);
    const G X_sf = X_ws.inverse() * X_wf;
    V6 noise;
    for (int i = 0; i < 6; ++i) noise[i] = sampling::standardNormal(rng) * (i < 3 ? 0.3 : deg2rad(0.5));
    if (k == outlier) noise[1] += 30;
    obs.mean = G::exp(noise) * X_sf;
    obs.covariance = v6(0.09, 0.09, 0.09, 7.6e-5, 7.6e-5, 7.6e-5).asDiagonal();
    ++k;
  }
};

bool sameBits(const V6& a, const V6& b) { return std::memcmp(a.data(), b.data(), sizeof(double) * 6) == 0; }
bool sameBits(const Gaussian& a, const Gaussian& b) {
  return std::memcmp(a.mean.matrix().data(), b.mean.matrix().data(), sizeof(double) * 16) == 0 &&
         std::memcmp(a.covariance.data(), b.covariance.data(), sizeof(double) * 36) == 0;
}

PushLoop::Options pushOptions() {
  PushLoop::Options o;
  o.controller = pushingPreset<double>(PushingConfiguration::single_arm);
  o.controller.target = G(SO3<double>(), Eigen::Vector3d(0, 200, 600));
  return o;
}
}  // namespace

TEST_CASE("tactile loop: equals the hand-wired filter and servo, bit for bit, gate included",
          "[control][loop]") {
  ServoLoop::Options o;
  o.filter.gating = true;
  o.controller = surfaceFollowingPreset<double>();
  ServoLoop loop(o);
  REQUIRE(loop.configurationStatus() == Status::ok);
  Filter filter(o.filter);
  TactileServoController<G> servo(o.controller);
  Frames frames;
  frames.outlier = 40;
  long gated = 0;
  for (int k = 0; k < 200; ++k) {
    G X_ws;
    Gaussian obs;
    frames.next(X_ws, obs);
    V6 u_loop = V6::Zero(), u_hand = V6::Zero();
    REQUIRE(loop.step(X_ws, obs, 0.05, u_loop) == Status::ok);
    const Status f = filter.step(X_ws, obs);
    REQUIRE((f == Status::ok || f == Status::outlier_rejected));
    REQUIRE(servo.step(filter.filtered().mean, 0.05, u_hand) == Status::ok);
    CHECK(sameBits(u_loop, u_hand));
    CHECK(sameBits(loop.filter().filtered(), filter.filtered()));
    const LoopOutcome expected = k == 0 ? LoopOutcome::initialised
                                 : f == Status::outlier_rejected ? LoopOutcome::gated
                                                                 : LoopOutcome::commanded;
    CHECK(loop.outcome() == expected);
    gated += loop.outcome() == LoopOutcome::gated;
  }
  CHECK(gated >= 1);  // the 30 mm outlier at least
}

TEST_CASE("tactile loop: pushing equals the hand-wired pair and ends terminated", "[control][loop]") {
  PushLoop::Options o = pushOptions();
  o.controller.target = G(SO3<double>(), Eigen::Vector3d(60, 0, 3));  // reached as the sensor moves
  PushLoop loop(o);
  Filter filter(o.filter);
  PushingController<SE3d> push(o.controller);
  Frames frames;
  bool terminated = false;
  for (int k = 0; k < 200 && !terminated; ++k) {
    G X_ws;
    Gaussian obs;
    frames.next(X_ws, obs);
    V6 u_loop = V6::Ones(), u_hand = V6::Ones();
    REQUIRE(loop.step(X_ws, obs, 0.05, u_loop) == Status::ok);
    REQUIRE(filter.step(X_ws, obs) == Status::ok);
    REQUIRE(push.step(X_ws, filter.filtered().mean, 0.05, u_hand) == Status::ok);
    CHECK(sameBits(u_loop, u_hand));
    terminated = push.terminated();
    CHECK(loop.terminated() == terminated);
    CHECK((loop.outcome() == LoopOutcome::terminated) == terminated);
    if (terminated) CHECK(u_loop.isZero(0));
  }
  CHECK(terminated);
}

TEST_CASE("tactile loop: every refusal leaves filter, controller and twist unchanged", "[control][loop]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  PushLoop loop(pushOptions());
  Frames frames;
  G X_ws;
  Gaussian obs;
  V6 u = V6::Zero();
  for (int k = 0; k < 5; ++k) {
    frames.next(X_ws, obs);
    REQUIRE(loop.step(X_ws, obs, 0.05, u) == Status::ok);
  }
  frames.next(X_ws, obs);
  const Gaussian filtered = loop.filter().filtered();
  const G sensor = loop.filter().sensorPose();
  const long pid_steps = loop.controller().servo().pid().steps();
  const V6 integral = loop.controller().servo().pid().integral();
  const V6 u_before = v6(1, 2, 3, 4, 5, 6);
  auto refused = [&](Status expected, const G& pose, const Gaussian& g, double dt) {
    V6 v = u_before;
    CHECK(loop.step(pose, g, dt, v) == expected);
    CHECK(loop.outcome() == LoopOutcome::refused);
    CHECK(loop.lastStatus() == expected);
    CHECK(sameBits(v, u_before));
    CHECK(sameBits(loop.filter().filtered(), filtered));
    CHECK(loop.filter().sensorPose().matrix() == sensor.matrix());
    CHECK(loop.controller().servo().pid().steps() == pid_steps);
    CHECK(loop.controller().servo().pid().integral() == integral);
  };
  refused(Status::invalid_time_step, X_ws, obs, 0.0);
  refused(Status::invalid_time_step, X_ws, obs, -0.05);
  refused(Status::invalid_time_step, X_ws, obs, nan);
  Gaussian bad = obs;
  bad.covariance(2, 2) = -1;
  refused(Status::not_spd, X_ws, bad, 0.05);
  bad = obs;
  bad.covariance(0, 0) = nan;
  refused(Status::non_finite_input, X_ws, bad, 0.05);
  Eigen::Matrix4d skewed = X_ws.matrix();
  skewed(0, 0) *= 1.2;
  refused(Status::not_orthonormal, G::fromMatrixUnchecked(skewed), obs, 0.05);
  // and the loop still runs on from where it was
  CHECK(loop.step(X_ws, obs, 0.05, u) == Status::ok);
  CHECK(loop.outcome() == LoopOutcome::commanded);
}

TEST_CASE("tactile loop: a controller's refusal after the filter's step puts the filter back", "[control][loop]") {
  ServoLoop::Options o;
  o.controller.pid.kp(0, 0) = 1e308;  // the PID's output overflows once the x error exceeds ~1.8 mm
  ServoLoop loop(o);
  REQUIRE(loop.configurationStatus() == Status::ok);
  Gaussian obs;
  obs.mean = G(SO3<double>(), Eigen::Vector3d(0.1, 0, 0));
  obs.covariance = V6::Constant(0.01).asDiagonal();
  V6 u = V6::Zero();
  REQUIRE(loop.step(G(), obs, 0.05, u) == Status::ok);
  REQUIRE(loop.outcome() == LoopOutcome::initialised);
  const Gaussian filtered = loop.filter().filtered();
  const auto corrections = loop.filter().diagnostics().corrections;
  obs.mean = G(SO3<double>(), Eigen::Vector3d(50, 0, 0));
  const V6 u_before = u;
  CHECK(loop.step(G(), obs, 0.05, u) == Status::numerical_failure);
  CHECK(loop.outcome() == LoopOutcome::refused);
  CHECK(sameBits(u, u_before));
  CHECK(sameBits(loop.filter().filtered(), filtered));
  CHECK(loop.filter().diagnostics().corrections == corrections);
}

TEST_CASE("tactile loop: refused options, reset, and the other groups", "[control][loop]") {
  ServoLoop::Options o;
  o.filter.gate_probability = 2;
  ServoLoop bad(o);
  CHECK(bad.configurationStatus() == Status::invalid_argument);
  V6 u = V6::Zero();
  CHECK(bad.step(G(), Gaussian(), 0.05, u) == Status::invalid_argument);
  o.filter.gate_probability = 0.999;
  o.controller.reference = G::fromMatrixUnchecked(Eigen::Matrix4d::Constant(2));
  CHECK(ServoLoop::validate(o) == Status::not_orthonormal);
  ServoLoop loop;
  CHECK(loop.configure(o) == Status::not_orthonormal);
  CHECK(loop.controller().options().reference.matrix() == G().matrix());

  Frames frames;
  G X_ws;
  Gaussian obs;
  frames.next(X_ws, obs);
  REQUIRE(loop.step(X_ws, obs, 0.05, u) == Status::ok);
  REQUIRE(loop.step(X_ws, obs, 0.05, u) == Status::ok);
  CHECK(loop.outcome() == LoopOutcome::commanded);
  loop.reset();
  CHECK_FALSE(loop.filter().initialised());
  CHECK(loop.controller().pid().steps() == 0);
  REQUIRE(loop.step(X_ws, obs, 0.05, u) == Status::ok);
  CHECK(loop.outcome() == LoopOutcome::initialised);

  // SE(2) and SO(3): the same class on the groups a scene models (lesson 06).
  TactileLoop<TactileServoController<SE2<double>>> planar;
  ConcentratedGaussian<SE2<double>> g2;
  g2.mean = SE2<double>::exp(Eigen::Vector3d(1, 0.5, 0.1));
  g2.covariance = Eigen::Vector3d(0.1, 0.1, 0.01).asDiagonal();
  SE2<double>::Tangent u2;
  CHECK(planar.step(SE2<double>(), g2, 0.05, u2) == Status::ok);
  CHECK(planar.outcome() == LoopOutcome::initialised);
  TactileLoop<TactileServoController<SO3<float>>> attitude;
  ConcentratedGaussian<SO3<float>> g3;
  g3.mean = SO3<float>::exp(Eigen::Vector3f(0.1f, 0, 0));
  g3.covariance = Eigen::Matrix3f::Identity() * 0.01f;
  SO3<float>::Tangent u3;
  CHECK(attitude.step(SO3<float>(), g3, 0.05f, u3) == Status::ok);
  CHECK(std::string(describe(LoopOutcome::gated)) == "gated");
}

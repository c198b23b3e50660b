// examples/franka/franka_adapter.cpp, unchanged, against the libfranka test double
// (examples/franka/sim_double): the tactile thread's commands cross the lock-free channel to the
// 1 kHz callback on the adapter's own thread, through the watchdog and the smoother, and drive
// the simulated Panda. Faults a hardware user meets, each with its safe outcome, on the double's
// kinematic arm (the joints do exactly what the resolved rate commands) and, where MuJoCo is
// found, again on its dynamic arm (the joints under MuJoCo's dynamics and the Panda's joint
// controller: dynamic_servo.hpp). Bounds written before the first run; time bounds leave room
// for a loaded test machine.
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <thread>

#include <franka_adapter.hpp>
#include <franka_sim/arm.h>

#if LIESERVO_TEST_DYNAMIC_ARM
#include "dynamic_servo.hpp"
#endif

using lieservo::Status;
using lieservo::franka_adapter::FrankaAdapter;
using lieservo::franka_adapter::FrankaAdapterOptions;
using lieservo::realtime::WatchdogState;
using SE3d = lieservo::SE3<double>;
using Twist = SE3d::Tangent;
using Clock = std::chrono::steady_clock;
namespace panda = lieservo::sim::panda;

namespace {

enum class Joints { kinematic, dynamic };

/// The arms a fault test runs on, one run each (Catch2's GENERATE).
Joints eachArm() {
#if LIESERVO_TEST_DYNAMIC_ARM
  return GENERATE(Joints::kinematic, Joints::dynamic);
#else
  return Joints::kinematic;
#endif
}

const char* nameOf(Joints j) { return j == Joints::dynamic ? "dynamic arm" : "kinematic arm"; }

/// A simulated arm registered under its own address for one test.
struct SimArm {
  std::string address;
  Joints kind;
  std::shared_ptr<franka_sim::Arm> arm;
  explicit SimArm(std::string a, Joints k = Joints::kinematic, const panda::Joints& q0 = panda::readyPose())
      : address(std::move(a)), kind(k), arm(franka_sim::Arm::create(address, q0, servoFor(k, q0))) {}
  ~SimArm() { franka_sim::Arm::remove(address); }
  FrankaAdapterOptions options() const {
    FrankaAdapterOptions o;
    o.robot_ip = address;
    o.enforce_realtime = false;
    return o;
  }
  /// At rest: the kinematic joints stop exactly; the dynamic ones settle under their
  /// controller, so every joint slower than 1e-4 rad/s (a braked arm stops exactly on both).
  bool atRest() const {
    const double tol = kind == Joints::dynamic ? 1e-4 : 0.0;
    return arm->jointVelocities().cwiseAbs().maxCoeff() <= tol;
  }

 private:
  static std::shared_ptr<franka_sim::JointServo> servoFor(Joints k, const panda::Joints& q0) {
#if LIESERVO_TEST_DYNAMIC_ARM
    if (k == Joints::dynamic) return std::make_shared<lieservo_test::DynamicServo>(q0);
#endif
    (void)k, (void)q0;
    return nullptr;  // the double's KinematicServo
  }
};

/// Sends `twist` at 20 Hz for n periods (the tactile thread); when the last command was sent.
Clock::time_point commandFor(FrankaAdapter& adapter, const Twist& twist, int n) {
  auto next = Clock::now(), last = next;
  for (int i = 0; i < n; ++i) {
    last = Clock::now();
    REQUIRE(adapter.commandVelocity(twist, 0.05) == Status::ok);
    next += std::chrono::milliseconds(50);
    std::this_thread::sleep_until(next);
  }
  return last;
}

/// Waits (≤ limit_s) until pred() holds; the seconds it took, or a negative number.
template <class Pred>
double waitFor(Pred pred, double limit_s) {
  const auto t0 = Clock::now();
  while (std::chrono::duration<double>(Clock::now() - t0).count() < limit_s) {
    if (pred()) return std::chrono::duration<double>(Clock::now() - t0).count();
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return -1.0;
}

}  // namespace

TEST_CASE("franka adapter on the double: the pose read back and a move to a goal", "[robot][franka]") {
  SimArm sim("sim-panda-move");
  FrankaAdapter adapter(sim.options());
  SE3d X;
  REQUIRE(adapter.readPose(X) == Status::ok);
  const Eigen::Matrix4d T = panda::flange(panda::readyPose());
  CHECK((X.translation() - 1e3 * T.block<3, 1>(0, 3)).norm() <= 1e-9);  // mm
  CHECK((X.rotationMatrix() - T.topLeftCorner<3, 3>()).norm() <= 1e-12);

  // 20 mm down the sensor's z (the flange points down) and 5° about it.
  Twist step;
  step << 0, 0, 20, 0, 0, 5 * lieservo::pi<double>() / 180;
  const SE3d goal = X * SE3d::exp(step);
  REQUIRE(adapter.moveTo(goal) == Status::ok);
  SE3d Y;
  REQUIRE(adapter.readPose(Y) == Status::ok);
  const Twist e = (Y.inverse() * goal).log();
  CHECK(e.head<3>().norm() <= 0.2);   // mm; moveTo stops at 0.1
  CHECK(e.tail<3>().norm() <= 0.004);  // rad; moveTo stops at 0.002

  // What the arm was commanded stayed inside the adapter's smoother limits (SI).
  const franka_sim::ArmReport r = sim.arm->report();
  const auto lim = sim.options().limits;
  INFO("speed " << r.max_speed << " m/s, accel " << r.max_accel << ", jerk " << r.max_jerk << "; twist error "
                << r.max_twist_error << ", manipulability >= " << r.min_manipulability);
  CHECK(r.errors == 0);
  CHECK(r.motions == 1);
  CHECK(r.max_speed <= lim.translation.velocity * (1 + 1e-9));
  CHECK(r.max_accel <= lim.translation.acceleration * (1 + 1e-6));
  CHECK(r.max_jerk <= lim.translation.jerk * (1 + 1e-6));
  CHECK(r.max_angular_speed <= lim.rotation.velocity * (1 + 1e-9));
  CHECK(r.max_twist_error <= 1e-9);  // achieved twist = commanded (no damping needed here)
  CHECK(r.damped_cycles == 0);
}

TEST_CASE("franka adapter on the double: 20 Hz commands move the arm, a stalled tactile thread stops it",
          "[robot][franka]") {
  // 24 commands of 10 mm/s along the sensor's x at 20 Hz, then none: the watchdog (0.2 s)
  // must bring the arm to rest. The kinematic arm within 0.5 s of wall-clock time (the timeout,
  // the ramp down and scheduling); the dynamic one within 0.6 s of the arm's own clock (its
  // 1 ms cycles: the joint controller settles in cycles, and on a loaded machine the cycles
  // fall behind wall-clock time), the joint controller settling after the ramp.
  const Joints kind = eachArm();
  INFO(nameOf(kind));
  SimArm sim("sim-panda-stall", kind);
  FrankaAdapter adapter(sim.options());
  SE3d X0;
  REQUIRE(adapter.readPose(X0) == Status::ok);
  Twist v = Twist::Zero();
  v[0] = 10.0;  // mm/s along the sensor's x
  auto next = Clock::now(), t_last = next;
  std::uint64_t last_ms = 0;  // the arm's clock at the last command
  for (int i = 0; i < 24; ++i) {  // 1.2 s; the watchdog arms after 3 fresh commands
    t_last = Clock::now();
    last_ms = sim.arm->readOnce().time.toMSec();
    REQUIRE(adapter.commandVelocity(v, 0.05) == Status::ok);
    next += std::chrono::milliseconds(50);
    std::this_thread::sleep_until(next);
  }
  std::uint64_t rest_ms = 0;
  const double t_rest = waitFor(
      [&] {
        rest_ms = sim.arm->readOnce().time.toMSec();
        return sim.atRest();
      },
      2.0);
  const double since_last = std::chrono::duration<double>(Clock::now() - t_last).count();
  const double since_last_arm = 1e-3 * double(rest_ms - last_ms);
  INFO("at rest " << since_last << " s of wall-clock time, " << since_last_arm << " s of the arm's clock after the "
                  << "last command");
  REQUIRE(t_rest >= 0);
  if (kind == Joints::kinematic)
    CHECK(since_last <= 0.2 + 0.3);
  else
    CHECK(since_last_arm <= 0.6);
  const auto st = adapter.stats();
  CHECK(st.running);
  CHECK_FALSE(st.faulted);
  CHECK(st.watchdog == WatchdogState::tripped_timeout);
  CHECK(st.pipeline_errors == 0);

  SE3d X1;
  REQUIRE(adapter.readPose(X1) == Status::ok);
  const Twist d = (X0.inverse() * X1).log();
  INFO("moved " << d.transpose());
  CHECK(d[0] >= 5.0);
  CHECK(d[0] <= 15.0);
  CHECK(std::abs(d[1]) <= 0.5);
  CHECK(std::abs(d[2]) <= 0.5);
  CHECK(d.tail<3>().norm() <= 1e-3);
  adapter.stop();
  CHECK_FALSE(adapter.stats().running);
  CHECK(sim.arm->report().errors == 0);
}

TEST_CASE("franka adapter on the double: late frames within the timeout keep it moving, a longer gap rests it until "
          "fresh frames return",
          "[robot][franka]") {
  const Joints kind = eachArm();
  INFO(nameOf(kind));
  SimArm sim("sim-panda-late", kind);
  // The rest bound: the timeout, the ramp down and scheduling (0.15 s); the dynamic joints
  // also settle under their controller (0.6 s in all, as in the stall test on the arm's clock
  // above). The late frame comes after more than that.
  const double rest_bound = kind == Joints::dynamic ? 0.6 + 0.15 : 0.2 + 0.15;
  const auto gap = std::chrono::milliseconds(kind == Joints::dynamic ? 800 : 400);
  FrankaAdapter adapter(sim.options());
  Twist v = Twist::Zero();
  v[0] = 10.0;  // mm/s along the sensor's x
  // A camera and model that deliver late: intervals of 30 to 150 ms, under the 0.2 s timeout
  // with room for a loaded test machine.
  const int gaps_ms[] = {30, 120, 150, 60, 150, 90, 140, 40};
  int trips = 0;
  auto next = Clock::now();
  for (int i = 0; i < 24; ++i) {
    REQUIRE(adapter.commandVelocity(v, 0.05) == Status::ok);
    if (i >= 3 && adapter.stats().watchdog != WatchdogState::active) ++trips;  // armed after 3
    next += std::chrono::milliseconds(gaps_ms[i % 8]);
    std::this_thread::sleep_until(next);
  }
  CHECK(trips == 0);
  CHECK_FALSE(sim.atRest());

  // A frame late by `gap` (over the timeout): the arm comes to rest while it waits ...
  const auto t_last = Clock::now();
  REQUIRE(adapter.commandVelocity(v, 0.05) == Status::ok);
  const double t_rest = waitFor([&] { return sim.atRest(); }, std::chrono::duration<double>(gap).count());
  INFO("at rest " << t_rest << " s after the last command");
  REQUIRE(t_rest >= 0);
  CHECK(t_rest <= rest_bound);
  CHECK(adapter.stats().watchdog == WatchdogState::tripped_timeout);
  std::this_thread::sleep_until(t_last + gap);

  // ... and moves again once fresh frames are back (3 in a row re-arm the watchdog).
  SE3d X0;
  REQUIRE(adapter.readPose(X0) == Status::ok);
  commandFor(adapter, v, 12);  // 0.6 s at 20 Hz
  CHECK(adapter.stats().watchdog == WatchdogState::active);
  CHECK_FALSE(sim.atRest());
  SE3d X1;
  REQUIRE(adapter.readPose(X1) == Status::ok);
  const Twist d = (X0.inverse() * X1).log();
  INFO("moved " << d.transpose() << " mm after the gap");
  CHECK(d[0] >= 2.0);  // 10 mm/s for 0.6 s less the re-arming (0.15 s) and the ramp up
  CHECK(d[0] <= 7.0);
  adapter.stop();
  CHECK(sim.atRest());
  CHECK(sim.arm->report().errors == 0);  // no discontinuity libfranka would have rejected
  CHECK_FALSE(adapter.stats().faulted);
}

TEST_CASE("franka adapter on the double: bad commands are refused and start nothing", "[robot][franka]") {
  const Joints kind = eachArm();
  INFO(nameOf(kind));
  SimArm sim("sim-panda-bad", kind);
  FrankaAdapter adapter(sim.options());
  const panda::Joints q0 = sim.arm->joints();
  Twist nan_twist = Twist::Zero();
  nan_twist[2] = std::nan("");
  CHECK(adapter.commandVelocity(nan_twist, 0.05) == Status::non_finite_input);
  CHECK(adapter.commandVelocity(Twist::Zero(), 0.0) == Status::invalid_time_step);
  CHECK(adapter.commandVelocity(Twist::Zero(), -0.05) == Status::invalid_time_step);
  CHECK(adapter.moveTo(SE3d::fromMatrixUnchecked(Eigen::Matrix4d::Constant(std::nan("")))) ==
        Status::non_finite_input);
  CHECK_FALSE(adapter.stats().running);
  CHECK(sim.arm->report().cycles == 0);
  CHECK(sim.arm->joints() == q0);
}

TEST_CASE("franka adapter on the double: a reflex faults the adapter, the arm rests, recover() clears it",
          "[robot][franka]") {
  const Joints kind = eachArm();
  INFO(nameOf(kind));
  SimArm sim("sim-panda-reflex", kind);
  FrankaAdapter adapter(sim.options());
  Twist v = Twist::Zero();
  v[1] = 5.0;
  commandFor(adapter, v, 6);
  sim.arm->injectReflex("cartesian_reflex");
  REQUIRE(waitFor([&] { return adapter.stats().faulted; }, 2.0) >= 0);
  CHECK(sim.atRest());
  CHECK(adapter.lastError().find("cartesian_reflex") != std::string::npos);
  CHECK(adapter.commandVelocity(v, 0.05) == Status::not_initialised);
  REQUIRE(adapter.recover() == Status::ok);
  CHECK_FALSE(adapter.stats().faulted);
  commandFor(adapter, v, 6);
  adapter.stop();
  CHECK(sim.arm->report().errors == 1);
  CHECK(sim.arm->report().motions == 1);  // the second motion ended normally
}

TEST_CASE("franka adapter on the double: a twist that drives a joint into its limit stops at rest", "[robot][franka]") {
  panda::Joints q0 = panda::readyPose();
  q0[6] = panda::upperLimits()[6] - 0.03;  // joint 7 (the flange's own axis) near its limit
  const Joints kind = eachArm();
  INFO(nameOf(kind));
  SimArm sim("sim-panda-limit", kind, q0);
  FrankaAdapter adapter(sim.options());
  Twist w = Twist::Zero();
  w[5] = 0.3;  // rad/s about the sensor's z: turns joint 7 towards its limit
  auto next = Clock::now();
  for (int i = 0; i < 40 && !adapter.stats().faulted; ++i) {
    (void)adapter.commandVelocity(w, 0.05);
    next += std::chrono::milliseconds(50);
    std::this_thread::sleep_until(next);
  }
  REQUIRE(waitFor([&] { return adapter.stats().faulted; }, 1.0) >= 0);
  INFO(adapter.lastError());
  CHECK(adapter.lastError().find("joint_position_limits_violation") != std::string::npos);
  CHECK(sim.atRest());
  CHECK(panda::jointLimitMargin(sim.arm->joints()) >= 0);
  CHECK(sim.arm->report().errors == 1);
}

TEST_CASE("franka adapter on the double: a twist that leaves the workspace stops at rest inside it", "[robot][franka]") {
  // Straight out along the base's x at 100 mm/s from the ready pose: the target leaves the
  // Panda's reach (855 mm from the shoulder, 333 mm above the base) within about 5 s. The
  // arm must stop on a reflex of the joints (their position or velocity limits, as the real
  // robot would near a stretched elbow or the singularity there), at rest, with no
  // discontinuity that libfranka would reject, and inside its reach.
  const Joints kind = eachArm();
  INFO(nameOf(kind));
  SimArm sim("sim-panda-workspace", kind);
  FrankaAdapter adapter(sim.options());
  SE3d X0;
  REQUIRE(adapter.readPose(X0) == Status::ok);
  Twist w = Twist::Zero();
  w.head<3>() = X0.rotationMatrix().transpose() * Eigen::Vector3d(100, 0, 0);  // mm/s, sensor frame
  auto next = Clock::now();
  for (int i = 0; i < 300 && !adapter.stats().faulted; ++i) {  // ≤ 15 s at 20 Hz
    (void)adapter.commandVelocity(w, 0.05);
    next += std::chrono::milliseconds(50);
    std::this_thread::sleep_until(next);
  }
  REQUIRE(waitFor([&] { return adapter.stats().faulted; }, 1.0) >= 0);
  const std::string error = adapter.lastError();
  INFO(error);
  CHECK((error.find("joint_position_limits_violation") != std::string::npos ||
         error.find("joint_velocity_limits_violation") != std::string::npos));
  CHECK(error.find("discontinuity") == std::string::npos);
  CHECK(sim.atRest());
  CHECK(panda::jointLimitMargin(sim.arm->joints()) >= 0);
  CHECK(sim.arm->report().errors == 1);
  const Eigen::Matrix4d T = panda::flange(sim.arm->joints());
  const Eigen::Vector3d from_shoulder = T.block<3, 1>(0, 3) - Eigen::Vector3d(0, 0, 0.333);
  INFO("flange " << 1e3 * (T(0, 3) - 1e-3 * X0.translation().x()) << " mm further out, " << 1e3 * from_shoulder.norm()
                 << " mm from the shoulder");
  CHECK(from_shoulder.norm() <= 0.855);
  CHECK(T(0, 3) - 1e-3 * X0.translation().x() >= 0.2);  // it was driven out before it stopped
}


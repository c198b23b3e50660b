// Tutorial 07 — Pushing an object in the simulated world, from the tactile estimate to the robot's
// command.
//
// Lessons 03 and 04 met the filter and the servo controller one at a time. Here everything runs
// together in a physics engine (MuJoCo), as it would on a robot:
//
//   20 Hz tactile loop:  contact → GDN-like observation (μ, σ)
//                        → concentrated Gaussian (eq. 14)
//                        → Bayes filter with a χ² gate (Algorithm 2)
//                        → pushing controller (Section 3.3.3), the two as one TactileLoop
//                        → a sensor twist, written to a channel;
//   robot loop (here 400 Hz, the engine's step; 1 kHz on a Franka): read the newest twist → the
//                        command watchdog → the twist in the robot's base frame, in m/s →
//                        the jerk-limited smoother → the robot's velocity command.
//
// The robot is the sensor body of the simulated world: it executes the smoothed base twist, so
// what pushes the object is exactly what the real-time layer would send to an arm. Every call
// returns a Status and every Status is handled. One observation is corrupted on purpose (30 mm
// off, as a misread tactile image would be) to show the gate reject it while the filter carries
// on with its prediction.
//
// The object is the paper's 100 mm blue square on MDF
// (Section 5.6): the sensor starts 250 mm before the origin and pushes it
// to a target 375 mm away along y, so the controller must turn the object on the way.
// Exits with status 1 if a check stated at report() fails.
//
// Build and run:  cmake --build <build> --target lieservo_tutorial_07_pushing_to_the_robot &&
//                 <build>/examples/tutorials/lieservo_tutorial_07_pushing_to_the_robot
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>

#include <lieservo/lieservo.hpp>
#include <lieservo/realtime.hpp>

#include "lieservo_sim/contact_model.hpp"
#include "lieservo_sim/mujoco_world.hpp"
#include "lieservo_sim/observation_model.hpp"
#include "lieservo_sim/sensor_arm.hpp"
#include "lieservo_sim/tasks.hpp"

using namespace lieservo;
using namespace lieservo::sim;

namespace {

// Prints a failed Status with where it came from; returns whether it was ok.
bool ok(Status s, const char* where) {
  if (s != Status::ok) std::printf("%s: %s\n", where, describe(s));
  return s == Status::ok;
}

// X_OE in metres, as a robot reports it (the sensor is the end effector here: an identity mount).
SE3d inMetres(const SE3d& X_ws) { return SE3d(X_ws.so3(), 1e-3 * X_ws.translation()); }

// The robot executes a base twist [ṗ (m/s); ω (rad/s)]: the simulated sensor body takes it as a
// body twist in mm/s and rad/s.
Vec6 baseToSensorTwist(const SE3d& X_ws, const std::array<double, 6>& base) {
  const Mat3 Rt = X_ws.rotationMatrix().transpose();
  Vec6 u;
  u.head<3>() = Rt * Vec3(base[0], base[1], base[2]) * 1e3;
  u.tail<3>() = Rt * Vec3(base[3], base[4], base[5]);
  return u;
}

// 1. The world: the support, the object in front of the sensor with 1 mm of contact, and the
//    sensor on the paper's right-angle mount (z_s along the push +x, x_s down). It is the demo's
//    pushing scene (pushingScene): the blue square on MDF, the sensor 45 mm above the support at
//    `start`, and a GDN-like observation model with the paper's Table 1 errors, seeded (the same
//    run every time).
struct PushWorld {
  static constexpr double kHeight = 45;  // mm, the sensor's axis above the support

  PushWorld(const Vec3& start, double h) : world(scene(start, h)), robot(world, 0), contact(ContactParams{}) {}

  static mujoco::SceneSpec scene(const Vec3& start, double h) {
    PushingSetup setup;
    setup.object = shortObjects().front();  // the blue square
    setup.start = start.head<2>();
    setup.sensor_height = kHeight;
    return pushingScene(setup, ContactParams{}, h);
  }

  mujoco::World world;
  MujocoSensorArm robot;
  ContactModel contact;
  GdnObservationModel gdn;
};

// 2. The tactile loop: the paper's filter with the χ² gate on, and the paper's single-arm pushing
//    controller (Tables 7-8) aimed at the target, stepped together by one class (the same class
//    the simulated tasks and the Franka program step; docs/control.md, section 8).
TactileLoop<PushingController<SE3d>>::Options loopOptions(const Vec3& target) {
  TactileLoop<PushingController<SE3d>>::Options options;
  options.filter.gating = true;  // reject an observation whose NIS is above χ²(6) at 0.999
  options.controller = pushingPreset<double>(PushingConfiguration::single_arm);
  options.controller.target = SE3d(SO3d::identity(), target);
  return options;
}

// 3. The real-time side: the channel that hands twists to the robot loop, and the pipeline
//    (watchdog + base-frame conversion + jerk-limited smoother) that the robot loop runs at
//    period h. Time is simulated: the stamps are the engine's clock in ns.
struct RobotLoop {
  explicit RobotLoop(double period) : h(period) { options.control_period_s = h; }

  /// One cycle of the robot loop (stopping: the ramped stop); false when the robot or the engine fails.
  bool cycle(PushWorld& w, bool stopping) {
    std::array<double, 6> base{};
    const Status s = stopping ? pipeline.stepStopping(base) : pipeline.step(inMetres(w.robot.pose()), channel, now_ns, base);
    if (s != Status::ok) {  // a bad pose or twist: stop this cycle instead, and stay stopped
      std::printf("robot loop: %s, stopping\n", describe(s));
      (void)pipeline.stepStopping(base);
    }
    fastest = std::max(fastest, std::hypot(base[0], base[1], base[2]));
    hardest = std::max(hardest, std::hypot(base[0] - last[0], base[1] - last[1], base[2] - last[2]) / h);
    last = base;
    if (!ok(w.robot.commandVelocity(baseToSensorTwist(w.robot.pose(), base), h), "robot")) return false;
    if (!ok(w.world.step(h), "engine")) return false;
    now_ns += static_cast<std::int64_t>(std::llround(h * 1e9));
    return true;
  }

  /// The tactile loop's twist `u`, handed to the robot loop.
  void send(const SE3d::Tangent& u, bool in_contact) {
    realtime::TwistCommand command;
    for (int i = 0; i < 6; ++i) command.twist_s[std::size_t(i)] = u[i];
    command.in_contact = in_contact;
    channel.write(command, now_ns);
  }

  const realtime::SmootherLimits<double>& limits() const { return options.limits; }

  double h;
  realtime::PipelineOptions options;
  realtime::LatestValueChannel<realtime::TwistCommand> channel;
  realtime::CartesianVelocityPipeline pipeline;
  double fastest = 0, hardest = 0;  // the largest commanded base speed (m/s) and acceleration (m/s²)
  std::array<double, 6> last{};
  std::int64_t now_ns = 0;
};

// What the run did, for the checks at the end.
struct Run {
  long steps = 0, rejected = 0, stop_cycles = 0;
  LoopOutcome outlier_outcome = LoopOutcome::refused;
};

// Checks: the push ends at the target (the controller's termination, within 120 s); the
// corrupted observation is rejected; no command exceeds the smoother's speed or acceleration
// limit; the arm is at rest within 0.1 s of the stop request.
bool report(const Run& run, PushWorld& w, const TactileLoop<PushingController<SE3d>>& loop, const RobotLoop& r,
            double dt) {
  const PushingController<SE3d>& pusher = loop.controller();
  const realtime::SmootherLimits<double>& limits = r.limits();
  const SE3d X_wo = w.world.objectPose(0);
  std::printf("after %.1f s: the tip %.1f mm from the target, the object at (%.1f, %.1f) mm; "
              "%ld observation(s) rejected by the gate; the injected one: %s\n",
              run.steps * dt, pusher.terminationDistance(), X_wo.translation().x(), X_wo.translation().y(),
              run.rejected, describe(run.outlier_outcome));
  std::printf("base commands: fastest %.1f mm/s (limit %.0f), hardest acceleration %.2f m/s^2 (limit %.1f); "
              "at rest %.1f ms after the stop request\n",
              r.fastest * 1e3, limits.translation.velocity * 1e3, r.hardest, limits.translation.acceleration,
              run.stop_cycles * r.h * 1e3);
  const bool reached = pusher.terminated();
  const bool gated = run.outlier_outcome == LoopOutcome::gated;
  const bool within = r.fastest <= limits.translation.velocity * (1 + 1e-9) &&
                      r.hardest <= limits.translation.acceleration * (1 + 1e-9);
  const bool stopped = r.pipeline.stopped() && run.stop_cycles * r.h <= 0.1;
  std::printf("reached the target: %s; outlier rejected: %s; within the speed and acceleration limits: %s; stopped: %s\n",
              reached ? "yes" : "NO", gated ? "yes" : "NO", within ? "yes" : "NO", stopped ? "yes" : "NO");
  return reached && gated && within && stopped;
}

}  // namespace

int main() {
  const double dt = 0.05;                  // the 20 Hz tactile loop
  const int substeps = stepsPerPeriod(dt);  // the engine's steps per tactile period
  const double h = dt / substeps;           // 2.5 ms: the robot loop's period here
  const Vec3 start(-250, 100, PushWorld::kHeight), target(0, 375, PushWorld::kHeight);
  PushWorld w(start, h);
  TactileLoop<PushingController<SE3d>> loop(loopOptions(target));
  if (!ok(loop.configurationStatus(), "tactile loop")) return 1;
  RobotLoop robot_loop(h);
  if (!ok(robot_loop.pipeline.configure(robot_loop.options), "pipeline")) return 1;

  // 4. The loops.
  const long outlier_step = 200;  // 10 s in: one corrupted observation
  Run run;
  std::printf("   t (s)   object (x, y) mm   distance to target (mm)   bearing (deg)\n");
  while (run.steps * dt < 120) {
    // Tactile loop: observe, then filter and control in one step.
    const ContactState state = touchContact(w.world, 0, w.contact);  // what the sensor feels
    GdnObservation obs = w.gdn.observe(state);
    if (run.steps == outlier_step) obs.mu[1] += 30;  // the misread image: 30 mm of shear along y
    ConcentratedGaussian<SE3d> observation;
    if (!ok(fromTangentGaussian(obs.mu, obs.sigma, observation), "observation")) break;
    SE3d::Tangent u;
    // A refusal changes nothing and ends the run; everything else commands (the first step
    // initialises the filter; a gated observation is not an error: the controller then uses
    // the prediction from the robot's own motion).
    if (!ok(loop.step(w.robot.pose(), observation, dt, u), "tactile loop")) break;
    if (run.steps == outlier_step) run.outlier_outcome = loop.outcome();
    if (loop.outcome() == LoopOutcome::gated) ++run.rejected;
    if (loop.outcome() == LoopOutcome::terminated) break;  // the tip is within 20 mm of the target: stop (below)

    robot_loop.send(u, state.in_contact);
    for (int j = 0; j < substeps; ++j)
      if (!robot_loop.cycle(w, false)) return 1;
    if (run.steps % 200 == 0) {
      const SE3d X_wo = w.world.objectPose(0);
      std::printf("  %6.1f   (%6.1f, %6.1f)   %23.1f   %13.1f\n", run.steps * dt, X_wo.translation().x(),
                  X_wo.translation().y(), loop.controller().terminationDistance(), rad2deg(loop.controller().bearing()));
    }
    ++run.steps;
  }
  // 5. Stop, the arm still moving: the watchdog stops passing commands and the smoother ramps
  //    the arm down within its acceleration and jerk limits.
  robot_loop.pipeline.requestStop();
  while (!robot_loop.pipeline.stopped() && run.stop_cycles < 400) {
    if (!robot_loop.cycle(w, true)) return 1;
    ++run.stop_cycles;
  }
  return report(run, w, loop, robot_loop, dt) ? 0 : 1;
}

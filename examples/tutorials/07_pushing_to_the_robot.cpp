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
// Exits with status 1 if a check stated at the end of main() fails.
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

}  // namespace

int main() {
  // 1. The world: the support, the object in front of the sensor with 1 mm of contact, and the
  //    sensor on the paper's right-angle mount (z_s along the push +x, x_s down).
  const double dt = 0.05;                  // the 20 Hz tactile loop
  const int substeps = stepsPerPeriod(dt);  // the engine's steps per tactile period
  const double h = dt / substeps;           // 2.5 ms: the robot loop's period here
  const ContactParams contact_params;
  const double height = 45;                 // mm, the sensor's axis above the support
  const Vec3 start(-250, 100, height), target(0, 375, height);

  // The demo's pushing scene (pushingScene): the blue square on MDF in front of the sensor,
  // 1 mm into contact, the sensor on the paper's right-angle mount at `start`.
  PushingSetup setup;
  setup.object = shortObjects().front();  // the blue square
  setup.start = start.head<2>();
  setup.sensor_height = height;
  const mujoco::SceneSpec scene = pushingScene(setup, contact_params, h);
  mujoco::World world(scene);
  MujocoSensorArm robot(world, 0);
  ContactModel contact(contact_params);
  GdnObservationModel gdn;  // the paper's Table 1 errors, seeded: the same run every time

  // 2. The tactile loop: the paper's filter with the χ² gate on, and the paper's single-arm
  //    pushing controller (Tables 7-8) aimed at the target, stepped together by one class (the
  //    same class the simulated tasks and the Franka program step; docs/control.md, section 8).
  TactileLoop<PushingController<SE3d>>::Options loop_options;
  loop_options.filter.gating = true;  // reject an observation whose NIS is above χ²(6) at 0.999
  loop_options.controller = pushingPreset<double>(PushingConfiguration::single_arm);
  loop_options.controller.target = SE3d(SO3d::identity(), target);
  TactileLoop<PushingController<SE3d>> loop(loop_options);
  if (!ok(loop.configurationStatus(), "tactile loop")) return 1;
  const PushingController<SE3d>& pusher = loop.controller();

  // 3. The real-time side: the channel that hands twists to the robot loop, and the pipeline
  //    (watchdog + base-frame conversion + jerk-limited smoother) that the robot loop runs.
  realtime::LatestValueChannel<realtime::TwistCommand> channel;
  realtime::PipelineOptions pipeline_options;
  pipeline_options.control_period_s = h;
  realtime::CartesianVelocityPipeline pipeline;
  if (!ok(pipeline.configure(pipeline_options), "pipeline")) return 1;
  const realtime::SmootherLimits<double>& limits = pipeline_options.limits;

  // 4. The loops. Time is simulated: the stamps are the engine's clock in ns.
  const long outlier_step = 200;  // 10 s in: one corrupted observation
  LoopOutcome outlier_outcome = LoopOutcome::refused;
  long rejected = 0, steps = 0;
  double fastest = 0, hardest = 0;  // the largest commanded base speed (m/s) and acceleration (m/s²)
  std::array<double, 6> last{};
  std::int64_t now_ns = 0;
  auto robotCycle = [&](bool stopping) {  // one cycle of the robot loop
    std::array<double, 6> base{};
    const Status s = stopping ? pipeline.stepStopping(base) : pipeline.step(inMetres(robot.pose()), channel, now_ns, base);
    if (s != Status::ok) {  // a bad pose or twist: stop this cycle instead, and stay stopped
      std::printf("robot loop: %s, stopping\n", describe(s));
      (void)pipeline.stepStopping(base);
    }
    fastest = std::max(fastest, std::hypot(base[0], base[1], base[2]));
    hardest = std::max(hardest, std::hypot(base[0] - last[0], base[1] - last[1], base[2] - last[2]) / h);
    last = base;
    if (!ok(robot.commandVelocity(baseToSensorTwist(robot.pose(), base), h), "robot")) return false;
    if (!ok(world.step(h), "engine")) return false;
    now_ns += static_cast<std::int64_t>(std::llround(h * 1e9));
    return true;
  };

  std::printf("   t (s)   object (x, y) mm   distance to target (mm)   bearing (deg)\n");
  while (steps * dt < 120) {
    // Tactile loop: observe, then filter and control in one step.
    const ContactState state = touchContact(world, 0, contact);  // what the sensor feels
    GdnObservation obs = gdn.observe(state);
    if (steps == outlier_step) obs.mu[1] += 30;  // the misread image: 30 mm of shear along y
    ConcentratedGaussian<SE3d> observation;
    if (!ok(fromTangentGaussian(obs.mu, obs.sigma, observation), "observation")) break;
    SE3d::Tangent u;
    // A refusal changes nothing and ends the run; everything else commands (the first step
    // initialises the filter; a gated observation is not an error: the controller then uses
    // the prediction from the robot's own motion).
    if (!ok(loop.step(robot.pose(), observation, dt, u), "tactile loop")) break;
    if (steps == outlier_step) outlier_outcome = loop.outcome();
    if (loop.outcome() == LoopOutcome::gated) ++rejected;
    if (loop.outcome() == LoopOutcome::terminated) break;  // the tip is within 20 mm of the target: stop (below)

    realtime::TwistCommand command;
    for (int i = 0; i < 6; ++i) command.twist_s[std::size_t(i)] = u[i];
    command.in_contact = state.in_contact;
    channel.write(command, now_ns);
    for (int j = 0; j < substeps; ++j)
      if (!robotCycle(false)) return 1;
    if (steps % 200 == 0) {
      const SE3d X_wo = world.objectPose(0);
      std::printf("  %6.1f   (%6.1f, %6.1f)   %23.1f   %13.1f\n", steps * dt, X_wo.translation().x(),
                  X_wo.translation().y(), pusher.terminationDistance(), rad2deg(pusher.bearing()));
    }
    ++steps;
  }
  // 5. Stop, the arm still moving: the watchdog stops passing commands and the smoother ramps
  //    the arm down within its acceleration and jerk limits.
  pipeline.requestStop();
  long stop_cycles = 0;
  while (!pipeline.stopped() && stop_cycles < 400) {
    if (!robotCycle(true)) return 1;
    ++stop_cycles;
  }

  const SE3d X_wo = world.objectPose(0);
  std::printf("after %.1f s: the tip %.1f mm from the target, the object at (%.1f, %.1f) mm; "
              "%ld observation(s) rejected by the gate; the injected one: %s\n",
              steps * dt, pusher.terminationDistance(), X_wo.translation().x(), X_wo.translation().y(), rejected,
              describe(outlier_outcome));
  std::printf("base commands: fastest %.1f mm/s (limit %.0f), hardest acceleration %.2f m/s^2 (limit %.1f); "
              "at rest %.1f ms after the stop request\n",
              fastest * 1e3, limits.translation.velocity * 1e3, hardest, limits.translation.acceleration,
              stop_cycles * h * 1e3);

  // Checks: the push ends at the target (the controller's termination, within 120 s); the
  // corrupted observation is rejected; no command exceeds the smoother's speed or acceleration
  // limit; the arm is at rest within 0.1 s of the stop request.
  const bool reached = pusher.terminated();
  const bool gated = outlier_outcome == LoopOutcome::gated;
  const bool within = fastest <= limits.translation.velocity * (1 + 1e-9) &&
                      hardest <= limits.translation.acceleration * (1 + 1e-9);
  const bool stopped = pipeline.stopped() && stop_cycles * h <= 0.1;
  std::printf("reached the target: %s; outlier rejected: %s; within the speed and acceleration limits: %s; stopped: %s\n",
              reached ? "yes" : "NO", gated ? "yes" : "NO", within ? "yes" : "NO", stopped ? "yes" : "NO");
  return reached && gated && within && stopped ? 0 : 1;
}

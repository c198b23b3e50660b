// Three tasks through the Franka adapter, each beside the driven-body run of the same scene:
// single-arm pushing of the paper's blue square on MDF (Section 5.6,
// sec:single_arm_object_pushing_exp), dual-arm pushing of it with two Pandas (Section 5.7,
// the paper's leader and follower) and surface following on the curved ramp (Section 5.5,
// sec:surface_follow_exp), with examples/franka/franka_adapter.cpp, unchanged, driving the
// simulated Panda of the libfranka test double. The tactile loop (this thread, 20 Hz of
// simulated time) observes the contact in the MuJoCo world, filters it and runs the task's
// controller; its twist goes through the adapter's channel to the 1 kHz callback on the
// adapter's own thread (watchdog, base-frame conversion, jerk-limited smoother) and moves the
// arm, a MuJoCo model of the Panda under its joint controller (panda_dynamics.hpp) that lags the
// commands and carries the contact's load; the world's sensor follows the arm's flange through
// the sensor mount. The arm and the
// world share one clock: the double runs in lockstep (franka_sim::Arm::advance), 2 or 3 arm
// cycles per 2.5 ms world step.
//
// What the driven-body world of the tasks does not show, reported here: the twist the arm
// achieved against the one commanded, the smoother's effect, the joints' lag and torques under
// the load, joint-limit margins, manipulability, watchdog trips, and the task's end beside the
// driven-body run. Bounds written
// before the first run.
#include <catch2/catch.hpp>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <thread>
#include <vector>
#include <algorithm>
#include <initializer_list>

#include <franka_adapter.hpp>
#include <franka_sim/arm.h>
#include <tactile_run.hpp>

#include "dynamic_servo.hpp"

#include <lieservo/lieservo.hpp>

#include "lieservo_sim/contact_model.hpp"
#include "lieservo_sim/mujoco_world.hpp"
#include "lieservo_sim/observation_model.hpp"
#include "lieservo_sim/panda_dynamics.hpp"
#include "lieservo_sim/sensor_arm.hpp"
#include "lieservo_sim/tasks.hpp"

using lieservo::Status;
using lieservo::franka_adapter::FrankaAdapter;
using lieservo::franka_adapter::FrankaAdapterOptions;
using namespace lieservo::sim;
using lieservo_test::DynamicServo;
namespace panda = lieservo::sim::panda;

namespace {

constexpr double kDt = 0.05;  // the 20 Hz tactile loop
const Vec3 kStart(-250, 100, 45), kTarget(0, 375, 45);

/// The blue square on MDF in front of a sensor at kStart on the paper's right-angle mount, 1 mm
/// into contact (the demo's pushing scene, lieservo::sim::pushingScene); `dual`: the follower
/// opposite, 3 mm into the far face. The scene of lesson 07 and of the driven-body pushing tasks.
mujoco::SceneSpec squareOnMdf(const ContactParams& contact, double h, bool dual = false) {
  PushingSetup setup;
  setup.object = shortObjects().front();
  setup.dual_arm = dual;
  setup.start = kStart.head<2>();
  setup.sensor_height = kStart.z();
  return pushingScene(setup, contact, h);
}

/// The flange pose O_T_EE of joints q, in mm.
SE3d flangeMm(const panda::Joints& q) {
  Eigen::Matrix4d T = panda::flange(q);
  T.topRightCorner<3, 1>() *= 1e3;
  return SE3d::fromMatrixUnchecked(T);
}

/// What one run of the tactile loop did.
struct RunOutcome {
  bool finished = false;           ///< the task said it had finished (pushing: terminated)
  double time = 0;                 ///< s simulated
  double max_twist_gap = 0;        ///< mm/s: achieved against commanded translation, worst period
  double rms_twist_gap = 0;        ///< mm/s, over the periods after the watchdog armed
  double max_pose_gap = 0;         ///< mm: the world's sensor against the arm's, worst step
  Status status = Status::ok;      ///< the first non-ok Status met (ok if none)
  std::string where;
};

Vec3 planar(const SE3d& X) {
  const Eigen::Matrix3d R = X.rotationMatrix();
  return Vec3(X.translation().x(), X.translation().y(), std::atan2(R(1, 0), R(0, 0)));
}

/// The tactile loop shared by every run, one period of kDt at a time: read X_ws, observe the
/// contact through the seeded GDN model (both runs of a task see the same noise sequence for the
/// same contacts), step the task's lieservo::TactileLoop (the filter, then the controller: the
/// class the simulated tasks and the Franka program step), let the task say from the true
/// contact whether it has finished, send the twist with `command`, and move the robot and the
/// world through the period with `run_period`.
/// One period's inputs and command, as `tactileLoop` records them when asked.
struct RecordedFrame {
  SE3d X_ws;
  lieservo::ConcentratedGaussian<SE3d> observation;
  SE3d::Tangent u;
};

template <class Task, class Command, class RunPeriod, class Pose>
RunOutcome tactileLoop(mujoco::World& world, const ContactParams& contact_params, double timeout, Task&& task,
                       Command command, RunPeriod run_period, Pose pose, std::vector<RecordedFrame>* record = nullptr) {
  RunOutcome out;
  ContactModel contact(contact_params);
  GdnObservationModel gdn;
  auto fail = [&](Status s, const char* where) {
    out.status = s;
    out.where = where;
  };
  double sum_gap2 = 0;
  long gaps = 0, lost = 0;
  for (long k = 0; k * kDt < timeout; ++k) {
    SE3d X_ws;
    Status s = pose(X_ws);
    if (s != Status::ok) return fail(s, "pose"), out;
    const ContactState state = touchContact(world, 0, contact);
    lost = state.in_contact ? 0 : lost + 1;
    if (lost * kDt >= 1.0) return fail(Status::invalid_argument, "contact lost for 1 s"), out;
    const GdnObservation obs = gdn.observe(state);
    lieservo::ConcentratedGaussian<SE3d> g;
    s = lieservo::fromTangentGaussian(obs.mu, obs.sigma, g);
    if (s != Status::ok) return fail(s, "observation"), out;
    SE3d::Tangent u;
    s = task.loop.step(X_ws, g, kDt, u);
    if (s != Status::ok) return fail(s, "tactile loop"), out;
    if (record) record->push_back({X_ws, g, u});
    const bool finished = task.finished(state);
    out.time = double(k) * kDt;
    if (finished) {
      out.finished = true;
      break;
    }
    s = command(u, state.in_contact);
    if (s != Status::ok) return fail(s, "command"), out;
    SE3d X_after;
    s = run_period();
    if (s == Status::ok) s = pose(X_after);
    if (s != Status::ok) return fail(s, "robot period"), out;
    // The twist achieved over the period (body twist, as commanded) against the command.
    const SE3d::Tangent achieved = (X_ws.inverse() * X_after).log() / kDt;
    if (k >= 10) {  // after the watchdog has armed (3 fresh commands) and the ramp
      const double gap = (achieved - u).head<3>().norm();
      out.max_twist_gap = std::max(out.max_twist_gap, gap);
      sum_gap2 += gap * gap;
      ++gaps;
    }
  }
  out.rms_twist_gap = gaps ? std::sqrt(sum_gap2 / double(gaps)) : 0.0;
  return out;
}

/// The driven-body robot: the world's sensors follow the commanded twists exactly (the tasks'
/// world, MujocoSensorArm), `substeps` world steps of h per period.
struct DrivenBodies {
  mujoco::World& world;
  std::vector<MujocoSensorArm> bodies;
  std::vector<SE3d::Tangent> u_now;
  int substeps;
  double h;

  DrivenBodies(mujoco::World& w, int n, double step) : world(w), substeps(n), h(step) {
    for (int s = 0; s < w.sensorCount(); ++s) bodies.emplace_back(w, s);
    u_now.assign(bodies.size(), SE3d::Tangent::Zero());
  }
  Status command(int arm, const SE3d::Tangent& u, bool) {
    u_now[std::size_t(arm)] = u;
    return Status::ok;
  }
  Status runPeriod() {
    for (int j = 0; j < substeps; ++j) {
      for (std::size_t a = 0; a < bodies.size(); ++a) {
        const Status s = bodies[a].commandVelocity(u_now[a], h);
        if (s != Status::ok) return s;
      }
      if (const Status s = world.step(h); s != Status::ok) return s;
    }
    return Status::ok;
  }
  Status pose(int arm, SE3d& X) { return bodies[std::size_t(arm)].readPose(X); }
};

/// The Panda of the libfranka test double holding the world's sensor `sensor`, commanded
/// through FrankaAdapter as on hardware. Its joints move under MuJoCo's dynamics (DynamicServo)
/// and carry the contact's load: before each world step the arm is given the force the world's
/// tip feels, at the contact point. The Panda starts at its ready pose with the sensor at the
/// scene's start: its base stands upright, turned by `base_yaw` about the vertical, the mount
/// X_ES puts the tip 100 mm beyond the flange along its z (the same right-angle mount for every
/// arm when the bases face each other), and the base goes where that puts it. The arm runs in
/// lockstep with the world: 2 or 3 arm cycles of 1 ms per 2.5 ms world step (runPeriods).
class AdapterRig {
 public:
  AdapterRig(const std::string& address, mujoco::World& world, int sensor = 0, double base_yaw = 0)
      : address_(address),
        servo_(std::make_shared<DynamicServo>(panda::readyPose())),
        arm_(franka_sim::Arm::create(address, panda::readyPose(), servo_)),
        remove_{address},
        world_(world),
        sensor_(sensor),
        X_ES_(mount(world, sensor, base_yaw)),
        X_wO_(world.sensorPose(sensor) * (flangeMm(panda::readyPose()) * X_ES_).inverse()),
        adapter_(options(address, X_ES_, X_wO_)) {
    REQUIRE((X_wO_.rotationMatrix() - rotZ(base_yaw)).norm() < 1e-12);
    arm_->setLockstep(true);
  }

  Status command(const SE3d::Tangent& u, bool in_contact) { return adapter_.commandVelocity(u, kDt, in_contact); }

  /// One tactile period of the world with this arm alone.
  Status runPeriod() { return runPeriods(world_, {this}); }

  /// One tactile period (substeps world steps of h) of the world with the arms together.
  static Status runPeriods(mujoco::World& world, std::initializer_list<AdapterRig*> rigs) {
    const int substeps = stepsPerPeriod(kDt);
    const double h = kDt / substeps;
    for (AdapterRig* r : rigs)
      if (const Status s = r->awaitControl(); s != Status::ok) return s;
    for (int j = 0; j < substeps; ++j) {
      const int cycles = j % 2 == 0 ? 2 : 3;  // 50 cycles of 1 ms per 20 steps of 2.5 ms
      for (AdapterRig* r : rigs)
        if (const Status s = r->armCycles(cycles, h); s != Status::ok) return s;
      if (const Status s = world.step(h); s != Status::ok) return s;
    }
    for (AdapterRig* r : rigs) r->countWatchdog();
    return Status::ok;
  }

  Status pose(SE3d& X) { return adapter_.readPose(X); }

  /// Ends the run (the stop's ramp runs at wall-clock pace) and prints and checks what the
  /// driven-body world does not show, with the bounds written before the first run: no error
  /// anywhere (double, adapter, pipeline, watchdog); after the watchdog has armed, the
  /// translation achieved over each period within 2 mm/s rms (5 mm/s worst) of the command (the
  /// smoother's lag at the tasks' 10-25 mm/s); the world's sensor within 0.5 mm of the flange's
  /// mount; the arm inside its joint limits and away from singularities; the joint controller's
  /// torques inside the Panda's limits.
  void finishAndCheck(const char* task, RunOutcome& run) {
    run.max_pose_gap = max_pose_gap_;
    const auto stats = adapter_.stats();
    arm_->setLockstep(false);
    adapter_.stop();
    const franka_sim::ArmReport report = arm_->report();
    std::printf(
        "  %s through the adapter: achieved against commanded twist: rms %.3f mm/s, worst %.3f mm/s; world sensor "
        "against the arm's flange: %.4f mm; watchdog arming for %ld periods, tripped after %ld; %s %s\n",
        task, run.rms_twist_gap, run.max_twist_gap, run.max_pose_gap, waiting_, trips_,
        run.status == Status::ok ? "no error" : describe(run.status), run.where.c_str());
    std::printf(
        "  the double: %llu cycles, %llu errors %s; min joint margin %.3f rad, min manipulability %.4f, damped "
        "cycles %llu, max speed %.1f mm/s, accel %.2f m/s^2, jerk %.0f m/s^3; adapter callbacks %llu, pipeline "
        "errors %llu\n",
        static_cast<unsigned long long>(report.cycles), static_cast<unsigned long long>(report.errors),
        report.last_error.c_str(), report.min_joint_margin, report.min_manipulability,
        static_cast<unsigned long long>(report.damped_cycles), report.max_speed * 1e3, report.max_accel,
        report.max_jerk, static_cast<unsigned long long>(stats.callbacks),
        static_cast<unsigned long long>(stats.pipeline_errors));
    std::printf(
        "  the dynamic arm: flange velocity achieved against commanded, worst cycle %.3f mm/s; joints behind the "
        "desired trajectory by at most %.2e rad; joint torques at most %.1f %% of their limits; contact load at most "
        "%.2f N\n",
        report.max_achieved_error * 1e3, servo_->max_lag, servo_->max_torque_ratio * 100, max_load_);
    CHECK(run.status == Status::ok);
    CHECK(report.errors == 0);
    CHECK(stats.pipeline_errors == 0);
    CHECK(trips_ == 0);
    CHECK(run.rms_twist_gap <= 2.0);
    CHECK(run.max_twist_gap <= 5.0);
    CHECK(run.max_pose_gap <= 0.5);
    CHECK(report.min_joint_margin > 0.0);
    CHECK(report.damped_cycles == 0);
    CHECK(servo_->max_torque_ratio < 1.0);  // the joint controller never saturates
  }

 private:
  // The adapter starts its control loop on the first command: wait for it (≤ 2 s).
  Status awaitControl() {
    for (int i = 0; i < 2000 && !arm_->inControl(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    return arm_->inControl() ? Status::ok : Status::device_error;
  }
  // The arm's share of one world step of h: the load, its 1 kHz cycles, and the world's sensor
  // sent after the flange.
  Status armCycles(int cycles, double h) {
    // The load: the tip's push on what it touches, reversed, at the contact point (m, {O}).
    const mujoco::TipGeometry tip = world_.tipGeometry(sensor_);
    const Vec3 f_w = -world_.tipContactForce(sensor_);
    const Vec3 p_w = tip.valid ? tip.point_w : world_.sensorPose(sensor_).translation();
    max_load_ = std::max(max_load_, f_w.norm());
    arm_->setLoad(X_wO_.rotationMatrix().transpose() * f_w, (X_wO_.inverse() * p_w) * 1e-3);
    if (arm_->advance(cycles) != cycles) return Status::device_error;
    // The world's sensor follows the flange: the body twist that takes it there in h.
    const SE3d X_arm = X_wO_ * flangeMm(arm_->joints()) * X_ES_;
    const SE3d X_world = world_.sensorPose(sensor_);
    max_pose_gap_ = std::max(max_pose_gap_, (X_arm.translation() - X_world.translation()).norm());
    return world_.setSensorTwist(sensor_, (X_world.inverse() * X_arm).log() / h);
  }
  void countWatchdog() {
    const auto state = adapter_.stats().watchdog;
    if (state == lieservo::realtime::WatchdogState::waiting) ++waiting_;  // arming: 3 fresh commands
    else if (state != lieservo::realtime::WatchdogState::active) ++trips_;
  }
  static SE3d mount(const mujoco::World& world, int sensor, double base_yaw) {
    const SE3d X_OE0 = flangeMm(panda::readyPose());
    return SE3d(SO3d::fromMatrixUnchecked(X_OE0.rotationMatrix().transpose() * rotZ(base_yaw).transpose() *
                                          world.sensorPose(sensor).rotationMatrix()),
                Vec3(0, 0, 100));
  }
  static FrankaAdapterOptions options(const std::string& address, const SE3d& X_ES, const SE3d& X_wO) {
    FrankaAdapterOptions o;
    o.robot_ip = address;
    o.enforce_realtime = false;
    o.X_ee_s = X_ES;
    o.X_w_base = X_wO;
    return o;
  }
  struct Remove {
    std::string a;
    ~Remove() { franka_sim::Arm::remove(a); }
  };

  std::string address_;
  std::shared_ptr<DynamicServo> servo_;
  std::shared_ptr<franka_sim::Arm> arm_;
  Remove remove_;
  mujoco::World& world_;
  int sensor_;
  SE3d X_ES_, X_wO_;
  FrankaAdapter adapter_;
  double max_pose_gap_ = 0, max_load_ = 0;
  long trips_ = 0, waiting_ = 0;  // periods ending with the watchdog tripped, or still arming
};

/// What one dual-arm run did.
struct DualOutcome {
  bool finished = false;         ///< the leader reached the target (the controller terminated)
  double time = 0;               ///< s simulated
  double min_opposition = 180;   ///< deg: the smallest angle between the contact normals
  long follower_out = 0;         ///< periods with the follower out of contact
  long both_touching = 0;        ///< periods with both arms in contact (where the angle is read)
  RunOutcome arm[2];            ///< per arm: the achieved against commanded twist (as tactileLoop)
  Status status = Status::ok;    ///< the first non-ok Status met (ok if none)
  std::string where;
};

/// The paper's dual-arm pushing (Tables 8-9: DualArmPushing, with its two filters) for the
/// scene's two sensors, one tactile period at a time, as tactileLoop does for one arm: each
/// arm's contact observed through its seeded GDN model, both commanded, then the period run.
template <class Command, class RunPeriod, class Pose>
DualOutcome dualLoop(mujoco::World& world, const ContactParams& contact_params, double timeout, Command command,
                     RunPeriod run_period, Pose pose) {
  DualOutcome out;
  auto options = lieservo::dualArmPushingPreset<double>(false);
  options.leader.target = SE3d(SO3d::identity(), kTarget);
  lieservo::DualArmPushing<lieservo::SE3d> dual(options, lieservo::DiscriminativeBayesFilter<SE3d>(),
                                        lieservo::DiscriminativeBayesFilter<SE3d>());
  REQUIRE(dual.configurationStatus() == Status::ok);
  ContactModel contact[2] = {ContactModel(contact_params), ContactModel(contact_params)};
  GdnObservationModel gdn[2] = {GdnObservationModel(GdnCalibration::paperTable1(), {}, 1),
                                GdnObservationModel(GdnCalibration::paperTable1(), {}, 2)};
  auto fail = [&](Status s, const char* where) {
    out.status = s;
    out.where = where;
    return out;
  };
  long lost = 0, gaps = 0;  // gaps: per-arm samples, both arms counted
  for (long k = 0; k * kDt < timeout; ++k) {
    lieservo::DualArmPushing<lieservo::SE3d>::ArmInput in[2];
    ContactState state[2];
    for (int a = 0; a < 2; ++a) {
      if (const Status s = pose(a, in[a].sensor_pose); s != Status::ok) return fail(s, "pose");
      state[a] = touchContact(world, a, contact[a]);
      const GdnObservation obs = gdn[a].observe(state[a]);
      if (const Status s = lieservo::fromTangentGaussian(obs.mu, obs.sigma, in[a].observation); s != Status::ok)
        return fail(s, "observation");
    }
    lost = state[0].in_contact ? 0 : lost + 1;
    if (lost * kDt >= 1.0) return fail(Status::invalid_argument, "leader's contact lost for 1 s");
    if (!state[1].in_contact) ++out.follower_out;
    if (state[0].in_contact && state[1].in_contact) ++out.both_touching;
    if (state[0].in_contact && state[1].in_contact)
      out.min_opposition = std::min(
          out.min_opposition,
          std::acos(std::clamp(state[0].normal_w.dot(state[1].normal_w), -1.0, 1.0)) * 180 / lieservo::pi<double>());
    lieservo::DualArmPushing<lieservo::SE3d>::ArmOutput u[2];
    if (const Status s = dual.step(in[0], in[1], kDt, u[0], u[1]); s != Status::ok) return fail(s, "controller");
    out.time = double(k) * kDt;
    if (dual.terminated()) {
      out.finished = true;
      break;
    }
    for (int a = 0; a < 2; ++a)
      if (const Status s = command(a, u[a].velocity, state[a].in_contact); s != Status::ok) return fail(s, "command");
    if (const Status s = run_period(); s != Status::ok) return fail(s, "robot period");
    for (int a = 0; a < 2 && k >= 10; ++a) {  // after the watchdogs have armed, as tactileLoop
      SE3d X_after;
      if (const Status s = pose(a, X_after); s != Status::ok) return fail(s, "pose");
      const double gap = ((in[a].sensor_pose.inverse() * X_after).log() / kDt - u[a].velocity).head<3>().norm();
      out.arm[a].max_twist_gap = std::max(out.arm[a].max_twist_gap, gap);
      out.arm[a].rms_twist_gap += gap * gap;  // a sum until the end
      ++gaps;
    }
  }
  for (RunOutcome& a : out.arm) a.rms_twist_gap = gaps ? std::sqrt(2 * a.rms_twist_gap / double(gaps)) : 0.0;
  return out;
}

/// The following task's ramp (followingRamp) under a sensor pointing down (z_s = −z_w,
/// y_s = +y_w) at 3 mm depth, 30 mm before the curve, as the task starts it.
mujoco::SceneSpec followingScene(const ContactParams& contact, double h) {
  mujoco::SceneSpec scene;
  scene.timestep = h;
  scene.fixtures = {followingRamp()};
  scene.fixtures[0].friction = contact.skin_friction;
  const double y0 = -30, depth = lieservo::paper::kSurfaceFollowing.reference_pose[2];
  scene.sensors = {taskSensor("sensor", contact,
                              makePose(fromColumns(-Vec3::UnitX(), Vec3::UnitY(), -Vec3::UnitZ()),
                                       Vec3(0, y0, mujoco::rampHeight(scene.fixtures[0], y0) + contact.tip_radius - depth)))};
  return scene;
}

/// Surface following along the ramp (Table 7's servo, 10 mm/s along +y) until the contact passes
/// y = L + 30, with the depth error and tilt of the true contact every period (as the task).
struct Following {
  using Loop = lieservo::TactileLoop<lieservo::TactileServoController<SE3d>>;
  Loop loop;
  Stat depth_error, tilt;  // |depth − 3 mm| (mm), angle of z_s from the normal (deg)
  bool contact_kept = true;

  Following() {
    Loop::Options o;
    o.controller = lieservo::surfaceFollowingPreset<double>();
    o.controller.feedforward = lieservo::surfaceFollowingFeedforward<double>(lieservo::pi<double>() / 2);
    REQUIRE(loop.configure(o) == Status::ok);
  }
  bool finished(const ContactState& c) {
    depth_error.add(c.depth - lieservo::paper::kSurfaceFollowing.reference_pose[2]);
    tilt.add(c.tilt * 180 / lieservo::pi<double>());
    contact_kept = contact_kept && c.in_contact;
    return c.point_w.y() > followingRamp().size2 + 30;
  }
};

/// Single-arm pushing: Table 8's controller towards kTarget; the trial ends when it terminates.
struct Pushing {
  using Loop = lieservo::TactileLoop<lieservo::PushingController<lieservo::SE3d>>;
  Loop loop;
  Pushing() {
    Loop::Options o;
    o.controller = lieservo::pushingPreset<double>(lieservo::PushingConfiguration::single_arm);
    o.controller.target = SE3d(SO3d::identity(), kTarget);
    REQUIRE(loop.configure(o) == Status::ok);
  }
  bool finished(const ContactState&) const { return loop.outcome() == lieservo::LoopOutcome::terminated; }
};

}  // namespace

namespace {

/// The Franka program's side of the comparison below: recorded frames as its front end's
/// samples (a first one that only sets the clock, then one every 50 ms), and a robot that reads
/// the recorded poses and keeps what it is commanded.
struct RecordedFrontEnd final : lieservo::franka_example::TactileFrontEnd {
  const std::vector<RecordedFrame>& frames;
  std::size_t next_frame = 0;
  bool clock_set = false;
  explicit RecordedFrontEnd(const std::vector<RecordedFrame>& f) : frames(f) {}
  bool next(lieservo::franka_example::TactileSample& out, std::string& error) override {
    const std::size_t k = clock_set ? next_frame++ : 0;
    if (k >= frames.size()) {
      error = "end of the recording";
      return false;
    }
    out.observation = frames[k].observation;
    out.in_contact = true;
    out.stamp = std::chrono::steady_clock::time_point{} + std::chrono::milliseconds(50 * (clock_set ? k + 1 : 0));
    clock_set = true;
    return true;
  }
};
struct RecordingRobot {
  struct Stats {
    bool faulted = false;
    lieservo::realtime::WatchdogState watchdog = lieservo::realtime::WatchdogState::active;
  };
  const std::vector<RecordedFrame>& frames;
  std::size_t reads = 0;
  std::vector<SE3d::Tangent> commands;
  std::vector<double> dts;
  explicit RecordingRobot(const std::vector<RecordedFrame>& f) : frames(f) {}
  Status readPose(SE3d& X) {
    // Once before the first frame, then once a frame.
    X = frames[std::min(reads == 0 ? 0 : reads - 1, frames.size() - 1)].X_ws;
    ++reads;
    return Status::ok;
  }
  Status commandVelocity(const SE3d::Tangent& u, double dt, bool) {
    commands.push_back(u);
    dts.push_back(dt);
    return Status::ok;
  }
  Stats stats() const { return {}; }
  std::string lastError() const { return ""; }
};

}  // namespace

TEST_CASE("the Franka program's tactile thread commands what the simulation's loop commands, bit for bit",
          "[robot][franka][loop]") {
  const ContactParams contact_params;
  const int substeps = stepsPerPeriod(kDt);
  const double h = kDt / substeps;
  // The simulation's path: the pushing scene's first 8 s, the sensor body driven by the twists.
  std::vector<RecordedFrame> frames;
  {
    mujoco::World world(squareOnMdf(contact_params, h));
    DrivenBodies robot(world, substeps, h);
    const RunOutcome run = tactileLoop(
        world, contact_params, 8.0, Pushing(), [&](const SE3d::Tangent& u, bool c) { return robot.command(0, u, c); },
        [&] { return robot.runPeriod(); }, [&](SE3d& X) { return robot.pose(0, X); }, &frames);
    REQUIRE(run.status == Status::ok);
  }
  REQUIRE(frames.size() >= 150);
  // The Franka program's path (examples/franka/tactile_run.hpp) on the same frames.
  RecordedFrontEnd sensor(frames);
  RecordingRobot robot(frames);
  Pushing task;
  lieservo::franka_example::RunSettings settings;
  settings.duration_s = 3600;
  const std::atomic<bool> quit{false};
  const std::string ended = lieservo::franka_example::runTactileLoop(settings, robot, sensor, task.loop, quit);
  CHECK(ended == "tactile front end failed: end of the recording");
  REQUIRE(robot.commands.size() == frames.size());
  long same = 0;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    same += std::memcmp(robot.commands[k].data(), frames[k].u.data(), sizeof(double) * 6) == 0;
    CHECK(robot.dts[k] == kDt);
  }
  CHECK(same == long(frames.size()));
}

TEST_CASE("franka adapter on the double: single-arm pushing of the blue square on MDF", "[robot][franka][task]") {
  const ContactParams contact_params;
  const int substeps = stepsPerPeriod(kDt);  // 20 world steps of 2.5 ms per tactile period
  const double h = kDt / substeps;
  constexpr double kTimeout = 120;

  // 1. The driven-body run: the sensor body follows the controller's twist exactly.
  RunOutcome driven;
  Vec3 driven_object;
  {
    mujoco::World world(squareOnMdf(contact_params, h));
    DrivenBodies robot(world, substeps, h);
    driven = tactileLoop(
        world, contact_params, kTimeout, Pushing(),
        [&](const SE3d::Tangent& u, bool c) { return robot.command(0, u, c); }, [&] { return robot.runPeriod(); },
        [&](SE3d& X) { return robot.pose(0, X); });
    driven_object = planar(world.objectPose(0));
  }

  // 2. The same scene through the adapter on the double's Panda.
  mujoco::World world(squareOnMdf(contact_params, h));
  AdapterRig rig("sim-panda-pushing-task", world);
  RunOutcome through = tactileLoop(
      world, contact_params, kTimeout, Pushing(), [&](const SE3d::Tangent& u, bool c) { return rig.command(u, c); },
      [&] { return rig.runPeriod(); }, [&](SE3d& X) { return rig.pose(X); });
  const Vec3 object = planar(world.objectPose(0));
  std::printf(
      "pushing: %s after %.1f s through the adapter (driven body: %s after %.1f s); object at (%.1f, %.1f) mm, "
      "%.1f deg (driven body: (%.1f, %.1f) mm, %.1f deg); driven body's twist gap rms %.3f mm/s\n",
      through.finished ? "reached" : "NOT reached", through.time, driven.finished ? "reached" : "NOT reached",
      driven.time, object.x(), object.y(), object.z() * 180 / lieservo::pi<double>(), driven_object.x(),
      driven_object.y(), driven_object.z() * 180 / lieservo::pi<double>(), driven.rms_twist_gap);
  rig.finishAndCheck("pushing", through);

  // Bounds, written before the first run (the adapter's own in finishAndCheck):
  // - both runs reach the target (the controller's termination: the tip within 20 mm) within
  //   120 s;
  CHECK(driven.finished);
  CHECK(driven.status == Status::ok);
  CHECK(through.finished);
  // - the object ends where the driven-body run leaves it, within 30 mm (the two runs differ by
  //   the smoother and the arm's 1 kHz steps, and pushing amplifies small differences).
  CHECK((object.head<2>() - driven_object.head<2>()).norm() <= 30.0);
}

TEST_CASE("franka adapter on the double: dual-arm pushing of the blue square on MDF with two Pandas",
          "[robot][franka][task]") {
  // Two Pandas facing each other across the object, each with its own adapter (its own 1 kHz
  // thread), the same right-angle mount, the paper's leader and follower (Tables 8-9); this
  // thread is the tactile loop of both. Bounds, written before the first run: both runs reach
  // the target within 120 s with the contact normals at least 150 deg apart whenever both touch
  // (the demo's opposition criterion) and the leader's contact never lost for 1 s; each arm
  // within the adapter's bounds (finishAndCheck); the object within 30 mm of the driven-body
  // run's.
  const ContactParams contact_params;
  const int substeps = stepsPerPeriod(kDt);
  const double h = kDt / substeps;
  constexpr double kTimeout = 120;

  DualOutcome driven;
  Vec3 driven_object;
  {
    mujoco::World world(squareOnMdf(contact_params, h, true));
    DrivenBodies robot(world, substeps, h);
    driven = dualLoop(
        world, contact_params, kTimeout,
        [&](int a, const SE3d::Tangent& u, bool c) { return robot.command(a, u, c); },
        [&] { return robot.runPeriod(); }, [&](int a, SE3d& X) { return robot.pose(a, X); });
    driven_object = planar(world.objectPose(0));
  }

  mujoco::World world(squareOnMdf(contact_params, h, true));
  AdapterRig leader("sim-panda-dual-leader", world, 0, 0.0);
  AdapterRig follower("sim-panda-dual-follower", world, 1, lieservo::pi<double>());
  AdapterRig* rigs[2] = {&leader, &follower};
  DualOutcome through = dualLoop(
      world, contact_params, kTimeout,
      [&](int a, const SE3d::Tangent& u, bool c) { return rigs[a]->command(u, c); },
      [&] { return AdapterRig::runPeriods(world, {&leader, &follower}); },
      [&](int a, SE3d& X) { return rigs[a]->pose(X); });
  const Vec3 object = planar(world.objectPose(0));
  std::printf(
      "dual-arm pushing: %s after %.1f s through two adapters (driven bodies: %s after %.1f s); contact normals at "
      "least %.1f deg apart (driven: %.1f), follower out of contact for %ld periods (driven: %ld); object at (%.1f, "
      "%.1f) mm, %.1f deg (driven bodies: (%.1f, %.1f) mm, %.1f deg) %s %s\n",
      through.finished ? "reached" : "NOT reached", through.time, driven.finished ? "reached" : "NOT reached",
      driven.time, through.min_opposition, driven.min_opposition, through.follower_out, driven.follower_out,
      object.x(), object.y(), object.z() * 180 / lieservo::pi<double>(), driven_object.x(), driven_object.y(),
      driven_object.z() * 180 / lieservo::pi<double>(), describe(through.status), through.where.c_str());
  for (RunOutcome& a : through.arm) {
    a.status = through.status;
    a.where = through.where;
  }
  leader.finishAndCheck("dual-arm leader", through.arm[0]);
  follower.finishAndCheck("dual-arm follower", through.arm[1]);

  for (const DualOutcome* r : {&driven, &through}) {
    CHECK(r->finished);
    CHECK(r->status == Status::ok);
    CHECK(r->min_opposition >= 150.0);
    CHECK(r->both_touching > 0);  // the angle was read at all
  }
  CHECK((object.head<2>() - driven_object.head<2>()).norm() <= 30.0);
}

TEST_CASE("franka adapter on the double: surface following on the curved ramp", "[robot][franka][task]") {
  const ContactParams contact_params;
  const int substeps = stepsPerPeriod(kDt);
  const double h = kDt / substeps;
  const double timeout = 1.6 * (followingRamp().size2 + 60) / 10;  // the task's: 1.6 × the path at 10 mm/s

  // 1. The driven-body run (the task's world).
  Following driven;
  RunOutcome driven_run;
  {
    mujoco::World world(followingScene(contact_params, h));
    DrivenBodies robot(world, substeps, h);
    driven_run = tactileLoop(
        world, contact_params, timeout, driven,
        [&](const SE3d::Tangent& u, bool c) { return robot.command(0, u, c); }, [&] { return robot.runPeriod(); },
        [&](SE3d& X) { return robot.pose(0, X); });
  }
  driven.depth_error.finish();
  driven.tilt.finish();

  // 2. The same path through the adapter on the double's Panda.
  mujoco::World world(followingScene(contact_params, h));
  AdapterRig rig("sim-panda-following-task", world);
  Following through;
  RunOutcome run = tactileLoop(
      world, contact_params, timeout, through,
      [&](const SE3d::Tangent& u, bool c) { return rig.command(u, c); }, [&] { return rig.runPeriod(); },
      [&](SE3d& X) { return rig.pose(X); });
  through.depth_error.finish();
  through.tilt.finish();
  std::printf(
      "following the ramp: %s after %.1f s through the adapter (driven body: %s after %.1f s); depth error mean %.2f "
      "/ max %.2f mm, tilt mean %.2f / max %.2f deg (driven body: %.2f / %.2f mm, %.2f / %.2f deg)\n",
      run.finished ? "reached the end" : "did NOT reach the end", run.time,
      driven_run.finished ? "reached the end" : "did NOT reach the end", driven_run.time, through.depth_error.mean,
      through.depth_error.max, through.tilt.mean, through.tilt.max, driven.depth_error.mean, driven.depth_error.max,
      driven.tilt.mean, driven.tilt.max);
  rig.finishAndCheck("following", run);

  // Bounds, written before the first run (the adapter's own in finishAndCheck): both runs reach
  // the end of the path with contact kept and within the surface-following task's bounds
  // (Bounds::following_*: depth error mean 0.5 / max 2.5 mm, tilt mean 3 / max 10 deg).
  for (const auto* f : {&driven, &through}) {
    CHECK(f->contact_kept);
    CHECK(f->depth_error.mean <= Bounds::following_depth_mean);
    CHECK(f->depth_error.max <= Bounds::following_depth_max);
    CHECK(f->tilt.mean <= Bounds::following_tilt_mean);
    CHECK(f->tilt.max <= Bounds::following_tilt_max);
  }
  CHECK(driven_run.finished);
  CHECK(driven_run.status == Status::ok);
  CHECK(run.finished);
}

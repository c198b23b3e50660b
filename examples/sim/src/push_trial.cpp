// One pushing trial on MuJoCo (paper Section 5.6 (sec:single_arm_object_pushing_exp), Section 5.7
// (sec:dual_arm_object_pushing_exp), Section 5.7.2 (sec:dual_arm_tall_object_pushing)).
//
// Work frame: the support is the x–y plane, z up. The leader's sensor starts at
// (x, y, z) = (−250, 100, 45) mm with its axis along +x (right-angle mount: x_s up,
// y_s = −y_w), the object is placed centrally in front of it with a face normal to the sensor
// axis at 1 mm depth (seeded jitter: sideways and yaw normal, sd 2 mm and 2°, clipped at
// 2 sd), and the target is (x, y) = (0, 375) mm. The dual-arm follower starts opposite, normal
// to the far face at 3 mm.
//
// Each control period (20 Hz): observation → filter → controller → twist (the library's
// TactileLoop, or DualArmPushing for two arms); then, per MuJoCo step, each sensor arm moves by
// its twist (MujocoSensorArm), the engine steps (objects slide, turn and topple under the gel
// and support contacts), and each sensor's contact state (ContactModel: feature frame, depth,
// stick/slip shear) is updated from the engine's tip geometry.
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include <lieservo/control/centralised_dual_arm.hpp>
#include <lieservo/control/dual_arm.hpp>
#include <lieservo/control/presets.hpp>
#include <lieservo/control/pushing_controller.hpp>
#include <lieservo/sampling/random.hpp>

#include "task_common.hpp"

namespace lieservo::sim {

namespace {

using detail::EngineArm;
using detail::Filter;
using mujoco::World;

constexpr double kGiveUpAfter = 1.0;  // s out of contact: the push has failed, stop the trial
constexpr double kPassedBy = 20;      // mm beyond the closest approach, inside ρ*: the target was passed

Vec3 objectPlanar(const SE3d& X) {
  const Mat3 R = X.rotationMatrix();
  return Vec3(X.translation().x(), X.translation().y(), std::atan2(R(1, 0), R(0, 0)));
}

double cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

// The trial's scene: the support's μ_s within ±10 %, or all three assumed parameters drawn
// from their ranges (--randomise), into `opt` and `tr`; the object placed by hand in front of
// the leader (pushingScene).
mujoco::SceneSpec pushScene(const PushingSetup& setup, TaskOptions& opt, lieservo::sampling::Rng& rng, double h,
                            PushTrial& tr) {
  auto draw = [&](const double (&range)[2]) { return lieservo::sampling::uniform(rng, range[0], range[1]); };
  // Drawn even when TaskOptions fixes it, so that μ_c and k_gel draw as they would.
  const double friction_scale = opt.randomise ? draw(opt.ranges.support_friction_scale) : draw({0.9, 1.1});
  if (opt.randomise) {
    opt.contact.skin_friction = draw(opt.ranges.skin_friction);
    opt.contact.gel_stiffness = draw(opt.ranges.gel_stiffness);
  }
  // Placed by hand in front of the leader: the offset and yaw drawn (normal, sd 2 mm and 2°,
  // clipped at 2 sd; a round object is not turned), or fixed by TaskOptions.
  const bool round = setup.object.shape == "circle";
  const double drawn_offset = 2.0 * std::clamp(lieservo::sampling::standardNormal(rng), -2.0, 2.0);
  const double drawn_yaw = round ? 0.0 : deg2rad(2.0) * std::clamp(lieservo::sampling::standardNormal(rng), -2.0, 2.0);
  tr.start_offset = std::isnan(opt.start_offset) ? drawn_offset : opt.start_offset;
  tr.start_yaw = round ? 0.0 : std::isnan(opt.start_yaw) ? drawn_yaw : opt.start_yaw;
  const mujoco::SceneSpec scene =
      pushingScene(setup, opt.contact, h, {tr.start_offset, tr.start_yaw},
                   std::isnan(opt.support_friction_scale) ? friction_scale : opt.support_friction_scale);
  tr.support_friction = scene.support.friction;
  tr.skin_friction = opt.contact.skin_friction;
  tr.gel_stiffness = opt.contact.gel_stiffness;
  return scene;
}

// The trial's tactile loops: the single-arm TactileLoop, or both arms under the paper's
// dual-arm controller or the centralised one, configured from their presets with the target.
class PushControl {
 public:
  PushControl(const PushingSetup& setup, const SE3d& X_wt) : dual_arm_(setup.dual_arm), centralised_(setup.centralised) {
    if (dual_arm_ && centralised_) {
      auto o = lieservo::centralisedDualArmPushingPreset<double>(setup.tall);
      o.arms.leader.target = X_wt;
      central_ = lieservo::CentralisedDualArmPushing<lieservo::SE3d>(o, Filter(), Filter());
      if (central_.configurationStatus() != Status::ok) throw SceneError("centralised dual-arm preset rejected");
    } else if (dual_arm_) {
      auto o = lieservo::dualArmPushingPreset<double>(setup.tall);
      o.leader.target = X_wt;
      dual_ = lieservo::DualArmPushing<lieservo::SE3d>(o, Filter(), Filter());
      if (dual_.configurationStatus() != Status::ok) throw SceneError("dual-arm pushing preset rejected");
    } else {
      detail::PushLoop::Options o;
      o.controller = lieservo::pushingPreset<double>(lieservo::PushingConfiguration::single_arm);
      o.controller.target = X_wt;
      if (single_.configure(o) != Status::ok) throw SceneError("pushing preset rejected");
    }
  }

  /// One control period: each arm observes, and its loop writes its twist.
  Status step(EngineArm& leader, EngineArm* follower, double dt, Vec6& uL, Vec6& uF) {
    if (!dual_arm_) return leader.step(single_, dt, uL);
    lieservo::DualArmPushing<lieservo::SE3d>::ArmInput inL, inF;
    inL.sensor_pose = leader.pose();
    inF.sensor_pose = follower->pose();
    Status s = leader.observe(inL.observation);
    if (s == Status::ok) s = follower->observe(inF.observation);
    lieservo::DualArmPushing<lieservo::SE3d>::ArmOutput oL, oF;
    if (s == Status::ok) s = centralised_ ? central_.step(inL, inF, dt, oL, oF) : dual_.step(inL, inF, dt, oL, oF);
    uL = oL.velocity;
    uF = oF.velocity;
    return s;
  }

  bool terminated() const {
    return dual_arm_ ? (centralised_ ? central_.terminated() : dual_.terminated()) : single_.terminated();
  }
  const lieservo::PushingController<lieservo::SE3d>& pusher() const {
    return dual_arm_ ? (centralised_ ? central_.leader() : dual_.leader()) : single_.controller();
  }

 private:
  bool dual_arm_, centralised_;
  detail::PushLoop single_;
  lieservo::DualArmPushing<lieservo::SE3d> dual_;
  lieservo::CentralisedDualArmPushing<lieservo::SE3d> central_;
};

// What a trial counts over its periods.
struct Counts {
  long steps = 0, follower_steps_in_contact = 0, leader_force_steps = 0;
  double lost_for = 0;  // s the leader has been out of contact
};

// One period's engine steps: each arm moves by its twist, the engine steps, the contacts are
// updated; the tip contact forces averaged over the period into fL, fF.
void moveArms(World& world, EngineArm& leader, EngineArm* follower, const Vec6& uL, const Vec6& uF, int substeps,
              double h, Vec3& fL, Vec3& fF) {
  fL = fF = Vec3::Zero();
  for (int j = 0; j < substeps; ++j) {
    Status moved = leader.arm.commandVelocity(uL, h);
    if (moved == Status::ok && follower) moved = follower->arm.commandVelocity(uF, h);
    if (moved == Status::ok) moved = world.step(h);
    if (moved != Status::ok) break;
    leader.touch(world);
    if (follower) follower->touch(world);
    fL += world.tipContactForce(0) / substeps;
    if (follower) fF += world.tipContactForce(1) / substeps;
  }
}

// The follower's contact, depth, path and the opposition of the two contact normals this period.
void recordFollower(const ContactState& cL, const EngineArm& follower, const Vec3& fF, Counts& n, PushTrial& tr) {
  const ContactState& cF = follower.state;
  if (!cF.in_contact) tr.follower_contact_kept = false;
  else ++n.follower_steps_in_contact, tr.follower_vertical_force += fF.z();
  tr.max_follower_depth = std::max(tr.max_follower_depth, cF.depth);
  tr.min_follower_depth = std::min(tr.min_follower_depth, cF.depth);
  tr.follower_path.push_back(follower.pose().translation());
  double angle = std::numeric_limits<double>::quiet_NaN();
  if (cL.in_contact && cF.in_contact) angle = rad2deg(std::acos(std::clamp(cL.normal_w.dot(cF.normal_w), -1.0, 1.0)));
  tr.opposition.push_back(angle);
  if (!std::isnan(angle)) tr.min_opposition = std::min(tr.min_opposition, angle);
}

// Records one period; true when the trial ends here (the target passed, the object toppled).
bool recordPeriod(const PushingSetup& setup, World& world, const EngineArm& leader, const EngineArm* follower,
                  const lieservo::PushingController<lieservo::SE3d>& pusher, const Vec3& fL, const Vec3& fF, double dt,
                  Counts& n, PushTrial& tr) {
  const ContactState& cL = leader.state;
  if (!cL.in_contact) tr.contact_kept = false;
  n.lost_for = cL.in_contact ? 0.0 : n.lost_for + dt;
  tr.max_leader_depth = std::max(tr.max_leader_depth, cL.depth);
  if (cL.in_contact) tr.leader_vertical_force += fL.z(), ++n.leader_force_steps;
  if (follower) recordFollower(cL, *follower, fF, n, tr);
  tr.sensor_path.push_back(leader.pose().translation());
  tr.bearing.push_back(rad2deg(pusher.bearing()));
  tr.alignment_velocity.push_back(pusher.alignmentVelocity()[1]);
  tr.leader_depth.push_back(cL.depth);
  tr.leader_tilt.push_back(rad2deg(cL.X_fs.so3().toEulerXYZ()[0]));
  tr.follower_depth.push_back(follower ? follower->state.depth : 0.0);
  tr.object_path.push_back(objectPlanar(world.objectPose(0)));
  // Every period has its tilt (the log writes one row per period); the period that passes the
  // target ends the trial before the tilt is judged.
  tr.object_tilt.push_back(rad2deg(world.objectTilt(0)));
  const double r = (leader.pose().translation().head<2>() - setup.target).norm();
  tr.closest_approach = std::min(tr.closest_approach, r);
  if (tr.closest_approach < lieservo::paper::kAlignmentCutoff && r > tr.closest_approach + kPassedBy) {
    tr.passed_target = true;
    return true;
  }
  tr.max_tilt = std::max(tr.max_tilt, tr.object_tilt.back());
  if (tr.max_tilt > Bounds::topple_tilt) {
    tr.toppled = true;
    return true;
  }
  return false;
}

// The trial's outcome: the means over its periods and the final target error, the perpendicular
// distance from the target to the leader's contact normal (Tables 3-5).
void finishTrial(const PushingSetup& setup, World& world, const EngineArm& leader, const Counts& n, double t,
                 bool terminated, PushTrial& tr) {
  if (tr.states.times.back() < t) tr.states.add(t, world.positions());
  tr.terminated = terminated;
  tr.duration = t;
  tr.follower_contact_fraction = n.steps ? double(n.follower_steps_in_contact) / double(n.steps) : 1.0;
  if (n.leader_force_steps) tr.leader_vertical_force /= double(n.leader_force_steps);
  if (n.follower_steps_in_contact) tr.follower_vertical_force /= double(n.follower_steps_in_contact);
  const ContactState& cL = leader.state;
  const Vec2 p = cL.point_w.head<2>(), nrm = cL.normal_w.head<2>().normalized();
  const Vec2 T = setup.target;
  tr.target_error = std::abs(cross2(T - p, nrm));
  tr.final_distance = (leader.pose().translation().head<2>() - T).norm();
  if (tr.object_path.empty()) tr.object_path.push_back(objectPlanar(world.objectPose(0)));
}

}  // namespace

mujoco::SceneSpec pushingScene(const PushingSetup& setup, const ContactParams& contact, double h,
                               const PushPlacement& placement, double friction_scale) {
  mujoco::SceneSpec scene;
  scene.timestep = h;
  scene.support = setup.surface;
  scene.support.friction *= friction_scale;
  ObjectSpec obj = setup.object;
  obj.friction = contact.skin_friction;
  obj.contact_height = setup.sensor_height;
  obj.yaw = placement.yaw;
  const double R = contact.tip_radius;
  const double a = mujoco::halfExtentX(obj);
  obj.x = setup.start.x() + R - setup.initial_depth + a;
  obj.y = setup.start.y() + placement.offset;
  scene.objects = {obj};
  const double H = setup.sensor_height;
  // The paper's right-angle mount (Section 5.7.2, sec:dual_arm_tall_object_pushing): z_s along
  // the push (+x), x_s down, y_s = z_s × x_s = +y. The tall-object reference offsets then move
  // each sensor along ±x_s against its sticking contact: the leader's +0.5 mm presses the
  // pushed side down, the follower's −0.5 mm the stabilised side up.
  const Mat3 R_leader = fromColumns(-Vec3::UnitZ(), Vec3::UnitY(), Vec3::UnitX());
  scene.sensors = {taskSensor("leader", contact, makePose(R_leader, Vec3(setup.start.x(), setup.start.y(), H)))};
  if (setup.dual_arm) {
    // Opposite, along the line through the object's centre, normal to the far face; x_s down.
    const Mat3 Ro = rotZ(obj.yaw);
    const Vec3 dir = -Ro.col(0);  // sensor axis: into the far face
    scene.sensors.push_back(taskSensor(
        "follower", contact,
        makePose(fromColumns(-Vec3::UnitZ(), -dir.cross(Vec3::UnitZ()), dir),
                 Vec3(obj.x, obj.y, H) + Ro.col(0) * (a + R - setup.follower_depth))));
  }
  return scene;
}

PushTrial runPushTrial(const PushingSetup& setup, const TaskOptions& options, std::uint64_t trial_seed) {
  setup.validate();
  options.validate();
  PushTrial tr;
  const double dt = 1.0 / options.control_rate;
  const int substeps = stepsPerPeriod(dt);
  const double h = dt / substeps;
  lieservo::sampling::Rng rng(trial_seed * 6364136223846793005ULL + 1442695040888963407ULL);
  TaskOptions opt = options;
  const mujoco::SceneSpec scene = pushScene(setup, opt, rng, h, tr);
  World world(scene);

  const std::uint64_t s0 = trial_seed * 1000003ULL;
  EngineArm leader(world, 0, opt, s0 + 1);
  std::unique_ptr<EngineArm> follower;
  if (setup.dual_arm) follower = std::make_unique<EngineArm>(world, 1, opt, s0 + 2);
  PushControl control(setup, makePose(Mat3::Identity(), Vec3(setup.target.x(), setup.target.y(), setup.sensor_height)));

  leader.touch(world);
  if (follower) follower->touch(world);
  const long state_every = std::max(1L, std::lround(kStatePeriod / dt));
  tr.states.scene = scene;
  tr.states.add(0, world.positions());
  double t = 0;
  bool terminated = false;
  Counts n;
  while (t < setup.timeout && n.lost_for < kGiveUpAfter) {
    Vec6 uL = Vec6::Zero(), uF = Vec6::Zero();
    const Status s = control.step(leader, follower.get(), dt, uL, uF);
    terminated = control.terminated();
    if (s != Status::ok || terminated) break;
    Vec3 fL, fF;
    moveArms(world, leader, follower.get(), uL, uF, substeps, h, fL, fF);
    t += dt;
    ++n.steps;
    if (n.steps % state_every == 0) tr.states.add(t, world.positions());
    if (recordPeriod(setup, world, leader, follower.get(), control.pusher(), fL, fF, dt, n, tr)) break;
  }
  finishTrial(setup, world, leader, n, t, terminated, tr);
  return tr;
}

}  // namespace lieservo::sim

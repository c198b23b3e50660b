// Tasks (c) and (d): single- and dual-arm pushing (paper Section 5.6 (sec:single_arm_object_pushing_exp),
// Section 5.7 (sec:dual_arm_object_pushing_exp), Section 5.7.2 (sec:dual_arm_tall_object_pushing)) on MuJoCo.
//
// Work frame: the support is the x–y plane, z up. The leader's sensor starts at
// (x, y, z) = (−250, 100, 45) mm with its axis along +x (right-angle mount: x_s up,
// y_s = −y_w), the object is placed centrally in front of it with a face normal to the sensor
// axis at 1 mm depth (seeded jitter: sideways and yaw normal, sd 2 mm and 2°, clipped at
// 2 sd), and the target is (x, y) = (0, 375) mm. The dual-arm follower starts opposite, normal
// to the far face at 3 mm.
//
// Each control period (20 Hz): observation → filter → controller → twist; then, per MuJoCo
// step, each sensor arm moves by its twist (MujocoSensorArm), the engine steps (objects slide,
// turn and topple under the gel and support contacts), and each sensor's contact state
// (ContactModel: feature frame, depth, stick/slip shear) is updated from the engine's tip
// geometry.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <exception>
#include <functional>
#include <limits>
#include <memory>
#include <thread>

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
using detail::Gaussian;
using mujoco::World;

constexpr double kGiveUpAfter = 1.0;  // s out of contact: the push has failed, stop the trial
constexpr double kPassedBy = 20;      // mm beyond the closest approach, inside ρ*: the target was passed

Vec3 objectPlanar(const SE3d& X) {
  const Mat3 R = X.rotationMatrix();
  return Vec3(X.translation().x(), X.translation().y(), std::atan2(R(1, 0), R(0, 0)));
}

double cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

}  // namespace

PushTrial runPushTrial(const PushingSetup& setup, const TaskOptions& options, std::uint64_t trial_seed) {
  setup.validate();
  options.validate();
  PushTrial tr;
  const double dt = 1.0 / options.control_rate;
  const int substeps = stepsPerPeriod(dt);
  const double h = dt / substeps;
  const double R = options.contact.tip_radius;
  lieservo::sampling::Rng rng(trial_seed * 6364136223846793005ULL + 1442695040888963407ULL);
  auto draw = [&](const double (&range)[2]) { return lieservo::sampling::uniform(rng, range[0], range[1]); };

  // The physical parameters: the support's μ_s within ±10 %, or all three assumed parameters
  // drawn from their ranges (--randomise).
  TaskOptions opt = options;
  mujoco::SceneSpec scene;
  scene.timestep = h;
  scene.support = setup.surface;
  // Drawn even when TaskOptions fixes it, so that μ_c and k_gel draw as they would.
  const double friction_scale = opt.randomise ? draw(opt.ranges.support_friction_scale) : draw({0.9, 1.1});
  scene.support.friction *= std::isnan(opt.support_friction_scale) ? friction_scale : opt.support_friction_scale;
  if (opt.randomise) {
    opt.contact.skin_friction = draw(opt.ranges.skin_friction);
    opt.contact.gel_stiffness = draw(opt.ranges.gel_stiffness);
  }
  tr.support_friction = scene.support.friction;
  tr.skin_friction = opt.contact.skin_friction;
  tr.gel_stiffness = opt.contact.gel_stiffness;

  // The object in front of the leader, one or two sensors.
  ObjectSpec obj = setup.object;
  obj.friction = opt.contact.skin_friction;
  obj.contact_height = setup.sensor_height;
  // Placed by hand in front of the leader: the offset and yaw drawn (normal, sd 2 mm and 2°,
  // clipped at 2 sd; a round object is not turned), or fixed by TaskOptions.
  const double drawn_offset = 2.0 * std::clamp(lieservo::sampling::standardNormal(rng), -2.0, 2.0);
  const double drawn_yaw =
      obj.shape == "circle" ? 0.0 : deg(2.0) * std::clamp(lieservo::sampling::standardNormal(rng), -2.0, 2.0);
  tr.start_offset = std::isnan(opt.start_offset) ? drawn_offset : opt.start_offset;
  tr.start_yaw = obj.shape == "circle" ? 0.0 : std::isnan(opt.start_yaw) ? drawn_yaw : opt.start_yaw;
  obj.yaw = tr.start_yaw;
  const double a = mujoco::halfExtentX(obj);
  obj.x = setup.start.x() + R - setup.initial_depth + a;
  obj.y = setup.start.y() + tr.start_offset;
  scene.objects = {obj};
  const double H = setup.sensor_height;
  // The paper's right-angle mount (Section 5.7.2, sec:dual_arm_tall_object_pushing): z_s along
  // the push (+x), x_s down, y_s = z_s × x_s = +y. The tall-object reference offsets then move
  // each sensor along ±x_s against its sticking contact: the leader's +0.5 mm presses the
  // pushed side down, the follower's −0.5 mm the stabilised side up.
  const Mat3 R_leader = fromColumns(-Vec3::UnitZ(), Vec3::UnitY(), Vec3::UnitX());
  scene.sensors = {taskSensor("leader", opt.contact, makePose(R_leader, Vec3(setup.start.x(), setup.start.y(), H)))};
  if (setup.dual_arm) {
    // Opposite, along the line through the object's centre, normal to the far face; x_s down.
    const Mat3 Ro = rotZ(obj.yaw);
    const Vec3 dir = -Ro.col(0);  // sensor axis: into the far face
    scene.sensors.push_back(taskSensor(
        "follower", opt.contact,
        makePose(fromColumns(-Vec3::UnitZ(), -dir.cross(Vec3::UnitZ()), dir),
                 Vec3(obj.x, obj.y, H) + Ro.col(0) * (a + R - setup.follower_depth))));
  }
  World world(scene);

  const std::uint64_t s0 = trial_seed * 1000003ULL;
  EngineArm leader(world, 0, opt, s0 + 1);
  std::unique_ptr<EngineArm> follower;
  if (setup.dual_arm) follower = std::make_unique<EngineArm>(world, 1, opt, s0 + 2);
  const SE3d X_wt = makePose(Mat3::Identity(), Vec3(setup.target.x(), setup.target.y(), H));

  detail::PushLoop single;
  lieservo::DualArmPushing<double> dual;
  lieservo::CentralisedDualArmPushing<double> central;
  if (setup.dual_arm && setup.centralised) {
    auto o = lieservo::centralisedDualArmPushingPreset<double>(setup.tall);
    o.arms.leader.target = X_wt;
    central = lieservo::CentralisedDualArmPushing<double>(o, Filter(), Filter());
    if (central.configurationStatus() != Status::ok) throw SceneError("centralised dual-arm preset rejected");
  } else if (setup.dual_arm) {
    auto o = lieservo::dualArmPushingPreset<double>(setup.tall);
    o.leader.target = X_wt;
    dual = lieservo::DualArmPushing<double>(o, Filter(), Filter());
    if (dual.configurationStatus() != Status::ok) throw SceneError("dual-arm pushing preset rejected");
  } else {
    detail::PushLoop::Options o;
    o.controller = lieservo::pushingPreset<double>(lieservo::PushingConfiguration::single_arm);
    o.controller.target = X_wt;
    if (single.configure(o) != Status::ok) throw SceneError("pushing preset rejected");
  }
  const lieservo::PushingController<double>& pusher =
      setup.dual_arm ? (setup.centralised ? central.leader() : dual.leader()) : single.controller();

  leader.touch(world);
  if (follower) follower->touch(world);
  const long state_every = std::max(1L, std::lround(kStatePeriod / dt));
  tr.states.scene = scene;
  tr.states.add(0, world.positions());

  double t = 0;
  bool terminated = false;
  long steps = 0, follower_steps_in_contact = 0, leader_force_steps = 0;
  double lost_for = 0;  // s the leader has been out of contact
  while (t < setup.timeout && lost_for < kGiveUpAfter) {
    Vec6 uL = Vec6::Zero(), uF = Vec6::Zero();
    Status s;
    if (setup.dual_arm) {
      lieservo::DualArmPushing<double>::ArmInput inL, inF;
      inL.sensor_pose = leader.pose();
      inF.sensor_pose = follower->pose();
      s = leader.observe(inL.observation);
      if (s == Status::ok) s = follower->observe(inF.observation);
      lieservo::DualArmPushing<double>::ArmOutput oL, oF;
      if (s == Status::ok) s = setup.centralised ? central.step(inL, inF, dt, oL, oF) : dual.step(inL, inF, dt, oL, oF);
      uL = oL.velocity;
      uF = oF.velocity;
      terminated = setup.centralised ? central.terminated() : dual.terminated();
    } else {
      s = leader.step(single, dt, uL);
      terminated = single.terminated();
    }
    if (s != Status::ok || terminated) break;
    Vec3 force_L = Vec3::Zero(), force_F = Vec3::Zero();
    for (int j = 0; j < substeps; ++j) {
      Status moved = leader.arm.commandVelocity(uL, h);
      if (moved == Status::ok && follower) moved = follower->arm.commandVelocity(uF, h);
      if (moved == Status::ok) moved = world.step(h);
      if (moved != Status::ok) break;
      leader.touch(world);
      if (follower) follower->touch(world);
      force_L += world.tipContactForce(0) / substeps;
      if (follower) force_F += world.tipContactForce(1) / substeps;
    }
    t += dt;
    ++steps;
    if (steps % state_every == 0) tr.states.add(t, world.positions());
    const ContactState& cL = leader.state;
    if (!cL.in_contact) tr.contact_kept = false;
    lost_for = cL.in_contact ? 0.0 : lost_for + dt;
    tr.max_leader_depth = std::max(tr.max_leader_depth, cL.depth);
    if (cL.in_contact) tr.leader_vertical_force += force_L.z(), ++leader_force_steps;
    if (follower) {
      const ContactState& cF = follower->state;
      if (!cF.in_contact) tr.follower_contact_kept = false;
      else ++follower_steps_in_contact, tr.follower_vertical_force += force_F.z();
      tr.max_follower_depth = std::max(tr.max_follower_depth, cF.depth);
      tr.min_follower_depth = std::min(tr.min_follower_depth, cF.depth);
      tr.follower_path.push_back(follower->pose().translation());
      double angle = std::numeric_limits<double>::quiet_NaN();
      if (cL.in_contact && cF.in_contact)
        angle = toDeg(std::acos(std::clamp(cL.normal_w.dot(cF.normal_w), -1.0, 1.0)));
      tr.opposition.push_back(angle);
      if (!std::isnan(angle)) tr.min_opposition = std::min(tr.min_opposition, angle);
    }
    tr.sensor_path.push_back(leader.pose().translation());
    tr.bearing.push_back(toDeg(pusher.bearing()));
    tr.alignment_velocity.push_back(pusher.alignmentVelocity()[1]);
    tr.leader_depth.push_back(cL.depth);
    tr.leader_tilt.push_back(toDeg(eulerXYZ(cL.X_fs.rotationMatrix())[0]));
    tr.follower_depth.push_back(follower ? follower->state.depth : 0.0);
    tr.object_path.push_back(objectPlanar(world.objectPose(0)));
    const double r = (leader.pose().translation().head<2>() - setup.target).norm();
    tr.closest_approach = std::min(tr.closest_approach, r);
    if (tr.closest_approach < lieservo::paper::kAlignmentCutoff && r > tr.closest_approach + kPassedBy) {
      tr.passed_target = true;
      break;
    }
    tr.object_tilt.push_back(toDeg(world.objectTilt(0)));
    tr.max_tilt = std::max(tr.max_tilt, tr.object_tilt.back());
    if (tr.max_tilt > Bounds::topple_tilt) {
      tr.toppled = true;
      break;
    }
  }
  if (tr.states.times.back() < t) tr.states.add(t, world.positions());
  tr.terminated = terminated;
  tr.duration = t;
  tr.follower_contact_fraction = steps ? double(follower_steps_in_contact) / double(steps) : 1.0;
  if (leader_force_steps) tr.leader_vertical_force /= double(leader_force_steps);
  if (follower_steps_in_contact) tr.follower_vertical_force /= double(follower_steps_in_contact);
  const ContactState& cL = leader.state;
  const Vec2 p = cL.point_w.head<2>(), n = cL.normal_w.head<2>().normalized();
  const Vec2 T = setup.target;
  tr.target_error = std::abs(cross2(T - p, n));
  tr.final_distance = (leader.pose().translation().head<2>() - T).norm();
  if (tr.object_path.empty()) tr.object_path.push_back(objectPlanar(world.objectPose(0)));
  return tr;
}

namespace {

// fn(i) for i in [0, n) on all cores (each trial has its own world, filters and seed, so the
// results do not depend on how many); the first exception is rethrown.
void parallelFor(int n, const std::function<void(int)>& fn) {
  std::vector<std::exception_ptr> errors(static_cast<std::size_t>(n));
  std::atomic<int> next{0};
  auto worker = [&] {
    for (int i = next++; i < n; i = next++) {
      try {
        fn(i);
      } catch (...) {
        errors[std::size_t(i)] = std::current_exception();
      }
    }
  };
  const int threads = std::min(n, std::max(1, int(std::thread::hardware_concurrency())));
  std::vector<std::thread> pool;
  for (int k = 1; k < threads; ++k) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
}

std::uint64_t trialSeed(const TaskOptions& opt, int i) { return opt.seed * 1000 + std::uint64_t(i) + 1; }

PushingCase judgeCase(const PushingSetup& setup, std::vector<PushTrial> trials, bool judged, const TaskOptions& opt);

}  // namespace

PushingCase runPushingCase(const PushingSetup& setup, const TaskOptions& opt, int trials, bool judged) {
  if (trials < 1) throw SceneError("runPushingCase: trials must be >= 1");
  std::vector<PushTrial> runs(static_cast<std::size_t>(trials));
  parallelFor(trials, [&](int i) { runs[std::size_t(i)] = runPushTrial(setup, opt, trialSeed(opt, i)); });
  return judgeCase(setup, std::move(runs), judged, opt);
}

namespace {

PushingCase judgeCase(const PushingSetup& setup, std::vector<PushTrial> trials, bool judged, const TaskOptions& opt) {
  PushingCase pc;
  pc.setup = setup;
  pc.judged = judged;
  pc.trials = std::move(trials);
  // Statistics over the trials that reached the target.
  double m = 0;
  for (const auto& t : pc.trials) {
    if (t.terminated) m += t.target_error, ++pc.reached_trials;
    if (t.toppled) ++pc.toppled_trials;
    if (t.follower_contact_kept) ++pc.follower_kept_trials;
  }
  m = pc.reached_trials ? m / pc.reached_trials : std::numeric_limits<double>::quiet_NaN();
  double v = 0;
  for (const auto& t : pc.trials)
    if (t.terminated) v += (t.target_error - m) * (t.target_error - m);
  pc.mean_error = m;
  pc.sd_error = pc.reached_trials > 1 ? std::sqrt(v / (pc.reached_trials - 1)) : 0.0;
  for (const auto& t : pc.trials) pc.min_opposition = std::min(pc.min_opposition, t.min_opposition);
  // The criteria (docs/simulation.md, "Success criteria"); an unjudged case lists its misses
  // too, and they do not count (PushingResult::reported).
  const std::string tag = std::string(setup.dual_arm ? (setup.centralised ? "dual-arm (centralised) " : "dual-arm ")
                                                     : "single-arm ") +
                          displayName(setup.object) + " on " + setup.surface.name;
  char buf[240];
  for (std::size_t i = 0; i < pc.trials.size(); ++i) {
    const PushTrial& t = pc.trials[i];
    // Each miss names the trial's start placement: the single-arm miss follows it
    // (docs/simulation.md, "Margins").
    char start[80];
    std::snprintf(start, sizeof start, " (start: offset %+.1f mm, yaw %+.1f deg)", t.start_offset, toDeg(t.start_yaw));
    auto fail = [&](const std::string& why) {
      pc.failures.push_back(tag + " trial " + std::to_string(i + 1) + ": " + why + start);
    };
    if (t.toppled) {
      std::snprintf(buf, sizeof buf, "toppled (tilt %.0f deg > %.0f deg)", t.max_tilt, Bounds::topple_tilt);
      fail(buf);
    } else if (t.passed_target) {
      std::snprintf(buf, sizeof buf, "passed the target at %.0f mm without reaching it (termination within %.0f mm)",
                    t.closest_approach, opt.contact.tip_radius);
      fail(buf);
    } else if (!t.terminated) {
      std::snprintf(buf, sizeof buf, "target not reached in %.0f s (final distance %.0f mm)", setup.timeout,
                    t.final_distance);
      fail(buf);
    } else if (t.target_error > Bounds::pushing_error_max) {
      std::snprintf(buf, sizeof buf, "target error %.1f mm > %.0f mm", t.target_error, Bounds::pushing_error_max);
      fail(buf);
    }
    if (!t.contact_kept) fail("pusher lost contact");
    if (setup.dual_arm && !t.follower_contact_kept) {
      std::snprintf(buf, sizeof buf, "follower out of contact for %.0f%% of the push",
                    100.0 * (1.0 - t.follower_contact_fraction));
      fail(buf);
    }
    if (setup.dual_arm && t.max_tilt > Bounds::upright_tilt_max) {
      std::snprintf(buf, sizeof buf, "object tilted %.1f deg > %.0f deg", t.max_tilt, Bounds::upright_tilt_max);
      fail(buf);
    }
    if (setup.dual_arm && t.min_opposition < Bounds::opposition_min) {
      std::snprintf(buf, sizeof buf, "opposition lost: the contact normals %.0f deg apart (< %.0f deg)",
                    t.min_opposition, Bounds::opposition_min);
      fail(buf);
    }
  }
  pc.success = pc.failures.empty();
  return pc;
}

}  // namespace

namespace {

void writeCase(const PushingCase& pc, const std::string& dir, const std::string& stem) {
  CsvWriter csv;
  if (!csv.open(detail::join(dir, stem + ".csv"),
                {"trial", "step", "sensor_x", "sensor_y", "follower_x", "follower_y", "object_x", "object_y",
                 "object_theta_deg", "object_tilt_deg", "bearing_deg", "align_uy", "leader_depth", "leader_alpha_deg",
                 "follower_depth", "opposition_deg"}))
    return;
  for (std::size_t i = 0; i < pc.trials.size(); ++i) {
    const PushTrial& t = pc.trials[i];
    for (std::size_t k = 0; k < t.sensor_path.size(); ++k) {
      const Vec3& s = t.sensor_path[k];
      const Vec3 f = k < t.follower_path.size() ? t.follower_path[k] : Vec3(NAN, NAN, NAN);
      const Vec3& o = t.object_path[k];
      const double opposition = k < t.opposition.size() ? t.opposition[k] : NAN;
      csv.row({double(i + 1), double(k), s.x(), s.y(), f.x(), f.y(), o.x(), o.y(), toDeg(o.z()), t.object_tilt[k],
               t.bearing[k], t.alignment_velocity[k], t.leader_depth[k], t.leader_tilt[k], t.follower_depth[k],
               opposition});
    }
  }
}

}  // namespace

void writePushingPlot(const std::vector<const PushingCase*>& cases, const std::string& path, const std::string& title) {
  SvgFigure fig(title);
  for (const PushingCase* pc : cases) {
    const PushTrial& t = pc->trials.front();
    SvgPanel& P = fig.panel(displayName(pc->setup.object), "x (mm)", "y (mm)");
    const std::vector<Vec2> outline = mujoco::footprint(pc->setup.object);
    auto drawObject = [&](const Vec3& xyth, const std::string& colour, bool dashed) {
      const Eigen::Rotation2Dd Rz(xyth.z());
      std::vector<Vec2> pts;
      for (const Vec2& q : outline) pts.push_back(Rz * q + xyth.head<2>());
      pts.push_back(pts.front());
      P.line(pts, colour, 1.5, dashed);
    };
    // The first logged pose is one control period after the start (< 1 mm of motion).
    drawObject(t.object_path.front(), "#888", true);
    drawObject(t.object_path.back(), "#2060c0", false);
    std::vector<Vec2> sp, fp;
    for (const auto& s : t.sensor_path) sp.emplace_back(s.x(), s.y());
    for (const auto& s : t.follower_path) fp.emplace_back(s.x(), s.y());
    P.line(sp, "#d62728", 1.5, false, "leader sensor");
    if (!fp.empty()) P.line(fp, "#2ca02c", 1.5, false, "follower sensor");
    P.marker(pc->setup.target, 20, "#d62728", false);
    P.marker(pc->setup.target, 3, "#d62728", true);
  }
  fig.write(path, 360);
}

namespace {

struct Group {
  SupportSpec surface;
  std::vector<ObjectSpec> objects;
  bool tall;
  std::string stem;
};

// `judged(object)`: whether the object's case decides the result (else it is reported).
PushingResult runGroups(const std::vector<Group>& groups, bool dual, bool centralised,
                        const std::function<bool(const ObjectSpec&)>& judged, const TaskOptions& opt, int trials) {
  if (trials < 1) throw SceneError("pushing: trials must be >= 1");
  // Every trial of every case in one pool, so no core waits for the last trial of a case.
  std::vector<PushingSetup> setups;
  std::vector<std::size_t> group_of;
  for (std::size_t g = 0; g < groups.size(); ++g)
    for (const ObjectSpec& o : groups[g].objects) {
      PushingSetup su;
      su.object = o;
      su.surface = groups[g].surface;
      su.dual_arm = dual;
      su.centralised = centralised;
      su.tall = groups[g].tall;
      setups.push_back(su);
      group_of.push_back(g);
    }
  std::vector<std::vector<PushTrial>> runs(setups.size(), std::vector<PushTrial>(std::size_t(trials)));
  parallelFor(int(setups.size()) * trials, [&](int j) {
    const std::size_t c = std::size_t(j / trials), i = std::size_t(j % trials);
    runs[c][i] = runPushTrial(setups[c], opt, trialSeed(opt, int(i)));
  });
  PushingResult res;
  for (std::size_t c = 0; c < setups.size(); ++c) {
    res.cases.push_back(judgeCase(setups[c], std::move(runs[c]), judged(setups[c].object), opt));
    if (!opt.out_dir.empty()) res.cases.back().figure_stem = groups[group_of[c]].stem;
  }
  if (!opt.out_dir.empty()) {
    makeDirectories(opt.out_dir);
    for (std::size_t g = 0; g < groups.size(); ++g) {
      std::vector<const PushingCase*> fig;
      for (std::size_t c = 0; c < setups.size(); ++c) {
        if (group_of[c] != g) continue;
        fig.push_back(&res.cases[c]);
        writeCase(res.cases[c], opt.out_dir, groups[g].stem + "_" + res.cases[c].setup.object.name);
      }
      writePushingPlot(fig, detail::join(opt.out_dir, groups[g].stem + ".svg"),
                       std::string(dual ? (centralised ? "Dual-arm (centralised follower)" : "Dual-arm") : "Single-arm") +
                           " pushing on " + groups[g].surface.name +
                           " (trial 1; target: red circle; object at start dashed, at end solid" +
                           (dual ? "; leader red, follower green)" : ")"));
    }
  }
  for (const auto& c : res.cases) {
    auto& into = c.judged ? res.failures : res.reported;
    into.insert(into.end(), c.failures.begin(), c.failures.end());
    for (const auto& t : c.trials) res.sim_time += t.duration;
  }
  res.success = res.failures.empty();
  return res;
}

bool always(const ObjectSpec&) { return true; }

}  // namespace

bool isRound(const ObjectSpec& object) { return object.shape == "circle"; }

std::vector<ObjectSpec> tallAndEverydayObjects() {
  std::vector<ObjectSpec> v = tallObjects();
  for (const ObjectSpec& o : everydayObjects()) v.push_back(o);
  return v;
}

void writeOppositionPlot(const PushingResult& paper, const PushingResult& centralised, const std::string& path) {
  SvgFigure fig("Dual-arm pushing of the round objects: the angle between the two contact normals (trial 1; "
                "paper's follower red, centralised follower blue; 150 deg: the criterion)");
  for (const PushingCase& pc : paper.cases) {
    if (!isRound(pc.setup.object)) continue;
    const PushingCase* cc = nullptr;
    for (const PushingCase& c : centralised.cases)
      if (c.setup.object.name == pc.setup.object.name && c.setup.surface.name == pc.setup.surface.name) cc = &c;
    SvgPanel& P = fig.panel(displayName(pc.setup.object) + ", " + pc.setup.surface.name, "t (s)", "opposition (deg)");
    auto trace = [](const PushTrial& t, double dt) {
      std::vector<Vec2> v;
      for (std::size_t k = 0; k < t.opposition.size(); ++k)
        if (!std::isnan(t.opposition[k])) v.emplace_back(double(k) * dt, t.opposition[k]);
      return v;
    };
    const PushTrial& first = pc.trials.front();
    const double dt = first.opposition.empty() ? 0.05 : first.duration / double(first.opposition.size());
    const auto a = trace(first, dt);
    if (a.size() > 1) P.line(a, "#d62728", 1.5, false, "paper's follower");
    if (cc) {
      const PushTrial& c1 = cc->trials.front();
      const auto b = trace(c1, c1.opposition.empty() ? 0.05 : c1.duration / double(c1.opposition.size()));
      if (b.size() > 1) P.line(b, "#1f77b4", 1.5, false, "centralised");
    }
    const double t_end = std::max(a.empty() ? 1.0 : a.back().x(), 1.0);
    P.line({Vec2(0, Bounds::opposition_min), Vec2(t_end, Bounds::opposition_min)}, "#888", 1.0, true);
    P.line({Vec2(0, 0), Vec2(0, 180)}, "none", 0.1);  // the axis spans 0-180 deg
  }
  fig.write(path, 360);
}

std::vector<ToppleRow> toppleTable(const std::vector<ObjectSpec>& objects) {
  std::vector<ToppleRow> rows(objects.size());
  std::atomic<std::size_t> next{0};
  std::vector<std::exception_ptr> errors(objects.size());
  auto worker = [&] {
    for (std::size_t i = next++; i < objects.size(); i = next++) {
      try {
        rows[i] = toppleAnalysis(objects[i]);
      } catch (...) {
        errors[i] = std::current_exception();
      }
    }
  };
  std::vector<std::thread> pool;
  for (unsigned k = 1; k < std::max(1u, std::thread::hardware_concurrency()); ++k) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
  return rows;
}

PushingResult runSingleArmPushing(const TaskOptions& opt, int trials) {
  return runGroups({{SupportSpec::foam(), shortObjects(), false, "pushing_single_foam"},
                    {SupportSpec::mdf(), shortObjects(), false, "pushing_single_MDF"}},
                   false, false, always, opt, trials);
}

PushingResult runDualArmPushing(const TaskOptions& opt, int trials, bool centralised) {
  const std::string suffix = centralised ? "_centralised" : "";
  const std::vector<Group> groups = {
      {SupportSpec::foam(), shortObjects(), false, "pushing_dual_short_foam" + suffix},
      {SupportSpec::mdf(), shortObjects(), false, "pushing_dual_short_MDF" + suffix},
      {SupportSpec::mdf(), tallAndEverydayObjects(), true, "pushing_dual_tall_MDF" + suffix}};
  // The paper's decentralised follower on round objects is reported, as the criteria declare
  // (docs/simulation.md, "The paper's follower on round objects"): run, not judged.
  return runGroups(groups, true, centralised,
                   centralised ? std::function<bool(const ObjectSpec&)>(always)
                               : [](const ObjectSpec& o) { return !isRound(o); },
                   opt, trials);
}

PushingResult runTallSingleArmPushing(const TaskOptions& opt, int trials) {
  return runGroups({{SupportSpec::foam(), tallAndEverydayObjects(), false, "pushing_single_tall_foam"}}, false, false,
                   [](const ObjectSpec&) { return false; }, opt, trials);
}

// ---- toppling ---------------------------------------------------------------------------------

bool tipsBeforeSliding(const ObjectSpec& object, double support_friction, double push_height) {
  mujoco::SceneSpec scene;
  scene.support = SupportSpec::rigid(support_friction);
  ObjectSpec o = object;
  o.x = o.y = o.yaw = 0;
  scene.objects = {o};
  World w(scene);
  const double m = o.mass, g = 9.81, a = mujoco::halfExtentX(o);
  const double F_max = 2 * support_friction * m * g + m * g * a / push_height;  // past both thresholds
  const double ramp = 4.0, dt = 0.01;  // s: slow, so the object is quasi-static when it gives
  // Statics asks which threshold the rising force meets first, so the first motion decides:
  // the base centre sliding 1 mm, or the object turning 3° about its leading edge (which moves
  // the base centre up, not along). Past that the ramped force would keep rising over a sliding
  // object's friction and tip it in motion, a dynamic threshold statics does not describe.
  const double slide = 1.0, tilt = deg(3);
  for (double t = 0; t < ramp; t += dt) {
    const SE3d X = w.objectPose(0);
    const Vec3 face = X * Vec3(-a, 0, push_height);
    w.applyObjectForce(0, X.rotationMatrix() * Vec3(F_max * t / ramp, 0, 0), face);
    if (w.step(dt) != Status::ok) return false;
    if (w.objectTilt(0) > tilt) return true;
    if (w.objectPose(0).translation().head<2>().norm() > slide) return false;
  }
  return w.objectTilt(0) > tilt;
}

ToppleRow toppleAnalysis(const ObjectSpec& object, double support_friction, double push_height, double tolerance) {
  ToppleRow row;
  row.object = object;
  row.support_friction = support_friction;
  row.push_height = push_height;
  const double a = mujoco::halfExtentX(object);  // w / 2 along the push
  row.statics_height = a / support_friction;
  row.statics_friction = a / push_height;
  // Bisection: below the critical height (or friction) the object slides, above it tips.
  auto bisect = [&](double lo, double hi, const std::function<bool(double)>& tips) {
    while (hi - lo > tolerance * lo) {
      const double mid = 0.5 * (lo + hi);
      (tips(mid) ? hi : lo) = mid;
    }
    return 0.5 * (lo + hi);
  };
  // Pushed at its top, does it tip at all? If not, neither critical height is on the object.
  const double top = 0.98 * object.height;
  if (row.statics_height >= top && !tipsBeforeSliding(object, support_friction, top)) {
    row.engine_height = row.statics_height = std::numeric_limits<double>::infinity();
  } else {
    row.engine_height = bisect(0.5 * std::min(row.statics_height, top), std::min(top, 2 * row.statics_height),
                               [&](double h) { return tipsBeforeSliding(object, support_friction, h); });
  }
  row.engine_friction = bisect(0.5 * row.statics_friction, 2 * row.statics_friction,
                               [&](double mu) { return tipsBeforeSliding(object, mu, push_height); });
  return row;
}

}  // namespace lieservo::sim

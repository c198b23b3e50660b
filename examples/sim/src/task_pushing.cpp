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
#include <limits>
#include <memory>
#include <thread>

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

PushTrial runPushTrial(const PushingSetup& setup, const TaskOptions& opt, std::uint64_t trial_seed) {
  setup.validate();
  opt.validate();
  PushTrial tr;
  const double dt = 1.0 / opt.control_rate;
  const int substeps = detail::stepsPerPeriod(dt);
  const double h = dt / substeps;
  const double R = opt.contact.tip_radius;
  lieservo::sampling::Rng rng(trial_seed * 6364136223846793005ULL + 1442695040888963407ULL);

  // The scene: support (friction ±10 %), the object in front of the leader, one or two sensors.
  mujoco::SceneSpec scene;
  scene.timestep = h;
  scene.support = setup.surface;
  scene.support.friction *= lieservo::sampling::uniform(rng, 0.9, 1.1);
  ObjectSpec obj = setup.object;
  obj.friction = opt.contact.skin_friction;
  obj.contact_height = setup.sensor_height;
  const double jitter_y = 2.0 * std::clamp(lieservo::sampling::standardNormal(rng), -2.0, 2.0);
  obj.yaw = obj.shape == "circle" ? 0.0 : deg(2.0) * std::clamp(lieservo::sampling::standardNormal(rng), -2.0, 2.0);
  const double a = mujoco::halfExtentX(obj);
  obj.x = setup.start.x() + R - setup.initial_depth + a;
  obj.y = setup.start.y() + jitter_y;
  scene.objects = {obj};
  const double H = setup.sensor_height;
  // Right-angle mount: z_s along the push (+x), x_s up, y_s = z_s × x_s = −y.
  const Mat3 R_leader = fromColumns(Vec3::UnitZ(), -Vec3::UnitY(), Vec3::UnitX());
  mujoco::SensorSpec leader_spec;
  leader_spec.name = "leader";
  leader_spec.tip_radius = R;
  leader_spec.gel_stiffness = setup.gel_stiffness;
  leader_spec.initial_pose = makePose(R_leader, Vec3(setup.start.x(), setup.start.y(), H));
  scene.sensors = {leader_spec};
  if (setup.dual_arm) {
    // Opposite, along the line through the object's centre, normal to the far face.
    const Mat3 Ro = rotZ(obj.yaw);
    const Vec3 dir = -Ro.col(0);  // sensor axis: into the far face
    mujoco::SensorSpec f = leader_spec;
    f.name = "follower";
    f.initial_pose = makePose(fromColumns(Vec3::UnitZ(), dir.cross(Vec3::UnitZ()), dir),
                              Vec3(obj.x, obj.y, H) + Ro.col(0) * (a + R - setup.follower_depth));
    scene.sensors.push_back(f);
  }
  World world(scene);

  const std::uint64_t s0 = trial_seed * 1000003ULL;
  EngineArm leader(world, 0, opt, s0 + 1);
  std::unique_ptr<EngineArm> follower;
  if (setup.dual_arm) follower = std::make_unique<EngineArm>(world, 1, opt, s0 + 2);
  const SE3d X_wt = makePose(Mat3::Identity(), Vec3(setup.target.x(), setup.target.y(), H));

  lieservo::PushingController<double> single;
  lieservo::DualArmPushing<double> dual;
  if (setup.dual_arm) {
    auto o = lieservo::dualArmPushingPreset<double>(setup.tall);
    o.leader.target = X_wt;
    if (setup.follower_y_gain > 0) {  // the named variant: a tangential channel, z's Ki/Kp and Kd/Kp
      auto& pid = o.follower.pid;
      pid.kp(1, 1) = setup.follower_y_gain;
      pid.ki(1, 1) = pid.ki(2, 2) * setup.follower_y_gain / pid.kp(2, 2);
      pid.kd(1, 1) = pid.kd(2, 2) * setup.follower_y_gain / pid.kp(2, 2);
    }
    dual = lieservo::DualArmPushing<double>(o, Filter(), Filter());
    if (dual.configurationStatus() != Status::ok) throw SceneError("dual-arm pushing preset rejected");
  } else {
    auto o = lieservo::pushingPreset<double>(lieservo::PushingConfiguration::single_arm);
    o.target = X_wt;
    single = lieservo::PushingController<double>(o);
    if (single.configurationStatus() != Status::ok) throw SceneError("pushing preset rejected");
  }

  leader.touch(world);
  if (follower) follower->touch(world);

  double t = 0;
  bool terminated = false;
  long steps = 0, follower_steps_in_contact = 0;
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
      if (s == Status::ok) s = dual.step(inL, inF, dt, oL, oF);
      uL = oL.velocity;
      uF = oF.velocity;
      terminated = dual.terminated();
    } else {
      SE3d X_sf;
      s = leader.sense(X_sf);
      if (s == Status::ok) s = single.step(leader.pose(), X_sf, dt, uL);
      terminated = single.terminated();
    }
    if (s != Status::ok || terminated) break;
    for (int j = 0; j < substeps; ++j) {
      leader.arm.commandVelocity(uL, h);
      if (follower) follower->arm.commandVelocity(uF, h);
      if (world.step(h) != Status::ok) break;
      leader.touch(world);
      if (follower) follower->touch(world);
    }
    t += dt;
    ++steps;
    const ContactState& cL = leader.state;
    if (!cL.in_contact) tr.contact_kept = false;
    lost_for = cL.in_contact ? 0.0 : lost_for + dt;
    tr.max_leader_depth = std::max(tr.max_leader_depth, cL.depth);
    if (follower) {
      const ContactState& cF = follower->state;
      if (!cF.in_contact) tr.follower_contact_kept = false;
      else ++follower_steps_in_contact;
      tr.max_follower_depth = std::max(tr.max_follower_depth, cF.depth);
      tr.min_follower_depth = std::min(tr.min_follower_depth, cF.depth);
      tr.follower_path.push_back(follower->pose().translation());
    }
    tr.sensor_path.push_back(leader.pose().translation());
    {
      const auto& pcn = setup.dual_arm ? dual.leader() : single;
      tr.bearing.push_back(toDeg(pcn.bearing()));
      tr.alignment_velocity.push_back(pcn.alignmentVelocity()[1]);
      tr.leader_depth.push_back(cL.depth);
      tr.leader_tilt.push_back(toDeg(eulerXYZ(cL.X_fs.rotationMatrix())[0]));
      tr.follower_depth.push_back(follower ? follower->state.depth : 0.0);
    }
    tr.object_path.push_back(objectPlanar(world.objectPose(0)));
    const double r = (leader.pose().translation().head<2>() - setup.target).norm();
    tr.closest_approach = std::min(tr.closest_approach, r);
    if (tr.closest_approach < lieservo::paper::kAlignmentCutoff && r > tr.closest_approach + kPassedBy) {
      tr.passed_target = true;
      break;
    }
    tr.max_tilt = std::max(tr.max_tilt, toDeg(world.objectTilt(0)));
    if (tr.max_tilt > Bounds::topple_tilt) {
      tr.toppled = true;
      break;
    }
  }
  tr.terminated = terminated;
  tr.duration = t;
  tr.follower_contact_fraction = steps ? double(follower_steps_in_contact) / double(steps) : 1.0;
  const ContactState& cL = leader.state;
  const Vec2 p = cL.point_w.head<2>(), n = cL.normal_w.head<2>().normalized();
  const Vec2 T = setup.target;
  tr.target_error = std::abs(cross2(T - p, n));
  tr.final_distance = (leader.pose().translation().head<2>() - T).norm();
  if (tr.object_path.empty()) tr.object_path.push_back(objectPlanar(world.objectPose(0)));
  return tr;
}

PushingCase runPushingCase(const PushingSetup& setup, const TaskOptions& opt, int trials, bool judged) {
  if (trials < 1) throw SceneError("runPushingCase: trials must be >= 1");
  PushingCase pc;
  pc.setup = setup;
  pc.judged = judged;
  // The trials are independent (each its own world, filters and seed), so they run on all
  // cores at once; the results do not depend on how many.
  pc.trials.resize(std::size_t(trials));
  std::vector<std::exception_ptr> errors(static_cast<std::size_t>(trials));
  std::atomic<int> next{0};
  auto worker = [&] {
    for (int i = next++; i < trials; i = next++) {
      try {
        pc.trials[std::size_t(i)] = runPushTrial(setup, opt, opt.seed * 1000 + std::uint64_t(i) + 1);
      } catch (...) {
        errors[std::size_t(i)] = std::current_exception();
      }
    }
  };
  const int threads = std::min(trials, std::max(1, int(std::thread::hardware_concurrency())));
  std::vector<std::thread> pool;
  for (int k = 1; k < threads; ++k) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
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
  if (!judged) {
    pc.success = true;
    return pc;
  }
  const std::string tag = std::string(setup.dual_arm ? "dual-arm " : "single-arm ") + displayName(setup.object) +
                          " on " + setup.surface.name;
  char buf[240];
  for (std::size_t i = 0; i < pc.trials.size(); ++i) {
    const PushTrial& t = pc.trials[i];
    auto fail = [&](const std::string& why) { pc.failures.push_back(tag + " trial " + std::to_string(i + 1) + ": " + why); };
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
  }
  pc.success = pc.failures.empty();
  return pc;
}

namespace {

void writeCase(const PushingCase& pc, const std::string& dir, const std::string& stem) {
  CsvWriter csv;
  if (!csv.open(detail::join(dir, stem + ".csv"),
                {"trial", "step", "sensor_x", "sensor_y", "follower_x", "follower_y", "object_x", "object_y",
                 "object_theta_deg", "bearing_deg", "align_uy", "leader_depth", "leader_alpha_deg", "follower_depth"}))
    return;
  for (std::size_t i = 0; i < pc.trials.size(); ++i) {
    const PushTrial& t = pc.trials[i];
    for (std::size_t k = 0; k < t.sensor_path.size(); ++k) {
      const Vec3& s = t.sensor_path[k];
      const Vec3 f = k < t.follower_path.size() ? t.follower_path[k] : Vec3(NAN, NAN, NAN);
      const Vec3& o = t.object_path[k];
      csv.row({double(i + 1), double(k), s.x(), s.y(), f.x(), f.y(), o.x(), o.y(), toDeg(o.z()), t.bearing[k],
               t.alignment_velocity[k], t.leader_depth[k], t.leader_tilt[k], t.follower_depth[k]});
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

PushingResult runGroups(const std::vector<Group>& groups, bool dual, bool judged, const TaskOptions& opt,
                        int trials, double follower_y_gain = 0) {
  PushingResult res;
  for (const Group& g : groups) {
    const std::size_t first = res.cases.size();
    for (const ObjectSpec& o : g.objects) {
      PushingSetup su;
      su.object = o;
      su.surface = g.surface;
      su.dual_arm = dual;
      su.tall = g.tall;
      su.follower_y_gain = follower_y_gain;
      res.cases.push_back(runPushingCase(su, opt, trials, judged));
    }
    if (!opt.out_dir.empty()) {
      makeDirectories(opt.out_dir);
      std::vector<const PushingCase*> fig;
      for (std::size_t i = first; i < res.cases.size(); ++i) {
        fig.push_back(&res.cases[i]);
        writeCase(res.cases[i], opt.out_dir, g.stem + "_" + res.cases[i].setup.object.name);
      }
      writePushingPlot(fig, detail::join(opt.out_dir, g.stem + ".svg"),
                std::string(dual ? "Dual-arm" : "Single-arm") + " pushing on " + g.surface.name +
                    " (trial 1; target: red circle; object at start dashed, at end solid" +
                    (dual ? "; leader red, follower green)" : ")"));
    }
  }
  for (const auto& c : res.cases) {
    res.failures.insert(res.failures.end(), c.failures.begin(), c.failures.end());
    for (const auto& t : c.trials) res.sim_time += t.duration;
  }
  res.success = res.failures.empty();
  return res;
}

std::vector<ObjectSpec> tallAndEveryday() {
  std::vector<ObjectSpec> v = tallObjects();
  for (const ObjectSpec& o : everydayObjects()) v.push_back(o);
  return v;
}

}  // namespace

PushingResult runSingleArmPushing(const TaskOptions& opt, int trials) {
  return runGroups({{SupportSpec::foam(), shortObjects(), false, "pushing_single_foam"},
                    {SupportSpec::mdf(), shortObjects(), false, "pushing_single_MDF"}},
                   false, true, opt, trials);
}

PushingResult runDualArmPushing(const TaskOptions& opt, int trials, double follower_y_gain, bool round_only) {
  std::vector<Group> groups = {{SupportSpec::foam(), shortObjects(), false, "pushing_dual_short_foam"},
                               {SupportSpec::mdf(), shortObjects(), false, "pushing_dual_short_MDF"},
                               {SupportSpec::mdf(), tallAndEveryday(), true, "pushing_dual_tall_MDF"}};
  const std::string suffix = follower_y_gain > 0 ? "_follower_y" : "";
  for (Group& g : groups) {
    if (round_only)
      g.objects.erase(std::remove_if(g.objects.begin(), g.objects.end(),
                                     [](const ObjectSpec& o) { return o.shape != "circle"; }),
                      g.objects.end());
    g.stem += suffix;
  }
  return runGroups(groups, true, true, opt, trials, follower_y_gain);
}

PushingResult runTallSingleArmPushing(const TaskOptions& opt, int trials) {
  return runGroups({{SupportSpec::mdf(), tallAndEveryday(), false, "pushing_single_tall_MDF"}}, false, false, opt,
                   trials);
}

}  // namespace lieservo::sim

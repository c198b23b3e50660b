// Task (b): surface following (paper Section 5.5 (sec:surface_follow_exp)), on MuJoCo, Table 7 controller
// (reference (0, 0, 3, 0, 0, 0): normal contact at 3 mm depth) with feedforward
// u_s'2 = (10 cos θ, 10 sin θ, 0, 0, 0, 0) mm/s in the reference sensor frame, mapped into the
// sensor frame with Ad(X_ss') inside TactileServoController (Section 3.3.2, sec:servoing_controller).
//
//  * curved ramp (a fixed "ramp" fixture, H = 40 mm, L = 200 mm: a convex-then-concave cosine
//    profile, slope up to 17.4°): start on the top at 3 mm depth with the sensor y-axis along the
//    ramp (work +y), heading θ = 90° (u = (0, 10, 0, …)), until the contact passes y = L + 30.
//  * hemispherical dome (a fixed "dome" fixture, radius 80 mm): start on the top at 3 mm
//    depth, 8 radial paths θ_i = 0, 45°, …, 315°, each until the contact is 50° from the pole
//    (70 mm of arc); between paths the world returns to its start (World::reset) and the
//    filter, controller and contact anchor are reset.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include <lieservo/control/presets.hpp>

#include "task_common.hpp"

namespace lieservo::sim {

namespace {

struct PathLog {
  std::vector<Vec3> pos;
  std::vector<std::pair<Vec3, Vec3>> axes;
  std::vector<Vec2> depth, tilt;
};

// The paper's filter and Table 7's servo with the feedforward along `heading` (rad).
detail::ServoLoop::Options followingLoop(double heading, double speed) {
  detail::ServoLoop::Options o;
  o.controller = lieservo::surfaceFollowingPreset<double>();
  o.controller.feedforward = lieservo::surfaceFollowingFeedforward<double>(heading, speed);
  return o;
}

// Runs one following path; `done` decides the end from the contact state.
template <class Done>
void followPath(mujoco::World& world, detail::EngineArm& sa, detail::ServoLoop& loop,
                const TaskOptions& opt, double ref_depth, double timeout, Done done, FollowingPath& out, PathLog& log,
                CsvWriter& csv, int path_id, double& t_global, std::vector<std::string>& failures) {
  const double dt = 1.0 / opt.control_rate;
  const int substeps = stepsPerPeriod(dt);
  const double h = dt / substeps;
  sa.touch(world);
  const Vec3 p_start = sa.state.point_w;
  double t = 0;
  long k = 0;
  const long state_every = std::max(1L, std::lround(kStatePeriod / dt));
  out.states.scene = world.spec();
  out.states.add(0, world.positions());
  Vec3 p_prev = p_start;
  while (t < timeout) {
    Vec6 u = Vec6::Zero();
    Status s = sa.step(loop, dt, u);  // observe, filter, control
    if (s != Status::ok) {
      failures.push_back("following " + out.name + ": loop status " + lieservo::describe(s));
      return;
    }
    for (int j = 0; j < substeps && s == Status::ok; ++j) {
      s = sa.arm.commandVelocity(u, h);
      if (s == Status::ok) s = world.step(h);
      sa.touch(world);
    }
    if (s != Status::ok) {
      failures.push_back("following " + out.name + ": world status " + lieservo::describe(s));
      return;
    }
    t += dt;
    ++k;
    if (k % state_every == 0) out.states.add(t, world.positions());
    const ContactState& c = sa.state;
    out.depth_error.add(c.depth - ref_depth);
    out.tilt.add(rad2deg(c.tilt));
    if (!c.in_contact) out.contact_kept = false;
    out.distance += (c.point_w - p_prev).norm();
    p_prev = c.point_w;
    const SE3d X = sa.pose();
    log.pos.push_back(X.translation());
    if (k % int(opt.control_rate) == 0) log.axes.push_back({X.translation(), Vec3(X.rotationMatrix().col(2))});
    log.depth.emplace_back(t_global + t, c.depth - ref_depth);
    log.tilt.emplace_back(t_global + t, rad2deg(c.tilt));
    if (csv.isOpen()) {
      const Vec6 e = X.toEulerXYZ6();
      csv.row({t_global + t, double(path_id), e[0], e[1], e[2], rad2deg(e[3]), rad2deg(e[4]), rad2deg(e[5]), c.depth,
               rad2deg(c.tilt), c.point_w.x(), c.point_w.y(), c.point_w.z(), c.shear.x(), c.shear.y()});
    }
    if (done(c)) {
      out.reached_end = true;
      break;
    }
    if (!c.in_contact && c.depth < -5) break;  // hopelessly off the surface
  }
  if (out.states.times.back() < t) out.states.add(t, world.positions());
  t_global += t;
  out.depth_error.finish();
  out.tilt.finish();
}

void check(const FollowingPath& p, std::vector<std::string>& failures) {
  char buf[220];
  if (!p.contact_kept) failures.push_back("following " + p.name + ": contact lost");
  if (!p.reached_end) failures.push_back("following " + p.name + ": did not reach the end of the path");
  if (p.depth_error.mean > Bounds::following_depth_mean || p.depth_error.max > Bounds::following_depth_max) {
    std::snprintf(buf, sizeof buf, "following %s: depth error mean %.2f / max %.2f mm over bounds %.1f / %.1f",
                  p.name.c_str(), p.depth_error.mean, p.depth_error.max, Bounds::following_depth_mean,
                  Bounds::following_depth_max);
    failures.push_back(buf);
  }
  if (p.tilt.mean > Bounds::following_tilt_mean || p.tilt.max > Bounds::following_tilt_max) {
    std::snprintf(buf, sizeof buf, "following %s: tilt mean %.2f / max %.2f deg over bounds %.1f / %.1f",
                  p.name.c_str(), p.tilt.mean, p.tilt.max, Bounds::following_tilt_mean, Bounds::following_tilt_max);
    failures.push_back(buf);
  }
}

std::vector<Vec2> proj(const std::vector<Vec3>& v, int a, int b) {
  std::vector<Vec2> o;
  for (const auto& p : v) o.emplace_back(p[a], p[b]);
  return o;
}

// A scene of one fixture and one sensor starting at X_ws0.
mujoco::SceneSpec followingScene(const mujoco::FixtureSpec& fixture, const SE3d& X_ws0, const TaskOptions& opt) {
  mujoco::SceneSpec scene;
  scene.timestep = taskTimestep(1.0 / opt.control_rate);
  scene.fixtures = {fixture};
  scene.fixtures[0].friction = opt.contact.skin_friction;
  scene.sensors = {taskSensor("sensor", opt.contact, X_ws0)};
  return scene;
}

// The dome's paths pooled into one (means and rms weighted by their samples).
void poolDome(FollowingResult& res) {
  FollowingPath& P = res.dome_pooled;
  P.name = "dome (8 paths)";
  P.reached_end = true;
  double n = 0;
  for (const auto& p : res.dome) {
    const double w = double(p.depth_error.n);
    P.depth_error.mean += p.depth_error.mean * w;
    P.tilt.mean += p.tilt.mean * w;
    P.depth_error.rms += p.depth_error.rms * p.depth_error.rms * w;
    P.tilt.rms += p.tilt.rms * p.tilt.rms * w;
    P.depth_error.max = std::max(P.depth_error.max, p.depth_error.max);
    P.tilt.max = std::max(P.tilt.max, p.tilt.max);
    P.distance += p.distance;
    P.contact_kept = P.contact_kept && p.contact_kept;
    P.reached_end = P.reached_end && p.reached_end;
    n += w;
  }
  if (n > 0) {
    P.depth_error.mean /= n, P.tilt.mean /= n;
    P.depth_error.rms = std::sqrt(P.depth_error.rms / n), P.tilt.rms = std::sqrt(P.tilt.rms / n);
    P.depth_error.n = P.tilt.n = std::size_t(n);
  }
}

// The ramp's figure: the path over the profile with the sensor's axis each second, the top
// view, and the errors over time.
void writeRampFigure(const std::string& dir, const mujoco::FixtureSpec& ramp, const PathLog& ramp_log) {
  SvgFigure fig("Surface following: curved ramp (tip-centre trajectory, sensor z-axis every 1 s)");
  SvgPanel& P = fig.panel("y-z (side view)", "y (mm)", "z (mm)");
  std::vector<Vec2> profile;
  for (double y = -80; y <= ramp.size2 + 80; y += 2) profile.emplace_back(y, mujoco::rampHeight(ramp, y));
  P.line(profile, "#888", 2.0);
  P.line(proj(ramp_log.pos, 1, 2), "#d62728", 1.2, false, "sensor");
  for (const auto& [p, z] : ramp_log.axes) P.arrow(Vec2(p.y(), p.z()), Vec2(p.y() + 15 * z.y(), p.z() + 15 * z.z()), "#1f4fd8");
  SvgPanel& Q = fig.panel("x-y (top view)", "x (mm)", "y (mm)");
  Q.line(proj(ramp_log.pos, 0, 1), "#d62728", 1.2);
  SvgPanel& D = fig.panel("depth error / tilt", "t (s)", "mm | deg");
  D.equal_aspect = false;
  D.line(ramp_log.depth, "#d62728", 1.0, false, "depth − 3 mm");
  D.line(ramp_log.tilt, "#1f4fd8", 1.0, false, "tilt (deg)");
  fig.write(detail::join(dir, "following_ramp.svg"));
}

// The dome's figure: the eight paths in three views with the sensor's axis each second.
void writeDomeFigure(const std::string& dir, double a, const std::vector<PathLog>& dome_logs) {
  SvgFigure fig("Surface following: 8 radial paths over a hemispherical dome (radius 80 mm)");
  SvgPanel& P = fig.panel("x-y (top view)", "x (mm)", "y (mm)");
  SvgPanel& Q = fig.panel("x-z (side view)", "x (mm)", "z (mm)");
  SvgPanel& S = fig.panel("y-z (side view)", "y (mm)", "z (mm)");
  std::vector<Vec2> circle, arc;
  for (int k = 0; k <= 96; ++k) {
    circle.emplace_back(a * std::cos(2 * kPi * k / 96), a * std::sin(2 * kPi * k / 96));
    if (k <= 48) arc.emplace_back(a * std::cos(kPi * k / 48), a * std::sin(kPi * k / 48));
  }
  P.line(circle, "#888", 1.5);
  Q.line(arc, "#888", 1.5);
  S.line(arc, "#888", 1.5);
  const char* colours[8] = {"#d62728", "#ff7f0e", "#bcbd22", "#2ca02c", "#17becf", "#1f77b4", "#9467bd", "#e377c2"};
  for (int i = 0; i < 8; ++i) {
    P.line(proj(dome_logs[i].pos, 0, 1), colours[i], 1.5);
    Q.line(proj(dome_logs[i].pos, 0, 2), colours[i], 1.2);
    S.line(proj(dome_logs[i].pos, 1, 2), colours[i], 1.2);
    for (const auto& [p, z] : dome_logs[i].axes) {
      Q.arrow(Vec2(p.x(), p.z()), Vec2(p.x() + 12 * z.x(), p.z() + 12 * z.z()), "#1f4fd8");
      S.arrow(Vec2(p.y(), p.z()), Vec2(p.y() + 12 * z.y(), p.z() + 12 * z.z()), "#1f4fd8");
    }
  }
  fig.write(detail::join(dir, "following_dome.svg"));
}

}  // namespace

mujoco::FixtureSpec followingRamp() {
  mujoco::FixtureSpec ramp;
  ramp.name = "ramp";
  ramp.shape = "ramp";
  ramp.size = 40;    // H
  ramp.size2 = 200;  // L
  ramp.width = 80;
  return ramp;
}

FollowingResult runSurfaceFollowing(const TaskOptions& opt) {
  opt.validate();
  using detail::EngineArm;
  FollowingResult res;
  const double R = opt.contact.tip_radius;
  const double ref_depth = lieservo::paper::kSurfaceFollowing.reference_pose[2];
  const double speed = lieservo::paper::kSurfaceFollowingSpeed;
  // Sensor pointing down (z_s = −z_w) with y_s = +y_w.
  const Mat3 R_down = fromColumns(-Vec3::UnitX(), Vec3::UnitY(), -Vec3::UnitZ());

  CsvWriter csv;
  if (!opt.out_dir.empty()) {
    makeDirectories(opt.out_dir);
    csv.open(detail::join(opt.out_dir, "following.csv"),
             {"t", "path", "sensor_x", "sensor_y", "sensor_z", "sensor_a_deg", "sensor_b_deg", "sensor_g_deg", "depth",
              "tilt_deg", "contact_x", "contact_y", "contact_z", "shear_x", "shear_y"});
  }
  double t_global = 0;

  // ---- curved ramp ----
  const mujoco::FixtureSpec ramp = followingRamp();
  PathLog ramp_log;
  {
    const double y0 = -30;
    mujoco::World world(followingScene(ramp, makePose(R_down, Vec3(0, y0, mujoco::rampHeight(ramp, y0) + R - ref_depth)), opt));
    EngineArm sa(world, 0, opt, opt.seed * 104729 + 3);
    detail::ServoLoop loop(followingLoop(kPi / 2, speed));
    res.ramp.name = "curved ramp";
    const double y_end = ramp.size2 + 30;
    followPath(world, sa, loop, opt, ref_depth, 1.6 * (y_end - y0) / speed,
               [&](const ContactState& c) { return c.point_w.y() > y_end; }, res.ramp, ramp_log, csv, 0, t_global,
               res.failures);
  }
  check(res.ramp, res.failures);

  // ---- hemispherical dome ----
  const double a = 80;
  mujoco::FixtureSpec dome;
  dome.name = "dome";
  dome.shape = "dome";
  dome.size = a;
  const double stop_angle = deg2rad(50) * std::clamp(opt.duration_scale, 0.3, 1.0);
  std::vector<PathLog> dome_logs(8);
  {
    const SE3d X0 = makePose(R_down, Vec3(0, 0, a + R - ref_depth));
    mujoco::World world(followingScene(dome, X0, opt));
    EngineArm sa(world, 0, opt, opt.seed * 15485863 + 5);
    detail::ServoLoop loop;
    for (int i = 0; i < 8; ++i) {
      const double th = deg2rad(45.0 * i);
      world.reset();
      sa.arm.stop();
      sa.restart(loop);
      if (loop.configure(followingLoop(th, speed)) != Status::ok) throw SceneError("surface following preset rejected");
      FollowingPath p;
      char nm[40];
      std::snprintf(nm, sizeof nm, "dome %d deg", 45 * i);
      p.name = nm;
      followPath(world, sa, loop, opt, ref_depth, 2.0 * a * stop_angle / speed + 3,
                 [&](const ContactState& c) { return std::acos(std::clamp(c.normal_w.z(), -1.0, 1.0)) > stop_angle; },
                 p, dome_logs[i], csv, i + 1, t_global, res.failures);
      check(p, res.failures);
      res.dome.push_back(p);
    }
  }
  poolDome(res);
  res.sim_time = t_global;
  res.success = res.failures.empty();
  if (!opt.out_dir.empty()) {
    writeRampFigure(opt.out_dir, ramp, ramp_log);
    writeDomeFigure(opt.out_dir, a, dome_logs);
  }
  return res;
}

}  // namespace lieservo::sim

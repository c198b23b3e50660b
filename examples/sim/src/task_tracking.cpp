// Task (a): object pose tracking (paper Section 5.4 (sec:obj_pose_tracking_exp)), on MuJoCo.
//
// A leader arm carries a flat plate (a carried "plate" fixture, 160 mm square, its face
// normal +z_o towards the follower). The follower's sensor starts normal to the plate at 6 mm
// depth (Table 6 reference (0,0,6,0,0,0)).
// Part 1 (Section 5.4.1, sec:object_pose_tracking_single_exp): the leader moves 200 mm along −x, +y, +z of the
// work frame and rotates 60° about x (−α), y, z through the plate centre, each leg out and back
// with a smooth (raised-cosine) profile of `leg_time` s.  Part 2 (Section 5.4.2, sec:object_pose_tracking_multi_exp):
// v_j(t) = (2π b_j / T) cos(2πt/T + φ_j), b = (75, 75, 75 mm, 25°, 25°, 25°),
// φ = (π/2, 0, …, 0), T = 30 s, three periods; integrated as position
// p_j(t) = b_j (sin(2πt/T + φ_j) − sin φ_j) (Euler angles for the rotational part).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include <lieservo/control/presets.hpp>
#include <lieservo/control/tactile_servo_controller.hpp>

#include "task_common.hpp"

namespace lieservo::sim {

namespace {

struct Leg {
  std::string name;
  Vec3 translation;  // total displacement of the leg (work frame)
  Vec3 axis;         // rotation axis (work frame), zero for translations
  double angle;      // total rotation (rad)
  double out;        // +1 out, −1 back
};

// Leader plate pose at time t of the single-axis sequence.  Returns false past the end.
SE3d legPose(const std::vector<Leg>& legs, double leg_time, double hold, double t, const SE3d& X0,
             std::size_t& leg_index) {
  const double per = leg_time + hold;
  leg_index = std::min<std::size_t>(std::size_t(t / per), legs.size() - 1);
  // Accumulate the completed out/back pairs: back legs return to X0, so only the current
  // out-leg offset matters.
  const Leg& L = legs[leg_index];
  const double tau = std::clamp((t - leg_index * per) / leg_time, 0.0, 1.0);
  const double s = 0.5 * (1 - std::cos(kPi * tau));  // 0 → 1
  const double frac = L.out > 0 ? s : 1 - s;          // back legs go 1 → 0
  Mat3 R = Mat3::Identity();
  if (L.axis.norm() > 0) R = Eigen::AngleAxisd(frac * L.angle, L.axis.normalized()).toRotationMatrix();
  const Vec3 p = X0.translation() + frac * L.translation;
  return makePose(R * X0.rotationMatrix(), p);  // rotation about the plate centre (TCP)
}

SE3d periodicPose(double t, double T, const SE3d& X0) {
  const double b[6] = {75, 75, 75, deg2rad(25), deg2rad(25), deg2rad(25)};
  const double phi[6] = {kPi / 2, 0, 0, 0, 0, 0};
  double q[6];
  for (int j = 0; j < 6; ++j) q[j] = b[j] * (std::sin(2 * kPi * t / T + phi[j]) - std::sin(phi[j]));
  return makePose(SO3d::fromEulerXYZ(q[3], q[4], q[5]).rotationMatrix() * X0.rotationMatrix(), X0.translation() + Vec3(q[0], q[1], q[2]));
}

// The scene: the leader's carried plate at the origin (normal +z_w) and the follower's sensor
// normal to it at the reference depth (z_s = −z_w, x_s = x_w, y_s = −y_w).
mujoco::SceneSpec trackingScene(const TaskOptions& opt, double h, double ref_depth) {
  mujoco::SceneSpec scene;
  scene.timestep = h;
  mujoco::FixtureSpec plate;
  plate.name = "plate";
  plate.shape = "plate";
  plate.size = 160;
  plate.size2 = 10;
  plate.carried = true;
  plate.pose = SE3d::identity();
  plate.friction = opt.contact.skin_friction;
  scene.fixtures = {plate};
  scene.sensors = {taskSensor(
      "follower", opt.contact,
      makePose(fromColumns(Vec3::UnitX(), -Vec3::UnitY(), -Vec3::UnitZ()),
               Vec3(0, 0, opt.contact.tip_radius - ref_depth)))};
  return scene;
}

// Part 1's legs, out and back along −x, +y, +z and about x (−α), y, z; S < 1 shortens the moves
// at the same speeds.
std::vector<Leg> trackingLegs(double S) {
  const double L = 200 * S, A = deg2rad(60) * S;
  std::vector<Leg> legs;
  auto addPair = [&](const std::string& n, Vec3 tr, Vec3 ax, double ang) {
    legs.push_back({n + " out", tr, ax, ang, +1});
    legs.push_back({n + " back", tr, ax, ang, -1});
  };
  addPair("-x", Vec3(-L, 0, 0), Vec3::Zero(), 0);
  addPair("+y", Vec3(0, L, 0), Vec3::Zero(), 0);
  addPair("+z", Vec3(0, 0, L), Vec3::Zero(), 0);
  addPair("-alpha", Vec3::Zero(), Vec3::UnitX(), -A);
  addPair("beta", Vec3::Zero(), Vec3::UnitY(), A);
  addPair("gamma", Vec3::Zero(), Vec3::UnitZ(), A);
  return legs;
}

// What the figures draw: both parts' leader and follower paths, the follower's axis once a
// second, and the depth error and tilt over time.
struct TrackingTrace {
  std::vector<Vec3> lead1, foll1, lead2, foll2;
  std::vector<std::pair<Vec3, Vec3>> axes1, axes2;  // follower position, z axis (sampled)
  std::vector<Vec2> depth_series, tilt_series;
};

// One control period's record: the segment's statistics, the CSV row, the traces.
void recordPeriod(const TaskOptions& opt, double t, long k, bool part2, const SE3d& X_wl, double ref_depth,
                  const detail::EngineArm& follower, const detail::ServoLoop& loop, TrackingSegment& seg,
                  CsvWriter& csv, TrackingTrace& tr) {
  const ContactState& c = follower.state;
  const double depth_err = c.depth - ref_depth;
  const Vec3 pc = X_wl.inverse() * c.point_w;
  seg.depth_error.add(depth_err);
  seg.tilt.add(rad2deg(c.tilt));
  seg.twist.add(rad2deg(c.twist));
  seg.lag.add(pc.head<2>().norm());
  if (!c.in_contact) seg.contact_kept = false;
  const SE3d Xs = follower.pose();
  if (csv.isOpen()) {
    const Vec6 el = X_wl.toEulerXYZ6(), es = Xs.toEulerXYZ6();
    const Vec6 est = loop.filter().filtered().mean.inverse().toEulerXYZ6();
    csv.row({t, part2 ? 2.0 : 1.0, el[0], el[1], el[2], rad2deg(el[3]), rad2deg(el[4]), rad2deg(el[5]), es[0], es[1], es[2],
             rad2deg(es[3]), rad2deg(es[4]), rad2deg(es[5]), c.depth, est[2], rad2deg(c.tilt), c.shear.x(), c.shear.y(),
             rad2deg(c.twist), c.slipped ? 1.0 : 0.0});
  }
  (part2 ? tr.lead2 : tr.lead1).push_back(X_wl.translation());
  (part2 ? tr.foll2 : tr.foll1).push_back(Xs.translation());
  if (k % int(opt.control_rate) == 0)
    (part2 ? tr.axes2 : tr.axes1).push_back({Xs.translation(), Vec3(Xs.rotationMatrix().col(2))});
  tr.depth_series.emplace_back(t, depth_err);
  tr.tilt_series.emplace_back(t, rad2deg(c.tilt));
}

// The per-period log, dir/tracking.csv.
void openLog(const std::string& dir, CsvWriter& csv) {
  makeDirectories(dir);
  csv.open(detail::join(dir, "tracking.csv"),
           {"t", "part", "leader_x", "leader_y", "leader_z", "leader_a_deg", "leader_b_deg", "leader_g_deg",
            "sensor_x", "sensor_y", "sensor_z", "sensor_a_deg", "sensor_b_deg", "sensor_g_deg", "depth",
            "depth_est", "tilt_deg", "shear_x", "shear_y", "twist_deg", "slipped"});
}

// The single-axis legs pooled into one segment (means and rms weighted by their samples).
TrackingSegment pool(const std::vector<TrackingSegment>& segs, std::size_t b, std::size_t e, const std::string& n) {
  TrackingSegment p;
  p.name = n;
  double wd = 0, wt = 0, ww = 0, wl = 0, rd = 0, rt = 0, rw = 0, rl = 0;
  std::size_t N = 0;
  for (std::size_t i = b; i < e; ++i) {
    const auto& s = segs[i];
    const double n_i = double(s.depth_error.n);
    N += s.depth_error.n;
    wd += s.depth_error.mean * n_i, wt += s.tilt.mean * n_i, ww += s.twist.mean * n_i, wl += s.lag.mean * n_i;
    rd += s.depth_error.rms * s.depth_error.rms * n_i, rt += s.tilt.rms * s.tilt.rms * n_i;
    rw += s.twist.rms * s.twist.rms * n_i, rl += s.lag.rms * s.lag.rms * n_i;
    p.depth_error.max = std::max(p.depth_error.max, s.depth_error.max);
    p.tilt.max = std::max(p.tilt.max, s.tilt.max);
    p.twist.max = std::max(p.twist.max, s.twist.max);
    p.lag.max = std::max(p.lag.max, s.lag.max);
    p.contact_kept = p.contact_kept && s.contact_kept;
  }
  if (N) {
    const double nn = double(N);
    p.depth_error.mean = wd / nn, p.tilt.mean = wt / nn, p.twist.mean = ww / nn, p.lag.mean = wl / nn;
    p.depth_error.rms = std::sqrt(rd / nn), p.tilt.rms = std::sqrt(rt / nn), p.twist.rms = std::sqrt(rw / nn);
    p.lag.rms = std::sqrt(rl / nn);
    p.depth_error.n = p.tilt.n = p.twist.n = p.lag.n = N;
  }
  return p;
}

// The criteria (docs/simulation.md, "Success criteria") on both parts.
void judgeTracking(TrackingResult& res) {
  for (const TrackingSegment* p : {&res.single_axis, &res.periodic}) {
    char buf[200];
    if (!p->contact_kept) res.failures.push_back("tracking " + p->name + ": contact lost");
    if (p->depth_error.mean > Bounds::tracking_depth_mean || p->depth_error.max > Bounds::tracking_depth_max) {
      std::snprintf(buf, sizeof buf, "tracking %s: depth error mean %.2f / max %.2f mm over bounds %.1f / %.1f",
                    p->name.c_str(), p->depth_error.mean, p->depth_error.max, Bounds::tracking_depth_mean,
                    Bounds::tracking_depth_max);
      res.failures.push_back(buf);
    }
    if (p->tilt.mean > Bounds::tracking_tilt_mean || p->tilt.max > Bounds::tracking_tilt_max) {
      std::snprintf(buf, sizeof buf, "tracking %s: tilt mean %.2f / max %.2f deg over bounds %.1f / %.1f",
                    p->name.c_str(), p->tilt.mean, p->tilt.max, Bounds::tracking_tilt_mean, Bounds::tracking_tilt_max);
      res.failures.push_back(buf);
    }
  }
  res.success = res.failures.empty();
}

// The figures: both parts' paths in three projections, and the errors over time.
void writeTrackingFigures(const std::string& dir, const TrackingTrace& tr) {
  using detail::join;
  auto proj = [](const std::vector<Vec3>& v, int a, int b) {
    std::vector<Vec2> o;
    o.reserve(v.size());
    for (const auto& p : v) o.emplace_back(p[a], p[b]);
    return o;
  };
  auto addAxes = [](SvgPanel& P, const std::vector<std::pair<Vec3, Vec3>>& ax, int a, int b) {
    for (const auto& [p, z] : ax) P.arrow(Vec2(p[a], p[b]), Vec2(p[a] + 10 * z[a], p[b] + 10 * z[b]), "#1f4fd8");
  };
  const char* names[3] = {"x (mm)", "y (mm)", "z (mm)"};
  const int pairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  for (int part = 1; part <= 2; ++part) {
    SvgFigure fig(part == 1 ? "Object tracking: single-axis moves (leader plate centre vs follower tip centre)"
                            : "Object tracking: periodic trajectory (3 periods)");
    for (const auto& pr : pairs) {
      SvgPanel& P = fig.panel(std::string(names[pr[0]]).substr(0, 1) + "-" + std::string(names[pr[1]]).substr(0, 1) +
                                  " projection",
                              names[pr[0]], names[pr[1]]);
      P.line(proj(part == 1 ? tr.lead1 : tr.lead2, pr[0], pr[1]), "#888", 1.5, true, "leader (plate)");
      P.line(proj(part == 1 ? tr.foll1 : tr.foll2, pr[0], pr[1]), "#d62728", 1.2, false, "follower (sensor)");
      addAxes(P, part == 1 ? tr.axes1 : tr.axes2, pr[0], pr[1]);
    }
    fig.write(join(dir, part == 1 ? "tracking_single_axis.svg" : "tracking_periodic.svg"));
  }
  SvgFigure ts("Object tracking: contact-depth error and tilt from the normal");
  SvgPanel& a = ts.panel("depth error (true − 6 mm)", "t (s)", "mm");
  a.equal_aspect = false;
  a.line(tr.depth_series, "#d62728", 1.0);
  SvgPanel& b = ts.panel("angle from surface normal", "t (s)", "deg");
  b.equal_aspect = false;
  b.line(tr.tilt_series, "#1f4fd8", 1.0);
  ts.write(join(dir, "tracking_errors.svg"), 520);
}

}  // namespace

TrackingResult runObjectTracking(const TaskOptions& opt) {
  opt.validate();
  TrackingResult res;
  const double dt = 1.0 / opt.control_rate;
  const int substeps = stepsPerPeriod(dt);
  const double h = dt / substeps;
  const double ref_depth = lieservo::paper::kObjectTracking.reference_pose[2];
  const SE3d X_wl0 = SE3d::identity();  // plate centre at the origin, normal +z_w
  const mujoco::SceneSpec scene = trackingScene(opt, h, ref_depth);
  mujoco::World world(scene);
  detail::EngineArm follower(world, 0, opt, opt.seed * 7919 + 11);
  detail::ServoLoop::Options loop_options;
  loop_options.controller = lieservo::objectTrackingPreset<double>();
  detail::ServoLoop loop(loop_options);
  if (loop.configurationStatus() != Status::ok) throw SceneError("object tracking preset rejected");

  // duration_scale < 1 shortens the legs at the same speeds (shorter moves, shorter times).
  const double S = std::min(1.0, std::max(0.1, opt.duration_scale));
  const double leg_time = 12.0 * S, hold = 1.0;
  const std::vector<Leg> legs = trackingLegs(S);
  const double T1 = legs.size() * (leg_time + hold);
  const double Tper = 30.0;
  const int periods = opt.duration_scale >= 1 ? 3 : 1;
  const double T2 = opt.duration_scale >= 1 ? periods * Tper : std::max(5.0, opt.duration_scale * Tper);
  res.segments.resize(legs.size() + 1);
  for (std::size_t i = 0; i < legs.size(); ++i) res.segments[i].name = legs[i].name;
  res.segments.back().name = "periodic";

  CsvWriter csv;
  if (!opt.out_dir.empty()) openLog(opt.out_dir, csv);
  TrackingTrace trace;
  SE3d X_wl = X_wl0;
  follower.touch(world);
  double t = 0;
  long k = 0;
  const long state_every = std::max(1L, std::lround(kStatePeriod / dt));
  res.states.scene = scene;
  res.states.add(0, world.positions());
  while (t < T1 + T2 - 1e-9) {
    const bool part2 = t >= T1;
    std::size_t leg = legs.size();
    Vec6 u = Vec6::Zero();
    Status s = follower.step(loop, dt, u);  // observe, filter, control
    if (s != Status::ok) {
      res.failures.push_back(std::string("tracking: loop status ") + lieservo::describe(s));
      break;
    }
    // MuJoCo steps: the leader moves the plate, the follower its sensor; the engine steps;
    // the contact sticks or slips.
    for (int j = 0; j < substeps; ++j) {
      const double tj = t + (j + 1) * h;
      X_wl = tj < T1 ? legPose(legs, leg_time, hold, tj, X_wl0, leg) : periodicPose(tj - T1, Tper, X_wl0);
      s = world.setFixturePose(0, X_wl);
      if (s == Status::ok) s = follower.arm.commandVelocity(u, h);
      if (s == Status::ok) s = world.step(h);
      if (s != Status::ok) break;
      follower.touch(world);
    }
    if (s != Status::ok) {
      res.failures.push_back(std::string("tracking: world status ") + lieservo::describe(s));
      break;
    }
    t += dt;
    ++k;
    if (k % state_every == 0) res.states.add(t, world.positions());
    if (!part2) legPose(legs, leg_time, hold, t - 0.5 * dt, X_wl0, leg);
    recordPeriod(opt, t, k, part2, X_wl, ref_depth, follower, loop, part2 ? res.segments.back() : res.segments[leg],
                 csv, trace);
  }
  if (res.states.times.back() < t) res.states.add(t, world.positions());
  res.sim_time = t;
  for (auto& seg : res.segments) seg.depth_error.finish(), seg.tilt.finish(), seg.twist.finish(), seg.lag.finish();
  res.single_axis = pool(res.segments, 0, legs.size(), "single-axis");
  res.periodic = res.segments.back();
  judgeTracking(res);
  if (!opt.out_dir.empty()) writeTrackingFigures(opt.out_dir, trace);
  return res;
}

}  // namespace lieservo::sim

// Tasks (c) and (d): single- and dual-arm pushing (paper sec:single_arm_object_pushing_exp,
// sec:dual_arm_object_pushing_exp, sec:dual_arm_tall_object_pushing).
//
// Work frame: the support is the y–z plane, x is up.  The leader's sensor starts at
// (x, y, z) = (45, −250, 100) mm with its axis along +y (right-angle mount: x_s up, y_s = −z_w),
// the object is placed centrally in front of it with a face normal to the sensor axis
// (seeded jitter: ±2 mm sideways, ±2° yaw), and the target is (y, z) = (0, 375) mm.
// The dual-arm follower starts opposite, normal to the far face at 3 mm depth.
//
// World update (every sub-step, after the arms moved): the tip presses on the object with
// force k·depth.  The object stays put while the net push is below the support friction
// μ_s m g (quasi-static), i.e. while depth_pusher − depth_other ≤ d_fric = μ_s m g / k; the
// excess is removed by moving the object with the quasi-static pushing model
// (planar_pushing.hpp: ellipsoidal limit surface, motion cone, stick/slide), driven by the
// pusher's displacement relative to the object scaled to the excess penetration.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include <lieservo/control/dual_arm.hpp>
#include <lieservo/control/presets.hpp>
#include <lieservo/control/pushing_controller.hpp>

#include "lieservo_sim/planar_pushing.hpp"
#include "task_common.hpp"

namespace lieservo::sim {

namespace {

using detail::Gaussian;
using detail::SensorArm;

PrismSurface makePrism(const PushObject& o) {
  if (o.shape == "square") return PrismSurface::square(o.size, o.height, o.name);
  if (o.shape == "circle") return PrismSurface::circle(o.size, o.height, o.name);
  return PrismSurface::regularPolygon(6, o.size, o.height, o.name);
}
double apothem(const PushObject& o) {
  if (o.shape == "square") return o.size / 2;
  if (o.shape == "circle") return o.size;
  return o.size * std::cos(kPi / 6);
}

// Object frame: x_o → y_w, y_o → z_w, z_o → x_w (up); yaw θ about x_w.
const Mat3 kR0 = fromColumns(Vec3::UnitY(), Vec3::UnitZ(), Vec3::UnitX());
SE3d objectPose(const Vec3& yzth) { return makePose(rotX(yzth.z()) * kR0, Vec3(0, yzth.x(), yzth.y())); }
Vec3 objectPlanar(const SE3d& X) {
  const Mat3 R = X.rotationMatrix() * kR0.transpose();  // = Rx(θ)
  return Vec3(X.translation().y(), X.translation().z(), std::atan2(R(2, 1), R(1, 1)));
}

struct World {
  PrismSurface prism;
  SE3d X_wo;
  double d_fric;      // mm
  double mu_c, c_ls;  // pusher friction, limit-surface ratio
  double mu_hold;     // holding friction of the opposite (stabilising) sensor
  double tip_radius;
  long push_steps = 0, slide_steps = 0;

  struct PusherState {
    Vec2 prev = Vec2::Zero();
  };
  PusherState ps[2];

  Vec2 centreInObject(const SE3d& X_ws) const { return (X_wo.inverse() * X_ws.translation()).head<2>(); }
  double depthOf(const Vec2& c, SurfacePoint& sp) const {
    sp = prism.closest2d(c);
    return tip_radius - sp.signed_distance;
  }
  void remember(const SE3d* arms[2], int n) {
    for (int i = 0; i < n; ++i) ps[i].prev = centreInObject(*arms[i]);
  }
  // Moves the object so that no pusher exceeds the friction-limited penetration.
  void resolve(const SE3d* arms[2], int n) {
    for (int iter = 0; iter < 3; ++iter) {
      Vec2 c[2];
      SurfacePoint sp[2];
      double pen[2] = {0, 0};
      for (int i = 0; i < n; ++i) {
        c[i] = centreInObject(*arms[i]);
        pen[i] = std::max(0.0, depthOf(c[i], sp[i]));
      }
      int who = -1;
      double excess = 0;
      for (int i = 0; i < n; ++i) {
        const double other = n == 2 ? pen[1 - i] : 0.0;
        const double e = pen[i] - other - d_fric;
        if (e > 1e-7 && e > excess) excess = e, who = i;
      }
      if (who < 0) break;
      const Vec2 nrm = sp[who].normal.head<2>();
      const Vec2 r = sp[who].point.head<2>();
      const Vec2 dc = c[who] - ps[who].prev;
      const double dn = -dc.dot(nrm);
      Vec2 u = (iter == 0 && dn > 1e-9) ? Vec2(dc * std::min(excess / dn, 4.0)) : Vec2(-nrm * excess);
      PushOutcome po = quasiStaticPush(r, nrm, u, mu_c, c_ls);
      if (po.separating) break;
      if (iter == 0) {
        ++push_steps;
        if (po.sliding) ++slide_steps;
      }
      Vec3 V = po.twist;
      const int other = 1 - who;
      if (n == 2 && pen[other] > 0) {
        // The opposite sensor presses with k·depth and holds the object by friction: its
        // contact point should move with it tangentially.  Minimal change of V in the
        // limit-surface metric W = diag(1, 1, c²) subject to that constraint; if the needed
        // tangential force exceeds μ_c times its normal force (relative to the pusher's
        // force), the constraint force saturates (the object slides under the other sensor).
        const Vec2 nO = sp[other].normal.head<2>(), rO = sp[other].point.head<2>();
        const Vec2 tO(-nO.y(), nO.x());
        const Vec3 a(tO.x(), tO.y(), rO.x() * tO.y() - rO.y() * tO.x());
        const double b = (c[other] - ps[other].prev).dot(tO);
        const Vec3 Winv_a(a.x(), a.y(), a.z() / (c_ls * c_ls));
        double lambda = (b - a.dot(V)) / a.dot(Winv_a);
        const double push_force = V.head<2>().norm();
        const double limit = mu_hold * pen[other] / std::max(pen[who], 1e-6) * push_force;
        lambda = std::clamp(lambda, -limit, limit);
        V += lambda * Winv_a;
      }
      Vec6 xi = Vec6::Zero();
      xi << V.x(), V.y(), 0, 0, 0, V.z();
      X_wo = X_wo * SE3d::exp(xi);
      X_wo.normalize();
    }
    remember(arms, n);
  }
};

double cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

}  // namespace

PushTrial runPushTrial(const PushingSetup& setup, const TaskOptions& opt, std::uint64_t trial_seed) {
  setup.validate();
  opt.validate();
  PushTrial tr;
  const double dt = 1.0 / opt.control_rate, h = dt / opt.substeps;
  const double R = opt.contact.tip_radius;
  std::mt19937_64 rng(trial_seed * 6364136223846793005ULL + 1442695040888963407ULL);
  std::normal_distribution<double> N01(0, 1);
  std::uniform_real_distribution<double> U(0.9, 1.1);

  World w{makePrism(setup.object), SE3d::identity(), 0, 0, 0, 0, R, 0, 0, {}};
  w.mu_hold = setup.surface.holding_friction;
  const double mu_s = setup.surface.object_friction * U(rng);
  w.d_fric = mu_s * setup.object.mass * 9.81 / setup.tip_stiffness;
  w.mu_c = setup.surface.pusher_friction;
  w.c_ls = setup.surface.pressure_factor * w.prism.uniformPressureLimitSurfaceRatio();
  const double jitter_z = 2.0 * std::clamp(N01(rng), -2.0, 2.0);
  const double jitter_th = setup.object.shape == "circle" ? 0.0 : deg(2.0) * std::clamp(N01(rng), -2.0, 2.0);
  const double ap = apothem(setup.object);
  const Vec3 obj0(setup.start.x() + R - setup.initial_depth + ap, setup.start.y() + jitter_z, jitter_th);
  w.X_wo = objectPose(obj0);

  const double H = setup.sensor_height;
  const SE3d X_ws_leader = makePose(fromColumns(Vec3::UnitX(), -Vec3::UnitZ(), Vec3::UnitY()),
                                    Vec3(H, setup.start.x(), setup.start.y()));
  // Follower opposite: along the line through the object centre, at the far face.
  const Vec3 far_c = w.X_wo * Vec3(ap + R - setup.follower_depth, 0, H);
  const Vec3 far_dir = w.X_wo.rotationMatrix() * Vec3(-1, 0, 0);  // sensor axis: into the far face
  const SE3d X_ws_follower =
      makePose(fromColumns(Vec3::UnitX(), far_dir.cross(Vec3::UnitX()), far_dir), far_c);

  const std::uint64_t s0 = trial_seed * 1000003ULL;
  SensorArm leader(X_ws_leader, w.prism, opt, s0 + 1);
  SensorArm follower(setup.dual_arm ? X_ws_follower : X_ws_leader, w.prism, opt, s0 + 2);
  const SE3d X_wt = makePose(Mat3::Identity(), Vec3(H, setup.target.x(), setup.target.y()));

  lieservo::PushingController<double> single;
  lieservo::DualArmPushing<double> dual;
  if (setup.dual_arm) {
    auto o = lieservo::dualArmPushingPreset<double>(setup.tall);
    o.leader.target = X_wt;
    dual = lieservo::DualArmPushing<double>(o, detail::Filter(), detail::Filter());
    if (dual.configurationStatus() != Status::ok) throw SceneError("dual-arm pushing preset rejected");
  } else {
    auto o = lieservo::pushingPreset<double>(lieservo::PushingConfiguration::single_arm);
    o.target = X_wt;
    single = lieservo::PushingController<double>(o);
    if (single.configurationStatus() != Status::ok) throw SceneError("pushing preset rejected");
  }

  const int n_arms = setup.dual_arm ? 2 : 1;
  const SE3d* arms[2] = {&leader.arm.pose(), &follower.arm.pose()};
  w.remember(arms, n_arms);
  leader.touch(w.X_wo);
  if (setup.dual_arm) follower.touch(w.X_wo);

  double t = 0;
  bool terminated = false;
  long steps = 0, follower_steps_in_contact = 0;
  while (t < setup.timeout) {
    Vec6 uL = Vec6::Zero(), uF = Vec6::Zero();
    Status s;
    if (setup.dual_arm) {
      lieservo::DualArmPushing<double>::ArmInput inL, inF;
      inL.sensor_pose = leader.arm.pose();
      inF.sensor_pose = follower.arm.pose();
      s = leader.observe(inL.observation);
      if (s == Status::ok) s = follower.observe(inF.observation);
      lieservo::DualArmPushing<double>::ArmOutput oL, oF;
      if (s == Status::ok) s = dual.step(inL, inF, dt, oL, oF);
      uL = oL.velocity;
      uF = oF.velocity;
      terminated = dual.terminated();
    } else {
      SE3d X_sf;
      s = leader.sense(X_sf);
      if (s == Status::ok) s = single.step(leader.arm.pose(), X_sf, dt, uL);
      terminated = single.terminated();
    }
    if (s != Status::ok) break;
    if (terminated) break;
    for (int j = 0; j < opt.substeps; ++j) {
      leader.arm.commandVelocity(uL, h);
      if (setup.dual_arm) follower.arm.commandVelocity(uF, h);
      w.resolve(arms, n_arms);
      leader.touch(w.X_wo);
      if (setup.dual_arm) follower.touch(w.X_wo);
    }
    t += dt;
    ++steps;
    const ContactState& cL = leader.state;
    if (!cL.in_contact) tr.contact_kept = false;
    tr.max_leader_depth = std::max(tr.max_leader_depth, cL.depth);
    if (setup.dual_arm) {
      const ContactState& cF = follower.state;
      if (!cF.in_contact) tr.follower_contact_kept = false;
      else ++follower_steps_in_contact;
      tr.max_follower_depth = std::max(tr.max_follower_depth, cF.depth);
      tr.min_follower_depth = std::min(tr.min_follower_depth, cF.depth);
      tr.follower_path.push_back(follower.arm.pose().translation());
    }
    tr.sensor_path.push_back(leader.arm.pose().translation());
    {
      const auto& pcn = setup.dual_arm ? dual.leader() : single;
      tr.bearing.push_back(toDeg(pcn.bearing()));
      tr.alignment_velocity.push_back(pcn.alignmentVelocity()[1]);
      tr.leader_depth.push_back(cL.depth);
      tr.leader_tilt.push_back(toDeg(eulerXYZ(cL.X_fs.rotationMatrix())[0]));
      tr.follower_depth.push_back(setup.dual_arm ? follower.state.depth : 0.0);
    }
    tr.object_path.push_back(objectPlanar(w.X_wo));
  }
  tr.terminated = terminated;
  tr.duration = t;
  tr.follower_contact_fraction = steps ? double(follower_steps_in_contact) / double(steps) : 1.0;
  const ContactState& cL = leader.state;
  const Vec2 p(cL.point_w.y(), cL.point_w.z()), n = Vec2(cL.normal_w.y(), cL.normal_w.z()).normalized();
  const Vec2 T = setup.target;
  tr.target_error = std::abs(cross2(T - p, n));
  tr.final_distance = (Vec2(leader.arm.pose().translation().y(), leader.arm.pose().translation().z()) - T).norm();
  tr.sliding_fraction = w.push_steps ? double(w.slide_steps) / double(w.push_steps) : 0.0;
  if (tr.object_path.empty()) tr.object_path.push_back(objectPlanar(w.X_wo));
  return tr;
}

PushingCase runPushingCase(const PushingSetup& setup, const TaskOptions& opt, int trials) {
  if (trials < 1) throw SceneError("runPushingCase: trials must be >= 1");
  PushingCase pc;
  pc.setup = setup;
  for (int i = 0; i < trials; ++i) pc.trials.push_back(runPushTrial(setup, opt, opt.seed * 1000 + std::uint64_t(i) + 1));
  // Statistics over the trials that reached the target (the paper's trials all did).
  double m = 0;
  for (const auto& t : pc.trials)
    if (t.terminated) m += t.target_error, ++pc.reached_trials;
  m = pc.reached_trials ? m / pc.reached_trials : std::numeric_limits<double>::quiet_NaN();
  double v = 0;
  for (const auto& t : pc.trials)
    if (t.terminated) v += (t.target_error - m) * (t.target_error - m);
  pc.mean_error = m;
  pc.sd_error = pc.reached_trials > 1 ? std::sqrt(v / (pc.reached_trials - 1)) : 0.0;
  const std::string tag = std::string(setup.dual_arm ? "dual-arm " : "single-arm ") + setup.object.name + " on " +
                          setup.surface.name;
  char buf[240];
  const int allowed_misses = trials / 5;  // 1 in 5 trials (Bounds::pushing_min_reached_fraction)
  for (std::size_t i = 0; i < pc.trials.size(); ++i) {
    const PushTrial& t = pc.trials[i];
    if (!t.terminated) {
      std::snprintf(buf, sizeof buf, "%s trial %zu: target not reached in %.0f s (final distance %.0f mm)", tag.c_str(),
                    i + 1, setup.timeout, t.final_distance);
      pc.notes.push_back(buf);
      continue;
    }
    if (!t.contact_kept) {
      std::snprintf(buf, sizeof buf, "%s trial %zu: pusher lost contact", tag.c_str(), i + 1);
      pc.failures.push_back(buf);
    }
    if (t.target_error > Bounds::pushing_error_max) {
      std::snprintf(buf, sizeof buf, "%s trial %zu: target error %.1f mm > %.0f mm", tag.c_str(), i + 1,
                    t.target_error, Bounds::pushing_error_max);
      pc.failures.push_back(buf);
    }
    if (setup.dual_arm && !t.follower_contact_kept) {
      std::snprintf(buf, sizeof buf, "%s trial %zu: follower out of contact for %.0f%% of the push", tag.c_str(),
                    i + 1, 100.0 * (1.0 - t.follower_contact_fraction));
      pc.notes.push_back(buf);
    }
    if (t.follower_contact_kept) ++pc.follower_kept_trials;
  }
  if (trials - pc.reached_trials > allowed_misses) {
    std::snprintf(buf, sizeof buf, "%s: target reached in only %d of %d trials (at most %d miss allowed)", tag.c_str(),
                  pc.reached_trials, trials, allowed_misses);
    pc.failures.push_back(buf);
  }
  pc.success = pc.failures.empty();
  return pc;
}

namespace {

void writeCase(const PushingCase& pc, const std::string& dir, const std::string& stem) {
  CsvWriter csv;
  if (!csv.open(detail::join(dir, stem + ".csv"),
                {"trial", "step", "sensor_y", "sensor_z", "follower_y", "follower_z", "object_y", "object_z",
                 "object_theta_deg", "bearing_deg", "align_uy", "leader_depth", "leader_alpha_deg", "follower_depth"}))
    return;
  for (std::size_t i = 0; i < pc.trials.size(); ++i) {
    const PushTrial& t = pc.trials[i];
    for (std::size_t k = 0; k < t.sensor_path.size(); ++k) {
      const Vec3& s = t.sensor_path[k];
      const Vec3 f = k < t.follower_path.size() ? t.follower_path[k] : Vec3(NAN, NAN, NAN);
      const Vec3& o = t.object_path[k];
      csv.row({double(i + 1), double(k), s.y(), s.z(), f.y(), f.z(), o.x(), o.y(), toDeg(o.z()), t.bearing[k],
               t.alignment_velocity[k], t.leader_depth[k], t.leader_tilt[k], t.follower_depth[k]});
    }
  }
}

void plotCases(const std::vector<const PushingCase*>& cases, const std::string& path, const std::string& title) {
  SvgFigure fig(title);
  for (const PushingCase* pc : cases) {
    const PushTrial& t = pc->trials.front();
    SvgPanel& P = fig.panel(pc->setup.object.name, "y (mm)", "z (mm)");
    const PrismSurface prism = makePrism(pc->setup.object);
    const auto outline = prism.outline().front();
    auto drawObject = [&](const Vec3& yzth, const std::string& colour, bool dashed) {
      const SE3d X = objectPose(yzth);
      std::vector<Vec2> pts;
      for (const auto& q : outline) {
        const Vec3 p = X * q;
        pts.emplace_back(p.y(), p.z());
      }
      P.line(pts, colour, 1.5, dashed);
    };
    // The start pose is the one before the first step: rebuild from the first logged pose is
    // close enough for a drawing (the object moves < 1 mm in one step).
    drawObject(t.object_path.front(), "#888", true);
    drawObject(t.object_path.back(), "#2060c0", false);
    std::vector<Vec2> sp, fp;
    for (const auto& s : t.sensor_path) sp.emplace_back(s.y(), s.z());
    for (const auto& s : t.follower_path) fp.emplace_back(s.y(), s.z());
    P.line(sp, "#d62728", 1.5, false, "leader sensor");
    if (!fp.empty()) P.line(fp, "#2ca02c", 1.5, false, "follower sensor");
    P.marker(pc->setup.target, 20, "#d62728", false);
    P.marker(pc->setup.target, 3, "#d62728", true);
  }
  fig.write(path, 360);
}

}  // namespace

PushingResult runSingleArmPushing(const TaskOptions& opt, int trials) {
  PushingResult res;
  for (const SupportSurface& s : {foamSurface(), mdfSurface()}) {
    std::vector<const PushingCase*> fig;
    for (const PushObject& o : shortObjects()) {
      PushingSetup su;
      su.object = o;
      su.surface = s;
      res.cases.push_back(runPushingCase(su, opt, trials));
    }
    if (!opt.out_dir.empty()) {
      makeDirectories(opt.out_dir);
      for (std::size_t i = res.cases.size() - 4; i < res.cases.size(); ++i) {
        fig.push_back(&res.cases[i]);
        std::string stem = "pushing_single_" + s.name + "_" + res.cases[i].setup.object.name;
        std::replace(stem.begin(), stem.end(), ' ', '_');
        writeCase(res.cases[i], opt.out_dir, stem);
      }
      plotCases(fig, detail::join(opt.out_dir, "pushing_single_" + s.name + ".svg"),
                "Single-arm pushing on " + s.name + " (trial 1; target: red circle; start dashed, end solid)");
    }
  }
  for (const auto& c : res.cases) {
    res.failures.insert(res.failures.end(), c.failures.begin(), c.failures.end());
    res.notes.insert(res.notes.end(), c.notes.begin(), c.notes.end());
  }
  res.success = res.failures.empty();
  return res;
}

PushingResult runDualArmPushing(const TaskOptions& opt, int trials) {
  PushingResult res;
  struct Group {
    SupportSurface s;
    bool tall;
    std::string stem;
  };
  for (const Group& g : {Group{foamSurface(), false, "short_foam"}, Group{mdfSurface(), false, "short_MDF"},
                         Group{mdfSurface(), true, "tall_MDF"}}) {
    std::vector<const PushingCase*> fig;
    for (const PushObject& o : g.tall ? tallObjects() : shortObjects()) {
      PushingSetup su;
      su.object = o;
      su.surface = g.s;
      su.dual_arm = true;
      su.tall = g.tall;
      res.cases.push_back(runPushingCase(su, opt, trials));
    }
    if (!opt.out_dir.empty()) {
      makeDirectories(opt.out_dir);
      for (std::size_t i = res.cases.size() - 4; i < res.cases.size(); ++i) {
        fig.push_back(&res.cases[i]);
        std::string stem = "pushing_dual_" + g.stem + "_" + res.cases[i].setup.object.name;
        std::replace(stem.begin(), stem.end(), ' ', '_');
        writeCase(res.cases[i], opt.out_dir, stem);
      }
      plotCases(fig, detail::join(opt.out_dir, "pushing_dual_" + g.stem + ".svg"),
                std::string("Dual-arm pushing, ") + (g.tall ? "tall objects" : "short objects") + " on " + g.s.name +
                    " (trial 1; leader red, follower green)");
    }
  }
  for (const auto& c : res.cases) {
    res.failures.insert(res.failures.end(), c.failures.begin(), c.failures.end());
    res.notes.insert(res.notes.end(), c.notes.begin(), c.notes.end());
  }
  res.success = res.failures.empty();
  return res;
}

}  // namespace lieservo::sim

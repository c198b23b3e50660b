// The pushing cases' verdicts (docs/simulation.md, "Success criteria"), their per-step logs
// (CSV) and their figures (SVG): the paths of trial 1, the opposition of the round objects.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "task_common.hpp"

namespace lieservo::sim {

PushVerdict judgeTrial(const PushingSetup& setup, const PushTrial& t) {
  PushVerdict v;
  v.reached = t.terminated && !t.toppled && !t.passed_target;
  v.within_error = v.reached && t.target_error <= Bounds::pushing_error_max;
  v.contact_kept = t.contact_kept;
  if (setup.dual_arm) {
    v.follower_contact_kept = t.follower_contact_kept;
    v.upright = t.max_tilt <= Bounds::upright_tilt_max;
    v.opposed = t.min_opposition >= Bounds::opposition_min;
  }
  return v;
}

PushingCase detail::judgeCase(const PushingSetup& setup, std::vector<PushTrial> trials, bool judged, const TaskOptions& opt) {
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
    std::snprintf(start, sizeof start, " (start: offset %+.1f mm, yaw %+.1f deg)", t.start_offset, rad2deg(t.start_yaw));
    auto fail = [&](const std::string& why) {
      pc.failures.push_back(tag + " trial " + std::to_string(i + 1) + ": " + why + start);
    };
    const PushVerdict verdict = judgeTrial(setup, t);
    if (t.toppled) {
      std::snprintf(buf, sizeof buf, "toppled (tilt %.0f deg > %.0f deg)", t.max_tilt, Bounds::topple_tilt);
      fail(buf);
    } else if (t.passed_target) {
      std::snprintf(buf, sizeof buf, "passed the target at %.0f mm without reaching it (termination within %.0f mm)",
                    t.closest_approach, opt.contact.tip_radius);
      fail(buf);
    } else if (!verdict.reached) {
      std::snprintf(buf, sizeof buf, "target not reached in %.0f s (final distance %.0f mm)", setup.timeout,
                    t.final_distance);
      fail(buf);
    } else if (!verdict.within_error) {
      std::snprintf(buf, sizeof buf, "target error %.1f mm > %.0f mm", t.target_error, Bounds::pushing_error_max);
      fail(buf);
    }
    if (!verdict.contact_kept) fail("pusher lost contact");
    if (!verdict.follower_contact_kept) {
      std::snprintf(buf, sizeof buf, "follower out of contact for %.0f%% of the push",
                    100.0 * (1.0 - t.follower_contact_fraction));
      fail(buf);
    }
    if (!verdict.upright) {
      std::snprintf(buf, sizeof buf, "object tilted %.1f deg > %.0f deg", t.max_tilt, Bounds::upright_tilt_max);
      fail(buf);
    }
    if (!verdict.opposed) {
      std::snprintf(buf, sizeof buf, "opposition lost: the contact normals %.0f deg apart (< %.0f deg)",
                    t.min_opposition, Bounds::opposition_min);
      fail(buf);
    }
  }
  pc.success = pc.failures.empty();
  return pc;
}

void detail::writeCase(const PushingCase& pc, const std::string& dir, const std::string& stem) {
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
      csv.row({double(i + 1), double(k), s.x(), s.y(), f.x(), f.y(), o.x(), o.y(), rad2deg(o.z()), t.object_tilt[k],
               t.bearing[k], t.alignment_velocity[k], t.leader_depth[k], t.leader_tilt[k], t.follower_depth[k],
               opposition});
    }
  }
}

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

}  // namespace lieservo::sim

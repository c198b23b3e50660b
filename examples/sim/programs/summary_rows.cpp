#include "summary_rows.hpp"

#include <cmath>
#include <cstdio>
#include <string>

namespace lieservo::sim::programs {

namespace {

std::string pm(double m, double s) {
  char b[64];
  if (std::isnan(m)) return "-";
  std::snprintf(b, sizeof b, "%.2f ± %.2f", m, s);
  return b;
}

std::string meanMax(const Stat& s) {
  char b[64];
  std::snprintf(b, sizeof b, "%.2f / %.2f", s.mean, s.max);
  return b;
}

// "blue square, foam (mm) [reached 5/5, contact 5/5, ...]"
std::string caseLabel(const PushingCase& c) {
  const int n = int(c.trials.size());
  int leader = 0, upright = 0;
  for (const auto& t : c.trials) leader += t.contact_kept, upright += t.max_tilt <= Bounds::upright_tilt_max;
  char b[200];
  if (c.setup.dual_arm)
    std::snprintf(b, sizeof b, " [reached %d/%d, contact %d/%d, follower %d/%d, upright %d/%d, opposition >= %.0f deg]",
                  c.reached_trials, n, leader, n, c.follower_kept_trials, n, upright, n, c.min_opposition);
  else
    std::snprintf(b, sizeof b, " [reached %d/%d, contact %d/%d]", c.reached_trials, n, leader, n);
  return displayName(c.setup.object) + ", " + c.setup.surface.name + " (mm)" + b + (c.judged ? "" : " (reported)");
}

std::string height(double h) {
  char b[32];
  if (std::isinf(h)) return "above the top";
  std::snprintf(b, sizeof b, "%.0f mm", h);
  return b;
}

}  // namespace

void addTrackingRows(const TrackingResult& tr, std::vector<Row>& rows) {
  for (const TrackingSegment* s : {&tr.single_axis, &tr.periodic}) {
    rows.push_back({"tracking", s->name + ": depth err mean/max (mm)", meanMax(s->depth_error),
                    "qualitative (6 mm ref)", tr.success});
    rows.push_back({"tracking", s->name + ": angle from normal mean/max (deg)", meanMax(s->tilt), "qualitative",
                    tr.success});
    rows.push_back({"tracking", s->name + ": gamma twist mean/max (deg)", meanMax(s->twist), "-", true, false});
    rows.push_back({"tracking", s->name + ": contact kept", s->contact_kept ? "yes" : "NO", "yes", s->contact_kept});
  }
}

void addFollowingRows(const FollowingResult& fr, std::vector<Row>& rows) {
  char buf[160];
  for (const FollowingPath* p : {&fr.ramp, &fr.dome_pooled}) {
    rows.push_back({"following", p->name + ": depth err mean/max (mm)", meanMax(p->depth_error),
                    "qualitative (3 mm ref)", fr.success});
    rows.push_back({"following", p->name + ": angle from normal mean/max (deg)", meanMax(p->tilt), "qualitative",
                    fr.success});
    std::snprintf(buf, sizeof buf, "%.0f mm, %s", p->distance, p->contact_kept ? "contact kept" : "CONTACT LOST");
    rows.push_back({"following", p->name + ": path length", buf, "-", p->contact_kept && p->reached_end});
  }
}

void addPushingRows(const PushingResult& r, const char* task, std::vector<Row>& rows) {
  for (const auto& c : r.cases) {
    const PaperValue pv = paperValue(c);
    rows.push_back({task, caseLabel(c), pm(c.mean_error, c.sd_error), pm(pv.mean, pv.sd), c.success || !c.judged,
                    c.judged});
  }
}

void addTallPushRows(const PushingResult& r, std::vector<Row>& rows) {
  char buf[64];
  for (const auto& c : r.cases) {
    std::snprintf(buf, sizeof buf, "%d of %d toppled", c.toppled_trials, int(c.trials.size()));
    rows.push_back({"1-arm tall push", displayName(c.setup.object) + ", foam (reported)", buf, "topples", true, false});
  }
}

void addToppleRows(const std::vector<ToppleRow>& table, std::vector<Row>& rows) {
  char buf[160], statics[64];
  for (const ToppleRow& r : table) {
    const bool above = std::isinf(r.statics_height) && std::isinf(r.engine_height);
    const bool agree = (above || std::abs(r.engine_height / r.statics_height - 1) <= 0.1) &&
                       std::abs(r.engine_friction / r.statics_friction - 1) <= 0.1;
    std::snprintf(buf, sizeof buf, "%s / %.2f", height(r.engine_height).c_str(), r.engine_friction);
    std::snprintf(statics, sizeof statics, "statics %s / %.2f", height(r.statics_height).c_str(), r.statics_friction);
    rows.push_back({"toppling", displayName(r.object) + ": h* at mu_s 0.35 / mu_s* at h 45 mm, engine", buf, statics,
                    agree});
  }
}

}  // namespace lieservo::sim::programs

// Short seeded closed-loop runs of the four tasks: contact kept, target reached, errors under
// the bounds of docs/simulation.md ("Success criteria").  Duration scales with
// LIESERVO_SIM_TEST_SCALE (default 1, or 0.3 in Debug/sanitizer builds: see CMakeLists.txt).
// Below 0.5 the pushing tests run one push each towards a nearer target (170 mm away).
#include <cstdlib>

#include <catch2/catch.hpp>

#include "lieservo_sim/tasks.hpp"

using namespace lieservo::sim;

namespace {
#ifndef LIESERVO_SIM_TEST_DEFAULT_SCALE
#define LIESERVO_SIM_TEST_DEFAULT_SCALE 1.0
#endif
double scale() {
  const char* s = std::getenv("LIESERVO_SIM_TEST_SCALE");
  const double v = s ? std::atof(s) : LIESERVO_SIM_TEST_DEFAULT_SCALE;
  return v > 0 ? v : 1.0;
}
bool reduced() { return scale() < 0.5; }
void shorten(PushingSetup& s) {
  if (reduced()) s.target = Vec2(-100, 180);  // 170 mm from the start instead of 400 mm
}
std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += x + "\n";
  return s;
}
}  // namespace

TEST_CASE("task (a): object tracking keeps contact at the reference depth", "[sim][task]") {
  TaskOptions o;
  o.seed = 3;
  o.duration_scale = 0.25 * scale();
  const TrackingResult r = runObjectTracking(o);
  INFO(joined(r.failures));
  CHECK(r.success);
  CHECK(r.single_axis.contact_kept);
  CHECK(r.periodic.contact_kept);
  CHECK(r.single_axis.depth_error.mean < Bounds::tracking_depth_mean);
  CHECK(r.single_axis.tilt.max < Bounds::tracking_tilt_max);
  CHECK(r.sim_time > (reduced() ? 20.0 : 40.0));
}

TEST_CASE("task (b): surface following on the ramp and the dome", "[sim][task]") {
  TaskOptions o;
  o.seed = 5;
  o.duration_scale = 0.3 * scale();
  const FollowingResult r = runSurfaceFollowing(o);
  INFO(joined(r.failures));
  CHECK(r.success);
  CHECK(r.ramp.reached_end);
  CHECK(r.ramp.contact_kept);
  CHECK(r.dome.size() == 8);
  CHECK(r.dome_pooled.contact_kept);
  CHECK(r.ramp.depth_error.max < Bounds::following_depth_max);
  CHECK(r.dome_pooled.tilt.mean < Bounds::following_tilt_mean);
}

TEST_CASE("task (c): single-arm pushing reaches the target", "[sim][task]") {
  TaskOptions o;
  o.seed = 11;
  PushingSetup s;
  s.object = shortObjects()[0];  // large square
  s.surface = SupportSpec::mdf();
  shorten(s);
  const PushTrial t = runPushTrial(s, o, 1);
  CHECK(t.terminated);
  CHECK(t.contact_kept);
  CHECK(t.target_error < Bounds::pushing_error_max);
  CHECK(t.final_distance < 21);
  if (reduced()) return;
  PushingSetup c = s;
  c.object = shortObjects()[1];  // circle
  c.surface = SupportSpec::foam();
  const PushTrial tc = runPushTrial(c, o, 2);
  CHECK(tc.terminated);
  CHECK(tc.contact_kept);
  CHECK(tc.target_error < Bounds::pushing_error_max);
}

// KNOWN FAILURE, marked [!shouldfail] so that CI stays green while it fails and goes red when
// it starts to pass (then remove the tag): on MuJoCo the paper's dual-arm configuration loses
// the leader's contact (docs/simulation.md, "Open problems: dual-arm pushing on MuJoCo").
TEST_CASE("task (d): dual-arm pushing keeps both contacts", "[sim][task][!shouldfail]") {
  TaskOptions o;
  o.seed = 13;
  PushingSetup s;
  s.object = shortObjects()[2];  // small square
  s.surface = SupportSpec::mdf();
  s.dual_arm = true;
  shorten(s);
  const PushTrial t = runPushTrial(s, o, 1);
  CHECK(t.terminated);
  CHECK(t.contact_kept);
  CHECK(t.follower_contact_kept);
  CHECK(t.max_tilt < Bounds::upright_tilt_max);
  CHECK(t.target_error < Bounds::pushing_error_max);
  if (reduced()) return;
  PushingSetup tall = s;
  tall.object = tallObjects()[0];
  tall.tall = true;
  const PushTrial tt = runPushTrial(tall, o, 2);
  CHECK(tt.terminated);
  CHECK(tt.contact_kept);
  CHECK(tt.follower_contact_kept);
  CHECK(tt.max_tilt < Bounds::upright_tilt_max);
  CHECK(tt.target_error < Bounds::pushing_error_max);
}

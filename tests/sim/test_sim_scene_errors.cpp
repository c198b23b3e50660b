// Bad scene configuration → lieservo::sim::SceneError at set-up, with a clear message.
#include <catch2/catch.hpp>

#include "lieservo_sim/contact_model.hpp"
#include "lieservo_sim/observation_model.hpp"
#include "lieservo_sim/simulated_arm.hpp"
#include "lieservo_sim/tasks.hpp"

using namespace lieservo::sim;
using Catch::Matchers::Contains;

TEST_CASE("scene errors: surfaces", "[sim][errors]") {
  CHECK_THROWS_WITH(SphereSurface(0), Contains("SphereSurface radius"));
  CHECK_THROWS_WITH(SphereSurface(std::nan("")), Contains("finite"));
  CHECK_THROWS_WITH(PlaneSurface(-1), Contains("half_extent"));
  CHECK_THROWS_WITH(RampSurface(80, 50), Contains("too sharply curved"));
  CHECK_THROWS_WITH(PrismSurface::polygon({Vec2(0, 0), Vec2(1, 0)}, 10, "x"), Contains("at least 3"));
  CHECK_THROWS_WITH(
      PrismSurface::polygon({Vec2(-1, -1), Vec2(1, -1), Vec2(0, -0.5), Vec2(1, 1), Vec2(-1, 1)}, 10, "x"),
      Contains("convex"));
  CHECK_THROWS_WITH(PrismSurface::polygon({Vec2(-1, -1), Vec2(-1, 1), Vec2(1, 1), Vec2(1, -1)}, 10, "cw"),
                    Contains("counter-clockwise"));
  CHECK_THROWS_WITH(PrismSurface::polygon({Vec2(1, 1), Vec2(3, 1), Vec2(2, 3)}, 10, "off"), Contains("origin"));
  CHECK_THROWS_WITH(PrismSurface::regularPolygon(2, 10, 10, "x"), Contains(">= 3"));
  CHECK_THROWS_AS(PrismSurface::circle(-5, 10, "x"), SceneError);
}

TEST_CASE("scene errors: contact, arm, observation, task options", "[sim][errors]") {
  PlaneSurface plane;
  ContactParams p;
  p.tip_radius = 0;
  CHECK_THROWS_WITH(ContactModel(plane, p), Contains("tip_radius"));
  p = ContactParams{};
  p.min_slip_radius = 6;
  CHECK_THROWS_WITH(ContactModel(plane, p), Contains("min_slip_radius"));
  ArmLimits l;
  l.substeps = 0;
  CHECK_THROWS_WITH(SimulatedArm(SE3d::identity(), l), Contains("substeps"));
  l = ArmLimits{};
  l.max_linear_speed = -1;
  CHECK_THROWS_WITH(SimulatedArm(SE3d::identity(), l), Contains("max_linear_speed"));
  SE3d bad = SE3d::identity();
  bad.translation() = Vec3(std::nan(""), 0, 0);
  CHECK_THROWS_WITH(SimulatedArm(bad), Contains("non-finite"));
  CHECK_THROWS_WITH(GdnCalibration::fromValues(Vec6::Zero(), "zero"), Contains("mae"));
  TaskOptions o;
  o.control_rate = 0;
  CHECK_THROWS_WITH(runObjectTracking(o), Contains("control_rate"));
  o = TaskOptions{};
  o.duration_scale = -1;
  CHECK_THROWS_WITH(runSurfaceFollowing(o), Contains("duration_scale"));
}

TEST_CASE("scene errors: pushing set-up", "[sim][errors]") {
  PushingSetup s;
  s.object = shortObjects()[0];
  s.surface = SupportSpec::mdf();
  s.sensor_height = 100;  // above the 60 mm prism
  CHECK_THROWS_WITH(s.validate(), Contains("sensor_height"));
  s.sensor_height = 45;
  s.object.shape = "triangle";
  CHECK_THROWS_WITH(s.validate(), Contains("shape"));
  s.object.shape = "square";
  s.object.mass = 0;
  CHECK_THROWS_WITH(s.validate(), Contains("mass"));
  s.object.mass = 0.4;
  s.target = s.start;
  CHECK_THROWS_WITH(s.validate(), Contains("target"));
  s.target = Vec2(0, 375);
  CHECK_NOTHROW(s.validate());
  CHECK_THROWS_WITH(runPushingCase(s, TaskOptions{}, 0), Contains("trials"));
}

// Bad scene configuration → lieservo::sim::SceneError at set-up, with a clear message.
#include <limits>

#include <catch2/catch.hpp>

#include "lieservo_sim/contact_model.hpp"
#include "lieservo_sim/observation_model.hpp"
#include "lieservo_sim/sensor_arm.hpp"
#include "lieservo_sim/tasks.hpp"

using namespace lieservo::sim;
using Catch::Matchers::Contains;

TEST_CASE("scene errors: contact, arm, observation, task options", "[sim][errors]") {
  ContactParams p;
  p.tip_radius = 0;
  CHECK_THROWS_WITH(ContactModel(p), Contains("tip_radius"));
  p = ContactParams{};
  p.min_slip_radius = 6;
  CHECK_THROWS_WITH(ContactModel(p), Contains("min_slip_radius"));
  mujoco::SceneSpec scene;
  scene.sensors.push_back({});
  mujoco::World world(scene);
  ArmLimits l;
  l.max_linear_speed = -1;
  CHECK_THROWS_WITH(MujocoSensorArm(world, 0, l), Contains("max_linear_speed"));
  CHECK_THROWS_WITH(MujocoSensorArm(world, 1), Contains("no sensor 1"));
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
  // A fixed start placement or friction must be one a person could set up; NaN means drawn.
  TaskOptions o;
  for (const double bad : {60.0, -51.0, std::numeric_limits<double>::infinity()}) {
    o.start_offset = bad;
    CHECK_THROWS_WITH(runPushTrial(s, o, 1), Contains("start_offset"));
  }
  o = TaskOptions{};
  o.start_yaw = deg2rad(50);
  CHECK_THROWS_WITH(runPushTrial(s, o, 1), Contains("start_yaw"));
  o = TaskOptions{};
  for (const double bad : {0.0, -1.0, 3.5, std::numeric_limits<double>::infinity()}) {
    o.support_friction_scale = bad;
    CHECK_THROWS_WITH(runPushTrial(s, o, 1), Contains("support_friction_scale"));
  }
}

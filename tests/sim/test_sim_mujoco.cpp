// The MuJoCo world (examples/sim mujoco_world.hpp) against hand calculations: a pushed box
// slides when the push exceeds μ m g and not before; a tall box topples when pushed above its
// tipping height and not below; the tip's contact depth and the gel's force per mm; the
// fixtures (dome, curved ramp, carried plate) against their analytic surfaces; the sensor arm's
// twist integration; bad scene input named in the error.
// Bounds are written from the hand calculations before running.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <lieservo_sim/mujoco_world.hpp>
#include <lieservo_sim/contact_model.hpp>
#include <lieservo_sim/sensor_arm.hpp>
#include <lieservo_sim/tasks.hpp>

using namespace lieservo::sim;
using namespace lieservo::sim::mujoco;
using lieservo::Status;

namespace {
constexpr double g = 9.81;

SceneSpec oneBox(double support_mu, double side, double height, double mass) {
  SceneSpec s;
  s.support = {"test", support_mu};
  ObjectSpec o;
  o.name = "box";
  o.shape = "square";
  o.size = side;
  o.height = height;
  o.mass = mass;
  s.objects.push_back(o);
  return s;
}

// Holds a horizontal force (N, along +x) at height h (mm) on the box's −x face for t seconds.
void push(World& w, double force, double h, double t) {
  const double dt = 0.01;
  for (double time = 0; time < t; time += dt) {
    const lieservo::SE3<double> X = w.objectPose(0);
    const Vec3 face = X.rotationMatrix() * Vec3(-w.spec().objects[0].size / 2, 0, h) + X.translation();
    w.applyObjectForce(0, Vec3(force, 0, 0), face);
    REQUIRE(w.step(dt) == Status::ok);
  }
  w.clearForces();
}
}  // namespace

TEST_CASE("mujoco: a box slides when the push exceeds mu m g, and not before", "[sim][mujoco]") {
  const double mu = 0.35, m = 0.5, side = 100;
  const double limit = mu * m * g;  // 1.72 N
  {
    World w(oneBox(mu, side, 60, m));
    push(w, 0.8 * limit, 30, 1.0);
    // Static friction holds: no more than 0.5 mm of creep in 1 s.
    CHECK(w.objectPose(0).translation().head<2>().norm() < 0.5);
  }
  {
    World w(oneBox(mu, side, 60, m));
    const double F = 1.5 * limit, t = 0.5;
    push(w, F, 30, t);
    // Sliding: x = ½ (F − μ m g)/m t² = 215 mm; within 25 % (contact softness, start-up).
    const double expected = 0.5 * (F - limit) / m * t * t * 1e3;
    CHECK(w.objectPose(0).translation()[0] == Approx(expected).epsilon(0.25));
    CHECK(w.objectTilt(0) < lieservo::sim::deg2rad(2));
  }
}

TEST_CASE("mujoco: a sliding tip drags a box by friction when mu_c N exceeds mu_s (m g + N), and not when below",
          "[sim][mujoco]") {
  // A tip pressed 3 mm into the top of a 0.3 kg box (N ≈ k_gel · 3 mm = 3 N at 1 N/mm) moves sideways
  // at 10 mm/s for 2 s. The box slides on the support once the tangential force exceeds
  // μ_s (m g + N) = 0.1 · 5.9 N = 0.59 N; the tip can give up to μ_c N: 2.4 N at μ_c = 0.8
  // (it sticks and drags the box along), 0.3 N at μ_c = 0.1 (it slides over the box, which
  // stays). A tip whose motion the solver did not see (a teleported body) slides over the box
  // with a small, velocity-dependent force whatever μ_c is.
  auto run = [](double mu_c) {
    SceneSpec s = oneBox(0.1, 100, 60, 0.3);
    s.objects[0].friction = mu_c;
    SensorSpec tip;
    tip.name = "tip";
    tip.gel_stiffness = 1.0;
    // z_s down into the top face, x_s along x, y_s = z_s × x_s = −y.
    Mat3 R;
    R << 1, 0, 0, 0, -1, 0, 0, 0, -1;
    tip.initial_pose = makePose(R, Vec3(0, 0, 60 + 20 - 3));
    s.sensors.push_back(tip);
    World w(s);
    REQUIRE(w.step(0.2) == Status::ok);  // the gel settles at its preload
    CHECK(w.tipNormalForce(0) == Approx(3.0).epsilon(0.15));  // the tip's weight is the arm's
    Vec6 u;
    u << 0, -10, 0, 0, 0, 0;  // along −y_s = +y_w, mm/s
    REQUIRE(w.setSensorTwist(0, u) == Status::ok);
    REQUIRE(w.step(2.0) == Status::ok);
    CHECK(w.sensorPose(0).translation().y() == Approx(20).margin(1e-6));
    return w.objectPose(0).translation().y();
  };
  CHECK(run(0.8) > 16.0);  // dragged: at least 80 % of the tip's 20 mm
  CHECK(std::abs(run(0.1)) < 0.5);
}

TEST_CASE("mujoco: a tall box topples when pushed above its tipping height, and not below", "[sim][mujoco]") {
  // Tall red square of the paper: side 75 mm, 120 mm tall, 0.324 kg; support friction high
  // enough that the box cannot slide under the push (F < μ m g).
  const double mu = 0.8, m = 0.324, side = 75, height = 120;
  const double F = 0.6 * mu * m * g;
  const double h_tip = m * g * side / 2 / F;  // F h = m g w/2: 78 mm
  {
    World w(oneBox(mu, side, height, m));
    push(w, F, 0.75 * h_tip, 1.0);
    CHECK(w.objectTilt(0) < lieservo::sim::deg2rad(2));
    CHECK(w.objectPose(0).translation().head<2>().norm() < 1.0);
  }
  {
    World w(oneBox(mu, side, height, m));
    push(w, F, 1.25 * h_tip, 1.0);
    REQUIRE(w.step(1.0) == Status::ok);
    CHECK(w.objectTilt(0) > lieservo::sim::deg2rad(60));  // fallen over
  }
}

TEST_CASE("mujoco: tip depth from MuJoCo's geometry, and the gel force per mm", "[sim][mujoco]") {
  for (const double m : {0.3, 0.6}) {
    for (const double depth : {1.0, 3.0, 6.0}) {
      // A box held by friction (μ 2: μ m g ≥ 5.9 N, above the gel force at 6 mm), the tip
      // pressing its −x face at mid-height.
      SceneSpec s = oneBox(2.0, 100, 60, m);
      SensorSpec tip;
      tip.name = "tip";
      const double x_tip = -50 - 20 + depth;
      Mat3 R;  // z_s along +x into the face, x_s down, y_s = z_s × x_s = +y
      R << 0, 0, 1, 0, 1, 0, -1, 0, 0;
      tip.initial_pose = makePose(R, Vec3(x_tip, 0, 30));
      s.sensors.push_back(tip);
      World w(s);
      REQUIRE(w.step(1.0) == Status::ok);
      const TipGeometry geo = w.tipGeometry(0);
      REQUIRE(geo.valid);
      CHECK(geo.object == 0);
      // The −x face of the box at its actual pose (the push tilts it slightly on the soft
      // support): outward normal n, a point p0 on it. Depth = R − n·(c − p0).
      const lieservo::SE3<double> X = w.objectPose(0);
      const Vec3 n = X.rotationMatrix() * Vec3(-1, 0, 0);
      const Vec3 p0 = X.translation() + X.rotationMatrix() * Vec3(-50, 0, 30);
      const Vec3 c(x_tip, 0, 30);
      CHECK(geo.normal_w.isApprox(n, 1e-9));
      CHECK(geo.depth == Approx(20 - n.dot(c - p0)).margin(1e-6));
      CHECK(n.dot(geo.point_w - p0) == Approx(0).margin(1e-6));  // on the face
      // The gel: F/depth = k_gel within 15 % (SensorSpec::gel_stiffness), whatever the mass.
      INFO("mass " << m << " commanded depth " << depth << " measured depth " << geo.depth);
      CHECK(geo.depth > 0.5 * depth);
      CHECK(w.tipNormalForce(0) / geo.depth == Approx(tip.gel_stiffness).epsilon(0.15));
    }
  }
}

TEST_CASE("mujoco: tip geometry on every object shape (box, rectangle, cylinder, hexagon mesh)", "[sim][mujoco]") {
  // A sensor whose axis points at the object's +x side at 35 mm height, its nominal tip 2 mm
  // inside the surface. The reported point must lie on that side (box faces and the hexagon's
  // face are at x = half extent; the cylinder's side at radius r), the normal along +x and
  // depth = R − distance of the tip centre from that point. Bounds: 1e-3 mm; the normal to
  // 1e-9 for boxes (MuJoCo's analytic sphere–box) and 1e-4 rad for the cylinder and the mesh,
  // which go through MuJoCo's iterative convex collider (MPR, run to 1e-10 m here; the mesh's
  // normal came out 1.7e-5 rad off).
  // Tall cylinders and hexagons touched low (the 290 mm glass bottle, the 120 mm hexagon, both
  // at 35 mm), and the 60 mm short circle touched at 35 mm, with the same bounds: their
  // collision segments are centred on the contact height (ObjectSpec::contact_height).
  struct Shape {
    const char* name;
    const char* shape;
    double size, size2, height;
  };
  for (const Shape& sh : {Shape{"box", "square", 100, 0, 80}, Shape{"rect", "rectangle", 58, 95, 80},
                          Shape{"cyl", "circle", 37, 0, 80}, Shape{"hex", "hexagon", 50, 0, 80},
                          Shape{"bottle", "circle", 37, 0, 290}, Shape{"tallhex", "hexagon", 50, 0, 120},
                          Shape{"short", "circle", 50, 0, 60}}) {
    SceneSpec s;
    s.support = {"test", 2.0};
    ObjectSpec o;
    o.name = sh.name;
    o.shape = sh.shape;
    o.size = sh.size;
    o.size2 = sh.size2;
    o.height = sh.height;
    o.contact_height = 35;
    o.mass = 0.4;
    s.objects.push_back(o);
    const double a = halfExtentX(o);
    SensorSpec tip;
    tip.name = "tip";
    const double depth = 2.0;
    // z_s along −x (into the +x side), x_s up, y_s = z_s × x_s.
    tip.initial_pose = makePose(fromColumns(Vec3::UnitZ(), -Vec3::UnitX().cross(Vec3::UnitZ()), -Vec3::UnitX()),
                                Vec3(a + 20 - depth, 0, 35));
    s.sensors.push_back(tip);
    World w(s);
    const TipGeometry geo = w.tipGeometry(0);  // before any step: the object is where it was put
    INFO(sh.name);
    REQUIRE(geo.valid);
    INFO("normal " << geo.normal_w.transpose());
    const bool analytic = std::string(sh.shape) == "square" || std::string(sh.shape) == "rectangle";
    CHECK((geo.normal_w - Vec3::UnitX()).norm() < (analytic ? 1e-9 : 1e-4));
    CHECK(geo.point_w.x() == Approx(a).margin(1e-3));
    CHECK(geo.point_w.y() == Approx(0).margin(1e-3));
    CHECK(geo.point_w.z() == Approx(35).margin(1e-3));
    CHECK(geo.depth == Approx(depth).margin(1e-3));
  }
}

namespace {
// A sensor whose axis points along −n at the surface point p, its nominal tip `depth` inside.
SensorSpec tipAt(const Vec3& p, const Vec3& n, double depth) {
  SensorSpec tip;
  tip.name = "tip";
  const Vec3 z = -n, x = z.unitOrthogonal();
  tip.initial_pose = makePose(fromColumns(x, z.cross(x), z), p + (20 - depth) * n);
  return tip;
}
}  // namespace

TEST_CASE("mujoco: fixtures against their analytic surfaces (dome, curved ramp)", "[sim][mujoco]") {
  // Dome: MuJoCo's analytic sphere–sphere, so point, normal and depth to rounding (1e-9).
  const double a = 80;
  for (const double theta : {0.0, 30.0, 50.0, 80.0}) {
    SceneSpec s;
    FixtureSpec dome;
    dome.name = "dome";
    dome.shape = "dome";
    dome.size = a;
    s.fixtures = {dome};
    const Vec3 u(std::sin(deg2rad(theta)) * std::cos(1.0), std::sin(deg2rad(theta)) * std::sin(1.0), std::cos(deg2rad(theta)));
    s.sensors = {tipAt(a * u, u, 3.0)};
    World w(s);
    const TipGeometry geo = w.tipGeometry(0);
    INFO("theta " << theta);
    REQUIRE(geo.valid);
    CHECK(geo.fixture == 0);
    CHECK(geo.object == -1);
    CHECK((geo.normal_w - u).norm() < 1e-9);
    CHECK((geo.point_w - a * u).norm() < 1e-6);
    CHECK(geo.depth == Approx(3.0).margin(1e-6));
  }
  // Ramp (H 40, L 200, 100 chords): the tip 3 mm into the cosine profile at points on the flat
  // top, the convex part, the inflection, the concave part and the flat bottom. The chords sit
  // within H π² L / (16 · 100²) = 5 µm of the arc (bound 0.02 mm on depth and point) and their
  // normals turn by h''_max L / 100 = 0.0099 rad from one chord to the next (bound 0.006 rad:
  // half a step, with margin).
  FixtureSpec ramp;
  ramp.name = "ramp";
  ramp.shape = "ramp";
  ramp.size = 40;
  ramp.size2 = 200;
  for (const double y : {-20.0, 30.0, 100.0, 137.0, 170.0, 230.0}) {
    const double h = rampHeight(ramp, y);
    const double slope = (y <= 0 || y >= 200) ? 0.0 : -40 * lieservo::sim::kPi / 400 * std::sin(lieservo::sim::kPi * y / 200);
    const Vec3 n = Vec3(0, -slope, 1).normalized();
    SceneSpec s;
    s.fixtures = {ramp};
    s.sensors = {tipAt(Vec3(5, y, h), n, 3.0)};
    World w(s);
    const TipGeometry geo = w.tipGeometry(0);
    INFO("y " << y << " normal " << geo.normal_w.transpose() << " point " << geo.point_w.transpose());
    REQUIRE(geo.valid);
    CHECK(geo.fixture == 0);
    CHECK(std::acos(std::min(1.0, geo.normal_w.dot(n))) < 0.006);
    CHECK((geo.point_w - Vec3(5, y, h)).norm() < 0.02 + 20 * 0.006);  // the normal's error moves the point
    CHECK(geo.depth == Approx(3.0).margin(0.02));
  }
}

TEST_CASE("mujoco: a carried plate follows its leader; fixed fixtures refuse; reset", "[sim][mujoco]") {
  SceneSpec s;
  FixtureSpec plate;
  plate.name = "plate";
  plate.carried = true;
  FixtureSpec dome;
  dome.name = "dome";
  dome.shape = "dome";
  dome.size = 50;
  dome.pose = makePose(Mat3::Identity(), Vec3(500, 0, 0));
  s.fixtures = {plate, dome};
  s.sensors = {tipAt(Vec3::Zero(), Vec3::UnitZ(), 2.0)};
  World w(s);
  TipGeometry geo = w.tipGeometry(0);
  REQUIRE(geo.valid);
  CHECK(geo.fixture == 0);
  CHECK(geo.depth == Approx(2.0).margin(1e-9));
  // The leader lifts the plate by 1.5 mm and tilts it by 10° about x through its centre.
  const SE3d X = makePose(rotX(deg2rad(10)), Vec3(0, 0, 1.5));
  REQUIRE(w.setFixturePose(0, X) == Status::ok);
  CHECK((w.fixturePose(0).translation() - X.translation()).norm() < 1e-9);
  CHECK((w.fixturePose(0).rotationMatrix() - X.rotationMatrix()).norm() < 1e-9);
  geo = w.tipGeometry(0);
  // Tip centre (0, 0, 18) against the plane through (0, 0, 1.5) with normal Rx(10°) z.
  const Vec3 n = rotX(deg2rad(10)).col(2);
  CHECK((geo.normal_w - n).norm() < 1e-9);
  CHECK(geo.depth == Approx(20 - n.dot(Vec3(0, 0, 18) - Vec3(0, 0, 1.5))).margin(1e-9));
  // A fixed fixture does not move; bad poses are refused; nothing changes.
  CHECK(w.setFixturePose(1, X) == Status::invalid_argument);
  CHECK(w.setFixturePose(2, X) == Status::invalid_argument);
  CHECK(w.setFixturePose(0, SE3d::fromMatrixUnchecked(2 * Eigen::Matrix4d::Identity())) == Status::not_orthonormal);
  CHECK((w.fixturePose(1).translation() - Vec3(500, 0, 0)).norm() < 1e-9);
  CHECK((w.fixturePose(0).translation() - X.translation()).norm() < 1e-9);
  // reset: back to the scene as built.
  REQUIRE(w.step(0.1) == Status::ok);
  w.reset();
  CHECK(w.fixturePose(0).translation().norm() < 1e-12);
  CHECK((w.sensorPose(0).translation() - s.sensors[0].initial_pose.translation()).norm() < 1e-9);
}

TEST_CASE("mujoco: the sensor arm integrates the body twist within its limits", "[sim][mujoco]") {
  SceneSpec s;
  SensorSpec tip;
  tip.name = "tip";
  tip.initial_pose = lieservo::SE3<double>(lieservo::SO3<double>::exp(Vec3(0, 0.5, 0)), Vec3(0, 0, 100));
  s.sensors.push_back(tip);
  World w(s);
  MujocoSensorArm arm(w, 0);
  lieservo::SE3<double>::Tangent u;
  u << 10, 0, 0, 0, 0, 0.1;  // mm/s, rad/s: well inside the limits
  for (int k = 0; k < 100; ++k) {
    REQUIRE(arm.commandVelocity(u, 0.01) == Status::ok);
    REQUIRE(w.step(0.01) == Status::ok);  // the world moves the sensor by the twist
  }
  // The acceleration limit ramps the first command: 10 mm/s reached within 0.01 s at
  // 1000 mm/s², so after 1 s the pose is X0 exp(u · 1 s) up to the ramp (≤ 0.01 s of motion).
  lieservo::SE3<double> X;
  REQUIRE(arm.readPose(X) == Status::ok);
  const lieservo::SE3<double> expected = tip.initial_pose * lieservo::SE3<double>::exp(u * 1.0);
  CHECK((X.translation() - expected.translation()).norm() < 0.11);
  // Limits: 1000 mm/s is clipped to 250 mm/s.
  u << 1000, 0, 0, 0, 0, 0;
  for (int k = 0; k < 100; ++k) REQUIRE(arm.commandVelocity(u, 0.01) == Status::ok);
  CHECK(arm.appliedTwist().head<3>().norm() == Approx(250));
  // stop() brings the sensor to rest: a step no longer moves it.
  arm.stop();
  REQUIRE(arm.readPose(X) == Status::ok);
  REQUIRE(w.step(0.01) == Status::ok);
  CHECK((arm.pose().translation() - X.translation()).norm() < 1e-12);
  // Bad commands change nothing.
  REQUIRE(arm.readPose(X) == Status::ok);
  CHECK(arm.commandVelocity(u, 0.0) == Status::invalid_time_step);
  u[0] = std::nan("");
  CHECK(arm.commandVelocity(u, 0.01) == Status::non_finite_input);
  lieservo::SE3<double> X2;
  REQUIRE(arm.readPose(X2) == Status::ok);
  CHECK(X2.matrix() == X.matrix());
}

TEST_CASE("mujoco: bad scene input names the parameter", "[sim][mujoco]") {
  auto throwsWith = [](const SceneSpec& s, const std::string& what) {
    try {
      World w(s);
    } catch (const SceneError& e) {
      INFO(e.what());
      CHECK(std::string(e.what()).find(what) != std::string::npos);
      return;
    }
    FAIL("no SceneError for " << what);
  };
  SceneSpec s = oneBox(0.35, 100, 60, 0.5);
  s.objects[0].size = 0;
  throwsWith(s, "size");
  s = oneBox(0.35, 100, 60, -1);
  throwsWith(s, "mass");
  s = oneBox(0.35, 100, -60, 0.5);
  throwsWith(s, "height");
  s = oneBox(-0.1, 100, 60, 0.5);
  throwsWith(s, "support friction");
  s = oneBox(0.35, 100, 60, 0.5);
  s.objects[0].shape = "teapot";
  throwsWith(s, "unknown shape 'teapot'");
  s.objects[0].shape = "rectangle";  // needs its second side
  throwsWith(s, "size2");
  s = oneBox(0.35, 100, 60, 0.5);
  s.objects[0].friction = -1;
  throwsWith(s, "friction");
  s = oneBox(0.35, 100, 60, 0.5);
  SensorSpec tip;
  tip.name = "box";
  s.sensors.push_back(tip);
  throwsWith(s, "duplicate name 'box'");
  s.sensors[0].name = "tip";
  s.sensors[0].initial_pose = lieservo::SE3<double>::fromMatrixUnchecked(2 * Eigen::Matrix4d::Identity());
  throwsWith(s, "initial_pose");
  s = SceneSpec{};
  FixtureSpec f;
  f.shape = "cone";
  s.fixtures = {f};
  throwsWith(s, "unknown shape 'cone'");
  s.fixtures[0] = FixtureSpec{};
  s.fixtures[0].size = -1;
  throwsWith(s, "fixture 'fixture' size");
  s.fixtures[0] = FixtureSpec{};
  s.fixtures[0].shape = "ramp";
  s.fixtures[0].segments = 0;
  throwsWith(s, "segments");
  s.fixtures[0] = FixtureSpec{};
  s.fixtures[0].friction = -0.1;
  throwsWith(s, "friction");
  s.fixtures[0] = FixtureSpec{};
  s.fixtures[0].pose = SE3d(s.fixtures[0].pose.so3(), Vec3(std::nan(""), 0, 0));
  throwsWith(s, "pose");
}

// ---- The distributed base contact (mujoco_world.hpp, basePoints) -------------------------------

TEST_CASE("mujoco: uniform-pressure radius of each base outline", "[sim][mujoco][base]") {
  // Exact: a square 0.3826 a (a (√2 + ln(1 + √2)) / 6), a disc 2R/3. The polygons' closed form
  // against a Monte Carlo integral over the outline (10⁵ seeded points, bound 1 %).
  ObjectSpec sq;
  sq.shape = "square", sq.size = 100;
  CHECK(uniformPressureRadius(sq) == Approx(100 * (std::sqrt(2.0) + std::log(1 + std::sqrt(2.0))) / 6).epsilon(1e-12));
  ObjectSpec disc;
  disc.shape = "circle", disc.size = 50;
  CHECK(uniformPressureRadius(disc) == Approx(100.0 / 3).epsilon(1e-12));
  ObjectSpec rect;
  rect.shape = "rectangle", rect.size = 58, rect.size2 = 95;
  ObjectSpec hex;
  hex.shape = "hexagon", hex.size = 50;
  for (const ObjectSpec& o : {sq, rect, hex}) {
    std::uint64_t state = 12345;
    auto u01 = [&] {
      state = state * 6364136223846793005ULL + 1442695040888963407ULL;
      return double(state >> 11) * 0x1.0p-53;
    };
    const std::vector<Vec2> v = footprint(o);
    double lo_x = 1e9, hi_x = -1e9, lo_y = 1e9, hi_y = -1e9;
    for (const Vec2& p : v) lo_x = std::min(lo_x, p.x()), hi_x = std::max(hi_x, p.x()), lo_y = std::min(lo_y, p.y()), hi_y = std::max(hi_y, p.y());
    double sum = 0;
    long n = 0;
    for (int k = 0; k < 100000; ++k) {
      const Vec2 p(lo_x + (hi_x - lo_x) * u01(), lo_y + (hi_y - lo_y) * u01());
      bool inside = true;
      for (std::size_t i = 0; i < v.size(); ++i) {
        const Vec2 e = v[(i + 1) % v.size()] - v[i], q = p - v[i];
        inside = inside && e.x() * q.y() - e.y() * q.x() >= 0;
      }
      if (inside) sum += p.norm(), ++n;
    }
    INFO(o.shape);
    CHECK(uniformPressureRadius(o) == Approx(sum / double(n)).epsilon(0.01));
    CHECK(baseArea(o) == Approx((hi_x - lo_x) * (hi_y - lo_y) * double(n) / 1e5).epsilon(0.01));
  }
}

TEST_CASE("mujoco: every object stands on 12 base points with the uniform-pressure mean radius, its outline among them",
          "[sim][mujoco][base]") {
  // The cost of a push grows with the base points (three constraint rows each), so the count is
  // fixed; the points' mean radius sets the breakaway torque over force (exact), the outline's
  // vertices the tipping edges, and their second moment the tilt stiffness (within 30 % of
  // the area's, as the Winkler test's bound).
  std::vector<ObjectSpec> objects = lieservo::sim::shortObjects();
  for (const ObjectSpec& o : lieservo::sim::tallAndEverydayObjects()) objects.push_back(o);
  for (const ObjectSpec& o : objects) {
    INFO(o.name);
    const std::vector<Vec2> p = basePoints(o);
    REQUIRE(p.size() == 12);
    double mean = 0, xx = 0, yy = 0;
    for (const Vec2& q : p) mean += q.norm() / 12, xx += q.x() * q.x() / 12, yy += q.y() * q.y() / 12;
    CHECK(mean == Approx(uniformPressureRadius(o)).epsilon(1e-12));
    double reach = 0;  // the outline: the farthest points lie on it
    for (const Vec2& q : p) reach = std::max(reach, q.norm());
    for (const Vec2& v : footprint(o)) {
      if (o.shape == "circle") break;
      bool found = false;
      for (const Vec2& q : p) found = found || (q - v).norm() < 1e-9;
      CHECK(found);
    }
    if (o.shape == "circle") CHECK(reach == Approx(o.size).epsilon(1e-12));
    // The area's second moments per unit area: a rectangle a²/12 and b²/12, a disc R²/4, the
    // regular hexagon (circumradius R) 5R²/24 about either axis.
    const double a = o.size, b = o.shape == "rectangle" ? o.size2 : o.size;
    double ixx = a * a / 12, iyy = b * b / 12;
    if (o.shape == "circle") ixx = iyy = a * a / 4;
    if (o.shape == "hexagon") ixx = iyy = 5 * a * a / 24;
    CHECK(xx / ixx == Approx(1.0).margin(0.30));
    CHECK(yy / iyy == Approx(1.0).margin(0.30));
  }
}

namespace {
// The force (N) along +x at the base, or the torque (N·m) about the vertical axis, ramped from
// 0 to `top` in 8 s, at which the base first slides faster than 0.2 mm/s: at its centre, or
// at the uniform-pressure radius when turning. (MuJoCo's soft friction creeps slowly just
// past the limit before it slides away, so one slip speed is used for both.)
double breakaway(const ObjectSpec& object, double mu, bool torque, double top) {
  SceneSpec s;
  s.support = SupportSpec::mdf();
  s.support.friction = mu;
  s.objects = {object};
  World w(s);
  REQUIRE(w.step(0.2) == Status::ok);  // settle
  const double dt = 0.005, ramp = 8.0, slip = 0.2;  // mm/s
  lieservo::SE3<double> X0 = w.objectPose(0);
  for (double t = 0; t < ramp; t += dt) {
    const double f = top * t / ramp;
    const Vec3 com = w.objectPose(0).translation();
    if (torque)
      w.applyObjectWrench(0, Vec3::Zero(), Vec3(0, 0, f));
    else
      w.applyObjectForce(0, Vec3(f, 0, 0), Vec3(com.x(), com.y(), 1.0));  // 1 mm above the base
    REQUIRE(w.step(dt) == Status::ok);
    const lieservo::SE3<double> X = w.objectPose(0);
    const double speed = (X.translation() - X0.translation()).head<2>().norm() / dt;
    const double rate = std::abs((X0.inverse() * X).log()[5]) / dt;
    if (torque ? rate * uniformPressureRadius(object) > slip : speed > slip) return f;
    X0 = X;
  }
  return top;
}
}  // namespace

TEST_CASE("mujoco: every pushed object's base slides at mu_s m g and turns as a uniformly pressed base",
          "[sim][mujoco][base]") {
  // Bounds fixed by the issue: breakaway force within ±10 % of μ_s m g, breakaway torque over
  // breakaway force within ±20 % of the uniform-pressure radius.
  std::vector<ObjectSpec> objects = lieservo::sim::shortObjects();
  for (const ObjectSpec& o : lieservo::sim::everydayObjects()) objects.push_back(o);
  for (const ObjectSpec& o : objects) {
    for (const double mu : {0.35, 0.6}) {
      const double W = o.mass * g;
      const double F = breakaway(o, mu, false, 2 * mu * W);
      const double T = breakaway(o, mu, true, 2 * mu * W * uniformPressureRadius(o) * 1e-3);
      INFO(o.name << " on mu_s " << mu << ": force " << F << " N (mu m g " << mu * W << "), torque/force "
                  << T / F * 1e3 << " mm (uniform pressure " << uniformPressureRadius(o) << " mm)");
      CHECK(F == Approx(mu * W).epsilon(0.10));
      CHECK(T / F * 1e3 == Approx(uniformPressureRadius(o)).epsilon(0.20));
    }
  }
}

TEST_CASE("mujoco: an object beds in by its Winkler depth, and tilts by it under a moment", "[sim][mujoco][base]") {
  // Sink = m g / (k_w A) within 20 % on foam and MDF. Under a moment M about y the base tilts
  // by M / (k_w I_y) (I_y = ∫ x² dA; a square a⁴/12): within 30 % (the points stand for the
  // area only on average).
  std::vector<ObjectSpec> objects = lieservo::sim::shortObjects();
  for (const ObjectSpec& o : lieservo::sim::everydayObjects()) objects.push_back(o);
  for (const ObjectSpec& o : objects) {
    for (const SupportSpec& support : {SupportSpec::foam(), SupportSpec::mdf()}) {
      SceneSpec s;
      s.support = support;
      s.objects = {o};
      World w(s);
      REQUIRE(w.step(1.0) == Status::ok);
      const double sink = -w.objectPose(0).translation().z();
      INFO(o.name << " on " << support.name << ": sink " << sink << " mm");
      CHECK(sink == Approx(o.mass * g / (support.foundation_modulus * baseArea(o))).epsilon(0.20));
    }
  }
  ObjectSpec sq = lieservo::sim::shortObjects()[0];
  SceneSpec s;
  s.support = SupportSpec::foam();
  s.objects = {sq};
  World w(s);
  const double M = 50;  // N·mm about y, well inside the base's kern
  w.applyObjectWrench(0, Vec3::Zero(), Vec3(0, M * 1e-3, 0));
  REQUIRE(w.step(1.0) == Status::ok);
  const double I = std::pow(sq.size, 4) / 12;
  CHECK(w.objectTilt(0) == Approx(M / (SupportSpec::foam().foundation_modulus * I)).epsilon(0.30));
}

TEST_CASE("mujoco: tipping height and friction by statics and by the engine agree within 10 %",
          "[sim][mujoco][base][topple]") {
  // Statics: a push at height h slides the object (F = μ_s m g) before it tips (F h = m g w/2)
  // when μ_s h < w/2, so h* = w/(2 μ_s) and μ_s* = w/(2 h). The engine, by bisection.
  for (const ObjectSpec& o : lieservo::sim::tallAndEverydayObjects()) {
    const lieservo::sim::ToppleRow r = lieservo::sim::toppleAnalysis(o, 0.35, 45, 0.01);
    INFO(o.name << ": h* statics " << r.statics_height << " engine " << r.engine_height << " mm; mu_s* statics "
                << r.statics_friction << " engine " << r.engine_friction);
    if (std::isinf(r.statics_height))
      CHECK(std::isinf(r.engine_height));  // tips by neither even when pushed at its top
    else
      CHECK(r.engine_height == Approx(r.statics_height).epsilon(0.10));
    CHECK(r.engine_friction == Approx(r.statics_friction).epsilon(0.10));
  }
}

// ---- One contact truth: the observed shear saturates where the engine's gel slips -----------

namespace {
// The gel tests run the engine at the step the tasks run it (20 Hz control).
const double kTaskStep = lieservo::sim::taskTimestep(0.05);
long stepsIn(double seconds) { return std::lround(seconds / kTaskStep); }

// A fixed plate (skin friction μ_c) and a tip above it, z_s down, pressed `depth` mm into it.
SceneSpec tipOnPlate(const ContactParams& cp, double depth) {
  SceneSpec s;
  s.timestep = kTaskStep;
  FixtureSpec plate;
  plate.name = "plate", plate.shape = "plate", plate.size = 200, plate.size2 = 10, plate.friction = cp.skin_friction;
  s.fixtures = {plate};
  SensorSpec tip;
  tip.name = "tip";
  tip.gel_stiffness = cp.gel_stiffness;
  tip.gel_tangential_ratio = cp.gel_tangential_ratio;
  Mat3 R;
  R << 1, 0, 0, 0, -1, 0, 0, 0, -1;
  tip.initial_pose = makePose(R, Vec3(0, 0, cp.tip_radius - depth));
  s.sensors = {tip};
  return s;
}
}  // namespace

TEST_CASE("mujoco: the contact model's shear saturates where the engine's gel contact starts to slip",
          "[sim][mujoco][gel]") {
  // A tip pressed into a fixed plate at depth d slides along it at 5 mm/s (the speed of the
  // pushes' tangential moves) for 40 mm. The engine's gel deflects sideways until k_t δ = μ_c N
  // and then slides: δ saturates (slower drags: the stick test below). The contact model fed
  // by the same engine geometry saturates its shear at slipRadius(d). Bound: 10 %.
  for (const double mu_c : {0.5, 0.8}) {
    for (const double depth : {2.0, 3.0, 4.0}) {
      ContactParams cp;
      cp.skin_friction = mu_c;
      World w(tipOnPlate(cp, depth));
      ContactModel model(cp);
      auto observe = [&] {
        const TipGeometry geo = w.tipGeometry(0);
        SurfacePoint sp;
        sp.point = geo.point_w;
        sp.normal = geo.normal_w;
        sp.signed_distance = 20 - geo.depth;
        return model.update(w.sensorPose(0), lieservo::SE3<double>::identity(), sp);
      };
      REQUIRE(w.step(0.3) == Status::ok);
      observe();
      Vec6 u;
      u << 5, 0, 0, 0, 0, 0;  // along x_s, mm/s
      REQUIRE(w.setSensorTwist(0, u) == Status::ok);
      ContactState c;
      for (long k = 0; k < stepsIn(8.0); ++k) {  // 8 s: 40 mm
        REQUIRE(w.step(kTaskStep) == Status::ok);
        c = observe();
      }
      const double engine = std::hypot(w.gelDeflection(0).x(), w.gelDeflection(0).y());
      INFO("mu_c " << mu_c << ", depth " << depth << " mm: engine gel slides at " << engine
                   << " mm, the contact model's shear saturates at " << c.shear.norm() << " mm");
      CHECK(c.slipped);
      CHECK(c.shear.norm() == Approx(model.slipRadius(c.depth)).epsilon(1e-9));
      CHECK(c.shear.norm() == Approx(engine).epsilon(0.10));
      // What the tasks observe: the shear read from the engine's gel, the sensor's displacement
      // against the skin, opposite to the gel's sideways deflection (the motion is along +x_s).
      ContactModel from_gel(cp);
      const TipGeometry geo = w.tipGeometry(0);
      SurfacePoint sp;
      sp.point = geo.point_w, sp.normal = geo.normal_w, sp.signed_distance = 20 - geo.depth;
      const ContactState g = from_gel.update(w.sensorPose(0), lieservo::SE3<double>::identity(), sp, w.gelDeflection(0));
      CHECK(g.shear.norm() == Approx(engine).epsilon(1e-9));
      const Vec2 d = g.X_wf.rotationMatrix().leftCols<2>().transpose() * (w.sensorPose(0).rotationMatrix() * w.gelDeflection(0));
      CHECK((d + g.shear).norm() < 1e-9);
    }
  }
}

TEST_CASE("mujoco: a gel stuck to a face holds its shear, on a fixed plate and on a pushed object",
          "[sim][mujoco][gel]") {
  // Bounds written before running. Below μ_c N a stuck gel deflects with the arm: it must not
  // creep back (MuJoCo's soft friction is a damper below its limit; kNoslipIterations and the
  // arm's mass hold it) nor slide when the contact's normal force ripples against a moving
  // object (the overdamped tip contact, kContactSolref).
  ContactParams cp;
  SECTION("fixed plate: 2.4 mm of drag at 1 mm/s, depth 4 mm (slip at about 4.4 mm)") {
    World w(tipOnPlate(cp, 4.0));
    REQUIRE(w.step(0.3) == Status::ok);
    const double x0 = w.gelDeflection(0).x();
    Vec6 u;
    u << 1, 0, 0, 0, 0, 0;
    REQUIRE(w.setSensorTwist(0, u) == Status::ok);
    for (long k = 0; k < stepsIn(2.4); ++k) REQUIRE(w.step(kTaskStep) == Status::ok);
    const double gained = x0 - w.gelDeflection(0).x();  // the tip lags the arm: δ_x < 0
    const double slip = cp.skin_friction * w.tipNormalForce(0) / (cp.gel_tangential_ratio * cp.gel_stiffness);
    INFO("gel deflection gained " << gained << " mm of 2.4 mm; slip at " << slip << " mm");
    REQUIRE(slip > 2.4);
    CHECK(gained >= 0.9 * 2.4);
  }
  SECTION("pushed object: the red square pushed at 10 mm/s on MDF while the arm rises at 0.7 mm/s") {
    SceneSpec s;
    s.support = SupportSpec::mdf();
    ObjectSpec o = shortObjects()[2];
    o.friction = cp.skin_friction;
    o.contact_height = 45;
    s.objects = {o};
    SensorSpec tip;
    tip.name = "leader";
    tip.tip_radius = cp.tip_radius;
    tip.gel_stiffness = cp.gel_stiffness;
    tip.gel_tangential_ratio = cp.gel_tangential_ratio;
    Mat3 R;
    R.col(0) = -Vec3::UnitZ(), R.col(1) = Vec3::UnitY(), R.col(2) = Vec3::UnitX();  // the pushes' mount
    tip.initial_pose = makePose(R, Vec3(-halfExtentX(o) - cp.tip_radius + 2.0, 0, 45));
    s.sensors = {tip};
    s.timestep = kTaskStep;
    World w(s);
    REQUIRE(w.step(0.5) == Status::ok);
    Vec6 u;
    u << -0.7, 0, 10, 0, 0, 0;  // up (−x_s) and forward (z_s), mm/s
    REQUIRE(w.setSensorTwist(0, u) == Status::ok);
    for (long k = 0; k < stepsIn(1.0); ++k) REQUIRE(w.step(kTaskStep) == Status::ok);
    INFO("after 1 s: gel deflection " << w.gelDeflection(0).x() << " mm of 0.7 mm");
    CHECK(w.gelDeflection(0).x() >= 0.8 * 0.7);  // the skin holds the face: the tip lags below
    double least = 1e9;
    for (long k = stepsIn(1.0); k < stepsIn(3.0); ++k) {
      REQUIRE(w.step(kTaskStep) == Status::ok);
      if (k < stepsIn(1.5)) continue;
      const double slip = cp.skin_friction * w.tipNormalForce(0) / (cp.gel_tangential_ratio * cp.gel_stiffness);
      least = std::min(least, w.gelDeflection(0).x() / slip);
    }
    INFO("from 1.5 s to 3 s: the gel's deflection is at least " << least << " of mu_c N / k_t");
    CHECK(least >= 0.5);
  }
}

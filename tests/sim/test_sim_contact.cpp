// Contact model against hand-computed cases (flat plane at known tilt/depth, sphere, stick/slip).
// The nearest surface points are computed by hand here (the engine's come from MuJoCo,
// test_sim_mujoco.cpp).
#include <catch2/catch.hpp>

#include "lieservo_sim/contact_model.hpp"

using namespace lieservo::sim;

namespace {
// The plane z_o = 0 (solid below) and a sphere of radius a at the origin: nearest points.
SurfacePoint planePoint(const SE3d& X_ws, const SE3d& X_wo) {
  const Vec3 q = X_wo.inverse() * X_ws.translation();
  return {Vec3(q.x(), q.y(), 0), Vec3::UnitZ(), q.z()};
}
SurfacePoint spherePoint(double a, const SE3d& X_ws) {
  const Vec3 q = X_ws.translation();
  return {a * q.normalized(), q.normalized(), q.norm() - a};
}
// The contact on the plane for sensor X_ws, object X_wo.
ContactState onPlane(ContactModel& cm, const SE3d& X_ws, const SE3d& X_wo = SE3d::identity()) {
  return cm.update(X_ws, X_wo, planePoint(X_ws, X_wo));
}
// Feature frame of a horizontal plane (z_f = −z_w) and a sensor in contact pose e = (x,y,z,α,β,γ)
// relative to it, for a plane at height 0 and first touch above the origin.
const Mat3 kRwf = fromColumns(Vec3::UnitX(), -Vec3::UnitY(), -Vec3::UnitZ());
SE3d sensorAt(double depth, double a, double b, double R = 20) {
  return makePose(kRwf * SO3d::fromEulerXYZ(a, b, 0).rotationMatrix(), Vec3(0, 0, R - depth));
}
}  // namespace

TEST_CASE("contact: flat plane, normal contact at known depth", "[sim][contact]") {
  ContactModel cm;
  const ContactState c = onPlane(cm, sensorAt(2.5, 0, 0));
  REQUIRE(c.in_contact);
  CHECK(c.depth == Approx(2.5));
  CHECK(c.tilt == Approx(0).margin(1e-12));
  const Vec6 e = c.label();
  CHECK(e[0] == Approx(0).margin(1e-12));
  CHECK(e[1] == Approx(0).margin(1e-12));
  CHECK(e[2] == Approx(2.5));
  CHECK(e.tail<3>().norm() == Approx(0).margin(1e-12));
}

TEST_CASE("contact: flat plane at known tilt gives (0, 0, z, alpha, beta, 0)", "[sim][contact]") {
  ContactModel cm;
  const double a = deg2rad(12), b = deg2rad(-7), z = 4.0;
  const ContactState c = onPlane(cm, sensorAt(z, a, b));
  const Vec6 e = c.label();
  CHECK(e[0] == Approx(0).margin(1e-9));
  CHECK(e[1] == Approx(0).margin(1e-9));
  CHECK(e[2] == Approx(z));
  CHECK(e[3] == Approx(a));
  CHECK(e[4] == Approx(b));
  CHECK(e[5] == Approx(0).margin(1e-12));
  // tilt = angle between sensor axis and inward normal: cos(tilt) = cos a cos b
  CHECK(std::cos(c.tilt) == Approx(std::cos(a) * std::cos(b)));
  // The plane moved with its object: same label in any object pose.
  const SE3d X_wo = makePose(SO3d::fromEulerXYZ(0.3, -0.2, 1.0).rotationMatrix(), Vec3(10, -20, 30));
  ContactModel cm2;
  const ContactState c2 = onPlane(cm2, X_wo * sensorAt(z, a, b), X_wo);
  CHECK((c2.label() - e).norm() == Approx(0).margin(1e-9));
}

TEST_CASE("contact: out of contact above the plane", "[sim][contact]") {
  ContactModel cm;
  const ContactState c = onPlane(cm, sensorAt(-1.0, 0, 0));
  CHECK_FALSE(c.in_contact);
  CHECK(c.depth == Approx(-1.0));
  CHECK_FALSE(cm.anchored());
}

TEST_CASE("contact: shear sticks below the slip radius and slips beyond it", "[sim][contact]") {
  ContactParams p;  // slip radius = clamp(μ_c z / ρ_t, 0.05, 5) = 1.5 z here
  p.skin_friction = 1.5;
  p.gel_tangential_ratio = 1.0;
  ContactModel cm(p);
  const double z = 3.0;  // slip radius 4.5 mm
  SE3d X = sensorAt(z, 0, 0);
  onPlane(cm, X);
  // Tangential move of the sensor by (1.0, −0.5) in {f}: f-axes are (x_w, −y_w).
  X = makePose(X.rotationMatrix(), X.translation() + Vec3(1.0, 0.5, 0));
  ContactState c = onPlane(cm, X);
  CHECK_FALSE(c.slipped);
  CHECK(c.shear.x() == Approx(1.0));
  CHECK(c.shear.y() == Approx(-0.5));
  CHECK(c.depth == Approx(z));
  // Far beyond the slip radius: shear saturates at 4.5 mm in the same direction.
  X = makePose(X.rotationMatrix(), X.translation() + Vec3(9.0, 0, 0));
  c = onPlane(cm, X);
  CHECK(c.slipped);
  CHECK(c.shear.norm() == Approx(4.5));
  CHECK(c.shear.y() / c.shear.x() == Approx(-0.5 / 10.0));
  // Coming back by 4.5 mm: the anchor moved, so the shear returns to zero.
  X = makePose(X.rotationMatrix(), X.translation() - c.X_wf.rotationMatrix() * Vec3(c.shear.x(), c.shear.y(), 0));
  c = onPlane(cm, X);
  CHECK(c.shear.norm() == Approx(0).margin(1e-9));
}

TEST_CASE("contact: twist about the normal sticks up to gamma_max", "[sim][contact]") {
  ContactModel cm;
  SE3d X = sensorAt(3.0, 0, 0);
  onPlane(cm, X);
  // Rotate the sensor about the surface normal (about its own z axis) by 3°, then by 8° more.
  X = X * makePose(rotZ(deg2rad(3)), Vec3::Zero());
  ContactState c = onPlane(cm, X);
  CHECK(c.twist == Approx(deg2rad(3)));
  CHECK_FALSE(c.slipped);
  X = X * makePose(rotZ(deg2rad(8)), Vec3::Zero());
  c = onPlane(cm, X);
  CHECK(c.slipped);
  CHECK(c.twist == Approx(deg2rad(5)));
}

TEST_CASE("contact: sphere (dome) depth and tilt", "[sim][contact]") {
  const double a = 50, R = 20, z = 2.0;
  ContactModel cm;
  const Vec3 u = Vec3(std::sin(deg2rad(30)), 0, std::cos(deg2rad(30)));  // 30° from the pole in x-z
  // Sensor axis pointing at the centre (−u), centre at distance a + R − z.
  const Vec3 zs = -u, xs = Vec3::UnitY().cross(zs).normalized(), ys = zs.cross(xs);
  const SE3d X = makePose(fromColumns(xs, ys, zs), (a + R - z) * u);
  ContactState c = cm.update(X, SE3d::identity(), spherePoint(a, X));
  CHECK(c.in_contact);
  CHECK(c.depth == Approx(z));
  CHECK(c.tilt == Approx(0).margin(1e-9));
  CHECK((c.point_w - a * u).norm() == Approx(0).margin(1e-9));
  CHECK((c.normal_w - u).norm() == Approx(0).margin(1e-12));
  // Tilting the sensor about its own centre by 10° changes the tilt, not the depth.
  ContactModel cm2;
  const SE3d Xt = X * makePose(rotX(deg2rad(10)), Vec3::Zero());
  c = cm2.update(Xt, SE3d::identity(), spherePoint(a, Xt));
  CHECK(c.depth == Approx(z));
  CHECK(c.tilt == Approx(deg2rad(10)));
  CHECK(c.label()[3] == Approx(deg2rad(10)));
}

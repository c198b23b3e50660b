// Contact model against hand-computed cases (flat plane at known tilt/depth, sphere, stick/slip).
#include <catch2/catch.hpp>

#include "lieservo_sim/contact_model.hpp"

using namespace lieservo::sim;

namespace {
// Feature frame of a horizontal plane (z_f = −z_w) and a sensor in contact pose e = (x,y,z,α,β,γ)
// relative to it, for a plane at height 0 and first touch above the origin.
const Mat3 kRwf = fromColumns(Vec3::UnitX(), -Vec3::UnitY(), -Vec3::UnitZ());
SE3d sensorAt(double depth, double a, double b, double R = 20) {
  return makePose(kRwf * eulerToMatrix(a, b, 0), Vec3(0, 0, R - depth));
}
}  // namespace

TEST_CASE("contact: flat plane, normal contact at known depth", "[sim][contact]") {
  PlaneSurface plane;
  ContactModel cm(plane);
  const ContactState c = cm.update(sensorAt(2.5, 0, 0), SE3d::identity());
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
  PlaneSurface plane;
  ContactModel cm(plane);
  const double a = deg(12), b = deg(-7), z = 4.0;
  const ContactState c = cm.update(sensorAt(z, a, b), SE3d::identity());
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
  const SE3d X_wo = makePose(eulerToMatrix(0.3, -0.2, 1.0), Vec3(10, -20, 30));
  ContactModel cm2(plane);
  const ContactState c2 = cm2.update(X_wo * sensorAt(z, a, b), X_wo);
  CHECK((c2.label() - e).norm() == Approx(0).margin(1e-9));
}

TEST_CASE("contact: out of contact above the plane", "[sim][contact]") {
  PlaneSurface plane;
  ContactModel cm(plane);
  const ContactState c = cm.update(sensorAt(-1.0, 0, 0), SE3d::identity());
  CHECK_FALSE(c.in_contact);
  CHECK(c.depth == Approx(-1.0));
  CHECK_FALSE(cm.anchored());
}

TEST_CASE("contact: shear sticks below the slip radius and slips beyond it", "[sim][contact]") {
  PlaneSurface plane;
  ContactParams p;  // slip radius = clamp(1.5 z, 0.5, 5)
  ContactModel cm(plane, p);
  const double z = 3.0;  // slip radius 4.5 mm
  SE3d X = sensorAt(z, 0, 0);
  cm.update(X, SE3d::identity());
  // Tangential move of the sensor by (1.0, −0.5) in {f}: f-axes are (x_w, −y_w).
  X = makePose(X.rotationMatrix(), X.translation() + Vec3(1.0, 0.5, 0));
  ContactState c = cm.update(X, SE3d::identity());
  CHECK_FALSE(c.slipped);
  CHECK(c.shear.x() == Approx(1.0));
  CHECK(c.shear.y() == Approx(-0.5));
  CHECK(c.depth == Approx(z));
  // Far beyond the slip radius: shear saturates at 4.5 mm in the same direction.
  X = makePose(X.rotationMatrix(), X.translation() + Vec3(9.0, 0, 0));
  c = cm.update(X, SE3d::identity());
  CHECK(c.slipped);
  CHECK(c.shear.norm() == Approx(4.5));
  CHECK(c.shear.y() / c.shear.x() == Approx(-0.5 / 10.0));
  // Coming back by 4.5 mm: the anchor moved, so the shear returns to zero.
  X = makePose(X.rotationMatrix(), X.translation() - c.X_wf.rotationMatrix() * Vec3(c.shear.x(), c.shear.y(), 0));
  c = cm.update(X, SE3d::identity());
  CHECK(c.shear.norm() == Approx(0).margin(1e-9));
}

TEST_CASE("contact: twist about the normal sticks up to gamma_max", "[sim][contact]") {
  PlaneSurface plane;
  ContactModel cm(plane);
  SE3d X = sensorAt(3.0, 0, 0);
  cm.update(X, SE3d::identity());
  // Rotate the sensor about the surface normal (about its own z axis) by 3°, then by 8° more.
  X = X * makePose(rotZ(deg(3)), Vec3::Zero());
  ContactState c = cm.update(X, SE3d::identity());
  CHECK(c.twist == Approx(deg(3)));
  CHECK_FALSE(c.slipped);
  X = X * makePose(rotZ(deg(8)), Vec3::Zero());
  c = cm.update(X, SE3d::identity());
  CHECK(c.slipped);
  CHECK(c.twist == Approx(deg(5)));
}

TEST_CASE("contact: sphere (dome) depth and tilt", "[sim][contact]") {
  const double a = 50, R = 20, z = 2.0;
  SphereSurface dome(a);
  ContactModel cm(dome);
  const Vec3 u = Vec3(std::sin(deg(30)), 0, std::cos(deg(30)));  // 30° from the pole in x-z
  // Sensor axis pointing at the centre (−u), centre at distance a + R − z.
  const Vec3 zs = -u, xs = Vec3::UnitY().cross(zs).normalized(), ys = zs.cross(xs);
  const SE3d X = makePose(fromColumns(xs, ys, zs), (a + R - z) * u);
  ContactState c = cm.update(X, SE3d::identity());
  CHECK(c.in_contact);
  CHECK(c.depth == Approx(z));
  CHECK(c.tilt == Approx(0).margin(1e-9));
  CHECK((c.point_w - a * u).norm() == Approx(0).margin(1e-9));
  CHECK((c.normal_w - u).norm() == Approx(0).margin(1e-12));
  // Tilting the sensor about its own centre by 10° changes the tilt, not the depth.
  ContactModel cm2(dome);
  const SE3d Xt = X * makePose(rotX(deg(10)), Vec3::Zero());
  c = cm2.update(Xt, SE3d::identity());
  CHECK(c.depth == Approx(z));
  CHECK(c.tilt == Approx(deg(10)));
  CHECK(c.label()[3] == Approx(deg(10)));
}

TEST_CASE("contact: curved ramp nearest point and normal", "[sim][contact]") {
  RampSurface ramp(40, 200);
  for (double y : {-20.0, 30.0, 100.0, 170.0, 230.0}) {
    const double h = ramp.height(y), s = ramp.slope(y);
    const Vec3 n = Vec3(0, -s, 1).normalized();
    const Vec3 q = Vec3(5, y, h) + 12.0 * n;
    const SurfacePoint sp = ramp.closest(q);
    CHECK(sp.signed_distance == Approx(12.0).epsilon(1e-6));
    CHECK((sp.point - Vec3(5, y, h)).norm() == Approx(0).margin(1e-6));
  }
}

TEST_CASE("contact: prism faces and corners", "[sim][contact]") {
  const PrismSurface sq = PrismSurface::square(100, 60, "square");
  SurfacePoint sp = sq.closest(Vec3(-70, 10, 45));
  CHECK(sp.signed_distance == Approx(20));
  CHECK((sp.normal - Vec3(-1, 0, 0)).norm() == Approx(0).margin(1e-12));
  CHECK(sp.point.z() == Approx(45));
  sp = sq.closest(Vec3(53, 54, 0));  // beyond the corner (50, 50)
  CHECK(sp.signed_distance == Approx(5));
  const PrismSurface hex = PrismSurface::regularPolygon(6, 50, 60, "hex");
  sp = hex.closest(Vec3(-80, 0, 0));  // a flat face points along −x
  CHECK(sp.signed_distance == Approx(80 - 50 * std::cos(kPi / 6)));
  CHECK((sp.normal - Vec3(-1, 0, 0)).norm() == Approx(0).margin(1e-9));
  const PrismSurface circ = PrismSurface::circle(50, 60, "circle");
  CHECK(circ.uniformPressureLimitSurfaceRatio() == Approx(2.0 * 50 / 3));
  CHECK(sq.uniformPressureLimitSurfaceRatio() == Approx(0.3826 * 100).epsilon(0.01));
}

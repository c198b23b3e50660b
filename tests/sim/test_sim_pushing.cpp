// Quasi-static pushing model against analytic sticking/sliding cases.
#include <catch2/catch.hpp>

#include "lieservo_sim/planar_pushing.hpp"

using namespace lieservo::sim;

TEST_CASE("pushing: through the centre of mass gives pure translation", "[sim][pushing]") {
  const Vec2 r(-50, 0), n(-1, 0);
  const PushOutcome o = quasiStaticPush(r, n, Vec2(1, 0), 0.25, 20);
  CHECK(o.sticking);
  CHECK(o.twist.x() == Approx(1));
  CHECK(o.twist.y() == Approx(0).margin(1e-12));
  CHECK(o.twist.z() == Approx(0).margin(1e-12));
  // Any face orientation: the push along −n through the centre.
  const Vec2 n2 = Vec2(std::cos(0.7), std::sin(0.7));
  const PushOutcome o2 = quasiStaticPush(30 * n2, n2, -2 * n2, 0.5, 15);
  CHECK(o2.sticking);
  CHECK((o2.twist.head<2>() + 2 * n2).norm() == Approx(0).margin(1e-12));
  CHECK(o2.twist.z() == Approx(0).margin(1e-12));
}

TEST_CASE("pushing: inside the motion cone the contact sticks", "[sim][pushing]") {
  const Vec2 r(-50, 10), n(-1, 0), vp(1, 0.6);
  const PushOutcome o = quasiStaticPush(r, n, vp, 0.25, 20);
  REQUIRE(o.sticking);
  CHECK((contactPointVelocity(o.twist, r) - vp).norm() == Approx(0).margin(1e-12));
}

TEST_CASE("pushing: outside the motion cone it slides along the cone edge", "[sim][pushing]") {
  // Contact at the face centre r = (−a, 0), n = (−1, 0): friction-cone edge f = (1, ±μ),
  // m = r × f = ∓aμ, twist ∝ (1, ±μ, ∓aμ/c²), contact-point velocity (1, ±μ(1 + a²/c²)).
  const double a = 50, c = 20, mu = 0.25;
  const double edge = mu * (1 + a * a / (c * c));  // tan of the motion-cone half angle: 1.8125
  const Vec2 r(-a, 0), n(-1, 0);
  const PushOutcome o = quasiStaticPush(r, n, Vec2(1, 2.0), mu, c);  // 2.0 > 1.8125: outside
  REQUIRE(o.sliding);
  CHECK(o.twist.x() == Approx(1));
  CHECK(o.twist.y() == Approx(mu));
  CHECK(o.twist.z() == Approx(-a * mu / (c * c)));
  const Vec2 vc = contactPointVelocity(o.twist, r);
  CHECK(vc.x() == Approx(1));
  CHECK(vc.y() == Approx(edge));
  // The other side, mirrored.
  const PushOutcome m = quasiStaticPush(r, n, Vec2(1, -2.0), mu, c);
  REQUIRE(m.sliding);
  CHECK(m.twist.y() == Approx(-mu));
  CHECK(m.twist.z() == Approx(a * mu / (c * c)));
  CHECK(m.slide_side == -o.slide_side);
  // Just inside the edge it sticks.
  CHECK(quasiStaticPush(r, n, Vec2(1, 0.99 * edge), mu, c).sticking);
}

TEST_CASE("pushing: frictionless pusher pushes along the normal only", "[sim][pushing]") {
  const Vec2 r(-50, 20), n(-1, 0);
  const PushOutcome o = quasiStaticPush(r, n, Vec2(1, 0.5), 0.0, 25);
  REQUIRE(o.sliding);
  // f = −n = (1, 0): twist ∝ (1, 0, m/c²) with m = r × f = −r_y
  CHECK(o.twist.y() == Approx(0).margin(1e-12));
  CHECK(o.twist.z() / o.twist.x() == Approx(-20.0 / (25.0 * 25.0)));
  CHECK(contactPointVelocity(o.twist, r).dot(n) == Approx(-1));
}

TEST_CASE("pushing: a separating pusher moves nothing", "[sim][pushing]") {
  const PushOutcome o = quasiStaticPush(Vec2(-50, 0), Vec2(-1, 0), Vec2(-1, 0.3), 0.5, 20);
  CHECK(o.separating);
  CHECK(o.twist.norm() == 0);
}

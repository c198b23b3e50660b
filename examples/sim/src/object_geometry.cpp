// lieservo_sim/object_geometry.cpp — the objects' footprints, base areas and base points,
// and their extent along the push.
#include "lieservo_sim/mujoco_world.hpp"

#include <algorithm>
#include <cmath>

namespace lieservo::sim::mujoco {

std::vector<Vec2> footprint(const ObjectSpec& o) {
  std::vector<Vec2> v;
  if (o.shape == "square" || o.shape == "rectangle") {
    const double a = o.size / 2, b = (o.shape == "square" ? o.size : o.size2) / 2;
    return {{a, b}, {-a, b}, {-a, -b}, {a, -b}};
  }
  const int n = o.shape == "circle" ? 48 : 6;
  const double a0 = o.shape == "hexagon" ? kPi / 6 : 0.0;  // as hexagonMesh
  for (int k = 0; k < n; ++k) v.emplace_back(o.size * std::cos(a0 + 2 * kPi * k / n), o.size * std::sin(a0 + 2 * kPi * k / n));
  return v;
}

double baseArea(const ObjectSpec& o) {
  if (o.shape == "circle") return kPi * o.size * o.size;
  const std::vector<Vec2> v = footprint(o);
  double a = 0;
  for (std::size_t i = 0; i < v.size(); ++i) a += 0.5 * (v[i].x() * v[(i + 1) % v.size()].y() - v[(i + 1) % v.size()].x() * v[i].y());
  return a;
}

double uniformPressureRadius(const ObjectSpec& o) {
  if (o.shape == "circle") return 2 * o.size / 3;
  // Over the triangle (axis, v_i, v_(i+1)) in polar coordinates about the axis, ∫∫ r dA =
  // ∫ ρ(θ)³/3 dθ with ρ = d / cos(θ − θ_n) (d, θ_n: the edge line's distance and normal), and
  // ∫ sec³ φ dφ = (sec φ tan φ + ln(sec φ + tan φ)) / 2.
  const std::vector<Vec2> v = footprint(o);
  auto F = [](double phi) {
    const double sec = 1 / std::cos(phi), tan = std::tan(phi);
    return 0.5 * (sec * tan + std::log(sec + tan));
  };
  double integral = 0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const Vec2 a = v[i], b = v[(i + 1) % v.size()];
    const Vec2 e = (b - a).normalized();
    const Vec2 n(e.y(), -e.x());  // outward for a counter-clockwise outline
    const double d = n.dot(a), theta_n = std::atan2(n.y(), n.x());
    const double phi_a = std::remainder(std::atan2(a.y(), a.x()) - theta_n, 2 * kPi);
    const double phi_b = std::remainder(std::atan2(b.y(), b.x()) - theta_n, 2 * kPi);
    integral += d * d * d / 3 * (F(phi_b) - F(phi_a));
  }
  return integral / baseArea(o);
}

std::vector<Vec2> basePoints(const ObjectSpec& o) {
  // The outline: a polygon's vertices, six points on a circle's rim (one on +x). The inner
  // ring: the outline again, for a rectangle with its edge midpoints (eight points, so that the
  // base's second moment stays near the area's: its four corners alone would put it 50 %
  // above), scaled so that all points' mean distance from the axis is the uniform-pressure
  // radius. Every base point costs three constraint rows in each step.
  std::vector<Vec2> outline, inner;
  if (o.shape == "circle") {
    for (int k = 0; k < 6; ++k) outline.emplace_back(o.size * std::cos(kPi * k / 3), o.size * std::sin(kPi * k / 3));
    inner = outline;
  } else {
    outline = footprint(o);
    for (std::size_t i = 0; i < outline.size(); ++i) {
      inner.push_back(outline[i]);
      if (outline.size() == 4) inner.push_back(0.5 * (outline[i] + outline[(i + 1) % outline.size()]));
    }
  }
  double sum_outline = 0, sum_inner = 0;
  for (const Vec2& p : outline) sum_outline += p.norm();
  for (const Vec2& p : inner) sum_inner += p.norm();
  const double n = double(outline.size() + inner.size());
  const double lambda = (n * uniformPressureRadius(o) - sum_outline) / sum_inner;
  std::vector<Vec2> points = outline;
  for (const Vec2& p : inner) points.push_back(lambda * p);
  return points;
}

double halfExtentX(const ObjectSpec& o) {
  if (o.shape == "hexagon") return o.size * std::cos(kPi / 6);  // apothem: a face is normal to +x
  return o.shape == "circle" ? o.size : o.size / 2;
}

}  // namespace lieservo::sim::mujoco

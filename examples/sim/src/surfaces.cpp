// Surfaces of the simulation scenes (see lieservo_sim/surfaces.hpp).
#include "lieservo_sim/surfaces.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace lieservo::sim {

void requirePositive(double v, const char* name) {
  if (!(std::isfinite(v) && v > 0)) {
    std::ostringstream s;
    s << name << " must be finite and > 0 (got " << v << ")";
    throw SceneError(s.str());
  }
}
void requireNonNegative(double v, const char* name) {
  if (!(std::isfinite(v) && v >= 0)) {
    std::ostringstream s;
    s << name << " must be finite and >= 0 (got " << v << ")";
    throw SceneError(s.str());
  }
}
void requireValidPose(const SE3d& X, const char* name) {
  const Mat3 R = X.rotationMatrix();
  if (!X.allFinite()) throw SceneError(std::string(name) + " has a non-finite entry");
  if ((R.transpose() * R - Mat3::Identity()).norm() > 1e-6 || R.determinant() < 0)
    throw SceneError(std::string(name) + " rotation is not orthonormal with det +1");
}

// ---- plane ---------------------------------------------------------------------------------
PlaneSurface::PlaneSurface(double half_extent) : half_(half_extent) {
  requirePositive(half_extent, "PlaneSurface half_extent");
}
SurfacePoint PlaneSurface::closest(const Vec3& q) const {
  SurfacePoint s;
  s.point = Vec3(q.x(), q.y(), 0);
  s.normal = Vec3::UnitZ();
  s.signed_distance = q.z();
  return s;
}
std::vector<std::vector<Vec3>> PlaneSurface::outline() const {
  const double h = half_;
  return {{Vec3(-h, -h, 0), Vec3(h, -h, 0), Vec3(h, h, 0), Vec3(-h, h, 0), Vec3(-h, -h, 0)}};
}

// ---- sphere (dome) ---------------------------------------------------------------------------
SphereSurface::SphereSurface(double radius) : a_(radius) { requirePositive(radius, "SphereSurface radius"); }
SurfacePoint SphereSurface::closest(const Vec3& q) const {
  SurfacePoint s;
  const double n = q.norm();
  s.normal = n > 1e-12 ? Vec3(q / n) : Vec3(Vec3::UnitZ());
  s.point = a_ * s.normal;
  s.signed_distance = n - a_;
  return s;
}
std::vector<std::vector<Vec3>> SphereSurface::outline() const {
  std::vector<std::vector<Vec3>> out;
  for (int k = 0; k < 4; ++k) {  // four meridians and the rim
    const double th = k * kPi / 4;
    std::vector<Vec3> m;
    for (int i = 0; i <= 36; ++i) {
      const double phi = -kPi / 2 + i * kPi / 36;
      m.emplace_back(a_ * std::sin(phi) * std::cos(th), a_ * std::sin(phi) * std::sin(th), a_ * std::cos(phi));
    }
    out.push_back(m);
  }
  std::vector<Vec3> rim;
  for (int i = 0; i <= 72; ++i) rim.emplace_back(a_ * std::cos(i * kPi / 36), a_ * std::sin(i * kPi / 36), 0);
  out.push_back(rim);
  return out;
}

// ---- curved ramp -----------------------------------------------------------------------------
RampSurface::RampSurface(double height, double length, double width) : H_(height), L_(length), W_(width) {
  requirePositive(height, "RampSurface height");
  requirePositive(length, "RampSurface length");
  requirePositive(width, "RampSurface width");
  // Smallest radius of curvature L²/(H π²/2) must exceed the tip radius by a margin so that
  // the nearest point is unique for tip centres within 20 mm of the surface.
  const double rmin = L_ * L_ / (H_ * kPi * kPi / 2);
  if (rmin < 40) {
    std::ostringstream s;
    s << "RampSurface too sharply curved: min radius of curvature " << rmin << " mm < 40 mm";
    throw SceneError(s.str());
  }
}
double RampSurface::height(double y) const {
  if (y <= 0) return H_;
  if (y >= L_) return 0;
  return 0.5 * H_ * (1 + std::cos(kPi * y / L_));
}
double RampSurface::slope(double y) const {
  if (y <= 0 || y >= L_) return 0;
  return -0.5 * H_ * (kPi / L_) * std::sin(kPi * y / L_);
}
double RampSurface::curvature2(double y) const {
  if (y <= 0 || y >= L_) return 0;
  return -0.5 * H_ * (kPi / L_) * (kPi / L_) * std::cos(kPi * y / L_);
}
SurfacePoint RampSurface::closest(const Vec3& q) const {
  // Minimise f(y) = (y − q_y)² + (h(y) − q_z)² by Newton steps from y = q_y (the profile is
  // C¹ and gently curved, so this converges in a few steps); guard with a bracketed search.
  double y = q.y();
  for (int it = 0; it < 20; ++it) {
    const double h = height(y), hp = slope(y), hpp = curvature2(y);
    const double g = (y - q.y()) + (h - q.z()) * hp;
    const double H = 1 + hp * hp + (h - q.z()) * hpp;
    const double step = H > 1e-6 ? g / H : g;
    y -= step;
    if (std::abs(step) < 1e-10) break;
  }
  SurfacePoint s;
  const double h = height(y), hp = slope(y);
  s.point = Vec3(q.x(), y, h);
  s.normal = Vec3(0, -hp, 1).normalized();
  s.signed_distance = (q - s.point).dot(s.normal);
  return s;
}
std::vector<std::vector<Vec3>> RampSurface::outline() const {
  std::vector<std::vector<Vec3>> out;
  for (double x : {-W_ / 2, 0.0, W_ / 2}) {
    std::vector<Vec3> p;
    for (int i = 0; i <= 60; ++i) {
      const double y = -0.2 * L_ + i * 1.4 * L_ / 60;
      p.emplace_back(x, y, height(y));
    }
    out.push_back(p);
  }
  return out;
}

// ---- prisms ----------------------------------------------------------------------------------
static double cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

PrismSurface PrismSurface::polygon(std::vector<Vec2> v, double height, std::string name) {
  requirePositive(height, "PrismSurface height");
  if (v.size() < 3) throw SceneError("PrismSurface polygon needs at least 3 vertices");
  for (const auto& p : v)
    if (!p.allFinite()) throw SceneError("PrismSurface polygon has a non-finite vertex");
  const std::size_t n = v.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 e0 = v[(i + 1) % n] - v[i], e1 = v[(i + 2) % n] - v[(i + 1) % n];
    if (cross2(e0, e1) <= 1e-9)
      throw SceneError("PrismSurface polygon must be strictly convex and counter-clockwise");
  }
  Vec2 c = Vec2::Zero();
  for (const auto& p : v) c += p;
  c /= double(n);
  for (std::size_t i = 0; i < n; ++i)
    if (cross2(v[(i + 1) % n] - v[i], -v[i]) <= 0)
      throw SceneError("PrismSurface polygon must contain its origin (the centre of mass)");
  PrismSurface s;
  s.vertices_ = std::move(v);
  s.height_ = height;
  s.name_ = std::move(name);
  return s;
}
PrismSurface PrismSurface::square(double side, double height, std::string name) {
  requirePositive(side, "PrismSurface square side");
  const double h = side / 2;
  return polygon({Vec2(-h, -h), Vec2(h, -h), Vec2(h, h), Vec2(-h, h)}, height, std::move(name));
}
PrismSurface PrismSurface::regularPolygon(int sides, double R, double height, std::string name) {
  if (sides < 3) throw SceneError("PrismSurface regularPolygon needs >= 3 sides");
  requirePositive(R, "PrismSurface circumradius");
  std::vector<Vec2> v;
  // Vertices at π/N + 2πi/N: face normals at 2π(i+1)/N, so for even N a flat face points
  // along −x_o (towards the pusher in the pushing scenes).
  for (int i = 0; i < sides; ++i) {
    const double a = kPi / sides + 2 * kPi * i / sides;
    v.emplace_back(R * std::cos(a), R * std::sin(a));
  }
  return polygon(std::move(v), height, std::move(name));
}
PrismSurface PrismSurface::circle(double radius, double height, std::string name) {
  requirePositive(radius, "PrismSurface circle radius");
  requirePositive(height, "PrismSurface height");
  PrismSurface s;
  s.radius_ = radius;
  s.height_ = height;
  s.name_ = std::move(name);
  return s;
}

SurfacePoint PrismSurface::closest2d(const Vec2& q) const {
  SurfacePoint s;
  if (radius_ > 0) {
    const double n = q.norm();
    const Vec2 u = n > 1e-12 ? Vec2(q / n) : Vec2(0, -1);
    s.point = Vec3(radius_ * u.x(), radius_ * u.y(), 0);
    s.normal = Vec3(u.x(), u.y(), 0);
    s.signed_distance = n - radius_;
    return s;
  }
  const std::size_t n = vertices_.size();
  // Inside test and max face distance (for points inside).
  double best_face = -std::numeric_limits<double>::infinity();
  std::size_t best_i = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 a = vertices_[i], b = vertices_[(i + 1) % n];
    const Vec2 e = (b - a).normalized();
    const Vec2 nout(e.y(), -e.x());
    const double d = (q - a).dot(nout);
    if (d > best_face) {
      best_face = d;
      best_i = i;
    }
  }
  if (best_face <= 0) {  // inside: nearest face
    const Vec2 a = vertices_[best_i], b = vertices_[(best_i + 1) % n];
    const Vec2 e = (b - a).normalized();
    const Vec2 nout(e.y(), -e.x());
    const Vec2 p = q - best_face * nout;
    s.point = Vec3(p.x(), p.y(), 0);
    s.normal = Vec3(nout.x(), nout.y(), 0);
    s.signed_distance = best_face;
    return s;
  }
  double best = std::numeric_limits<double>::infinity();
  Vec2 bp = Vec2::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 a = vertices_[i], b = vertices_[(i + 1) % n];
    const double t = std::clamp((q - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
    const Vec2 p = a + t * (b - a);
    const double d = (q - p).norm();
    if (d < best) {
      best = d;
      bp = p;
    }
  }
  const Vec2 u = (q - bp) / std::max(best, 1e-12);
  s.point = Vec3(bp.x(), bp.y(), 0);
  s.normal = Vec3(u.x(), u.y(), 0);
  s.signed_distance = best;
  return s;
}
SurfacePoint PrismSurface::closest(const Vec3& q) const {
  SurfacePoint s = closest2d(q.head<2>());
  s.point.z() = q.z();
  return s;
}
std::vector<std::vector<Vec3>> PrismSurface::outline() const {
  std::vector<Vec3> p;
  if (radius_ > 0) {
    for (int i = 0; i <= 72; ++i) p.emplace_back(radius_ * std::cos(i * kPi / 36), radius_ * std::sin(i * kPi / 36), 0);
  } else {
    for (const auto& v : vertices_) p.emplace_back(v.x(), v.y(), 0);
    p.push_back(p.front());
  }
  return {p};
}
double PrismSurface::uniformPressureLimitSurfaceRatio() const {
  if (radius_ > 0) return 2.0 * radius_ / 3.0;
  // Mean distance from the origin over the footprint, on a 200 x 200 grid.
  const double R = circumradius();
  const int N = 200;
  double area = 0, moment = 0;
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j) {
      const Vec2 p(-R + (i + 0.5) * 2 * R / N, -R + (j + 0.5) * 2 * R / N);
      if (closest2d(p).signed_distance < 0) {
        area += 1;
        moment += p.norm();
      }
    }
  return moment / area;
}
double PrismSurface::circumradius() const {
  if (radius_ > 0) return radius_;
  double r = 0;
  for (const auto& v : vertices_) r = std::max(r, v.norm());
  return r;
}

}  // namespace lieservo::sim

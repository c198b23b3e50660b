// Quasi-static planar pushing (see lieservo_sim/planar_pushing.hpp).
#include "lieservo_sim/planar_pushing.hpp"

#include <algorithm>
#include <cmath>

namespace lieservo::sim {

static double cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

static Vec3 twistForForce(const Vec2& f, const Vec2& r, double c) {
  const double m = r.x() * f.y() - r.y() * f.x();
  return Vec3(f.x(), f.y(), m / (c * c));
}

PushOutcome quasiStaticPush(const Vec2& r, const Vec2& n_in, const Vec2& v_p, double mu, double c) {
  PushOutcome out;
  const Vec2 n = n_in.normalized();
  const double vn = v_p.dot(n);
  if (!(vn < 0)) {
    out.separating = true;
    return out;
  }
  const Vec2 t(-n.y(), n.x());  // tangent
  const Vec2 fl = -n + mu * t, fr = -n - mu * t;
  const Vec3 Vl = twistForForce(fl, r, c), Vr = twistForForce(fr, r, c);
  const Vec2 vl = contactPointVelocity(Vl, r), vr = contactPointVelocity(Vr, r);
  // Inside the cone spanned by vl and vr (the cone is convex: angle < π).
  const double s_lr = cross2(vl, vr);
  const bool inside = (s_lr >= 0) ? (cross2(vl, v_p) >= 0 && cross2(v_p, vr) >= 0)
                                  : (cross2(vl, v_p) <= 0 && cross2(v_p, vr) <= 0);
  if (inside) {
    const Vec2 w(-r.y(), r.x());
    const Eigen::Matrix2d A = Eigen::Matrix2d::Identity() + w * w.transpose() / (c * c);
    const Vec2 f = A.ldlt().solve(v_p);
    out.twist = Vec3(f.x(), f.y(), w.dot(f) / (c * c));
    out.sticking = true;
    return out;
  }
  // Sliding on the edge nearer to v_p (by angle).
  const double al = std::acos(std::clamp(vl.normalized().dot(v_p.normalized()), -1.0, 1.0));
  const double ar = std::acos(std::clamp(vr.normalized().dot(v_p.normalized()), -1.0, 1.0));
  const bool left = al < ar;
  const Vec3 V = left ? Vl : Vr;
  const Vec2 vc = contactPointVelocity(V, r);
  const double k = vn / vc.dot(n);
  out.twist = k * V;
  out.sliding = true;
  // The pusher slips relative to the object along ±t.
  out.slide_side = ((v_p - k * vc).dot(t) >= 0) ? +1 : -1;
  return out;
}

}  // namespace lieservo::sim

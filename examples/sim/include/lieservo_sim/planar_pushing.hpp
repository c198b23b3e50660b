// lieservo_sim/planar_pushing.hpp — quasi-static planar pushing with an ellipsoidal limit
// surface (Goyal et al. 1991; Lynch, Maekawa & Tanie 1992 "motion cone").
//
// Object frame {o}: origin at the centre of mass, x_o y_o in the support plane.  A point
// pusher touches the object at r = (r_x, r_y) (relative to the centre of mass) with outward
// object normal n; it pushes with force f inside the friction cone of half-angle atan μ_c
// about −n.  The ellipsoidal limit surface f_x²/f_max² + f_y²/f_max² + m²/m_max² = 1 gives an
// object twist normal to it, V = (v_x, v_y, ω) ∝ (f_x, f_y, m / c²) with c = m_max / f_max and
// m = r × f.  The velocity of the contact point is v_c = (v_x − ω r_y, v_y + ω r_x).
//
//  * the two friction-cone edges give the motion-cone edges v_l, v_r;
//  * if the pusher velocity v_p lies inside the motion cone the contact STICKS: V solves
//    v_c(V) = v_p, i.e. f = (I + w wᵀ / c²)⁻¹ v_p with w = (−r_y, r_x) and ω = wᵀ f / c²;
//  * otherwise it SLIDES: f is on the nearer cone edge and V is scaled so that the normal
//    components agree, v_c · n = v_p · n;
//  * a pusher that is not moving into the object (v_p · n ≥ 0) moves nothing.
// Works on displacements as well as velocities (the model is rate-independent).
#pragma once

#include "common.hpp"

namespace lieservo::sim {

struct PushOutcome {
  Vec3 twist = Vec3::Zero();  ///< (v_x, v_y, ω) of the object, object frame (same scale as v_p)
  bool sticking = false;
  bool sliding = false;       ///< on a motion-cone edge
  bool separating = false;    ///< v_p · n ≥ 0: no push
  int slide_side = 0;         ///< +1 / −1: which cone edge (sign of the tangential slip)
};

/// r: contact point (object frame, w.r.t. centre of mass); n: outward unit normal at r;
/// v_p: pusher velocity (or displacement) in the object frame; mu: pusher–object friction;
/// c: limit-surface ratio m_max / f_max (> 0).
PushOutcome quasiStaticPush(const Vec2& r, const Vec2& n, const Vec2& v_p, double mu, double c);

/// Contact-point velocity of a planar twist (v_x, v_y, ω) at r.
inline Vec2 contactPointVelocity(const Vec3& V, const Vec2& r) {
  return Vec2(V.x() - V.z() * r.y(), V.y() + V.z() * r.x());
}

}  // namespace lieservo::sim

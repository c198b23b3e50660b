// Contact model (see lieservo_sim/contact_model.hpp).
#include "lieservo_sim/contact_model.hpp"

#include <algorithm>
#include <cmath>

namespace lieservo::sim {

void ContactParams::validate() const {
  requirePositive(tip_radius, "ContactParams.tip_radius");
  requirePositive(min_slip_radius, "ContactParams.min_slip_radius");
  requirePositive(max_slip_radius, "ContactParams.max_slip_radius");
  requirePositive(max_twist, "ContactParams.max_twist");
  if (min_slip_radius > max_slip_radius)
    throw SceneError("ContactParams.min_slip_radius must be <= max_slip_radius");
  if (max_twist >= kPi / 2) throw SceneError("ContactParams.max_twist must be < 90 deg");
  requireNonNegative(skin_friction, "ContactParams.skin_friction");
  requirePositive(gel_stiffness, "ContactParams.gel_stiffness");
  requirePositive(gel_tangential_ratio, "ContactParams.gel_tangential_ratio");
}

ContactModel::ContactModel(const ContactParams& params) : params_(params) { params_.validate(); }

double ContactModel::slipRadius(double depth) const {
  // The gel's slip law (contact_model.hpp): k_t |s| = μ_c k_gel z.
  return std::clamp(params_.skin_friction * depth / params_.gel_tangential_ratio, params_.min_slip_radius,
                    params_.max_slip_radius);
}

ContactModel::Anchor ContactModel::newAnchor(const SurfacePoint& sp, const SE3d& X_os) const {
  Anchor a;
  a.p = sp.point;
  const Vec3 zf = -sp.normal;
  const Mat3 Ros = X_os.rotationMatrix();
  Vec3 x0 = Ros.col(0) - Ros.col(0).dot(zf) * zf;
  if (x0.norm() < 1e-6) x0 = Ros.col(1) - Ros.col(1).dot(zf) * zf;
  x0.normalize();
  const Mat3 Rof0 = fromColumns(x0, zf.cross(x0), zf);
  const Mat3 Rf0s = Rof0.transpose() * Ros;
  const double g0 = std::atan2(Rf0s(1, 0), Rf0s(0, 0));  // γ of Rz(γ)Ry(β)Rx(α)
  a.t = (Rof0 * rotZ(g0)).col(0);
  return a;
}

ContactState ContactModel::evaluate(const SE3d& X_wo, const Anchor& a, const SurfacePoint& sp,
                                    const SE3d& X_os) const {
  ContactState st;
  const double R = params_.tip_radius;
  const Vec3 n = sp.normal, zf = -n;
  Vec3 xf = a.t - a.t.dot(zf) * zf;
  if (xf.norm() < 1e-9) xf = zf.unitOrthogonal();
  xf.normalize();
  const Vec3 yf = zf.cross(xf);
  const Vec3 ds = sp.point - a.p;
  const Vec2 s(ds.dot(xf), ds.dot(yf));
  const Vec3 of = sp.point + R * n - s.x() * xf - s.y() * yf;
  const SE3d X_of = makePose(fromColumns(xf, yf, zf), of);
  st.X_wf = X_wo * X_of;
  st.X_fs = X_of.inverse() * X_os;
  st.depth = R - sp.signed_distance;
  st.in_contact = st.depth > 0;
  const Vec3 zs = X_os.rotationMatrix().col(2);
  st.tilt = std::acos(std::clamp(zs.dot(zf), -1.0, 1.0));
  st.shear = st.X_fs.translation().head<2>();
  st.twist = st.X_fs.so3().toEulerXYZ()[2];
  st.point_w = X_wo * sp.point;
  st.normal_w = X_wo.rotationMatrix() * n;
  return st;
}

ContactState ContactModel::update(const SE3d& X_ws, const SE3d& X_wo, const SurfacePoint& sp) {
  const SE3d X_os = X_wo.inverse() * X_ws;
  const double depth = params_.tip_radius - sp.signed_distance;
  if (depth <= 0) {
    anchored_ = false;
    return evaluate(X_wo, newAnchor(sp, X_os), sp, X_os);
  }
  if (!anchored_) {
    anchor_ = newAnchor(sp, X_os);
    anchored_ = true;
  }
  ContactState st = evaluate(X_wo, anchor_, sp, X_os);
  bool slipped = false;
  // Translational slip: slide the anchor so that |s| = r_slip.
  const double r = st.shear.norm();
  const double rs = slipRadius(depth);
  if (r > rs) {
    const Vec3 zf = -sp.normal;
    Vec3 xf = anchor_.t - anchor_.t.dot(zf) * zf;
    xf.normalize();
    const Vec3 yf = zf.cross(xf);
    const double f = 1.0 - rs / r;
    const Vec3 p_new = anchor_.p + f * (st.shear.x() * xf + st.shear.y() * yf);
    anchor_.p = p_new;
    slipped = true;
  }
  // Rotational slip about the normal: |γ| ≤ γ_max.
  if (std::abs(st.twist) > params_.max_twist) {
    const double excess = st.twist - std::copysign(params_.max_twist, st.twist);
    const Vec3 zf = -sp.normal;
    anchor_.t = Eigen::AngleAxisd(excess, zf) * anchor_.t;
    slipped = true;
  }
  if (slipped) st = evaluate(X_wo, anchor_, sp, X_os);
  st.slipped = slipped;
  return st;
}

ContactState ContactModel::update(const SE3d& X_ws, const SE3d& X_wo, const SurfacePoint& sp, const Vec3& gel_s) {
  ContactState st = update(X_ws, X_wo, sp);
  if (!st.in_contact) return st;
  // The gel's tangential deflection in the contact's tangent plane (object frame), sign
  // flipped: the sensor moved the other way against the stuck skin.
  const Vec3 zf = -sp.normal;
  Vec3 xf = anchor_.t - anchor_.t.dot(zf) * zf;
  xf.normalize();
  const Vec3 yf = zf.cross(xf);
  const SE3d X_os = X_wo.inverse() * X_ws;
  const Vec3 d = X_os.rotationMatrix() * gel_s;
  Vec2 shear(-d.dot(xf), -d.dot(yf));
  if (shear.norm() > params_.max_slip_radius) shear *= params_.max_slip_radius / shear.norm();
  anchor_.p = sp.point - shear.x() * xf - shear.y() * yf;
  const bool slipped = st.slipped;
  st = evaluate(X_wo, anchor_, sp, X_os);
  st.slipped = slipped;
  return st;
}

}  // namespace lieservo::sim

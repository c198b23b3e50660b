// lieservo_sim/contact_model.hpp — true surface contact pose and post-contact shear of a
// hemispherical sensor tip against a rigid surface (paper Section 3.1.1 (sec:surface_contact_poses)).
//
// Geometry.  The sensor frame {s} sits at the centre c of the hemispherical tip (radius R,
// 20 mm for the 40 mm TacTip), z out of the tip.  With the nearest surface point p, outward
// normal n and signed distance d of c, the contact depth is z = R − d (> 0 in contact): the
// tip is "brought into normal contact through distance z".  The tilt is the angle between
// the sensor axis z_s and the inward normal −n (the paper's (α, β)).
//
// Feature frame {f} (z_f = −n, into the surface).  When contact starts, the model records a
// stuck anchor point p_a on the surface and a reference tangent t_a chosen so that the
// contact starts with γ = 0.  Each update builds
//     x_f = t_a projected on the tangent plane at p,  y_f = z_f × x_f,
//     s   = (p − p_a) in (x_f, y_f)                         (translational shear, mm)
//     o_f = p + R n − s                                     ({f} origin: the tip centre at
//                                                           first touch, before the shear)
// so that X_fs = X_wf⁻¹ X_ws has Euler components (x, y, z, α, β, γ) = (s_x, s_y, depth,
// tilt angles, twist): exactly the paper's X_fs = X_∥ X_⊥ with R_fs = Rz(γ) Ry(β) Rx(α).
//
// Friction (stick/slip).  The shear sticks until |s| exceeds the slip radius
//     r_slip(z) = clamp(k_slip · z, r_min, r_max)     (deeper contact → more normal force →
//                                                      larger friction-limited shear)
// and the twist until |γ| exceeds γ_max; beyond that the anchor slides (p_a, t_a move) so the
// shear stays on the limit (kinetic friction), which is what "slip" looks like to the GDN.
// Default r_max = 5 mm and γ_max = 5° are the ranges of the paper's training data
// (Section 3.1.2, sec:data_collection: shear disk radius 5 mm, γ ∈ [−5°, 5°], "chosen to limit slippage").
//
// The anchor lives in the object frame, so a moving object (tracking leader, pushed prism)
// drags the contact with it.  Out of contact (z ≤ 0) the anchor is released.
//
// The nearest point comes from the physics engine (World::tipGeometry, passed to update() as a
// SurfacePoint in the object frame); a slipping anchor moves on the tangent plane of the
// current contact.
#pragma once

#include "common.hpp"

namespace lieservo::sim {

/// The surface point nearest to the tip centre, in the object's frame.
struct SurfacePoint {
  Vec3 point = Vec3::Zero();    ///< nearest surface point (object frame)
  Vec3 normal = Vec3::UnitZ();  ///< outward unit normal at `point`
  double signed_distance = 0;   ///< of the tip centre; > 0 outside the solid
};

struct ContactParams {
  double tip_radius = 20.0;           ///< R (mm): 40 mm diameter hemispherical TacTip
  double slip_radius_per_depth = 1.5; ///< k_slip (mm of shear per mm of depth)
  double min_slip_radius = 0.5;       ///< r_min (mm)
  double max_slip_radius = 5.0;       ///< r_max (mm): paper's shear training radius
  double max_twist = deg(5.0);        ///< γ_max (rad): paper's γ training range
  /// μ_c, skin–object sliding friction in the MuJoCo scenes: the TacTip's rubber-like skin
  /// (Agilus 30, paper sec. on the sensor) on smooth plastic; assumed (rubber on plastic is
  /// typically 0.5–1), not measured. docs/simulation.md reports the results' sensitivity to it.
  double skin_friction = 0.8;

  void validate() const;              ///< throws SceneError
};

struct ContactState {
  bool in_contact = false;
  SE3d X_fs = SE3d::identity();  ///< true contact pose of {s} in {f}
  SE3d X_wf = SE3d::identity();  ///< feature frame in the work frame
  double depth = 0;              ///< z = R − d (mm); ≤ 0 out of contact
  double tilt = 0;               ///< angle of z_s from the inward normal (rad)
  Vec2 shear = Vec2::Zero();     ///< (x, y) translational shear (mm)
  double twist = 0;              ///< γ (rad)
  Vec3 point_w = Vec3::Zero();   ///< nearest surface point (work frame)
  Vec3 normal_w = Vec3::UnitZ(); ///< outward normal (work frame)
  bool slipped = false;          ///< the anchor slid during this update
  /// Euler 6-vector (x, y, z, α, β, γ) of X_fs (mm, rad): the GDN training label.
  Vec6 label() const { return euler6(X_fs); }
};

class ContactModel {
 public:
  /// Throws SceneError for bad parameters.
  explicit ContactModel(const ContactParams& params = {});

  /// Evaluates the contact of the sensor at X_ws with the object at X_wo, whose surface point
  /// nearest to the tip centre is `sp` (object frame); updates the stick/slip anchor. Never
  /// throws.
  ContactState update(const SE3d& X_ws, const SE3d& X_wo, const SurfacePoint& sp);
  /// Forget the anchor (the next contact starts unsheared).
  void release() { anchored_ = false; }
  bool anchored() const { return anchored_; }
  const ContactParams& params() const { return params_; }
  double slipRadius(double depth) const;

 private:
  struct Anchor {
    Vec3 p = Vec3::Zero();
    Vec3 t = Vec3::UnitX();
  };
  ContactState evaluate(const SE3d& X_wo, const Anchor& a, const SurfacePoint& sp,
                        const SE3d& X_os) const;
  Anchor newAnchor(const SurfacePoint& sp, const SE3d& X_os) const;

  ContactParams params_;
  bool anchored_ = false;
  Anchor anchor_;
};

}  // namespace lieservo::sim

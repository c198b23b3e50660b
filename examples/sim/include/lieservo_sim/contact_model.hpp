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
// Friction (stick/slip): one law with the engine's gel contact. The gel (mujoco_world.hpp)
// is a spring of stiffness k_gel along the sensor axis and k_t = ρ_t k_gel across it, so a
// contact at depth z presses with N ≈ k_gel z and a sticking shear s pulls sideways with
// k_t |s|; it slides when k_t |s| > μ_c N, i.e. beyond the slip radius
//     r_slip(z) = clamp(μ_c z / ρ_t, r_min, r_max)       (μ_c: skin_friction, ρ_t:
//                                                           gel_tangential_ratio)
// and the twist beyond γ_max; then the anchor slides (p_a, t_a move) so the shear stays on
// the limit (kinetic friction), which is what "slip" looks like to the GDN. r_max = 5 mm and
// γ_max = 5° are the ranges of the paper's training data (Section 3.1.2, sec:data_collection:
// shear disk radius 5 mm, γ ∈ [−5°, 5°], "chosen to limit slippage"), beyond which the GDN
// has seen no image. The gel has no torsional spring, so γ_max is the model's own.
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

/// The gel's tangential over normal stiffness: Mindlin's ratio 2(1 − ν)/(2 − ν) for an
/// elastic contact, 2/3 for an incompressible gel (ν = 0.5). With μ_c = 0.8 the contact slips
/// beyond 1.2 z, which is where the real TacTip data's shear saturates (docs/simulation.md,
/// "The gel and its slip, from the data").
inline constexpr double kGelTangentialRatio = 2.0 / 3.0;
/// k_gel (N/mm): the secant F/d of a Hertz contact of the 20 mm tip (E* ≈ 0.1 MPa, assumed:
/// F = (4/3) E* √R d^1.5) at the 1.5–2.5 N of a push.
inline constexpr double kGelStiffness = 0.8;

struct ContactParams {
  double tip_radius = 20.0;           ///< R (mm): 40 mm diameter hemispherical TacTip
  double min_slip_radius = 0.05;      ///< r_min (mm)
  double max_slip_radius = 5.0;       ///< r_max (mm): paper's shear training radius
  double max_twist = deg2rad(5.0);        ///< γ_max (rad): paper's γ training range
  /// μ_c, skin–object sliding friction, in the MuJoCo scenes and in the slip radius: the
  /// TacTip's rubber-like skin (Agilus 30, paper Section 4.2, sec:tactile_sensor) on smooth
  /// plastic; assumed (rubber on plastic is typically 0.5–1), not measured. docs/simulation.md
  /// reports the results' sensitivity to it.
  double skin_friction = 0.8;
  /// k_gel (N/mm): the gel's normal force per mm of contact depth (mujoco::SensorSpec).
  double gel_stiffness = kGelStiffness;
  /// ρ_t = k_t / k_gel: the gel's tangential stiffness over its normal one (mujoco::SensorSpec).
  double gel_tangential_ratio = kGelTangentialRatio;

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
  Vec6 label() const { return X_fs.toEulerXYZ6(); }
};

class ContactModel {
 public:
  /// Throws SceneError for bad parameters.
  explicit ContactModel(const ContactParams& params = {});

  /// Evaluates the contact of the sensor at X_ws with the object at X_wo, whose surface point
  /// nearest to the tip centre is `sp` (object frame); updates the stick/slip anchor. Never
  /// throws.
  ContactState update(const SE3d& X_ws, const SE3d& X_wo, const SurfacePoint& sp);
  /// As above, with the translational shear read from the physics engine's gel: `gel_s` is
  /// where the touching tip sits relative to the arm's nominal tip (mm, sensor frame;
  /// mujoco::World::gelDeflection). The shear is the sensor's displacement against its
  /// contact, i.e. minus the gel's tangential deflection (clipped at max_slip_radius, the data's
  /// range); the anchor follows it, so the engine's stick, slip and creep are what is observed.
  ContactState update(const SE3d& X_ws, const SE3d& X_wo, const SurfacePoint& sp, const Vec3& gel_s);
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

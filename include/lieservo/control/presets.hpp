// lieservo/control/presets.hpp — the paper's controller parameters (Appendix
// Appendix D (sec:controller_parameters), Tables 6–9) stored in the paper's units and converted to the
// library's units in code.
//
// Paper units: translations in mm, angles in degrees (reference poses as extrinsic-xyz Euler
// 6-vectors (x, y, z, α, β, γ)), velocities in mm/s and deg/s, the bearing error in degrees.
// The paper's high-level loop was (we assume) a per-step PID: integral = Σ e over steps,
// derivative = Δē per step (as in the group's earlier tactile-servoing code), so Ki, Kd and
// the integral clipping bounds are per control step.
//
// Library units: translations in the caller's unit (mm here), angles in radians, time in
// seconds, gains per second (pid.hpp).  Conversions (T = assumed paper control period):
//   Kp            unchanged (mm→mm/s and rad→rad/s are both "per second"; deg→deg/s too)
//   Ki            Ki_step / T
//   Kd            Kd_step · T
//   integral clip c_step · T on translational channels (mm·s),
//                 c_step · (π/180) · T on rotational channels (rad·s)
//   output clip   velocity bounds: mm/s unchanged, deg/s × π/180
//   ref pose      SE3::fromEulerXYZ6Degrees (mm unchanged, degrees → radians)
//   feedforward   mm/s unchanged, deg/s × π/180
//   bearing PID   (deg → mm/s): Kp, Ki, Kd × 180/π (then the per-step conversion);
//                 integral clip × π/180 (and × T); output clip (mm/s) unchanged
//   EWMA          the per-step weight 0.5 becomes the time constant τ = −T / ln(1 − 0.5)
// With PaperGainConvention::per_step = false the paper's Ki, Kd and clips are taken to be
// per second already, and only the unit conversions apply.  See docs/control.md.
#pragma once
#include <lieservo/detail/options_push.hpp>

#include <cmath>
#include <limits>

#include <Eigen/Core>

#include <lieservo/control/pid.hpp>
#include <lieservo/control/pushing_controller.hpp>
#include <lieservo/control/tactile_servo_controller.hpp>
#include <lieservo/groups/se3.hpp>
#include <lieservo/units.hpp>

namespace lieservo {
namespace paper {

/// "Not used" in a clipping row.
inline constexpr double kNoClip = std::numeric_limits<double>::infinity();

/// A MIMO (6-channel, [v; ω]) controller table in the paper's units, per control step.
struct MimoTable {
  const char* label;             ///< the table's LaTeX label in the paper
  double kp[6];                  ///< 1/s
  double ki[6];                  ///< per step (u per Σe)
  double kd[6];                  ///< per step (u per Δē)
  double integral_clip;          ///< symmetric [−c, c], all components (mm·step, deg·step)
  double reference_pose[6];      ///< X_fs': (x, y, z) mm, (α, β, γ) deg, extrinsic xyz
  double feedforward[6];         ///< u_s'2: mm/s, deg/s
};

/// The SISO target-alignment table (PID 2) in the paper's units, per control step.
struct SisoTable {
  const char* label;         ///< the table's LaTeX label in the paper
  double kp;                 ///< mm/s per deg
  double ki_single_arm;      ///< per step
  double ki_dual_arm;        ///< per step
  double kd;                 ///< per step
  double integral_clip;      ///< deg·step
  double output_clip;        ///< mm/s
  double reference_bearing;  ///< deg
};

/// Table 6 (tab:object_tracking_control_params) (object tracking, follower arm).
inline constexpr MimoTable kObjectTracking{
    "Table 6 (tab:object_tracking_control_params)",
    {5, 5, 5, 2, 2, 0},
    {0.5, 0.5, 0.5, 0.2, 0.2, 0.2},
    {0.5, 0.5, 0.5, 0.2, 0.2, 0.2},
    kNoClip,
    {0, 0, 6, 0, 0, 0},
    {0, 0, 0, 0, 0, 0}};

/// Table 7 (tab:surface_follow_control_params) (surface following).  The feedforward is
/// task-dependent: here the curved-ramp value u_s'2 = (0, 10, 0, 0, 0, 0)
/// (Section 5.5.1, sec:surface_follow_ramp); the dome uses (10 cos θi, 10 sin θi, 0, 0, 0, 0).
inline constexpr MimoTable kSurfaceFollowing{
    "Table 7 (tab:surface_follow_control_params)",
    {0, 0, 2, 2, 2, 0},
    {0, 0, 0.1, 0.1, 0.1, 0},
    {0, 0, 0.05, 0.05, 0.05, 0},
    25,
    {0, 0, 3, 0, 0, 0},
    {0, 10, 0, 0, 0, 0}};

/// Table 8 (tab:pushing_control_params), PID 1 (MIMO tactile servoing of the pusher).
inline constexpr MimoTable kPushingServo{
    "Table 8 (tab:pushing_control_params)",
    {1, 0, 0, 1, 0, 0},
    {0.1, 0, 0, 0.1, 0, 0},
    {0.1, 0, 0, 0.1, 0, 0},
    25,
    {0, 0, 0, 0, 0, 0},
    {0, 0, 10, 0, 0, 0}};

/// Table 8 (tab:pushing_control_params), PID 2 (SISO target alignment).
inline constexpr SisoTable kPushingAlignment{
    "Table 8 (tab:pushing_control_params)", 0.9, 0.3, 0.5, 0.9, 10, 15, 0};

/// Table 9 (tab:stabiliser_control_params) (dual-arm follower, stabilising servoing).
inline constexpr MimoTable kStabiliser{
    "Table 9 (tab:stabiliser_control_params)",
    {5, 0, 5, 1, 0, 0},
    {0.5, 0, 0.5, 0.1, 0, 0},
    {0.5, 0, 0.5, 0.1, 0, 0},
    200,
    {0, 0, 3, 0, 0, 0},
    {0, 0, 0, 0, 0, 0}};

/// Section 5.7.2 (sec:dual_arm_tall_object_pushing): modified reference poses for tall objects (the first
/// component moved by ±0.5 mm): leader (pusher) and follower (stabiliser).
inline constexpr double kTallObjectLeaderReference[6] = {0.5, 0, 0, 0, 0, 0};     ///< leader (pusher)
inline constexpr double kTallObjectFollowerReference[6] = {-0.5, 0, 3, 0, 0, 0};  ///< follower (stabiliser)

/// Surface-following speed (mm/s) of Section 5.5.1 (sec:surface_follow_ramp) / Section 5.5.2 (sec:surface_follow_hemisphere).
inline constexpr double kSurfaceFollowingSpeed = 10;
/// The paper's EWMA decay coefficient (Section 3.3.1, sec:tangent_space_control), per control step.
inline constexpr double kSmoothing = 0.5;
/// Alignment cut-off ρ* (mm) and termination radius (mm) of Section 3.3.3 (sec:pushing_controller).
inline constexpr double kAlignmentCutoff = 120;   ///< ρ* (mm)
inline constexpr double kTerminationRadius = 20;  ///< tip radius (mm)

}  // namespace paper

/// How the paper's per-step gains carry over (docs/control.md, "How the paper's gains carry over").
struct PaperGainConvention {
  /// Assumed period (s) of the paper's high-level control loop.  The paper does not state
  /// it (only the 1 kHz libfranka loop); 1/20 s is our assumption (camera-rate loop with
  /// GDN inference and filtering in Python).  Change it to re-derive the gains.
  double control_period = 1.0 / 20.0;
  /// true: the paper's Ki, Kd and integral clips are per step (Σe, Δē) → convert with T.
  /// false: take them as per-second values (unit conversions only).
  bool per_step = true;
  /// true: express the paper's per-step EWMA weight 0.5 as the time constant it has at
  /// control_period (rate-independent smoothing); false: keep α = 0.5 per step.
  bool smoothing_as_time_constant = true;
};

namespace detail {
template <class Scalar>
Eigen::Matrix<Scalar, 6, 1> toVec(const double (&v)[6]) {
  Eigen::Matrix<Scalar, 6, 1> r;
  for (int i = 0; i < 6; ++i) r[i] = Scalar(v[i]);
  return r;
}
inline double stepPeriod(const PaperGainConvention& c) { return c.per_step ? c.control_period : 1.0; }
}  // namespace detail

/// A reference pose given as a paper Euler 6-vector (mm, degrees) → SE3 (mm, radians).
template <class Scalar>
SE3<Scalar> paperPose(const double (&pose_mm_deg)[6]) {
  return SE3<Scalar>::fromEulerXYZ6Degrees(detail::toVec<Scalar>(pose_mm_deg));
}

/// A twist in paper units (mm/s, deg/s) → library units (mm/s, rad/s).
template <class Scalar>
Eigen::Matrix<Scalar, 6, 1> paperTwist(const double (&twist_mm_deg)[6]) {
  Eigen::Matrix<Scalar, 6, 1> v = detail::toVec<Scalar>(twist_mm_deg);
  for (int i = 3; i < 6; ++i) v[i] = deg2rad(v[i]);
  return v;
}

/// EWMA smoothing settings for the paper's per-step weight under `c`.
template <class Scalar, class PidOptions>
void applyPaperSmoothing(PidOptions& o, const PaperGainConvention& c) {
  o.smoothing = Scalar(paper::kSmoothing);
  o.smoothing_time_constant = Scalar(0);
  if (c.smoothing_as_time_constant)
    o.smoothing_time_constant = Scalar(-c.control_period / std::log(1.0 - paper::kSmoothing));
}

/// A MIMO table → MimoPid<Scalar, 6>::Options in library units.
template <class Scalar>
typename MimoPid<Scalar, 6>::Options paperMimoPid(const paper::MimoTable& t,
                                                  const PaperGainConvention& c = {}) {
  using Vec = Eigen::Matrix<Scalar, 6, 1>;
  const double T = detail::stepPeriod(c);
  Vec kp = detail::toVec<Scalar>(t.kp);
  Vec ki = detail::toVec<Scalar>(t.ki) / Scalar(T);
  Vec kd = detail::toVec<Scalar>(t.kd) * Scalar(T);
  auto o = MimoPid<Scalar, 6>::Options::diagonal(kp, ki, kd);
  for (int i = 0; i < 6; ++i) {
    double clip = t.integral_clip * T;       // mm·step → mm·s
    if (i >= 3) clip = deg2rad(clip);        // deg·step → rad·s
    o.integral_min[i] = Scalar(-clip);
    o.integral_max[i] = Scalar(clip);
  }
  applyPaperSmoothing<Scalar>(o, c);
  return o;
}

/// The SISO alignment table → SisoPid<Scalar>::Options (bearing error in rad → u_y in mm/s).
template <class Scalar>
typename SisoPid<Scalar>::Options paperAlignmentPid(bool dual_arm, const PaperGainConvention& c = {}) {
  const paper::SisoTable& t = paper::kPushingAlignment;
  const double T = detail::stepPeriod(c);
  const double per_rad = rad2deg(1.0);  // (mm/s per deg) → (mm/s per rad): × 180/π
  typename SisoPid<Scalar>::Options o;
  o.kp = Scalar(t.kp * per_rad);
  o.ki = Scalar((dual_arm ? t.ki_dual_arm : t.ki_single_arm) * per_rad / T);
  o.kd = Scalar(t.kd * per_rad * T);
  o.integral_min = Scalar(-deg2rad(t.integral_clip) * T);
  o.integral_max = Scalar(deg2rad(t.integral_clip) * T);
  o.output_min = Scalar(-t.output_clip);
  o.output_max = Scalar(t.output_clip);
  applyPaperSmoothing<Scalar>(o, c);
  return o;
}

/// A MIMO table → tactile servoing options on SE3 (reference pose and feedforward included).
template <class Scalar>
typename TactileServoController<SE3<Scalar>>::Options paperServoOptions(
    const paper::MimoTable& t, const PaperGainConvention& c = {}) {
  typename TactileServoController<SE3<Scalar>>::Options o;
  o.pid = paperMimoPid<Scalar>(t, c);
  o.reference = paperPose<Scalar>(t.reference_pose);
  o.feedforward = paperTwist<Scalar>(t.feedforward);
  return o;
}

/// Table 6 (tab:object_tracking_control_params): object tracking, zero feedforward.
template <class Scalar>
typename TactileServoController<SE3<Scalar>>::Options objectTrackingPreset(const PaperGainConvention& c = {}) {
  return paperServoOptions<Scalar>(paper::kObjectTracking, c);
}

/// Surface-following feedforward u_s'2 = (speed cos θ, speed sin θ, 0, 0, 0, 0): heading θ
/// (rad) in the xy-plane of the reference sensor frame (Section 5.5.2, sec:surface_follow_hemisphere;
/// the ramp is θ = π/2).
template <class Scalar>
Eigen::Matrix<Scalar, 6, 1> surfaceFollowingFeedforward(Scalar heading, Scalar speed = Scalar(paper::kSurfaceFollowingSpeed)) {
  Eigen::Matrix<Scalar, 6, 1> v = Eigen::Matrix<Scalar, 6, 1>::Zero();
  v[0] = speed * std::cos(heading);
  v[1] = speed * std::sin(heading);
  return v;
}

/// Table 7 (tab:surface_follow_control_params) with the curved-ramp feedforward (0, 10, 0, 0, 0, 0).
template <class Scalar>
typename TactileServoController<SE3<Scalar>>::Options surfaceFollowingPreset(const PaperGainConvention& c = {}) {
  return paperServoOptions<Scalar>(paper::kSurfaceFollowing, c);
}

/// Which pushing experiment (Section 5.6, sec:single_arm_object_pushing_exp, Section 5.7 (sec:dual_arm_object_pushing_exp)).
enum class PushingConfiguration {
  single_arm,                   ///< Table 8, Ki(PID 2) = 0.3
  dual_arm_leader,              ///< Table 8, Ki(PID 2) = 0.5
  dual_arm_leader_tall_object,  ///< as dual_arm_leader, reference pose (0.5, 0, 0, 0, 0, 0)
};

/// Table 8 (tab:pushing_control_params): PID 1 + PID 2, ρ* = 120 mm, termination radius 20 mm.
/// The target X_wt is task-specific (paper: (y, z) = (0, 375) mm in the work frame): set
/// Options::target or call PushingController::setTarget.
template <class Scalar>
typename PushingController<SE3<Scalar>>::Options pushingPreset(
    PushingConfiguration config = PushingConfiguration::single_arm, const PaperGainConvention& c = {}) {
  typename PushingController<SE3<Scalar>>::Options o;
  o.servo = paperServoOptions<Scalar>(paper::kPushingServo, c);
  if (config == PushingConfiguration::dual_arm_leader_tall_object)
    o.servo.reference = paperPose<Scalar>(paper::kTallObjectLeaderReference);
  o.alignment = paperAlignmentPid<Scalar>(config != PushingConfiguration::single_arm, c);
  o.reference_bearing = Scalar(deg2rad(paper::kPushingAlignment.reference_bearing));
  o.alignment_cutoff = Scalar(paper::kAlignmentCutoff);
  o.termination_radius = Scalar(paper::kTerminationRadius);
  return o;
}

/// Table 9 (tab:stabiliser_control_params): the dual-arm follower; `tall_object` selects the
/// reference pose (−0.5, 0, 3, 0, 0, 0) of Section 5.7.2 (sec:dual_arm_tall_object_pushing).
template <class Scalar>
typename TactileServoController<SE3<Scalar>>::Options stabiliserPreset(bool tall_object = false,
                                                                      const PaperGainConvention& c = {}) {
  auto o = paperServoOptions<Scalar>(paper::kStabiliser, c);
  if (tall_object) o.reference = paperPose<Scalar>(paper::kTallObjectFollowerReference);
  return o;
}

}  // namespace lieservo

#include <lieservo/detail/options_pop.hpp>

// lieservo_sim/panda_kinematics.hpp — the Franka Emika Panda's kinematic chain, for the
// simulated robot behind the Franka adapter (docs/hardware.md).
//
// The 7 revolute joints with Franka's published parameters (modified Denavit–Hartenberg,
// Craig's convention: T_i = Rot_x(α_i) · Trans_x(a_i) · Rot_z(q_i) · Trans_z(d_i)), the
// flange 0.107 m along joint 7's axis, and the joint limits of Franka's datasheet. Units are
// libfranka's: metres, radians, seconds; the base frame {O} is libfranka's, so flange(q) is
// libfranka's O_T_EE for an end effector configured at the flange.
//
// Resolved-rate control maps a commanded end-effector twist to joint velocities by damped
// least squares, dq = Jᵀ (J Jᵀ + λ² I)⁻¹ v, with λ raised only near a singularity, and the
// result scaled down as a whole (direction kept) to the joint velocity limits.
#pragma once

#include <array>

#include <Eigen/Core>

namespace lieservo::sim::panda {

constexpr int kJoints = 7;
using Joints = Eigen::Matrix<double, kJoints, 1>;
using Jacobian = Eigen::Matrix<double, 6, kJoints>;  ///< rows [v; ω] in {O}, v of the flange origin
using Twist = Eigen::Matrix<double, 6, 1>;          ///< [v (m/s); ω (rad/s)] in {O}

/// One row of the modified DH table (metres, radians).
struct Link {
  double a, d, alpha;
};

/// Franka's table, joints 1–7, then the flange (q = 0).
inline constexpr std::array<Link, kJoints + 1> kLinks{{{0.0, 0.333, 0.0},
                                                       {0.0, 0.0, -1.5707963267948966},
                                                       {0.0, 0.316, 1.5707963267948966},
                                                       {0.0825, 0.0, 1.5707963267948966},
                                                       {-0.0825, 0.384, -1.5707963267948966},
                                                       {0.0, 0.0, 1.5707963267948966},
                                                       {0.088, 0.0, 1.5707963267948966},
                                                       {0.0, 0.107, 0.0}}};

/// Joint position limits (rad) and velocity limits (rad/s) of Franka's datasheet.
inline const Joints& lowerLimits() {
  static const Joints q = (Joints() << -2.8973, -1.7628, -2.8973, -3.0718, -2.8973, -0.0175, -2.8973).finished();
  return q;
}
inline const Joints& upperLimits() {
  static const Joints q = (Joints() << 2.8973, 1.7628, 2.8973, -0.0698, 2.8973, 3.7525, 2.8973).finished();
  return q;
}
inline const Joints& velocityLimits() {
  static const Joints dq = (Joints() << 2.1750, 2.1750, 2.1750, 2.1750, 2.6100, 2.6100, 2.6100).finished();
  return dq;
}

/// Franka's "ready" configuration: the flange 0.307 m in front of the base, pointing down.
inline Joints readyPose() {
  return (Joints() << 0.0, -0.785398163397, 0.0, -2.35619449019, 0.0, 1.57079632679, 0.785398163397).finished();
}

/// One step of the chain: Rot_x(α) · Trans_x(a) · Rot_z(θ) · Trans_z(d) (Craig's convention).
Eigen::Matrix4d linkTransform(const Link& link, double theta);

/// The flange pose in {O} (O_T_EE with the end effector at the flange).
Eigen::Matrix4d flange(const Joints& q);

/// The geometric Jacobian at the flange: twist [v; ω] in {O} = J(q) · dq.
Jacobian jacobian(const Joints& q);

/// Yoshikawa's manipulability √det(J Jᵀ) (m³/rad³ scale): 0 at a singularity.
double manipulability(const Jacobian& J);

/// The smallest distance of q to a position limit (rad); negative outside the limits.
double jointLimitMargin(const Joints& q);

struct ResolvedRateOptions {
  double damping = 0.05;           ///< λ at a singularity (m); λ = 0 where σ_min ≥ singular_band
  double singular_band = 0.05;     ///< σ_min (of J) below which damping fades in
};

struct ResolvedRate {
  Joints dq = Joints::Zero();  ///< joint velocities (rad/s), within velocityLimits()
  double lambda = 0.0;         ///< the damping used
  double sigma_min = 0.0;      ///< J's smallest singular value
  double scale = 1.0;          ///< ≤ 1: how far dq was scaled down to the velocity limits
  /// Where damping acts (lambda > 0): max_i |dq_i| / limit_i of the undamped minimum-norm
  /// solution J⁺v, the joint speed an arm that follows the twist exactly would need (infinite
  /// at a singularity the twist pushes into); 0 where lambda = 0 (dq is then that solution).
  double exact_speed_ratio = 0.0;
};

/// dq for the flange twist v at q (damped least squares, scaled to the velocity limits).
ResolvedRate resolvedRate(const Joints& q, const Twist& v, const ResolvedRateOptions& options = {});

}  // namespace lieservo::sim::panda

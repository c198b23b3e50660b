// lieservo/realtime/velocity_smoother.hpp — jerk-limited Cartesian velocity smoother.
//
// The paper's rig (Section 4.4, sec:software) runs libfranka's 1 kHz Cartesian velocity callback
// under an in-house smoother that keeps the commanded velocity, acceleration and jerk
// inside limits. This is lieservo's version of that layer: it tracks a target twist
// [v; ω] (translation first) as fast as the limits allow, reaches the target with zero
// acceleration, and never overshoots a target approached along a straight line.
//
// Limits are applied to the Euclidean NORMS of the linear and the angular parts
// (two independent 3-D limiters). Norm limits imply the same per-axis limits
// (|x_i| <= ||x||), so a per-axis check (as a robot controller may do) passes too;
// they are frame-independent (the same in base and sensor coordinates) and keep the
// direction of straight-line motions. See docs/hardware.md for the full rationale.
//
// Guarantees (the acceleration/jerk are the finite differences that a 1 kHz robot
// controller sees: a_k = (v_k − v_{k−1})/dt_k, j_k = (a_k − a_{k−1})/dt_k):
//   ||v_k|| <= V, ||a_k|| <= A, ||j_k|| <= J for each part, for any input sequence,
//   starting from reset() (or from a state given to reset(v, a) that satisfies them and
//   can still brake inside V — checked), at a CONSTANT dt (the robot's command period).
//   All bounds hold up to floating-point rounding (relative ~1e-12). If dt varies from
//   step to step, the acceleration and jerk bounds still hold exactly, but the velocity
//   bound only approximately (the braking plan assumed the current dt; measured < 1% over
//   for dt in [0.5, 3] ms) — the libfranka adapter always steps with the fixed 1 ms.
//
// Algorithm, per part, per step (discrete time, step T):
//   1. Clamp the target w to the velocity ball ||w|| <= V (direction kept).
//   2. Desired acceleration along the error e = w − v: the largest magnitude a* such that
//      taking a* now and then braking at full jerk brings the velocity exactly to w with
//      zero acceleration (closed form of the discrete braking sum, `brakeInverse`).
//   3. Move the acceleration towards a* inside the jerk ball ||a' − a|| <= J T, then
//      keep it inside ||a'|| <= A (along the segment from a, which is feasible).
//   4. Velocity invariant: the velocity of the full-jerk braking plan from the new state
//      must stay inside ||·|| <= V; if not, back off along the segment towards the
//      braking step (always feasible) by a fixed 48-step bisection (bounded time).
//   In one dimension steps 2–3 are the exact time-optimal discrete rule
//   a' = clamp(a*, a − JT, a + JT) ∩ [−A, A], which never overshoots a constant target and
//   handles reversing targets (it brakes at full jerk first); step 4 never triggers then.
//
// Real-time contract: noexcept, no allocation, Status on bad input with state unchanged.
#pragma once
#include <lieservo/detail/options_push.hpp>

#include <lieservo/configurable.hpp>
#include <lieservo/status.hpp>

#include <Eigen/Core>
#include <cmath>

namespace lieservo::realtime {

/// Velocity, acceleration and jerk limits of one part (linear or angular). Valid: each in
/// [1e-9, 1e9] and the acceleration ramp A/J at most 1000 s. Within these bounds, and at a step
/// dt in [1e-6, 1] s (VelocitySmoother::step), no product the smoother forms overflows, in
/// float as in double; any robot's limits, in m or mm, are far inside them.
template <typename Scalar = double>
struct AxisLimits {
  Scalar velocity;  ///< |v| limit (units/s)
  Scalar acceleration;  ///< |a| limit (units/s²)
  Scalar jerk;  ///< |j| limit (units/s³)
  /// ok, non_finite_input (a NaN or infinite limit) or invalid_argument (outside the bounds).
  Status validate() const noexcept {
    if (!std::isfinite(velocity) || !std::isfinite(acceleration) || !std::isfinite(jerk))
      return Status::non_finite_input;
    const auto inRange = [](Scalar x) { return x >= Scalar(1e-9) && x <= Scalar(1e9); };
    if (!inRange(velocity) || !inRange(acceleration) || !inRange(jerk) || !(acceleration <= Scalar(1e3) * jerk))
      return Status::invalid_argument;
    return Status::ok;
  }
};

/// Limits of a twist [v; ω]: translation (length units/s, /s², /s³) and rotation (rad/s, …).
///
/// The default values are conservative limits for a collaborative arm in SI units (m, rad):
/// translation 0.25 m/s, 2.5 m/s², 250 m/s³; rotation 0.8 rad/s, 5 rad/s², 500 rad/s³ (a
/// robot's adapter checks them against its documented limits with within(), e.g.
/// examples/franka/franka_frames.hpp).
/// Tactile servoing in the paper moves at ~10–25 mm/s, far inside these.
template <typename Scalar = double>
struct SmootherLimits {
  AxisLimits<Scalar> translation{Scalar(0.25), Scalar(2.5), Scalar(250)};  ///< linear part (length units)
  AxisLimits<Scalar> rotation{Scalar(0.8), Scalar(5), Scalar(500)};  ///< angular part (rad)

  /// ok, or the first axis's AxisLimits::validate() Status (translation, then rotation).
  Status validate() const noexcept {
    const Status s = translation.validate();
    return s != Status::ok ? s : rotation.validate();
  }

  /// Every limit of *this is <= the corresponding one of `outer`.
  bool within(const SmootherLimits& outer) const noexcept {
    auto le = [](const AxisLimits<Scalar>& a, const AxisLimits<Scalar>& b) {
      return a.velocity <= b.velocity && a.acceleration <= b.acceleration && a.jerk <= b.jerk;
    };
    return le(translation, outer.translation) && le(rotation, outer.rotation);
  }
};

namespace detail {

/// Jerk-limited limiter for one 3-vector under norm limits (see the file comment).
template <typename Scalar>
class NormLimiter3 {
 public:
  using Vec3 = Eigen::Matrix<Scalar, 3, 1>;

  void reset() noexcept {
    v_.setZero();
    a_.setZero();
  }
  void set(const Vec3& v, const Vec3& a) noexcept {
    v_ = v;
    a_ = a;
  }
  const Vec3& velocity() const noexcept { return v_; }
  const Vec3& acceleration() const noexcept { return a_; }

  /// Velocity gained after the current step when the acceleration magnitude x is brought to
  /// zero at full jerk J with step T: T Σ_{i>=1} max(x − iJT, 0) (the final partial step to 0
  /// adds nothing).
  static Scalar brakeTail(Scalar x, Scalar J, Scalar T) noexcept {
    const Scalar jt = J * T;
    if (!(x > jt)) return Scalar(0);
    const Scalar m = std::floor(x / jt);
    return T * (m * x - jt * m * (m + Scalar(1)) / Scalar(2));
  }

  /// Inverse of g(x) = T x + brakeTail(x): the acceleration x >= 0 to take now so that
  /// braking afterwards changes the velocity by exactly e >= 0. g is continuous, strictly
  /// increasing and piecewise linear (slope T (m+1) on [mJT, (m+1)JT]).
  static Scalar brakeInverse(Scalar e, Scalar J, Scalar T) noexcept {
    if (!(e > Scalar(0))) return Scalar(0);
    const Scalar c = J * T * T;  // g(m J T) = c m (m+1)/2
    const Scalar x = e / c;
    Scalar m = std::floor((std::sqrt(Scalar(1) + Scalar(8) * x) - Scalar(1)) / Scalar(2));
    if (m < Scalar(0)) m = Scalar(0);
    // Guard the rounding of the square root (at most one step either way).
    if ((m + Scalar(1)) * (m + Scalar(2)) / Scalar(2) <= x) m += Scalar(1);
    if (m > Scalar(0) && m * (m + Scalar(1)) / Scalar(2) > x) m -= Scalar(1);
    return m * J * T + (e - c * m * (m + Scalar(1)) / Scalar(2)) / (T * (m + Scalar(1)));
  }

  /// One step towards `target` (finite, checked by the caller) with limits `lim` and step T.
  void step(const Vec3& target, const AxisLimits<Scalar>& lim, Scalar T) noexcept {
    const Scalar V = lim.velocity, A = lim.acceleration, J = lim.jerk;
    // The target clamped onto the velocity ball along its direction. A component beyond V is
    // scaled down first, so that the norm of a huge target (1e200) cannot overflow to ∞ and
    // turn the direction into 0.
    Vec3 w = target;
    const Scalar big = w.cwiseAbs().maxCoeff();
    if (big > V) w /= big;
    const Scalar nw = w.norm();
    if (big > V || nw > V) w *= V / nw;

    // 2. Desired acceleration along the error.
    const Vec3 e = w - v_;
    const Scalar ne = e.norm();
    Vec3 a_des = Vec3::Zero();
    if (ne > Scalar(0)) {
      const Scalar mag = std::fmin(brakeInverse(ne, J, T), A);
      a_des = e * (mag / ne);
    }

    // 3. Jerk ball around a_, then the acceleration ball (along the segment from a_).
    const Scalar r = J * T;
    Vec3 a_new = a_des;
    bool exact = true;  // a_new == a_des (no limit was active)
    const Vec3 d = a_des - a_;
    const Scalar nd = d.norm();
    if (nd > r) {
      a_new = a_ + d * (r / nd);
      exact = false;
    }
    if (a_new.squaredNorm() > A * A) {
      a_new = a_ + (a_new - a_) * segmentToBall(a_, a_new - a_, A);
      exact = false;
    }

    // 4. Velocity invariant, with the full-jerk braking step as the always-feasible fallback.
    if (!feasible(a_new, V, J, T)) {
      exact = false;
      const Scalar na = a_.norm();
      const Vec3 a_brake = na > r ? Vec3(a_ * ((na - r) / na)) : Vec3::Zero();
      Scalar lo = 0, hi = 1;
      const Vec3 dir = a_new - a_brake;
      for (int i = 0; i < 48; ++i) {
        const Scalar mid = Scalar(0.5) * (lo + hi);
        if (feasible(a_brake + dir * mid, V, J, T))
          lo = mid;
        else
          hi = mid;
      }
      a_new = a_brake + dir * lo;
    }

    // Landing step: a_des = e/T lands on w in this step (error within one step's reach,
    // e <= J T²); take w itself so the target is reached exactly, not up to rounding.
    if (exact && ne > Scalar(0) && ne <= J * T * T)
      v_ = w;
    else
      v_ += a_new * T;
    a_ = a_new;
  }

  /// Time to bring this part to rest from the current state with a zero target (upper bound).
  Scalar stoppingTimeBound(const AxisLimits<Scalar>& lim, Scalar T) const noexcept {
    const Scalar na = a_.norm();
    const Scalar dv = v_.norm() + T * na + brakeTail(na, lim.jerk, T);
    return na / lim.jerk + dv / lim.acceleration + lim.acceleration / lim.jerk + Scalar(4) * T;
  }

 private:
  // Largest μ in [0, 1] with ||p + μ d|| <= R, given ||p|| <= R.
  static Scalar segmentToBall(const Vec3& p, const Vec3& d, Scalar R) noexcept {
    const Scalar dd = d.squaredNorm();
    if (!(dd > Scalar(0))) return Scalar(0);
    const Scalar pd = p.dot(d);
    const Scalar c = p.squaredNorm() - R * R;  // <= 0 (up to rounding)
    const Scalar disc = std::fmax(pd * pd - dd * c, Scalar(0));
    const Scalar mu = (-pd + std::sqrt(disc)) / dd;
    return std::fmin(std::fmax(mu, Scalar(0)), Scalar(1));
  }

  // The velocity after taking `a`, and the end of the full-jerk braking from there, both in
  // the V ball (the braking path is a straight segment, so its ends bound it).
  // A few ulps of slack: a target clamped onto the sphere ||w|| = V may have a norm one ulp
  // above V, and must still be reachable exactly.
  bool feasible(const Vec3& a, Scalar V, Scalar J, Scalar T) const noexcept {
    const Scalar V2 = V * V * (Scalar(1) + Scalar(16) * Eigen::NumTraits<Scalar>::epsilon());
    const Vec3 v1 = v_ + a * T;
    if (v1.squaredNorm() > V2) return false;
    const Scalar na = a.norm();
    if (!(na > Scalar(0))) return true;
    const Vec3 v_end = v1 + a * (brakeTail(na, J, T) / na);
    return v_end.squaredNorm() <= V2;
  }

  Vec3 v_ = Vec3::Zero();
  Vec3 a_ = Vec3::Zero();
};

}  // namespace detail

/// Jerk-limited smoother of a 6-D twist [v; ω] (translation first), stepped at the robot
/// command rate (1 kHz on a Franka). Unit-agnostic: the limits are in the twist's units.
template <typename Scalar = double>
class VelocitySmoother : public Configurable<VelocitySmoother<Scalar>> {
 public:
  using Twist = Eigen::Matrix<Scalar, 6, 1>;  ///< [v; ω]
  using Vec3 = Eigen::Matrix<Scalar, 3, 1>;  ///< one part of a twist
  using Limits = SmootherLimits<Scalar>;  ///< velocity, acceleration and jerk limits of both parts

  using Options = Limits;  ///< the smoother's options are its limits

  VelocitySmoother() noexcept { reset(); }
  /// At rest with `limits`; invalid ones are kept as configurationStatus(), which step()
  /// returns until a configure() succeeds (Configurable).
  explicit VelocitySmoother(const Options& limits) noexcept {
    reset();
    this->configureOnConstruction(limits);
  }

  /// The limits' own check (SmootherLimits::validate).
  static Status validate(const Options& limits) noexcept { return limits.validate(); }
  /// Set the limits; invalid → validate()'s Status, the smoother unchanged. Lowering limits
  /// while moving is allowed, but the bounds are then only guaranteed once the state has come
  /// back inside the new limits (reset() first to be safe).
  Status configure(const Options& limits) noexcept { return this->configureChecked(limits); }
  const Options& options() const noexcept { return limits_; }  ///< the limits in force
  const Limits& limits() const noexcept { return limits_; }  ///< the limits in force (as options())

  /// Rest: zero velocity and acceleration.
  void reset() noexcept {
    lin_.reset();
    ang_.reset();
  }

  /// Start from a known commanded velocity/acceleration (e.g. the robot's last command).
  /// Non-finite → non_finite_input; outside the limits, or a state whose full-jerk braking
  /// (checked at the 1 kHz step) would leave the velocity limit → invalid_argument
  /// (state unchanged).
  Status reset(const Twist& velocity, const Twist& acceleration) noexcept {
    if (!velocity.allFinite() || !acceleration.allFinite()) return Status::non_finite_input;
    if (!inside(velocity.template head<3>(), acceleration.template head<3>(), limits_.translation) ||
        !inside(velocity.template tail<3>(), acceleration.template tail<3>(), limits_.rotation))
      return Status::invalid_argument;
    lin_.set(velocity.template head<3>(), acceleration.template head<3>());
    ang_.set(velocity.template tail<3>(), acceleration.template tail<3>());
    return Status::ok;
  }

  /// Whether the smoother takes a step of dt (s): dt in [1e-6, 1] (a robot's command period is
  /// about 1e-3 s); false for NaN.
  static bool validStep(Scalar dt) noexcept { return dt >= Scalar(1e-6) && dt <= Scalar(1); }

  /// One step of length dt (s) towards `target`. dt not validStep → invalid_time_step;
  /// non-finite target → non_finite_input; refused limits → configurationStatus(); state
  /// unchanged in all three cases.
  Status step(const Twist& target, Scalar dt) noexcept {
    if (const Status c = this->configurationStatus(); c != Status::ok) return c;
    if (!validStep(dt)) return Status::invalid_time_step;
    if (!target.allFinite()) return Status::non_finite_input;
    lin_.step(target.template head<3>(), limits_.translation, dt);
    ang_.step(target.template tail<3>(), limits_.rotation, dt);
    return Status::ok;
  }

  /// step() and copy the new commanded velocity to `out` (untouched unless ok).
  Status step(const Twist& target, Scalar dt, Twist& out) noexcept {
    const Status s = step(target, dt);
    if (s == Status::ok) out = velocity();
    return s;
  }

  /// The current commanded velocity [v; ω].
  Twist velocity() const noexcept {
    Twist t;
    t << lin_.velocity(), ang_.velocity();
    return t;
  }
  /// The current acceleration (finite difference of the last step).
  Twist acceleration() const noexcept {
    Twist t;
    t << lin_.acceleration(), ang_.acceleration();
    return t;
  }

  /// True when velocity and acceleration are exactly zero.
  bool atRest() const noexcept {
    return lin_.velocity().isZero(0) && ang_.velocity().isZero(0) && lin_.acceleration().isZero(0) &&
           ang_.acceleration().isZero(0);
  }

  /// Upper bound on the time (s) to come to rest with a zero target from the current state
  /// at step dt: |a|/J + (|v| + braking overshoot)/A + A/J + 4 dt, the slower of both parts.
  Scalar stoppingTimeBound(Scalar dt) const noexcept {
    return std::fmax(lin_.stoppingTimeBound(limits_.translation, dt),
                     ang_.stoppingTimeBound(limits_.rotation, dt));
  }

 private:
  friend class Configurable<VelocitySmoother>;
  Status apply(const Options& limits) noexcept {  // validated (Configurable)
    limits_ = limits;
    return Status::ok;
  }
  // Within the limits, and the full-jerk braking from (v, a) ends inside the velocity ball.
  static bool inside(const Vec3& v, const Vec3& a, const AxisLimits<Scalar>& lim) noexcept {
    if (v.norm() > lim.velocity || a.norm() > lim.acceleration) return false;
    const Scalar na = a.norm();
    if (!(na > Scalar(0))) return true;
    const Scalar tail = detail::NormLimiter3<Scalar>::brakeTail(na, lim.jerk, Scalar(1e-3));
    return (v + a * (tail / na)).norm() <= lim.velocity;
  }

  Limits limits_{};
  detail::NormLimiter3<Scalar> lin_;
  detail::NormLimiter3<Scalar> ang_;
};

}  // namespace lieservo::realtime

#include <lieservo/detail/options_pop.hpp>

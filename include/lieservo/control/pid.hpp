// lieservo/control/pid.hpp — MIMO and SISO feedforward-feedback PID controllers with an
// explicit time step (paper: eq. 19 (eqn:ff_fb_pid_control), Section 3.3.1 (sec:tangent_space_control)).
//
//   u_k = clip_out( v_k + Kp e_k + Ki I_k + Kd d_k )
//
//   I_k  = clip_int( I_{k-1} + e_k dt_k )                       backward-Euler integral
//   ē_k  = α_k e_k + (1 − α_k) ē_{k−1}   (ē_0 = e_0)            exponentially smoothed error
//   d_k  = (ē_k − ē_{k−1}) / dt_k        (d_0 = 0)               backward-Euler derivative of ē
//
// α is the weight of the newest sample.  The paper smooths "with decay coefficient 0.5": for
// 0.5 the weight of the new sample and the decay of the old one are both 0.5, so either
// reading gives the same filter.  α is either a fixed per-step weight (Options::smoothing,
// the paper's behaviour at its own control rate) or derived from a time constant τ
// (Options::smoothing_time_constant > 0): α_k = 1 − exp(−dt_k/τ), which makes the smoothing
// independent of the control rate.
//
// Gains are per second: Ki multiplies ∫e dt (error·s), Kd multiplies de/dt (error/s).  Gains
// tuned for a per-step PID (Σe, Δe; no dt) convert as Ki = Ki_step/dt, Kd = Kd_step·dt, and
// per-step integral clipping bounds as I_max = I_max_step·dt (see docs/control.md).
//
// Clipping is per component, applied to the accumulated integral (anti-windup) and to the
// total output u (feedforward included).  ±infinity means "no clipping".
//
// Real-time contract: step() is noexcept, never allocates, and leaves the state and its
// output untouched unless it returns Status::ok.
#pragma once
#include <lieservo/detail/options_push.hpp>

#include <cmath>
#include <limits>

#include <Eigen/Core>

#include <lieservo/configurable.hpp>
#include <lieservo/detail/finite.hpp>
#include <lieservo/detail/flatten.hpp>
#include <lieservo/status.hpp>

namespace lieservo {

/// Multi-input multi-output PID with feedforward (eq. 19, eqn:ff_fb_pid_control).  N channels;
/// gains are full N×N matrices (the paper uses diagonal ones: see Options::diagonal).
template <class Scalar, int N>
class MimoPid : public Configurable<MimoPid<Scalar, N>> {
  static_assert(N > 0, "MimoPid needs a fixed, positive number of channels");

 public:
  using Vector = Eigen::Matrix<Scalar, N, 1>;  ///< one value per channel
  using Matrix = Eigen::Matrix<Scalar, N, N>;  ///< a gain matrix

  /// +∞: the open end of a clip range.
  static constexpr Scalar infinity() noexcept { return std::numeric_limits<Scalar>::infinity(); }

  /// Gains, clip ranges and error smoothing; checked by validate().
  struct Options {
    Matrix kp = Matrix::Zero();  ///< proportional gain, 1/s for a velocity output (u per e)
    Matrix ki = Matrix::Zero();  ///< integral gain, 1/s² (u per ∫e dt)
    Matrix kd = Matrix::Zero();  ///< derivative gain, dimensionless (u per de/dt)
    Vector integral_min = Vector::Constant(-infinity());  ///< lower clip of ∫e dt
    Vector integral_max = Vector::Constant(infinity());   ///< upper clip of ∫e dt
    Vector output_min = Vector::Constant(-infinity());    ///< lower clip of u
    Vector output_max = Vector::Constant(infinity());     ///< upper clip of u
    /// Per-step weight α ∈ (0, 1] of the newest error in the smoothed error (paper: 0.5;
    /// 1 = no smoothing).  Used when smoothing_time_constant == 0.
    Scalar smoothing = Scalar(0.5);
    /// τ ≥ 0 (seconds).  When > 0, α_k = 1 − exp(−dt_k/τ) replaces `smoothing`.
    Scalar smoothing_time_constant = Scalar(0);

    /// Diagonal gain matrices from per-channel gain vectors.
    static Options diagonal(const Vector& kp, const Vector& ki, const Vector& kd) {
      Options o;
      o.kp = kp.asDiagonal();
      o.ki = ki.asDiagonal();
      o.kd = kd.asDiagonal();
      return o;
    }
    /// Same integral clip [lo, hi] on every channel.
    Options& clipIntegral(Scalar lo, Scalar hi) {
      integral_min.setConstant(lo);
      integral_max.setConstant(hi);
      return *this;
    }
    /// Same output clip [lo, hi] on every channel.
    Options& clipOutput(Scalar lo, Scalar hi) {
      output_min.setConstant(lo);
      output_max.setConstant(hi);
      return *this;
    }
  };

  /// The four contributions of the last successful step (before output clipping).
  struct Terms {
    Vector feedforward = Vector::Zero();  ///< v_k
    Vector proportional = Vector::Zero();  ///< K_p e_k
    Vector integral = Vector::Zero();  ///< K_i ∫e dt (clipped integral)
    Vector derivative = Vector::Zero();  ///< K_d dē/dt (smoothed error)
    Vector unclipped = Vector::Zero();  ///< sum of the four
    Vector output = Vector::Zero();     ///< after output clipping
  };

  /// Zero gains, no clipping, α = 0.5.
  MimoPid() = default;

  /// Configures with `options`; if they are invalid the controller refuses to run
  /// (step() returns configurationStatus(), i.e. Status::invalid_argument).
  explicit MimoPid(const Options& options) { this->configureOnConstruction(options); }

  /// Checks options: finite gains; clip bounds not NaN with min ≤ max, each range holding a
  /// finite value (±inf allowed as open ends, but not [+inf, +inf] or [−inf, −inf]);
  /// smoothing ∈ (0, 1]; smoothing_time_constant finite and ≥ 0.
  /// The first reason is returned: non_finite_input for a NaN (or, where a finite value is
  /// needed, infinite) entry, invalid_argument for a finite value out of its range.
  static Status validate(const Options& o) noexcept {
    if (!o.kp.allFinite() || !o.ki.allFinite() || !o.kd.allFinite()) return Status::non_finite_input;
    for (int i = 0; i < N; ++i) {
      if (std::isnan(o.integral_min[i]) || std::isnan(o.integral_max[i]) || std::isnan(o.output_min[i]) ||
          std::isnan(o.output_max[i]))
        return Status::non_finite_input;
      if (!clipRangeValid(o.integral_min[i], o.integral_max[i]) ||
          !clipRangeValid(o.output_min[i], o.output_max[i]))
        return Status::invalid_argument;
    }
    if (!std::isfinite(o.smoothing) || !std::isfinite(o.smoothing_time_constant)) return Status::non_finite_input;
    if (!(o.smoothing > Scalar(0) && o.smoothing <= Scalar(1))) return Status::invalid_argument;
    if (!(o.smoothing_time_constant >= Scalar(0))) return Status::invalid_argument;
    return Status::ok;
  }

  /// Replaces the options (state kept; the integral is re-clipped into the new bounds).
  /// Invalid options: returns Status::invalid_argument and changes nothing.
  Status configure(const Options& options) noexcept { return this->configureChecked(options); }

  /// One control step.  `error` e_k, `feedforward` v_k, time step dt_k > 0 since the last
  /// step (the first step after construction/reset uses dt only for the integral).
  /// Status::invalid_time_step if dt ≤ 0 or non-finite; Status::non_finite_input if e or v
  /// has a NaN/inf; Status::numerical_failure if the result overflows.  On failure nothing
  /// changes, `u` included.
  LIESERVO_FLATTEN Status step(const Vector& error, const Vector& feedforward, Scalar dt, Vector& u) noexcept {
    if (const Status c = this->configurationStatus(); c != Status::ok) return c;
    if (!(dt > Scalar(0)) || !std::isfinite(dt)) return Status::invalid_time_step;
    if (!detail::allFinite(error, feedforward)) return Status::non_finite_input;

    const Vector integral =
        (integral_ + dt * error).cwiseMax(options_.integral_min).cwiseMin(options_.integral_max);
    // Locals are computed whole and stored only after the finiteness check (no zero-fill, no
    // Terms temporary copied into terms_): the controller step is a 1 kHz hot path.
    Vector smoothed, derivative;
    if (!started_) {
      smoothed = error;
      derivative.setZero();
    } else {
      // A fixed control period repeats dt: 1 − exp(−dt/τ) is computed once, not every step
      // (the exp call was a tenth of the step).  alpha_dt_ = 0 means "no memo" (dt > 0 here).
      if (dt != alpha_dt_) {
        alpha_ = alpha(dt);
        alpha_dt_ = dt;
      }
      const Scalar a = alpha_;
      smoothed = a * error + (Scalar(1) - a) * smoothed_;
      derivative = (smoothed - smoothed_) * (Scalar(1) / dt);
    }
    Vector proportional, integral_term, derivative_term;
    if (diagonal_gains_) {
      proportional = kp_diag_.cwiseProduct(error);
      integral_term = ki_diag_.cwiseProduct(integral);
      derivative_term = kd_diag_.cwiseProduct(derivative);
    } else {
      proportional.noalias() = options_.kp * error;
      integral_term.noalias() = options_.ki * integral;
      derivative_term.noalias() = options_.kd * derivative;
    }
    const Vector unclipped = feedforward + proportional + integral_term + derivative_term;
    const Vector output = unclipped.cwiseMax(options_.output_min).cwiseMin(options_.output_max);
    if (!detail::allFinite(output, integral, smoothed, derivative)) return Status::numerical_failure;

    terms_.feedforward = feedforward;
    terms_.proportional = proportional;
    terms_.integral = integral_term;
    terms_.derivative = derivative_term;
    terms_.unclipped = unclipped;
    terms_.output = output;
    integral_ = integral;
    smoothed_ = smoothed;
    derivative_ = derivative;
    started_ = true;
    ++steps_;
    u = output;
    return Status::ok;
  }

  /// Clears the integral, the smoothed error and the derivative (options kept).
  void reset() noexcept {
    integral_.setZero();
    smoothed_.setZero();
    derivative_.setZero();
    terms_ = Terms{};
    started_ = false;
    steps_ = 0;
  }

  /// Smoothing weight used for a step of length dt.
  Scalar alpha(Scalar dt) const noexcept {
    return options_.smoothing_time_constant > Scalar(0)
               ? Scalar(1) - std::exp(-dt / options_.smoothing_time_constant)
               : options_.smoothing;
  }

  const Options& options() const noexcept { return options_; }  ///< the options in force
  const Vector& integral() const noexcept { return integral_; }       ///< clipped ∫e dt
  const Vector& smoothedError() const noexcept { return smoothed_; }  ///< ē_k
  const Vector& derivative() const noexcept { return derivative_; }   ///< (ē_k − ē_{k−1})/dt
  const Terms& lastTerms() const noexcept { return terms_; }  ///< the contributions of the last successful step
  bool started() const noexcept { return started_; }  ///< whether a step has run since construction or reset()
  long steps() const noexcept { return steps_; }  ///< successful steps since construction or reset()

 private:
  friend class Configurable<MimoPid>;
  Status apply(const Options& options) noexcept {  // validated (Configurable)
    options_ = options;
    // The paper's gains are diagonal: then step() multiplies per channel (N instead of N²).
    diagonal_gains_ = isDiagonal(options_.kp) && isDiagonal(options_.ki) && isDiagonal(options_.kd);
    kp_diag_ = options_.kp.diagonal();
    ki_diag_ = options_.ki.diagonal();
    kd_diag_ = options_.kd.diagonal();
    integral_ = integral_.cwiseMax(options_.integral_min).cwiseMin(options_.integral_max);
    alpha_dt_ = Scalar(0);  // the memo below belongs to the old options
    return Status::ok;
  }

  Options options_{};
  Vector integral_ = Vector::Zero();
  Vector smoothed_ = Vector::Zero();
  Vector derivative_ = Vector::Zero();
  Terms terms_{};
  bool started_ = false;
  long steps_ = 0;
  bool diagonal_gains_ = true;  // zero gains (the default) are diagonal
  Vector kp_diag_ = Vector::Zero();
  Vector ki_diag_ = Vector::Zero();
  Vector kd_diag_ = Vector::Zero();
  Scalar alpha_dt_ = Scalar(0);  // dt of the memoised smoothing weight (0: none)
  Scalar alpha_ = Scalar(0);     // alpha(alpha_dt_)

  // A clip range [lo, hi] must contain a finite number: [+inf, +inf] would clip every output
  // to infinity and fail every step.
  static bool clipRangeValid(Scalar lo, Scalar hi) noexcept {
    return lo <= hi && lo < infinity() && hi > -infinity();  // false for NaN too
  }

  static bool isDiagonal(const Matrix& m) noexcept {
    for (int j = 0; j < N; ++j)
      for (int i = 0; i < N; ++i)
        if (i != j && m(i, j) != Scalar(0)) return false;
    return true;
  }
};

/// Single-input single-output PID with feedforward (the paper's target-alignment "PID 2",
/// Section 3.3.3 (sec:pushing_controller)).  Same update law and contract as MimoPid with N = 1.
template <class Scalar>
class SisoPid : public Configurable<SisoPid<Scalar>> {
  using Impl = MimoPid<Scalar, 1>;

 public:
  /// MimoPid::Options for one channel, with scalars.
  struct Options {
    Scalar kp = Scalar(0);  ///< 1/s for a rate output
    Scalar ki = Scalar(0);  ///< 1/s²
    Scalar kd = Scalar(0);  ///< dimensionless
    Scalar integral_min = -Impl::infinity();  ///< lower clip of ∫e dt
    Scalar integral_max = Impl::infinity();  ///< upper clip of ∫e dt
    Scalar output_min = -Impl::infinity();  ///< lower clip of u
    Scalar output_max = Impl::infinity();  ///< upper clip of u
    Scalar smoothing = Scalar(0.5);             ///< per-step α ∈ (0, 1]
    Scalar smoothing_time_constant = Scalar(0); ///< τ (s); > 0 overrides `smoothing`
  };
  using Terms = typename Impl::Terms;  ///< the contributions of a step (one channel)

  SisoPid() = default;  ///< zero gains, no clipping, α = 0.5
  /// Configures with `options` (as MimoPid's constructor).
  explicit SisoPid(const Options& options) { this->configureOnConstruction(options); }

  /// The same options for MimoPid with N = 1.
  static typename Impl::Options toMimo(const Options& o) {
    typename Impl::Options m;
    m.kp(0, 0) = o.kp;
    m.ki(0, 0) = o.ki;
    m.kd(0, 0) = o.kd;
    m.integral_min[0] = o.integral_min;
    m.integral_max[0] = o.integral_max;
    m.output_min[0] = o.output_min;
    m.output_max[0] = o.output_max;
    m.smoothing = o.smoothing;
    m.smoothing_time_constant = o.smoothing_time_constant;
    return m;
  }
  /// As MimoPid::validate.
  static Status validate(const Options& o) noexcept { return Impl::validate(toMimo(o)); }

  /// As MimoPid::configure: invalid options change nothing.
  Status configure(const Options& options) noexcept { return this->configureChecked(options); }

  /// See MimoPid::step.  On failure nothing changes, `u` included.
  Status step(Scalar error, Scalar feedforward, Scalar dt, Scalar& u) noexcept {
    if (const Status c = this->configurationStatus(); c != Status::ok) return c;
    typename Impl::Vector e, v;
    typename Impl::Vector out = Impl::Vector::Zero();
    e[0] = error;
    v[0] = feedforward;
    const Status s = pid_.step(e, v, dt, out);
    if (s == Status::ok) u = out[0];
    return s;
  }

  void reset() noexcept { pid_.reset(); }  ///< as MimoPid::reset

  const Options& options() const noexcept { return options_; }  ///< the options in force
  Scalar integral() const noexcept { return pid_.integral()[0]; }  ///< clipped ∫e dt
  Scalar smoothedError() const noexcept { return pid_.smoothedError()[0]; }  ///< ē_k
  Scalar derivative() const noexcept { return pid_.derivative()[0]; }  ///< (ē_k − ē_{k−1})/dt
  const Terms& lastTerms() const noexcept { return pid_.lastTerms(); }  ///< the contributions of the last successful step
  bool started() const noexcept { return pid_.started(); }  ///< whether a step has run since construction or reset()
  long steps() const noexcept { return pid_.steps(); }  ///< successful steps since construction or reset()
  Scalar alpha(Scalar dt) const noexcept { return pid_.alpha(dt); }  ///< the smoothing weight for a step of length dt

 private:
  friend class Configurable<SisoPid>;
  Status apply(const Options& options) noexcept {  // validated (Configurable)
    if (const Status s = pid_.configure(toMimo(options)); s != Status::ok) return s;
    options_ = options;
    return Status::ok;
  }

  Impl pid_{};
  Options options_{};
};

}  // namespace lieservo

#include <lieservo/detail/options_pop.hpp>

// lieservo/control/tactile_servo_controller.hpp — the tactile servoing controller
// (paper: Section 3.3.2 (sec:servoing_controller), Figure fig:pushing_controller (a)).
//
// Frames (paper notation): {s} current sensor frame (origin at the centre of the hemispherical
// sensor tip, z out of the tip), {s'} reference sensor frame, {f} surface feature frame
// (z normal to and into the surface).  Each control cycle:
//
//   E = X_ss' = X_sf X_s'f⁻¹ = X_sf X_fs'          eq. 20 (eqn:se3_tactile_servo_error)
//   e = log(E)^∨                                    eq. 18 (eqn:local_tangent_space_error)
//   v = Ad(X_ss') u_s'2                             feedforward twist mapped into {s}
//   u = v + Kp e + Ki ∫e dt + Kd dē/dt              eq. 19 (eqn:ff_fb_pid_control) (MimoPid)
//
// X_sf is the (filtered) feature pose in the current sensor frame; X_fs' = X_ref is the
// reference sensor pose in the feature frame (the tables' "Feedback ref pose"); u_s'2 is the
// feedforward twist expressed in the reference sensor frame.  The output u is a body twist
// of the sensor, expressed in the current sensor frame {s}: a kinematic robot follows it as
// X_ws(t+dt) = X_ws(t) exp(dt u^) (right multiplication).
//
// Generic over the group G (SE3, SE2, SO3, SO2): anything with G::DoF, Tangent, Jacobian,
// operator*, inverse(), log(), Ad(), allFinite() and identity().
#pragma once
#include <lieservo/detail/options_push.hpp>

#include <cmath>

#include <Eigen/Core>

#include <lieservo/configurable.hpp>
#include <lieservo/control/pid.hpp>
#include <lieservo/detail/flatten.hpp>
#include <lieservo/groups/perturbation.hpp>
#include <lieservo/status.hpp>

namespace lieservo {

template <class G>
/// The tactile servoing controller (Section 3.3.2, sec:servoing_controller): a feedforward-
/// feedback MIMO PID on the tangent-space servo error (eqs. 18-20); the header comment gives the law.
class TactileServoController : public Configurable<TactileServoController<G>> {
 public:
  using Group = G;  ///< the pose group (SE3, SE2, SO3, SO2)
  using Scalar = typename G::Scalar;  ///< float or double
  static constexpr int DoF = G::DoF;  ///< channels of the PID
  using Tangent = typename G::Tangent;  ///< a twist
  using Jacobian = typename G::Jacobian;  ///< DoF × DoF
  using Pid = MimoPid<Scalar, DoF>;  ///< the feedback PID

  /// The PID, the reference pose and the feedforward twist.
  struct Options {
    typename Pid::Options pid{};       ///< MIMO PID on e (radians on rotational channels)
    G reference = G::identity();       ///< X_ref = X_fs': reference sensor pose in {f}
    Tangent feedforward = Tangent::Zero();  ///< u_s'2: feedforward twist in {s'}
  };

  TactileServoController() = default;

  /// Configures with `options`; invalid options make step() return Status::invalid_argument.
  explicit TactileServoController(const Options& options) { this->configureOnConstruction(options); }

  /// ok, or the first reason: the reference's validateElement() Status (non_finite_input,
  /// not_orthonormal), non_finite_input (a NaN or infinite feedforward, as setFeedforward), or
  /// the PID options' (MimoPid::validate).
  static Status validate(const Options& o) noexcept {
    if (const Status s = validateElement(o.reference); s != Status::ok) return s;
    if (!o.feedforward.allFinite()) return Status::non_finite_input;
    return Pid::validate(o.pid);
  }

  /// Replaces the options; the PID state is kept (see MimoPid::configure).
  Status configure(const Options& options) noexcept { return this->configureChecked(options); }

  /// New reference sensor pose X_fs' (e.g. the paper's ±0.5 mm tall-object offsets).
  /// non_finite_input / not_orthonormal (validateElement) leave the reference unchanged.
  Status setReference(const G& reference_sensor_pose_in_feature) noexcept {
    const Status s = validateElement(reference_sensor_pose_in_feature);
    if (s != Status::ok) return s;
    options_.reference = reference_sensor_pose_in_feature;
    return Status::ok;
  }

  /// New feedforward twist u_s'2 (reference sensor frame), e.g. a surface-following heading.
  Status setFeedforward(const Tangent& feedforward_in_reference) noexcept {
    if (!feedforward_in_reference.allFinite()) return Status::non_finite_input;
    options_.feedforward = feedforward_in_reference;
    feedforward_is_zero_ = options_.feedforward.isZero(Scalar(0));
    return Status::ok;
  }

  /// E = X_sf X_s'f⁻¹ = X_sf X_fs' (eq. 20, eqn:se3_tactile_servo_error): the reference sensor pose
  /// in the current sensor frame, X_ss'.
  static G servoError(const G& feature_in_sensor, const G& reference_sensor_in_feature) {
    return feature_in_sensor * reference_sensor_in_feature;
  }

  /// One control cycle.  `feature_in_sensor` = X_sf (filtered), `dt` > 0 the time since the
  /// last cycle, `u` receives the sensor body twist in {s}.  A non-finite or non-orthonormal
  /// X_sf gives non_finite_input / not_orthonormal.  On any non-ok Status nothing changes
  /// (u, error(), PID state).
  LIESERVO_FLATTEN Status step(const G& feature_in_sensor, Scalar dt, Tangent& u) noexcept {
    if (const Status c = this->configurationStatus(); c != Status::ok) return c;
    if (!(dt > Scalar(0)) || !std::isfinite(dt)) return Status::invalid_time_step;
    const Status c = validateElement(feature_in_sensor);
    if (c != Status::ok) return c;

    const G E = servoError(feature_in_sensor, options_.reference);   // X_ss'
    const Tangent e = E.log();                                       // eq. 18 (eqn:local_tangent_space_error)
    // Ad(X_ss') u_s'2; most presets have no feedforward, and then Ad is not needed at all.
    const Tangent v = feedforward_is_zero_ ? Tangent(Tangent::Zero())
                                           : Tangent(E.Ad() * options_.feedforward);
    // The PID checks e and v for NaN/inf itself; the input was finite, so a non-finite e or v
    // is our numerical failure (the log or Ad overflowed), not the caller's bad input.
    Tangent out;
    const Status s = pid_.step(e, v, dt, out);
    if (s == Status::non_finite_input) return Status::numerical_failure;
    if (s != Status::ok) return s;
    error_pose_ = E;
    error_ = e;
    feedforward_sensor_ = v;
    u = out;
    return Status::ok;
  }

  /// Clears the PID state and the exposed error (options kept).
  void reset() noexcept {
    pid_.reset();
    error_pose_ = G::identity();
    error_ = Tangent::Zero();
    feedforward_sensor_ = Tangent::Zero();
  }

  /// E = X_ss' of the last successful step (identity before the first).
  const G& poseError() const noexcept { return error_pose_; }
  /// e = log(E)^∨ of the last successful step.
  const Tangent& tangentError() const noexcept { return error_; }
  /// Ad(X_ss') of the last successful step: maps twists in {s'} to {s} (formed on demand).
  Jacobian referenceToSensorAdjoint() const noexcept { return error_pose_.Ad(); }
  /// v = Ad(X_ss') u_s'2 of the last successful step (feedforward in {s}).
  const Tangent& feedforwardInSensorFrame() const noexcept { return feedforward_sensor_; }
  const Pid& pid() const noexcept { return pid_; }  ///< the feedback PID
  const Options& options() const noexcept { return options_; }  ///< the options in force

 private:
  friend class Configurable<TactileServoController>;
  Status apply(const Options& options) noexcept {  // validated (Configurable)
    if (const Status p = pid_.configure(options.pid); p != Status::ok) return p;
    options_ = options;
    feedforward_is_zero_ = options_.feedforward.isZero(Scalar(0));
    return Status::ok;
  }

  Options options_{};
  Pid pid_{};
  G error_pose_ = G::identity();
  Tangent error_ = Tangent::Zero();
  Tangent feedforward_sensor_ = Tangent::Zero();
  bool feedforward_is_zero_ = true;
};

}  // namespace lieservo

#include <lieservo/detail/options_pop.hpp>

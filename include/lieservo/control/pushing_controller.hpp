// lieservo/control/pushing_controller.hpp — the tactile pushing controller: tactile servoing
// plus target alignment (paper: Section 3.3.3 (sec:pushing_controller), Figure fig:pushing_controller (b)).
//
// Each control cycle, with X_ws the sensor pose in the robot work frame (proprioception),
// X_wt the target pose and X_ss' the servo error of the tactile servoing controller:
//
//   u_servo = tactile servoing output (TactileServoController<SE3>)   Section 3.3.2 (sec:servoing_controller)
//   X_s't   = X_ss'⁻¹ X_ws⁻¹ X_wt                                     eq. 21 (eqn:transformed_target_pose)
//   θ = atan2(y, z),  r = sqrt(y² + z²)   ((x, y, z) = translation of X_s't)
//                                                                     eq. 22 (eqn:target_bearing_distance)
//   e_θ = wrap(θ_ref − θ)                 (θ_ref = 0 in the paper)
//   u_y = SISO PID(e_θ)                   tangential y velocity in {s'}
//   u   = u_servo + Ad(X_ss') [0, u_y, 0, 0, 0, 0]ᵀ
//
// Sign: a target at positive bearing (towards +y of {s'}) gives e_θ < 0 and, with positive
// gains, u_y < 0: the pusher slides towards −y along the contacted face, so the pushed object
// turns its face (and, through the servoing loop, the sensor) towards the target.
//
// Alignment cut-off (paper ρ* = 120 mm): when r < ρ* the alignment output is zero and its PID
// is not stepped (held); only the servoing controller acts.  r is the distance of
// eq. 22 (eqn:target_bearing_distance), i.e. measured in the y–z plane of the reference sensor frame.
//
// Termination (paper: "the centre of the sensor tip is closer than its radius of 20 mm from
// the target"): the sensor frame origin is the tip centre, so the compared distance is that
// between the sensor origin p_ws and the target origin p_wt, by default measured in the y–z
// plane of the current sensor frame (the push plane: z = push direction, y = tangential;
// the sensor-x offset — the height in the paper's right-angle-mount set-up — is ignored),
// or, with TerminationDistance::euclidean, as the full 3-D distance ‖p_wt − p_ws‖.  Once
// d < termination_radius the controller latches `terminated()`, outputs a zero twist and
// steps nothing until reset() or setTarget().
//
// Translation units are the caller's (the paper and the presets: mm); angles in radians.
#pragma once
#include <lieservo/detail/options_push.hpp>

#include <type_traits>

#include <cmath>
#include <limits>

#include <Eigen/Core>

#include <lieservo/configurable.hpp>
#include <lieservo/control/pid.hpp>
#include <lieservo/control/tactile_servo_controller.hpp>
#include <lieservo/groups/perturbation.hpp>
#include <lieservo/groups/se3.hpp>
#include <lieservo/status.hpp>
#include <lieservo/units.hpp>

namespace lieservo {

/// Which sensor-to-target distance is compared with PushingController::Options::termination_radius.
enum class TerminationDistance {
  sensor_yz_plane,  ///< sqrt(y² + z²) of X_ws⁻¹ X_wt: in the push plane of the current sensor frame
  euclidean,        ///< ‖X_ws⁻¹ X_wt translation‖: full 3-D distance tip centre → target
};

/// The tactile pushing controller (Section 3.3.3, sec:pushing_controller): tactile servoing
/// plus target alignment by a SISO PID on the bearing (eqs. 21-22); the header comment gives the law.
/// `G`: the pose group, as every controller's (SE3<float> or SE3<double>: pushing is on SE(3)).
template <class G>
class PushingController : public Configurable<PushingController<G>> {
  static_assert(std::is_same_v<G, SE3<typename G::Scalar>>, "PushingController pushes on SE(3): G = SE3<Scalar>");

 public:
  using Group = G;  ///< poses
  using Scalar = typename G::Scalar;  ///< float or double
  using Servo = TactileServoController<Group>;  ///< PID 1: the tactile servo
  using Tangent = typename Group::Tangent;  ///< a twist [v; ω]
  using Alignment = SisoPid<Scalar>;  ///< PID 2: the bearing alignment

  /// Both PIDs, the bearing reference, the alignment cut-off, the termination test and the target.
  struct Options {
    typename Servo::Options servo{};          ///< PID 1 (MIMO), reference pose, feedforward
    typename Alignment::Options alignment{};  ///< PID 2 (SISO): bearing error (rad) → u_y
    Scalar reference_bearing = Scalar(0);     ///< θ_s'r (rad); paper: 0
    Scalar alignment_cutoff = Scalar(120);    ///< ρ*: alignment zeroed when r < ρ* (paper 120 mm)
    Scalar termination_radius = Scalar(20);   ///< stop when d < radius (paper: tip radius 20 mm)
    TerminationDistance termination_distance = TerminationDistance::sensor_yz_plane;  ///< how d is measured
    Group target = Group::identity();         ///< X_wt: target pose in the work frame
  };

  PushingController() = default;
  /// Configures with `options` (configurationStatus() keeps the result).
  explicit PushingController(const Options& options) { this->configureOnConstruction(options); }

  /// ok, or the first reason: the servo's and the alignment PID's validate(), non_finite_input
  /// (a NaN bearing, cut-off or radius; the target's validateElement()), not_orthonormal (the
  /// target), invalid_argument (a negative cut-off or radius, a TerminationDistance outside the enum).
  static Status validate(const Options& o) noexcept {
    if (const Status s = Servo::validate(o.servo); s != Status::ok) return s;
    if (const Status s = Alignment::validate(o.alignment); s != Status::ok) return s;
    if (!std::isfinite(o.reference_bearing)) return Status::non_finite_input;
    if (const Status s = validateElement(o.target); s != Status::ok) return s;
    if (std::isnan(o.alignment_cutoff) || std::isnan(o.termination_radius)) return Status::non_finite_input;
    if (o.alignment_cutoff < Scalar(0) || o.termination_radius < Scalar(0)) return Status::invalid_argument;
    if (o.termination_distance != TerminationDistance::sensor_yz_plane &&
        o.termination_distance != TerminationDistance::euclidean)
      return Status::invalid_argument;  // a value cast into the enum from outside its list
    return Status::ok;
  }

  /// Replaces the options (controller states kept; termination latch kept).
  Status configure(const Options& options) noexcept { return this->configureChecked(options); }

  /// New target X_wt; clears the termination latch. non_finite_input / not_orthonormal
  /// (validateElement) leave the target and the latch unchanged.
  Status setTarget(const Group& target_in_work) noexcept {
    const Status s = validateElement(target_in_work);
    if (s != Status::ok) return s;
    options_.target = target_in_work;
    terminated_ = false;
    return Status::ok;
  }

  /// New reference sensor pose X_fs' of the servoing loop (e.g. the tall-object offset).
  Status setReference(const Group& reference_sensor_in_feature) noexcept {
    const Status s = servo_.setReference(reference_sensor_in_feature);
    if (s == Status::ok) options_.servo.reference = reference_sensor_in_feature;
    return s;
  }

  /// One control cycle: `sensor_in_work` X_ws (the robot's sensor pose, first as in the
  /// filter's step), `feature_in_sensor` X_sf (filtered), `dt` > 0; `u` receives the sensor body
  /// twist in {s}.  After termination: u = 0, Status::ok.  A non-finite or non-orthonormal pose
  /// gives non_finite_input / not_orthonormal.  On any non-ok Status nothing changes.
  Status step(const Group& sensor_in_work, const Group& feature_in_sensor, Scalar dt,
              Tangent& u) noexcept {
    if (const Status c = this->configurationStatus(); c != Status::ok) return c;
    if (!(dt > Scalar(0)) || !std::isfinite(dt)) return Status::invalid_time_step;
    Status s = validateElement(sensor_in_work);
    if (s == Status::ok) s = validateElement(feature_in_sensor);
    if (s != Status::ok) return s;

    // Termination check: tip centre (sensor origin) to target origin.
    const Group X_sw = sensor_in_work.inverse();
    const Group X_st = X_sw * options_.target;
    const auto p_st = X_st.translation();
    const Scalar d = options_.termination_distance == TerminationDistance::euclidean
                         ? Scalar(p_st.norm())
                         : Scalar(std::hypot(p_st[1], p_st[2]));
    if (terminated_ || d < options_.termination_radius) {
      terminated_ = true;
      termination_distance_ = d;
      u.setZero();
      alignment_active_ = false;
      alignment_velocity_.setZero();
      return Status::ok;
    }

    // Tactile servoing (PID 1); copies of both PIDs restore the state if a later stage fails
    // (a two-phase step: nothing is kept unless every stage succeeded).
    const Servo servo_backup = servo_;
    const Alignment alignment_backup = alignment_;
    Tangent u_servo = Tangent::Zero();
    s = servo_.step(feature_in_sensor, dt, u_servo);
    if (s != Status::ok) return s;

    // Target in the reference sensor frame, eq. 21 (eqn:transformed_target_pose).
    const Group& X_ssr = servo_.poseError();
    const Group X_srt = X_ssr.inverse() * X_st;
    const auto p = X_srt.translation();
    const Scalar y = p[1];
    const Scalar z = p[2];
    const Scalar theta = std::atan2(y, z);   // eq. 22 (eqn:target_bearing_distance)
    const Scalar r = std::hypot(y, z);

    Tangent u_align_ref = Tangent::Zero();
    bool active = false;
    if (r >= options_.alignment_cutoff) {
      const Scalar e_theta = wrapAngle(options_.reference_bearing - theta);
      Scalar uy = Scalar(0);
      s = alignment_.step(e_theta, Scalar(0), dt, uy);
      if (s != Status::ok) {
        servo_ = servo_backup;
        return s;
      }
      u_align_ref[1] = uy;
      active = true;
    }
    const Tangent u_align = servo_.referenceToSensorAdjoint() * u_align_ref;
    const Tangent out = u_servo + u_align;
    if (!out.allFinite()) {
      servo_ = servo_backup;
      alignment_ = alignment_backup;
      return Status::numerical_failure;
    }
    target_in_reference_ = X_srt;
    bearing_ = theta;
    distance_ = r;
    termination_distance_ = d;
    alignment_active_ = active;
    alignment_velocity_ = u_align;
    servo_velocity_ = u_servo;
    u = out;
    return Status::ok;
  }

  /// Clears both PIDs, the exposed quantities and the termination latch (options kept).
  void reset() noexcept {
    servo_.reset();
    alignment_.reset();
    terminated_ = false;
    alignment_active_ = false;
    bearing_ = distance_ = Scalar(0);
    termination_distance_ = std::numeric_limits<Scalar>::infinity();
    target_in_reference_ = Group::identity();
    alignment_velocity_.setZero();
    servo_velocity_.setZero();
  }

  /// Wraps an angle to (−π, π].
  static Scalar wrapAngle(Scalar a) noexcept {
    const Scalar pi = lieservo::pi<Scalar>();
    a = std::remainder(a, Scalar(2) * pi);
    return a <= -pi ? a + Scalar(2) * pi : a;
  }

  bool terminated() const noexcept { return terminated_; }  ///< whether d < termination_radius was reached (latched until reset() or setTarget())
  /// θ_s' (rad) of the last active step.
  Scalar bearing() const noexcept { return bearing_; }
  /// r_s' of the last active step (compared with ρ*).
  Scalar distance() const noexcept { return distance_; }
  /// d of the last step (compared with termination_radius; +inf before the first step).
  Scalar terminationDistance() const noexcept { return termination_distance_; }
  /// Whether the alignment controller acted on the last step (r ≥ ρ*).
  bool alignmentActive() const noexcept { return alignment_active_; }
  /// Alignment contribution Ad(X_ss') [0, u_y, 0, 0, 0, 0]ᵀ in {s} of the last step.
  const Tangent& alignmentVelocity() const noexcept { return alignment_velocity_; }
  /// Servoing contribution (PID 1 + feedforward) in {s} of the last step.
  const Tangent& servoVelocity() const noexcept { return servo_velocity_; }
  /// X_s't of the last active step.
  const Group& targetInReference() const noexcept { return target_in_reference_; }
  const Servo& servo() const noexcept { return servo_; }  ///< PID 1
  const Alignment& alignment() const noexcept { return alignment_; }  ///< PID 2
  const Options& options() const noexcept { return options_; }  ///< the options in force

 private:
  friend class Configurable<PushingController>;
  Status apply(const Options& options) noexcept {  // validated (Configurable)
    if (const Status c = servo_.configure(options.servo); c != Status::ok) return c;
    if (const Status c = alignment_.configure(options.alignment); c != Status::ok) return c;
    options_ = options;
    return Status::ok;
  }

  Options options_{};
  Servo servo_{};
  Alignment alignment_{};
  bool terminated_ = false;
  bool alignment_active_ = false;
  Scalar bearing_ = Scalar(0);
  Scalar distance_ = Scalar(0);
  Scalar termination_distance_ = std::numeric_limits<Scalar>::infinity();
  Group target_in_reference_ = Group::identity();
  Tangent alignment_velocity_ = Tangent::Zero();
  Tangent servo_velocity_ = Tangent::Zero();
};

}  // namespace lieservo

#include <lieservo/detail/options_pop.hpp>

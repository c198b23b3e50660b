// lieservo/control/dual_arm.hpp — leader/follower dual-arm pushing
// (paper: Section 3.3.4 (sec:single_dual_arm_controllers), Section 5.7 (sec:dual_arm_object_pushing_exp)).
//
// The leader arm runs a pushing controller (Table 8, dual-arm Ki), the follower arm a
// stabilising tactile servoing controller (Table 9).  Each arm has its own discriminative
// Bayes filter (Algorithm 2, alg:se3_bayes_filter) turning the GDN observation of the feature pose X_sf
// (with covariance) and the arm's sensor pose X_ws into the filtered X_sf its controller uses.
// The two arms are decentralised: they share nothing but the time step.
//
// Per step and arm, the tactile loop's policy (control/tactile_loop.hpp, filterForControl): the
// filter (its first step initialises), then the controller. An observation rejected by the
// filter's gate is not an error: the controller uses the predicted belief, and the arm's
// ArmOutput::outcome is LoopOutcome::gated. When the leader's push terminates
// (PushingController::terminated()), both arms output a zero twist and the outcome terminated:
// the pushing sequence is over. On any non-ok Status nothing changes (filters, controllers,
// outputs): the step is refused.
#pragma once
#include <lieservo/detail/options_push.hpp>

#include <cmath>

#include <Eigen/Core>

#include <lieservo/configurable.hpp>
#include <lieservo/control/presets.hpp>
#include <lieservo/control/pushing_controller.hpp>
#include <lieservo/control/tactile_loop.hpp>
#include <lieservo/control/tactile_servo_controller.hpp>
#include <lieservo/estimation/bayes_filter.hpp>
#include <lieservo/estimation/concentrated_gaussian.hpp>
#include <lieservo/groups/perturbation.hpp>
#include <lieservo/groups/se3.hpp>
#include <lieservo/status.hpp>

namespace lieservo {

/// Leader (pusher) + follower (stabiliser), each with its own filter: the dual-arm tactile loop.
/// `Filter` must provide step(sensor_pose, observation) that initialises on its first call,
/// initialised(), reset() and filtered()
/// (a ConcentratedGaussian<G> or anything with a `mean` member): the lifecycle of
/// DiscriminativeBayesFilter. `G`: the pose group, as every controller's (SE3<Scalar>).
template <class G, class Filter = DiscriminativeBayesFilter<G>>
class DualArmPushing : public Configurable<DualArmPushing<G, Filter>> {
 public:
  using Group = G;  ///< poses of sensors, features and targets
  using Scalar = typename G::Scalar;  ///< float or double
  using Tangent = typename Group::Tangent;  ///< a twist [v; ω]
  using Observation = ConcentratedGaussian<Group>;  ///< a GDN estimate with covariance
  using Leader = PushingController<G>;  ///< the pusher's controller
  using Follower = TactileServoController<Group>;  ///< the stabiliser's controller

  /// Both arms' controller options.
  struct Options {
    typename Leader::Options leader{};  ///< the pushing controller (leader)
    typename Follower::Options follower{};  ///< the stabilising servo (follower)
  };

  /// One arm's measurements for a control cycle.
  struct ArmInput {
    Group sensor_pose = Group::identity();  ///< X_ws from the robot (proprioception)
    Observation observation{};              ///< GDN estimate of X_sf with covariance
  };

  /// One arm's result for a control cycle.
  struct ArmOutput {
    Tangent velocity = Tangent::Zero();             ///< body twist in the arm's sensor frame
    Group feature_in_sensor = Group::identity();    ///< filtered X_sf used by the controller
    /// initialised, commanded or gated (this arm's filter), or terminated (the leader's push is over)
    LoopOutcome outcome = LoopOutcome::refused;
  };

  DualArmPushing() = default;
  /// Configures with `options` (configurationStatus() keeps the result), with the arms' filters.
  DualArmPushing(const Options& options, const Filter& leader_filter, const Filter& follower_filter)
      : leader_filter_(leader_filter), follower_filter_(follower_filter) {
    this->configureOnConstruction(options);
  }

  /// ok, or the leader's, then the follower's validate() Status.
  static Status validate(const Options& o) noexcept {
    if (const Status s = Leader::validate(o.leader); s != Status::ok) return s;
    return Follower::validate(o.follower);
  }

  /// Replaces both controllers' options (states kept); invalid options change nothing and
  /// return validate()'s Status.
  Status configure(const Options& options) noexcept { return this->configureChecked(options); }

  /// Steps both filters and both controllers with the same dt (the filters initialise on
  /// their first step).  Non-finite or non-orthonormal poses: non_finite_input /
  /// not_orthonormal from the filter that checks them, and nothing changes (rolled back).
  Status step(const ArmInput& leader_in, const ArmInput& follower_in, Scalar dt, ArmOutput& leader_out,
              ArmOutput& follower_out) noexcept {
    if (const Status c = this->configurationStatus(); c != Status::ok) return c;
    if (!(dt > Scalar(0)) || !std::isfinite(dt)) return Status::invalid_time_step;

    const Filter leader_filter_backup = leader_filter_;
    const Filter follower_filter_backup = follower_filter_;
    const Leader leader_backup = leader_;
    const Follower follower_backup = follower_;
    auto restore = [&]() noexcept {
      leader_filter_ = leader_filter_backup;
      follower_filter_ = follower_filter_backup;
      leader_ = leader_backup;
      follower_ = follower_backup;
    };

    ArmOutput lo, fo;
    Status s = filterStep(leader_filter_, leader_in, lo);
    if (s != Status::ok) {
      restore();
      return s;
    }
    s = filterStep(follower_filter_, follower_in, fo);
    if (s != Status::ok) {
      restore();
      return s;
    }

    s = leader_.step(leader_in.sensor_pose, lo.feature_in_sensor, dt, lo.velocity);
    if (s != Status::ok) {
      restore();
      return s;
    }
    if (leader_.terminated()) {
      fo.velocity.setZero();
      lo.outcome = fo.outcome = LoopOutcome::terminated;
    } else {
      s = follower_.step(fo.feature_in_sensor, dt, fo.velocity);
      if (s != Status::ok) {
        restore();
        return s;
      }
    }
    leader_out = lo;
    follower_out = fo;
    return Status::ok;
  }

  /// New reference sensor poses X_fs' for both arms (e.g. the tall-object offsets).  Both or
  /// neither: a non-finite or non-orthonormal pose changes nothing.
  Status setReferences(const Group& leader_reference, const Group& follower_reference) noexcept {
    Status s = validateElement(leader_reference);
    if (s == Status::ok) s = validateElement(follower_reference);
    if (s != Status::ok) return s;
    // Both were validated above, the only check setReference makes: neither can refuse now.
    (void)leader_.setReference(leader_reference);
    (void)follower_.setReference(follower_reference);
    return Status::ok;
  }

  /// Clears both controllers and both filters (options kept): the next step re-initialises.
  void reset() noexcept {
    leader_.reset();
    follower_.reset();
    leader_filter_.reset();
    follower_filter_.reset();
  }
  bool terminated() const noexcept { return leader_.terminated(); }  ///< whether the leader has reached the target (latched)
  const Leader& leader() const noexcept { return leader_; }  ///< the leader's controller
  const Follower& follower() const noexcept { return follower_; }  ///< the follower's controller
  Leader& leader() noexcept { return leader_; }  ///< the leader's controller, to set its target
  Follower& follower() noexcept { return follower_; }  ///< the follower's controller
  const Filter& leaderFilter() const noexcept { return leader_filter_; }  ///< the leader's filter
  const Filter& followerFilter() const noexcept { return follower_filter_; }  ///< the follower's filter

 private:
  friend class Configurable<DualArmPushing>;
  Status apply(const Options& options) noexcept {  // validated (Configurable)
    if (const Status s = leader_.configure(options.leader); s != Status::ok) return s;
    return follower_.configure(options.follower);
  }

  static Status filterStep(Filter& filter, const ArmInput& in, ArmOutput& out) noexcept {
    const Status s = filterForControl(filter, in.sensor_pose, in.observation, out.outcome);
    if (s != Status::ok) return s;
    out.feature_in_sensor = filter.filtered().mean;
    return Status::ok;
  }

  Leader leader_{};
  Follower follower_{};
  Filter leader_filter_{};
  Filter follower_filter_{};
};

/// Options for the paper's dual-arm pushing (Table 8 dual-arm leader + Table 9 follower),
/// with the tall-object reference offsets of Section 5.7.2 (sec:dual_arm_tall_object_pushing) when
/// `tall_object` is true.
template <class Scalar, class Filter = DiscriminativeBayesFilter<SE3<Scalar>>>
typename DualArmPushing<SE3<Scalar>, Filter>::Options dualArmPushingPreset(bool tall_object = false,
                                                                      const PaperGainConvention& c = {}) {
  typename DualArmPushing<SE3<Scalar>, Filter>::Options o;
  o.leader = pushingPreset<Scalar>(tall_object ? PushingConfiguration::dual_arm_leader_tall_object
                                               : PushingConfiguration::dual_arm_leader,
                                   c);
  o.follower = stabiliserPreset<Scalar>(tall_object, c);
  return o;
}

}  // namespace lieservo

#include <lieservo/detail/options_pop.hpp>

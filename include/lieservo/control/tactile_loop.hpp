// lieservo/control/tactile_loop.hpp — the paper's tactile loop as one class (Figure 1,
// fig:system_architecture): each tactile frame, the observation Gaussian of the feature pose
// X_sf and the robot's sensor pose X_ws go through the discriminative Bayes filter (Algorithm 2,
// alg:se3_bayes_filter) and then the controller (Section 3.3, sec:se3_feedforward_feedback_control),
// which returns the sensor's body twist.
//
// One policy for every Status, the same in the simulation, the tests and the robot programs:
//   filter ok, first step      → LoopOutcome::initialised  (fil_0 = obs_0; the controller commands)
//   filter ok                  → LoopOutcome::commanded
//   filter outlier_rejected    → LoopOutcome::gated        (the controller uses the prediction)
//   controller terminated      → LoopOutcome::terminated   (the twist is zero: the push is over)
//   any other Status, from the loop's own checks, the filter or the controller
//                              → LoopOutcome::refused: step() returns that Status, NOTHING changes
//                                (filter, controller, the caller's twist); the caller sends no new
//                                command and ends the run (a robot: its watchdog and the ramped stop).
// step() returns Status::ok exactly when it wrote a twist.
//
// TactileLoop is the single-arm loop (TactileServoController<G> for tracking and surface
// following, PushingController<SE3<Scalar>> for pushing); DualArmPushing and CentralisedDualArmPushing
// run the same policy on each of their arms (filterForControl below).
#pragma once
#include <lieservo/detail/options_push.hpp>

#include <cmath>

#include <lieservo/configurable.hpp>
#include <lieservo/control/pushing_controller.hpp>
#include <lieservo/control/tactile_servo_controller.hpp>
#include <lieservo/estimation/bayes_filter.hpp>
#include <lieservo/estimation/concentrated_gaussian.hpp>
#include <lieservo/status.hpp>

namespace lieservo {

/// What one step of a tactile loop did (the header comment gives the policy).
enum class LoopOutcome : int {
  initialised,  ///< the filter started from this observation; the controller commanded
  commanded,    ///< the filter corrected with the observation; the controller commanded
  gated,        ///< the filter's χ² gate rejected the observation; the controller used the prediction
  terminated,   ///< the controller's task is over (pushing: the target is reached); the twist is zero
  refused,      ///< a check, the filter or the controller refused: nothing changed, no twist
};

/// The outcome's name (as the Python module gives it); never allocates.
constexpr const char* describe(LoopOutcome o) noexcept {
  switch (o) {
    case LoopOutcome::initialised: return "initialised";
    case LoopOutcome::commanded: return "commanded";
    case LoopOutcome::gated: return "gated";
    case LoopOutcome::terminated: return "terminated";
    case LoopOutcome::refused: return "refused";
  }
  return "unknown outcome";
}

/// The estimation half of the policy, for one arm: steps `filter` (the first step initialises)
/// and says what it did. ok with `outcome` initialised, commanded or gated (filtered() is then
/// the prediction); any other Status is the filter's refusal (its state unchanged, `outcome`
/// untouched).
template <class Filter, class G>
Status filterForControl(Filter& filter, const G& sensor_pose, const ConcentratedGaussian<G>& observation,
                        LoopOutcome& outcome) noexcept {
  const bool first = !filter.initialised();
  const Status s = filter.step(sensor_pose, observation);
  if (s == Status::outlier_rejected) {
    outcome = LoopOutcome::gated;
    return Status::ok;
  }
  if (s != Status::ok) return s;
  outcome = first ? LoopOutcome::initialised : LoopOutcome::commanded;
  return Status::ok;
}

namespace detail {

// The controller half: each controller's step, with the sensor pose where it takes one, and
// whether its task is over.
template <class G>
Status controlStep(TactileServoController<G>& c, const G&, const G& feature_in_sensor, typename G::Scalar dt,
                   typename G::Tangent& u) noexcept {
  return c.step(feature_in_sensor, dt, u);
}
template <class Scalar>
Status controlStep(PushingController<SE3<Scalar>>& c, const SE3<Scalar>& sensor_in_work,
                   const SE3<Scalar>& feature_in_sensor, Scalar dt, typename SE3<Scalar>::Tangent& u) noexcept {
  return c.step(sensor_in_work, feature_in_sensor, dt, u);
}
template <class G>
bool controlTerminated(const TactileServoController<G>&) noexcept {
  return false;
}
template <class Scalar>
bool controlTerminated(const PushingController<SE3<Scalar>>& c) noexcept {
  return c.terminated();
}

}  // namespace detail

/// The single-arm tactile loop (Figure 1, fig:system_architecture): the Bayes filter (Algorithm 2) and a
/// controller (TactileServoController<G> or PushingController<G>), stepped together under
/// the policy of the header comment. Real-time: step() is noexcept and allocation-free.
template <class Controller, class Filter = DiscriminativeBayesFilter<typename Controller::Group>>
class TactileLoop : public Configurable<TactileLoop<Controller, Filter>> {
 public:
  using Group = typename Controller::Group;  ///< the pose group
  using Scalar = typename Group::Scalar;  ///< float or double
  using Tangent = typename Group::Tangent;  ///< a twist
  using Observation = ConcentratedGaussian<Group>;  ///< an observation of X_sf with its covariance

  /// The filter's and the controller's options.
  struct Options {
    typename Filter::Options filter{};  ///< process noise, fusion, gating
    typename Controller::Options controller{};  ///< the controller (a paper preset, e.g. pushingPreset)
  };

  /// The default filter (the paper's) and a default controller.
  TactileLoop() noexcept { this->configureOnConstruction(Options()); }
  /// Configures with `options` (configurationStatus() keeps a refusal; step() returns it).
  explicit TactileLoop(const Options& options) noexcept { this->configureOnConstruction(options); }

  /// ok, or the filter's, then the controller's validate() Status.
  static Status validate(const Options& o) noexcept {
    if (const Status s = Filter::validate(o.filter); s != Status::ok) return s;
    return Controller::validate(o.controller);
  }
  /// Replaces both options (states kept); invalid options change nothing.
  Status configure(const Options& options) noexcept { return this->configureChecked(options); }

  /// One tactile frame: `sensor_pose` X_ws (proprioception), `observation` of X_sf (eq. 14,
  /// fromTangentGaussian), `dt` > 0 the time since the last frame; `u` receives the sensor body
  /// twist in {s}. ok exactly when `u` was written; outcome() says how. Any other Status:
  /// outcome() is refused and nothing else changes.
  Status step(const Group& sensor_pose, const Observation& observation, Scalar dt, Tangent& u) noexcept {
    outcome_ = LoopOutcome::refused;
    if (const Status c = this->configurationStatus(); c != Status::ok) return status_ = c;
    if (!(dt > Scalar(0)) || !std::isfinite(dt)) return status_ = Status::invalid_time_step;
    const Filter backup = filter_;  // the controller may still refuse: then the filter goes back
    LoopOutcome o = LoopOutcome::refused;
    Status s = filterForControl(filter_, sensor_pose, observation, o);
    if (s != Status::ok) return status_ = s;
    s = detail::controlStep(controller_, sensor_pose, filter_.filtered().mean, dt, u);
    if (s != Status::ok) {
      filter_ = backup;
      return status_ = s;
    }
    outcome_ = detail::controlTerminated(controller_) ? LoopOutcome::terminated : o;
    return status_ = Status::ok;
  }

  /// The filter forgets (the next step initialises) and the controller is cleared (options
  /// kept): a new contact.
  void reset() noexcept {
    filter_.reset();
    controller_.reset();
    outcome_ = LoopOutcome::refused;
    status_ = Status::not_initialised;
  }

  /// What the latest step did (refused before the first).
  LoopOutcome outcome() const noexcept { return outcome_; }
  /// The latest step's Status (ok when it commanded).
  Status lastStatus() const noexcept { return status_; }
  /// Whether the controller's task is over (pushing: latched until reset() or a new target).
  bool terminated() const noexcept { return detail::controlTerminated(controller_); }
  const Filter& filter() const noexcept { return filter_; }  ///< the Bayes filter
  const Controller& controller() const noexcept { return controller_; }  ///< the controller
  /// The controller, for what it sets between steps (a target, a reference, a feedforward).
  Controller& controller() noexcept { return controller_; }

 private:
  friend class Configurable<TactileLoop>;
  Status apply(const Options& options) noexcept {  // validated (Configurable)
    if (const Status s = filter_.configure(options.filter); s != Status::ok) return s;
    return controller_.configure(options.controller);
  }

  Filter filter_{};
  Controller controller_{};
  LoopOutcome outcome_ = LoopOutcome::refused;
  Status status_ = Status::not_initialised;
};

}  // namespace lieservo

#include <lieservo/detail/options_pop.hpp>

// Internal helpers shared by the task implementations (not installed).
#pragma once

#include <cmath>
#include <memory>

#include <lieservo/estimation/bayes_filter.hpp>
#include <lieservo/estimation/concentrated_gaussian.hpp>

#include "lieservo_sim/contact_model.hpp"
#include "lieservo_sim/observation_model.hpp"
#include "lieservo_sim/plot.hpp"
#include "lieservo_sim/simulated_arm.hpp"
#include "lieservo_sim/tasks.hpp"

namespace lieservo::sim::detail {

using Filter = lieservo::DiscriminativeBayesFilter<SE3d>;
using Gaussian = lieservo::ConcentratedGaussian<SE3d>;

/// GDN-like observation of the true contact → concentrated Gaussian on X_sf
/// (eq:se3_inverse_transform).
inline Status observeContact(GdnObservationModel& gdn, const ContactState& state, Gaussian& g) {
  const GdnObservation obs = gdn.observe(state);
  return lieservo::fromTangentGaussian<lieservo::ClosedFormJacobian>(obs.mu, obs.sigma, g);
}

/// Observation + filter step at sensor pose X_ws; X_sf receives the filtered mean. An
/// observation the filter's gate rejected is not an error (the prediction is used).
inline Status senseContact(GdnObservationModel& gdn, const ContactState& state, Filter& filter, const SE3d& X_ws,
                           SE3d& X_sf) {
  Gaussian g;
  Status s = observeContact(gdn, state, g);
  if (s != Status::ok) return s;
  s = filter.step(X_ws, g);  // the first step initialises
  if (s != Status::ok && s != Status::outlier_rejected) return s;
  X_sf = filter.filtered().mean;
  return Status::ok;
}

/// One sensorised arm: kinematic arm, contact model, GDN-like observations, Bayes filter.
struct SensorArm {
  SimulatedArm arm;
  ContactModel contact;
  GdnObservationModel gdn;
  Filter filter;
  ContactState state;

  SensorArm(const SE3d& X0, const Surface& surface, const TaskOptions& opt, std::uint64_t seed)
      : arm(X0, opt.arm), contact(surface, opt.contact), gdn(opt.calibration, {}, seed) {
    arm.stop();
  }
  /// Updates the true contact (stick/slip anchor) for object pose X_wo.
  void touch(const SE3d& X_wo) { state = contact.update(arm.pose(), X_wo); }
  Status observe(Gaussian& g) { return observeContact(gdn, state, g); }
  Status sense(SE3d& X_sf) { return senseContact(gdn, state, filter, arm.pose(), X_sf); }
  void resetEstimation() {
    filter = Filter();
    contact.release();
  }
};

inline std::string join(const std::string& dir, const std::string& file) {
  return dir.empty() ? file : (dir.back() == '/' ? dir + file : dir + "/" + file);
}

inline double wrapPi(double a) { return std::remainder(a, 2 * kPi); }

}  // namespace lieservo::sim::detail

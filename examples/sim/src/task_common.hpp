// Internal helpers shared by the task implementations (not installed).
#pragma once

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include <lieservo/estimation/bayes_filter.hpp>
#include <lieservo/estimation/concentrated_gaussian.hpp>

#include <lieservo_plot/svg_figure.hpp>

#include "lieservo_sim/contact_model.hpp"
#include "lieservo_sim/csv_log.hpp"
#include "lieservo_sim/mujoco_world.hpp"
#include "lieservo_sim/observation_model.hpp"
#include "lieservo_sim/sensor_arm.hpp"
#include "lieservo_sim/tasks.hpp"

namespace lieservo::sim {
// The tasks draw their figures with the examples' SVG figures.
using plot::SvgFigure;
using plot::SvgPanel;
}  // namespace lieservo::sim

namespace lieservo::sim::detail {

using Filter = lieservo::DiscriminativeBayesFilter<SE3d>;
using Gaussian = lieservo::ConcentratedGaussian<SE3d>;

/// GDN observation of the true contact → concentrated Gaussian on X_sf
/// (eq. 14, eq:se3_inverse_transform).
inline Status observeContact(ObservationSource& gdn, const ContactState& state, Gaussian& g) {
  GdnObservation obs;
  const Status s = gdn.observe(state, obs);
  if (s != Status::ok) return s;
  return lieservo::fromTangentGaussian(obs.mu, obs.sigma, g);  // DefaultJacobian, as the filter
}

/// Observation + filter step at sensor pose X_ws; X_sf receives the filtered mean. An
/// observation the filter's gate rejected is not an error (the prediction is used).
inline Status senseContact(ObservationSource& gdn, const ContactState& state, Filter& filter, const SE3d& X_ws,
                           SE3d& X_sf) {
  Gaussian g;
  Status s = observeContact(gdn, state, g);
  if (s != Status::ok) return s;
  s = filter.step(X_ws, g);  // the first step initialises
  if (s != Status::ok && s != Status::outlier_rejected) return s;
  X_sf = filter.filtered().mean;
  return Status::ok;
}

/// One sensorised arm in the MuJoCo world: the arm, the tactile contact state, its
/// observations (TaskOptions::observations, or its own seeded Gaussian model) and the Bayes
/// filter.
struct EngineArm {
  MujocoSensorArm arm;
  ContactModel contact;
  GdnObservationModel gaussian;
  std::shared_ptr<ObservationSource> shared;
  ObservationSource* gdn;
  Filter filter;
  ContactState state;

  EngineArm(mujoco::World& w, int sensor, const TaskOptions& opt, std::uint64_t seed)
      : arm(w, sensor, opt.arm),
        contact(opt.contact),
        gaussian(opt.calibration, {}, seed),
        shared(opt.observations),
        gdn(shared ? shared.get() : &gaussian) {}
  EngineArm(const EngineArm&) = delete;
  EngineArm& operator=(const EngineArm&) = delete;

  SE3d pose() const { return arm.pose(); }
  /// The contact from the engine's nearest surface point (nothing in range: no contact).
  void touch(const mujoco::World& w) { state = touchContact(w, arm.sensor(), contact); }
  Status observe(Gaussian& g) { return observeContact(*gdn, state, g); }
  Status sense(SE3d& X_sf) { return senseContact(*gdn, state, filter, pose(), X_sf); }
  /// A new start: the filter forgets, the next contact starts unsheared.
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

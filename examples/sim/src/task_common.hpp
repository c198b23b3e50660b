// Internal helpers shared by the task implementations (not installed).
#pragma once

#include <functional>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include <lieservo/control/tactile_loop.hpp>
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
/// Tracking and following: the paper's filter and the servo controller (control/tactile_loop.hpp).
using ServoLoop = lieservo::TactileLoop<lieservo::TactileServoController<SE3d>>;
/// Single-arm pushing: the paper's filter and the pushing controller.
using PushLoop = lieservo::TactileLoop<lieservo::PushingController<lieservo::SE3d>>;

/// GDN observation of the true contact → concentrated Gaussian on X_sf
/// (eq. 14, eq:se3_inverse_transform).
inline Status observeContact(ObservationSource& gdn, const ContactState& state, Gaussian& g) {
  GdnObservation obs;
  const Status s = gdn.observe(state, obs);
  if (s != Status::ok) return s;
  return lieservo::fromTangentGaussian(obs.mu, obs.sigma, g);  // DefaultJacobian, as the filter
}

/// One sensorised arm in the MuJoCo world: the arm, the tactile contact state and its
/// observations (TaskOptions::observations, or its own seeded Gaussian model). The filter and
/// the controller are the task's tactile loop.
struct EngineArm {
  MujocoSensorArm arm;
  ContactModel contact;
  GdnObservationModel gaussian;
  std::shared_ptr<ObservationSource> shared;
  ObservationSource* gdn;
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
  /// One tactile period: this arm's contact observed, then `loop` (a TactileLoop) stepped at
  /// the arm's pose; `u` receives the twist when the Status is ok (the loop's policy).
  template <class Loop>
  Status step(Loop& loop, double dt, Vec6& u) {
    Gaussian g;
    const Status s = observe(g);
    return s == Status::ok ? loop.step(pose(), g, dt, u) : s;
  }
  /// A new start: the loop forgets (its filter re-initialises), the next contact starts unsheared.
  template <class Loop>
  void restart(Loop& loop) {
    loop.reset();
    contact.release();
  }
};

inline std::string join(const std::string& dir, const std::string& file) {
  return dir.empty() ? file : (dir.back() == '/' ? dir + file : dir + "/" + file);
}

inline double wrapPi(double a) { return std::remainder(a, 2 * kPi); }

/// fn(i) for i in [0, n) on all cores (each run has its own world, filters and seed, so the
/// results do not depend on how many); the first exception is rethrown (task_pushing.cpp).
void parallelFor(int n, const std::function<void(int)>& fn);

/// A pushing case's statistics and its misses against the criteria (docs/simulation.md,
/// "Success criteria"; push_report.cpp).
PushingCase judgeCase(const PushingSetup& setup, std::vector<PushTrial> trials, bool judged, const TaskOptions& opt);
/// A pushing case's per-step log, dir/stem.csv (push_report.cpp).
void writeCase(const PushingCase& pc, const std::string& dir, const std::string& stem);

}  // namespace lieservo::sim::detail

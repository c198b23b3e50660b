// lieservo/estimation/bayes_filter.hpp — the discriminative Bayesian filter on a Lie group G
// (Algorithm 2 (alg:se3_bayes_filter), Section 3.2 (sec:se3_bayes_filter)).
//
// Inputs per step k: an observation PDF (X̄_k^obs, Σ_k^obs) — e.g. the GDN estimate converted by
// fromTangentGaussian (eq. 14, eq:se3_inverse_transform) — and the sensor pose X_k^sens.
//   Initialisation:  fil_0 = bel_0 = obs_0.
//   Prediction (eq. 12, eqn:bayes_filter_prediction, eq. 41 (eqn:se3_rv_probabilistic_transform_2)):
//       T̄_k = (X_k^sens)⁻¹ X_{k−1}^sens,   X̄_k^bel = T̄_k X̄_{k−1}^fil,
//       Σ_k^bel = Ad(T̄_k) Σ_{k−1}^fil Ad(T̄_k)ᵀ + Σφ                  (Σφ: eq. 16 (eqn:state_dynamics_noise_cov))
//   Correction (eq. 13, eqn:bayes_filter_correction): (X̄_k^fil, Σ_k^fil) = fuse(obs_k, bel_k)
//       by Algorithm 3 (alg:se3_data_fusion), the operating point starting at the observation (as the paper).
//
// Real-time contract: reset/step/predict/correct are noexcept, allocation-free, return a
// Status, and leave the filter state (belief, filtered, sensor pose, counters) unchanged unless
// the Status is ok — with one documented exception: Status::outlier_rejected (gating on) means
// the observation failed the χ² gate and the state was PREDICTED ONLY (filtered = belief).
// Diagnostics::last_status is updated on every call.
#pragma once
#include <lieservo/detail/options_push.hpp>

#include <cmath>
#include <cstdint>

#include <Eigen/Core>

#include <lieservo/configurable.hpp>
#include <lieservo/status.hpp>
#include <lieservo/estimation/chi_square.hpp>
#include <lieservo/estimation/concentrated_gaussian.hpp>
#include <lieservo/estimation/detail/linalg.hpp>
#include <lieservo/estimation/fusion.hpp>
#include <lieservo/estimation/jacobian_policy.hpp>

namespace lieservo {

/// The paper's state-dynamics noise (eq. 16, eqn:state_dynamics_noise_cov): σφ = 0.5 "mm/s and deg/s"
/// per component. Translation components get σ = 0.5 (caller's unit, the paper's mm) and
/// rotation components σ = 0.5° = 0.5·π/180 rad (this library works in radians), i.e.
/// Σφ = diag(0.25, …, (0.5 π/180)², …).
template <class G>
typename G::Jacobian paperProcessNoise() noexcept {
  using Scalar = typename G::Scalar;
  constexpr int R = detail::rotationDoF<G>();
  typename G::Jacobian S = G::Jacobian::Zero();
  const Scalar st = Scalar(0.5);
  const Scalar sr = deg2rad(Scalar(0.5));
  for (int i = 0; i < G::DoF; ++i) S(i, i) = (i < G::DoF - R) ? st * st : sr * sr;
  return S;
}

template <class G, class Policy = DefaultJacobian>
/// The discriminative Bayes filter on a Lie group G (Algorithm 2, alg:se3_bayes_filter):
/// predict with the sensor's own motion, correct by fusing the observation (Algorithm 3);
/// the header comment gives the equations and the real-time contract.
class DiscriminativeBayesFilter : public Configurable<DiscriminativeBayesFilter<G, Policy>> {
 public:
  using Group = G;  ///< the state's group
  using Scalar = typename G::Scalar;  ///< float or double
  using Tangent = typename G::Tangent;  ///< a tangent vector of G
  using Jacobian = typename G::Jacobian;  ///< a DoF × DoF matrix (covariances)
  using Gaussian = ConcentratedGaussian<G>;  ///< observations, belief and filtered state
  static constexpr int DoF = G::DoF;  ///< tangent dimension

  /// Process noise, fusion and gating; checked by validate().
  struct Options {
    /// Σφ of the state dynamics (finite, symmetric, positive SEMI-definite; 0 allowed).
    Jacobian process_noise = paperProcessNoise<G>();
    /// The correction's data fusion: FusionOptions::paper() (exactly 5 iterations, the default)
    /// or FusionOptions::converged() (stop once an update is under 0.001 standard deviations).
    FusionOptions<Scalar> fusion{};
    /// Reject observations whose NIS exceeds the χ²(DoF) quantile at gate_probability.
    bool gating = false;
    /// In (0, 1). 0.999 → threshold 22.46 for DoF 6, 16.27 for DoF 3, 10.83 for DoF 1.
    Scalar gate_probability = Scalar(0.999);
  };

  /// What the latest call did (updated on every call, failed ones included).
  struct Diagnostics {
    Status last_status = Status::not_initialised;  ///< Status of the latest call
    int iterations = 0;            ///< fusion iterations of the latest correction
    Scalar step_norm = Scalar(0);  ///< ‖μ‖ of the last fusion update
    Scalar step_sigmas = Scalar(0);  ///< √(μᵀ Σ*⁻¹ μ) of the last update (FusionResult)
    bool converged = false;        ///< the converged rule was met (FusionResult)
    Scalar nis = Scalar(0);        ///< normalised innovation squared of the latest observation
    bool gated = false;            ///< the latest observation was rejected by the gate
    Scalar gate_threshold = Scalar(0);  ///< χ²(DoF) quantile at gate_probability
    Scalar max_rotation_separation = Scalar(0);  ///< rad, obs vs belief (FusionResult)
    std::uint64_t corrections = 0;  ///< accepted observations (incl. the first)
    std::uint64_t rejected = 0;     ///< observations rejected by the gate
  };

  DiscriminativeBayesFilter() noexcept { this->configureOnConstruction(Options()); }
  /// Invalid options (see validate) leave the filter unusable: every call returns validate()'s
  /// Status (configurationStatus()) until configure succeeds.
  explicit DiscriminativeBayesFilter(const Options& options) noexcept { this->configureOnConstruction(options); }

  /// ok, or the first reason: the fusion options' (FusionOptions::validate), non_finite_input /
  /// invalid_argument (gate_probability NaN / outside (0, 1)), non_finite_input / not_spd
  /// (process noise).
  static Status validate(const Options& o) noexcept {
    if (const Status s = o.fusion.validate(); s != Status::ok) return s;
    if (std::isnan(o.gate_probability)) return Status::non_finite_input;
    if (!(o.gate_probability > Scalar(0) && o.gate_probability < Scalar(1)))
      return Status::invalid_argument;
    return detail::checkPsd(o.process_noise);
  }

  /// Replaces the options (not real-time: computes the gate threshold). State is kept.
  /// Invalid options: the Status says why and nothing changes.
  Status configure(const Options& o) noexcept { return this->configureChecked(o); }
  const Options& options() const noexcept { return options_; }  ///< the options in force

  /// One step of Algorithm 2 (alg:se3_bayes_filter). The first step after construction or reset() is the
  /// algorithm's initialisation, fil_0 = bel_0 = obs_0, remembering X_0^sens; every later step
  /// predicts with T̄_k = (X_k^sens)⁻¹ X_{k−1}^sens, then corrects with the observation.
  /// Atomic: on any error nothing changes; on outlier_rejected the state is the prediction
  /// (and the sensor pose is advanced).
  Status step(const G& sensor_pose, const Gaussian& observation) noexcept {
    if (const Status c = this->configurationStatus(); c != Status::ok) return diag_.last_status = c;
    Status s = validateElement(sensor_pose);
    if (s != Status::ok) return diag_.last_status = s;
    if (!initialised_) return initialise(sensor_pose, observation);
    const G T_bar = sensor_pose.inverse() * sensor_pose_;
    Gaussian bel;
    Jacobian L[2];  // the Cholesky factors of the observation's and the belief's covariances
    s = predictInto(filtered_, T_bar, bel, L[1]);
    if (s != Status::ok) return diag_.last_status = s;
    FusionResult<G> fused;
    Diagnostics d = diag_;
    s = correctInto(bel, observation, L, fused, d);
    if (s != Status::ok && s != Status::outlier_rejected) return diag_.last_status = s;
    filtered_ = s == Status::ok ? fused.fused : bel;
    belief_ = bel;
    sensor_pose_ = sensor_pose;
    diag_ = d;
    return diag_.last_status = s;
  }

  /// Prediction only (eq. 12, eqn:bayes_filter_prediction) with an explicit T̄: belief = T̄·filtered
  /// (+Σφ), and filtered ← belief (no observation yet). The stored sensor pose is unchanged.
  /// T̄ maps the feature's pose in the previous sensor frame to the new one: for sensor poses
  /// X_{k−1} and X_k in the world, T̄ = X_k⁻¹ X_{k−1} (as step() forms it), the INVERSE of the
  /// sensor's odometry increment X_{k−1}⁻¹ X_k.
  Status predict(const G& T_bar) noexcept {
    if (const Status c = this->configurationStatus(); c != Status::ok) return diag_.last_status = c;
    if (!initialised_) return diag_.last_status = Status::not_initialised;
    Status s = validateElement(T_bar);
    if (s != Status::ok) return diag_.last_status = s;
    Gaussian bel;
    Jacobian L_bel;
    s = predictInto(filtered_, T_bar, bel, L_bel);
    if (s != Status::ok) return diag_.last_status = s;
    belief_ = bel;
    filtered_ = bel;
    return diag_.last_status = Status::ok;
  }

  /// Prediction only, from the sensor's odometry increment ΔX = X_{k−1}⁻¹ X_k (the new sensor
  /// pose in the previous sensor frame, the increment a robot or an odometry source reports):
  /// predict(ΔX⁻¹). The same refusals as predict(), checked on ΔX; state unchanged on error.
  Status predictFromOdometry(const G& sensor_increment) noexcept {
    if (const Status c = this->configurationStatus(); c != Status::ok) return diag_.last_status = c;
    if (!initialised_) return diag_.last_status = Status::not_initialised;
    const Status s = validateElement(sensor_increment);
    if (s != Status::ok) return diag_.last_status = s;
    return predict(sensor_increment.inverse());
  }

  /// Correction only (eq. 13, eqn:bayes_filter_correction): fuses the observation with the current
  /// state (the belief after predict()). outlier_rejected leaves the state as it was.
  Status correct(const Gaussian& observation) noexcept {
    if (const Status c = this->configurationStatus(); c != Status::ok) return diag_.last_status = c;
    if (!initialised_) return diag_.last_status = Status::not_initialised;
    Jacobian L[2];
    Status s = detail::choleskyChecked(filtered_.covariance, L[1]);
    if (s != Status::ok) return diag_.last_status = s;
    FusionResult<G> fused;
    Diagnostics d = diag_;
    s = correctInto(filtered_, observation, L, fused, d);
    if (s != Status::ok && s != Status::outlier_rejected) return diag_.last_status = s;
    if (s == Status::ok) filtered_ = fused.fused;  // rejected: the state stays as it was
    diag_ = d;
    return diag_.last_status = s;
  }

  /// (X̄_k^bel, Σ_k^bel): the prediction of the latest step.
  const Gaussian& belief() const noexcept { return belief_; }
  /// (X̄_k^fil, Σ_k^fil): the filtered state.
  const Gaussian& filtered() const noexcept { return filtered_; }
  /// X_k^sens of the latest accepted step (or reset).
  const G& sensorPose() const noexcept { return sensor_pose_; }
  const Diagnostics& diagnostics() const noexcept { return diag_; }  ///< what the latest call did
  bool initialised() const noexcept { return initialised_; }  ///< whether a first observation has initialised the state
  /// Back to the uninitialised state (options kept): the next step() initialises.
  void reset() noexcept {
    initialised_ = false;
    belief_ = Gaussian();
    filtered_ = Gaussian();
    sensor_pose_ = G();
    clearDiagnostics();
  }

 private:
  friend class Configurable<DiscriminativeBayesFilter>;
  Status apply(const Options& o) noexcept {  // validated (Configurable); not real-time: the gate threshold
    options_ = o;
    detail::symmetrize(options_.process_noise);
    diag_.gate_threshold = Scalar(chiSquareQuantile(double(o.gate_probability), double(G::DoF)));
    return Status::ok;
  }

  // Initialisation of Algorithm 2 (alg:se3_bayes_filter): fil_0 = bel_0 = obs_0 (step() checked the pose).
  Status initialise(const G& sensor_pose, const Gaussian& first_observation) noexcept {
    const Status s = first_observation.validate();
    if (s != Status::ok) return diag_.last_status = s;
    belief_ = first_observation;
    detail::symmetrize(belief_.covariance);
    filtered_ = belief_;
    sensor_pose_ = sensor_pose;
    initialised_ = true;
    clearDiagnostics();
    diag_.corrections = 1;
    return diag_.last_status = Status::ok;
  }

  // Fresh diagnostics; the gate threshold belongs to the options and stays.
  void clearDiagnostics() noexcept {
    const Scalar thr = diag_.gate_threshold;
    diag_ = Diagnostics();
    diag_.gate_threshold = thr;
  }

  // The state is valid at all times (initialise validates it, fuse checks what it returns) and
  // the options were validated by configure, so the step checks only what comes from outside: the
  // sensor pose and the observation. T̄ is a product of valid elements. Each covariance is
  // factorised once per step and its Cholesky factor handed on to the fusion. The outputs are
  // the caller's scratch (written in place, no temporaries copied), stored only on success.
  Status predictInto(const Gaussian& fil, const G& T_bar, Gaussian& bel, Jacobian& L_bel) const noexcept {
    // eq. 12 (eqn:bayes_filter_prediction): eq. 41's products, as transformUnchecked
    detail::transformProducts(fil, T_bar, options_.process_noise, bel);
    bel.mean.normalize();
    if (!bel.mean.allFinite()) return Status::numerical_failure;
    // repairSpd symmetrises, checks finiteness and factorises
    if (detail::repairSpd(bel.covariance, &L_bel) != Status::ok) return Status::numerical_failure;
    return Status::ok;
  }

  // L[1] holds the belief's Cholesky factor; L[0] receives the observation's. On ok, `fused` is
  // the correction; on outlier_rejected the caller keeps the belief.
  Status correctInto(const Gaussian& bel, const Gaussian& obs, Jacobian (&L)[2], FusionResult<G>& fused,
                     Diagnostics& d) const noexcept {
    Status s = validateElement(obs.mean);
    if (s != Status::ok) return s;
    s = detail::choleskyChecked(obs.covariance, L[0]);
    if (s != Status::ok) return s;
    // The innovation ν = ln(X̄_obs X̄_bel⁻¹)^∨ is also the belief's ξ at the fusion's first
    // operating point (the observation): it and its J(ν)⁻¹ are computed once, as the fusion
    // would compute them.
    detail::InitialResidual<G> innovation;
    innovation.xi = Policy::logAndInverse(obs.mean * bel.mean.inverse(), innovation.Jinv);
    Scalar nis(0);
    s = detail::innovationNis<G>(innovation.xi, obs.covariance, bel.covariance, nis);
    if (s != Status::ok) return s;
    if (options_.gating && !(nis <= d.gate_threshold)) {
      d.nis = nis;
      d.gated = true;
      d.iterations = 0;
      d.step_norm = Scalar(0);
      d.step_sigmas = Scalar(0);
      d.converged = false;
      ++d.rejected;
      return Status::outlier_rejected;
    }
    // Algorithm 3 (alg:se3_data_fusion), the operating point starting at the observation (as the paper).
    const G means[2] = {obs.mean, bel.mean};
    s = detail::fuseFactored<Policy>(means, L, 2, options_.fusion, fused, &innovation);
    if (s != Status::ok) return s;
    const FusionResult<G>& r = fused;
    d.nis = nis;
    d.gated = false;
    d.iterations = r.iterations;
    d.step_norm = r.step_norm;
    d.step_sigmas = r.step_sigmas;
    d.converged = r.converged;
    d.max_rotation_separation = r.max_rotation_separation;
    ++d.corrections;
    return Status::ok;
  }

  Options options_{};
  Gaussian belief_{};
  Gaussian filtered_{};
  G sensor_pose_{};
  bool initialised_ = false;
  Diagnostics diag_{};
};

}  // namespace lieservo

#include <lieservo/detail/options_pop.hpp>

// The Table 2 experiment (tab:bayes_filter_results): the process noise and motions of the
// paper's replay (eqs. 23-24) and the SE(3) Bayes filter over one sequence of observations.
#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

#include <lieservo/sampling/random.hpp>

#include "lieservo/estimation/bayes_filter.hpp"
#include "lieservo/units.hpp"
#include "replay.hpp"

namespace lieservo::replay {

namespace {

/// σψ per tangent component: mm for ρ, degrees converted to radians for φ.
SE3d::Tangent psiSigma(double sig) {
  SE3d::Tangent sd;
  sd << sig, sig, sig, deg2rad(sig), deg2rad(sig), deg2rad(sig);
  return sd;
}
}  // namespace

SE3d::Jacobian replayProcessNoise(double sig) { return psiSigma(sig).array().square().matrix().asDiagonal(); }

std::vector<SE3d> replayMotions(const std::vector<Sample>& samples, double sig, std::uint64_t seed) {
  const std::size_t n = samples.size();
  std::vector<SE3d> X(n), T(n);
  for (std::size_t i = 0; i < n; ++i) {
    SE3d::Tangent xi;
    for (int j = 0; j < 6; ++j) xi(j) = samples[i].xi[static_cast<std::size_t>(j)];
    X[i] = SE3d::exp(xi);
  }
  const SE3d::Tangent sd = psiSigma(sig);
  lieservo::sampling::Rng rng(seed);
  for (std::size_t k = 1; k < n; ++k) {
    SE3d::Tangent psi;
    for (int j = 0; j < 6; ++j) psi(j) = sd(j) * lieservo::sampling::standardNormal(rng);
    T[k] = SE3d::exp(psi) * X[k] * X[k - 1].inverse();
  }
  return T;
}

namespace {

// How far the filter's correction at this step is from the fusion run to convergence from the
// same belief (`reference`, a copy of the filter before the step): the worst so far in `worst`.
void measureFusionError(const DiscriminativeBayesFilter<SE3d>& filter, DiscriminativeBayesFilter<SE3d>& reference,
                        const SE3d& T, const ConcentratedGaussian<SE3d>& obs, FusionError& worst) {
  if (reference.predict(T) != Status::ok || reference.correct(obs) != Status::ok) return;
  const SE3d::Tangent e = lminus(filter.filtered().mean, reference.filtered().mean);
  worst.mm = std::max(worst.mm, e.head<3>().norm());
  worst.rad = std::max(worst.rad, e.tail<3>().norm());
  const Eigen::LLT<SE3d::Jacobian> llt(reference.filtered().covariance);
  worst.sigma = std::max(worst.sigma, llt.matrixL().solve(e).norm());
}

// Step k's filtered estimate (mm, deg) and precision (1/mm, 1/deg) into the run, its error
// against the label `actual` into the row's sums.
void recordEstimate(const DiscriminativeBayesFilter<SE3d>& filter, std::size_t k, const Vec6& actual, FilterRun& run) {
  const ConcentratedGaussian<SE3d>& f = filter.filtered();
  SE3d::Tangent mu;
  SE3d::Jacobian Sxi;
  if (toTangentGaussian(f, mu, Sxi) != Status::ok) {
    mu = f.mean.log();
    Sxi = f.covariance;
  }
  run.mu[k] = toReportUnits(mu);
  run.mean[k] = f.mean;
  const Eigen::Matrix<double, 6, 1> sdev = Sxi.diagonal().cwiseMax(0.0).cwiseSqrt();
  run.precision[k] = precisionReportUnits(sdev);
  for (std::size_t j = 0; j < 6; ++j) {
    run.row.mae[j] += std::fabs(run.mu[k][j] - actual[j]);
    run.row.mean_sigma[j] += 1.0 / run.precision[k][j];
  }
}

}  // namespace

Vec6 poseMae(const std::vector<SE3d>& X, const std::vector<Sample>& samples) {
  Vec6 sum = Vec6::Zero();
  for (std::size_t k = 0; k < X.size(); ++k) sum += (toReportUnits(X[k].log()) - toReportUnits(samples[k].xi)).cwiseAbs();
  return sum / static_cast<double>(X.size());
}

FilterRun replayFilter(const std::vector<Sample>& samples, const std::vector<ConcentratedGaussian<SE3d>>& obs,
                       double sig, std::uint64_t seed, const FusionOptions<double>& fusion, bool measure_fusion_error) {
  const std::size_t n = std::min(samples.size(), obs.size());
  FilterRun run;
  FilterRow& row = run.row;
  row.sigma_psi = sig;
  if (n == 0) return run;
  const std::vector<SE3d> T = replayMotions(samples, sig, seed);
  DiscriminativeBayesFilter<SE3d>::Options fo;
  fo.process_noise = replayProcessNoise(sig);  // Σφ = Σψ
  fo.fusion = fusion;
  DiscriminativeBayesFilter<SE3d> filter(fo);
  DiscriminativeBayesFilter<SE3d>::Options full = fo;  // the reference: the fusion run to convergence
  full.fusion.max_iterations = 50;
  full.fusion.tolerance = 1e-12;
  full.fusion.require_convergence = false;
  run.mu.resize(n);
  run.precision.resize(n);
  run.mean.resize(n);
  long iterations = 0, corrections = 0;
  for (std::size_t k = 0; k < n; ++k) {
    Status s = Status::ok;
    if (k == 0) {
      s = filter.step(SE3d(), obs[0]);  // the first step initialises
    } else {
      std::optional<DiscriminativeBayesFilter<SE3d>> reference;  // the same state, the reference fusion
      if (measure_fusion_error) {
        reference = filter;
        if (reference->configure(full) != Status::ok) throw std::logic_error("replayFilter: reference options rejected");
      }
      s = filter.predict(T[k]);
      if (s == Status::ok) s = filter.correct(obs[k]);
      if (s == Status::ok) {
        iterations += filter.diagnostics().iterations;
        ++corrections;
        if (reference) measureFusionError(filter, *reference, T[k], obs[k], run.fusion_error);
      }
    }
    if (s != Status::ok) {
      ++row.failures;
      if (row.failures <= 3)
        run.notes.push_back("sigma_psi " + std::to_string(sig) + ": step " + std::to_string(k) + " (" +
                            samples[k].image + "): " + describe(s) + "; filter re-initialised");
      filter.reset();
      (void)filter.step(SE3d(), obs[k]);  // a failure of this step too shows in the next one
    }
    recordEstimate(filter, k, toReportUnits(samples[k].xi), run);
  }
  for (std::size_t j = 0; j < 6; ++j) {
    row.mae[j] /= static_cast<double>(n);
    row.mean_sigma[j] /= static_cast<double>(n);
  }
  row.mean_iterations = corrections > 0 ? static_cast<double>(iterations) / static_cast<double>(corrections) : 0.0;
  return run;
}

}  // namespace lieservo::replay

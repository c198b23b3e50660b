// Table 2's experiment through the fixed-interval smoother (lieservo_ceres/smoother.hpp): the
// same observations, motions (eq. 23, eqn:se3_filter_exp_state_trans_model) and process noise
// (eq. 24, eqn:se3_filter_exp_state_trans_cov) as the filter, solved over the whole sequence.
#include <lieservo_ceres/smoother.hpp>

#include "replay.hpp"

namespace lieservo::replay {

SmootherRow replaySmoother(const std::vector<Sample>& samples, const std::vector<ConcentratedGaussian<SE3d>>& obs,
                           double sigma_psi, std::uint64_t seed, bool time_closed_form) {
  namespace sm = lieservo::ceres_adapter;
  SmootherRow row;
  row.sigma_psi = sigma_psi;
  row.filter = poseMae(replayFilter(samples, obs, sigma_psi, seed).mean, samples);
  const std::vector<SE3d> motions = replayMotions(samples, sigma_psi, seed);
  const SE3d::Jacobian Q = replayProcessNoise(sigma_psi);  // Σφ = Σψ, as the filter's
  std::vector<SE3d> with_jets, closed_form;
  sm::SmootherOptions o;
  const sm::SmootherReport r_ad = sm::smooth(obs, motions, Q, with_jets, o);
  sm::SmootherReport r_cf;
  if (time_closed_form && r_ad.status == Status::ok) {
    o.jacobians = sm::SmootherOptions::Jacobians::closed_form;
    r_cf = sm::smooth(obs, motions, Q, closed_form, o);
  }
  if (r_ad.status != Status::ok || r_cf.status != Status::ok) {
    row.refused = r_ad.status != Status::ok ? r_ad.message : r_cf.message;
    return row;
  }
  row.smoothed = poseMae(with_jets, samples);
  row.seconds_autodiff = r_ad.seconds;
  row.seconds_closed_form = r_cf.seconds;
  row.iterations = r_ad.iterations;
  return row;
}

}  // namespace lieservo::replay

// The fixed-interval smoother (examples/adapters/ceres, lieservo_ceres/smoother.hpp).
//
// Criteria (fixed before the first run):
//   - the closed-form residual Jacobians equal the Jets' to 1e-12 (relative to max(1, the largest
//     entry)) on 10^4 seeded pose pairs, motions and observations;
//   - on seeded 200-frame sequences from the filter's own model both variants converge to the
//     same trajectory (every pose within 1e-8 of each other), and the smoothed trajectory's cost
//     is at or below that of the observations' means and that of the filter's trajectory (the
//     smoother minimises the cost the filter's estimates are also scored on);
//   - a missing frame (a shorter observation list, a NaN observation), a non-SPD observation
//     covariance, a non-rigid motion and a solver stopped before convergence are refused with
//     the right Status and frame, and the caller's trajectory is unchanged.
#include <lieservo_ceres/smoother.hpp>

#include <cmath>
#include <limits>

#include <catch2/catch.hpp>
#include <lieservo/estimation/bayes_filter.hpp>
#include <lieservo/sampling/random.hpp>

namespace {

using namespace lieservo;
using lieservo::ceres_adapter::AmbientOf;
using lieservo::ceres_adapter::SmootherOptions;
using lieservo::ceres_adapter::SmootherReport;
using lieservo::sampling::Rng;
using SE3d = SE3<double>;
using Vec6 = SE3d::Tangent;
using Mat6 = SE3d::Jacobian;

Vec6 normal6(Rng& rng, const Vec6& sd) {
  Vec6 v;
  for (int j = 0; j < 6; ++j) v[j] = sd[j] * sampling::standardNormal(rng);
  return v;
}

struct Sequence {
  std::vector<SE3d> truth, motions;
  std::vector<ConcentratedGaussian<SE3d>> obs;
  Mat6 Q;
};

// X_k = exp(φ_k^) T_k X_{k−1}, Z_k = exp(ε_k^) X_k: the filter's own two models, with a
// known motion of a few mm and degrees per frame.
Sequence drawSequence(std::uint64_t seed, std::size_t n) {
  Rng rng(seed);
  Sequence s;
  const Vec6 sd_obs = (Vec6() << 0.4, 0.4, 0.1, 0.01, 0.012, 0.02).finished();
  const Vec6 sd_psi = (Vec6() << 0.1, 0.1, 0.1, 0.002, 0.002, 0.002).finished();
  s.Q = sd_psi.array().square().matrix().asDiagonal();
  const Mat6 R = sd_obs.array().square().matrix().asDiagonal();
  s.motions.assign(n, SE3d());
  s.truth.push_back(SE3d::exp(sampling::uniformVector<6>(rng, -0.5, 0.5)));
  for (std::size_t k = 1; k < n; ++k) {
    s.motions[k] = SE3d::exp(sampling::uniformVector<6>(rng, -0.05, 0.05) * 20.0);
    s.truth.push_back(SE3d::exp(normal6(rng, sd_psi)) * s.motions[k] * s.truth.back());
  }
  for (const SE3d& X : s.truth) s.obs.push_back({SE3d::exp(normal6(rng, sd_obs)) * X, R});
  return s;
}

double cost(const Sequence& s, const std::vector<SE3d>& X) {
  const Eigen::LLT<Mat6> q(s.Q);
  double c = 0;
  for (std::size_t k = 0; k < X.size(); ++k) {
    const Eigen::LLT<Mat6> r(s.obs[k].covariance);
    c += r.matrixL().solve(lminus(X[k], s.obs[k].mean)).squaredNorm();
    if (k > 0) c += q.matrixL().solve(lminus(X[k], s.motions[k] * X[k - 1])).squaredNorm();
  }
  return 0.5 * c;
}

double relDiff(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(1.0, b.cwiseAbs().maxCoeff());
}

Eigen::Matrix<double, 7, 1> ambient(const SE3d& X) {
  Eigen::Matrix<double, 7, 1> a;
  ceres_adapter::detail::write(X, a.data());
  return a;
}

}  // namespace

TEST_CASE("smoother: the closed-form residual Jacobians equal the Jets'", "[ceres][autodiff][smoother]") {
  Rng rng(20261202);
  double worst = 0;
  for (int i = 0; i < 10000; ++i) {
    const SE3d A = SE3d::exp(sampling::uniformVector<6>(rng, -2.0, 2.0));
    const SE3d B = SE3d::exp(sampling::uniformVector<6>(rng, -2.0, 2.0));
    const SE3d T = SE3d::exp(sampling::uniformVector<6>(rng, -2.0, 2.0));
    Mat6 W = Mat6::Random() * 0.1;
    W += Mat6::Identity();
    const Eigen::Matrix<double, 7, 1> a = ambient(A), b = ambient(B);
    const double* blocks[2] = {a.data(), b.data()};
    Eigen::Matrix<double, 6, 1> r_ad, r_cf;
    Eigen::Matrix<double, 6, 7, Eigen::RowMajor> J0_ad, J1_ad, J0_cf, J1_cf;
    double* J_ad[2] = {J0_ad.data(), J1_ad.data()};
    double* J_cf[2] = {J0_cf.data(), J1_cf.data()};

    ceres::AutoDiffCostFunction<ceres_adapter::detail::MotionResidual, 6, 7, 7> motion_ad(
        new ceres_adapter::detail::MotionResidual{T, W});
    ceres_adapter::detail::MotionCost motion_cf(T, W);
    REQUIRE(motion_ad.Evaluate(blocks, r_ad.data(), J_ad));
    REQUIRE(motion_cf.Evaluate(blocks, r_cf.data(), J_cf));
    worst = std::max({worst, relDiff(r_cf, r_ad), relDiff(J0_cf, J0_ad), relDiff(J1_cf, J1_ad)});

    ceres::AutoDiffCostFunction<ceres_adapter::detail::ObservationResidual, 6, 7> obs_ad(
        new ceres_adapter::detail::ObservationResidual{B, W});
    ceres_adapter::detail::ObservationCost obs_cf(B, W);
    REQUIRE(obs_ad.Evaluate(blocks, r_ad.data(), J_ad));
    REQUIRE(obs_cf.Evaluate(blocks, r_cf.data(), J_cf));
    worst = std::max({worst, relDiff(r_cf, r_ad), relDiff(J0_cf, J0_ad)});
  }
  INFO("largest relative difference " << worst);
  CHECK(worst <= 1e-12);
}

TEST_CASE("smoother: both Jacobian variants reach the same trajectory, at or below the filter's cost",
          "[ceres][autodiff][smoother]") {
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    const Sequence s = drawSequence(seed, 200);
    std::vector<SE3d> ad, cf;
    SmootherOptions o;
    const SmootherReport r_ad = ceres_adapter::smooth(s.obs, s.motions, s.Q, ad, o);
    o.jacobians = SmootherOptions::Jacobians::closed_form;
    const SmootherReport r_cf = ceres_adapter::smooth(s.obs, s.motions, s.Q, cf, o);
    INFO("seed " << seed << ": " << r_ad.message << r_cf.message);
    REQUIRE(r_ad.status == Status::ok);
    REQUIRE(r_cf.status == Status::ok);
    REQUIRE(ad.size() == 200);
    double apart = 0;
    for (std::size_t k = 0; k < ad.size(); ++k) apart = std::max(apart, lminus(ad[k], cf[k]).norm());
    CHECK(apart <= 1e-8);

    DiscriminativeBayesFilter<SE3d>::Options fo;
    fo.process_noise = s.Q;
    DiscriminativeBayesFilter<SE3d> filter(fo);
    std::vector<SE3d> filtered, means;
    for (std::size_t k = 0; k < s.obs.size(); ++k) {
      REQUIRE(filter.step(s.motions[k], s.obs[k]) == Status::ok);
      filtered.push_back(filter.filtered().mean);
      means.push_back(s.obs[k].mean);
    }
    CHECK(cost(s, ad) <= cost(s, filtered));
    CHECK(cost(s, ad) <= cost(s, means));
    CHECK(r_ad.final_cost == Approx(cost(s, ad)).epsilon(1e-9));
  }
}

TEST_CASE("smoother: bad input is refused with its frame, and the trajectory is kept", "[ceres][autodiff][smoother]") {
  const Sequence s = drawSequence(7, 30);
  const std::vector<SE3d> kept(3, SE3d::exp(Vec6::Constant(0.1)));
  auto refused = [&](const std::vector<ConcentratedGaussian<SE3d>>& obs, const std::vector<SE3d>& motions,
                     Status status, long frame, const SmootherOptions& o = {}) {
    std::vector<SE3d> poses = kept;
    const SmootherReport r = ceres_adapter::smooth(obs, motions, s.Q, poses, o);
    INFO(r.message);
    CHECK(r.status == status);
    CHECK(r.frame == frame);
    CHECK(r.message.find("frame " + std::to_string(frame)) != std::string::npos);
    REQUIRE(poses.size() == kept.size());
    for (std::size_t k = 0; k < kept.size(); ++k) CHECK(poses[k].matrix() == kept[k].matrix());
  };
  SECTION("a missing frame: one observation fewer than motions") {
    auto obs = s.obs;
    obs.pop_back();
    refused(obs, s.motions, Status::invalid_argument, 29);
  }
  SECTION("a missing frame: a NaN observation") {
    auto obs = s.obs;
    obs[11].covariance(2, 2) = std::numeric_limits<double>::quiet_NaN();
    refused(obs, s.motions, Status::non_finite_input, 11);
  }
  SECTION("a non-SPD observation covariance") {
    auto obs = s.obs;
    obs[5].covariance(4, 4) = -1e-3;
    refused(obs, s.motions, Status::not_spd, 5);
  }
  SECTION("a motion that is not a rigid transform") {
    auto motions = s.motions;
    Eigen::Matrix4d M = motions[8].matrix();
    M(0, 0) *= 1.1;
    motions[8] = SE3d::fromMatrixUnchecked(M);
    refused(s.obs, motions, Status::not_orthonormal, 8);
  }
  SECTION("a solver that does not converge") {
    SmootherOptions o;
    o.max_iterations = 1;
    std::vector<SE3d> poses = kept;
    const SmootherReport r = ceres_adapter::smooth(s.obs, s.motions, s.Q, poses, o);
    INFO(r.message);
    CHECK(r.status == Status::not_converged);
    CHECK(r.frame >= 0);
    CHECK(r.frame < 30);
    CHECK(r.message.find("frame " + std::to_string(r.frame)) != std::string::npos);
    for (std::size_t k = 0; k < kept.size(); ++k) CHECK(poses[k].matrix() == kept[k].matrix());
  }
}

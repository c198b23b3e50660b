// The discriminative Bayesian filter (Algorithm 2, alg:se3_bayes_filter): linear-Kalman limit, statistical
// consistency (NEES/NIS), gating, bad input, other groups, float vs double.
#include <catch2/catch.hpp>

#include <cstdio>
#include <cstring>
#include <type_traits>
#include <vector>

#include "estimation_test_helpers.hpp"
#include "test_support.hpp"

using namespace lieservo;
using namespace lieservo::est_test;

using SE3d = SE3<double>;
using SE3f = SE3<float>;
using SO3d = SO3<double>;
using SE2d = SE2<double>;
using SO2d = SO2<double>;

static_assert(noexcept(std::declval<DiscriminativeBayesFilter<SE3d>&>().step(
                  std::declval<const SE3d&>(), std::declval<const ConcentratedGaussian<SE3d>&>())),
              "step must be noexcept");
static_assert(noexcept(std::declval<DiscriminativeBayesFilter<SE3f>&>().reset()),
              "reset must be noexcept");

namespace {

/// A simulated pose-and-shear sequence following the filter's own model:
///   X_k = exp(φ_k^) T̄_k X_{k−1},  T̄_k = (X_k^sens)⁻¹ X_{k−1}^sens,  φ_k ~ N(0, Σφ),
///   X̄_k^obs = exp(n_k^) X_k,  n_k ~ N(0, Σ_k^obs)   (⇔ X_k = exp(−n_k^) X̄_k^obs: the
///   discriminative observation PDF p(x_k|y_k) of the filter).
template <class G>
struct Simulator {
  using Tangent = typename G::Tangent;
  using Jacobian = typename G::Jacobian;
  lieservo::sampling::Rng rng;
  Jacobian Sphi;
  Tangent obs_sigma;        // nominal observation σ per component
  double motion_scale;      // sensor motion per step (tangent σ)
  bool heteroscedastic = true;
  G X, sens;

  Simulator(unsigned seed, const Jacobian& process, const Tangent& sigma, double motion)
      : rng(seed), Sphi(process), obs_sigma(sigma), motion_scale(motion) {
    X = G::exp(randn<Tangent>(rng, 0.5));
    sens = G::exp(randn<Tangent>(rng, 1.0));
  }
  ConcentratedGaussian<G> observe() {
    Tangent s = obs_sigma;
    if (heteroscedastic)
      for (int i = 0; i < G::DoF; ++i) s[i] *= std::exp(uniform(rng, -0.7, 0.7));
    ConcentratedGaussian<G> o;
    o.covariance = correlatedCovariance<G>(rng, s);
    const ConcentratedGaussian<G> noise(G(), o.covariance);
    o.mean = draw(noise, rng) * X;  // exp(n) X
    return o;
  }
  /// Moves the sensor and the true state; returns the new sensor pose.
  G advance() {
    const G prev = sens;
    sens = sens * G::exp(randn<Tangent>(rng, motion_scale));
    const G T = sens.inverse() * prev;
    const ConcentratedGaussian<G> phi(T, Sphi);
    X = draw(phi, rng) * X;
    return sens;
  }
};

template <class G>
typename G::Jacobian diagCov(const typename G::Tangent& sigma) {
  return sigma.array().square().matrix().asDiagonal();
}

/// GDN-like per-component σ (paper Table 1 (tab:nn_pose_shear_estimate_results)): 0.4, 0.4, 0.12 mm
/// and 0.5°, 0.6°, 1.2°.
SE3d::Tangent gdnSigma() {
  SE3d::Tangent s;
  s << 0.4, 0.4, 0.12, 0.5 * kDeg, 0.6 * kDeg, 1.2 * kDeg;
  return s;
}

template <class G>
struct FilterSnapshot {
  Eigen::Matrix<typename G::Scalar, Eigen::Dynamic, 1> bytes;
  bool initialised;
  explicit FilterSnapshot(const DiscriminativeBayesFilter<G>& f) : initialised(f.initialised()) {
    const auto mb = f.belief().mean.matrix(), mf = f.filtered().mean.matrix(), ms = f.sensorPose().matrix();
    const auto cb = f.belief().covariance, cf = f.filtered().covariance;
    bytes.resize(mb.size() * 3 + cb.size() * 2);
    Eigen::Index k = 0;
    for (const auto* m : {&mb, &mf, &ms})
      for (Eigen::Index i = 0; i < m->size(); ++i) bytes[k++] = m->data()[i];
    for (const auto* m : {&cb, &cf})
      for (Eigen::Index i = 0; i < m->size(); ++i) bytes[k++] = m->data()[i];
  }
  bool bitwiseEqual(const FilterSnapshot& o) const {
    return initialised == o.initialised && bytes.size() == o.bytes.size() &&
           std::memcmp(bytes.data(), o.bytes.data(), sizeof(typename G::Scalar) * size_t(bytes.size())) == 0;
  }
};

}  // namespace

// ---------------------------------------------------------------------------------------------
TEST_CASE("filter: Euclidean limit equals a hand-written linear Kalman filter",
          "[estimation][filter]") {
  // Translation-only SE(3): sensor poses, observations and the state are pure translations;
  // the rotation covariances are tiny (1e-14), so the filter reduces to a 3-D linear KF with
  // F = I, the shift u_k = s_{k−1} − s_k (from T̄_k), process noise Q and measurement noise R_k.
  using G = SE3d;
  lieservo::sampling::Rng rng(29);
  const Eigen::Matrix3d Q = correlatedCovariance<G>(rng, G::Tangent::Constant(0.3)).topLeftCorner<3, 3>();
  G::Jacobian Sphi = G::Jacobian::Zero();
  Sphi.topLeftCorner<3, 3>() = Q;
  Sphi.bottomRightCorner<3, 3>() = 1e-14 * Eigen::Matrix3d::Identity();
  DiscriminativeBayesFilter<G>::Options opt;
  opt.process_noise = Sphi;
  DiscriminativeBayesFilter<G> filter(opt);

  auto makeObs = [&](Eigen::Vector3d& z, Eigen::Matrix3d& R) {
    R = correlatedCovariance<G>(rng, realisticSigma<G>(rng, 0.1, 1.0)).topLeftCorner<3, 3>();
    z = randn<Eigen::Vector3d>(rng, 2.0);
    ConcentratedGaussian<G> o;
    o.mean = G(SO3d(), z);
    o.covariance.setZero();
    o.covariance.topLeftCorner<3, 3>() = R;
    o.covariance.bottomRightCorner<3, 3>() = 1e-14 * Eigen::Matrix3d::Identity();
    return o;
  };
  Eigen::Vector3d z, s = randn<Eigen::Vector3d>(rng, 5.0);
  Eigen::Matrix3d R;
  ConcentratedGaussian<G> o = makeObs(z, R);
  REQUIRE(filter.step(G(SO3d(), s), o) == Status::ok);
  Eigen::Vector3d x = z;
  Eigen::Matrix3d P = R;
  double max_dx = 0, max_dP = 0;
  for (int k = 0; k < 300; ++k) {
    const Eigen::Vector3d s_new = s + randn<Eigen::Vector3d>(rng, 1.0);
    // KF predict
    x += s - s_new;
    P += Q;
    // KF update
    o = makeObs(z, R);
    const Eigen::Matrix3d K = P * (P + R).inverse();
    x += K * (z - x);
    P = (Eigen::Matrix3d::Identity() - K) * P;
    P = 0.5 * (P + P.transpose()).eval();
    s = s_new;
    REQUIRE(filter.step(G(SO3d(), s), o) == Status::ok);
    max_dx = std::max(max_dx, (filter.filtered().mean.translation() - x).norm() / (1 + x.norm()));
    max_dP = std::max(max_dP, relDiff(filter.filtered().covariance.topLeftCorner<3, 3>(), P));
    CHECK(filter.filtered().mean.so3().log().norm() < 1e-9);
  }
  INFO("max rel translation diff " << max_dx << ", covariance " << max_dP);
  CHECK(max_dx < 1e-9);
  CHECK(max_dP < 1e-9);
}

TEST_CASE("filter: SO(2) equals the scalar Kalman filter on the angle", "[estimation][filter]") {
  using G = SO2d;
  lieservo::sampling::Rng rng(31);
  DiscriminativeBayesFilter<G, ClosedFormJacobian>::Options opt;
  opt.process_noise = G::Jacobian::Constant(0.01 * 0.01);
  DiscriminativeBayesFilter<G, ClosedFormJacobian> filter(opt);
  double x = 0.2, P = 0.05 * 0.05, sens = 0.0;
  REQUIRE(filter.step(G(sens), ConcentratedGaussian<G>(G(x), G::Jacobian::Constant(P))) == Status::ok);
  for (int k = 0; k < 500; ++k) {
    const double sens_new = sens + uniform(rng, -0.05, 0.05);
    const double z = 0.1 * std::sin(0.01 * k) + uniform(rng, -0.05, 0.05);
    const double r = std::pow(uniform(rng, 0.01, 0.1), 2);
    x += sens - sens_new;  // T̄ = R(sens_new)⁻¹ R(sens)
    P += 0.01 * 0.01;
    const double K = P / (P + r);
    x += K * (z - x);
    P *= (1 - K);
    sens = sens_new;
    REQUIRE(filter.step(G(sens), ConcentratedGaussian<G>(G(z), G::Jacobian::Constant(r))) == Status::ok);
    CHECK(filter.filtered().mean.log()[0] == Approx(x).margin(1e-12));
    CHECK(filter.filtered().covariance(0, 0) == Approx(P).epsilon(1e-10));
  }
}

// ---------------------------------------------------------------------------------------------
template <class G>
void consistencyTest(unsigned seed, const typename G::Jacobian& Sphi,
                     const typename G::Tangent& obs_sigma, double motion, long runs, int steps,
                     long long_steps,
                     const FusionOptions<typename G::Scalar>& fusion = FusionOptions<typename G::Scalar>::paper()) {
  // (a) `runs` independent runs of `steps` steps: the NEES at the last step of each run are
  // independent χ²(DoF) samples, so their average lies in [χ²_{.025}(DoF·M), χ²_{.975}(DoF·M)]/M
  // with 95 % probability.
  const int D = G::DoF;
  double nees_sum = 0, nis_sum = 0;
  long nis_n = 0;
  for (long r = 0; r < runs; ++r) {
    Simulator<G> sim(seed + unsigned(r), Sphi, obs_sigma, motion);
    typename DiscriminativeBayesFilter<G>::Options opt;
    opt.process_noise = Sphi;
    opt.fusion = fusion;
    DiscriminativeBayesFilter<G> f(opt);
    REQUIRE(f.step(sim.sens, sim.observe()) == Status::ok);
    for (int k = 0; k < steps; ++k) {
      const G s = sim.advance();
      REQUIRE(f.step(s, sim.observe()) == Status::ok);
      nis_sum += double(f.diagnostics().nis);
      ++nis_n;
    }
    typename G::Scalar nees;
    REQUIRE(mahalanobisSquared(f.filtered(), sim.X, nees) == Status::ok);
    nees_sum += double(nees);
  }
  const double M = double(runs);
  const double lo = chiSquareQuantile(0.025, D * M) / M, hi = chiSquareQuantile(0.975, D * M) / M;
  const double anees = nees_sum / M, anis = nis_sum / double(nis_n);
  std::printf("[consistency DoF %d] %ld independent runs x %d steps: ANEES %.3f in [%.3f, %.3f]; "
              "mean NIS %.3f\n", D, runs, steps, anees, lo, hi, anis);
  CHECK(anees > lo);
  CHECK(anees < hi);
  CHECK(anis == Approx(D).epsilon(0.05));

  // (b) One long sequence of `long_steps` steps, time-averaged NEES against the χ²(DoF·K)
  // interval. Consecutive filter errors are correlated (the filter has memory), so the K
  // NEES values are not independent: the interval is computed for the effective number of
  // independent samples K_eff = K (1 − ρ1)/(1 + ρ1), ρ1 = measured lag-1 autocorrelation of the
  // NEES (AR(1) approximation), i.e. χ²(DoF·K_eff)/K_eff.
  Simulator<G> sim(seed + 100000u, Sphi, obs_sigma, motion);
  typename DiscriminativeBayesFilter<G>::Options opt;
  opt.process_noise = Sphi;
  opt.fusion = fusion;
  DiscriminativeBayesFilter<G> f(opt);
  REQUIRE(f.step(sim.sens, sim.observe()) == Status::ok);
  std::vector<double> nees_k;
  double nis_long = 0;
  for (long k = 0; k < long_steps; ++k) {
    const G s = sim.advance();
    REQUIRE(f.step(s, sim.observe()) == Status::ok);
    typename G::Scalar nees;
    REQUIRE(mahalanobisSquared(f.filtered(), sim.X, nees) == Status::ok);
    nees_k.push_back(double(nees));
    nis_long += double(f.diagnostics().nis);
  }
  const double K = double(long_steps);
  double mean = 0;
  for (double v : nees_k) mean += v;
  mean /= K;
  double c0 = 0, c1 = 0;
  for (size_t i = 0; i < nees_k.size(); ++i) {
    c0 += (nees_k[i] - mean) * (nees_k[i] - mean);
    if (i > 0) c1 += (nees_k[i] - mean) * (nees_k[i - 1] - mean);
  }
  const double rho1 = std::max(0.0, c1 / c0);
  const double Keff = K * (1 - rho1) / (1 + rho1);
  const double lo2 = chiSquareQuantile(0.025, D * Keff) / Keff, hi2 = chiSquareQuantile(0.975, D * Keff) / Keff;
  std::printf("[consistency DoF %d] one sequence of %ld steps: ANEES %.3f in [%.3f, %.3f] "
              "(chi2 interval for K_eff = %.0f; lag-1 autocorrelation %.2f; for K: [%.3f, %.3f]), "
              "mean NIS %.3f\n",
              D, long_steps, mean, lo2, hi2, Keff, rho1, chiSquareQuantile(0.025, D * K) / K,
              chiSquareQuantile(0.975, D * K) / K, nis_long / K);
  CHECK(mean > lo2);
  CHECK(mean < hi2);
}

TEST_CASE("filter: statistical consistency on simulated SE(3) sequences (NEES, NIS)",
          "[estimation][filter][consistency]") {
  using G = SE3d;
  // The paper's process noise (σφ = 0.5 mm, 0.5°) and GDN-like observation noise.
  consistencyTest<G>(1000, paperProcessNoise<G>(), gdnSigma(), 0.02,
                     test::scaledCount(1000, 100), 20, 2000);
}

TEST_CASE("filter: the converged rule stays consistent at the paper's noise", "[estimation][filter][consistency]") {
  // FusionOptions::converged() (an update under 0.001 σ, at most the paper's 5): the same NEES
  // and NIS intervals as the paper's fixed count (criteria set before the run). At large
  // rotation noise: test_fusion.cpp, "what one iteration costs".
  using G = SE3d;
  consistencyTest<G>(1000, paperProcessNoise<G>(), gdnSigma(), 0.02, test::scaledCount(1000, 100), 20, 2000,
                     FusionOptions<double>::converged());
}

TEST_CASE("filter: the converged rule's NEES is the paper's count's, within 5.9 to 6.1",
          "[estimation][filter][consistency]") {
  // 2·10⁴ independent runs of 20 steps at the paper's noise; the NEES of the last filtered
  // state at the true pose. Criteria (set before the run): with FusionOptions::converged() the
  // average is within 0.01 of the paper's 5 iterations on the same runs, and within four
  // standard errors of the χ²(6) mean 6 (±0.10 at 2·10⁴ runs: [5.9, 6.1]).
  using G = SE3d;
  const long runs = test::scaledCount(20000, 2000);
  double sum[2] = {0, 0}, sum_sq[2] = {0, 0}, iterations = 0;
  for (int rule = 0; rule < 2; ++rule) {
    for (long r = 0; r < runs; ++r) {
      Simulator<G> sim(1000 + unsigned(r), paperProcessNoise<G>(), gdnSigma(), 0.02);
      DiscriminativeBayesFilter<G>::Options o;
      o.fusion = rule ? FusionOptions<double>::converged() : FusionOptions<double>::paper();
      DiscriminativeBayesFilter<G> f(o);
      REQUIRE(f.step(sim.sens, sim.observe()) == Status::ok);
      for (int k = 0; k < 20; ++k) {
        const G s = sim.advance();
        REQUIRE(f.step(s, sim.observe()) == Status::ok);
        if (rule) iterations += f.diagnostics().iterations;
      }
      double nees = 0;
      REQUIRE(mahalanobisSquared(f.filtered(), sim.X, nees) == Status::ok);
      sum[rule] += nees;
      sum_sq[rule] += nees * nees;
    }
  }
  const double paper = sum[0] / double(runs), converged = sum[1] / double(runs);
  const double se = std::sqrt(std::max(0.0, sum_sq[1] / double(runs) - converged * converged) / double(runs));
  std::printf("[consistency, converged rule] %ld runs x 20 steps: ANEES %.3f +- %.3f (s.e.) at %.2f iterations on "
              "average; the paper's 5 iterations %.3f\n",
              runs, converged, se, iterations / double(20 * runs), paper);
  CHECK(std::abs(converged - paper) < 0.01);
  CHECK(std::abs(converged - 6.0) <= 4 * se);
}

TEST_CASE("filter: statistical consistency for SE(2) and SO(3)", "[estimation][filter][consistency]") {
  {
    using G = SE2d;
    G::Tangent s;
    s << 0.4, 0.4, 1.0 * kDeg;
    consistencyTest<G>(2000, paperProcessNoise<G>(), s, 0.02, test::scaledCount(500, 100), 20, 1000);
  }
  {
    using G = SO3d;
    const G::Tangent s = G::Tangent::Constant(1.0 * kDeg);
    consistencyTest<G>(3000, diagCov<G>(G::Tangent::Constant(0.5 * kDeg)), s, 0.05,
                       test::scaledCount(500, 100), 20, 1000);
  }
}

// ---------------------------------------------------------------------------------------------
TEST_CASE("filter: chi-square gating rejects outliers", "[estimation][filter][gating]") {
  using G = SE3d;
  Simulator<G> sim(41, paperProcessNoise<G>(), gdnSigma(), 0.02);
  DiscriminativeBayesFilter<G>::Options opt;
  opt.gating = true;
  opt.gate_probability = 0.999;
  DiscriminativeBayesFilter<G> gated(opt);
  opt.gating = false;
  DiscriminativeBayesFilter<G> plain(opt);
  CHECK(gated.diagnostics().gate_threshold == Approx(22.457744484825323).epsilon(1e-6));
  const auto o0 = sim.observe();
  REQUIRE(gated.step(sim.sens, o0) == Status::ok);
  REQUIRE(plain.step(sim.sens, o0) == Status::ok);
  int rejected = 0, false_alarms = 0, outliers = 0;
  double nees_gated = 0, nees_plain = 0;
  const int steps = 2000;
  for (int k = 0; k < steps; ++k) {
    const G s = sim.advance();
    auto o = sim.observe();
    const bool outlier = (k % 50 == 25);
    if (outlier) {  // a gross error: 5 mm and 10° off
      G::Tangent d;
      d << 5, -5, 3, 10 * kDeg, -10 * kDeg, 10 * kDeg;
      o.mean = G::exp(d) * o.mean;
      ++outliers;
    }
    const auto bel_expected = transformUnchecked(gated.filtered(), s.inverse() * gated.sensorPose(),
                                        gated.options().process_noise);
    const Status st = gated.step(s, o);
    REQUIRE((st == Status::ok || st == Status::outlier_rejected));
    if (st == Status::outlier_rejected) {
      ++rejected;
      if (!outlier) ++false_alarms;
      CHECK(gated.diagnostics().gated);
      CHECK(gated.diagnostics().nis > gated.diagnostics().gate_threshold);
      // State predicted only.
      CHECK(gated.filtered().mean.isApprox(bel_expected.mean, 1e-12));
      CHECK(relDiff(gated.filtered().covariance, bel_expected.covariance) < 1e-12);
      CHECK(gated.sensorPose().matrix() == s.matrix());
    } else {
      CHECK(!outlier);
    }
    REQUIRE(plain.step(s, o) == Status::ok);
    double n1, n2;
    REQUIRE(mahalanobisSquared(gated.filtered(), sim.X, n1) == Status::ok);
    REQUIRE(mahalanobisSquared(plain.filtered(), sim.X, n2) == Status::ok);
    nees_gated += n1;
    nees_plain += n2;
  }
  std::printf("[gating] %d outliers, %d rejected (%d false alarms); ANEES gated %.2f, ungated %.2f\n",
              outliers, rejected, false_alarms, nees_gated / steps, nees_plain / steps);
  CHECK(rejected >= outliers);
  CHECK(false_alarms <= 10);  // expected ≈ 0.001 · 2000 = 2
  CHECK(gated.diagnostics().rejected == std::uint64_t(rejected));
  CHECK(nees_gated / steps < 7.0);
  CHECK(nees_plain / steps > nees_gated / steps);
}

// ---------------------------------------------------------------------------------------------
TEMPLATE_TEST_CASE("filter: bad input returns a clear Status and leaves the state bitwise unchanged",
                   "[estimation][filter][badinput]", SE3d, SE3f) {
  using G = TestType;
  using S = typename G::Scalar;
  using CG = ConcentratedGaussian<G>;
  typename DiscriminativeBayesFilter<G>::Options opt;
  DiscriminativeBayesFilter<G> f(opt);
  lieservo::sampling::Rng rng(43);
  const typename G::Tangent sig = gdnSigma().template cast<S>();
  CG good;
  REQUIRE(fromTangentGaussian(randn<typename G::Tangent>(rng, 0.3), sig, good) == Status::ok);
  const G sens = G::exp(randn<typename G::Tangent>(rng, 1.0));

  // Before the first observation.
  {
    const FilterSnapshot<G> before(f);
    CHECK(f.predict(sens) == Status::not_initialised);
    CHECK(f.predictFromOdometry(sens) == Status::not_initialised);
    CHECK(f.correct(good) == Status::not_initialised);
    CHECK(f.diagnostics().last_status == Status::not_initialised);
    CHECK(FilterSnapshot<G>(f).bitwiseEqual(before));
  }
  // Bad first observations.
  CG nan_cov = good;
  nan_cov.covariance(2, 3) = std::numeric_limits<S>::quiet_NaN();
  CHECK(f.step(sens, nan_cov) == Status::non_finite_input);
  CHECK(!f.initialised());

  REQUIRE(f.step(sens, good) == Status::ok);  // the first step initialises
  CHECK(f.initialised());
  CHECK(f.diagnostics().corrections == 1);
  for (int k = 0; k < 10; ++k) {
    CG o;
    REQUIRE(fromTangentGaussian(randn<typename G::Tangent>(rng, 0.3), sig, o) == Status::ok);
    REQUIRE(f.step(G::exp(randn<typename G::Tangent>(rng, 0.01)) * f.sensorPose(), o) == Status::ok);
  }
  const G next = G::exp(randn<typename G::Tangent>(rng, 0.01)) * f.sensorPose();

  struct Case {
    const char* what;
    CG obs;
    G pose;
    Status expected;
    bool only_step;  // the observation is valid on its own (only bad relative to the belief)
  };
  std::vector<Case> cases;
  auto add = [&](const char* w, const CG& o, const G& p, Status e, bool only_step = false) {
    cases.push_back({w, o, p, e, only_step});
  };
  {
    CG o = good;
    o.covariance(0, 0) = std::numeric_limits<S>::quiet_NaN();
    add("NaN covariance", o, next, Status::non_finite_input);
    o = good;
    o.covariance(4, 4) = std::numeric_limits<S>::infinity();
    add("inf covariance", o, next, Status::non_finite_input);
    o = good;
    auto M = o.mean.matrix();
    M(0, 3) = std::numeric_limits<S>::infinity();
    o.mean = G::fromMatrixUnchecked(M);
    add("inf mean", o, next, Status::non_finite_input);
    o = good;
    M = o.mean.matrix();
    M.template topLeftCorner<3, 3>() *= S(1.01);
    o.mean = G::fromMatrixUnchecked(M);
    add("non-orthonormal mean", o, next, Status::not_orthonormal);
    o = good;
    o.covariance(1, 1) = -o.covariance(1, 1);
    add("negative variance", o, next, Status::not_spd);
    o = good;
    o.covariance(0, 1) += S(0.01);
    add("asymmetric covariance", o, next, Status::not_spd);
    o = good;
    o.covariance.setZero();
    add("zero covariance", o, next, Status::not_spd);
    o = good;
    o.covariance = G::Jacobian::Ones();
    add("rank-one covariance", o, next, Status::not_spd);
    auto P = next.matrix();
    P(1, 1) = S(-P(1, 1));
    add("non-orthonormal sensor pose", good, G::fromMatrixUnchecked(P), Status::not_orthonormal);
    P = next.matrix();
    P(2, 3) = std::numeric_limits<S>::quiet_NaN();
    add("NaN sensor pose", good, G::fromMatrixUnchecked(P), Status::non_finite_input);
    // An observation π away in rotation from the belief: on the cut locus.
    o = good;
    typename G::Tangent d = G::Tangent::Zero();
    d[4] = lieservo::pi<S>();
    const G bel_mean = (next.inverse() * f.sensorPose()) * f.filtered().mean;
    o.mean = G::exp(d) * bel_mean;
    add("observation pi away (cut locus)", o, next, Status::invalid_argument, true);
  }
  for (const Case& c : cases) {
    INFO(c.what);
    const FilterSnapshot<G> before(f);
    const auto diag_before = f.diagnostics();
    CHECK(f.step(c.pose, c.obs) == c.expected);
    CHECK(f.diagnostics().last_status == c.expected);
    CHECK(FilterSnapshot<G>(f).bitwiseEqual(before));
    CHECK(f.diagnostics().corrections == diag_before.corrections);
    if (c.only_step) continue;
    if (c.pose.matrix() == next.matrix()) {
      CHECK(f.correct(c.obs) == c.expected);
      CHECK(FilterSnapshot<G>(f).bitwiseEqual(before));
    } else {
      CHECK(f.predict(c.pose) == c.expected);
      CHECK(FilterSnapshot<G>(f).bitwiseEqual(before));
      CHECK(f.predictFromOdometry(c.pose) == c.expected);
      CHECK(FilterSnapshot<G>(f).bitwiseEqual(before));
    }
    DiscriminativeBayesFilter<G> fresh(opt);  // as the initialising first step
    CHECK(fresh.step(c.pose, c.obs) == c.expected);
    CHECK(!fresh.initialised());
  }
  // Invalid options: the filter refuses to run.
  typename DiscriminativeBayesFilter<G>::Options bad = opt;
  bad.gate_probability = S(1);
  CHECK(f.configure(bad) == Status::invalid_argument);
  bad = opt;
  bad.fusion.max_iterations = 0;
  CHECK(f.configure(bad) == Status::invalid_argument);
  bad = opt;
  bad.process_noise(0, 0) = S(-1);
  CHECK(f.configure(bad) == Status::not_spd);
  DiscriminativeBayesFilter<G> broken(bad);  // the constructor keeps configure's own Status
  CHECK(broken.step(sens, good) == Status::not_spd);
  CHECK(broken.configurationStatus() == Status::not_spd);
  CHECK(!broken.initialised());
  // And a good step still works afterwards.
  CG o;
  REQUIRE(fromTangentGaussian(randn<typename G::Tangent>(rng, 0.3), sig, o) == Status::ok);
  CHECK(f.step(next, o) == Status::ok);
}

// ---------------------------------------------------------------------------------------------
TEST_CASE("filter: float and double agree; predict+correct equals step", "[estimation][filter]") {
  using G = SE3d;
  Simulator<G> sim(47, paperProcessNoise<G>(), gdnSigma(), 0.02);
  DiscriminativeBayesFilter<G> fd;
  DiscriminativeBayesFilter<SE3f> ff;
  DiscriminativeBayesFilter<G> fm;  // manual predict + correct
  DiscriminativeBayesFilter<G> fo;  // the same from the odometry increment X_{k-1}^-1 X_k
  const auto o0 = sim.observe();
  REQUIRE(fd.step(sim.sens, o0) == Status::ok);
  REQUIRE(ff.step(sim.sens.cast<float>(), castGaussian<float>(o0)) == Status::ok);
  REQUIRE(fm.step(sim.sens, o0) == Status::ok);
  REQUIRE(fo.step(sim.sens, o0) == Status::ok);
  double max_err = 0, max_cov = 0;
  G prev = sim.sens;
  for (int k = 0; k < 500; ++k) {
    const G s = sim.advance();
    const auto o = sim.observe();
    REQUIRE(fd.step(s, o) == Status::ok);
    REQUIRE(ff.step(s.cast<float>(), castGaussian<float>(o)) == Status::ok);
    REQUIRE(fm.predict(s.inverse() * prev) == Status::ok);
    CHECK(fm.belief().mean.isApprox(fd.belief().mean, 1e-12));
    REQUIRE(fo.predictFromOdometry(prev.inverse() * s) == Status::ok);
    CHECK(fo.belief().mean.isApprox(fd.belief().mean, 1e-12));
    CHECK(relDiff(fo.belief().covariance, fd.belief().covariance) < 1e-12);
    REQUIRE(fo.correct(o) == Status::ok);
    REQUIRE(fm.correct(o) == Status::ok);
    CHECK(fm.filtered().mean.isApprox(fd.filtered().mean, 1e-12));
    CHECK(relDiff(fm.filtered().covariance, fd.filtered().covariance) < 1e-12);
    prev = s;
    max_err = std::max(max_err, mahalanobis(lminus(ff.filtered().mean.cast<double>(),
                                                           fd.filtered().mean),
                                            fd.filtered().covariance));
    max_cov = std::max(max_cov, relDiff(ff.filtered().covariance.cast<double>().eval(),
                                        fd.filtered().covariance));
  }
  std::printf("[float vs double] 500 steps: max mean difference %.2e sigma, covariance %.2e\n",
              max_err, max_cov);
  CHECK(max_err < 1e-2);
  CHECK(max_cov < 1e-3);
  CHECK(fd.diagnostics().iterations == 5);
}

// ---------------------------------------------------------------------------------------------
template <class Policy>
void checkCorrectionIsFusion(unsigned seed) {
  using G = SE3d;
  Simulator<G> sim(seed, paperProcessNoise<G>(), gdnSigma(), 0.02);
  DiscriminativeBayesFilter<G, Policy> f;
  REQUIRE(f.step(sim.sens, sim.observe()) == Status::ok);
  for (int k = 0; k < 1000; ++k) {
    const G s = sim.advance();
    const auto o = sim.observe();
    REQUIRE(f.step(s, o) == Status::ok);
    FusionResult<G> r;
    REQUIRE(fuse<Policy>(o, f.belief(), FusionOptions<double>{}, r) == Status::ok);
    double nis = -1;
    REQUIRE(normalizedInnovationSquared(o, f.belief(), nis) == Status::ok);
    REQUIRE(f.filtered().mean.matrix() == r.fused.mean.matrix());
    REQUIRE(f.filtered().covariance == r.fused.covariance);
    REQUIRE(f.diagnostics().nis == nis);
  }
}

TEST_CASE("filter: the correction is fuse(observation, belief) and its NIS the public one",
          "[estimation][filter]") {
  // Criterion (set before the run): the step shares the innovation's log and J⁻¹ with the
  // fusion and hands on its Cholesky factors, and must still give what the public functions
  // give on the same belief: over 1000 seeded steps per policy, bit for bit (the same
  // operations on the same operands).
  checkCorrectionIsFusion<PaperJacobian>(53);
  checkCorrectionIsFusion<ClosedFormJacobian>(59);
}

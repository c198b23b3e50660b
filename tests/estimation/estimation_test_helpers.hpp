// Helpers shared by the estimation tests (random SPD covariances, tangents, Euclidean
// reference computations). Header-only; each test executable includes it once.
#pragma once

#include <cmath>
#include <stdexcept>

#include <Eigen/Dense>

#include <lieservo/estimation.hpp>
#include <lieservo/groups.hpp>
#include <lieservo/sampling/random.hpp>

namespace lieservo::est_test {

constexpr double kDeg = lieservo::pi<double>() / 180.0;

template <class Vec, class Rng>
Vec randn(Rng& rng, double scale = 1.0) {
  Vec v;
  for (Eigen::Index i = 0; i < v.size(); ++i)
    v.data()[i] = typename Vec::Scalar(scale * lieservo::sampling::standardNormal(rng));
  return v;
}

/// One draw of `x` (lieservo::sample); a refused draw (an invalid mean or a covariance that is
/// not SPD) is a broken test set-up, so it throws and the test case fails.
template <class G, class Rng>
G draw(const ConcentratedGaussian<G>& x, Rng& rng) {
  G out;
  if (sample(x, rng, out) != Status::ok) throw std::runtime_error("draw: the Gaussian was refused");
  return out;
}

inline double uniform(lieservo::sampling::Rng& rng, double lo, double hi) {
  return lieservo::sampling::uniform(rng, lo, hi);
}

/// A random orthogonal n×n matrix (QR of a Gaussian matrix). The helpers below compute with
/// dynamic sizes: one instantiation of Eigen's decompositions serves every group, which keeps
/// these test files quick to compile (fixed sizes buy nothing in a test's set-up).
inline Eigen::MatrixXd randomOrthogonal(lieservo::sampling::Rng& rng, int n) {
  Eigen::MatrixXd A(n, n);
  for (Eigen::Index i = 0; i < A.size(); ++i) A.data()[i] = lieservo::sampling::standardNormal(rng);
  return Eigen::HouseholderQR<Eigen::MatrixXd>(A).householderQ();
}

template <int N>
Eigen::Matrix<double, N, N> randomOrthogonal(lieservo::sampling::Rng& rng) {
  return randomOrthogonal(rng, N);
}

/// The correlated covariance diag(s)·C·diag(s), C the correlation matrix of Q·diag(ev)·Qᵀ.
inline Eigen::MatrixXd correlatedCovariance(const Eigen::MatrixXd& Q, const Eigen::VectorXd& ev,
                                            const Eigen::VectorXd& s) {
  Eigen::MatrixXd C = Q * ev.asDiagonal() * Q.transpose();
  const Eigen::VectorXd d = C.diagonal().cwiseSqrt().cwiseInverse();
  C = d.asDiagonal() * C * d.asDiagonal();  // correlation matrix
  Eigen::MatrixXd S = s.asDiagonal() * C * s.asDiagonal();
  return 0.5 * (S + S.transpose());
}

/// Realistic per-component standard deviations for group G: translations σ ∈ [t_lo, t_hi]
/// (mm), rotations σ ∈ [r_lo, r_hi] (degrees, returned in radians).
template <class G>
typename G::Tangent realisticSigma(lieservo::sampling::Rng& rng, double t_lo = 0.1, double t_hi = 1.0,
                                   double r_lo_deg = 0.5, double r_hi_deg = 2.0) {
  constexpr int R = detail::rotationDoF<G>();
  typename G::Tangent s;
  for (int i = 0; i < G::DoF; ++i)
    s[i] = typename G::Scalar(i < G::DoF - R ? uniform(rng, t_lo, t_hi)
                                             : uniform(rng, r_lo_deg, r_hi_deg) * kDeg);
  return s;
}

/// A random SPD covariance with the given per-component standard deviations and random
/// correlations (correlation matrix from a random orthogonal basis with eigenvalues in
/// [0.2, 1.8]).
template <class G>
typename G::Jacobian correlatedCovariance(lieservo::sampling::Rng& rng, const typename G::Tangent& sigma) {
  constexpr int D = G::DoF;
  const Eigen::MatrixXd Q = randomOrthogonal(rng, D);
  Eigen::VectorXd ev(D);
  for (int i = 0; i < D; ++i) ev[i] = uniform(rng, 0.2, 1.8);
  const Eigen::VectorXd s = sigma.template cast<double>();
  const Eigen::Matrix<double, D, D> S = correlatedCovariance(Q, ev, s);
  return S.template cast<typename G::Scalar>();
}

/// Sample from a concentrated Gaussian in double.
template <class G>
ConcentratedGaussian<G> randomFactor(lieservo::sampling::Rng& rng, const G& centre,
                                     const typename G::Tangent& sigma) {
  ConcentratedGaussian<G> f;
  f.covariance = correlatedCovariance<G>(rng, sigma);
  // Draw the mean from the factor's own distribution around `centre` (so factors disagree
  // by about one standard deviation, as a prediction and an observation typically do).
  const ConcentratedGaussian<G> around(centre, f.covariance);
  f.mean = draw(around, rng);
  return f;
}

/// Mahalanobis length of a tangent vector v under covariance S (in double).
inline double mahalanobis(const Eigen::VectorXd& v, const Eigen::MatrixXd& S) {
  return std::sqrt(v.dot(S.ldlt().solve(v)));
}

template <class Vec, class Mat>
double mahalanobis(const Vec& v, const Mat& S) {
  return mahalanobis(Eigen::VectorXd(v.template cast<double>()), Eigen::MatrixXd(S.template cast<double>()));
}

/// Relative Frobenius difference ‖A − B‖/‖B‖.
template <class MA, class MB>
double relDiff(const MA& A, const MB& B) {
  return (A.template cast<double>() - B.template cast<double>()).norm() /
         B.template cast<double>().norm();
}

}  // namespace lieservo::est_test

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

/// A random orthogonal matrix (QR of a Gaussian matrix).
template <int N>
Eigen::Matrix<double, N, N> randomOrthogonal(lieservo::sampling::Rng& rng) {
  const Eigen::Matrix<double, N, N> A = randn<Eigen::Matrix<double, N, N>>(rng);
  Eigen::HouseholderQR<Eigen::Matrix<double, N, N>> qr(A);
  return qr.householderQ();
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
  const Eigen::Matrix<double, D, D> Q = randomOrthogonal<D>(rng);
  Eigen::Matrix<double, D, 1> ev;
  for (int i = 0; i < D; ++i) ev[i] = uniform(rng, 0.2, 1.8);
  Eigen::Matrix<double, D, D> C = Q * ev.asDiagonal() * Q.transpose();
  const Eigen::Matrix<double, D, 1> d = C.diagonal().cwiseSqrt().cwiseInverse();
  C = d.asDiagonal() * C * d.asDiagonal();  // correlation matrix
  const Eigen::Matrix<double, D, 1> s = sigma.template cast<double>();
  Eigen::Matrix<double, D, D> S = s.asDiagonal() * C * s.asDiagonal();
  S = 0.5 * (S + S.transpose()).eval();
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

/// Mahalanobis length of a tangent vector under covariance S.
template <class Vec, class Mat>
double mahalanobis(const Vec& v, const Mat& S) {
  const Eigen::Matrix<double, Vec::RowsAtCompileTime, 1> vd = v.template cast<double>();
  const Eigen::Matrix<double, Mat::RowsAtCompileTime, Mat::ColsAtCompileTime> Sd =
      S.template cast<double>();
  return std::sqrt(vd.dot(Sd.ldlt().solve(vd)));
}

/// Relative Frobenius difference ‖A − B‖/‖B‖.
template <class MA, class MB>
double relDiff(const MA& A, const MB& B) {
  return (A.template cast<double>() - B.template cast<double>()).norm() /
         B.template cast<double>().norm();
}

}  // namespace lieservo::est_test

// SE(3): group axioms, exp/log round trips (random and named hard cases incl. |rho| up to 1e6),
// adjoint, Jacobians (closed form vs series vs central differences), BCH, interpolation,
// checked construction, sampling.
#include "group_properties.hpp"

using lieservo::SE3;

TEMPLATE_TEST_CASE("SE3 group axioms", "[core][se3]", float, double) { lst::checkAxioms<SE3<TestType>>(2000); }

TEMPLATE_TEST_CASE("SE3 exp/log round trips on 1e5 random samples", "[core][se3]", float, double) {
  lst::checkRoundTrips<SE3<TestType>>(100000, 1.0);
}

TEMPLATE_TEST_CASE("SE3 exp/log named hard cases", "[core][se3]", float, double) {
  lst::checkHardCases<SE3<TestType>>();
}

TEMPLATE_TEST_CASE("SE3 adjoint and ad", "[core][se3]", float, double) { lst::checkAdjoint<SE3<TestType>>(2000); }

TEMPLATE_TEST_CASE("SE3 Jacobian identities", "[core][se3]", float, double) {
  lst::checkJacobianIdentities<SE3<TestType>>(2000);
}

TEST_CASE("SE3 Jacobians against central differences", "[core][se3]") {
  lst::checkNumericalJacobians<lieservo::SE3d>(300);
}

TEST_CASE("SE3 float agrees with double", "[core][se3]") { lst::checkFloatAgainstDouble<SE3>(2000); }

TEST_CASE("SE3 series inverse Jacobian converges to the closed form", "[core][se3]") {
  lst::checkSeriesConvergence<lieservo::SE3d>("SE3");
}

// SE3 evaluates the series in 3×3 blocks (and N ≤ 2 directly); it must equal the plain 6×6
// Horner evaluation in ad(ξ) (detail::inverseJacobianSeries) for every order.
template <int N>
static double blockSeriesDeviation(const lieservo::SE3d::Tangent& xi) {
  const auto block = lieservo::SE3d::leftJacobianInverseSeries<N>(xi);
  const auto dense = lieservo::detail::inverseJacobianSeries<lieservo::SE3d, N>(xi);
  return (block - dense).cwiseAbs().maxCoeff() / (1.0 + dense.cwiseAbs().maxCoeff());
}

TEST_CASE("SE3 block series inverse Jacobian equals the dense Horner series", "[core][se3]") {
  lieservo::sampling::Rng rng(31);
  for (int rep = 0; rep < 20000; ++rep) {
    const lieservo::SE3d::Tangent xi = lst::randomTangent<lieservo::SE3d>(rng, 3.0, 50.0);
    const double d[7] = {blockSeriesDeviation<0>(xi), blockSeriesDeviation<1>(xi),
                         blockSeriesDeviation<2>(xi), blockSeriesDeviation<3>(xi),
                         blockSeriesDeviation<4>(xi), blockSeriesDeviation<6>(xi),
                         blockSeriesDeviation<9>(xi)};
    for (double e : d) REQUIRE(e <= 1e-13);  // rounding order only
  }
}

TEST_CASE("SE3 BCH approximations have O(|xi_small|^2) error", "[core][se3]") { lst::checkBch<lieservo::SE3d>(); }

TEMPLATE_TEST_CASE("SE3 interpolation", "[core][se3]", float, double) { lst::checkInterpolate<SE3<TestType>>(500); }

TEMPLATE_TEST_CASE("SE3 checked construction", "[core][se3]", float, double) {
  using S = TestType;
  using G = SE3<S>;
  lst::checkCheckedConstruction<G>();
  // a bottom row other than [0 0 0 1] is rejected with invalid_argument, out untouched
  lieservo::sampling::Rng rng(1);
  const G X = G::sampleUniform(rng, S(2));
  G out;
  typename G::Matrix M = X.matrix();
  M(3, 0) = S(0.5);
  CHECK(G::fromMatrix(M, out) == lieservo::Status::invalid_argument);
  CHECK(G::fromMatrixProjected(M, out) == lieservo::Status::invalid_argument);
  CHECK(lst::matDiff(out, G()) == 0.0);
}

TEMPLATE_TEST_CASE("SE3 sampling and cast", "[core][se3]", float, double) {
  lst::checkSamplingAndCast<SE3<TestType>>();
}

/// J(ξ) = Σ_{n≥0} ad(ξ)^n/(n+1)! (eq. 33, eqn:left_jacobian_def), summed in long double.
static Eigen::Matrix<long double, 6, 6> leftJacobianSeriesLd(const Eigen::Matrix<double, 6, 1>& xi) {
  using Ml = Eigen::Matrix<long double, 6, 6>;
  const Ml ad = lieservo::SE3d::ad(xi).cast<long double>();
  Ml sum = Ml::Zero(), term = Ml::Identity();
  for (int n = 0; n < 60; ++n) {
    sum += term / static_cast<long double>(n + 1);
    term = (term * ad / static_cast<long double>(n + 1)).eval();
  }
  return sum;
}

TEST_CASE("SE3 closed-form left Jacobian (Barfoot Q) equals its defining series", "[core][se3]") {
  using G = lieservo::SE3d;
  lieservo::sampling::Rng rng(2);
  const std::vector<double> angles = {0, 1e-12, 1e-8, 1e-4, 1e-2, 0.1, 0.44, 0.5, 1.0, 1.16, 1.2, 2.0, 3.0, 3.14};
  double worst = 0, worst_inv = 0;
  for (double a : angles) {
    for (int rep = 0; rep < 20; ++rep) {
      const G::Tangent xi = lst::tangentWithAngle<G>(rng, a, 3.0);
      const Eigen::Matrix<long double, 6, 6> ref = leftJacobianSeriesLd(xi);
      const double e = static_cast<double>((G::leftJacobian(xi).cast<long double>() - ref).norm() / ref.norm());
      const Eigen::Matrix<long double, 6, 6> refinv = ref.inverse();
      const double ei = static_cast<double>((G::leftJacobianInverse(xi).cast<long double>() - refinv).norm() /
                                            refinv.norm());
      worst = std::max(worst, e);
      worst_inv = std::max(worst_inv, ei);
    }
  }
  INFO("worst relative error: J " << worst << ", J^-1 " << worst_inv);
  CHECK(worst <= 1e-14);
  CHECK(worst_inv <= 1e-14);
}

TEST_CASE("SE3 tiny rotation with a huge translation", "[core][se3]") {
  using G = lieservo::SE3d;
  for (double rho : {1.0, 1e3, 1e6}) {
    for (double th : {0.0, 1e-12, 1e-8, 1e-4}) {
      G::Tangent xi;
      xi << rho, -0.5 * rho, 0.25 * rho, th, -th, 0.5 * th;
      const G::Tangent back = G::exp(xi).log();
      INFO("rho " << rho << " theta " << th);
      // relative accuracy of each block
      CHECK((back.head<3>() - xi.head<3>()).norm() <= 8 * 2.3e-16 * xi.head<3>().norm());
      CHECK((back.tail<3>() - xi.tail<3>()).norm() <= 8 * 2.3e-16 * (xi.tail<3>().norm() + 1e-300));
    }
  }
}

TEST_CASE("SE3 adjoint matches the paper's block form", "[core][se3]") {
  using G = lieservo::SE3d;
  lieservo::sampling::Rng rng(4);
  const G X = G::sampleUniform(rng, 3.0);
  const Eigen::Matrix3d C = X.rotationMatrix();
  const Eigen::Vector3d r = X.translation();
  Eigen::Matrix<double, 6, 6> A = Eigen::Matrix<double, 6, 6>::Zero();
  A.topLeftCorner<3, 3>() = C;
  A.topRightCorner<3, 3>() = lieservo::SO3d::hat(r) * C;
  A.bottomRightCorner<3, 3>() = C;
  CHECK((X.Ad() - A).norm() == 0.0);
}

TEMPLATE_TEST_CASE("SE3 adjointCongruence equals Ad Sigma Ad^T", "[core][se3]", float, double) {
  // Criterion, fixed before the run: every entry within 32 eps · (1 + |r|)² · max|Σ_ij| of the
  // 6×6 products (both are sums of at most 36 products of that size), on 10⁵ seeded samples
  // with |r| up to 1000 and covariances spanning six decades, plus the identity exactly.
  using S = TestType;
  using G = SE3<S>;
  using J = typename G::Jacobian;
  lieservo::sampling::Rng rng(77);
  double worst = 0;
  for (int k = 0; k < 100000; ++k) {
    const S scale = S(std::pow(10.0, 3.0 * lieservo::sampling::uniform(rng, -1.0, 1.0)));
    const G X = lst::uniformElement<G>(rng, scale);
    J A;
    for (int i = 0; i < 36; ++i) A(i) = S(lieservo::sampling::standardNormal(rng));
    for (int i = 0; i < 6; ++i) A.row(i) *= S(std::pow(10.0, 1.5 * lieservo::sampling::uniform(rng, -1.0, 1.0)));
    J Sigma = A * A.transpose();
    lieservo::detail::symmetrize(Sigma);
    const J Ad = X.Ad();
    const J ref = Ad * Sigma * Ad.transpose();
    const double r = double(X.translation().norm());
    const double bound = 32 * lst::epsOf<S>() * (1 + r) * (1 + r) * double(Sigma.cwiseAbs().maxCoeff());
    worst = std::max(worst, double((X.adjointCongruence(Sigma) - ref).cwiseAbs().maxCoeff()) / bound);
  }
  INFO("worst error over its bound " << worst);
  CHECK(worst <= 1.0);
  const J Sigma = J::Identity() * S(2);
  CHECK((G::identity().adjointCongruence(Sigma) - Sigma).norm() == S(0));
}

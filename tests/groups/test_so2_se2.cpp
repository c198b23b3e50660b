// SO(2) and SE(2): the same property suite as SO(3)/SE(3).
#include "group_properties.hpp"

using lieservo::SE2;
using lieservo::SO2;

#define LIESERVO_GROUP_SUITE(G, NAME)                                                                   \
  TEMPLATE_TEST_CASE(NAME " group axioms", "[core]", float, double) { lst::checkAxioms<G<TestType>>(2000); } \
  TEMPLATE_TEST_CASE(NAME " exp/log round trips on 1e5 random samples", "[core]", float, double) {         \
    lst::checkRoundTrips<G<TestType>>(100000, 1.0);                                                         \
  }                                                                                                         \
  TEMPLATE_TEST_CASE(NAME " exp/log named hard cases", "[core]", float, double) {                          \
    lst::checkHardCases<G<TestType>>();                                                                     \
  }                                                                                                         \
  TEMPLATE_TEST_CASE(NAME " adjoint and ad", "[core]", float, double) { lst::checkAdjoint<G<TestType>>(2000); } \
  TEMPLATE_TEST_CASE(NAME " Jacobian identities", "[core]", float, double) {                               \
    lst::checkJacobianIdentities<G<TestType>>(2000);                                                        \
  }                                                                                                         \
  TEST_CASE(NAME " Jacobians against central differences", "[core]") {                                     \
    lst::checkNumericalJacobians<G<double>>(300);                                                           \
  }                                                                                                         \
  TEST_CASE(NAME " float agrees with double", "[core]") { lst::checkFloatAgainstDouble<G>(2000); }          \
  TEST_CASE(NAME " series inverse Jacobian converges", "[core]") {                                         \
    lst::checkSeriesConvergence<G<double>>(NAME);                                                           \
  }                                                                                                         \
  TEMPLATE_TEST_CASE(NAME " interpolation", "[core]", float, double) { lst::checkInterpolate<G<TestType>>(500); } \
  TEMPLATE_TEST_CASE(NAME " checked construction", "[core]", float, double) {                              \
    lst::checkCheckedConstruction<G<TestType>>();                                                           \
  }                                                                                                         \
  TEMPLATE_TEST_CASE(NAME " sampling and cast", "[core]", float, double) {                                 \
    lst::checkSamplingAndCast<G<TestType>>();                                                               \
  }

LIESERVO_GROUP_SUITE(SO2, "SO2")
LIESERVO_GROUP_SUITE(SE2, "SE2")

TEST_CASE("SE2 BCH approximations have O(|xi_small|^2) error", "[core][se2]") { lst::checkBch<lieservo::SE2d>(); }

TEST_CASE("SO2 log returns -pi < theta <= pi, with +pi at a half turn", "[core][so2]") {
  using G = lieservo::SO2d;
  CHECK(G::fromCosSinUnchecked(-1.0, 0.0).angle() == lieservo::pi<double>());
  CHECK(G::fromCosSinUnchecked(-1.0, -0.0).angle() == lieservo::pi<double>());
  CHECK(G(3.0).angle() == Approx(3.0).epsilon(1e-15));
  CHECK(G(4.0).angle() == Approx(4.0 - 2 * lieservo::pi<double>()).epsilon(1e-14));
}

TEST_CASE("SE2 Jacobian blocks match the hand-derived form", "[core][se2]") {
  using G = lieservo::SE2d;
  const double t = 0.9, x = 0.3, y = -1.2;
  const double s = std::sin(t), c = std::cos(t);
  Eigen::Matrix3d J;
  J << s / t, -(1 - c) / t, (t * x - s * x + y - c * y) / (t * t),  //
      (1 - c) / t, s / t, (t * y - s * y - x + c * x) / (t * t),      //
      0, 0, 1;
  CHECK((G::leftJacobian(G::Tangent(x, y, t)) - J).norm() <= 1e-15);
}

// Found by fuzz_log: the projection normalised (m00 + m11, m10 − m01) with a plain norm, which
// overflowed above ~1e154 and underflowed below ~1e-154 while returning ok.
TEMPLATE_TEST_CASE("SO2/SE2 projection to the nearest rotation at any finite scale", "[core][so2]",
                   float, double) {
  using S = TestType;
  using G = lieservo::SO2<S>;
  const S big = std::numeric_limits<S>::max(), tiny = std::numeric_limits<S>::denorm_min();
  const S scales[] = {S(1), S(1e-30), S(1e30), big, big / S(3), std::numeric_limits<S>::min(),
                      tiny, S(4) * tiny};
  const S angle = S(0.7);
  for (S k : scales) {
    INFO("scale " << k);
    typename G::Matrix M = G(angle).matrix() * k;
    if (k == big) M << big, -big, big, big;  // both sums overflow in the naive formula
    G out;
    REQUIRE(G::fromMatrixProjected(M, out) == lieservo::Status::ok);
    G chk;
    CHECK(G::fromMatrix(out.matrix(), chk) == lieservo::Status::ok);
    const S expected = k == big ? S(lieservo::pi<double>() / 4) : angle;
    // A subnormal scale keeps only a few significant bits of (c, s).
    const S tol = k <= S(4) * tiny ? S(0.5) : S(8) * std::numeric_limits<S>::epsilon();
    CHECK(std::abs(out.angle() - expected) <= tol);
    lieservo::SE2<S> pose;
    typename lieservo::SE2<S>::Matrix H = lieservo::SE2<S>::Matrix::Identity();
    H.template topLeftCorner<2, 2>() = M;
    REQUIRE(lieservo::SE2<S>::fromMatrixProjected(H, pose) == lieservo::Status::ok);
    CHECK(pose.so2().isApprox(out, S(0)));
  }
  G out;
  CHECK(G::fromMatrixProjected(G::Matrix::Zero(), out) == lieservo::Status::invalid_argument);
}

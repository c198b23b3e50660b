// Left plus/minus (lieservo/groups/perturbation.hpp): X ⊕ ε = exp(ε^) X, X ⊖ Y = ln(X Y⁻¹)^∨,
// and validateElement. Properties over 10⁵ seeded samples per group, plus named cases.
#include <catch2/catch.hpp>

#include <lieservo/sampling/random.hpp>

#include "group_properties.hpp"

using namespace lieservo;

TEMPLATE_TEST_CASE("lplus/lminus: inverse operations on the principal branch", "[core][perturbation]",
                   SO2<double>, SE2<double>, SO3<double>, SE3<double>, SE3<float>) {
  using G = TestType;
  using S = typename G::Scalar;
  lieservo::sampling::Rng rng(2024);
  const int n = 100000;
  // Tolerances relative to eps (written before the run): the round trip goes through one exp,
  // one product, one inverse and one log, each accurate to a few ulp; 2000 eps leaves room
  // for the conditioning of log near π (angles up to 3.0 rad here).
  const double tol = 2000 * lst::epsOf<S>();
  double worst_eps = 0, worst_X = 0;
  for (int k = 0; k < n; ++k) {
    const G X = lst::uniformElement<G>(rng, S(2));
    const G Y = lst::uniformElement<G>(rng, S(2));
    const typename G::Tangent eps = lst::randomTangent<G>(rng, 3.0, 1.0);
    // lminus(lplus(X, ε), X) = ε
    const typename G::Tangent back = lminus(lplus(X, eps), X);
    worst_eps = std::max(worst_eps, double((back - eps).norm()) / (1.0 + double(eps.norm())));
    // lplus(Y, lminus(X, Y)) = X
    const G X2 = lplus(Y, lminus(X, Y));
    worst_X = std::max(worst_X, double((X2.matrix() - X.matrix()).norm()) / (1.0 + double(X.matrix().norm())));
  }
  INFO("worst relative errors " << worst_eps << ", " << worst_X << " (tol " << tol << ")");
  CHECK(worst_eps < tol);
  CHECK(worst_X < tol);
}

TEMPLATE_TEST_CASE("lplus/lminus: named cases", "[core][perturbation]", SO3<double>, SE3<double>) {
  using G = TestType;
  const G X = G::exp(G::Tangent::Constant(0.2));
  // ε = 0 is the identity operation; X ⊖ X = 0 exactly in rotation.
  CHECK(lplus(X, G::Tangent::Zero()).matrix() == (G::identity() * X).matrix());
  CHECK(lminus(X, X).norm() < 1e-15);
  // The left perturbation acts in the fixed frame: exp(ε) X, not X exp(ε).
  typename G::Tangent e = G::Tangent::Zero();
  e[G::DoF - 1] = 0.5;
  CHECK(lplus(X, e).isApprox(G::exp(e) * X, 1e-15));
  CHECK(!lplus(X, e).isApprox(X * G::exp(e), 1e-6));
}

TEMPLATE_TEST_CASE("validateElement: finite, orthonormal, det +1", "[core][perturbation]", SO3<double>,
                   SE3<double>, SE2<double>, SO2<double>) {
  using G = TestType;
  const G X = G::exp(G::Tangent::Constant(0.3));
  CHECK(validateElement(X) == Status::ok);
  typename G::Matrix M = X.matrix();
  M(0, 0) *= 1.01;
  CHECK(validateElement(G::fromMatrixUnchecked(M)) == Status::not_orthonormal);
  M = X.matrix();
  M(1, 0) = std::numeric_limits<double>::quiet_NaN();
  CHECK(validateElement(G::fromMatrixUnchecked(M)) == Status::non_finite_input);
}

// ⊕/⊖ on both sides and the Jacobians of the group operations (lieservo/groups/perturbation.hpp),
// and validateElement. Properties over 10⁵ seeded samples per group, plus named cases; every
// Jacobian against central differences.
#include <catch2/catch.hpp>

#include <lieservo/sampling/random.hpp>

#include "group_properties.hpp"
#include "test_support.hpp"

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

TEMPLATE_TEST_CASE("validateElement: the checked constructor's Status on 10^5 perturbed matrices",
                   "[core][perturbation]", SO3<double>, SE3<double>, SO3<float>, SE3<float>) {
  // SO(3) and SE(3) check their stored numbers (G::validate()); the Status must be the one
  // G::fromMatrix gives the same matrix: an entry moved by 1e-12 to 1e-2, a column
  // reflected, a NaN, an inf in the translation.
  using G = TestType;
  using S = typename G::Scalar;
  lieservo::sampling::Rng rng(91);
  int mismatches = 0, oks = 0, rejected = 0;
  for (int k = 0; k < 100000; ++k) {
    typename G::Matrix M = lst::uniformElement<G>(rng, S(10)).matrix();
    const int kind = k % 5;
    const int i = k % 3, j = (k / 3) % 3;
    if (kind == 1) M(i, j) += S(std::pow(10.0, lieservo::sampling::uniform(rng, -12.0, -2.0)));
    if (kind == 2) M.col(j).template head<3>() = -M.col(j).template head<3>();
    if (kind == 3) M(i, j) = std::numeric_limits<S>::quiet_NaN();
    if (kind == 4 && M.cols() == 4) M(i, 3) = std::numeric_limits<S>::infinity();
    G tmp;
    const Status expected = G::fromMatrix(M, tmp);
    const Status got = validateElement(G::fromMatrixUnchecked(M));
    mismatches += got != expected;
    (expected == Status::ok ? oks : rejected) += 1;
  }
  INFO(oks << " valid, " << rejected << " rejected");
  CHECK(mismatches == 0);
  CHECK(oks > 20000);
  CHECK(rejected > 40000);
}

TEMPLATE_TEST_CASE("rplus/rminus: inverse operations on the principal branch", "[core][perturbation]",
                   SO2<double>, SE2<double>, SO3<double>, SE3<double>, SE3<float>) {
  using G = TestType;
  using S = typename G::Scalar;
  lieservo::sampling::Rng rng(2025);
  const double tol = 2000 * lst::epsOf<S>();  // as for lplus/lminus
  double worst_eps = 0, worst_X = 0;
  for (int k = 0; k < 100000; ++k) {
    const G X = lst::uniformElement<G>(rng, S(2));
    const G Y = lst::uniformElement<G>(rng, S(2));
    const typename G::Tangent eps = lst::randomTangent<G>(rng, 3.0, 1.0);
    worst_eps = std::max(worst_eps, double((rminus(rplus(X, eps), X) - eps).norm()) / (1.0 + double(eps.norm())));
    worst_X = std::max(worst_X, lst::matDiff(rplus(Y, rminus(X, Y)), X) / (1.0 + double(X.matrix().norm())));
  }
  INFO("worst relative errors " << worst_eps << ", " << worst_X << " (tol " << tol << ")");
  CHECK(worst_eps < tol);
  CHECK(worst_X < tol);
  // The right perturbation acts in the body frame: X exp(ε), and rplus(X, ε) = lplus(X, Ad(X) ε).
  const G X = G::exp(G::Tangent::Constant(S(0.3)));
  const typename G::Tangent e = G::Tangent::Constant(S(0.2));
  CHECK(rplus(X, e).isApprox(X * G::exp(e), S(10) * Eigen::NumTraits<S>::epsilon()));
  CHECK(rplus(X, e).isApprox(lplus(X, typename G::Tangent(X.Ad() * e)), S(100) * Eigen::NumTraits<S>::epsilon()));
}

namespace {

constexpr double kStep = 1e-6;  // central differences: truncation ~1e-12, rounding ~1e-10

// Column i: the left-perturbation derivative of a group-valued f at X along e_i.
template <class G, class F>
typename G::Jacobian numericGroupByGroup(const G& X, F f) {
  const G fX = f(X);
  typename G::Jacobian J;
  for (int i = 0; i < G::DoF; ++i) {
    const typename G::Tangent d = G::Tangent::Unit(i) * kStep;
    J.col(i) = (lminus(f(lplus(X, d)), fX) - lminus(f(lplus(X, typename G::Tangent(-d))), fX)) / (2 * kStep);
  }
  return J;
}
// A vector-valued f of a group element.
template <class G, int Rows, class F>
Eigen::Matrix<double, Rows, G::DoF> numericVectorByGroup(const G& X, F f) {
  Eigen::Matrix<double, Rows, G::DoF> J;
  for (int i = 0; i < G::DoF; ++i) {
    const typename G::Tangent d = G::Tangent::Unit(i) * kStep;
    J.col(i) = (f(lplus(X, d)) - f(lplus(X, typename G::Tangent(-d)))) / (2 * kStep);
  }
  return J;
}
// A group-valued f of a vector (perturbed by addition).
template <class G, class V, class F>
Eigen::Matrix<double, G::DoF, V::RowsAtCompileTime> numericGroupByVector(const V& v, F f) {
  const G fv = f(v);
  Eigen::Matrix<double, G::DoF, V::RowsAtCompileTime> J;
  for (int i = 0; i < V::RowsAtCompileTime; ++i) {
    const V d = V::Unit(i) * kStep;
    J.col(i) = (lminus(f(V(v + d)), fv) - lminus(f(V(v - d)), fv)) / (2 * kStep);
  }
  return J;
}
template <class A, class B>
double relativeError(const A& analytic, const B& numeric) {
  return (analytic - numeric).cwiseAbs().maxCoeff() / (1.0 + analytic.cwiseAbs().maxCoeff());
}

}  // namespace

TEMPLATE_TEST_CASE("Jacobians of compose, inverse, act, and both sides' plus and minus against central differences",
                   "[core][perturbation][jacobian]", SO2<double>, SE2<double>, SO3<double>, SE3<double>) {
  using G = TestType;
  using T = typename G::Tangent;
  using J = typename G::Jacobian;
  using Point = typename G::Point;
  constexpr int P = Point::RowsAtCompileTime;
  lieservo::sampling::Rng rng(77);
  // Criterion, written before the run: every analytic Jacobian within 1e-6 (max-abs, relative
  // to 1 + its largest entry) of central differences with step 1e-6, on elements with
  // translations up to 2 and differences (ε, τ, σ) of rotation angle up to 2.5 rad.
  const double tol = 1e-6;
  const long n = lieservo::test::scaledCount(100000, 2000);
  double worst[13] = {};
  for (long k = 0; k < n; ++k) {
    const G X = lst::uniformElement<G>(rng, 2.0);
    const G Y = lst::uniformElement<G>(rng, 2.0);
    const T eps = lst::randomTangent<G>(rng, 2.5, 1.0);
    Point p;
    for (int i = 0; i < P; ++i) p(i) = lieservo::sampling::uniform(rng, -2.0, 2.0);
    J JA, JB;
    int w = 0;
    auto record = [&](const auto& analytic, const auto& numeric) {
      worst[w] = std::max(worst[w], relativeError(analytic, numeric));
      ++w;
    };
    compose(X, Y, JA, JB);
    record(JA, numericGroupByGroup(X, [&](const G& x) { return x * Y; }));
    record(JB, numericGroupByGroup(Y, [&](const G& y) { return X * y; }));
    inverse(X, JA);
    record(JA, numericGroupByGroup(X, [](const G& x) { return x.inverse(); }));
    Eigen::Matrix<double, P, G::DoF> JqX;
    Eigen::Matrix<double, P, P> Jqp;
    act(X, p, JqX, Jqp);
    record(JqX, numericVectorByGroup<G, P>(X, [&](const G& x) { return Point(x * p); }));
    record(Jqp, (Eigen::Matrix<double, P, P>() << X.rotationMatrix()).finished());
    lplus(X, eps, JA, JB);
    record(JB, numericGroupByVector<G>(eps, [&](const T& e) { return lplus(X, e); }));
    record(JA, numericGroupByGroup(X, [&](const G& x) { return lplus(x, eps); }));
    rplus(X, eps, JA, JB);
    record(JB, numericGroupByVector<G>(eps, [&](const T& e) { return rplus(X, e); }));
    record(JA, numericGroupByGroup(X, [&](const G& x) { return rplus(x, eps); }));
    // ⊖: Y placed so that the difference has an angle up to 2.5 rad (away from the cut locus).
    const G Yl = lplus(X, T(-eps));  // X ⊖ Yl = ε
    lminus(X, Yl, JA, JB);
    record(JA, numericVectorByGroup<G, G::DoF>(X, [&](const G& x) { return T(lminus(x, Yl)); }));
    record(JB, numericVectorByGroup<G, G::DoF>(Yl, [&](const G& y) { return T(lminus(X, y)); }));
    const G Yr = rplus(X, T(-eps));  // X ⊖ᵣ Yr = ε
    rminus(X, Yr, JA, JB);
    record(JA, numericVectorByGroup<G, G::DoF>(X, [&](const G& x) { return T(rminus(x, Yr)); }));
    record(JB, numericVectorByGroup<G, G::DoF>(Yr, [&](const G& y) { return T(rminus(X, y)); }));
  }
  const char* names[13] = {"compose/X", "compose/Y", "inverse", "act/X", "act/p (rotation, exact)", "lplus/eps",
                           "lplus/X", "rplus/eps", "rplus/X", "lminus/X", "lminus/Y", "rminus/X", "rminus/Y"};
  for (int i = 0; i < 13; ++i) {
    INFO(names[i] << ": worst relative error " << worst[i] << " over " << n << " samples (tol " << tol << ")");
    CHECK(worst[i] < tol);
  }
  // The trivial blocks are exact.
  const G X = G::exp(T::Constant(0.4));
  J JA, JB;
  compose(X, X, JA, JB);
  CHECK(JA == J::Identity());
  lplus(X, T::Constant(0.1), JA, JB);
  CHECK(JA == G::exp(T::Constant(0.1)).Ad());
  rplus(X, T::Constant(0.1), JA, JB);
  CHECK(JA == J::Identity());
}

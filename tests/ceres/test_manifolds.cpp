// The Ceres manifolds (examples/adapters/ceres): the left perturbation's Plus and Minus, and
// their closed-form Jacobians against Jets and against central differences.
//
// Criteria (fixed before the first run), on 10^5 seeded samples per group (rotation angles of X
// and δ up to 2.5 rad, translations up to 10) and on hard cases (X at the identity and at
// π − 1e-6, δ = 0 and 1e-9):
//   Plus(x, 0) == x bit for bit;
//   |Minus(Plus(x, δ), x) − δ| ≤ 1e-10 · max(1, |δ|);
//   Plus(y, Minus(x, y)) is x as an element: |lminus| ≤ 1e-10 · max(1, |x|);
//   PlusJacobian and MinusJacobian within 1e-12 (relative to max(1, the largest entry)) of the
//   Jets' derivative of Plus and Minus, within 1e-7 of central differences (step 1e-6);
//   MinusJacobian · PlusJacobian = I within 1e-12.
#include <lieservo_ceres/manifold.hpp>

#include <ceres/jet.h>

#include <cmath>

#include <catch2/catch.hpp>
#include <lieservo/sampling/random.hpp>

#include "test_support.hpp"

namespace {

using namespace lieservo;
using lieservo::ceres_adapter::AmbientOf;
using lieservo::ceres_adapter::LeftManifold;
using lieservo::sampling::Rng;

template <class G>
using AmbientVector = Eigen::Matrix<double, AmbientOf<G>::kSize, 1>;

template <class G>
AmbientVector<G> ambient(const G& X) {  // the ambient parameters of X, by Plus from the identity
  AmbientVector<G> id = AmbientVector<G>::Zero();
  id[0] = 1;
  const typename G::Tangent xi = X.log();
  AmbientVector<G> a;
  AmbientOf<G>::plus(id.data(), xi.data(), a.data());
  return a;
}

template <class G>
typename G::Tangent randomTangent(Rng& rng, double max_angle, double max_translation) {
  typename G::Tangent xi;
  for (int i = 0; i < G::DoF; ++i) xi[i] = sampling::uniform(rng, -1.0, 1.0);
  constexpr int rot = G::DoF - G::RotationDoF;
  const double angle = sampling::uniform(rng, 0.0, max_angle);
  const double n = xi.template tail<G::RotationDoF>().norm();
  if (n > 0) xi.template tail<G::RotationDoF>() *= angle / n;
  if (rot > 0) xi.template head<rot>() *= max_translation;
  return xi;
}

double relErr(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(1.0, b.cwiseAbs().maxCoeff());
}

struct Worst {
  double plus_zero = 0, minus_plus = 0, plus_minus = 0, plus_jet = 0, minus_jet = 0, plus_num = 0, minus_num = 0,
         inverse = 0;
};

template <class G>
void checkOne(const G& X, const G& Y, const typename G::Tangent& delta, Worst& w) {
  constexpr int K = AmbientOf<G>::kSize, N = G::DoF;
  using A = AmbientOf<G>;
  const LeftManifold<G> M;
  const AmbientVector<G> x = ambient(X), y = ambient(Y);
  AmbientVector<G> x0, xd, r;
  const typename G::Tangent zero = G::Tangent::Zero();
  M.Plus(x.data(), zero.data(), x0.data());
  w.plus_zero = std::max(w.plus_zero, (x0 - x).cwiseAbs().maxCoeff());
  M.Plus(x.data(), delta.data(), xd.data());
  typename G::Tangent back, m;
  M.Minus(xd.data(), x.data(), back.data());
  w.minus_plus = std::max(w.minus_plus, (back - delta).norm() / std::max(1.0, delta.norm()));
  M.Minus(x.data(), y.data(), m.data());
  M.Plus(y.data(), m.data(), r.data());
  w.plus_minus = std::max(w.plus_minus, lminus(A::read(r.data()), X).norm() / std::max(1.0, X.log().norm()));

  Eigen::Matrix<double, K, N, N == 1 ? Eigen::ColMajor : Eigen::RowMajor> P;  // row-major (Ceres); a column is either
  Eigen::Matrix<double, N, K, Eigen::RowMajor> Mj;
  M.PlusJacobian(x.data(), P.data());
  M.MinusJacobian(x.data(), Mj.data());
  w.inverse = std::max(w.inverse, relErr(Mj * P, Eigen::MatrixXd::Identity(N, N)));
  {  // Jets: d Plus(x, δ)/dδ at δ = 0, d Minus(y, x)/dy at y = x
    using JN = ceres::Jet<double, N>;
    using JK = ceres::Jet<double, K>;
    JN xJ[K], dJ[N], outJ[K];
    for (int i = 0; i < K; ++i) xJ[i] = JN(x[i]);
    for (int i = 0; i < N; ++i) dJ[i] = JN(0.0, i);
    A::plus(xJ, dJ, outJ);
    Eigen::MatrixXd D(K, N);
    for (int i = 0; i < K; ++i) D.row(i) = outJ[i].v.transpose();
    w.plus_jet = std::max(w.plus_jet, relErr(D, P));
    JK yJ[K], xK[K], mJ[N];
    for (int i = 0; i < K; ++i) yJ[i] = JK(x[i], i), xK[i] = JK(x[i]);
    A::minus(yJ, xK, mJ);
    Eigen::MatrixXd E(N, K);
    for (int i = 0; i < N; ++i) E.row(i) = mJ[i].v.transpose();
    w.minus_jet = std::max(w.minus_jet, relErr(E, Mj));
  }
  {  // central differences, step 1e-6
    const double h = 1e-6;
    Eigen::MatrixXd D(K, N), E(N, K);
    for (int j = 0; j < N; ++j) {
      typename G::Tangent dp = zero, dm = zero;
      dp[j] = h;
      dm[j] = -h;
      AmbientVector<G> ap, am;
      M.Plus(x.data(), dp.data(), ap.data());
      M.Plus(x.data(), dm.data(), am.data());
      D.col(j) = (ap - am) / (2 * h);
    }
    for (int j = 0; j < K; ++j) {
      AmbientVector<G> yp = x, ym = x;
      yp[j] += h;
      ym[j] -= h;
      typename G::Tangent mp, mm;
      M.Minus(yp.data(), x.data(), mp.data());
      M.Minus(ym.data(), x.data(), mm.data());
      E.col(j) = (mp - mm) / (2 * h);
    }
    w.plus_num = std::max(w.plus_num, relErr(D, P));
    w.minus_num = std::max(w.minus_num, relErr(E, Mj));
  }
}

}  // namespace

TEMPLATE_TEST_CASE("ceres manifolds: Plus, Minus and their Jacobians (left perturbation)", "[ceres][manifold]",
                   SO2<double>, SE2<double>, SO3<double>, SE3<double>) {
  using G = TestType;
  Rng rng(2026);
  Worst w;
  const double pi_d = pi<double>();
  for (double angle : {0.0, 1e-9, pi_d - 1e-6})
    for (double d : {0.0, 1e-9, 1.0}) {
      typename G::Tangent xi = randomTangent<G>(rng, 1.0, 10.0);
      xi.template tail<G::RotationDoF>() *= angle / std::max(1e-300, xi.template tail<G::RotationDoF>().norm());
      const typename G::Tangent delta = d * randomTangent<G>(rng, 2.5, 10.0);
      checkOne(G::exp(xi), G::exp(randomTangent<G>(rng, 2.5, 10.0)), delta, w);
    }
  const long n = lieservo::test::scaledCount(100000, 2000);
  for (long k = 0; k < n; ++k)
    checkOne(G::exp(randomTangent<G>(rng, 2.5, 10.0)), G::exp(randomTangent<G>(rng, 2.5, 10.0)),
             randomTangent<G>(rng, 2.5, 10.0), w);
  INFO("worst: Plus(x, 0) " << w.plus_zero << ", Minus(Plus) " << w.minus_plus << ", Plus(Minus) " << w.plus_minus
                            << ", PlusJacobian vs Jets " << w.plus_jet << " / central " << w.plus_num
                            << ", MinusJacobian vs Jets " << w.minus_jet << " / central " << w.minus_num
                            << ", M P - I " << w.inverse);
  CHECK(w.plus_zero == 0);
  CHECK(w.minus_plus <= 1e-10);
  CHECK(w.plus_minus <= 1e-10);
  CHECK(w.plus_jet <= 1e-12);
  CHECK(w.minus_jet <= 1e-12);
  CHECK(w.plus_num <= 1e-7);
  CHECK(w.minus_num <= 1e-7);
  CHECK(w.inverse <= 1e-12);
}

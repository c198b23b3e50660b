// SO(3): group axioms, exp/log round trips (random and named hard cases), adjoint, Jacobians,
// series inverse Jacobian, BCH, interpolation, checked construction, sampling.
#include <limits>
#include <sstream>

#include "group_properties.hpp"

using lieservo::sampling::uniform;
using lieservo::SO3;

TEMPLATE_TEST_CASE("SO3 group axioms", "[core][so3]", float, double) { lst::checkAxioms<SO3<TestType>>(2000); }

TEMPLATE_TEST_CASE("SO3 exp/log round trips on 1e5 random samples", "[core][so3]", float, double) {
  lst::checkRoundTrips<SO3<TestType>>(100000, 0.0);
}

TEMPLATE_TEST_CASE("SO3 exp/log named hard cases", "[core][so3]", float, double) {
  lst::checkHardCases<SO3<TestType>>();
}

TEMPLATE_TEST_CASE("SO3 adjoint and ad", "[core][so3]", float, double) { lst::checkAdjoint<SO3<TestType>>(2000); }

TEMPLATE_TEST_CASE("SO3 Jacobian identities", "[core][so3]", float, double) {
  lst::checkJacobianIdentities<SO3<TestType>>(2000);
}

TEST_CASE("SO3 Jacobians against central differences", "[core][so3]") {
  lst::checkNumericalJacobians<lieservo::SO3d>(300);
}

TEST_CASE("SO3 float agrees with double", "[core][so3]") { lst::checkFloatAgainstDouble<SO3>(2000); }

TEST_CASE("SO3 series inverse Jacobian converges to the closed form", "[core][so3]") {
  lst::checkSeriesConvergence<lieservo::SO3d>("SO3");
}

TEST_CASE("SO3 BCH approximations have O(|xi_small|^2) error", "[core][so3]") { lst::checkBch<lieservo::SO3d>(); }

TEMPLATE_TEST_CASE("SO3 interpolation", "[core][so3]", float, double) { lst::checkInterpolate<SO3<TestType>>(500); }

TEMPLATE_TEST_CASE("SO3 checked construction", "[core][so3]", float, double) {
  lst::checkCheckedConstruction<SO3<TestType>>();
}

TEMPLATE_TEST_CASE("SO3 sampling and cast", "[core][so3]", float, double) {
  lst::checkSamplingAndCast<SO3<TestType>>();
}

TEMPLATE_TEST_CASE("SO3 log near and at pi", "[core][so3]", float, double) {
  using S = TestType;
  using G = SO3<S>;
  using V = typename G::Tangent;
  const double eps = lst::epsOf<S>();
  // Exactly symmetric half-turn matrices (w = 0): the sign rule makes the largest-magnitude
  // axis component positive.
  const V axes[] = {V(1, 0, 0), V(0, -1, 0), V(0, 0, -1), V(-1, -2, 2).normalized(), V(3, -1, -2).normalized()};
  for (const V& a : axes) {
    const typename G::Matrix C = S(2) * a * a.transpose() - G::Matrix::Identity();  // exactly symmetric
    const V phi = G::fromMatrixUnchecked(C).log();
    INFO("axis " << a.transpose() << " log " << phi.transpose());
    CHECK(std::abs(static_cast<double>(phi.norm()) - lieservo::pi<double>()) <= 8 * eps);
    int k = 0;
    for (int i = 1; i < 3; ++i)
      if (std::abs(a(i)) > std::abs(a(k))) k = i;
    const V expect = (a(k) > S(0) ? S(1) : S(-1)) * lieservo::pi<S>() * a;
    CHECK(static_cast<double>((phi - expect).norm()) <= 16 * eps);
  }
  // π − 10^-k about random axes: the angle and axis come back to a few ulps.
  lieservo::sampling::Rng rng(5);
  for (int k = 1; k <= 12; ++k) {
    const double angle = lieservo::pi<double>() - std::pow(10.0, -k);
    if (static_cast<double>(S(angle)) >= lieservo::pi<double>()) continue;
    const V xi = lst::tangentWithAngle<G>(rng, angle, 0.0);
    const V back = G::exp(xi).log();
    INFO("pi - 1e-" << k << ": " << (back - xi).norm());
    CHECK(lst::nearPiError<G>(back, xi) <= 16 * eps);
  }
}

TEMPLATE_TEST_CASE("SO3 log with trace rounded past 3 or -1", "[core][so3]", float, double) {
  using S = TestType;
  using G = SO3<S>;
  using M = typename G::Matrix;
  const S e = Eigen::NumTraits<S>::epsilon();
  // trace slightly above 3
  M C = M::Identity() * (S(1) + S(2) * e);
  typename G::Tangent phi = G::fromMatrixUnchecked(C).log();
  CHECK(phi.allFinite());
  CHECK(static_cast<double>(phi.norm()) <= 4 * lst::epsOf<S>());
  // tiny rotation with trace rounding to 3 exactly
  C = G::exp(typename G::Tangent(S(1e-9), S(0), S(0))).matrix();
  phi = G::fromMatrixUnchecked(C).log();
  CHECK(static_cast<double>(std::abs(phi(0) - S(1e-9))) <= 1e-9 * 4 * lst::epsOf<S>() + 1e-30);
  // half turn with trace slightly below −1
  C << S(1) + e, S(0), S(0), S(0), -S(1) - e, S(0), S(0), S(0), -S(1) - e;
  phi = G::fromMatrixUnchecked(C).log();
  CHECK(phi.allFinite());
  CHECK(std::abs(static_cast<double>(phi.norm()) - lieservo::pi<double>()) <= 8 * lst::epsOf<S>());
  CHECK(static_cast<double>(phi(0)) > 0);
}

TEST_CASE("SO3 closed forms match hand-computed values", "[core][so3]") {
  using G = lieservo::SO3d;
  // Rz(90°) maps x to y.
  const G R = G::exp(Eigen::Vector3d(0, 0, lieservo::pi<double>() / 2));
  CHECK((R * Eigen::Vector3d(1, 0, 0) - Eigen::Vector3d(0, 1, 0)).norm() <= 1e-15);
  // J(φ) for φ = (0, 0, θ): [[s/θ, −(1−c)/θ, 0], [(1−c)/θ, s/θ, 0], [0, 0, 1]].
  const double t = 0.7;
  Eigen::Matrix3d Jexp;
  Jexp << std::sin(t) / t, -(1 - std::cos(t)) / t, 0, (1 - std::cos(t)) / t, std::sin(t) / t, 0, 0, 0, 1;
  CHECK((G::leftJacobian(Eigen::Vector3d(0, 0, t)) - Jexp).norm() <= 1e-15);
}

TEMPLATE_TEST_CASE("SO3 log (and logWithTerms) of a matrix against a long-double reference, on both branches",
                   "[core][so3]", float, double) {
  // log() takes θ and the axis from the antisymmetric part and the trace for tr C > 0 and from
  // Shepperd's quaternion beyond. The reference is the quaternion path in long double applied
  // to the same (rounded) matrix, so the error measured is log()'s own rounding only: relative
  // to θ for small angles, and a few ulp of π near the half turn. Angles are log-uniform in
  // [1e-10, π) and, half of them, within 1e-3 of the branch switch at θ = 2π/3.
  using S = TestType;
  using ld = long double;
  namespace d = lieservo::detail;
  lieservo::sampling::Rng rng(77);
  const double pi = lieservo::pi<double>();
  double worst = 0, worst_at = 0, worst_same = 0, worst_theta2 = 0, worst_trig = 0, worst_omc = 0,
         worst_omc_ctor = 0;
  int direct = 0, quaternion = 0, closed = 0;
  for (int i = 0; i < 100000; ++i) {
    const double angle = (i % 2 == 0) ? std::min(pi * (1 - 1e-7), 1e-10 * std::pow(pi * 1e10, uniform(rng, 0.0, 1.0)))
                                      : 2 * pi / 3 + 1e-3 * (2 * uniform(rng, 0.0, 1.0) - 1);
    const typename SO3<S>::Matrix C = SO3<S>::exp(lst::tangentWithAngle<SO3<S>>(rng, angle, 0.0)).matrix();
    (C.trace() > S(0) ? direct : quaternion)++;
    const Eigen::Matrix<ld, 3, 3> Cl = C.template cast<ld>();
    const Eigen::Matrix<ld, 3, 1> ref = d::rotationVectorFromQuaternion(d::quaternionFromMatrix(Cl));
    const Eigen::Matrix<ld, 3, 1> got = SO3<S>::fromMatrixUnchecked(C).log().template cast<ld>();
    const double err = static_cast<double>((got - ref).norm() / std::max<ld>(ref.norm(), 1e-300L));
    if (err > worst) worst = err, worst_at = static_cast<double>(ref.norm());
    // logWithTerms: the same φ, and the angle terms (no sin/cos call) to a few ulp.
    d::AngleTerms<S> t(S(0));
    const typename SO3<S>::Tangent phi_t = SO3<S>::fromMatrixUnchecked(C).logWithTerms(t);
    const ld th = ref.norm();
    worst_same = std::max(worst_same, static_cast<double>((phi_t.template cast<ld>() - got).norm()));
    worst_theta2 = std::max(worst_theta2, static_cast<double>(std::abs(static_cast<ld>(t.theta2) - th * th) / (th * th)));
    if (t.closed) {
      ++closed;
      worst_trig = std::max({worst_trig, static_cast<double>(std::abs(static_cast<ld>(t.sin) - std::sin(th))),
                             static_cast<double>(std::abs(static_cast<ld>(t.cos) - std::cos(th))),
                             static_cast<double>(std::abs(static_cast<ld>(t.theta) - th) / th)});
      const ld omc = 2 * std::sin(th / 2) * std::sin(th / 2);
      worst_omc = std::max(worst_omc, static_cast<double>(std::abs(static_cast<ld>(t.one_minus_cos) - omc) / omc));
      // The same quantity through the constructor (θ² → sin/cos of θ/2), for comparison.
      const d::AngleTerms<S> t0(phi_t.squaredNorm());
      worst_omc_ctor =
          std::max(worst_omc_ctor, static_cast<double>(std::abs(static_cast<ld>(t0.one_minus_cos) - omc) / omc));
    }
  }
  INFO("logWithTerms: phi differs by " << worst_same << "; theta2 rel " << worst_theta2 << ", sin/cos/theta "
                                       << worst_trig << ", 1 - cos rel " << worst_omc << " (from theta^2: "
                                       << worst_omc_ctor << "; " << closed << " closed-form samples)");
  CHECK(worst_same == 0.0);
  CHECK(closed > 50000);
  CHECK(worst_theta2 <= 8 * lst::epsOf<S>());
  CHECK(worst_trig <= 4 * lst::epsOf<S>());
  // From sinθ and cosθ, 1 − cosθ is more accurate than from θ² (whose ≈ 5-ulp relative error
  // it would inherit): ≈ 3 ulp.
  CHECK(worst_omc <= 6 * lst::epsOf<S>());
  CHECK(worst_omc <= worst_omc_ctor + 2 * lst::epsOf<S>());
  INFO("worst relative error " << worst << " at theta " << worst_at << "; direct " << direct << ", quaternion "
                               << quaternion);
  CHECK(direct > 20000);
  CHECK(quaternion > 20000);
  CHECK(worst <= 4 * lst::epsOf<S>());
}

TEST_CASE("SO3 float log on both sides of its small-angle form's cutoff", "[core][so3]") {
  // In float, log takes φ = (½ + |s|²/48) s below |s|² = Cutoffs<float>::HalfAsin (θ ≈ 0.0355
  // rad) and the arctangent's series above (docs/math.md). Criteria (set before the run): 10⁵
  // rotations within ±2 % of the cutoff angle, both forms taken at least 20 000 times, every
  // log within 4 ulp of the long-double reference on the same matrix (as the test above), and
  // logWithTerms giving the same φ.
  namespace d = lieservo::detail;
  using ld = long double;
  lieservo::sampling::Rng rng(78);
  const double cut = std::asin(std::sqrt(double(d::Cutoffs<float>::HalfAsin) / 4));
  double worst = 0;
  int below = 0, above = 0;
  for (int i = 0; i < 100000; ++i) {
    const double angle = cut * (1 + 0.02 * (2 * uniform(rng, 0.0, 1.0) - 1));
    const SO3<float>::Matrix C = SO3<float>::exp(lst::tangentWithAngle<SO3<float>>(rng, angle, 0.0)).matrix();
    const Eigen::Vector3f s(C(2, 1) - C(1, 2), C(0, 2) - C(2, 0), C(1, 0) - C(0, 1));
    (s.squaredNorm() < d::Cutoffs<float>::HalfAsin ? below : above)++;
    const Eigen::Matrix<ld, 3, 1> ref =
        d::rotationVectorFromQuaternion(d::quaternionFromMatrix(Eigen::Matrix<ld, 3, 3>(C.cast<ld>())));
    const Eigen::Vector3f got = SO3<float>::fromMatrixUnchecked(C).log();
    worst = std::max(worst, static_cast<double>((got.cast<ld>() - ref).norm() / ref.norm()));
    d::AngleTerms<float> t(0.0f);
    REQUIRE(SO3<float>::fromMatrixUnchecked(C).logWithTerms(t) == got);
  }
  INFO("below the cutoff " << below << ", above " << above << "; worst " << worst / lst::epsOf<float>() << " ulp");
  CHECK(below >= 20000);
  CHECK(above >= 20000);
  CHECK(worst <= 4 * lst::epsOf<float>());
}

TEMPLATE_TEST_CASE("SO3 exp against a long-double reference, on each of its three paths", "[core][so3]", float,
                   double) {
  // exp builds the rotation from three terms of the half-angle series below halfAngleShortMaxX,
  // from Rodrigues' A and B as series about the centres of kExpPieces pieces of [0, π²] or
  // about π² (within expHalfTurnMaxD of it) up to the half turn, and by Rodrigues with sin/cos
  // beyond. Reference: Rodrigues in long double on the same (rounded) φ. Criteria (largest
  // entry error; ‖CᵀC − I‖, largest entry):
  //  - θ ≤ π/2: ≤ 3 eps and no more than Rodrigues (sin/cos) on the same φ; ‖CᵀC − I‖ ≤ 4 eps;
  //  - π/2 < θ ≤ π, which Rodrigues (sin/cos) served before: no more than Rodrigues on the same
  //    φ, and the bounds that held there: ≤ 5 eps, ‖CᵀC − I‖ ≤ 2√3·5 eps;
  //  - θ > π: ≤ 5 eps, ‖CᵀC − I‖ ≤ 2√3·5 eps (its entry bound; it measures 5.7–6.6 eps).
  // An eighth of the samples each lie within a relative 1e-6 of θ = π, within 1e-6 of the
  // quarter turn or a boundary between pieces, within 1e-3 of the three-term series' end and within 1e-3 of the
  // end of the series about π² (expHalfTurnMaxD), on either side; an eighth beyond π (up to 3π/2:
  // exp's callers pass θ ≤ π, as log returns); three eighths uniform in [0, π).
  using S = TestType;
  using ld = long double;
  using G = SO3<S>;
  const double eps = lst::epsOf<S>(), pi = lieservo::pi<double>();
  const double short_end = std::sqrt(static_cast<double>(lieservo::detail::halfAngleShortMaxX<S>()));
  const double half_turn_end = std::sqrt(pi * pi - static_cast<double>(lieservo::detail::expHalfTurnMaxD<S>()));
  // Every other boundary sample at the quarter turn (where the criteria below change), the
  // rest at the boundaries between pieces in turn.
  const int pieces = lieservo::detail::kExpPieces;
  const auto boundary = [&](int k) {
    return k % 2 == 0 ? pi / 2 : pi * std::sqrt(double(1 + (k / 2) % (pieces - 1)) / pieces);
  };
  lieservo::sampling::Rng rng(2026);
  double worst[3] = {}, rodrigues[3] = {}, orth[3] = {}, worst_at[3] = {};
  int count[3] = {};
  for (int i = 0; i < 100000; ++i) {
    const double jitter = 2 * uniform(rng, 0.0, 1.0) - 1;
    const double angle = i % 8 == 0   ? uniform(rng, pi, 1.5 * pi)
                         : i % 8 == 1 ? boundary(i / 8) * (1 + 1e-6 * jitter)
                         : i % 8 == 2 ? short_end * (1 + 1e-3 * jitter)
                         : i % 8 == 3 ? pi * (1 + 1e-6 * jitter)
                         : i % 8 == 7 ? half_turn_end * (1 + 1e-3 * jitter)
                                      : uniform(rng, 0.0, pi);
    const typename G::Tangent phi = lst::tangentWithAngle<G>(rng, angle, 0.0);
    const typename G::Matrix C = G::exp(phi).matrix();
    const Eigen::Matrix<ld, 3, 1> p = phi.template cast<ld>();
    const ld th = p.norm();
    Eigen::Matrix<ld, 3, 3> K;
    K << 0, -p(2), p(1), p(2), 0, -p(0), -p(1), p(0), 0;
    const Eigen::Matrix<ld, 3, 3> ref = Eigen::Matrix<ld, 3, 3>::Identity() + (th > 0 ? std::sin(th) / th : 1) * K +
                                        (th > 0 ? (1 - std::cos(th)) / (th * th) : 0.5L) * K * K;
    const double err = static_cast<double>((C.template cast<ld>() - ref).cwiseAbs().maxCoeff());
    const S x = phi.squaredNorm();
    const int r = x <= S(pi * pi / 4) ? 0 : x <= S(lieservo::detail::kHalfAngleSeriesMaxX) ? 1 : 2;
    if (r < 2) {  // Rodrigues with sin/cos on the same φ, for comparison
      const typename G::Matrix Cr = G::expWith(phi, lieservo::detail::AngleTerms<S>(x)).matrix();
      rodrigues[r] = std::max(rodrigues[r], static_cast<double>((Cr.template cast<ld>() - ref).cwiseAbs().maxCoeff()));
    }
    if (err > worst[r]) worst_at[r] = static_cast<double>(th);
    worst[r] = std::max(worst[r], err);
    ++count[r];
    const Eigen::Matrix<ld, 3, 3> Cl = C.template cast<ld>();
    orth[r] = std::max(orth[r], static_cast<double>((Cl.transpose() * Cl - Eigen::Matrix<ld, 3, 3>::Identity())
                                                        .cwiseAbs()
                                                        .maxCoeff()));
  }
  std::ostringstream summary;
  for (int r = 0; r < 3; ++r)
    summary << "path " << r << " (" << count[r] << " samples): " << worst[r] / eps << " eps at theta " << worst_at[r]
            << " (Rodrigues on the same phi: " << rodrigues[r] / eps << " eps); orthonormality " << orth[r] / eps
            << " eps\n";
  INFO(summary.str());
  CHECK(count[0] > 35000);  // 6/16 of the samples by construction, 7/16 and 3/16
  CHECK(count[1] > 40000);
  CHECK(count[2] > 15000);
  CHECK(worst[0] <= 3 * eps);
  CHECK(worst[0] <= rodrigues[0]);
  CHECK(orth[0] <= 4 * eps);
  CHECK(worst[1] <= rodrigues[1]);
  CHECK(worst[1] <= 5 * eps);
  CHECK(orth[1] <= 2 * std::sqrt(3.0) * 5 * eps);
  CHECK(worst[2] <= 5 * eps);
  CHECK(orth[2] <= 2 * std::sqrt(3.0) * 5 * eps);
  // Named cases: the identity exactly, a tiny angle, and the switches.
  CHECK(G::exp(G::Tangent::Zero()).matrix() == G::Matrix::Identity());
  const typename G::Matrix tiny = G::exp(typename G::Tangent(S(1e-20), S(0), S(0))).matrix();
  CHECK(tiny(2, 1) == S(1e-20));
  CHECK(tiny(0, 0) == S(1));
  const S quarter = lieservo::pi<S>() / 2;
  const typename G::Matrix Rz = G::exp(typename G::Tangent(S(0), S(0), quarter)).matrix();
  CHECK(std::abs(static_cast<double>(Rz(1, 0)) - 1.0) <= 2 * eps);
  CHECK(std::abs(static_cast<double>(Rz(0, 0))) <= 2 * eps);
  // The half turn about z (π rounded to S): C = diag(−1, −1, 1) to within the rounding of π.
  const typename G::Matrix Rpi = G::exp(typename G::Tangent(S(0), S(0), lieservo::pi<S>())).matrix();
  CHECK(std::abs(static_cast<double>(Rpi(0, 0)) + 1.0) <= 2 * eps);
  CHECK(std::abs(static_cast<double>(Rpi(1, 0))) <= 2 * eps);
  CHECK(Rpi(2, 2) == S(1));
}

TEST_CASE("SO3 float exp: the SSE matrix assembly equals the scalar one bit for bit", "[core][so3]") {
  // detail::matrixFromHalfAngle and detail::matrixFromRodrigues have float overloads on SSE that
  // perform the scalar templates' operations in packets; <float> selects the template. On other
  // targets both are the template.
  lieservo::sampling::Rng rng(11);
  int differ = 0, differ_rodrigues = 0;
  for (int i = 0; i < 100000; ++i) {
    const Eigen::Vector3f phi = lst::tangentWithAngle<lieservo::SO3f>(rng, uniform(rng, 0.0, 1.6), 0.0);
    const float k = static_cast<float>(uniform(rng, 0.3, 0.5)), w = static_cast<float>(uniform(rng, 0.7, 1.0));
    Eigen::Matrix3f packed, scalar;
    lieservo::detail::matrixFromHalfAngle(phi, k, w, packed);
    lieservo::detail::matrixFromHalfAngle<float>(phi, k, w, scalar);
    differ += (packed.array() != scalar.array()).any() ? 1 : 0;
    const Eigen::Vector3f psi = lst::tangentWithAngle<lieservo::SO3f>(rng, uniform(rng, 0.0, 3.2), 0.0);
    const float x = psi.squaredNorm(), A = static_cast<float>(uniform(rng, 0.0, 1.0)),
                B = static_cast<float>(uniform(rng, 0.2, 0.5));
    lieservo::detail::matrixFromRodrigues(psi, x, A, B, packed);
    lieservo::detail::matrixFromRodrigues<float>(psi, x, A, B, scalar);
    differ_rodrigues += (packed.array() != scalar.array()).any() ? 1 : 0;
  }
  CHECK(differ == 0);
  CHECK(differ_rodrigues == 0);
}

TEMPLATE_TEST_CASE("checked construction refuses a negative or non-finite tolerance", "[core][so3][so2][se3][se2]",
                   float, double) {
  using S = TestType;
  const S bad[] = {S(-1), S(-0.0001), std::numeric_limits<S>::quiet_NaN(), std::numeric_limits<S>::infinity()};
  const SO3<S> keep = SO3<S>::exp(Eigen::Matrix<S, 3, 1>(S(0.1), S(0.2), S(0.3)));
  const Eigen::Matrix<S, 3, 3> scaled = keep.rotationMatrix() * S(1.2);  // not a rotation at any sane tolerance
  Eigen::Matrix<S, 4, 4> M = Eigen::Matrix<S, 4, 4>::Identity();
  M.template topLeftCorner<3, 3>() = scaled;
  const lieservo::SO2<S> keep2(S(0.4));
  const Eigen::Matrix<S, 2, 2> scaled2 = keep2.rotationMatrix() * S(1.2);
  Eigen::Matrix<S, 3, 3> M2 = Eigen::Matrix<S, 3, 3>::Identity();
  M2.template topLeftCorner<2, 2>() = scaled2;
  for (const S tol : bad) {
    SO3<S> out = keep;
    CHECK(SO3<S>::fromMatrix(scaled, out, tol) == lieservo::Status::invalid_argument);
    CHECK(out.rotationMatrix() == keep.rotationMatrix());
    lieservo::SE3<S> out_se3;
    CHECK(lieservo::SE3<S>::fromMatrix(M, out_se3, tol) == lieservo::Status::invalid_argument);
    lieservo::SO2<S> out2 = keep2;
    CHECK(lieservo::SO2<S>::fromMatrix(scaled2, out2, tol) == lieservo::Status::invalid_argument);
    CHECK(out2.rotationMatrix() == keep2.rotationMatrix());
    lieservo::SE2<S> out_se2;
    CHECK(lieservo::SE2<S>::fromMatrix(M2, out_se2, tol) == lieservo::Status::invalid_argument);
  }
  SO3<S> out;  // the tolerance itself is not the problem: 0 is valid, and refuses the scaled matrix
  CHECK(SO3<S>::fromMatrix(scaled, out, S(0)) == lieservo::Status::not_orthonormal);
}

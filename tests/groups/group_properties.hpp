// Generic property checks shared by the SO(2), SE(2), SO(3) and SE(3) tests.
// Each check is a function template on the group G; the test files instantiate them with
// TEMPLATE_TEST_CASE over float and double.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <catch2/catch.hpp>
#include <lieservo/lieservo.hpp>

namespace lst {

using lieservo::pi;
using lieservo::sampling::Rng;
using lieservo::sampling::standardNormalVector;
using lieservo::sampling::uniform;

template <class S>
double epsOf() {
  return static_cast<double>(Eigen::NumTraits<S>::epsilon());
}

// ---- which tangent entries are rotational --------------------------------------------------
template <class G>
struct RotIndex;  // first rotational index and count
template <class S>
struct RotIndex<lieservo::SO2<S>> {
  static constexpr int start = 0, count = 1;
};
template <class S>
struct RotIndex<lieservo::SE2<S>> {
  static constexpr int start = 2, count = 1;
};
template <class S>
struct RotIndex<lieservo::SO3<S>> {
  static constexpr int start = 0, count = 3;
};
template <class S>
struct RotIndex<lieservo::SE3<S>> {
  static constexpr int start = 3, count = 3;
};

// ---- a uniformly drawn element -------------------------------------------------------------
// Rotation groups have no translation, so only SE(2) and SE(3) take a translation scale.
template <class G>
constexpr bool hasTranslation() {
  return RotIndex<G>::start > 0;
}
template <class G, class R>
G uniformElement(R& rng, typename G::Scalar translation_scale) {
  if constexpr (hasTranslation<G>())
    return G::sampleUniform(rng, translation_scale);
  else
    return G::sampleUniform(rng);
}

template <class G>
double rotationAngle(const typename G::Tangent& xi) {
  return static_cast<double>(xi.template segment<RotIndex<G>::count>(RotIndex<G>::start).norm());
}

/// Tangent with rotation angle `angle` about a uniformly random axis (sign random in 2-D)
/// and translation uniform in [−trans, trans]^n.
template <class G>
typename G::Tangent tangentWithAngle(Rng& rng, double angle, double trans) {
  using S = typename G::Scalar;
  typename G::Tangent xi;
  for (int i = 0; i < G::DoF; ++i) xi(i) = S(trans * uniform(rng, -1.0, 1.0));
  constexpr int r0 = RotIndex<G>::start, rc = RotIndex<G>::count;
  Eigen::Matrix<double, rc, 1> axis;
  do {
    axis = standardNormalVector<rc>(rng);
  } while (axis.norm() < 1e-6);
  axis.normalize();
  for (int i = 0; i < rc; ++i) xi(r0 + i) = S(angle * axis(i));
  return xi;
}

/// Random tangent with angle uniform in [0, max_angle).
template <class G>
typename G::Tangent randomTangent(Rng& rng, double max_angle, double trans) {
  return tangentWithAngle<G>(rng, uniform(rng, 0.0, max_angle), trans);
}

template <class G>
double matDiff(const G& a, const G& b) {
  return static_cast<double>((a.matrix() - b.matrix()).norm());
}

// ---- group axioms ----------------------------------------------------------------------------
template <class G>
void checkAxioms(int n) {
  using S = typename G::Scalar;
  lieservo::sampling::Rng rng(7);
  const double tol = 64 * epsOf<S>();
  double worst = 0;
  for (int i = 0; i < n; ++i) {
    const G a = G::sampleUniform(rng), b = G::sampleUniform(rng), c = G::sampleUniform(rng);
    worst = std::max(worst, matDiff((a * b) * c, a * (b * c)));
    worst = std::max(worst, matDiff(a * G::identity(), a));
    worst = std::max(worst, matDiff(G::identity() * a, a));
    worst = std::max(worst, matDiff(a * a.inverse(), G::identity()));
    worst = std::max(worst, matDiff(a.inverse() * a, G()));
    // in-place composition is the same composition
    G ab = a;
    ab *= b;
    worst = std::max(worst, matDiff(ab, a * b));
    // action is compatible with the matrix
    typename G::Point p = G::Point::Random();
    Eigen::Matrix<S, G::Dim, 1> q = (a * b) * p;
    Eigen::Matrix<S, G::Dim, 1> q2 = a * (b * p);
    worst = std::max(worst, static_cast<double>((q - q2).norm()));
    // matrix representation is a homomorphism
    worst = std::max(worst, static_cast<double>(((a * b).matrix() - a.matrix() * b.matrix()).norm()));
  }
  INFO("worst axiom residual " << worst << " tol " << tol);
  CHECK(worst <= tol);
}

// ---- exp/log round trips on random samples ----------------------------------------------------
template <class G>
void checkRoundTrips(int n, double trans) {
  using S = typename G::Scalar;
  lieservo::sampling::Rng rng(42);
  double worst_group = 0, worst_tangent = 0, worst_angle = 0;
  for (int i = 0; i < n; ++i) {
    const G X = lst::uniformElement<G>(rng, S(trans));
    const typename G::Tangent xi = X.log();
    worst_angle = std::max(worst_angle, rotationAngle<G>(xi));
    worst_group = std::max(worst_group, matDiff(G::exp(xi), X) / (1 + trans));
    const typename G::Tangent z = randomTangent<G>(rng, static_cast<double>(pi<S>()) * (1 - 1e-6), trans);
    worst_tangent = std::max(worst_tangent, static_cast<double>((G::exp(z).log() - z).norm()) / (1 + trans));
  }
  const double tol = 200 * epsOf<S>();
  INFO("exp(log X) worst " << worst_group << ", log(exp xi) worst " << worst_tangent << ", tol " << tol);
  CHECK(worst_group <= tol);
  CHECK(worst_tangent <= tol);
  CHECK(worst_angle <= static_cast<double>(pi<S>()) * (1 + 4 * epsOf<S>()));
}

/// |log(exp ξ) − ξ|, except within 64 eps of θ = π, where the rounding of exp(ξ) itself can
/// move the rotation across the half turn: there the antipodal representative
/// ξ_rot (1 − 2π/θ) of the same rotation is accepted too (the rotation then agrees anyway).
template <class G>
double nearPiError(const typename G::Tangent& back, const typename G::Tangent& xi) {
  using S = typename G::Scalar;
  const double err = static_cast<double>((back - xi).norm());
  const double th = rotationAngle<G>(xi);
  if (lieservo::pi<double>() - th > 64 * epsOf<S>() || th == 0) return err;
  typename G::Tangent alt = xi;
  alt.template segment<RotIndex<G>::count>(RotIndex<G>::start) *= S(1 - 2 * lieservo::pi<double>() / th);
  const typename G::Tangent back_alt_frame = back;
  const double err_alt =
      static_cast<double>((back_alt_frame.template segment<RotIndex<G>::count>(RotIndex<G>::start) -
                           alt.template segment<RotIndex<G>::count>(RotIndex<G>::start))
                              .norm());
  // For the antipodal representative only the rotation part is compared (ρ = J⁻¹ r changes).
  return std::min(err, err_alt);
}

/// Named hard cases: θ = 0, 1e-12, 1e-8, 1e-4, 1e-2, π − 10^−k (k = 1…12), π, 2π, 3π, with
/// translations up to 1e6. For θ < π: log(exp ξ) ≈ ξ (absolute, relative to 1 + |ρ|);
/// for θ ≥ π: exp(log(exp ξ)) ≈ exp ξ and |log| ≤ π.
template <class G>
void checkHardCases() {
  using S = typename G::Scalar;
  const double p = static_cast<double>(pi<S>());
  std::vector<double> angles = {0, 1e-12, 1e-8, 1e-4, 1e-2, 0.5, 1, 2};
  for (int k = 1; k <= 12; ++k) angles.push_back(lieservo::pi<double>() - std::pow(10.0, -k));
  std::vector<double> wrap = {lieservo::pi<double>(), 2 * lieservo::pi<double>(), 3 * lieservo::pi<double>(), 7.5};
  const std::vector<double> trans = {0, 1, 1e3, 1e6};
  lieservo::sampling::Rng rng(3);
  const double eps = epsOf<S>();
  for (double tr : trans) {
    for (double a : angles) {
      // In float the angle itself rounds; keep only cases strictly below π after rounding.
      if (static_cast<double>(S(a)) >= p) continue;
      for (int rep = 0; rep < 8; ++rep) {
        const typename G::Tangent xi = tangentWithAngle<G>(rng, a, tr);
        const typename G::Tangent back = G::exp(xi).log();
        const double err = nearPiError<G>(back, xi);
        // Rotation part: absolute; translation part: relative to |ρ| (exp/log of a 1e6 shift
        // carries |ρ|·eps of rounding). Near π the tangent is ill-conditioned in float only
        // through the rounding of θ itself.
        const double tol = 100 * eps * (1 + static_cast<double>(xi.norm()));
        INFO("angle " << a << " trans " << tr << " err " << err << " tol " << tol);
        CHECK(err <= tol);
        CHECK(back.allFinite());
      }
    }
    for (double a : wrap) {
      for (int rep = 0; rep < 8; ++rep) {
        const typename G::Tangent xi = tangentWithAngle<G>(rng, a, tr);
        const G X = G::exp(xi);
        const typename G::Tangent back = X.log();
        INFO("wrap angle " << a << " trans " << tr);
        CHECK(back.allFinite());
        CHECK(rotationAngle<G>(back) <= p * (1 + 4 * eps));
        CHECK(matDiff(G::exp(back), X) <= 100 * eps * (1 + tr));
      }
    }
  }
}

// ---- adjoint ----------------------------------------------------------------------------------
template <class G>
void checkAdjoint(int n) {
  using S = typename G::Scalar;
  lieservo::sampling::Rng rng(11);
  double worst = 0, worst_conj = 0;
  for (int i = 0; i < n; ++i) {
    const G X = lst::uniformElement<G>(rng, S(2)), Y = lst::uniformElement<G>(rng, S(2));
    const typename G::Tangent xi = randomTangent<G>(rng, 3.0, 1.0);
    // X exp(ξ^) X⁻¹ = exp((Ad(X) ξ)^)
    worst_conj = std::max(worst_conj, matDiff(X * G::exp(xi) * X.inverse(), G::exp(X.Ad() * xi)));
    // X ξ^ X⁻¹ = (Ad(X) ξ)^
    worst = std::max(worst, static_cast<double>(
                                (X.matrix() * G::hat(xi) * X.inverse().matrix() - G::hat(X.Ad() * xi)).norm()));
    // Ad is a homomorphism, Ad(X⁻¹) = Ad(X)⁻¹
    worst = std::max(worst, static_cast<double>(((X * Y).Ad() - X.Ad() * Y.Ad()).norm()));
    worst = std::max(worst, static_cast<double>((X.inverse().Ad() * X.Ad() - G::Jacobian::Identity()).norm()));
    // ad(a) b = (a^ b^ − b^ a^)^∨
    const typename G::Tangent b = randomTangent<G>(rng, 3.0, 1.0);
    const typename G::Matrix A = G::hat(xi), B = G::hat(b);
    worst = std::max(worst, static_cast<double>((G::ad(xi) * b - G::vee(A * B - B * A)).norm()));
    // hat/vee inverse
    worst = std::max(worst, static_cast<double>((G::vee(G::hat(b)) - b).norm()));
  }
  INFO("worst adjoint residual " << worst << ", conjugation " << worst_conj);
  CHECK(worst <= 200 * epsOf<S>());
  CHECK(worst_conj <= 400 * epsOf<S>());
}

// ---- Jacobian identities ----------------------------------------------------------------------
template <class G>
void checkJacobianIdentities(int n) {
  using S = typename G::Scalar;
  using J = typename G::Jacobian;
  lieservo::sampling::Rng rng(13);
  double worst = 0;
  for (int i = 0; i < n; ++i) {
    const double angle = i % 4 == 0 ? 1e-3 * (i % 7) : 3.0 * (i % 97) / 97.0;
    const typename G::Tangent xi = tangentWithAngle<G>(rng, angle, 1.0);
    const J Jl = G::leftJacobian(xi), Jr = G::rightJacobian(xi);
    const J I = J::Identity();
    // Jl(ξ) = Ad(exp ξ) Jr(ξ);  Jl(−ξ) = Jr(ξ)
    worst = std::max(worst, static_cast<double>((Jl - G::exp(xi).Ad() * Jr).norm()));
    worst = std::max(worst, static_cast<double>((G::leftJacobian(-xi) - Jr).norm()));
    // J J⁻¹ = I (both sides)
    worst = std::max(worst, static_cast<double>((Jl * G::leftJacobianInverse(xi) - I).norm()));
    worst = std::max(worst, static_cast<double>((Jr * G::rightJacobianInverse(xi) - I).norm()));
    // shared-trig variants agree with the separate ones
    J Jshared;
    const G X = G::expAndLeftJacobian(xi, Jshared);
    worst = std::max(worst, matDiff(X, G::exp(xi)));
    worst = std::max(worst, static_cast<double>((Jshared - Jl).norm()));
    J Jinv;
    const typename G::Tangent l = X.logAndLeftJacobianInverse(Jinv);
    worst = std::max(worst, static_cast<double>((l - X.log()).norm()));
    worst = std::max(worst, static_cast<double>((Jinv - G::leftJacobianInverse(X.log())).norm()));
    // J(ξ) ξ = ξ (ad(ξ) ξ = 0)
    worst = std::max(worst, static_cast<double>((Jl * xi - xi).norm()));
  }
  INFO("worst Jacobian identity residual " << worst);
  CHECK(worst <= 400 * epsOf<S>());
}

/// Left Jacobian against central differences: column k of J(ξ) ≈
/// [log(exp(ξ + h e_k) exp(ξ)⁻¹) − log(exp(ξ − h e_k) exp(ξ)⁻¹)] / (2h)  (double only).
/// Inverse Jacobian: log(exp(h e_k) X) − log(exp(−h e_k) X) ≈ 2h J⁻¹(log X) e_k.
template <class G>
void checkNumericalJacobians(int n) {
  static_assert(std::is_same<typename G::Scalar, double>::value, "numerical Jacobians in double");
  using J = typename G::Jacobian;
  using T = typename G::Tangent;
  lieservo::sampling::Rng rng(17);
  const double h = 1e-5;
  double worst = 0, worst_inv = 0;
  std::vector<double> angles = {0, 1e-9, 1e-6, 1e-3, 0.1, 0.5, 1, 2, 3, 3.14};
  for (int i = 0; i < n; ++i) {
    const T xi = tangentWithAngle<G>(rng, angles[static_cast<size_t>(i) % angles.size()], 2.0);
    const G X = G::exp(xi), Xi = X.inverse();
    J num, num_inv;
    for (int k = 0; k < G::DoF; ++k) {
      const T e = T::Unit(k) * h;
      num.col(k) = ((G::exp(xi + e) * Xi).log() - (G::exp(xi - e) * Xi).log()) / (2 * h);
      num_inv.col(k) = ((G::exp(e) * X).log() - (G::exp(-e) * X).log()) / (2 * h);
    }
    worst = std::max(worst, (num - G::leftJacobian(xi)).norm());
    worst_inv = std::max(worst_inv, (num_inv - G::leftJacobianInverse(X.log())).norm());
  }
  INFO("numerical J residual " << worst << ", J^-1 residual " << worst_inv);
  CHECK(worst <= 1e-7);
  CHECK(worst_inv <= 1e-7);
}

/// Float results agree with double results to a few float ulps (relative).
template <template <class> class GT>
void checkFloatAgainstDouble(int n) {
  using Gd = GT<double>;
  using Gf = GT<float>;
  lieservo::sampling::Rng rng(19);
  double worst = 0;
  for (int i = 0; i < n; ++i) {
    const typename Gd::Tangent xd = randomTangent<Gd>(rng, 3.0, 1.0);
    const typename Gf::Tangent xf = xd.template cast<float>();
    const typename Gd::Tangent xr = xf.template cast<double>();  // the float input, exactly
    auto rel = [](const auto& a, const auto& b) {
      return (a.template cast<double>() - b).norm() / (1.0 + b.norm());
    };
    worst = std::max(worst, rel(Gf::exp(xf).matrix(), Gd::exp(xr).matrix()));
    worst = std::max(worst, rel(Gf::leftJacobian(xf), Gd::leftJacobian(xr)));
    worst = std::max(worst, rel(Gf::leftJacobianInverse(xf), Gd::leftJacobianInverse(xr)));
    worst = std::max(worst, rel(Gf::ad(xf), Gd::ad(xr)));
    const Gd Xd = Gd::exp(xr);
    const Gf Xf = Xd.template cast<float>();
    worst = std::max(worst, rel(Xf.log(), Xf.template cast<double>().log()));
  }
  INFO("worst float/double relative difference " << worst);
  CHECK(worst <= 64 * epsOf<float>());
}

/// Inverse-Jacobian series Σ_{n≤N} B_n/n! ad^n → closed form as N grows; prints a table.
template <class G, int N>
double seriesError(const typename G::Tangent& xi) {
  const typename G::Jacobian d = G::template leftJacobianInverseSeries<N>(xi) - G::leftJacobianInverse(xi);
  return static_cast<double>(d.norm() / G::leftJacobianInverse(xi).norm());
}

template <class G>
void checkSeriesConvergence(const char* name) {
  const std::vector<double> angles = {0.1, 0.5, 1.0, 2.0, 3.0};
  lieservo::sampling::Rng rng(23);
  std::printf("%s: relative error of the series inverse Jacobian vs closed form (|rho| ~ 1)\n", name);
  std::printf("  theta |      N=0      N=1      N=2      N=4      N=8     N=16     N=32\n");
  for (double a : angles) {
    const typename G::Tangent xi = tangentWithAngle<G>(rng, a, 1.0);
    const double e[7] = {seriesError<G, 0>(xi), seriesError<G, 1>(xi), seriesError<G, 2>(xi), seriesError<G, 4>(xi),
                         seriesError<G, 8>(xi), seriesError<G, 16>(xi), seriesError<G, 32>(xi)};
    std::printf("  %5.2f | %8.1e %8.1e %8.1e %8.1e %8.1e %8.1e %8.1e\n", a, e[0], e[1], e[2], e[3], e[4], e[5], e[6]);
    for (int k = 1; k < 7; ++k) CHECK(e[k] <= e[k - 1] * 1.0001 + 1e-15);
    CHECK(e[6] <= (a <= 2.0 ? 1e-12 : 1e-8));
  }
}

/// BCH approximations (eq. 32, eqn:bch_approx) against exact log(exp·exp), double only: the error
/// is O(|ξ_small|²), so halving the small argument divides it by about 4.
template <class G>
void checkBch() {
  using T = typename G::Tangent;
  lieservo::sampling::Rng rng(29);
  for (int rep = 0; rep < 20; ++rep) {
    const T big = randomTangent<G>(rng, 2.5, 1.0);
    const T dir = randomTangent<G>(rng, 1.0, 1.0).normalized();
    double prev_l = 0, prev_r = 0;
    for (int k = 0; k < 5; ++k) {
      const double s = 1e-2 / std::pow(2.0, k);
      const T small = s * dir;
      const T exact_l = (G::exp(small) * G::exp(big)).log();
      const T exact_r = (G::exp(big) * G::exp(small)).log();
      const double el = (G::bchLeftSmall(small, big) - exact_l).norm();
      const double er = (G::bchRightSmall(big, small) - exact_r).norm();
      CHECK(el <= 10 * s * s);
      CHECK(er <= 10 * s * s);
      if (k > 0 && prev_l > 1e-12) {
        INFO("left ratio " << prev_l / el);
        CHECK(prev_l / el > 3.0);
        CHECK(prev_l / el < 5.0);
      }
      if (k > 0 && prev_r > 1e-12) {
        INFO("right ratio " << prev_r / er);
        CHECK(prev_r / er > 3.0);
        CHECK(prev_r / er < 5.0);
      }
      prev_l = el;
      prev_r = er;
    }
  }
}

/// Interpolation endpoints and midpoint symmetry.
template <class G>
void checkInterpolate(int n) {
  using S = typename G::Scalar;
  lieservo::sampling::Rng rng(31);
  double worst = 0;
  for (int i = 0; i < n; ++i) {
    const G A = G::sampleUniform(rng), B = A * G::exp(randomTangent<G>(rng, 3.0, 1.0));
    worst = std::max(worst, matDiff(A.interpolate(B, S(0)), A));
    worst = std::max(worst, matDiff(A.interpolate(B, S(1)), B));
    const G M = A.interpolate(B, S(0.5));
    worst = std::max(worst, static_cast<double>(((A.inverse() * M).log() - (M.inverse() * B).log()).norm()));
  }
  CHECK(worst <= 200 * epsOf<S>());
}

/// Checked constructors: ok for good input; non_finite_input / not_orthonormal for bad
/// input with `out` unchanged; projection returns a proper rotation.
template <class G>
void checkCheckedConstruction() {
  using S = typename G::Scalar;
  using M = typename G::Matrix;
  lieservo::sampling::Rng rng(37);
  const G X = lst::uniformElement<G>(rng, S(3));
  const G sentinel = lst::uniformElement<G>(rng, S(3));
  G out = sentinel;
  REQUIRE(G::fromMatrix(X.matrix(), out) == lieservo::Status::ok);
  CHECK(matDiff(out, X) == 0.0);

  out = sentinel;
  M bad = X.matrix();
  bad(0, 0) = std::numeric_limits<S>::quiet_NaN();
  CHECK(G::fromMatrix(bad, out) == lieservo::Status::non_finite_input);
  CHECK(G::fromMatrixProjected(bad, out) == lieservo::Status::non_finite_input);
  bad(0, 0) = std::numeric_limits<S>::infinity();
  CHECK(G::fromMatrix(bad, out) == lieservo::Status::non_finite_input);
  CHECK(matDiff(out, sentinel) == 0.0);

  // scaled rotation block: not orthonormal
  M scaled = X.matrix();
  scaled.template topLeftCorner<G::Dim, G::Dim>() *= S(1.01);
  CHECK(G::fromMatrix(scaled, out) == lieservo::Status::not_orthonormal);
  CHECK(matDiff(out, sentinel) == 0.0);
  // reflection: orthonormal but det = −1
  M refl = X.matrix();
  refl.template topLeftCorner<G::Dim, G::Dim>().col(0) *= S(-1);
  CHECK(G::fromMatrix(refl, out) == lieservo::Status::not_orthonormal);
  CHECK(matDiff(out, sentinel) == 0.0);

  // projection: a perturbed rotation comes back as the nearest proper rotation
  M noisy = X.matrix();
  noisy.template topLeftCorner<G::Dim, G::Dim>() += S(1e-3) * Eigen::Matrix<S, G::Dim, G::Dim>::Random();
  REQUIRE(G::fromMatrixProjected(noisy, out) == lieservo::Status::ok);
  const Eigen::Matrix<S, G::Dim, G::Dim> R = out.matrix().template topLeftCorner<G::Dim, G::Dim>();
  CHECK(static_cast<double>((R.transpose() * R - Eigen::Matrix<S, G::Dim, G::Dim>::Identity()).norm()) <=
        16 * epsOf<S>());
  CHECK(static_cast<double>(R.determinant()) > 0);
  CHECK(matDiff(out, X) <= 1e-2);
  // the projected rotation is closer to the input than the original rotation
  CHECK((noisy - out.matrix()).norm() <= (noisy - X.matrix()).norm() * S(1.0001));
  // a zero rotation block has no unique nearest rotation
  M zero = X.matrix();
  zero.template topLeftCorner<G::Dim, G::Dim>().setZero();
  G keep = sentinel;
  CHECK(G::fromMatrixProjected(zero, keep) == lieservo::Status::invalid_argument);
  CHECK(matDiff(keep, sentinel) == 0.0);

  // SE(n): each entry of the bottom row (0, …, 0, 1) is checked within the tolerance, by both
  // fromMatrix and fromMatrixProjected, the state unchanged on a refusal.
  if constexpr (M::RowsAtCompileTime == G::Dim + 1) {
    const S tol = S(1e-3);
    for (int j = 0; j <= G::Dim; ++j) {
      INFO("bottom row entry " << j);
      M row = X.matrix();
      row(G::Dim, j) += S(0.5) * tol;
      G near = sentinel;
      CHECK(G::fromMatrix(row, near, tol) == lieservo::Status::ok);
      CHECK(matDiff(near, X) == 0.0);
      row(G::Dim, j) += tol;
      keep = sentinel;
      CHECK(G::fromMatrix(row, keep, tol) == lieservo::Status::invalid_argument);
      row(G::Dim, j) += S(1e-2);
      CHECK(G::fromMatrix(row, keep) == lieservo::Status::invalid_argument);
      CHECK(G::fromMatrixProjected(row, keep) == lieservo::Status::invalid_argument);
      CHECK(matDiff(keep, sentinel) == 0.0);
    }
  }
}

/// Seeded sampling is reproducible; cast round trip; isApprox/allFinite.
template <class G>
void checkSamplingAndCast() {
  using S = typename G::Scalar;
  lieservo::sampling::Rng r1(99), r2(99);
  for (int i = 0; i < 10; ++i) CHECK(matDiff(lst::uniformElement<G>(r1, S(5)), lst::uniformElement<G>(r2, S(5))) == 0.0);
  const G X = lst::uniformElement<G>(r1, S(5));
  CHECK(X.allFinite());
  CHECK(X.isApprox(X, S(0)));
  CHECK(X.isApprox(X * G::exp(G::Tangent::Constant(S(1e-4))), S(1e-3)));
  CHECK_FALSE(X.isApprox(X * G::exp(G::Tangent::Constant(S(1e-1))), S(1e-3)));
  const auto Xd = X.template cast<double>();
  CHECK(static_cast<double>((Xd.matrix() - X.matrix().template cast<double>()).norm()) == 0.0);
  const auto Xf = X.template cast<float>();
  CHECK(static_cast<double>((Xf.matrix().template cast<double>() - X.matrix().template cast<double>()).norm()) <= 1e-6);
}

}  // namespace lst

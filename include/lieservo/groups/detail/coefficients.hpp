// lieservo/groups/detail/coefficients.hpp — the scalar coefficient functions of SO(2), SE(2),
// SO(3) and SE(3), each accurate to a few ulp over θ ∈ [0, π] (and beyond, up to 2π where defined).
//
// Every coefficient f(θ) below is an even function of θ, evaluated from x = θ². Each has:
//   * a closed form, used for x ≥ its cutoff, written to avoid cancellation where it can
//     (1 − cosθ is always computed as 2 sin²(θ/2));
//   * a truncated Taylor series in x with K terms and ITS OWN cutoff
//     x_cut = (eps · |a0/a_K|)^(1/K) (see series.hpp), K chosen so that the closed form is
//     accurate to ≲ 10 eps wherever it is used (docs/math.md lists K, the cutoffs and the
//     error of each coefficient).
// The trigonometric work (one sin/cos of θ/2, one sqrt) is shared through AngleTerms.
#pragma once

#include <algorithm>
#include <cmath>
#include <type_traits>

#include <lieservo/groups/detail/series.hpp>

namespace lieservo {
namespace detail {

// ---- series tables (coefficients of x = θ²; last entry = first omitted term) -------------

/// A(θ) = sinθ/θ = Σ (−1)^k x^k/(2k+1)!. The closed form has no cancellation; the series
/// only avoids 0/0 at θ = 0, so three terms suffice.
inline constexpr SeriesTable<3> kSeriesA{{1.0L, -1.0L / 6, 1.0L / 120, -1.0L / 5040}};

/// B(θ) = (1 − cosθ)/θ² = 2 sin²(θ/2)/θ² = Σ (−1)^k x^k/(2k+2)!. No cancellation in the
/// 2 sin² form; the series only avoids 0/0.
inline constexpr SeriesTable<3> kSeriesB{{1.0L / 2, -1.0L / 24, 1.0L / 720, -1.0L / 40320}};

/// C(θ) = (θ − sinθ)/θ³ = Σ (−1)^k x^k/(2k+3)!. The closed form cancels (relative error
/// ≈ 6 eps/θ²), so the series runs to θ ≈ 0.44 (double) with six terms.
inline constexpr SeriesTable<6> kSeriesC{{1.0L / 6, -1.0L / 120, 1.0L / 5040, -1.0L / 362880,
                                          1.0L / 39916800, -1.0L / 6227020800,
                                          1.0L / 1307674368000}};

/// D(θ) = (1/θ²)(1 − θ sinθ / (2(1 − cosθ))) = (1 − (θ/2)cot(θ/2))/θ²
///      = Σ_{n≥1} (−1)^{n+1} B_{2n} x^{n−1}/(2n)!  (the SO(3) inverse-Jacobian coefficient).
/// The closed form cancels (relative error ≈ 12 eps/θ²); seven terms take the series to
/// θ ≈ 0.5 (double). Radius of convergence 2π.
inline constexpr SeriesTable<7> kSeriesD{{1.0L / 12, 1.0L / 720, 1.0L / 30240, 1.0L / 1209600,
                                          1.0L / 47900160, 691.0L / 1307674368000,
                                          1.0L / 74724249600,
                                          3617.0L / 10670622842880000}};

/// E(θ) = (θ² + 2cosθ − 2)/(2θ⁴) = (θ²/2 − (1 − cosθ))/θ⁴ = Σ (−1)^k x^k/(2k+4)!
/// (Barfoot's second SE(3) Q coefficient). Closed form cancels (≈ 12 eps/θ²).
inline constexpr SeriesTable<6> kSeriesE{{1.0L / 24, -1.0L / 720, 1.0L / 40320, -1.0L / 3628800,
                                          1.0L / 479001600, -1.0L / 87178291200,
                                          1.0L / 20922789888000}};

/// F(θ) = (2θ − 3 sinθ + θ cosθ)/(2θ⁵) = ½ Σ_{n≥2} (−1)^n (2n−2) x^{n−2}/(2n+1)!
/// (Barfoot's third SE(3) Q coefficient). The closed form cancels to fifth order (relative
/// error ≈ 120 eps/θ⁴), so eight terms take the series to θ ≈ 1.16 (double).
inline constexpr SeriesTable<8> kSeriesF{{1.0L / 120, -1.0L / 2520, 1.0L / 120960,
                                          -1.0L / 9979200, 1.0L / 1245404160,
                                          -1.0L / 217945728000, 1.0L / 50812489728000,
                                          -1.0L / 15205637551104000,
                                          1.0L / 5676771352412160000}};

/// H(θ) = (θ/2) cot(θ/2) = θ sinθ / (2(1 − cosθ)) = Σ (−1)^n B_{2n} x^n/(2n)!.
/// (SE(2) inverse of V; no cancellation, the series only avoids 0/0.)
inline constexpr SeriesTable<3> kSeriesH{{1.0L, -1.0L / 12, -1.0L / 720, -1.0L / 30240}};

/// atan(y)/y = Σ (−1)^k y^{2k}/(2k+1), in x = y² (SO(3) log through the quaternion; no
/// cancellation, the series only avoids 0/0 at the identity).
inline constexpr SeriesTable<3> kSeriesAtan{{1.0L, -1.0L / 3, 1.0L / 5, -1.0L / 7}};

// ---- cutoffs, computed once per real type --------------------------------------------------

template <class Scalar, std::size_t K>
constexpr RealOf<Scalar> cutoffOf(const SeriesTable<K>& s) noexcept {
  return static_cast<RealOf<Scalar>>(s.cutoff(epsilonOf<Scalar>()));
}

/// The cutoffs (in x = θ²) of every coefficient for one scalar type: compile-time constants.
template <class Scalar>
struct Cutoffs {
  using Real = RealOf<Scalar>;
  static constexpr Real A = cutoffOf<Scalar>(kSeriesA);
  static constexpr Real B = cutoffOf<Scalar>(kSeriesB);
  static constexpr Real C = cutoffOf<Scalar>(kSeriesC);
  static constexpr Real D = cutoffOf<Scalar>(kSeriesD);
  static constexpr Real E = cutoffOf<Scalar>(kSeriesE);
  static constexpr Real F = cutoffOf<Scalar>(kSeriesF);
  static constexpr Real H = cutoffOf<Scalar>(kSeriesH);
  static constexpr Real Atan = cutoffOf<Scalar>(kSeriesAtan);
  /// Trigonometric terms are needed as soon as any coefficient leaves its series.
  static constexpr Real trig = std::min({A, B, C, D, E, F, H});
  /// Backwards-compatible accessor (the values are static constants).
  static constexpr Cutoffs get() noexcept { return Cutoffs{}; }
};

/// θ, sinθ, cosθ and 1 − cosθ for x = θ² ≥ 0, computed from one sin/cos of θ/2 so that
/// 1 − cosθ = 2 sin²(θ/2) never cancels. Below the smallest cutoff nothing trigonometric is
/// evaluated (all coefficients use their series; important for autodiff scalars at θ = 0).
template <class Scalar>
struct AngleTerms {
  Scalar theta2;
  bool closed = false;  ///< true when theta/sin/cos/one_minus_cos are valid
  Scalar theta, sin, cos, one_minus_cos;

  explicit AngleTerms(const Scalar& x) : theta2(x), theta(0), sin(0), cos(1), one_minus_cos(0) {
    using std::cos;
    using std::sin;
    using std::sqrt;
    using Real = RealOf<Scalar>;
    if (!(x < Scalar(Cutoffs<Scalar>::trig))) {
      theta = sqrt(x);
      const Scalar half = theta / Scalar(Real(2));
      setHalfAngle(sin(half), cos(half));
    }
  }

  /// The same terms for an angle θ whose half-angle sine and cosine are already known (the
  /// quaternion logarithm has them): no trigonometric call.
  static AngleTerms fromHalfAngle(const Scalar& theta, const Scalar& sin_half, const Scalar& cos_half) {
    AngleTerms t(Scalar(0));
    t.theta2 = theta * theta;
    if (!(t.theta2 < Scalar(Cutoffs<Scalar>::trig))) {
      t.theta = theta;
      t.setHalfAngle(sin_half, cos_half);
    }
    return t;
  }

  /// The same terms for θ with known sinθ and cosθ > −1 (the matrix logarithm has them away
  /// from π). 1 − cosθ is formed without cancellation: directly while cosθ < ½, as
  /// sin²θ/(1 + cosθ) above (small θ).
  static AngleTerms fromSinCos(const Scalar& theta, const Scalar& sin_theta, const Scalar& cos_theta) {
    using Real = RealOf<Scalar>;
    AngleTerms t(Scalar(0));
    t.theta2 = theta * theta;
    if (!(t.theta2 < Scalar(Cutoffs<Scalar>::trig))) {
      t.closed = true;
      t.theta = theta;
      t.sin = sin_theta;
      t.cos = cos_theta;
      const Scalar one(Real(1));
      t.one_minus_cos = cos_theta < Scalar(Real(0.5)) ? one - cos_theta : sin_theta * sin_theta / (one + cos_theta);
    }
    return t;
  }

 private:
  void setHalfAngle(const Scalar& sh, const Scalar& ch) {
    using Real = RealOf<Scalar>;
    closed = true;
    this->sin = Scalar(Real(2)) * sh * ch;
    this->cos = (ch - sh) * (ch + sh);
    one_minus_cos = Scalar(Real(2)) * sh * sh;
  }
};

// ---- the half-angle terms of exp on SO(3), as series over a quarter turn ------------------
//
// exp(φ^) is the rotation of the unit quaternion (w, v) = (cos(θ/2), (sin(θ/2)/θ) φ). Both
// factors are even and entire in θ, so they are power series in x = θ² alone: no square root,
// no sin/cos call, no division. Over θ ≤ π/2 (x ≤ π²/4) a few terms reach the precision of
// the scalar, and the two series run side by side in one SIMD packet (lanesEval).

/// sin(θ/2)/θ = Σ (−1)^n xⁿ / (2·4ⁿ·(2n+1)!), the n-th coefficient.
constexpr long double halfSincTerm(int n) noexcept {
  long double d = 2.0L;
  for (int k = 1; k <= 2 * n + 1; ++k) d *= static_cast<long double>(k);
  for (int k = 0; k < n; ++k) d *= 4.0L;
  return (n % 2 == 0 ? 1.0L : -1.0L) / d;
}

/// cos(θ/2) = Σ (−1)^n xⁿ / (4ⁿ·(2n)!), the n-th coefficient.
constexpr long double halfCosTerm(int n) noexcept {
  long double d = 1.0L;
  for (int k = 1; k <= 2 * n; ++k) d *= static_cast<long double>(k);
  for (int k = 0; k < n; ++k) d *= 4.0L;
  return (n % 2 == 0 ? 1.0L : -1.0L) / d;
}

/// x = θ² up to which exp uses the half-angle series: a quarter turn, (π/2)².
constexpr long double kHalfAngleSeriesMaxX = 2.4674011002723396547086758650315838L;

/// The number of terms K for one scalar type: the first omitted term of each series stays
/// below eps·|a0| at x = π²/4, the same rule as every other series here (series.hpp).
template <class Scalar>
constexpr int halfAngleTermCount() noexcept {
  const long double eps = epsilonOf<Scalar>();
  for (int K = 3; K < 40; ++K) {
    long double xk = 1.0L;
    for (int k = 0; k < K; ++k) xk *= kHalfAngleSeriesMaxX;
    const long double s = halfSincTerm(K) * xk, c = halfCosTerm(K) * xk;
    if ((s < 0 ? -s : s) < eps * halfSincTerm(0) && (c < 0 ? -c : c) < eps * halfCosTerm(0)) return K;
  }
  return 40;
}

/// The two series' coefficients for one scalar type, lane 0 sin(θ/2)/θ and lane 1 cos(θ/2),
/// rounded once from long double; float pads to a 4-lane packet.
template <class Scalar>
struct HalfAngleSeries {
  using Real = RealOf<Scalar>;
  static constexpr int K = halfAngleTermCount<Scalar>();
  static constexpr int L = std::is_same<Real, float>::value ? 4 : 2;
  alignas(16) Real a[K][L];
  constexpr HalfAngleSeries() noexcept : a() {
    for (int n = 0; n < K; ++n) {
      a[n][0] = static_cast<Real>(halfSincTerm(n));
      a[n][1] = static_cast<Real>(halfCosTerm(n));
    }
  }
};

template <class Scalar>
inline constexpr HalfAngleSeries<Scalar> kHalfAngleSeries{};

/// sinθ/θ.
template <class Scalar>
inline Scalar coeffA(const AngleTerms<Scalar>& t) {
  if (!t.closed || t.theta2 < Scalar(Cutoffs<Scalar>::A)) return hornerEval(kSeriesA, t.theta2);
  return t.sin / t.theta;
}

/// (1 − cosθ)/θ².
template <class Scalar>
inline Scalar coeffB(const AngleTerms<Scalar>& t) {
  if (!t.closed || t.theta2 < Scalar(Cutoffs<Scalar>::B)) return hornerEval(kSeriesB, t.theta2);
  return t.one_minus_cos / t.theta2;
}

/// (θ − sinθ)/θ³.
template <class Scalar>
inline Scalar coeffC(const AngleTerms<Scalar>& t) {
  if (!t.closed || t.theta2 < Scalar(Cutoffs<Scalar>::C)) return hornerEval(kSeriesC, t.theta2);
  return (t.theta - t.sin) / (t.theta2 * t.theta);
}

/// (θ/2)cot(θ/2) = θ sinθ/(2(1 − cosθ)); evaluated as (θ/2)·cos(θ/2)/sin(θ/2) through the
/// shared terms: θ sinθ / (2 · 2 sin²(θ/2)).
template <class Scalar>
inline Scalar coeffH(const AngleTerms<Scalar>& t) {
  using Real = RealOf<Scalar>;
  if (!t.closed || t.theta2 < Scalar(Cutoffs<Scalar>::H)) return hornerEval(kSeriesH, t.theta2);
  return t.theta * t.sin / (Scalar(Real(2)) * t.one_minus_cos);
}

/// (1/θ²)(1 − θ sinθ/(2(1 − cosθ))) — SO(3) inverse-Jacobian coefficient.
template <class Scalar>
inline Scalar coeffD(const AngleTerms<Scalar>& t) {
  using Real = RealOf<Scalar>;
  if (!t.closed || t.theta2 < Scalar(Cutoffs<Scalar>::D)) return hornerEval(kSeriesD, t.theta2);
  return (Scalar(Real(1)) - coeffH(t)) / t.theta2;
}

/// (θ² + 2cosθ − 2)/(2θ⁴) — SE(3) Q coefficient of (φ^φ^ρ^ + ρ^φ^φ^ − 3φ^ρ^φ^).
template <class Scalar>
inline Scalar coeffE(const AngleTerms<Scalar>& t) {
  using Real = RealOf<Scalar>;
  if (!t.closed || t.theta2 < Scalar(Cutoffs<Scalar>::E)) return hornerEval(kSeriesE, t.theta2);
  return (t.theta2 / Scalar(Real(2)) - t.one_minus_cos) / (t.theta2 * t.theta2);
}

/// (2θ − 3 sinθ + θ cosθ)/(2θ⁵) — SE(3) Q coefficient of (φ^ρ^φ^φ^ + φ^φ^ρ^φ^).
template <class Scalar>
inline Scalar coeffF(const AngleTerms<Scalar>& t) {
  using Real = RealOf<Scalar>;
  if (!t.closed || t.theta2 < Scalar(Cutoffs<Scalar>::F)) return hornerEval(kSeriesF, t.theta2);
  return (Scalar(Real(2)) * t.theta - Scalar(Real(3)) * t.sin + t.theta * t.cos) /
         (Scalar(Real(2)) * t.theta2 * t.theta2 * t.theta);
}

}  // namespace detail
}  // namespace lieservo

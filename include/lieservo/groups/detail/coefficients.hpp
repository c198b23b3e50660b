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
#include <lieservo/detail/options_push.hpp>

#include <algorithm>
#include <cmath>
#include <type_traits>

#include <lieservo/groups/detail/ordered.hpp>
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

/// atan(y)/y = Σ (−1)^k y^{2k}/(2k+1), in x = y² (SO(3) log through the quaternion; no
/// cancellation, the series only avoids 0/0 at the identity).
inline constexpr SeriesTable<3> kSeriesAtan{{1.0L, -1.0L / 3, 1.0L / 5, -1.0L / 7}};

/// θ/(2 sinθ) = ½ asin(y)/y at y = sinθ, in x = 4 sin²θ = |s|² for s = 2 sinθ·axis (the
/// antisymmetric part of a rotation matrix): ½ + x/48 + 3x²/1280 + …  The SO(3) log's form near
/// the identity without a division or an arctangent (detail::rotationVectorFromMatrix).
inline constexpr SeriesTable<2> kSeriesHalfAsin{{1.0L / 2, 1.0L / 48, 3.0L / 1280}};

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
  static constexpr Real H = D;  ///< H = 1 − x D(x) takes D's series (coeffH)
  static constexpr Real Atan = cutoffOf<Scalar>(kSeriesAtan);
  static constexpr Real HalfAsin = cutoffOf<Scalar>(kSeriesHalfAsin);
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
      t.one_minus_cos = cos_theta < Scalar(Real(0.5)) ? one - cos_theta : quotient(sin_theta * sin_theta, one + cos_theta);
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

// ---- the half-angle terms of exp on SO(3), for tiny angles ----------------------------------
//
// exp(φ^) is the rotation of the unit quaternion (w, v) = (cos(θ/2), (sin(θ/2)/θ) φ). Both
// factors are even and entire in θ, so they are power series in x = θ² alone: no square root,
// no sin/cos call, no division. For tiny angles three terms reach the precision of the scalar,
// and the two series run side by side in one SIMD packet (lanesEval). Elsewhere up to the half
// turn exp takes Rodrigues' coefficients as series (further below).

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

/// x = θ² up to which exp uses the series at all: a half turn, π².
constexpr long double kHalfAngleSeriesMaxX = 9.8696044010893586188344909998761511L;

/// π² as a sum hi + lo of two numbers of the real type: d = (x − hi) − lo loses nothing to the
/// rounding of π² (x − hi is exact for x ∈ [hi/2, 2 hi], Sterbenz).
template <class Real>
struct PiSquaredSplit {
  Real hi, lo;
};
template <class Real>
inline constexpr PiSquaredSplit<Real> kPiSquared{
    static_cast<Real>(kHalfAngleSeriesMaxX),
    static_cast<Real>(kHalfAngleSeriesMaxX - static_cast<long double>(static_cast<Real>(kHalfAngleSeriesMaxX)))};

/// The larger of the two series' omitted terms after K terms at x, relative to their first.
constexpr long double halfAngleOmitted(int K, long double x) noexcept {
  long double xk = 1.0L;
  for (int k = 0; k < K; ++k) xk *= x;
  const long double s = halfSincTerm(K) / halfSincTerm(0) * xk, c = halfCosTerm(K) * xk;
  const long double as = s < 0 ? -s : s, ac = c < 0 ? -c : c;
  return as > ac ? as : ac;
}

/// x below which the first three terms reach eps by the rule of every other series here (the
/// first omitted term below eps·|a0|, series.hpp): θ < 0.015 in double, 0.42 in float. exp
/// takes them alone there, with no square root, and tiny angles never reach the high powers
/// of x, which would underflow into subnormal numbers (slow on x86 at θ ≲ 1e-8 in float).
template <class Scalar>
constexpr long double halfAngleShortMaxX() noexcept {
  const long double a3 = halfAngleOmitted(3, 1.0L);  // the larger omitted coefficient, relative
  return constexprRoot(epsilonOf<Scalar>() / a3, 3);
}

/// Lanes of a series packet: two in double, float padded to a 4-lane packet.
template <class Scalar>
constexpr int kSeriesLanes = std::is_same<RealOf<Scalar>, float>::value ? 4 : 2;

/// The first three terms of the two series for one scalar type (halfAngleShortMaxX), lane 0
/// sin(θ/2)/θ and lane 1 cos(θ/2), rounded once from long double.
template <class Scalar>
struct HalfAngleShortSeries {
  using Real = RealOf<Scalar>;
  static constexpr int L = kSeriesLanes<Scalar>;
  alignas(16) Real a[3][L];
  constexpr HalfAngleShortSeries() noexcept : a() {
    for (int n = 0; n < 3; ++n) {
      a[n][0] = static_cast<Real>(halfSincTerm(n));
      a[n][1] = static_cast<Real>(halfCosTerm(n));
    }
  }
};

template <class Scalar>
inline constexpr HalfAngleShortSeries<Scalar> kHalfAngleShortSeries{};

// ---- exp near the half turn: Rodrigues' coefficients as series about π² ----------------------
//
// Near θ = π the half-angle factor cos(θ/2) falls to 0, and its series at x = 0 would form it
// from terms of order one that cancel; the quaternion's matrix also rounds worse there than
// Rodrigues' form. So exp takes Rodrigues' A = sinθ/θ and B = (1 − cosθ)/θ² there, and near
// the half turn itself as series about x0 = π², in d = x − π² ≤ 0, where A = −d/(2π²) + …
// keeps its relative accuracy as it falls to 0. With f = cos(√x/2) and g = sin(√x/2)/√x,
// A = 2fg and B = 2g², and f′ = −g/4, x g′ = f/4 − g/2 give f's and g's coefficients from
// f₀ = 0, g₀ = 1/π by (n+1) f_{n+1} = −g_n/4 and x0 (n+1) g_{n+1} = f_n/4 − (n + 1/2) g_n (in
// long double).

/// The first 24 coefficients of A and B about x0 > 0, from f₀ = f(x0) and g₀ = g(x0).
struct RodriguesTerms {
  long double A[24] = {}, B[24] = {};
  constexpr RodriguesTerms(long double x0, long double f0, long double g0) noexcept {
    long double f[24] = {}, g[24] = {};
    f[0] = f0;
    g[0] = g0;
    for (int n = 0; n + 1 < 24; ++n) {
      f[n + 1] = -g[n] / (4.0L * (n + 1));
      g[n + 1] = (f[n] / 4.0L - (n + 0.5L) * g[n]) / (x0 * (n + 1));
    }
    for (int n = 0; n < 24; ++n)
      for (int i = 0; i <= n; ++i) {
        A[n] += 2.0L * f[i] * g[n - i];
        B[n] += 2.0L * g[i] * g[n - i];
      }
  }
};
/// About π²: f₀ = cos(π/2) = 0 and g₀ = 1/π, exactly.
inline constexpr RodriguesTerms kHalfTurnTerms{kHalfAngleSeriesMaxX, 0.0L,
                                               1.0L / 3.1415926535897932384626433832795029L};

// ---- exp up to the half turn: Rodrigues' coefficients piece by piece -------------------------
//
// Over x = θ² ∈ [0, π²] exp takes Rodrigues' A = sinθ/θ and B = (1 − cosθ)/θ² as series in
// d = x − c_i about the centre c_i of one of kExpPieces equal pieces, the piece chosen by
// arithmetic (i = ⌊x / w⌋), not by a branch: on angles spread over the half turn a branch
// between forms is mispredicted on every other call. The recurrence of kHalfTurnTerms gives
// the coefficients about any x0 > 0, from f₀ = cos(√x0/2), g₀ = sin(√x0/2)/√x0
// (rodriguesTermsAbout). By the omitted-term rule below that is 9 terms in double and 5 in
// float on every piece. Near the half turn A falls to 0, and about a centre
// inside the piece its terms would cancel there: so one more slot, chosen by the same
// arithmetic, holds the series about π² itself (kHalfTurnTerms, in d = x − π²), for d within
// expHalfTurnMaxD of 0.

/// Pieces of [0, π²].
constexpr int kExpPieces = 6;

/// sin and cos of y ∈ [0, π/2] by their Taylor series in long double (constexpr).
constexpr void constexprSinCos(long double y, long double& s, long double& c) noexcept {
  long double ts = y, tc = 1.0L;
  s = 0.0L;
  c = 0.0L;
  for (int n = 0; n < 40; ++n) {
    s += ts;
    c += tc;
    ts *= -y * y / ((2.0L * n + 2) * (2.0L * n + 3));
    tc *= -y * y / ((2.0L * n + 1) * (2.0L * n + 2));
  }
}

/// The coefficients about x0 ∈ (0, π²].
constexpr RodriguesTerms rodriguesTermsAbout(long double x0) noexcept {
  long double s = 0, c = 0;
  const long double r = constexprRoot(x0, 2);
  constexprSinCos(r / 2, s, c);
  return RodriguesTerms(x0, c, s / r);
}

/// Piece i's centre, rounded to the real type: d = x − c_i is exact near c_i (Sterbenz), and
/// the coefficients are those about the rounded centre.
template <class Real>
constexpr Real expPieceCentre(int i) noexcept {
  return static_cast<Real>(kHalfAngleSeriesMaxX * (i + 0.5L) / kExpPieces);
}

/// The larger omitted term after K terms at half a piece's width: A's absolute (A scales φ^,
/// whose entries are of order one), B's relative to B(c).
constexpr long double expPieceOmitted(const RodriguesTerms& t, int K) noexcept {
  long double hk = 1.0L;
  for (int k = 0; k < K; ++k) hk *= kHalfAngleSeriesMaxX / (2 * kExpPieces);
  const long double a = t.A[K] * hk, b = t.B[K] / t.B[0] * hk;
  const long double aa = a < 0 ? -a : a, ab = b < 0 ? -b : b;
  return aa > ab ? aa : ab;
}

/// Terms per piece: the first omitted term below eps/8 on every piece (one count for all, so
/// that the piece is a table index).
template <class Scalar>
constexpr int expPieceTermCount() noexcept {
  int K = 3;
  for (int i = 0; i < kExpPieces; ++i) {
    const RodriguesTerms t = rodriguesTermsAbout(static_cast<long double>(expPieceCentre<RealOf<Scalar>>(i)));
    while (K < 23 && expPieceOmitted(t, K) >= epsilonOf<Scalar>() / 8) ++K;
  }
  return K;
}

/// |d| = |x − π²| up to which the same number of terms of the series about π² holds its
/// omitted term below eps/64: A there multiplies φ^, whose entries reach π, and where the
/// slot ends its truncation must not make exp less accurate than Rodrigues with sin/cos
/// (tests/groups/test_so3.cpp samples that end). θ within 0.15 rad of π in double, 0.10 in float.
template <class Scalar>
constexpr long double expHalfTurnMaxD() noexcept {
  constexpr int K = expPieceTermCount<Scalar>();
  const long double a = kHalfTurnTerms.A[K] < 0 ? -kHalfTurnTerms.A[K] : kHalfTurnTerms.A[K];
  const long double b0 = kHalfTurnTerms.B[K] / kHalfTurnTerms.B[0], b = b0 < 0 ? -b0 : b0;
  return constexprRoot(epsilonOf<Scalar>() / (64.0L * (a > b ? a : b)), K);
}

/// The pieces for one scalar type: 1/width; per slot (the kExpPieces pieces, then the half
/// turn) the point expanded about, as hi + lo (d = (x − hi) − lo; lo ≠ 0 for π² alone), and
/// lane 0 A, lane 1 B.
template <class Scalar>
struct ExpPieces {
  using Real = RealOf<Scalar>;
  static constexpr int K = expPieceTermCount<Scalar>();
  static constexpr int L = kSeriesLanes<Scalar>;
  static constexpr int kHalfTurn = kExpPieces;  // the slot of the series about π²
  Real inv_width = static_cast<Real>(kExpPieces / kHalfAngleSeriesMaxX);
  Real half_turn_max_d = static_cast<Real>(expHalfTurnMaxD<Scalar>());
  Real hi[kExpPieces + 1] = {}, lo[kExpPieces + 1] = {};
  alignas(16) Real a[kExpPieces + 1][K][L];
  constexpr ExpPieces() noexcept : a() {
    for (int i = 0; i < kExpPieces; ++i) {
      hi[i] = expPieceCentre<Real>(i);
      const RodriguesTerms t = rodriguesTermsAbout(static_cast<long double>(hi[i]));
      for (int n = 0; n < K; ++n) {
        a[i][n][0] = static_cast<Real>(t.A[n]);
        a[i][n][1] = static_cast<Real>(t.B[n]);
      }
    }
    hi[kHalfTurn] = kPiSquared<Real>.hi;
    lo[kHalfTurn] = kPiSquared<Real>.lo;
    for (int n = 0; n < K; ++n) {
      a[kHalfTurn][n][0] = static_cast<Real>(kHalfTurnTerms.A[n]);
      a[kHalfTurn][n][1] = static_cast<Real>(kHalfTurnTerms.B[n]);
    }
  }
};

template <class Scalar>
inline constexpr ExpPieces<Scalar> kExpPieceSeries{};

/// sinθ/θ.
template <class Scalar>
inline Scalar coeffA(const AngleTerms<Scalar>& t) {
  if (!t.closed || t.theta2 < Scalar(Cutoffs<Scalar>::A)) return hornerEval(kSeriesA, t.theta2);
  return quotient(t.sin, t.theta);
}

/// (1 − cosθ)/θ².
template <class Scalar>
inline Scalar coeffB(const AngleTerms<Scalar>& t) {
  if (!t.closed || t.theta2 < Scalar(Cutoffs<Scalar>::B)) return hornerEval(kSeriesB, t.theta2);
  return quotient(t.one_minus_cos, t.theta2);
}

/// (θ − sinθ)/θ³.
template <class Scalar>
inline Scalar coeffC(const AngleTerms<Scalar>& t) {
  if (!t.closed || t.theta2 < Scalar(Cutoffs<Scalar>::C)) return hornerEval(kSeriesC, t.theta2);
  return quotient(t.theta - t.sin, t.theta2 * t.theta);
}

/// H(θ) = (θ/2)cot(θ/2) = θ sinθ/(2(1 − cosθ)), in the closed form through the shared terms:
/// θ sinθ / (2 · 2 sin²(θ/2)).
template <class Scalar>
inline Scalar coeffHClosed(const AngleTerms<Scalar>& t) {
  using Real = RealOf<Scalar>;
  return quotient(t.theta * t.sin, Scalar(Real(2)) * t.one_minus_cos);
}

/// H(θ) = (θ/2)cot(θ/2) = 1 − x D(x) (SE(2)'s V⁻¹). The closed form's value has no
/// cancellation, but its derivative (what an autodiff scalar carries) is a difference of two
/// terms ≈ 1/θ that cancel to −θ/6 (relative error ≈ 6 eps/θ²); so below D's cutoff (θ ≈ 0.5
/// in double) H is formed from D's series, whose value and derivative are both accurate.
template <class Scalar>
inline Scalar coeffH(const AngleTerms<Scalar>& t) {
  using Real = RealOf<Scalar>;
  if (!t.closed || t.theta2 < Scalar(Cutoffs<Scalar>::D))
    return Scalar(Real(1)) - t.theta2 * hornerEval(kSeriesD, t.theta2);
  return coeffHClosed(t);
}

/// (1/θ²)(1 − θ sinθ/(2(1 − cosθ))) — SO(3) inverse-Jacobian coefficient.
template <class Scalar>
inline Scalar coeffD(const AngleTerms<Scalar>& t) {
  using Real = RealOf<Scalar>;
  if (!t.closed || t.theta2 < Scalar(Cutoffs<Scalar>::D)) return hornerEval(kSeriesD, t.theta2);
  return quotient(Scalar(Real(1)) - coeffHClosed(t), t.theta2);
}

/// (θ² + 2cosθ − 2)/(2θ⁴) — SE(3) Q coefficient of (φ^φ^ρ^ + ρ^φ^φ^ − 3φ^ρ^φ^).
template <class Scalar>
inline Scalar coeffE(const AngleTerms<Scalar>& t) {
  using Real = RealOf<Scalar>;
  if (!t.closed || t.theta2 < Scalar(Cutoffs<Scalar>::E)) return hornerEval(kSeriesE, t.theta2);
  return quotient(t.theta2 / Scalar(Real(2)) - t.one_minus_cos, t.theta2 * t.theta2);
}

/// (2θ − 3 sinθ + θ cosθ)/(2θ⁵) — SE(3) Q coefficient of (φ^ρ^φ^φ^ + φ^φ^ρ^φ^).
template <class Scalar>
inline Scalar coeffF(const AngleTerms<Scalar>& t) {
  using Real = RealOf<Scalar>;
  if (!t.closed || t.theta2 < Scalar(Cutoffs<Scalar>::F)) return hornerEval(kSeriesF, t.theta2);
  return quotient(Scalar(Real(2)) * t.theta - Scalar(Real(3)) * t.sin + t.theta * t.cos,
                  Scalar(Real(2)) * t.theta2 * t.theta2 * t.theta);
}

}  // namespace detail
}  // namespace lieservo

#include <lieservo/detail/options_pop.hpp>

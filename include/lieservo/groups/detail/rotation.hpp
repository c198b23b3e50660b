// lieservo/groups/detail/rotation.hpp — 3-D rotation helpers: skew matrices, the matrix of a
// unit quaternion, Shepperd's matrix→quaternion conversion, the rotation logarithm (from a
// matrix or a quaternion) and the Rodrigues formulas.
#pragma once
#include <lieservo/detail/options_push.hpp>

#include <cmath>
#include <type_traits>

#include <Eigen/Core>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <lieservo/detail/flatten.hpp>
#include <lieservo/units.hpp>
#include <lieservo/groups/detail/coefficients.hpp>
#include <lieservo/groups/detail/ordered.hpp>

namespace lieservo {
namespace detail {

/// φ^ : the skew-symmetric matrix with φ^ v = φ × v (eq. 29, eqn:so3_hat_operator).
template <class Scalar>
inline Eigen::Matrix<Scalar, 3, 3> skew(const Eigen::Matrix<Scalar, 3, 1>& p) {
  Eigen::Matrix<Scalar, 3, 3> m;
  const Scalar z(0);
  m << z, -p(2), p(1),  //
      p(2), z, -p(0),   //
      -p(1), p(0), z;
  return m;
}

/// out = A B for 3×3 matrices, column by column (out.col(j) = Σ_k A.col(k) B(k, j)), written
/// into `out` (which must not alias A or B). Eigen's coefficient-wise 3×3 product is not inlined
/// for float (a function call per entry): this form is vectorised and inlined for both types.
template <class Scalar>
inline void multiply3(const Eigen::Matrix<Scalar, 3, 3>& A, const Eigen::Matrix<Scalar, 3, 3>& B,
                      Eigen::Matrix<Scalar, 3, 3>& out) {
  for (int j = 0; j < 3; ++j)
    out.col(j) = A.col(0) * B(0, j) + A.col(1) * B(1, j) + A.col(2) * B(2, j);
}

/// The rotation matrix of the unit quaternion (w, v), v = k φ (exp: k = sin(θ/2)/θ,
/// w = cos(θ/2)): C = I + 2w v^ + 2 v^v^, entry by entry. The diagonal 1 − 2(v_j² + v_k²) sums
/// two squares, so nothing cancels. Written into `C`.
template <class Scalar>
inline void matrixFromHalfAngle(const Eigen::Matrix<Scalar, 3, 1>& phi, const Scalar& k, const Scalar& w,
                                Eigen::Matrix<Scalar, 3, 3>& C) {
  const Eigen::Matrix<Scalar, 3, 1> v = k * phi;
  const Eigen::Matrix<Scalar, 3, 1> v2 = v + v;
  const Scalar xx = v2(0) * v(0), yy = v2(1) * v(1), zz = v2(2) * v(2);
  const Scalar xy = v2(0) * v(1), xz = v2(0) * v(2), yz = v2(1) * v(2);
  const Scalar wx = v2(0) * w, wy = v2(1) * w, wz = v2(2) * w;
  const Scalar one(1);
  C(0, 0) = one - (yy + zz);
  C(1, 0) = xy + wz;
  C(2, 0) = xz - wy;
  C(0, 1) = xy - wz;
  C(1, 1) = one - (xx + zz);
  C(2, 1) = yz + wx;
  C(0, 2) = xz + wy;
  C(1, 2) = yz - wx;
  C(2, 2) = one - (xx + yy);
}

#if defined(__SSE2__)
/// The same for float on SSE, with the three diagonal entries, the three "+" and the three
/// "−" off-diagonal entries each formed in one packet: the same operations on the same
/// operands, so the same result bit for bit (tests/groups). GCC compiles the scalar form to
/// scalar float instructions and shuffles for the stores; that took SO3f exp to 7.5 ns against
/// 5.2–5.7 ns with the packets (docs/performance.md).
inline void matrixFromHalfAngle(const Eigen::Matrix<float, 3, 1>& phi, const float& k, const float& w,
                                Eigen::Matrix<float, 3, 3>& C) {
  const __m128 v = _mm_mul_ps(_mm_set1_ps(k), _mm_setr_ps(phi(0), phi(1), phi(2), 0.f));
  const __m128 v2 = _mm_add_ps(v, v);
  const __m128 sq = _mm_mul_ps(v2, v);                                                     // xx yy zz
  const __m128 wv = _mm_mul_ps(v2, _mm_set1_ps(w));                                        // wx wy wz
  const __m128 off = _mm_mul_ps(v2, _mm_shuffle_ps(v, v, _MM_SHUFFLE(3, 0, 2, 1)));       // xy yz zx
  const __m128 w_zxy = _mm_shuffle_ps(wv, wv, _MM_SHUFFLE(3, 1, 0, 2));                    // wz wx wy
  const __m128 sum = _mm_add_ps(_mm_shuffle_ps(sq, sq, _MM_SHUFFLE(3, 0, 2, 1)),           // yy zz xx
                                _mm_shuffle_ps(sq, sq, _MM_SHUFFLE(3, 1, 0, 2)));          // zz xx yy
  const __m128 diag = _mm_sub_ps(_mm_set1_ps(1.f), sum);                                   // C00 C11 C22
  const __m128 plus = _mm_add_ps(off, w_zxy);                                              // C10 C21 C02
  const __m128 minus = _mm_sub_ps(off, w_zxy);                                             // C01 C12 C20
  // Column-major storage: C00 C10 C20 C01 | C11 C21 C02 C12 | C22.
  const __m128 dp = _mm_unpacklo_ps(diag, plus);                                           // C00 C10 C11 C21
  const __m128 first = _mm_movelh_ps(dp, _mm_shuffle_ps(minus, minus, _MM_SHUFFLE(0, 0, 0, 2)));
  const __m128 pm = _mm_shuffle_ps(plus, minus, _MM_SHUFFLE(1, 1, 2, 2));                  // C02 C02 C12 C12
  const __m128 second = _mm_shuffle_ps(dp, pm, _MM_SHUFFLE(2, 0, 3, 2));
  _mm_storeu_ps(C.data(), first);
  _mm_storeu_ps(C.data() + 4, second);
  C.data()[8] = _mm_cvtss_f32(_mm_shuffle_ps(diag, diag, _MM_SHUFFLE(2, 2, 2, 2)));
}
#endif

/// Rodrigues' C = I + A φ^ + B φ^φ^ = B φφᵀ + (1 − Bθ²) I + A φ^ (exp: A = sinθ/θ,
/// B = (1 − cosθ)/θ², x = θ²), entry by entry, packet-friendly like matrixFromHalfAngle. The
/// diagonal B φ_i² + (1 − B x) adds cosθ to a square: beyond the quarter turn that rounds
/// better than 1 − B(φ_j² + φ_k²), which cancels towards cosθ ≈ −1 at the half turn.
/// Written into `C`.
template <class Scalar>
LIESERVO_ALWAYS_INLINE void matrixFromRodrigues(const Eigen::Matrix<Scalar, 3, 1>& phi, const Scalar& x, const Scalar& A,
                                const Scalar& B, Eigen::Matrix<Scalar, 3, 3>& C) {
  const Eigen::Matrix<Scalar, 3, 1> b = B * phi, a = A * phi;
  const Scalar c = Scalar(1) - B * x;
  const Scalar xy = b(0) * phi(1), yz = b(1) * phi(2), xz = b(2) * phi(0);  // the packets' order
  C(0, 0) = b(0) * phi(0) + c;
  C(1, 0) = xy + a(2);
  C(2, 0) = xz - a(1);
  C(0, 1) = xy - a(2);
  C(1, 1) = b(1) * phi(1) + c;
  C(2, 1) = yz + a(0);
  C(0, 2) = xz + a(1);
  C(1, 2) = yz - a(0);
  C(2, 2) = b(2) * phi(2) + c;
}

#if defined(__SSE2__)
/// The same for float on SSE, packet by packet as matrixFromHalfAngle's: the same operations on
/// the same operands as the scalar form, so the same result bit for bit.
LIESERVO_ALWAYS_INLINE void matrixFromRodrigues(const Eigen::Matrix<float, 3, 1>& phi, const float& x, const float& A,
                                const float& B, Eigen::Matrix<float, 3, 3>& C) {
  const __m128 v = _mm_setr_ps(phi(0), phi(1), phi(2), 0.f);
  const __m128 vb = _mm_mul_ps(_mm_set1_ps(B), v);
  const __m128 sq = _mm_mul_ps(vb, v);                                                     // xx yy zz
  const __m128 wv = _mm_mul_ps(_mm_set1_ps(A), v);                                         // A φ
  const __m128 off = _mm_mul_ps(vb, _mm_shuffle_ps(v, v, _MM_SHUFFLE(3, 0, 2, 1)));       // xy yz zx
  const __m128 w_zxy = _mm_shuffle_ps(wv, wv, _MM_SHUFFLE(3, 1, 0, 2));
  const __m128 diag = _mm_add_ps(sq, _mm_set1_ps(1.f - B * x));
  const __m128 plus = _mm_add_ps(off, w_zxy);
  const __m128 minus = _mm_sub_ps(off, w_zxy);
  const __m128 dp = _mm_unpacklo_ps(diag, plus);
  const __m128 first = _mm_movelh_ps(dp, _mm_shuffle_ps(minus, minus, _MM_SHUFFLE(0, 0, 0, 2)));
  const __m128 pm = _mm_shuffle_ps(plus, minus, _MM_SHUFFLE(1, 1, 2, 2));
  const __m128 second = _mm_shuffle_ps(dp, pm, _MM_SHUFFLE(2, 0, 3, 2));
  _mm_storeu_ps(C.data(), first);
  _mm_storeu_ps(C.data() + 4, second);
  C.data()[8] = _mm_cvtss_f32(_mm_shuffle_ps(diag, diag, _MM_SHUFFLE(2, 2, 2, 2)));
}
#endif

/// Unit quaternion (w, x, y, z) of a rotation matrix by Shepperd's pivot: the largest of
/// {tr C, C00, C11, C22} selects which of 4w², 4x², 4y², 4z² is taken under the square root,
/// so the radicand is ≥ 1 for any orthonormal C and no component is recovered from a small,
/// cancelling difference. Works unchanged when rounding pushes the trace past 3 or −1.
/// Sign rule: w ≥ 0; when w == 0 exactly (θ = π) the vector part's largest-magnitude
/// component (the first such on ties) is made positive. The result is normalised.
template <class Scalar>
inline Eigen::Matrix<Scalar, 4, 1> quaternionFromMatrix(const Eigen::Matrix<Scalar, 3, 3>& C) {
  using std::sqrt;
  using Real = RealOf<Scalar>;
  const Scalar one(Real(1)), quarter(Real(0.25)), two(Real(2));
  const Scalar t = C(0, 0) + C(1, 1) + C(2, 2);
  Scalar w, x, y, z;
  if (t >= C(0, 0) && t >= C(1, 1) && t >= C(2, 2)) {
    const Scalar s = two * sqrt(one + t);  // s = 4w
    w = quarter * s;
    x = quotient(C(2, 1) - C(1, 2), s);
    y = quotient(C(0, 2) - C(2, 0), s);
    z = quotient(C(1, 0) - C(0, 1), s);
  } else if (C(0, 0) >= C(1, 1) && C(0, 0) >= C(2, 2)) {
    const Scalar s = two * sqrt(one + C(0, 0) - C(1, 1) - C(2, 2));  // s = 4x
    w = quotient(C(2, 1) - C(1, 2), s);
    x = quarter * s;
    y = quotient(C(0, 1) + C(1, 0), s);
    z = quotient(C(0, 2) + C(2, 0), s);
  } else if (C(1, 1) >= C(2, 2)) {
    const Scalar s = two * sqrt(one + C(1, 1) - C(0, 0) - C(2, 2));  // s = 4y
    w = quotient(C(0, 2) - C(2, 0), s);
    x = quotient(C(0, 1) + C(1, 0), s);
    y = quarter * s;
    z = quotient(C(1, 2) + C(2, 1), s);
  } else {
    const Scalar s = two * sqrt(one + C(2, 2) - C(0, 0) - C(1, 1));  // s = 4z
    w = quotient(C(1, 0) - C(0, 1), s);
    x = quotient(C(0, 2) + C(2, 0), s);
    y = quotient(C(1, 2) + C(2, 1), s);
    z = quarter * s;
  }
  Eigen::Matrix<Scalar, 4, 1> q(w, x, y, z);
  const Scalar n = norm(q);
  for (int i = 0; i < 4; ++i) q(i) = quotient(q(i), n);
  if (q(0) < Scalar(0)) {
    q = -q;
  } else if (q(0) == Scalar(0)) {
    using std::abs;
    int k = 1;
    for (int i = 2; i < 4; ++i)
      if (abs(q(i)) > abs(q(k))) k = i;
    if (q(k) < Scalar(0)) q = -q;
  }
  return q;
}

/// θ = atan2(|s|, c) ∈ [0, π] for s = k sinθ·a and c = k cosθ (any k > 0, unit axis a), with
/// n = |s| and factor = θ/n, so that θ·a = factor·s. Near θ = 0 the factor uses the series of
/// atan(y)/y in y² = n²/c² (no 0/0); elsewhere an arctangent is accurate for every θ (no acos,
/// so no NaN when rounding pushes a cosine past ±1). The arctangent is atan of the smaller over
/// the larger of n and |c| (θ ≤ π/4: atan(n/c); beyond: π/2 − atan(c/n), both divisions by n
/// through one reciprocal, and the series again where c/n is small): glibc's atan is about 3×
/// faster than its atan2 (14 against 40 ns here), which was the largest single cost of log().
/// With WithAngle false only `factor` is formed (on the series path n and θ are not needed for
/// the rotation vector: no square root). Shared by both logarithm paths below.
template <class Scalar, bool WithAngle = true>
struct AngleFromSinCos {
  Scalar n, theta, factor;
  LIESERVO_ALWAYS_INLINE AngleFromSinCos(const Scalar& n2, const Scalar& c) {
    using std::atan;
    using std::sqrt;
    if (c > Scalar(0) && n2 < Scalar(Cutoffs<Scalar>::Atan) * c * c) {
      const Scalar inv_c = Scalar(RealOf<Scalar>(1)) / c;
      factor = hornerEval(kSeriesAtan, n2 * (inv_c * inv_c)) * inv_c;
      if (WithAngle) {
        // An autodiff scalar at the identity exactly: √0 has no derivative, and n, θ have none
        // to give (only θ² enters the series terms there, and its derivative is 0).
        if constexpr (!std::is_floating_point<Scalar>::value)
          n = n2 > Scalar(0) ? Scalar(sqrt(n2)) : Scalar(0);
        else
          n = sqrt(n2);
        theta = factor * n;
      }
      return;
    }
    n = sqrt(n2);
    if (c >= n) {
      theta = atan(quotient(n, c));
      factor = quotient(theta, n);
      return;
    }
    const Scalar inv_n = Scalar(RealOf<Scalar>(1)) / n, z = c * inv_n;
    const Scalar z2 = z * z;
    // Small z (the half angle near π/2, i.e. θ near π in the quaternion's form): atan(z) by the
    // same series and cutoff as the branch above, no atan call.
    const Scalar atan_z = z2 < Scalar(Cutoffs<Scalar>::Atan) ? z * hornerEval(kSeriesAtan, z2) : atan(z);
    theta = Scalar(pi<RealOf<Scalar>>() / RealOf<Scalar>(2)) - atan_z;
    factor = theta * inv_n;
  }
};

/// Rotation vector of a unit quaternion (w, v) with w ≥ 0: φ = 2 atan2(|v|, w) v/|v|,
/// θ = |φ| ∈ [0, π] (v = sin(θ/2)·axis, w = cos(θ/2)). With `terms`, also the AngleTerms of θ
/// from the same half-angle sine and cosine.
template <class Scalar>
inline Eigen::Matrix<Scalar, 3, 1> rotationVectorFromQuaternion(const Eigen::Matrix<Scalar, 4, 1>& q,
                                                                 AngleTerms<Scalar>* terms = nullptr) {
  using Real = RealOf<Scalar>;
  const Scalar two(Real(2));
  const AngleFromSinCos<Scalar> half(squaredNorm(Eigen::Matrix<Scalar, 3, 1>(q.template tail<3>())), q(0));
  if (terms) *terms = AngleTerms<Scalar>::fromHalfAngle(two * half.theta, half.n, q(0));
  return (two * half.factor) * q.template tail<3>();
}

/// log(C)^∨ for tr C ≤ 0 (θ ≥ 2π/3), from Shepperd's quaternion left unnormalised. Row i of
/// the symmetric 4×4 matrix of Bar-Itzhack's method is 4 q_i (w, x, y, z): (C_kj − C_jk,
/// 1 + C_ii − C_jj − C_kk at i, C_ij + C_ji at j, C_ik + C_ki at k) for (i, j, k) cyclic. The
/// row of the largest diagonal entry (the pivot of quaternionFromMatrix; for tr C ≤ 0 the trace
/// never is) has its own entry ≥ 1. No square root and no division (the angle step is
/// scale-invariant). Each component is selected from the three rows by value, and w's sign
/// moves to v by copysign, so that a random axis costs no mispredicted branch (a table of rows
/// indexed by the pivot would stall: the loads wait on the stores). Q_w = 0 exactly (θ = π)
/// takes quaternionFromMatrix for its sign rule.
template <class Scalar>
inline Eigen::Matrix<Scalar, 3, 1> rotationVectorNearPi(const Eigen::Matrix<Scalar, 3, 3>& C,
                                                        AngleTerms<Scalar>* terms) {
  using std::abs;
  using std::copysign;
  using std::sqrt;
  using Real = RealOf<Scalar>;
  const Scalar one(Real(1));
  const bool y = C(1, 1) > C(0, 0);
  const bool z = C(2, 2) > (y ? C(1, 1) : C(0, 0));  // ties keep the first, as Shepperd's pivot
  const Scalar s01 = C(0, 1) + C(1, 0), s02 = C(0, 2) + C(2, 0), s12 = C(1, 2) + C(2, 1);
  const Scalar qw = z ? C(1, 0) - C(0, 1) : y ? C(0, 2) - C(2, 0) : C(2, 1) - C(1, 2);
  if (qw == Scalar(0)) return rotationVectorFromQuaternion(quaternionFromMatrix(C), terms);
  const Scalar qx = z ? s02 : y ? s01 : one + C(0, 0) - C(1, 1) - C(2, 2);
  const Scalar qy = z ? s12 : y ? one - C(0, 0) + C(1, 1) - C(2, 2) : s01;
  const Scalar qz = z ? one - C(0, 0) - C(1, 1) + C(2, 2) : y ? s12 : s02;
  const Scalar sign = copysign(one, qw);  // w ≥ 0: its sign goes to v
  const Eigen::Matrix<Scalar, 3, 1> v(sign * qx, sign * qy, sign * qz);
  const Scalar w = abs(qw);
  const Scalar n2 = squaredNorm(v);
  if (!terms) return (Scalar(Real(2)) * AngleFromSinCos<Scalar, false>(n2, w).factor) * v;
  const AngleFromSinCos<Scalar> half(n2, w);
  const Scalar inv = one / sqrt(n2 + w * w);
  *terms = AngleTerms<Scalar>::fromHalfAngle(Scalar(Real(2)) * half.theta, half.n * inv, w * inv);
  return (Scalar(Real(2)) * half.factor) * v;
}

/// log(C)^∨ of a rotation matrix, θ ∈ [0, π]. For tr C > 0 (θ < 2π/3) the antisymmetric part
/// gives s = 2 sinθ·axis and the trace c = 1 + 2 cosθ − 1 = 2 cosθ directly: the axis error is
/// ~ε/sinθ ≤ 1.2ε there, and this costs one sqrt and one atan2. Towards π sinθ → 0 and s is all
/// rounding, so the axis comes from Shepperd's quaternion instead (rotationVectorNearPi).
/// With `terms`, also the AngleTerms of θ from the same sine and cosine (no sin/cos call:
/// log and J⁻¹ share the trigonometric work).
// Always inlined: in a translation unit with many call sites GCC otherwise keeps it (and the
// angle step above) out of line, and the calls cost a fifth of a controller step. The rarer
// branch near π stays a call.
template <class Scalar>
LIESERVO_ALWAYS_INLINE Eigen::Matrix<Scalar, 3, 1> rotationVectorFromMatrix(const Eigen::Matrix<Scalar, 3, 3>& C,
                                                            AngleTerms<Scalar>* terms = nullptr) {
  using Real = RealOf<Scalar>;
  const Scalar t = C(0, 0) + C(1, 1) + C(2, 2);
  if (t > Scalar(0)) {
    const Eigen::Matrix<Scalar, 3, 1> s(C(2, 1) - C(1, 2), C(0, 2) - C(2, 0), C(1, 0) - C(0, 1));
    const Scalar c = t - Scalar(Real(1));
    // Near the identity θ/|s| is a two-term series in |s|² (kSeriesHalfAsin): no division and
    // no arctangent. Only where its cutoff covers the small angles that occur (θ up to 0.01
    // rad and beyond: float, θ < 0.035 rad); in double it would stop at θ ≈ 2.3e-4 and split a
    // set of small angles between two branches, so double keeps the arctangent's series.
    if constexpr (Real(Cutoffs<Scalar>::HalfAsin) >= Real(4e-4)) {
      const Scalar n2 = squaredNorm(s);
      if (n2 < Scalar(Cutoffs<Scalar>::HalfAsin)) {
        const Scalar factor = hornerEval(kSeriesHalfAsin, n2);
        if (terms) {
          using std::sqrt;
          const Scalar n = sqrt(n2), half(Real(0.5));
          *terms = AngleTerms<Scalar>::fromSinCos(factor * n, half * n, half * c);
        }
        return factor * s;
      }
    }
    if (!terms) return AngleFromSinCos<Scalar, false>(squaredNorm(s), c).factor * s;
    const AngleFromSinCos<Scalar> a(squaredNorm(s), c);
    const Scalar half(Real(0.5));
    *terms = AngleTerms<Scalar>::fromSinCos(a.theta, half * a.n, half * c);
    return a.factor * s;
  }
  return rotationVectorNearPi(C, terms);
}

}  // namespace detail
}  // namespace lieservo

#include <lieservo/detail/options_pop.hpp>

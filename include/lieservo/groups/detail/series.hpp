// lieservo/groups/detail/series.hpp — power-series helpers shared by the groups.
//
// Why: every closed-form coefficient of the rotation groups (sinθ/θ, (1−cosθ)/θ², …) is a
// ratio whose numerator and denominator both vanish at θ = 0; near zero the closed form
// either divides by zero or cancels catastrophically. Each coefficient therefore carries
// its own truncated Taylor series in x = θ² and its own cutoff, derived from the scalar's
// machine epsilon: with the series a0 + a1 x + … + a_{K−1} x^{K−1} the first omitted term
// is a_K x^K, and we use the series while |a_K| x^K < eps·|a0|, i.e. while
//     x < x_cut = (eps · |a0 / a_K|)^(1/K).
// The number of terms K of each coefficient is chosen (see docs/math.md) so that x_cut lies
// beyond the region where the closed form loses accuracy through cancellation.
#pragma once
#include <lieservo/detail/options_push.hpp>

#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <type_traits>
#include <utility>

#include <Eigen/Core>

#include <lieservo/detail/flatten.hpp>

namespace lieservo {
namespace detail {

/// The floating-point type behind a scalar: the scalar itself for float, double and long double;
/// for an autodiff scalar the real type of its value (ceres::Jet<double, N>: double), whose
/// epsilon sets the series' cut-offs. Ceres's NumTraits name the Jet itself as its Real, so the
/// Jet is unwrapped here (a declaration of the template, not an include: the core needs no Ceres).
// value(x): the real part (a table index is computed from it, not from the scalar).
template <class Scalar, class = void>
struct RealOfImpl {
  using type = typename Eigen::NumTraits<Scalar>::Real;
  static type value(const Scalar& x) { return static_cast<type>(x); }
};
template <class Scalar>
struct RealOfImpl<Scalar, std::enable_if_t<std::is_floating_point<Scalar>::value>> {
  using type = Scalar;
  static constexpr type value(const Scalar& x) noexcept { return x; }
};
}  // namespace detail
}  // namespace lieservo
namespace ceres {
template <typename T, int N>
struct Jet;
}  // namespace ceres
namespace lieservo {
namespace detail {
template <class T, int N>
struct RealOfImpl<ceres::Jet<T, N>, void> {
  using type = typename RealOfImpl<T>::type;
  static type value(const ceres::Jet<T, N>& x) { return RealOfImpl<T>::value(x.a); }
};
template <class Scalar>
using RealOf = typename RealOfImpl<Scalar>::type;
/// The real part of a scalar (itself for float and double, the value of an autodiff scalar).
template <class Scalar>
RealOf<Scalar> realValue(const Scalar& x) {
  return RealOfImpl<Scalar>::value(x);
}

/// Machine epsilon of the scalar's real type, as long double (cutoffs are computed in long
/// double at compile time).
template <class Scalar>
constexpr long double epsilonOf() noexcept {
  return static_cast<long double>(std::numeric_limits<RealOf<Scalar>>::epsilon());
}

/// y^(1/K) for y > 0 by bisection (constexpr: the cutoffs are compile-time constants, so a
/// coefficient's branch test is a comparison with an immediate).
constexpr long double constexprRoot(long double y, std::size_t K) noexcept {
  long double lo = 0.0L, hi = y > 1.0L ? y : 1.0L;
  for (int it = 0; it < 200; ++it) {
    const long double mid = 0.5L * (lo + hi);
    long double p = 1.0L;
    for (std::size_t k = 0; k < K; ++k) p *= mid;
    (p < y ? lo : hi) = mid;
  }
  return 0.5L * (lo + hi);
}

/// A truncated series in x = θ²: coefficients a[0..K−1] used, a[K] is the first omitted one.
/// The tables are long double so that float, double and long double all round once.
template <std::size_t K>
struct SeriesTable {
  long double a[K + 1];
  /// x_cut = (eps · |a0/a_K|)^(1/K): below it the omitted tail is under eps relative to a0.
  constexpr long double cutoff(long double eps) const noexcept {
    const long double ratio = a[0] / a[K] < 0 ? -(a[0] / a[K]) : a[0] / a[K];
    return constexprRoot(eps * ratio, K);
  }
};

/// Horner evaluation of the first K terms of a series in x.
template <class Scalar, std::size_t K>
inline Scalar hornerEval(const SeriesTable<K>& s, const Scalar& x) {
  using Real = RealOf<Scalar>;
  Scalar r = Scalar(Real(s.a[K - 1]));
  for (std::size_t k = K - 1; k-- > 0;) r = Scalar(Real(s.a[k])) + x * r;
  return r;
}

/// Estrin's scheme on packets q_0 … q_{N−1} in y: pairs q_{2i} + y q_{2i+1} (an odd last one
/// carried over), then the same in y², until one is left. Written as compile-time recursion,
/// not as loops: GCC keeps such loops, and the packets in memory, in some files even under
/// `#pragma GCC unroll` (SO3 exp over [0, π) 24 against 15 ns in the peer benchmark).
template <std::size_t I, class Lanes, class Scalar, std::size_t N>
LIESERVO_ALWAYS_INLINE Lanes estrinPair(const std::array<Lanes, N>& q, const Scalar& y) {
  if constexpr (2 * I + 1 < N) {
    return q[2 * I] + y * q[2 * I + 1];
  } else {
    return q[2 * I];
  }
}
template <class Lanes, class Scalar, std::size_t N, std::size_t... I>
LIESERVO_ALWAYS_INLINE Lanes estrinReduce(const std::array<Lanes, N>& q, const Scalar& y, std::index_sequence<I...>) {
  if constexpr (N == 1) {
    return q[0];
  } else {
    const std::array<Lanes, sizeof...(I)> next{{estrinPair<I>(q, y)...}};
    const Scalar y2 = y * y;
    return estrinReduce(next, y2, std::make_index_sequence<(sizeof...(I) + 1) / 2>{});
  }
}

/// {f(First), f(First + 1), …}.
template <class Lanes, int First, class F, std::size_t... I>
LIESERVO_ALWAYS_INLINE std::array<Lanes, sizeof...(I)> lanesFrom(const F& f, std::index_sequence<I...>) {
  return {{f(First + int(I))...}};
}

/// Several series in the same x, one per lane, evaluated together: one SIMD packet per step
/// for float (4 lanes) and double (2 lanes). a0 + x(a1 + x·E(x)), with the tail E by Estrin's
/// scheme (pairs a_i + x a_{i+1}, then x², x⁴, …): the two Horner steps at the bottom keep the
/// rounding of a Horner evaluation (they dominate it), the Estrin tail shortens the chain of
/// dependent multiply-adds. K ≥ 3 terms, lanes side by side in a[k][0..L−1].
template <class Scalar, int K, int L>
LIESERVO_ALWAYS_INLINE Eigen::Array<Scalar, L, 1> lanesEval(const RealOf<Scalar> (&a)[K][L], const Scalar& x) {
  static_assert(K >= 3, "lanesEval needs at least three terms");
  using Lanes = Eigen::Array<Scalar, L, 1>;
  const auto term = [&a](int k) -> Lanes {
    return Eigen::Map<const Eigen::Array<RealOf<Scalar>, L, 1>>(a[k]).template cast<Scalar>();
  };
  // The tail a_2 … a_{K−1} as packets, then reduced in x.
  const std::array<Lanes, K - 2> tail = lanesFrom<Lanes, 2>(term, std::make_index_sequence<K - 2>{});
  const Lanes e = estrinReduce(tail, x, std::make_index_sequence<(K - 1) / 2>{});
  return term(0) + x * (term(1) + x * e);
}

/// B_n / n! (Bernoulli numbers with B_1 = −1/2), from the generating function x/(eˣ−1):
/// Σ_{k=0}^{n} b_k / (n+1−k)! = 0 for n ≥ 1, b_0 = 1. Exact enough in long double for n ≤ 60.
/// constexpr, so that the series' coefficients are compile-time constants (BernoulliTable).
constexpr long double bernoulliOverFactorial(int n) noexcept {
  if (n < 0) return 0.0L;
  if (n == 0) return 1.0L;
  if (n == 1) return -0.5L;
  if (n % 2 == 1) return 0.0L;  // B_{2k+1} = 0 for k ≥ 1
  // b_j = −Σ_{k=0}^{j−1} b_k / (j+1−k)!
  long double b[64] = {};
  const int m = n < 63 ? n : 63;
  b[0] = 1.0L;
  for (int j = 1; j <= m; ++j) {
    long double sum = 0.0L;
    long double fact = 2.0L;  // (j+1−k)! for k = j−1, then 3!, 4!, … as k decreases
    for (int k = j - 1; k >= 0; --k) {
      sum += b[k] / fact;
      fact *= static_cast<long double>(j + 1 - k + 1);
    }
    b[j] = -sum;
  }
  return b[m];
}

/// B_n/n! for n = 0..N as compile-time constants (the inverse-Jacobian series' coefficients).
template <int N>
struct BernoulliTable {
  long double b[N + 1] = {};
  constexpr BernoulliTable() noexcept {
    for (int n = 0; n <= N; ++n) b[n] = bernoulliOverFactorial(n);
  }
};

}  // namespace detail
}  // namespace lieservo

#include <lieservo/detail/options_pop.hpp>

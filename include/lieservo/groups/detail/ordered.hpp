// lieservo/groups/detail/ordered.hpp — arithmetic that rounds the same way for every scalar.
//
// Why: the groups are templates on the scalar, and an autodiff scalar (ceres::Jet<double, N>)
// carries a value that should be the double result bit for bit (docs/conventions.md,
// "Autodiff scalars"). Two things round differently when left to the libraries:
//   - Eigen vectorises double products and reductions (packets, summed in their own order) but
//     not those of a Jet, which it sums as a scalar tree: a 3 × 3 product or a dot product of
//     3-vectors rounds differently;
//   - ceres::Jet forms a quotient's value as f · (1/g), two roundings where f / g is one.
// The helpers below fix one order: every sum left to right (dot products, squared norms, each
// entry of a matrix–vector product), and a quotient whose value rounds once. For float and
// double they are the same operations as Eigen's, in a fixed order, or the division itself;
// float's dot products keep Eigen's own order (see dot).
#pragma once
#include <lieservo/detail/options_push.hpp>

#include <cmath>
#include <type_traits>

#include <Eigen/Core>

#include <lieservo/detail/flatten.hpp>
#include <lieservo/groups/detail/series.hpp>

namespace lieservo {
namespace detail {

/// a / b rounded once for every scalar. For float and double the division itself. For an
/// autodiff scalar, its own quotient (whose derivative it keeps) with the value moved to the
/// once-rounded realValue(a) / realValue(b): the two differ by an ulp or so, so their
/// difference is exact (Sterbenz) and adding it gives that quotient exactly.
template <class Scalar>
LIESERVO_ALWAYS_INLINE Scalar quotient(const Scalar& a, const Scalar& b) {
  if constexpr (std::is_floating_point<Scalar>::value) {
    return a / b;
  } else {
    const Scalar q = a / b;
    const auto d = realValue(a) / realValue(b) - realValue(q);
    using std::isfinite;
    return isfinite(d) ? Scalar(q + Scalar(d)) : q;
  }
}

/// Σ_i a_i b_i, summed left to right (as Eigen's vectorised double reduction of a 3-vector). Float
/// keeps Eigen's own order (a_0 b_0 + (a_1 b_1 + a_2 b_2) for 3-vectors): no autodiff scalar is
/// compared with it, and its accuracy tests were measured with that order.
template <class Scalar, int N>
LIESERVO_ALWAYS_INLINE Scalar dot(const Eigen::Matrix<Scalar, N, 1>& a, const Eigen::Matrix<Scalar, N, 1>& b) {
  if constexpr (std::is_same<Scalar, float>::value) {
    return a.dot(b);
  } else {
    Scalar s = a(0) * b(0);
    for (int i = 1; i < N; ++i) s += a(i) * b(i);
    return s;
  }
}

/// Σ_i a_i², as dot(a, a).
template <class Scalar, int N>
LIESERVO_ALWAYS_INLINE Scalar squaredNorm(const Eigen::Matrix<Scalar, N, 1>& a) {
  return dot(a, a);
}

/// ‖a‖ = √(Σ_i a_i²).
template <class Scalar, int N>
LIESERVO_ALWAYS_INLINE Scalar norm(const Eigen::Matrix<Scalar, N, 1>& a) {
  using std::sqrt;
  return sqrt(squaredNorm(a));
}

/// A v with each entry summed left to right: out_i = Σ_k A_ik v_k. Written entry by entry, not as
/// Eigen's column combination A.col(k) v_k, which sums in the same order but is not inlined into
/// straight-line code for float 3-vectors (SE3f act took 8.3 against 1.9 ns).
template <class Scalar, int R, int C>
LIESERVO_ALWAYS_INLINE Eigen::Matrix<Scalar, R, 1> times(const Eigen::Matrix<Scalar, R, C>& A,
                                                         const Eigen::Matrix<Scalar, C, 1>& v) {
  Scalar s[R];  // every entry before the first store: the result may be where A or v was
  for (int i = 0; i < R; ++i) {
    s[i] = A(i, 0) * v(0);
    for (int k = 1; k < C; ++k) s[i] += A(i, k) * v(k);
  }
  Eigen::Matrix<Scalar, R, 1> out;
  for (int i = 0; i < R; ++i) out(i) = s[i];
  return out;
}

/// Aᵀ v: entry j is dot(A.col(j), v).
template <class Scalar, int R, int C>
LIESERVO_ALWAYS_INLINE Eigen::Matrix<Scalar, C, 1> transposeTimes(const Eigen::Matrix<Scalar, R, C>& A,
                                                                  const Eigen::Matrix<Scalar, R, 1>& v) {
  Eigen::Matrix<Scalar, C, 1> out;
  for (int j = 0; j < C; ++j) out(j) = dot(Eigen::Matrix<Scalar, R, 1>(A.col(j)), v);
  return out;
}

}  // namespace detail
}  // namespace lieservo

#include <lieservo/detail/options_pop.hpp>

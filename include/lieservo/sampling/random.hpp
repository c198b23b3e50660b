// lieservo/sampling/random.hpp — the one place random numbers come from: a seeded generator and
// uniform and normal draws built from its raw bits.
//
// Why not std::uniform_real_distribution / std::normal_distribution: the standard fixes the
// generators bit for bit but not the distributions, so libstdc++ and libc++ turn the same seed
// into different numbers. Everything here is computed from the generator's raw output, so a
// seed gives the same uniform draws on every platform and the same normal draws up to the
// rounding of std::log and std::cos. Used by simulations, tests, benchmarks and tutorials;
// nothing here is on the real-time path.
#pragma once
#include <lieservo/detail/options_push.hpp>

#include <lieservo/units.hpp>

#include <Eigen/Core>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <type_traits>

namespace lieservo::detail {
/// Number of significant bits of v (bitWidth(2^k − 1) = k).
constexpr int bitWidth(std::uint64_t v) {
  int n = 0;
  while (v != 0) {
    ++n;
    v >>= 1;
  }
  return n;
}
}  // namespace lieservo::detail

namespace lieservo::sampling {

/// The seeded generator used throughout: the 64-bit Mersenne Twister (fixed by the standard).
using Rng = std::mt19937_64;

/// A uniform draw in [0, 1) with std::numeric_limits<Scalar>::digits random bits, built from
/// the generator's raw output only. The generator's range max()−min() must be 2^k − 1 (true
/// for std::mt19937, std::mt19937_64, std::ranlux48_base, ...).
template <class Scalar, class URBG>
Scalar uniformCanonical(URBG& rng) {
  static_assert(std::is_floating_point_v<Scalar>, "Scalar must be a floating-point type");
  using R = typename URBG::result_type;
  static_assert(std::is_unsigned_v<R>, "URBG must produce unsigned integers");
  constexpr std::uint64_t range = static_cast<std::uint64_t>(URBG::max() - URBG::min());
  static_assert(range != 0 && (range & (range + 1)) == 0,
                "URBG range must be 2^k - 1 (e.g. std::mt19937_64)");
  constexpr int kbits = lieservo::detail::bitWidth(range);
  constexpr int need = std::numeric_limits<Scalar>::digits < 63 ? std::numeric_limits<Scalar>::digits : 63;
  std::uint64_t acc = 0;
  int have = 0;
  while (have < need) {
    std::uint64_t v = static_cast<std::uint64_t>(rng() - URBG::min());
    const int take = kbits < need - have ? kbits : need - have;
    v >>= (kbits - take);  // keep the high bits
    acc = (acc << take) | v;
    have += take;
  }
  return static_cast<Scalar>(acc) * std::ldexp(Scalar(1), -need);
}

/// a + (b − a)·u, u uniform in [0, 1): the paper's 𝒰(a, b).
template <class Scalar, class URBG>
Scalar uniform(URBG& rng, Scalar a, Scalar b) {
  return a + (b - a) * uniformCanonical<Scalar>(rng);
}

/// A standard normal draw, N(0, 1), by the Box–Muller transform of two uniform draws:
/// z = √(−2 ln(1 − u₁)) cos(2π u₂). Computed in double (1 − u₁ ∈ (0, 1], so the log is finite;
/// |z| < 8.6) and rounded to Scalar. Each call uses two draws and keeps no state.
template <class Scalar = double, class URBG>
Scalar standardNormal(URBG& rng) {
  const double u1 = uniformCanonical<double>(rng);
  const double u2 = uniformCanonical<double>(rng);
  return static_cast<Scalar>(std::sqrt(-2.0 * std::log(1.0 - u1)) * std::cos(2.0 * pi<double>() * u2));
}

/// An N-vector of independent 𝒰(a, b) draws.
template <int N, class Scalar = double, class URBG>
Eigen::Matrix<Scalar, N, 1> uniformVector(URBG& rng, Scalar a, Scalar b) {
  Eigen::Matrix<Scalar, N, 1> v;
  for (int i = 0; i < N; ++i) v[i] = uniform<Scalar>(rng, a, b);
  return v;
}

/// An N-vector of independent N(0, 1) draws.
template <int N, class Scalar = double, class URBG>
Eigen::Matrix<Scalar, N, 1> standardNormalVector(URBG& rng) {
  Eigen::Matrix<Scalar, N, 1> z;
  for (int i = 0; i < N; ++i) z[i] = standardNormal<Scalar>(rng);
  return z;
}

/// Independent zero-mean normal draws with per-component standard deviations `sigma`.
template <class Derived, class URBG>
typename Derived::PlainObject normalVector(URBG& rng, const Eigen::MatrixBase<Derived>& sigma) {
  static_assert(Derived::ColsAtCompileTime == 1, "sigma must be a column vector");
  using Scalar = typename Derived::Scalar;
  typename Derived::PlainObject z(sigma.size());
  for (Eigen::Index i = 0; i < sigma.size(); ++i) z[i] = sigma[i] * standardNormal<Scalar>(rng);
  return z;
}

}  // namespace lieservo::sampling

#include <lieservo/detail/options_pop.hpp>

// Goodness-of-fit statistics for the sampling tests: Kolmogorov–Smirnov against U(0, 1) and
// Pearson's chi-square, with their p-values (asymptotic Kolmogorov distribution with
// Stephens' finite-n correction; Boost.Math's chi-square distribution, independent of the
// library's own chi_square.hpp).
#pragma once

#include <boost/math/distributions/chi_squared.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace lieservo::test {

/// sup |F_n − F| of the sample u against U(0, 1).
inline double ksStatisticUniform(std::vector<double> u) {
  std::sort(u.begin(), u.end());
  const double n = static_cast<double>(u.size());
  double d = 0;
  for (std::size_t i = 0; i < u.size(); ++i) {
    const double x = std::clamp(u[i], 0.0, 1.0);
    d = std::max({d, (static_cast<double>(i) + 1) / n - x, x - static_cast<double>(i) / n});
  }
  return d;
}

/// P(D_n ≥ d) under H0: Q_KS((√n + 0.12 + 0.11/√n)·d), Q_KS(λ) = 2 Σ (−1)^{k−1} e^{−2k²λ²}.
inline double ksPValue(double d, std::size_t n) {
  const double sn = std::sqrt(static_cast<double>(n));
  const double lambda = (sn + 0.12 + 0.11 / sn) * d;
  if (lambda < 0.2) return 1.0;
  double sum = 0, sign = 1;
  for (int k = 1; k <= 100; ++k) {
    const double term = std::exp(-2.0 * k * k * lambda * lambda);
    sum += sign * term;
    sign = -sign;
    if (term < 1e-16) break;
  }
  return std::clamp(2.0 * sum, 0.0, 1.0);
}

/// P(χ²_df ≥ x).
inline double chiSquarePValue(double x, int df) {
  if (!(x > 0)) return 1.0;
  return boost::math::cdf(boost::math::complement(boost::math::chi_squared_distribution<double>(df), x));
}

/// Pearson's statistic Σ (O − E)² / E for equal expected counts.
inline double chiSquareEqualCells(const std::vector<long>& counts) {
  double total = 0;
  for (long c : counts) total += static_cast<double>(c);
  const double e = total / static_cast<double>(counts.size());
  double x = 0;
  for (long c : counts) x += (static_cast<double>(c) - e) * (static_cast<double>(c) - e) / e;
  return x;
}

}  // namespace lieservo::test

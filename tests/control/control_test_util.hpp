// Helpers shared by the control tests (one executable; under a unity build its files are one
// translation unit, so a helper defined in two of them would clash).
#pragma once

#include <Eigen/Core>

#include <limits>

namespace lieservo::test {

inline constexpr double kInf = std::numeric_limits<double>::infinity();

/// A 6-vector from its components, ξ = [ρ; φ].
inline Eigen::Matrix<double, 6, 1> v6(double a, double b, double c, double d, double e, double f) {
  Eigen::Matrix<double, 6, 1> v;
  v << a, b, c, d, e, f;
  return v;
}

}  // namespace lieservo::test

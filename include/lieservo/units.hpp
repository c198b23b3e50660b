// lieservo/units.hpp — degree/radian helpers. The library works in radians; degrees appear
// only at the edges (dataset labels, presets, reports). Translation units are the caller's
// (the paper uses millimetres) and are never converted here.
#pragma once
#include <lieservo/detail/options_push.hpp>

#include <type_traits>

#include <Eigen/Core>

namespace lieservo {

/// π in the scalar's precision (from a long double literal, rounded once).
template <class Scalar>
constexpr Scalar pi() {
  return Scalar(3.141592653589793238462643383279502884L);
}

namespace detail {
/// Integer arguments (deg2rad(30)) compute in double.
template <class T>
using AngleScalar = std::conditional_t<std::is_integral<T>::value, double, T>;
}  // namespace detail

/// Degrees → radians.
template <class Scalar>
constexpr detail::AngleScalar<Scalar> deg2rad(Scalar deg) {
  using S = detail::AngleScalar<Scalar>;
  return S(deg) * (pi<S>() / S(180));
}

/// Radians → degrees.
template <class Scalar>
constexpr detail::AngleScalar<Scalar> rad2deg(Scalar rad) {
  using S = detail::AngleScalar<Scalar>;
  return S(rad) * (S(180) / pi<S>());
}

/// A pose/shear 6-vector (x, y, z, α, β, γ) with angles in degrees → angles in radians
/// (translation unchanged, e.g. mm stays mm).
template <class Scalar>
Eigen::Matrix<Scalar, 6, 1> poseDegToRad(const Eigen::Matrix<Scalar, 6, 1>& v) {
  Eigen::Matrix<Scalar, 6, 1> r = v;
  for (int i = 3; i < 6; ++i) r(i) = deg2rad(v(i));
  return r;
}

/// A pose/shear 6-vector (x, y, z, α, β, γ) with angles in radians → angles in degrees.
template <class Scalar>
Eigen::Matrix<Scalar, 6, 1> poseRadToDeg(const Eigen::Matrix<Scalar, 6, 1>& v) {
  Eigen::Matrix<Scalar, 6, 1> r = v;
  for (int i = 3; i < 6; ++i) r(i) = rad2deg(v(i));
  return r;
}

}  // namespace lieservo

#include <lieservo/detail/options_pop.hpp>

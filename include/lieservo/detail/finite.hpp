// lieservo/detail/finite.hpp — a fast "all entries finite?" test for fixed-size Eigen objects.
#pragma once

#include <Eigen/Core>

namespace lieservo {
namespace detail {

/// All entries finite? x − x is 0 for a finite x and NaN for ±inf or NaN, so the sum is 0 exactly
/// when every entry is finite. Unlike DenseBase::allFinite it is a vectorised, unrolled sum for
/// fixed sizes: the real-time paths check every input and output with it. (Like Eigen's own
/// test it assumes IEEE arithmetic: not valid under -ffast-math.)
template <class Derived>
bool allFinite(const Eigen::MatrixBase<Derived>& m) noexcept {
  using Scalar = typename Derived::Scalar;
  return (m - m).sum() == Scalar(0);
}

}  // namespace detail
}  // namespace lieservo

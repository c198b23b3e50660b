// lieservo/detail/finite.hpp — a fast "all entries finite?" test for fixed-size Eigen objects.
#pragma once
#include <lieservo/detail/options_push.hpp>

#include <Eigen/Core>

#include <lieservo/detail/flatten.hpp>

namespace lieservo {
namespace detail {

/// All entries finite? x − x is 0 for a finite x and NaN for ±inf or NaN, so the sum is 0 exactly
/// when every entry is finite. Unlike DenseBase::allFinite it is a vectorised, unrolled sum for
/// fixed sizes: the real-time paths check every input and output with it. Several objects of
/// the same size are checked with one reduction: allFinite(a, b, c). (Like Eigen's own test it
/// assumes IEEE arithmetic: not valid under -ffast-math.) Always inlined: as an out-of-line call
/// the multi-object form costs more than the reduction it saves.
template <class D0, class... Ds>
LIESERVO_ALWAYS_INLINE bool allFinite(const Eigen::MatrixBase<D0>& m0, const Eigen::MatrixBase<Ds>&... ms) noexcept {
  using Scalar = typename D0::Scalar;
  return ((m0 - m0) + ... + (ms - ms)).sum() == Scalar(0);
}

}  // namespace detail
}  // namespace lieservo

#include <lieservo/detail/options_pop.hpp>

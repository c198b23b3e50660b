// lieservo/groups/detail/rotation.hpp — 3-D rotation helpers: skew matrices, Shepperd's
// matrix→quaternion conversion, the quaternion logarithm and the Rodrigues formulas.
#pragma once

#include <cmath>

#include <Eigen/Core>

#include "coefficients.hpp"

namespace lieservo {
namespace detail {

/// φ^ : the skew-symmetric matrix with φ^ v = φ × v (eqn:so3_hat_operator).
template <class Scalar>
inline Eigen::Matrix<Scalar, 3, 3> skew(const Eigen::Matrix<Scalar, 3, 1>& p) {
  Eigen::Matrix<Scalar, 3, 3> m;
  const Scalar z(0);
  m << z, -p(2), p(1),  //
      p(2), z, -p(0),   //
      -p(1), p(0), z;
  return m;
}

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
    x = (C(2, 1) - C(1, 2)) / s;
    y = (C(0, 2) - C(2, 0)) / s;
    z = (C(1, 0) - C(0, 1)) / s;
  } else if (C(0, 0) >= C(1, 1) && C(0, 0) >= C(2, 2)) {
    const Scalar s = two * sqrt(one + C(0, 0) - C(1, 1) - C(2, 2));  // s = 4x
    w = (C(2, 1) - C(1, 2)) / s;
    x = quarter * s;
    y = (C(0, 1) + C(1, 0)) / s;
    z = (C(0, 2) + C(2, 0)) / s;
  } else if (C(1, 1) >= C(2, 2)) {
    const Scalar s = two * sqrt(one + C(1, 1) - C(0, 0) - C(2, 2));  // s = 4y
    w = (C(0, 2) - C(2, 0)) / s;
    x = (C(0, 1) + C(1, 0)) / s;
    y = quarter * s;
    z = (C(1, 2) + C(2, 1)) / s;
  } else {
    const Scalar s = two * sqrt(one + C(2, 2) - C(0, 0) - C(1, 1));  // s = 4z
    w = (C(1, 0) - C(0, 1)) / s;
    x = (C(0, 2) + C(2, 0)) / s;
    y = (C(1, 2) + C(2, 1)) / s;
    z = quarter * s;
  }
  Eigen::Matrix<Scalar, 4, 1> q(w, x, y, z);
  q /= q.norm();
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

/// Rotation vector of a unit quaternion (w, v) with w ≥ 0: φ = 2 atan2(|v|, w) v/|v|,
/// θ = |φ| ∈ [0, π]. Near the identity the factor 2 atan2(n, w)/n uses the series of
/// atan(y)/y in y² = n²/w² (no 0/0); near π (w → 0) atan2 stays fully accurate (no acos).
template <class Scalar>
inline Eigen::Matrix<Scalar, 3, 1> rotationVectorFromQuaternion(const Eigen::Matrix<Scalar, 4, 1>& q) {
  using std::atan2;
  using std::sqrt;
  using Real = RealOf<Scalar>;
  const Scalar w = q(0);
  const Eigen::Matrix<Scalar, 3, 1> v = q.template tail<3>();
  const Scalar n2 = v.squaredNorm();
  const Scalar two(Real(2));
  // Series branch: y² = n²/w² below its cutoff (w ≈ 1 there, so no division hazard).
  if (n2 < Scalar(Cutoffs<Scalar>::Atan) * w * w) {
    const Scalar y2 = n2 / (w * w);
    return (two / w * hornerEval(kSeriesAtan, y2)) * v;
  }
  const Scalar n = sqrt(n2);
  return (two * atan2(n, w) / n) * v;
}

}  // namespace detail
}  // namespace lieservo

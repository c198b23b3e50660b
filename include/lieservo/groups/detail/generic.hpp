// lieservo/groups/detail/generic.hpp — operations written once for every group G.
#pragma once
#include <lieservo/detail/options_push.hpp>

#include <cmath>
#include <cstdint>
#include <random>

#include <Eigen/Core>

#include <lieservo/groups/detail/series.hpp>
#include <lieservo/status.hpp>

namespace lieservo {
namespace detail {

/// A tolerance a caller may give the checked constructors: finite and >= 0 (x - x is 0 only for
/// a finite x; a negative tolerance would square to a positive one).
template <class Scalar>
bool validTolerance(Scalar tol) noexcept {
  return tol >= Scalar(0) && tol - tol == Scalar(0);
}

/// The rigid motion (SE(2) or SE(3)) of a homogeneous matrix M, the checks of both groups'
/// fromMatrix and fromMatrixProjected: non_finite_input; then the rotation block's status from
/// Rotation::fromMatrix at tol, or from Rotation::fromMatrixProjected when `projected`; then
/// invalid_argument unless the bottom row is (0, …, 0, 1) within tol. `out` is written only
/// when ok.
template <class Rigid, class Rotation>
Status rigidFromMatrix(const typename Rigid::Matrix& M, bool projected, typename Rigid::Scalar tol,
                       Rigid& out) noexcept {
  constexpr int n = Rigid::Dim;
  using Scalar = typename Rigid::Scalar;
  using std::abs;
  if (!M.allFinite()) return Status::non_finite_input;
  const typename Rotation::Matrix block = M.template topLeftCorner<n, n>();
  Rotation R;
  const Status s = projected ? Rotation::fromMatrixProjected(block, R) : Rotation::fromMatrix(block, R, tol);
  if (s != Status::ok) return s;
  for (int j = 0; j < n; ++j)
    if (!(abs(M(n, j)) <= tol)) return Status::invalid_argument;
  if (!(abs(M(n, n) - Scalar(1)) <= tol)) return Status::invalid_argument;
  out = Rigid(R, M.template topRightCorner<n, 1>());
  return Status::ok;
}

/// Truncated inverse-Jacobian series Σ_{n=0}^{N} (B_n/n!) (ξ⋏)^n (eq. 34, eqn:inv_jacobian_def),
/// evaluated by Horner's rule in ad(ξ). Converges for |θ| < 2π.
template <class G, int N>
inline typename G::Jacobian inverseJacobianSeries(const typename G::Tangent& xi) {
  static_assert(N >= 0, "series order must be >= 0");
  using Jacobian = typename G::Jacobian;
  using Scalar = typename G::Scalar;
  using Real = RealOf<Scalar>;
  constexpr BernoulliTable<N> c;
  const Jacobian ad = G::ad(xi);
  Jacobian r = Jacobian::Identity() * Scalar(Real(c.b[N]));
  for (int n = N - 1; n >= 0; --n) {
    Jacobian t = ad * r;
    t.diagonal().array() += Scalar(Real(c.b[n]));
    r = t;
  }
  return r;
}

/// A uniform double in [0, 1) from any URBG; std::generate_canonical's algorithm is fixed
/// by the standard, so a seeded engine gives the same samples on every platform.
template <class Rng>
inline double uniform01(Rng& rng) {
  double u = std::generate_canonical<double, 53>(rng);
  if (u >= 1.0) u = std::nextafter(1.0, 0.0);  // guard the known libstdc++ edge case
  return u;
}

/// Shoemake's uniformly distributed unit quaternion (w, x, y, z) from three uniforms.
template <class Rng>
inline Eigen::Vector4d uniformQuaternion(Rng& rng) {
  const double kTwoPi = 6.283185307179586476925286766559;
  const double u1 = uniform01(rng), u2 = uniform01(rng), u3 = uniform01(rng);
  const double a = std::sqrt(1.0 - u1), b = std::sqrt(u1);
  return Eigen::Vector4d(b * std::cos(kTwoPi * u3), a * std::sin(kTwoPi * u2),
                         a * std::cos(kTwoPi * u2), b * std::sin(kTwoPi * u3));
}

}  // namespace detail
}  // namespace lieservo

#include <lieservo/detail/options_pop.hpp>

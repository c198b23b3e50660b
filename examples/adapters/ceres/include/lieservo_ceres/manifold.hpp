// lieservo_ceres/manifold.hpp — the groups as Ceres manifolds (ceres::Manifold, Ceres ≥ 2.1), with
// the library's left perturbation: Plus(x, δ) = exp(δ^) X and Minus(y, x) = ln(Y X⁻¹)^∨
// (docs/conventions.md), Jacobians in closed form.
//
// Ambient parameters (what a Ceres parameter block holds):
//   SO(2)  [cos θ, sin θ]                 SE(2)  [cos θ, sin θ, t_x, t_y]
//   SO(3)  [w, x, y, z] (unit quaternion)  SE(3)  [w, x, y, z, t_x, t_y, t_z]
// Tangents as everywhere in lieservo: translation first, ξ = [ρ; φ]. The unit complex number or
// quaternion is normalised on the way in, so Minus's Jacobian has no radial component.
//
//   ceres::Problem problem;
//   double pose[7] = {1, 0, 0, 0, 0, 0, 0};
//   problem.AddParameterBlock(pose, 7, new lieservo::ceres_adapter::SE3Manifold);
//
// Not part of the core: the core includes no Ceres header (this is the optional lieservo::ceres
// target, built when Ceres is found).
#pragma once

#include <type_traits>

#include <ceres/manifold.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <lieservo/groups.hpp>

namespace lieservo::ceres_adapter {

/// How a group's element sits in its ambient parameters: Plus and Minus on any scalar T (double,
/// or ceres::Jet to check the closed forms), and the closed-form Jacobians of Plus and Minus at
/// δ = 0 (y = x), row-major as Ceres stores them. One specialisation per group.
template <class G>
struct AmbientOf;

namespace detail {
// A tangent into the parameter array.
template <class V, class T>
void store(const V& v, T* out) {
  for (int i = 0; i < v.size(); ++i) out[i] = v[i];
}
template <class T>
Eigen::Matrix<T, 2, 1> unitComplex(const T* a) {
  using std::sqrt;
  const T n = sqrt(a[0] * a[0] + a[1] * a[1]);
  return Eigen::Matrix<T, 2, 1>(a[0] / n, a[1] / n);
}
template <class T>
Eigen::Quaternion<T> unitQuaternion(const T* a) {
  using std::sqrt;
  const T n = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2] + a[3] * a[3]);
  return Eigen::Quaternion<T>(a[0] / n, a[1] / n, a[2] / n, a[3] / n);
}
// q_δ ⊗ q: the product keeps the block's sign (a recomputed quaternion could come back as −q).
template <class T>
void leftProduct(const Eigen::Matrix<T, 3, 1>& phi, const T* q, T* out) {
  const Eigen::Quaternion<T> r = SO3<T>::exp(phi).unitQuaternion() * Eigen::Quaternion<T>(q[0], q[1], q[2], q[3]);
  out[0] = r.w();
  out[1] = r.x();
  out[2] = r.y();
  out[3] = r.z();
}
// Q(q): d(q_δ ⊗ q)/dδ = ½ Q for q_δ = (1, δ/2), rows (w, x, y, z); orthonormal columns ⟂ q.
inline Eigen::Matrix<double, 4, 3> quaternionTangent(const double* a) {
  const Eigen::Quaterniond q = unitQuaternion(a);
  const double w = q.w(), x = q.x(), y = q.y(), z = q.z();
  Eigen::Matrix<double, 4, 3> Q;
  Q << -x, -y, -z, w, z, -y, -z, w, x, y, -x, w;
  return Q;
}
}  // namespace detail

template <>
struct AmbientOf<SO2<double>> {
  static constexpr int kSize = 2;
  template <class T>
  static SO2<T> read(const T* a) {
    const Eigen::Matrix<T, 2, 1> cs = detail::unitComplex(a);
    return SO2<T>::fromCosSinUnchecked(cs[0], cs[1]);
  }
  // exp(δ) X with X as stored: exp(0) X is X bit for bit.
  template <class T>
  static void plus(const T* x, const T* delta, T* out) {
    const SO2<T> Y = SO2<T>::exp(Eigen::Matrix<T, 1, 1>(delta[0])) * SO2<T>::fromCosSinUnchecked(x[0], x[1]);
    out[0] = Y.complex()[0];
    out[1] = Y.complex()[1];
  }
  template <class T>
  static void minus(const T* y, const T* x, T* out) {
    detail::store(lminus(read(y), read(x)), out);
  }
  // d(c, s)/dθ = (−s, c); Minus: its transpose (orthonormal, no radial part).
  static void plusJacobian(const double* a, double* J) {
    const Eigen::Vector2d cs = detail::unitComplex(a);
    J[0] = -cs[1];
    J[1] = cs[0];
  }
  static void minusJacobian(const double* a, double* J) { plusJacobian(a, J); }
};

template <>
struct AmbientOf<SE2<double>> {
  static constexpr int kSize = 4;
  template <class T>
  static SE2<T> read(const T* a) {
    return SE2<T>(AmbientOf<SO2<double>>::read(a), Eigen::Matrix<T, 2, 1>(a[2], a[3]));
  }
  template <class T>
  static void plus(const T* x, const T* delta, T* out) {
    const SE2<T> X(SO2<T>::fromCosSinUnchecked(x[0], x[1]), Eigen::Matrix<T, 2, 1>(x[2], x[3]));
    const SE2<T> Y = SE2<T>::exp(Eigen::Matrix<T, 3, 1>(delta[0], delta[1], delta[2])) * X;
    out[0] = Y.so2().complex()[0];
    out[1] = Y.so2().complex()[1];
    out[2] = Y.translation()[0];
    out[3] = Y.translation()[1];
  }
  template <class T>
  static void minus(const T* y, const T* x, T* out) {
    detail::store(lminus(read(y), read(x)), out);
  }
  // Rows [c, s, t_x, t_y], columns [ρ_x, ρ_y, θ]: P = [[0, p], [I, q]] with p = (−s, c),
  // q = d(R t)/dθ = (−t_y, t_x).
  static void plusJacobian(const double* a, double* J) {
    const Eigen::Vector2d cs = detail::unitComplex(a);
    const double c = cs[0], s = cs[1], tx = a[2], ty = a[3];
    const double P[12] = {0, 0, -s, 0, 0, c, 1, 0, -ty, 0, 1, tx};
    for (int i = 0; i < 12; ++i) J[i] = P[i];
  }
  // M = [[−q pᵀ, I], [pᵀ, 0]]: the left inverse of P with no radial part (M P = I).
  static void minusJacobian(const double* a, double* J) {
    const Eigen::Vector2d cs = detail::unitComplex(a);
    const double c = cs[0], s = cs[1], tx = a[2], ty = a[3];
    const double M[12] = {-ty * s, ty * c, 1, 0, tx * s, -tx * c, 0, 1, -s, c, 0, 0};
    for (int i = 0; i < 12; ++i) J[i] = M[i];
  }
};

template <>
struct AmbientOf<SO3<double>> {
  static constexpr int kSize = 4;
  template <class T>
  static SO3<T> read(const T* a) {
    return SO3<T>::fromQuaternion(detail::unitQuaternion(a));
  }
  template <class T>
  static void plus(const T* x, const T* delta, T* out) {
    detail::leftProduct(Eigen::Matrix<T, 3, 1>(delta[0], delta[1], delta[2]), x, out);
  }
  template <class T>
  static void minus(const T* y, const T* x, T* out) {
    detail::store(lminus(read(y), read(x)), out);
  }
  static void plusJacobian(const double* a, double* J) {
    Eigen::Map<Eigen::Matrix<double, 4, 3, Eigen::RowMajor>> map(J);
    map = 0.5 * detail::quaternionTangent(a);
  }
  static void minusJacobian(const double* a, double* J) {
    Eigen::Map<Eigen::Matrix<double, 3, 4, Eigen::RowMajor>> map(J);
    map = 2.0 * detail::quaternionTangent(a).transpose();
  }
};

template <>
struct AmbientOf<SE3<double>> {
  static constexpr int kSize = 7;
  template <class T>
  static SE3<T> read(const T* a) {
    return SE3<T>(AmbientOf<SO3<double>>::read(a), Eigen::Matrix<T, 3, 1>(a[4], a[5], a[6]));
  }
  template <class T>
  static void plus(const T* x, const T* delta, T* out) {
    const Eigen::Map<const Eigen::Matrix<T, 6, 1>> d(delta);
    detail::leftProduct(Eigen::Matrix<T, 3, 1>(d.template tail<3>()), x, out);
    // exp(δ) X's translation is C_δ t + J ρ: X's rotation does not enter.
    const Eigen::Matrix<T, 3, 1> t = (SE3<T>::exp(d) * SE3<T>(SO3<T>(), Eigen::Matrix<T, 3, 1>(x[4], x[5], x[6]))).translation();
    for (int i = 0; i < 3; ++i) out[4 + i] = t[i];
  }
  template <class T>
  static void minus(const T* y, const T* x, T* out) {
    detail::store(lminus(read(y), read(x)), out);
  }
  // Rows [q (4); t (3)], columns [ρ; φ]: P = [[0, ½Q], [I, −t^]].
  static void plusJacobian(const double* a, double* J) {
    Eigen::Map<Eigen::Matrix<double, 7, 6, Eigen::RowMajor>> P(J);
    P.setZero();
    P.block<4, 3>(0, 3) = 0.5 * detail::quaternionTangent(a);
    P.block<3, 3>(4, 0).setIdentity();
    P.block<3, 3>(4, 3) = -SO3<double>::hat(Eigen::Vector3d(a[4], a[5], a[6]));
  }
  // M = [[2 t^ Qᵀ, I], [2 Qᵀ, 0]]: the left inverse of P with no radial part (M P = I).
  static void minusJacobian(const double* a, double* J) {
    Eigen::Map<Eigen::Matrix<double, 6, 7, Eigen::RowMajor>> M(J);
    const Eigen::Matrix<double, 3, 4> Qt = detail::quaternionTangent(a).transpose();
    M.setZero();
    M.block<3, 4>(0, 0) = 2.0 * SO3<double>::hat(Eigen::Vector3d(a[4], a[5], a[6])) * Qt;
    M.block<3, 3>(0, 4).setIdentity();
    M.block<3, 4>(3, 0) = 2.0 * Qt;
  }
};

/// A lieservo group as a ceres::Manifold with the left perturbation (the header comment).
template <class G>
class LeftManifold final : public ::ceres::Manifold {
 public:
  using Ambient = AmbientOf<G>;
  int AmbientSize() const override { return Ambient::kSize; }
  int TangentSize() const override { return G::DoF; }

  /// x ⊞ δ = exp(δ^) X.
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override {
    Ambient::plus(x, delta, x_plus_delta);
    return true;
  }
  bool PlusJacobian(const double* x, double* jacobian) const override {
    Ambient::plusJacobian(x, jacobian);
    return true;
  }
  /// y ⊟ x = ln(Y X⁻¹)^∨ (lminus).
  bool Minus(const double* y, const double* x, double* y_minus_x) const override {
    Ambient::minus(y, x, y_minus_x);
    return true;
  }
  bool MinusJacobian(const double* x, double* jacobian) const override {
    Ambient::minusJacobian(x, jacobian);
    return true;
  }
};

using SO2Manifold = LeftManifold<SO2<double>>;  ///< [cos θ, sin θ]
using SE2Manifold = LeftManifold<SE2<double>>;  ///< [cos θ, sin θ, t_x, t_y]
using SO3Manifold = LeftManifold<SO3<double>>;  ///< [w, x, y, z]
using SE3Manifold = LeftManifold<SE3<double>>;  ///< [w, x, y, z, t_x, t_y, t_z]

}  // namespace lieservo::ceres_adapter

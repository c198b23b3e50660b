// lieservo/groups/se2.hpp — SE(2), planar rigid transformations [[R, t], [0ᵀ, 1]], stored as
// an SO2 and a translation. Tangent ξ = [ρx, ρy, θ] (translation first, as SE(3)).
#pragma once
#include <lieservo/detail/options_push.hpp>

#include <cmath>

#include <Eigen/Core>

#include <lieservo/groups/detail/coefficients.hpp>
#include <lieservo/groups/detail/generic.hpp>
#include <lieservo/groups/detail/ordered.hpp>
#include <lieservo/groups/lie_group_base.hpp>
#include <lieservo/groups/so2.hpp>

namespace lieservo {

template <typename Scalar_>
/// SE(2): a planar rigid motion (rotation R, translation t). The tangent is ξ = [ρ; θ],
/// translation first (docs/conventions.md); left perturbation X = exp(ε^) X̄.
class SE2 : public LieGroupBase<SE2<Scalar_>, Eigen::Matrix<Scalar_, 3, 1>, Eigen::Matrix<Scalar_, 3, 3>> {
 public:
  using Scalar = Scalar_;  ///< float, double or long double
  using Real = detail::RealOf<Scalar>;  ///< the real type behind Scalar
  static constexpr int DoF = 3;  ///< tangent dimension
  static constexpr int Dim = 2;  ///< dimension of the space it moves
  static constexpr int RotationDoF = 1;  ///< rotational part of the tangent, its tail (ξ = [ρ; φ])
  using Tangent = Eigen::Matrix<Scalar, 3, 1>;  ///< ξ = [ρ; θ]
  using Jacobian = Eigen::Matrix<Scalar, 3, 3>;  ///< DoF × DoF
  using Point = Eigen::Matrix<Scalar, 2, 1>;  ///< a point of the plane
  using Matrix = Eigen::Matrix<Scalar, 3, 3>;  ///< the homogeneous 3 × 3 matrix
  using Vector2 = Eigen::Matrix<Scalar, 2, 1>;  ///< 2-vector
  using Matrix2 = Eigen::Matrix<Scalar, 2, 2>;  ///< 2 × 2 matrix
  using SO2Type = SO2<Scalar>;  ///< the rotation part's group

  /// The identity.
  SE2() : R_(), t_(Vector2::Zero()) {}
  /// From a rotation and a translation: p ↦ R p + t.
  SE2(const SO2Type& R, const Vector2& t) : R_(R), t_(t) {}
  static SE2 identity() { return SE2(); }  ///< the identity

  /// Composition: (*this * o)(p) = *this(o(p)).
  SE2 operator*(const SE2& o) const { return SE2(R_ * o.R_, R_ * o.t_ + t_); }
  /// *this = *this * o.
  SE2& operator*=(const SE2& o) {
    *this = *this * o;
    return *this;
  }
  /// The moved point R p + t.
  Point operator*(const Point& p) const { return R_ * p + t_; }
  /// The inverse motion (Rᵀ, −Rᵀ t).
  SE2 inverse() const {
    const SO2Type Ri = R_.inverse();
    return SE2(Ri, -(Ri * t_));
  }

  /// exp(ξ^) = [[R(θ), V(θ) ρ], [0ᵀ, 1]], V = (sinθ/θ) I + ((1 − cosθ)/θ) [[0, −1], [1, 0]].
  static SE2 exp(const Tangent& xi) {
    const Scalar th = xi(2);
    const detail::AngleTerms<Scalar> t(th * th);
    return SE2(rotationWith(th, t), detail::times(V(th, t), Vector2(xi.template head<2>())));
  }
  /// log: θ = atan2 ∈ (−π, π], ρ = V(θ)⁻¹ t with V⁻¹ = [[H, θ/2], [−θ/2, H]], H = (θ/2)cot(θ/2).
  Tangent log() const {
    const Scalar th = R_.angle();
    const detail::AngleTerms<Scalar> t(th * th);
    Tangent xi;
    xi.template head<2>() = detail::times(Vinv(th, t), t_);
    xi(2) = th;
    return xi;
  }

  /// ξ^ = [[θ [[0, −1], [1, 0]], ρ], [0ᵀ, 0]].
  static Matrix hat(const Tangent& xi) {
    Matrix m;
    m << Scalar(0), -xi(2), xi(0),  //
        xi(2), Scalar(0), xi(1),     //
        Scalar(0), Scalar(0), Scalar(0);
    return m;
  }
  /// The inverse of hat (θ from the antisymmetrised rotation block).
  static Tangent vee(const Matrix& m) { return Tangent(m(0, 2), m(1, 2), Scalar(Real(0.5)) * (m(1, 0) - m(0, 1))); }

  /// Ad(X) = [[R, (t_y, −t_x)ᵀ], [0, 1]] (the planar analogue of eq. 30 (eqn:se3_adjoint)).
  Jacobian Ad() const {
    Jacobian A = Jacobian::Zero();
    A.template topLeftCorner<2, 2>() = R_.matrix();
    A(0, 2) = t_(1);
    A(1, 2) = -t_(0);
    A(2, 2) = Scalar(1);
    return A;
  }
  /// ad(ξ) = [[θ [[0, −1], [1, 0]], (ρ_y, −ρ_x)ᵀ], [0, 0]] (analogue of eq. 31 (eqn:se3_algebra_adjoint)).
  static Jacobian ad(const Tangent& xi) {
    Jacobian A = Jacobian::Zero();
    A(0, 1) = -xi(2);
    A(1, 0) = xi(2);
    A(0, 2) = xi(1);
    A(1, 2) = -xi(0);
    return A;
  }

  /// Left Jacobian (closed form of eq. 33 (eqn:left_jacobian_def)): [[V(θ), w], [0, 1]],
  /// w = (θ C(θ) ρx + B(θ) ρy, θ C(θ) ρy − B(θ) ρx), B = (1 − cosθ)/θ², C = (θ − sinθ)/θ³.
  static Jacobian leftJacobian(const Tangent& xi) {
    const Scalar th = xi(2);
    const detail::AngleTerms<Scalar> t(th * th);
    return leftJacobianWith(xi, t);
  }
  /// Inverse (closed form of eq. 34 (eqn:inv_jacobian_def)): [[V⁻¹, −V⁻¹ w], [0, 1]].
  static Jacobian leftJacobianInverse(const Tangent& xi) {
    const Scalar th = xi(2);
    const detail::AngleTerms<Scalar> t(th * th);
    return leftJacobianInverseWith(xi, t);
  }
  /// exp(ξ), and J(ξ) into J, sharing the trigonometric terms.
  static SE2 expAndLeftJacobian(const Tangent& xi, Jacobian& J) {
    const Scalar th = xi(2);
    const detail::AngleTerms<Scalar> t(th * th);
    J = leftJacobianWith(xi, t);
    return SE2(rotationWith(th, t), detail::times(Matrix2(J.template topLeftCorner<2, 2>()), Vector2(xi.template head<2>())));
  }
  /// log(), and J(ξ)⁻¹ of the result into Jinv, sharing the trigonometric terms.
  Tangent logAndLeftJacobianInverse(Jacobian& Jinv) const {
    const Scalar th = R_.angle();
    const detail::AngleTerms<Scalar> t(th * th);
    Tangent xi;
    xi.template head<2>() = detail::times(Vinv(th, t), t_);
    xi(2) = th;
    Jinv = leftJacobianInverseWith(xi, t);
    return xi;
  }

  /// The homogeneous matrix [[R, t], [0ᵀ, 1]].
  Matrix matrix() const {
    Matrix m = Matrix::Identity();
    m.template topLeftCorner<2, 2>() = R_.matrix();
    m.template topRightCorner<2, 1>() = t_;
    return m;
  }
  /// Read-only parts (as SE3's).
  const SO2Type& so2() const { return R_; }
  Matrix2 rotationMatrix() const { return R_.matrix(); }  ///< R
  const Vector2& translation() const { return t_; }  ///< t

  /// From a homogeneous matrix as given: no check of its rotation block or bottom row.
  static SE2 fromMatrixUnchecked(const Matrix& m) {
    return SE2(SO2Type::fromMatrixUnchecked(m.template topLeftCorner<2, 2>()), m.template topRightCorner<2, 1>());
  }
  /// Checked, at SO2::defaultTolerance(); see the overload with a tolerance.
  static Status fromMatrix(const Matrix& m, SE2& out) noexcept { return fromMatrix(m, out, SO2Type::defaultTolerance()); }
  /// Checked: non_finite_input; the rotation block as SO2::fromMatrix; invalid_argument unless
  /// the bottom row is (0, 0, 1) within tol. `out` is written only when ok.
  static Status fromMatrix(const Matrix& m, SE2& out, Scalar tol) noexcept {
    return detail::rigidFromMatrix<SE2, SO2Type>(m, false, tol, out);
  }
  /// The nearest rotation (SO2::fromMatrixProjected) with m's translation; the bottom row
  /// checked as in fromMatrix. `out` is written only when ok.
  static Status fromMatrixProjected(const Matrix& m, SE2& out) noexcept {
    return detail::rigidFromMatrix<SE2, SO2Type>(m, true, SO2Type::defaultTolerance(), out);
  }
  /// Re-normalises the rotation (after long chains of compositions).
  void normalize() noexcept { R_.normalize(); }
  bool allFinite() const { return R_.allFinite() && t_.allFinite(); }  ///< whether every stored number is finite
  /// Whether the rotations agree within tol (SO2::isApprox) and the translations within
  /// tol · (1 + the larger ‖t‖).
  bool isApprox(const SE2& o, Scalar tol) const {
    using std::max;
    const Scalar scale = Scalar(1) + max(t_.norm(), o.t_.norm());
    return R_.isApprox(o.R_, tol) && (t_ - o.t_).norm() <= tol * scale;
  }
  /// The same motion in another scalar type.
  template <class NewScalar>
  SE2<NewScalar> cast() const {
    return SE2<NewScalar>(R_.template cast<NewScalar>(), t_.template cast<NewScalar>());
  }
  /// Uniform rotation and translation uniform in [−s, s]², s = translation_scale.
  template <class Rng>
  static SE2 sampleUniform(Rng& rng, Scalar translation_scale = Scalar(1)) {
    const SO2Type R = SO2Type::sampleUniform(rng);
    Vector2 t;
    for (int i = 0; i < 2; ++i) t(i) = translation_scale * Scalar(2.0 * detail::uniform01(rng) - 1.0);
    return SE2(R, t);
  }

 private:
  /// R(θ) from the shared terms: cosθ = 1 − θ²B, sinθ = θA (no second sin/cos call).
  static SO2Type rotationWith(const Scalar& th, const detail::AngleTerms<Scalar>& t) {
    return SO2Type::fromCosSinUnchecked(Scalar(1) - t.theta2 * detail::coeffB(t), th * detail::coeffA(t));
  }
  static Matrix2 V(const Scalar& th, const detail::AngleTerms<Scalar>& t) {
    const Scalar a = detail::coeffA(t), b = th * detail::coeffB(t);
    Matrix2 m;
    m << a, -b, b, a;
    return m;
  }
  static Matrix2 Vinv(const Scalar& th, const detail::AngleTerms<Scalar>& t) {
    const Scalar h = detail::coeffH(t), hth = Scalar(Real(0.5)) * th;
    Matrix2 m;
    m << h, hth, -hth, h;
    return m;
  }
  static Vector2 wOf(const Tangent& xi, const detail::AngleTerms<Scalar>& t) {
    const Scalar tc = xi(2) * detail::coeffC(t), b = detail::coeffB(t);
    return Vector2(tc * xi(0) + b * xi(1), tc * xi(1) - b * xi(0));
  }
  static Jacobian leftJacobianWith(const Tangent& xi, const detail::AngleTerms<Scalar>& t) {
    Jacobian J = Jacobian::Zero();
    J.template topLeftCorner<2, 2>() = V(xi(2), t);
    J.template topRightCorner<2, 1>() = wOf(xi, t);
    J(2, 2) = Scalar(1);
    return J;
  }
  static Jacobian leftJacobianInverseWith(const Tangent& xi, const detail::AngleTerms<Scalar>& t) {
    Jacobian J = Jacobian::Zero();
    const Matrix2 Vi = Vinv(xi(2), t);
    J.template topLeftCorner<2, 2>() = Vi;
    J.template topRightCorner<2, 1>() = -(Vi * wOf(xi, t));
    J(2, 2) = Scalar(1);
    return J;
  }
  SO2Type R_;
  Vector2 t_;
};

using SE2d = SE2<double>;  ///< SE(2) in double
using SE2f = SE2<float>;   ///< SE(2) in float

}  // namespace lieservo

#include <lieservo/detail/options_pop.hpp>

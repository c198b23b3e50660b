// lieservo/groups/so2.hpp — SO(2), planar rotations, stored as the unit complex number (cos θ, sin θ).
//
// Tangent: θ (a 1-vector, radians). The group is abelian: Ad = 1, ad = 0, J = 1.
#pragma once
#include <lieservo/detail/options_push.hpp>

#include <cmath>

#include <Eigen/Core>

#include <lieservo/status.hpp>
#include <lieservo/units.hpp>
#include <lieservo/groups/detail/generic.hpp>
#include <lieservo/groups/detail/series.hpp>
#include <lieservo/groups/lie_group_base.hpp>

namespace lieservo {

/// SO(2): a planar rotation, stored as the unit complex number (cos θ, sin θ). The tangent is
/// θ in radians; the group is abelian, so Ad = 1, ad = 0 and every Jacobian is 1.
template <typename Scalar_>
class SO2 : public LieGroupBase<SO2<Scalar_>, Eigen::Matrix<Scalar_, 1, 1>, Eigen::Matrix<Scalar_, 1, 1>> {
 public:
  using Scalar = Scalar_;                      ///< float, double or long double
  using Real = detail::RealOf<Scalar>;         ///< the real type behind Scalar
  static constexpr int DoF = 1;                ///< tangent dimension
  static constexpr int Dim = 2;                ///< dimension of the space it rotates
  static constexpr int RotationDoF = 1;  ///< rotational part of the tangent, its tail (ξ = [ρ; φ])
  using Tangent = Eigen::Matrix<Scalar, 1, 1>;   ///< θ (rad)
  using Jacobian = Eigen::Matrix<Scalar, 1, 1>;  ///< DoF × DoF
  using Point = Eigen::Matrix<Scalar, 2, 1>;     ///< a point of the plane
  using Matrix = Eigen::Matrix<Scalar, 2, 2>;    ///< the rotation matrix
  using Vector2 = Eigen::Matrix<Scalar, 2, 1>;   ///< 2-vector
  using Matrix2 = Eigen::Matrix<Scalar, 2, 2>;   ///< 2 × 2 matrix

  /// The identity.
  SO2() : cs_(Scalar(1), Scalar(0)) {}
  /// Rotation by θ radians.
  explicit SO2(Scalar theta) : cs_(cosOf(theta), sinOf(theta)) {}
  static SO2 identity() { return SO2(); }                     ///< the identity
  static SO2 fromAngle(Scalar theta) { return SO2(theta); }  ///< rotation by θ radians

  /// Composition: the rotation by this angle plus o's.
  SO2 operator*(const SO2& o) const {
    return fromCosSinUnchecked(c() * o.c() - s() * o.s(), s() * o.c() + c() * o.s());
  }
  /// *this = *this * o.
  SO2& operator*=(const SO2& o) {
    *this = *this * o;
    return *this;
  }
  /// The rotated point R p.
  Point operator*(const Point& p) const { return Point(c() * p(0) - s() * p(1), s() * p(0) + c() * p(1)); }
  SO2 inverse() const { return fromCosSinUnchecked(c(), -s()); }  ///< the opposite rotation

  static SO2 exp(const Tangent& theta) { return SO2(theta(0)); }  ///< rotation by θ
  /// θ = atan2(sin, cos) ∈ (−π, π]; exactly π at a half turn (−π is mapped to +π).
  Tangent log() const { return Tangent(angle()); }
  /// The angle of log(), as a scalar.
  Scalar angle() const {
    using std::atan2;
    const Scalar a = atan2(s(), c());
    return a == -pi<Scalar>() ? pi<Scalar>() : a;
  }

  /// θ^ = [[0, −θ], [θ, 0]].
  static Matrix hat(const Tangent& t) {
    Matrix m;
    m << Scalar(0), -t(0), t(0), Scalar(0);
    return m;
  }
  /// The inverse of hat (the mean of the two off-diagonal entries, antisymmetrised).
  static Tangent vee(const Matrix& m) { return Tangent(Scalar(Real(0.5)) * (m(1, 0) - m(0, 1))); }

  Jacobian Ad() const { return Jacobian::Identity(); }                         ///< adjoint: 1
  static Jacobian ad(const Tangent&) { return Jacobian::Zero(); }              ///< ad(θ) = 0
  static Jacobian leftJacobian(const Tangent&) { return Jacobian::Identity(); }  ///< J(θ) = 1
  static Jacobian leftJacobianInverse(const Tangent&) { return Jacobian::Identity(); }  ///< J(θ)⁻¹ = 1
  /// exp(θ), and J(θ) = 1 into J.
  static SO2 expAndLeftJacobian(const Tangent& t, Jacobian& J) {
    J.setIdentity();
    return exp(t);
  }
  /// log(), and J⁻¹ = 1 into Jinv.
  Tangent logAndLeftJacobianInverse(Jacobian& Jinv) const {
    Jinv.setIdentity();
    return log();
  }

  /// The rotation matrix.
  Matrix matrix() const {
    Matrix m;
    m << c(), -s(), s(), c();
    return m;
  }
  Matrix rotationMatrix() const { return matrix(); }  ///< the rotation matrix (as matrix())
  Scalar cosAngle() const { return c(); }             ///< cos θ
  Scalar sinAngle() const { return s(); }             ///< sin θ
  const Vector2& complex() const { return cs_; }      ///< the stored (cos θ, sin θ)

  /// From (cos θ, sin θ) as given: no check that it has unit length.
  static SO2 fromCosSinUnchecked(Scalar c, Scalar s) {
    SO2 r;
    r.cs_ = Vector2(c, s);
    return r;
  }
  /// From the first column of m: no check that m is a rotation.
  static SO2 fromMatrixUnchecked(const Matrix& m) { return fromCosSinUnchecked(m(0, 0), m(1, 0)); }
  /// fromMatrix's tolerance on ‖mᵀm − 1‖: √eps of Real.
  static Scalar defaultTolerance() {
    using std::sqrt;
    return Scalar(sqrt(Eigen::NumTraits<Real>::epsilon()));
  }
  /// Checked, at defaultTolerance(); see the overload with a tolerance.
  static Status fromMatrix(const Matrix& m, SO2& out) noexcept { return fromMatrix(m, out, defaultTolerance()); }
  /// Checked: invalid_argument for a negative or non-finite tol, non_finite_input, or
  /// not_orthonormal unless ‖mᵀm − 1‖ ≤ tol and det m > 0; `out` is written only when ok.
  static Status fromMatrix(const Matrix& m, SO2& out, Scalar tol) noexcept {
    if (!detail::validTolerance(tol)) return Status::invalid_argument;
    if (!m.allFinite()) return Status::non_finite_input;
    if (!((m.transpose() * m - Matrix2::Identity()).norm() <= tol)) return Status::not_orthonormal;
    if (!(m.determinant() > Scalar(0))) return Status::not_orthonormal;
    out = fromMatrixUnchecked(m);
    return Status::ok;
  }
  /// Nearest rotation in the Frobenius norm: angle atan2(m10 − m01, m00 + m11).
  static Status fromMatrixProjected(const Matrix& m, SO2& out) noexcept {
    if (!m.allFinite()) return Status::non_finite_input;
    // Scale to max |m_ij| = 1 first: m00 + m11 overflows near the largest finite value, and
    // the plain norm of (c, s) overflows or underflows long before that (|(c, s)| ≷ 1e±154).
    const Scalar scale = m.cwiseAbs().maxCoeff();
    if (!(scale > Scalar(0))) return Status::invalid_argument;
    const Matrix u = m / scale;
    const Scalar c = u(0, 0) + u(1, 1), s = u(1, 0) - u(0, 1);
    if (c == Scalar(0) && s == Scalar(0)) return Status::invalid_argument;
    SO2 r = fromCosSinUnchecked(c, s);
    r.normalize();
    if (!r.allFinite()) return Status::numerical_failure;
    out = r;
    return Status::ok;
  }
  /// Rescales (cos, sin) to unit length; stableNormalize avoids the norm's over/underflow.
  void normalize() noexcept { cs_.stableNormalize(); }
  bool allFinite() const { return cs_.allFinite(); }  ///< whether both stored numbers are finite
  /// Whether the rotation matrices differ by at most tol (Frobenius norm).
  bool isApprox(const SO2& o, Scalar tol) const { return (matrix() - o.matrix()).norm() <= tol; }
  /// The same rotation in another scalar type.
  template <class NewScalar>
  SO2<NewScalar> cast() const {
    return SO2<NewScalar>::fromCosSinUnchecked(NewScalar(c()), NewScalar(s()));
  }
  /// Uniformly distributed rotation: the angle uniform in [−π, π).
  template <class Rng>
  static SO2 sampleUniform(Rng& rng) {
    return SO2(Scalar(pi<double>() * (2.0 * detail::uniform01(rng) - 1.0)));
  }

 private:
  static Scalar cosOf(const Scalar& t) {
    using std::cos;
    return cos(t);
  }
  static Scalar sinOf(const Scalar& t) {
    using std::sin;
    return sin(t);
  }
  const Scalar& c() const { return cs_(0); }
  const Scalar& s() const { return cs_(1); }
  Vector2 cs_;
};

using SO2d = SO2<double>;  ///< SO(2) in double
using SO2f = SO2<float>;   ///< SO(2) in float

}  // namespace lieservo

#include <lieservo/detail/options_pop.hpp>

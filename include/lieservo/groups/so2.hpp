// lieservo/groups/so2.hpp — SO(2), planar rotations, stored as the unit complex number (cos θ, sin θ).
//
// Tangent: θ (a 1-vector, radians). The group is abelian: Ad = 1, ad = 0, J = 1.
#pragma once

#include <cmath>

#include <Eigen/Core>

#include <lieservo/status.hpp>
#include <lieservo/units.hpp>
#include <lieservo/groups/detail/generic.hpp>
#include <lieservo/groups/detail/series.hpp>

namespace lieservo {

template <typename Scalar_>
class SO2 {
 public:
  using Scalar = Scalar_;
  using Real = detail::RealOf<Scalar>;
  static constexpr int DoF = 1;
  static constexpr int Dim = 2;
  using Tangent = Eigen::Matrix<Scalar, 1, 1>;
  using Jacobian = Eigen::Matrix<Scalar, 1, 1>;
  using Point = Eigen::Matrix<Scalar, 2, 1>;
  using Matrix = Eigen::Matrix<Scalar, 2, 2>;
  using Vector2 = Eigen::Matrix<Scalar, 2, 1>;
  using Matrix2 = Eigen::Matrix<Scalar, 2, 2>;

  SO2() : cs_(Scalar(1), Scalar(0)) {}
  /// Rotation by θ radians.
  explicit SO2(Scalar theta) : cs_(cosOf(theta), sinOf(theta)) {}
  static SO2 identity() { return SO2(); }
  static SO2 fromAngle(Scalar theta) { return SO2(theta); }

  SO2 operator*(const SO2& o) const {
    return fromCosSinUnchecked(c() * o.c() - s() * o.s(), s() * o.c() + c() * o.s());
  }
  SO2& operator*=(const SO2& o) {
    *this = *this * o;
    return *this;
  }
  Point operator*(const Point& p) const { return Point(c() * p(0) - s() * p(1), s() * p(0) + c() * p(1)); }
  SO2 inverse() const { return fromCosSinUnchecked(c(), -s()); }

  static SO2 exp(const Tangent& theta) { return SO2(theta(0)); }
  /// θ = atan2(sin, cos) ∈ (−π, π]; exactly π at a half turn (−π is mapped to +π).
  Tangent log() const { return Tangent(angle()); }
  Scalar angle() const {
    using std::atan2;
    const Scalar a = atan2(s(), c());
    return a == -pi<Scalar>() ? pi<Scalar>() : a;
  }

  static Matrix hat(const Tangent& t) {
    Matrix m;
    m << Scalar(0), -t(0), t(0), Scalar(0);
    return m;
  }
  static Tangent vee(const Matrix& m) { return Tangent(Scalar(Real(0.5)) * (m(1, 0) - m(0, 1))); }

  Jacobian Ad() const { return Jacobian::Identity(); }
  static Jacobian ad(const Tangent&) { return Jacobian::Zero(); }
  static Jacobian leftJacobian(const Tangent&) { return Jacobian::Identity(); }
  static Jacobian leftJacobianInverse(const Tangent&) { return Jacobian::Identity(); }
  template <int N>
  static Jacobian leftJacobianInverseSeries(const Tangent& t) {
    return detail::inverseJacobianSeries<SO2, N>(t);
  }
  static Jacobian rightJacobian(const Tangent&) { return Jacobian::Identity(); }
  static Jacobian rightJacobianInverse(const Tangent&) { return Jacobian::Identity(); }
  static SO2 expAndLeftJacobian(const Tangent& t, Jacobian& J) {
    J.setIdentity();
    return exp(t);
  }
  Tangent logAndLeftJacobianInverse(Jacobian& Jinv) const {
    Jinv.setIdentity();
    return log();
  }
  static Tangent bchLeftSmall(const Tangent& xi1_small, const Tangent& xi2) { return xi1_small + xi2; }
  static Tangent bchRightSmall(const Tangent& xi1, const Tangent& xi2_small) { return xi1 + xi2_small; }
  SO2 interpolate(const SO2& other, Scalar t) const { return *this * exp(t * (inverse() * other).log()); }

  Matrix matrix() const {
    Matrix m;
    m << c(), -s(), s(), c();
    return m;
  }
  Matrix rotationMatrix() const { return matrix(); }
  Scalar cosAngle() const { return c(); }
  Scalar sinAngle() const { return s(); }
  const Vector2& complex() const { return cs_; }

  static SO2 fromCosSinUnchecked(Scalar c, Scalar s) {
    SO2 r;
    r.cs_ = Vector2(c, s);
    return r;
  }
  static SO2 fromMatrixUnchecked(const Matrix& m) { return fromCosSinUnchecked(m(0, 0), m(1, 0)); }
  static Scalar defaultTolerance() {
    using std::sqrt;
    return Scalar(sqrt(Eigen::NumTraits<Real>::epsilon()));
  }
  static Status fromMatrix(const Matrix& m, SO2& out) noexcept { return fromMatrix(m, out, defaultTolerance()); }
  static Status fromMatrix(const Matrix& m, SO2& out, Scalar tol) noexcept {
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
  bool allFinite() const { return cs_.allFinite(); }
  bool isApprox(const SO2& o, Scalar tol) const { return (matrix() - o.matrix()).norm() <= tol; }
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

using SO2d = SO2<double>;
using SO2f = SO2<float>;

}  // namespace lieservo

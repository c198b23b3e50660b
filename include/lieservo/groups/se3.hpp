// lieservo/groups/se3.hpp — SE(3), rigid transformations X = [[C, r], [0ᵀ, 1]]
// (eq. 26, eqn:se3_matrix_def), stored as an SO3 and a translation vector.
//
// Conventions (docs/conventions.md): ξ = [ρ; φ] (translation first, eq. 28 (eqn:se3_hat_operator)),
// left perturbation X = exp(ε^) X̄, Ad(X) = [[C, r^C], [0, C]] (eq. 30, eqn:se3_adjoint),
// ad(ξ) = [[φ^, ρ^], [0, φ^]] (eq. 31, eqn:se3_algebra_adjoint), J = left Jacobian (eq. 33, eqn:left_jacobian_def).
#pragma once
#include <lieservo/detail/options_push.hpp>

#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <lieservo/detail/flatten.hpp>
#include <lieservo/groups/detail/generic.hpp>
#include <lieservo/groups/lie_group_base.hpp>
#include <lieservo/groups/so3.hpp>

namespace lieservo {

// Implementation note: tangent vectors are filled with fixed-size head<3>()/tail<3>()
// assignments, not the comma initializer, which trips GCC 12's -Warray-bounds (a false
// positive in Eigen's packet path for float 3-vectors at -O3).
template <typename Scalar_>
/// SE(3): a rigid motion X = [[C, r], [0ᵀ, 1]] (eq. 26, eqn:se3_matrix_def). The tangent is
/// ξ = [ρ; φ], translation first; left perturbation X = exp(ε^) X̄ (docs/conventions.md).
class SE3 : public LieGroupBase<SE3<Scalar_>, Eigen::Matrix<Scalar_, 6, 1>, Eigen::Matrix<Scalar_, 6, 6>> {
 public:
  using Scalar = Scalar_;  ///< float, double or long double
  using Real = detail::RealOf<Scalar>;  ///< the real type behind Scalar
  static constexpr int DoF = 6;  ///< tangent dimension
  static constexpr int Dim = 3;  ///< dimension of the space it moves
  static constexpr int RotationDoF = 3;  ///< rotational part of the tangent, its tail (ξ = [ρ; φ])
  using Tangent = Eigen::Matrix<Scalar, 6, 1>;  ///< ξ = [ρ; φ]
  using Jacobian = Eigen::Matrix<Scalar, 6, 6>;  ///< DoF × DoF
  using Point = Eigen::Matrix<Scalar, 3, 1>;  ///< a point of space
  using Matrix = Eigen::Matrix<Scalar, 4, 4>;  ///< the homogeneous 4 × 4 matrix
  using Vector3 = Eigen::Matrix<Scalar, 3, 1>;  ///< 3-vector
  using Vector6 = Eigen::Matrix<Scalar, 6, 1>;  ///< 6-vector
  using Matrix3 = Eigen::Matrix<Scalar, 3, 3>;  ///< 3 × 3 matrix
  using Matrix4 = Eigen::Matrix<Scalar, 4, 4>;  ///< 4 × 4 matrix
  using Isometry = Eigen::Transform<Scalar, 3, Eigen::Isometry>;  ///< Eigen's rigid transform
  using Quaternion = Eigen::Quaternion<Scalar>;  ///< Eigen's quaternion
  using SO3Type = SO3<Scalar>;  ///< the rotation part's group

  /// The identity.
  SE3() : C_(), r_(Vector3::Zero()) {}
  /// From a rotation and a translation: p ↦ C p + r.
  SE3(const SO3Type& C, const Vector3& r) : C_(C), r_(r) {}
  static SE3 identity() { return SE3(); }  ///< the identity

  // ---- group operations -----------------------------------------------------------------
  /// Written in place from the operands (see SO3::operator*: no temporaries read back).
  SE3 operator*(const SE3& o) const {
    SE3 x;
    detail::multiply3(C_.C_, o.C_.C_, x.C_.C_);
    x.r_ = r_ + detail::times(C_.rotationMatrix(), o.r_);
    return x;
  }
  SE3& operator*=(const SE3& o) { return *this = *this * o; }  ///< *this = *this * o
  Point operator*(const Point& p) const { return C_ * p + r_; }  ///< the moved point C p + r
  /// [Cᵀ, −Cᵀr], both read from C (not from the stored transpose: see operator*).
  SE3 inverse() const {
    SE3 x;
    x.C_.C_ = C_.C_.transpose();
    x.r_ = -detail::transposeTimes(C_.rotationMatrix(), r_);
    return x;
  }

  // ---- exp / log --------------------------------------------------------------------------
  /// exp(ξ^) = [[exp(φ^), J(φ) ρ], [0ᵀ, 1]] (eq. 28, eqn:se3_hat_operator, Barfoot's closed form).
  LIESERVO_FLATTEN static SE3 exp(const Tangent& xi) {
    const Vector3 rho = xi.template head<3>(), phi = xi.template tail<3>();
    const detail::AngleTerms<Scalar> t(detail::squaredNorm(phi));
    return SE3(SO3Type::expWith(phi, t), detail::times(SO3Type::leftJacobianWith(phi, t), rho));
  }
  /// log(X)^∨ = [J(φ)⁻¹ r; φ] with φ = log(C), θ ∈ [0, π] (sign rule at π as SO3::log).
  LIESERVO_FLATTEN Tangent log() const {
    detail::AngleTerms<Scalar> t(Scalar(0));
    const Vector3 phi = C_.logWithTerms(t);  // log and J⁻¹ share the trigonometric work
    Tangent xi;
    xi.template head<3>() = detail::times(SO3Type::leftJacobianInverseWith(phi, t), r_);
    xi.template tail<3>() = phi;
    return xi;
  }

  /// ξ^ = [[φ^, ρ], [0ᵀ, 0]] (eq. 28, eqn:se3_hat_operator).
  static Matrix hat(const Tangent& xi) {
    Matrix m = Matrix::Zero();
    m.template topLeftCorner<3, 3>() = detail::skew(Vector3(xi.template tail<3>()));
    m.template topRightCorner<3, 1>() = xi.template head<3>();
    return m;
  }
  /// The inverse of hat: [ρ; φ] from the translation column and the rotation block.
  static Tangent vee(const Matrix& m) {
    Tangent xi;
    xi.template head<3>() = m.template topRightCorner<3, 1>();
    xi.template tail<3>() = SO3Type::vee(m.template topLeftCorner<3, 3>());
    return xi;
  }

  /// Ad(X) = [[C, r^C], [0, C]] (eq. 30, eqn:se3_adjoint).
  /// Written column by column (column j of r^C is r × C's column j): each column is stored
  /// whole, once, with no 3×3 product and no temporary.
  Jacobian Ad() const {
    Jacobian A;
    const Matrix3& C = C_.rotationMatrix();
    for (int j = 0; j < 3; ++j) {
      A.col(j).template head<3>() = C.col(j);
      A.col(j).template tail<3>().setZero();
      A.col(j + 3).template head<3>() = r_.cross(C.col(j));
      A.col(j + 3).template tail<3>() = C.col(j);
    }
    return A;
  }
  /// Ad Σ Adᵀ for a symmetric Σ (a covariance carried through this motion, eq. 41,
  /// eqn:se3_rv_probabilistic_transform_2), by 3×3 blocks: Ad = [[I, r^], [0, I]] diag(C, C), so
  /// with C Σ Cᵀ blockwise = [[A, B], [Bᵀ, D]] and B' = B + r^D the result is
  /// [[A + r^Bᵀ + (r^B'ᵀ)ᵀ, B'], [B'ᵀ, D]]: half the multiplications of the 6×6 products.
  /// Symmetric up to rounding in the top-left block (callers symmetrise).
  Jacobian adjointCongruence(const Jacobian& Sigma) const noexcept {
    const Matrix3& C = C_.rotationMatrix();
    const Matrix3 A = C * Sigma.template topLeftCorner<3, 3>() * C.transpose();
    const Matrix3 B = C * Sigma.template topRightCorner<3, 3>() * C.transpose();
    const Matrix3 D = C * Sigma.template bottomRightCorner<3, 3>() * C.transpose();
    Matrix3 B2 = B;
    for (int j = 0; j < 3; ++j) B2.col(j) += r_.cross(D.col(j));
    Matrix3 top = A;
    for (int j = 0; j < 3; ++j) top.col(j) += r_.cross(Vector3(B.row(j).transpose()));
    for (int j = 0; j < 3; ++j) top.row(j) += r_.cross(Vector3(B2.row(j).transpose())).transpose();
    Jacobian out;
    out.template topLeftCorner<3, 3>() = top;
    out.template topRightCorner<3, 3>() = B2;
    out.template bottomLeftCorner<3, 3>() = B2.transpose();
    out.template bottomRightCorner<3, 3>() = D;
    return out;
  }
  /// ad(ξ) = ξ⋏ = [[φ^, ρ^], [0, φ^]] (eq. 31, eqn:se3_algebra_adjoint).
  static Jacobian ad(const Tangent& xi) {
    Jacobian A;
    const Matrix3 P = detail::skew(Vector3(xi.template tail<3>()));
    A.template topLeftCorner<3, 3>() = P;
    A.template topRightCorner<3, 3>() = detail::skew(Vector3(xi.template head<3>()));
    A.template bottomLeftCorner<3, 3>().setZero();
    A.template bottomRightCorner<3, 3>() = P;
    return A;
  }

  // ---- Jacobians ---------------------------------------------------------------------------
  /// Barfoot's Q(ρ, φ), the top-right block of the SE(3) left Jacobian:
  /// Q = ½ρ^ + C(θ)(φ^ρ^ + ρ^φ^ + φ^ρ^φ^) + E(θ)(φ^φ^ρ^ + ρ^φ^φ^ − 3φ^ρ^φ^)
  ///     + F(θ)(φ^ρ^φ^φ^ + φ^φ^ρ^φ^), with C, E, F from detail/coefficients.hpp.
  static Matrix3 Q(const Vector3& rho, const Vector3& phi) {
    const detail::AngleTerms<Scalar> t(detail::squaredNorm(phi));
    return QWith(rho, phi, t);
  }
  /// Left Jacobian, closed form of eq. 33 (eqn:left_jacobian_def): [[J(φ), Q(ρ, φ)], [0, J(φ)]].
  static Jacobian leftJacobian(const Tangent& xi) {
    const Vector3 rho = xi.template head<3>(), phi = xi.template tail<3>();
    const detail::AngleTerms<Scalar> t(detail::squaredNorm(phi));
    return leftJacobianWith(rho, phi, t);
  }
  /// Inverse left Jacobian, closed form of eq. 34 (eqn:inv_jacobian_def):
  /// [[J⁻¹, −J⁻¹ Q J⁻¹], [0, J⁻¹]].
  static Jacobian leftJacobianInverse(const Tangent& xi) {
    const Vector3 rho = xi.template head<3>(), phi = xi.template tail<3>();
    const detail::AngleTerms<Scalar> t(detail::squaredNorm(phi));
    return leftJacobianInverseWith(rho, phi, t);
  }
  /// Truncated series Σ_{n=0}^{N} B_n/n! (ξ⋏)^n (eq. 34, eqn:inv_jacobian_def); N = 2 is the paper's.
  /// Written out block by block (it hides LieGroupBase's generic 6 × 6 Horner form).
  template <int N>
  static Jacobian leftJacobianInverseSeries(const Tangent& xi) {
    constexpr detail::BernoulliTable<N> c;
    const Vector3 rho = xi.template head<3>(), phi = xi.template tail<3>();
    Jacobian Jinv;
    if constexpr (N <= 2) {
      // Up to the paper's order, entry by entry straight into the result (small Eigen block
      // expressions here were left as out-of-line loops and cost more than the arithmetic):
      // with Φ² = φφᵀ − θ²1 and ΦP + PΦ = ρφᵀ + φρᵀ − 2(φ·ρ)1 (a^b^ = baᵀ − (a·b)1),
      // D = 1 + b1 Φ + b2 Φ², U = b1 P + b2 (ΦP + PΦ).
      const Scalar b1 = N >= 1 ? Scalar(Real(c.b[N >= 1 ? 1 : 0])) : Scalar(0);
      const Scalar b2 = N >= 2 ? Scalar(Real(c.b[N >= 2 ? 2 : 0])) : Scalar(0);
      const Scalar dd = Scalar(1) - b2 * detail::squaredNorm(phi);  // D's diagonal offset
      const Scalar ud = Scalar(-2) * b2 * detail::dot(phi, rho);       // U's diagonal offset
      const Vector3 p1 = b1 * phi, r1 = b1 * rho, p2 = b2 * phi, r2 = b2 * rho;
      for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) {
          const Scalar d = p2(i) * phi(j) + (i == j ? dd : Scalar(0));
          const Scalar u = r2(i) * phi(j) + p2(i) * rho(j) + (i == j ? ud : Scalar(0));
          Jinv(i, j) = d;
          Jinv(i + 3, j + 3) = d;
          Jinv(i, j + 3) = u;
          Jinv(i + 3, j) = Scalar(0);
        }
      // the skew parts b1 φ^ and b1 ρ^ (off-diagonal only)
      Jinv(0, 1) -= p1(2); Jinv(1, 0) += p1(2); Jinv(0, 2) += p1(1);
      Jinv(2, 0) -= p1(1); Jinv(1, 2) -= p1(0); Jinv(2, 1) += p1(0);
      Jinv(3, 4) -= p1(2); Jinv(4, 3) += p1(2); Jinv(3, 5) += p1(1);
      Jinv(5, 3) -= p1(1); Jinv(4, 5) -= p1(0); Jinv(5, 4) += p1(0);
      Jinv(0, 4) -= r1(2); Jinv(1, 3) += r1(2); Jinv(0, 5) += r1(1);
      Jinv(2, 3) -= r1(1); Jinv(1, 5) -= r1(0); Jinv(2, 4) += r1(0);
    } else {
      // Horner in ad(ξ) = [[Φ, P], [0, Φ]] (Φ = φ^, P = ρ^), 3×3 blocks: every partial sum
      // r = [[D, U], [0, D]] keeps that shape, and ad·r = [[ΦD, ΦU + PD], [0, ΦD]], so a
      // step costs three 3×3 products instead of one dense 6×6 product (81 vs 216 multiplies).
      const Matrix3 Phi = detail::skew(phi);
      const Matrix3 P = detail::skew(rho);
      Matrix3 D = Matrix3::Identity() * Scalar(Real(c.b[N]));
      Matrix3 U = Matrix3::Zero();
      for (int n = N - 1; n >= 0; --n) {
        U = (Phi * U + P * D).eval();
        D = (Phi * D).eval();
        D.diagonal().array() += Scalar(Real(c.b[n]));
      }
      Jinv.template topLeftCorner<3, 3>() = D;
      Jinv.template topRightCorner<3, 3>() = U;
      Jinv.template bottomLeftCorner<3, 3>().setZero();
      Jinv.template bottomRightCorner<3, 3>() = D;
    }
    return Jinv;
  }
  /// exp(ξ), and J(ξ) into J, sharing the trigonometric work.
  LIESERVO_FLATTEN static SE3 expAndLeftJacobian(const Tangent& xi, Jacobian& J) {
    const Vector3 rho = xi.template head<3>(), phi = xi.template tail<3>();
    const detail::AngleTerms<Scalar> t(detail::squaredNorm(phi));
    J = leftJacobianWith(rho, phi, t);
    return SE3(SO3Type::expWith(phi, t), detail::times(Matrix3(J.template topLeftCorner<3, 3>()), rho));
  }
  /// log(), and J(ξ)⁻¹ of the result into Jinv, sharing the trigonometric work.
  LIESERVO_FLATTEN Tangent logAndLeftJacobianInverse(Jacobian& Jinv) const {
    detail::AngleTerms<Scalar> t(Scalar(0));
    const Vector3 phi = C_.logWithTerms(t);  // log and J⁻¹ share the trigonometric work
    const Matrix3 Ji = SO3Type::leftJacobianInverseWith(phi, t);
    const Vector3 rho = detail::times(Ji, r_);
    Jinv.template topLeftCorner<3, 3>() = Ji;
    Jinv.template topRightCorner<3, 3>() = -(Ji * QWith(rho, phi, t) * Ji);
    Jinv.template bottomLeftCorner<3, 3>().setZero();
    Jinv.template bottomRightCorner<3, 3>() = Ji;
    Tangent xi;
    xi.template head<3>() = rho;
    xi.template tail<3>() = phi;
    return xi;
  }

  // ---- matrices and construction -----------------------------------------------------------
  /// The homogeneous matrix [[C, r], [0ᵀ, 1]].
  Matrix matrix() const {
    Matrix m = Matrix::Identity();
    m.template topLeftCorner<3, 3>() = C_.rotationMatrix();
    m.template topRightCorner<3, 1>() = r_;
    return m;
  }
  /// Read-only parts: an element changes only through the group operations and the checked
  /// or explicitly unchecked constructors, so a valid element stays valid.
  const SO3Type& so3() const { return C_; }
  const Matrix3& rotationMatrix() const { return C_.rotationMatrix(); }  ///< C
  const Vector3& translation() const { return r_; }  ///< r

  /// Unchecked: the top-left block is taken as the rotation, the last column as r; the
  /// bottom row is ignored.
  static SE3 fromMatrixUnchecked(const Matrix& M) {
    return SE3(SO3Type::fromMatrixUnchecked(M.template topLeftCorner<3, 3>()), M.template topRightCorner<3, 1>());
  }
  /// Checked: finite; rotation block orthonormal with det +1 (tolerance as SO3::fromMatrix);
  /// bottom row [0 0 0 1] within the same tolerance (else invalid_argument).
  static Status fromMatrix(const Matrix& M, SE3& out) noexcept { return fromMatrix(M, out, SO3Type::defaultTolerance()); }
  /// As the overload above, with the tolerance given.
  static Status fromMatrix(const Matrix& M, SE3& out, Scalar tol) noexcept {
    return detail::rigidFromMatrix<SE3, SO3Type>(M, false, tol, out);
  }
  /// Projects the rotation block to the nearest rotation (SO3::fromMatrixProjected).
  static Status fromMatrixProjected(const Matrix& M, SE3& out) noexcept {
    return detail::rigidFromMatrix<SE3, SO3Type>(M, true, SO3Type::defaultTolerance(), out);
  }
  /// fromMatrix's checks of the stored element (validateElement), without forming the 4×4
  /// matrix: ok, non_finite_input (a NaN or inf anywhere) or not_orthonormal (the rotation).
  LIESERVO_ALWAYS_INLINE Status validate() const noexcept {
    if (!detail::allFinite(C_.rotationMatrix()) || !detail::allFinite(r_)) return Status::non_finite_input;
    return C_.validate();
  }
  /// Re-orthonormalises the rotation (SO3::normalize), after long chains of compositions.
  void normalize() noexcept { C_.normalize(); }
  bool allFinite() const noexcept { return C_.allFinite() && detail::allFinite(r_); }  ///< whether every stored number is finite
  /// Rotation ‖ΔC‖_F ≤ tol and translation ‖Δr‖ ≤ tol · (1 + max(‖r1‖, ‖r2‖)).
  bool isApprox(const SE3& o, Scalar tol) const {
    using std::max;
    const Scalar scale = Scalar(1) + max(r_.norm(), o.r_.norm());
    return C_.isApprox(o.C_, tol) && (r_ - o.r_).norm() <= tol * scale;
  }
  /// The same motion in another scalar type.
  template <class NewScalar>
  SE3<NewScalar> cast() const {
    return SE3<NewScalar>(C_.template cast<NewScalar>(), r_.template cast<NewScalar>());
  }
  /// Uniform rotation (Haar) and translation uniform in [−s, s]³, s = translation_scale.
  template <class Rng>
  static SE3 sampleUniform(Rng& rng, Scalar translation_scale = Scalar(1)) {
    const SO3Type C = SO3Type::sampleUniform(rng);
    Vector3 r;
    for (int i = 0; i < 3; ++i) r(i) = translation_scale * Scalar(2.0 * detail::uniform01(rng) - 1.0);
    return SE3(C, r);
  }

  // ---- conversions --------------------------------------------------------------------------
  /// From Eigen's isometry, unchecked: its linear part is taken as the rotation.
  static SE3 fromIsometry(const Isometry& T) { return SE3(SO3Type::fromMatrixUnchecked(T.linear()), T.translation()); }
  /// As Eigen's isometry.
  Isometry isometry() const {
    Isometry T = Isometry::Identity();
    T.linear() = C_.rotationMatrix();
    T.translation() = r_;
    return T;
  }
  /// (x, y, z, α, β, γ), angles in radians, C = Rz(γ) Ry(β) Rx(α), r = (x, y, z).
  static SE3 fromEulerXYZ6(const Vector6& v) {
    return SE3(SO3Type::fromEulerXYZ(v(3), v(4), v(5)), v.template head<3>());
  }
  /// The inverse of fromEulerXYZ6: (x, y, z, α, β, γ), angles as SO3::toEulerXYZ.
  Vector6 toEulerXYZ6() const {
    Vector6 v;
    v.template head<3>() = r_;
    v.template tail<3>() = C_.toEulerXYZ();
    return v;
  }
  /// As fromEulerXYZ6 with the angles in degrees (translation unchanged; the dataset's labels).
  static SE3 fromEulerXYZ6Degrees(const Vector6& v) { return fromEulerXYZ6(poseDegToRad(v)); }
  Vector6 toEulerXYZ6Degrees() const { return poseRadToDeg(toEulerXYZ6()); }  ///< as toEulerXYZ6 with the angles in degrees

 private:
  // Barfoot's Q reduced with the skew-matrix identities (d = φᵀρ, x = θ², S = (φ^)² = φφᵀ − xI):
  //   φ^ρ^ = ρφᵀ − dI,  ρ^φ^ = φρᵀ − dI,  φ^ρ^φ^ = −d φ^,  φ^φ^ρ^ + ρ^φ^φ^ = −xρ^ − dφ^,
  //   φ^ρ^φ^φ^ + φ^φ^ρ^φ^ = −2d S,
  // so Q = ½ρ^ + C(ρφᵀ + φρᵀ − 2dI − dφ^) + E(2dφ^ − xρ^) − 2dF S: a few dozen flops instead of
  // seven 3×3 products, and the same value.
  static Matrix3 QWith(const Vector3& rho, const Vector3& phi, const detail::AngleTerms<Scalar>& t) {
    const Scalar c = detail::coeffC(t), e = detail::coeffE(t), f = detail::coeffF(t);
    const Scalar d = detail::dot(phi, rho), x = t.theta2;
    const Scalar two(Real(2));
    // symmetric part: C(ρφᵀ + φρᵀ − 2dI) − 2dF S
    Matrix3 Q = (-two * d * f) * SO3Type::skewSquared(phi);
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) Q(i, j) += c * (rho(i) * phi(j) + phi(i) * rho(j));
    const Scalar diag = -two * d * c;
    Q(0, 0) += diag;
    Q(1, 1) += diag;
    Q(2, 2) += diag;
    // skew part: (½ − E x) ρ^ + (2E − C) d φ^
    const Vector3 w = (Scalar(Real(0.5)) - e * x) * rho + ((two * e - c) * d) * phi;
    Q(0, 1) -= w(2);
    Q(1, 0) += w(2);
    Q(0, 2) += w(1);
    Q(2, 0) -= w(1);
    Q(1, 2) -= w(0);
    Q(2, 1) += w(0);
    return Q;
  }
  static Jacobian leftJacobianWith(const Vector3& rho, const Vector3& phi, const detail::AngleTerms<Scalar>& t) {
    Jacobian J;
    const Matrix3 Jr = SO3Type::leftJacobianWith(phi, t);
    J.template topLeftCorner<3, 3>() = Jr;
    J.template topRightCorner<3, 3>() = QWith(rho, phi, t);
    J.template bottomLeftCorner<3, 3>().setZero();
    J.template bottomRightCorner<3, 3>() = Jr;
    return J;
  }
  static Jacobian leftJacobianInverseWith(const Vector3& rho, const Vector3& phi,
                                          const detail::AngleTerms<Scalar>& t) {
    Jacobian J;
    const Matrix3 Ji = SO3Type::leftJacobianInverseWith(phi, t);
    J.template topLeftCorner<3, 3>() = Ji;
    J.template topRightCorner<3, 3>() = -(Ji * QWith(rho, phi, t) * Ji);
    J.template bottomLeftCorner<3, 3>().setZero();
    J.template bottomRightCorner<3, 3>() = Ji;
    return J;
  }
  SO3Type C_;
  Vector3 r_;
};

using SE3d = SE3<double>;  ///< SE(3) in double
using SE3f = SE3<float>;   ///< SE(3) in float

}  // namespace lieservo

#include <lieservo/detail/options_pop.hpp>

// lieservo/groups/so3.hpp — SO(3), the group of 3-D rotations, stored as a 3×3 rotation matrix C.
//
// Conventions (docs/conventions.md): tangent φ ∈ R³ (rotation vector, radians), left
// perturbation C = exp(δφ^) C̄, Ad(C) = C, ad(φ) = φ^, J = left Jacobian.
#pragma once
#include <lieservo/detail/options_push.hpp>

#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/SVD>

#include <lieservo/detail/flatten.hpp>
#include <lieservo/detail/finite.hpp>
#include <lieservo/status.hpp>
#include <lieservo/units.hpp>
#include <lieservo/groups/detail/coefficients.hpp>
#include <lieservo/groups/detail/generic.hpp>
#include <lieservo/groups/detail/ordered.hpp>
#include <lieservo/groups/lie_group_base.hpp>
#include <lieservo/groups/detail/rotation.hpp>

namespace lieservo {

template <typename Scalar_>
/// SO(3): a rotation of space, stored as its 3 × 3 matrix C. The tangent is φ (rad);
/// left perturbation C = exp(ε^) C̄ (docs/conventions.md).
class SO3 : public LieGroupBase<SO3<Scalar_>, Eigen::Matrix<Scalar_, 3, 1>, Eigen::Matrix<Scalar_, 3, 3>> {
 public:
  using Scalar = Scalar_;  ///< float, double or long double
  using Real = detail::RealOf<Scalar>;  ///< the real type behind Scalar
  static constexpr int DoF = 3;  ///< tangent dimension
  static constexpr int Dim = 3;  ///< dimension of the space it rotates
  static constexpr int RotationDoF = 3;  ///< rotational part of the tangent, its tail (ξ = [ρ; φ])
  using Tangent = Eigen::Matrix<Scalar, 3, 1>;  ///< φ, the rotation vector (rad)
  using Jacobian = Eigen::Matrix<Scalar, 3, 3>;  ///< DoF × DoF
  using Point = Eigen::Matrix<Scalar, 3, 1>;  ///< a point of space
  using Matrix = Eigen::Matrix<Scalar, 3, 3>;  ///< the rotation matrix
  using Vector3 = Eigen::Matrix<Scalar, 3, 1>;  ///< 3-vector
  using Matrix3 = Eigen::Matrix<Scalar, 3, 3>;  ///< 3 × 3 matrix
  using Quaternion = Eigen::Quaternion<Scalar>;  ///< Eigen's quaternion

  /// Identity rotation.
  SO3() : C_(Matrix3::Identity()) {}
  static SO3 identity() { return SO3(); }  ///< the identity

  // ---- group operations -----------------------------------------------------------------
  /// Composition: a plain matrix product (no hidden renormalisation; see normalize()).
  /// The result is written in place, not copied from a temporary: a copy reads back with
  /// vector loads what was just stored element-wise, and that store-to-load forwarding stall
  /// cost more than the product itself (the same in SE3).
  SO3 operator*(const SO3& o) const {
    SO3 r;
    detail::multiply3(C_, o.C_, r.C_);
    return r;
  }
  SO3& operator*=(const SO3& o) { return *this = *this * o; }  ///< *this = *this * o
  Point operator*(const Point& p) const { return detail::times(C_, p); }  ///< the rotated point C p
  /// The inverse rotation Cᵀ.
  SO3 inverse() const {
    SO3 r;
    r.C_ = C_.transpose();
    return r;
  }

  // ---- exp / log --------------------------------------------------------------------------
  /// exp(φ^) = I + (sinθ/θ) φ^ + ((1 − cosθ)/θ²) φ^φ^ (Rodrigues). Any |φ|. Up to a half
  /// turn no square root, sin/cos call or division is taken; every factor is a short series in
  /// x = θ²:
  ///  - for tiny angles the unit quaternion (w, v) = (cos(θ/2), (sin(θ/2)/θ) φ), three terms;
  ///  - elsewhere Rodrigues' A = sinθ/θ and B = (1 − cosθ)/θ² as series about the centre of
  ///    one of six equal pieces of [0, π²], or about π² itself near the half turn, where A
  ///    falls to 0 (detail::kExpPieceSeries): the series is picked by a table index computed
  ///    from x, not by a branch.
  /// Beyond a half turn, Rodrigues with one sin/cos of θ/2.
  // Inlined. The two branches go the same way for almost every angle of a set (tiny, or beyond
  // the half turn), so they are predicted; a branch between forms of similar cost would be
  // mispredicted half the time on angles spread over the half turn (docs/math.md, "SO(3) exp
  // up to a half turn").
  static LIESERVO_ALWAYS_INLINE SO3 exp(const Tangent& phi) {
    const Scalar x = detail::squaredNorm(phi);
    if (x < Scalar(Real(detail::halfAngleShortMaxX<Scalar>()))) {
      const auto kw = detail::lanesEval(detail::kHalfAngleShortSeries<Scalar>.a, x);
      return fromHalfAngle(phi, kw(0), kw(1));
    }
    if (!(x <= Scalar(Real(detail::kHalfAngleSeriesMaxX)))) return expWith(phi, detail::AngleTerms<Scalar>(x));
    const auto& p = detail::kExpPieceSeries<Scalar>;
    constexpr int h = detail::ExpPieces<Scalar>::kHalfTurn;
    const Scalar d_half_turn = (x - Scalar(p.hi[h])) - Scalar(p.lo[h]);
    int i = std::min(int(detail::realValue(x) * p.inv_width), detail::kExpPieces - 1);
    i = d_half_turn > -Scalar(p.half_turn_max_d) ? h : i;
    const auto AB = detail::lanesEval(p.a[i], (x - Scalar(p.hi[i])) - Scalar(p.lo[i]));
    return fromRodrigues(phi, x, AB(0), AB(1));
  }

  /// log(C)^∨ with θ = |φ| ∈ [0, π]: θ = atan2(sinθ, cosθ) from the antisymmetric part and the
  /// trace for θ < 2π/3, Shepperd's quaternion and θ = 2 atan2(|v|, w) beyond. At θ = π exactly
  /// the axis sign follows quaternionFromMatrix's rule (largest-magnitude component positive).
  /// In float near the identity (θ < 0.035 rad) a division-free series instead (docs/math.md).
  /// Accurate to a few ulp everywhere, including near π.
  LIESERVO_ALWAYS_INLINE Tangent log() const { return detail::rotationVectorFromMatrix(C_); }
  /// log(C)^∨ and the AngleTerms of θ = |φ| from the same work (for J(φ)⁻¹ and Q): no sin/cos.
  Tangent logWithTerms(detail::AngleTerms<Scalar>& terms) const {
    return detail::rotationVectorFromMatrix(C_, &terms);
  }

  /// φ^ (eq. 29, eqn:so3_hat_operator).
  static Matrix hat(const Tangent& phi) { return detail::skew(phi); }
  /// Inverse of hat: reads the skew-symmetric part (averaging the two copies of each entry).
  static Tangent vee(const Matrix& m) {
    const Scalar h(Real(0.5));
    return Tangent(h * (m(2, 1) - m(1, 2)), h * (m(0, 2) - m(2, 0)), h * (m(1, 0) - m(0, 1)));
  }

  /// Ad(C) = C (the rotation block of eq. 30 (eqn:se3_adjoint)).
  Jacobian Ad() const { return C_; }
  /// ad(φ) = φ^ (the rotation block of eq. 31 (eqn:se3_algebra_adjoint)).
  static Jacobian ad(const Tangent& phi) { return detail::skew(phi); }

  // ---- Jacobians ---------------------------------------------------------------------------
  /// Left Jacobian, closed form of eq. 33 (eqn:left_jacobian_def):
  /// J = I + ((1 − cosθ)/θ²) φ^ + ((θ − sinθ)/θ³) φ^φ^.
  static Jacobian leftJacobian(const Tangent& phi) {
    const detail::AngleTerms<Scalar> t(detail::squaredNorm(phi));
    return leftJacobianWith(phi, t);
  }
  /// Inverse left Jacobian, closed form of eq. 34 (eqn:inv_jacobian_def):
  /// J⁻¹ = I − ½ φ^ + (1/θ²)(1 − θ sinθ/(2(1 − cosθ))) φ^φ^  (singular at θ = 2π).
  static Jacobian leftJacobianInverse(const Tangent& phi) {
    const detail::AngleTerms<Scalar> t(detail::squaredNorm(phi));
    return leftJacobianInverseWith(phi, t);
  }
  /// exp(φ) and J(φ) sharing the trigonometric work.
  static SO3 expAndLeftJacobian(const Tangent& phi, Jacobian& J) {
    const detail::AngleTerms<Scalar> t(detail::squaredNorm(phi));
    J = leftJacobianWith(phi, t);
    return expWith(phi, t);
  }
  /// log(C) and J(log C)⁻¹ sharing the trigonometric work.
  Tangent logAndLeftJacobianInverse(Jacobian& Jinv) const {
    detail::AngleTerms<Scalar> t(Scalar(0));
    const Tangent phi = logWithTerms(t);
    Jinv = leftJacobianInverseWith(phi, t);
    return phi;
  }

  // ---- matrices and construction -----------------------------------------------------------
  Matrix matrix() const { return C_; }  ///< the rotation matrix C
  /// Read-only: a rotation changes only through the group operations and the checked or
  /// explicitly unchecked constructors (fromMatrix, fromMatrixUnchecked, ...).
  const Matrix3& rotationMatrix() const { return C_; }

  /// Unchecked fast path: C is taken as is (the caller guarantees C ∈ SO(3)).
  static SO3 fromMatrixUnchecked(const Matrix& C) {
    SO3 r;
    r.C_ = C;
    return r;
  }
  /// Default tolerance of fromMatrix on ‖CᵀC − I‖_F: √eps (1.5e-8 double, 3.5e-4 float).
  static Scalar defaultTolerance() {
    using std::sqrt;
    return Scalar(sqrt(Eigen::NumTraits<Real>::epsilon()));
  }
  /// Checked: finite, ‖CᵀC − I‖_F ≤ tol, det C > 0. `out` is untouched unless ok.
  static Status fromMatrix(const Matrix& C, SO3& out) noexcept { return fromMatrix(C, out, defaultTolerance()); }
  /// As the overload above, with the tolerance on ‖CᵀC − I‖_F given.
  /// A negative or non-finite tolerance: invalid_argument.
  static Status fromMatrix(const Matrix& C, SO3& out, Scalar tol) noexcept {
    if (!detail::validTolerance(tol)) return Status::invalid_argument;
    const Status s = check(C, tol);
    if (s == Status::ok) out.C_ = C;
    return s;
  }
  /// fromMatrix's checks of the stored matrix at the default tolerance (validateElement):
  /// ok, non_finite_input or not_orthonormal, without a copy.
  LIESERVO_ALWAYS_INLINE Status validate() const noexcept { return check(C_, defaultTolerance()); }
  /// Nearest rotation in the Frobenius norm (SVD: U diag(1, 1, det(UVᵀ)) Vᵀ). Rejects
  /// non-finite input and matrices of rank < 2 (nearest rotation not unique).
  static Status fromMatrixProjected(const Matrix& M, SO3& out) noexcept {
    if (!M.allFinite()) return Status::non_finite_input;
    Eigen::JacobiSVD<Matrix3> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
    const Vector3 s = svd.singularValues();  // descending
    if (!(s(1) > Scalar(Real(16)) * Eigen::NumTraits<Real>::epsilon() * s(0))) return Status::invalid_argument;
    Matrix3 D = Matrix3::Identity();
    D(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < Scalar(0) ? Scalar(-1) : Scalar(1);
    Matrix3 C = svd.matrixU() * D * svd.matrixV().transpose();
    if (!C.allFinite()) return Status::numerical_failure;
    SO3 r = fromMatrixUnchecked(C);
    r.normalize();
    out = r;
    return Status::ok;
  }

  /// Cheap re-orthonormalisation (a few flops, no SVD): the first two columns are
  /// symmetrically decorrelated and normalised, the third is their cross product. Restores
  /// ‖CᵀC − I‖ to ~eps from a drift of up to ~1e-3. Composition never calls it implicitly.
  LIESERVO_ALWAYS_INLINE void normalize() noexcept {
    using std::sqrt;
    Vector3 x = C_.col(0), y = C_.col(1);
    const Scalar e = detail::dot(x, y) * Scalar(Real(0.5));
    const Vector3 x2 = x - e * y;
    const Vector3 y2 = y - e * x;
    const Scalar nx = detail::norm(x2);
    for (int i = 0; i < 3; ++i) x(i) = detail::quotient(x2(i), nx);
    y = y2 - detail::dot(x, y2) * x;
    const Scalar ny = detail::norm(y);
    for (int i = 0; i < 3; ++i) y(i) = detail::quotient(y(i), ny);
    C_.col(0) = x;
    C_.col(1) = y;
    C_.col(2) = x.cross(y);
  }
  bool allFinite() const noexcept { return detail::allFinite(C_); }  ///< whether every entry of C is finite
  /// ‖C1 − C2‖_F ≤ tol.
  bool isApprox(const SO3& o, Scalar tol) const { return (C_ - o.C_).norm() <= tol; }

  /// The same rotation in another scalar type.
  template <class NewScalar>
  SO3<NewScalar> cast() const {
    return SO3<NewScalar>::fromMatrixUnchecked(C_.template cast<NewScalar>());
  }

  /// Uniformly distributed rotation (Haar measure) from a unit quaternion (Shoemake).
  template <class Rng>
  static SO3 sampleUniform(Rng& rng) {
    const Eigen::Vector4d q = detail::uniformQuaternion(rng);
    return fromQuaternion(Quaternion(Scalar(q(0)), Scalar(q(1)), Scalar(q(2)), Scalar(q(3))));
  }

  // ---- conversions --------------------------------------------------------------------------
  /// Unit quaternion with w ≥ 0 (sign rule at w = 0 as in log()).
  Quaternion unitQuaternion() const {
    const Eigen::Matrix<Scalar, 4, 1> q = detail::quaternionFromMatrix(C_);
    return Quaternion(q(0), q(1), q(2), q(3));
  }
  /// From any non-zero quaternion (normalised here; unchecked for zero/non-finite).
  static SO3 fromQuaternion(const Quaternion& q) {
    const Scalar w = q.w(), x = q.x(), y = q.y(), z = q.z();
    const Scalar n2 = w * w + x * x + y * y + z * z;
    const Scalar two(Real(2));
    const Scalar s = detail::quotient(two, n2);
    Matrix3 C;
    C(0, 0) = Scalar(1) - s * (y * y + z * z);
    C(0, 1) = s * (x * y - w * z);
    C(0, 2) = s * (x * z + w * y);
    C(1, 0) = s * (x * y + w * z);
    C(1, 1) = Scalar(1) - s * (x * x + z * z);
    C(1, 2) = s * (y * z - w * x);
    C(2, 0) = s * (x * z - w * y);
    C(2, 1) = s * (y * z + w * x);
    C(2, 2) = Scalar(1) - s * (x * x + y * y);
    return fromMatrixUnchecked(C);
  }

  /// Extrinsic x-y-z Euler angles (radians): C = Rz(γ) Ry(β) Rx(α) (scipy "xyz", tf "sxyz").
  static SO3 fromEulerXYZ(Scalar a, Scalar b, Scalar g) {
    using std::cos;
    using std::sin;
    const Scalar ca = cos(a), sa = sin(a), cb = cos(b), sb = sin(b), cg = cos(g), sg = sin(g);
    Matrix3 C;
    C(0, 0) = cg * cb;
    C(0, 1) = cg * sb * sa - sg * ca;
    C(0, 2) = cg * sb * ca + sg * sa;
    C(1, 0) = sg * cb;
    C(1, 1) = sg * sb * sa + cg * ca;
    C(1, 2) = sg * sb * ca - cg * sa;
    C(2, 0) = -sb;
    C(2, 1) = cb * sa;
    C(2, 2) = cb * ca;
    return fromMatrixUnchecked(C);
  }
  static SO3 fromEulerXYZ(const Vector3& abg) { return fromEulerXYZ(abg(0), abg(1), abg(2)); }  ///< fromEulerXYZ(α, β, γ) from one vector
  /// (α, β, γ) with β ∈ [−π/2, π/2], α, γ ∈ (−π, π]. At gimbal lock (cos β ≈ 0) γ = 0.
  Vector3 toEulerXYZ() const {
    using std::atan2;
    using std::sqrt;
    const Scalar cb = sqrt(C_(0, 0) * C_(0, 0) + C_(1, 0) * C_(1, 0));
    const Scalar b = atan2(-C_(2, 0), cb);
    if (cb > Scalar(Real(16)) * Eigen::NumTraits<Real>::epsilon()) {
      return Vector3(atan2(C_(2, 1), C_(2, 2)), b, atan2(C_(1, 0), C_(0, 0)));
    }
    return Vector3(atan2(-C_(1, 2), C_(1, 1)), b, Scalar(0));
  }
  /// fromEulerXYZ with the angles in degrees (for labels and presets at the edges).
  static SO3 fromEulerXYZDegrees(Scalar a, Scalar b, Scalar g) {
    return fromEulerXYZ(deg2rad(a), deg2rad(b), deg2rad(g));
  }
  static SO3 fromEulerXYZDegrees(const Vector3& abg) { return fromEulerXYZDegrees(abg(0), abg(1), abg(2)); }  ///< the same from one vector (degrees)
  /// toEulerXYZ in degrees.
  Vector3 toEulerXYZDegrees() const {
    const Vector3 r = toEulerXYZ();
    return Vector3(rad2deg(r(0)), rad2deg(r(1)), rad2deg(r(2)));
  }

  // ---- shared-trig kernels (public for SE(3); not part of the contract) ------------------
  /// Kernel shared with SE3 (not part of the contract): exp from precomputed angle terms.
  static SO3 expWith(const Tangent& phi, const detail::AngleTerms<Scalar>& t) {
    return rodrigues(phi, t.theta2, detail::coeffA(t), detail::coeffB(t));
  }
  /// I + A φ^ + B φ^φ^ for A = sinθ/θ, B = (1 − cosθ)/θ², x = θ² = |φ|².
  static SO3 rodrigues(const Tangent& phi, const Scalar& x, const Scalar& A, const Scalar& B) {
    // φ^φ^ = φφᵀ − θ² I.
    Matrix3 C = (B * phi) * phi.transpose();
    const Scalar d = Scalar(1) - B * x;
    C(0, 0) += d;
    C(1, 1) += d;
    C(2, 2) += d;
    const Vector3 a = A * phi;
    C(0, 1) -= a(2);
    C(1, 0) += a(2);
    C(0, 2) += a(1);
    C(2, 0) -= a(1);
    C(1, 2) -= a(0);
    C(2, 1) += a(0);
    return fromMatrixUnchecked(C);
  }
  /// I + A φ^ + B φ^φ^ for x = θ² = |φ|² (detail::matrixFromRodrigues).
  static LIESERVO_ALWAYS_INLINE SO3 fromRodrigues(const Tangent& phi, const Scalar& x, const Scalar& A, const Scalar& B) {
    SO3 r;
    detail::matrixFromRodrigues(phi, x, A, B, r.C_);
    return r;
  }
  /// The rotation of the unit quaternion (w, v), v = k φ (detail::matrixFromHalfAngle).
  static SO3 fromHalfAngle(const Tangent& phi, const Scalar& k, const Scalar& w) {
    SO3 r;
    detail::matrixFromHalfAngle(phi, k, w, r.C_);
    return r;
  }
  /// Kernel shared with SE3 (not part of the contract): J(φ) from precomputed angle terms.
  static Jacobian leftJacobianWith(const Tangent& phi, const detail::AngleTerms<Scalar>& t) {
    return identityPlus(phi, detail::coeffB(t), detail::coeffC(t));
  }
  /// Kernel shared with SE3 (not part of the contract): J(φ)⁻¹ from precomputed angle terms.
  static Jacobian leftJacobianInverseWith(const Tangent& phi, const detail::AngleTerms<Scalar>& t) {
    return identityPlus(phi, Scalar(Real(-0.5)), detail::coeffD(t));
  }
  /// (φ^)² = φφᵀ − θ²I, with the diagonal −(φ_j² + φ_k²) summed directly (no cancellation).
  static Matrix3 skewSquared(const Tangent& phi) {
    const Scalar xx = phi(0) * phi(0), yy = phi(1) * phi(1), zz = phi(2) * phi(2);
    const Scalar xy = phi(0) * phi(1), xz = phi(0) * phi(2), yz = phi(1) * phi(2);
    Matrix3 m;
    m(0, 0) = -(yy + zz);
    m(1, 1) = -(xx + zz);
    m(2, 2) = -(xx + yy);
    m(0, 1) = m(1, 0) = xy;
    m(0, 2) = m(2, 0) = xz;
    m(1, 2) = m(2, 1) = yz;
    return m;
  }
  /// I + a φ^ + b (φ^)², entry by entry (the form of J, J⁻¹ and exp).
  static Matrix3 identityPlus(const Tangent& phi, const Scalar& a, const Scalar& b) {
    Matrix3 m = b * skewSquared(phi);
    m(0, 0) += Scalar(1);
    m(1, 1) += Scalar(1);
    m(2, 2) += Scalar(1);
    const Vector3 ap = a * phi;
    m(0, 1) -= ap(2);
    m(1, 0) += ap(2);
    m(0, 2) += ap(1);
    m(2, 0) -= ap(1);
    m(1, 2) -= ap(0);
    m(2, 1) += ap(0);
    return m;
  }

 private:
  // Finite, ‖CᵀC − I‖_F ≤ tol, det C > 0 (fromMatrix, validate).
  LIESERVO_ALWAYS_INLINE static Status check(const Matrix& C, Scalar tol) noexcept {
    if (!detail::allFinite(C)) return Status::non_finite_input;
    // ‖CᵀC − I‖_F² from the columns' dot products (CᵀC is symmetric: each off-diagonal entry
    // twice), written out because GCC calls a function per entry of Eigen's 3×3 CᵀC.
    const Vector3 c0 = C.col(0), c1 = C.col(1), c2 = C.col(2);
    const Scalar d0 = c0.squaredNorm() - Scalar(Real(1)), d1 = c1.squaredNorm() - Scalar(Real(1)),
                 d2 = c2.squaredNorm() - Scalar(Real(1));
    const Scalar o01 = c0.dot(c1), o02 = c0.dot(c2), o12 = c1.dot(c2);
    const Scalar e2 = d0 * d0 + d1 * d1 + d2 * d2 + Scalar(Real(2)) * (o01 * o01 + o02 * o02 + o12 * o12);
    if (!(e2 <= tol * tol)) return Status::not_orthonormal;
    if (!(C.determinant() > Scalar(0))) return Status::not_orthonormal;
    return Status::ok;
  }
  template <class>
  friend class SE3;  // composes and inverts into its own rotation in place (no temporaries)
  Matrix3 C_;
};

using SO3d = SO3<double>;  ///< SO(3) in double
using SO3f = SO3<float>;   ///< SO(3) in float

}  // namespace lieservo

#include <lieservo/detail/options_pop.hpp>

// lieservo/estimation/detail/linalg.hpp — small fixed-size linear-algebra helpers of the
// estimators: covariance checks, Cholesky factors, group-element validation.
// Everything here is noexcept and allocation-free (fixed-size Eigen, no dynamic storage).
#pragma once
#include <lieservo/detail/options_push.hpp>

#include <cmath>
#include <limits>

#include <Eigen/Core>

#include <lieservo/detail/finite.hpp>
#include <lieservo/groups/perturbation.hpp>
#include <lieservo/status.hpp>

namespace lieservo {
namespace detail {

/// Number of rotational degrees of freedom of G (G::RotationDoF: 1 for SO(2)/SE(2), 3 for
/// SO(3)/SE(3)): by the library's convention ξ = [ρ; φ], the rotation is the tail of the tangent.
template <class G>
constexpr int rotationDoF() noexcept {
  return G::RotationDoF;
}

/// Rotation angle |φ| of a tangent vector ξ = [ρ; φ].
template <class G>
typename G::Scalar rotationAngle(const typename G::Tangent& xi) noexcept {
  return xi.template tail<rotationDoF<G>()>().norm();
}

/// Relative tolerance used for the symmetry check of an input covariance:
/// |S_ij − S_ji| ≤ tol · sqrt(S_ii) sqrt(S_jj), tol = sqrt(eps) (1.5e-8 double, 3.5e-4 float).
template <class Scalar>
Scalar symmetryTolerance() noexcept {
  return std::sqrt(std::numeric_limits<Scalar>::epsilon());
}

/// Smallest accepted ratio L_ii² / S_ii of a Cholesky pivot to its diagonal entry (the
/// conditional variance over the marginal one, 1 − R² for a pair): below it the matrix is
/// numerically singular. 64 eps (1.4e-14 double, 7.6e-6 float).
template <class Scalar>
Scalar pivotTolerance() noexcept {
  return Scalar(64) * std::numeric_limits<Scalar>::epsilon();
}


/// Checks that S is finite and symmetric positive-definite, and returns the lower Cholesky
/// factor L of its symmetric part (S_sym = L Lᵀ). Status: ok, non_finite_input, not_spd, or
/// numerical_failure (the factor overflows on rescaling). L is not written on non_finite_input
/// or not_spd; on numerical_failure it holds the non-finite factor. L may alias S.
template <class Mat>
Status choleskyChecked(const Mat& S, Mat& L) noexcept {
  using Scalar = typename Mat::Scalar;
  constexpr int n = Mat::RowsAtCompileTime;
  static_assert(n > 0 && n == Mat::ColsAtCompileTime, "fixed-size square matrix expected");
  if (!allFinite(S)) return Status::non_finite_input;
  // Every loop is unrolled in full (n ≤ 6 here), so that the factor's entries stay in registers:
  // rolled, each column's pivot waits on entries stored and loaded again.
  Scalar sd[n];
#pragma GCC unroll 6
  for (int i = 0; i < n; ++i) {
    if (!(S(i, i) > Scalar(0))) return Status::not_spd;
    sd[i] = std::sqrt(S(i, i));
  }
  const Scalar tol = symmetryTolerance<Scalar>();
  bool symmetric = true;  // one branch for the whole test
#pragma GCC unroll 6
  for (int j = 0; j < n; ++j)
#pragma GCC unroll 6
    for (int i = j + 1; i < n; ++i) symmetric &= std::abs(S(i, j) - S(j, i)) <= tol * sd[i] * sd[j];
  if (!symmetric) return Status::not_spd;
  // Equilibrate: D S D with D = diag(1/sqrt(S_ii)) has a unit diagonal, so the pivot test
  // below is scale-free. Cholesky commutes with diagonal scaling: L = D⁻¹ chol(D S D).
  Scalar inv_sd[n];
#pragma GCC unroll 6
  for (int i = 0; i < n; ++i) inv_sd[i] = Scalar(1) / sd[i];
  // Cholesky in LDLᵀ form on the equilibrated matrix (lower triangle of the symmetric part),
  // every pivot d_j = L_jj² checked against pivotTolerance. Each column waits on one reciprocal
  // 1/d_j, where the LLᵀ form waits on a square root and then a reciprocal; the six square
  // roots L_jj = √d_j are independent and taken at the end. Written out: Eigen's LDLT pivots
  // (so its factor is not the Cholesky factor) and LLT also computes an unused L1 norm.
  // U(i, k) = L̃(i, k) d_k is kept beside the unit-lower L̃.
  Scalar Lt[n][n], U[n][n], dv[n];
  const Scalar ptol = pivotTolerance<Scalar>();
#pragma GCC unroll 6
  for (int j = 0; j < n; ++j) {
    Scalar d = Scalar(1);  // the equilibrated diagonal
#pragma GCC unroll 6
    for (int k = 0; k < j; ++k) d -= Lt[j][k] * U[j][k];
    if (!(d >= ptol)) return Status::not_spd;  // also catches NaN
    dv[j] = d;
    const Scalar inv_d = Scalar(1) / d;
#pragma GCC unroll 6
    for (int i = j + 1; i < n; ++i) {
      Scalar v = (Scalar(0.5) * (S(i, j) + S(j, i)) * inv_sd[i]) * inv_sd[j];
#pragma GCC unroll 6
      for (int k = 0; k < j; ++k) v -= Lt[i][k] * U[j][k];
      U[i][j] = v;
      Lt[i][j] = v * inv_d;
    }
  }
  // L = D⁻¹ L̃ diag(√d), written in place (S is not read again): a local factor copied out
  // would cost a sixth of the factorisation.
#pragma GCC unroll 6
  for (int j = 0; j < n; ++j) {
    const Scalar ljj = std::sqrt(dv[j]);
#pragma GCC unroll 6
    for (int i = 0; i < j; ++i) L(i, j) = Scalar(0);
    L(j, j) = ljj * sd[j];
#pragma GCC unroll 6
    for (int i = j + 1; i < n; ++i) L(i, j) = (Lt[i][j] * ljj) * sd[i];
  }
  if (!allFinite(L)) return Status::numerical_failure;
  return Status::ok;
}

/// Checks a covariance matrix (finite, symmetric, positive-definite).
template <class Mat>
Status checkSpd(const Mat& S) noexcept {
  Mat L;
  return choleskyChecked(S, L);
}

/// Whether the symmetric A (its lower triangle is read) is positive-definite: every pivot of
/// its unpivoted Cholesky factorisation A = L Lᵀ is > 0, the test of Eigen's LLT. Written out:
/// Eigen's LLT compiles its blocked path (triangular solves, rank updates) even for a fixed
/// 6 × 6, about 2 s of each includer's translation unit per matrix type. Not choleskyChecked:
/// its pivot floor (64 eps on the equilibrated matrix) is a stricter test than pivots > 0.
template <class Mat>
bool choleskyPivotsPositive(const Mat& A) noexcept {
  using Scalar = typename Mat::Scalar;
  constexpr int n = Mat::RowsAtCompileTime;
  Scalar L[n][n];
  for (int j = 0; j < n; ++j) {
    Scalar d = A(j, j);
    for (int k = 0; k < j; ++k) d -= L[j][k] * L[j][k];
    if (!(d > Scalar(0))) return false;  // NaN too
    const Scalar inv_ljj = Scalar(1) / std::sqrt(d);
    for (int i = j + 1; i < n; ++i) {
      Scalar v = A(i, j);
      for (int k = 0; k < j; ++k) v -= L[i][k] * L[j][k];
      L[i][j] = v * inv_ljj;
    }
  }
  return true;
}

/// Checks a matrix that may be positive semi-definite (e.g. process noise, which may be 0):
/// finite, symmetric (absolute+relative tolerance) and no eigenvalue below −sqrt(eps)·max|S_ii|.
template <class Mat>
Status checkPsd(const Mat& S) noexcept {
  using Scalar = typename Mat::Scalar;
  constexpr int n = Mat::RowsAtCompileTime;
  if (!S.allFinite()) return Status::non_finite_input;
  Scalar dmax = Scalar(0);
  for (int i = 0; i < n; ++i) {
    if (S(i, i) < Scalar(0)) return Status::not_spd;
    dmax = std::max(dmax, S(i, i));
  }
  const Scalar tol = symmetryTolerance<Scalar>();
  for (int j = 0; j < n; ++j)
    for (int i = j + 1; i < n; ++i) {
      if (!(std::abs(S(i, j) - S(j, i)) <= tol * std::sqrt(S(i, i)) * std::sqrt(S(j, j))))
        return Status::not_spd;
    }
  if (dmax == Scalar(0)) return S.isZero(Scalar(0)) ? Status::ok : Status::not_spd;
  // Shift by a small multiple of the largest diagonal entry and test definiteness. Halves
  // first: exactly 0.5 (S + Sᵀ), without its overflow for entries above half the largest float.
  Mat shifted = Scalar(0.5) * S + Scalar(0.5) * S.transpose();
  shifted.diagonal().array() += tol * dmax;
  return choleskyPivotsPositive(shifted) ? Status::ok : Status::not_spd;
}

/// Forward substitution, in place: B ← L⁻¹ B for a lower-triangular fixed-size L (only the
/// lower triangle is read). Written out (rather than Eigen's triangularView().solve()) to keep
/// the code path small, obviously allocation-free and free of spurious GCC warnings; one
/// division per row, not per entry.
template <class MatL, class MatB>
void lowerSolveInPlace(const MatL& L, MatB& B) noexcept {
  constexpr int n = MatL::RowsAtCompileTime;
  typename MatL::Scalar inv_diag[n];
  for (int i = 0; i < n; ++i) inv_diag[i] = typename MatL::Scalar(1) / L(i, i);
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < i; ++k) B.row(i) -= L(i, k) * B.row(k);
    B.row(i) *= inv_diag[i];
  }
}

/// L⁻¹ of a lower-triangular fixed-size L (only the lower triangle is read): lower triangular.
/// Entry by entry with the loops unrolled (n ≤ 6 here), the reciprocals of the diagonal first:
/// independent divisions overlap, and GCC keeps row operations on dynamic-length heads rolled.
template <class Mat>
Mat lowerTriangularInverse(const Mat& L) noexcept {
  using Scalar = typename Mat::Scalar;
  constexpr int n = Mat::RowsAtCompileTime;
  Scalar inv[n];
#pragma GCC unroll 6
  for (int i = 0; i < n; ++i) inv[i] = Scalar(1) / L(i, i);
  Mat W = Mat::Zero();
#pragma GCC unroll 6
  for (int i = 0; i < n; ++i) {
    W(i, i) = inv[i];
    // W(i, j) = −(Σ_{j≤k<i} L(i,k) W(k, j)) / L(i,i); columns > i stay zero.
#pragma GCC unroll 6
    for (int j = 0; j < i; ++j) {
      Scalar sum(0);
#pragma GCC unroll 6
      for (int k = j; k < i; ++k) sum += L(i, k) * W(k, j);
      W(i, j) = -sum * inv[i];
    }
  }
  return W;
}

/// Back substitution, in place: B ← R⁻¹ B for an upper-triangular fixed-size R (only the upper
/// triangle is read).
template <class MatR, class MatB>
void upperSolveInPlace(const MatR& R, MatB& B) noexcept {
  constexpr int n = MatR::RowsAtCompileTime;
  // The reciprocals first: independent divisions overlap, instead of one per row in the chain.
  typename MatR::Scalar inv_diag[n];
  for (int i = 0; i < n; ++i) inv_diag[i] = typename MatR::Scalar(1) / R(i, i);
  for (int i = n - 1; i >= 0; --i) {
    for (int k = i + 1; k < n; ++k) B.row(i) -= R(i, k) * B.row(k);
    B.row(i) *= inv_diag[i];
  }
}

/// R x for an upper-triangular fixed-size R (only the upper triangle is read). Written out:
/// Eigen's triangularView product runs through its run-time-sized triangular matrix-vector
/// kernel, compiled for every includer even at fixed size (3-7 % of the README loop's build).
template <class MatR, class Vec>
Vec upperTimes(const MatR& R, const Vec& x) noexcept {
  constexpr int n = MatR::RowsAtCompileTime;
  Vec y;
  for (int i = 0; i < n; ++i) {
    typename MatR::Scalar sum = R(i, i) * x(i);
    for (int k = i + 1; k < n; ++k) sum += R(i, k) * x(k);
    y(i) = sum;
  }
  return y;
}

/// R⁻¹ of an upper-triangular fixed-size R (only the upper triangle is read): upper triangular.
template <class Mat>
Mat upperTriangularInverse(const Mat& R) noexcept {
  constexpr int n = Mat::RowsAtCompileTime;
  Mat U = Mat::Zero();
  for (int i = n - 1; i >= 0; --i) {
    const typename Mat::Scalar inv = typename Mat::Scalar(1) / R(i, i);
    U(i, i) = inv;
    for (int k = i + 1; k < n; ++k) U.row(i).tail(n - 1 - i) -= R(i, k) * U.row(k).tail(n - 1 - i);
    U.row(i).tail(n - 1 - i) *= inv;
  }
  return U;
}

/// Symmetrises in place: S ← ½ (S + Sᵀ).
template <class Mat>
void symmetrize(Mat& S) noexcept {
  constexpr int n = Mat::RowsAtCompileTime;
#pragma GCC unroll 6
  for (int j = 0; j < n; ++j)
#pragma GCC unroll 6
    for (int i = j + 1; i < n; ++i) {
      const auto m = (S(i, j) + S(j, i)) * typename Mat::Scalar(0.5);
      S(i, j) = m;
      S(j, i) = m;
    }
}

/// Relative diagonal load used by repairSpd: 1024 eps (2.3e-13 double, 1.2e-4 float).
template <class Scalar>
Scalar spdRepairLoad() noexcept {
  return Scalar(1024) * std::numeric_limits<Scalar>::epsilon();
}

/// Makes a computed covariance usable: symmetrises it and, if rounding has made it fail the
/// SPD test (which happens when its condition number in a non-axis-aligned basis exceeds
/// ~1/eps — e.g. variances spanning 1e-12..1e12 mixed by a Jacobian), adds the conservative
/// relative diagonal load S_ii ← S_ii (1 + spdRepairLoad()) and tests again. The load changes
/// each variance by at most 2.3e-13 (double) relative. Status: ok, or numerical_failure
/// (non-finite, non-positive diagonal, or still not SPD). `chol` (optional) receives the lower
/// Cholesky factor of the returned S, which the SPD test computes anyway.
template <class Mat>
Status repairSpd(Mat& S, Mat* chol = nullptr) noexcept {
  symmetrize(S);
  if (!allFinite(S)) return Status::numerical_failure;
  Mat L;
  // choleskyChecked writes its factor only on success: straight into *chol when it is wanted.
  if (choleskyChecked(S, chol ? *chol : L) == Status::ok) return Status::ok;
  constexpr int n = Mat::RowsAtCompileTime;
  Mat loaded = S;
  const auto load = spdRepairLoad<typename Mat::Scalar>();
  for (int i = 0; i < n; ++i) {
    if (!(S(i, i) > 0)) return Status::numerical_failure;
    loaded(i, i) += load * S(i, i);
  }
  if (!allFinite(loaded) || choleskyChecked(loaded, L) != Status::ok)
    return Status::numerical_failure;
  S = loaded;
  if (chol) *chol = L;
  return Status::ok;
}

}  // namespace detail
}  // namespace lieservo

#include <lieservo/detail/options_pop.hpp>

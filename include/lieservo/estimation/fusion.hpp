// lieservo/estimation/fusion.hpp — probabilistic data fusion of concentrated Gaussians on a
// Lie group G: the normalised product p*(X) ∝ Π_i p_i(X) (Appendix C,
// sec:se3_probabilistic_fusion), computed by the fixed-point iteration of
// Algorithm 3 (alg:se3_data_fusion):
//
//     X̄ ← X̄_1                                              (operating point)
//     repeat:  ξ_i = ln(X̄ X̄_i⁻¹)^∨,  J_i⁻¹ = J(ξ_i)⁻¹            (policy: series of order N or closed form)
//              Σ   = (Σ_i J_i⁻ᵀ Σ_i⁻¹ J_i⁻¹)⁻¹
//              μ   = −Σ Σ_i J_i⁻ᵀ Σ_i⁻¹ ξ_i
//              X̄  ← exp(μ^) X̄                                 (eq. 54, eqn:se3_normalised_prod_update)
//     return (X̄, Σ)
//
// Numerics (docs/estimation.md). Each Σ_i is Cholesky-factorised ONCE per call (Σ_i = L_i L_iᵀ,
// after an equilibrating diagonal scaling) and L_i⁻¹ formed once (triangular). Per iteration
// the whitened factor rows are A_i = L_i⁻¹ J_i⁻¹ and b_i = L_i⁻¹ ξ_i (products), so that
// H = Σ_i A_iᵀA_i is the information matrix and g = Σ_i A_iᵀb_i. Two forms solve H μ = −g:
//
// FusionForm::information (default): H and g are formed and H is inverted explicitly, by 3×3
// blocks after a diagonal equilibration (detail::spdInverse): two divisions in the chain, where
// a factorisation waits on six square roots and six divisions in turn, and the last iteration's
// H⁻¹ is Σ*. H's condition number is the square of the square-root form's, so the explicit
// inverse is used only while the equilibrated H is well conditioned (trace of its inverse
// ≤ informationTraceLimit(): condition number ≤ 6000 for SE(3)); otherwise the whole call is
// handed to the square-root form, and the result is exactly that form's.
//
// FusionForm::square_root: the rows [A_i | b_i] are stacked and reduced by Householder
// reflections to an upper-triangular R with RᵀR = H (never formed) and c = Qᵀb, so μ = −R⁻¹c
// and Σ* = R⁻¹R⁻ᵀ. The condition number is never squared (covariance eigenvalues anywhere in
// [1e-12, 1e12] stay representable).
//
// Both are allocation-free (fixed-size storage for up to kMaxFusionFactors factors), and the
// result is symmetrised and checked to be SPD (a rounding-level loss of definiteness is
// repaired by a relative diagonal load of 1024 eps), except where the information form's
// explicit inverse is SPD by its own certificate (detail::spdInverseCertified: always in
// double), which makes the check redundant.
#pragma once
#include <lieservo/detail/options_push.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Core>
#include <Eigen/LU>

#include <lieservo/detail/flatten.hpp>
#include <lieservo/status.hpp>
#include <lieservo/units.hpp>
#include <lieservo/estimation/concentrated_gaussian.hpp>
#include <lieservo/estimation/detail/linalg.hpp>
#include <lieservo/estimation/jacobian_policy.hpp>

namespace lieservo {

/// How fuse() solves each iteration's normal equations (see the file comment).
enum class FusionForm {
  /// Whitened rows reduced by Householder reflections; the condition number is not squared.
  square_root,
  /// H = Σ A_iᵀA_i formed and inverted by blocks while it is well conditioned, the square-root
  /// form otherwise (the default: faster, and as accurate where it matters).
  information,
};

/// The most operating-point updates fuse() accepts: each costs about a seventh of the paper's
/// filter step, and in tolerance mode realistic inputs converge within 4; a larger bound would
/// only let a mistyped option stall a real-time loop.
inline constexpr int kMaxFusionIterations = 100;

/// Iteration control of fuse(): the paper's fixed count, or the converged rule.
template <class Scalar>
struct FusionOptions {
  /// Upper bound on the number of operating-point updates, in [1, kMaxFusionIterations]. The
  /// paper runs exactly 5 ("real-time mode": tolerance = 0 → always max_iterations updates,
  /// predictable timing). One update is a single linearisation at the first factor's mean,
  /// slightly over-confident at large rotation noise (docs/estimation.md, "Reading").
  int max_iterations = 5;
  /// The converged rule, if > 0: stop as soon as an update μ is shorter than `tolerance`
  /// standard deviations of the fused estimate, √(μᵀ Σ*⁻¹ μ) with Σ*⁻¹ the information of the
  /// same linearisation. Dimensionless: a step in mm and one in rad are each weighed by their
  /// own uncertainty (FusionResult::step_sigmas). Finite, ≥ 0; 0 = the fixed count.
  Scalar tolerance = Scalar(0);
  /// With tolerance > 0: whether max_iterations updates without meeting it is an error
  /// (Status::not_converged, for a reference that must converge) or returns the last update
  /// with ok (converged(): a step time bounded by max_iterations).
  bool require_convergence = true;
  /// Information (default, with its fall-back to the square-root form) or square-root form of
  /// each iteration's solve.
  FusionForm form = FusionForm::information;

  /// ok, or the first reason the options are refused: invalid_argument (max_iterations out of
  /// [1, kMaxFusionIterations], a negative tolerance, an unknown form), non_finite_input (a
  /// tolerance that is NaN or infinite).
  Status validate() const noexcept {
    if (max_iterations < 1 || max_iterations > kMaxFusionIterations) return Status::invalid_argument;
    if (!std::isfinite(tolerance)) return Status::non_finite_input;
    if (tolerance < Scalar(0)) return Status::invalid_argument;
    if (form != FusionForm::square_root && form != FusionForm::information) return Status::invalid_argument;
    return Status::ok;
  }

  /// The paper's fusion: exactly 5 updates (Algorithm 3 as the paper runs it).
  static FusionOptions paper() noexcept { return FusionOptions(); }
  /// The converged rule: stop once an update is under `tol` standard deviations, after at most
  /// `max` updates (never more work than the paper's 5; docs/estimation.md, "Stopping rule").
  static FusionOptions converged(Scalar tol = Scalar(0.001), int max = 5) noexcept {
    FusionOptions o;
    o.max_iterations = max;
    o.tolerance = tol;
    o.require_convergence = false;
    return o;
  }
};

/// The outcome of fuse().
template <class G>
struct FusionResult {
  ConcentratedGaussian<G> fused;  ///< (X̄*, Σ*): the normalised product
  int iterations = 0;             ///< operating-point updates performed
  /// ‖μ‖₂ of the last update (tangent units as given: e.g. mm and rad mixed, as in the paper).
  typename G::Scalar step_norm = typename G::Scalar(0);
  /// √(μᵀ Σ*⁻¹ μ) of the last update: its length in standard deviations of the result, what
  /// FusionOptions::tolerance compares. With the fixed count (tolerance = 0) the only sign of
  /// an iteration that has not settled: factors far outside the concentrated regime
  /// (rotational σ ≫ 1 rad) can make it wander (docs/performance_design.md, the hard set), and
  /// the result is still returned with ok.
  typename G::Scalar step_sigmas = typename G::Scalar(0);
  /// Whether the converged rule (tolerance > 0) was met; false with the fixed count.
  bool converged = false;
  /// Largest rotation angle |φ| (rad) of ξ_i = ln(X̄_1 X̄_i⁻¹)^∨ at the initial operating point:
  /// how far apart the factor means are in rotation (the concentrated-Gaussian assumption
  /// wants this small compared with π).
  typename G::Scalar max_rotation_separation = typename G::Scalar(0);
};

/// Most factors one fuse() call accepts (fixed-size scratch storage).
inline constexpr int kMaxFusionFactors = 16;

/// Two factor means whose relative rotation is within this margin (rad) of π lie on the cut
/// locus of ln: the geodesic between them is not unique and fuse() returns invalid_argument.
/// 8 sqrt(eps): 1.2e-7 rad for double, 2.8e-3 rad for float.
template <class Scalar>
Scalar cutLocusMargin() noexcept {
  return Scalar(8) * std::sqrt(std::numeric_limits<Scalar>::epsilon());
}

namespace detail {

/// Householder triangularisation, in place, of a fixed-size column-major M from column K on
/// (columns K..TriCols−1 are reduced; later columns are transformed along, i.e. they become
/// Qᵀ·column). Column-scaled reflectors avoid overflow/underflow in the norms. The columns are
/// walked as plain arrays with compile-time bounds: as fast as Eigen's fixed-size block products
/// here (the filter's hot path), and an order of magnitude cheaper to compile.
template <int K, int TriCols, class Mat>
void householderTriangularize(Mat& M) noexcept {
  using Scalar = typename Mat::Scalar;
  constexpr int R = Mat::RowsAtCompileTime;
  constexpr int C = Mat::ColsAtCompileTime;
  static_assert(!(Mat::Flags & Eigen::RowMajorBit), "householderTriangularize: column-major M");
  if constexpr (K < TriCols && K < R - 1) {
    Scalar* const m = M.data();
    Scalar* const colK = m + K * R;
    Scalar scale(0);
    for (int i = K; i < R; ++i) scale = std::max(scale, std::abs(colK[i]));
    // One reciprocal instead of a division per entry; a subnormal scale (whose reciprocal
    // overflows) is treated as zero: its column is negligible against any pivot.
    if (scale >= std::numeric_limits<Scalar>::min() && std::isfinite(scale)) {
      const Scalar inv_scale = Scalar(1) / scale;
      Scalar v[R];  // the reflector below the diagonal, v[K+1 .. R-1]
      Scalar sigma2(0);
      for (int i = K + 1; i < R; ++i) {
        v[i] = colK[i] * inv_scale;
        sigma2 += v[i] * v[i];
      }
      if (sigma2 != Scalar(0)) {
        const Scalar x0 = colK[K] * inv_scale;
        Scalar alpha = std::sqrt(x0 * x0 + sigma2);
        if (x0 > Scalar(0)) alpha = -alpha;  // v0 = x0 − alpha never cancels
        const Scalar v0 = x0 - alpha;
        const Scalar two_over_vtv = Scalar(2) / (v0 * v0 + sigma2);
        for (int j = K + 1; j < C; ++j) {  // column j −= v · (2 vᵀcolumn / vᵀv)
          Scalar* const col = m + j * R;
          Scalar f = v0 * col[K];
          for (int i = K + 1; i < R; ++i) f += v[i] * col[i];
          f *= two_over_vtv;
          col[K] -= v0 * f;
          for (int i = K + 1; i < R; ++i) col[i] -= v[i] * f;
        }
        colK[K] = alpha * scale;
        for (int i = K + 1; i < R; ++i) colK[i] = Scalar(0);
      }
    }
    householderTriangularize<K + 1, TriCols>(M);
  }
}

/// Accumulates whitened factor rows [A_i | b_i] into a square-root information pair [R | c]
/// (RᵀR = Σ A_iᵀA_i, Rᵀc = Σ A_iᵀb_i), compressing with Householder reflections whenever the
/// 2·DoF-row stack is full.
template <class G>
struct SqrtInformation {
  static constexpr int D = G::DoF;
  using Scalar = typename G::Scalar;
  using Stack = Eigen::Matrix<Scalar, 2 * D, D + 1>;
  Stack M;
  int rows = 0;

  void reset() noexcept {
    M.setZero();
    rows = 0;
  }
  void add(const typename G::Jacobian& A, const typename G::Tangent& b) noexcept {
    if (rows == 2 * D) compress();
    M.template block<D, D>(rows, 0) = A;
    M.template block<D, 1>(rows, D) = b;
    rows += D;
  }
  void compress() noexcept {
    // Rows at and below `rows` are zero (reset/compress clear them), and zero rows change
    // neither R nor c, so the whole stack is reduced with compile-time sizes.
    householderTriangularize<0, D>(M);
    M.template bottomRows<D>().setZero();
    rows = D;
  }
  /// Upper-triangular R (after compress()).
  auto R() const noexcept { return M.template topLeftCorner<D, D>(); }
  /// c = Qᵀ b (after compress()).
  auto c() const noexcept { return M.template block<D, 1>(0, D); }
};

/// (det, adj) of a 3×3 matrix: adj·M = det·I. Cofactors, so the inverse costs one division.
template <class Scalar>
Scalar adjugate3(const Eigen::Matrix<Scalar, 3, 3>& M, Eigen::Matrix<Scalar, 3, 3>& adj) noexcept {
  adj(0, 0) = M(1, 1) * M(2, 2) - M(1, 2) * M(2, 1);
  adj(0, 1) = M(0, 2) * M(2, 1) - M(0, 1) * M(2, 2);
  adj(0, 2) = M(0, 1) * M(1, 2) - M(0, 2) * M(1, 1);
  adj(1, 0) = M(1, 2) * M(2, 0) - M(1, 0) * M(2, 2);
  adj(1, 1) = M(0, 0) * M(2, 2) - M(0, 2) * M(2, 0);
  adj(1, 2) = M(0, 2) * M(1, 0) - M(0, 0) * M(1, 2);
  adj(2, 0) = M(1, 0) * M(2, 1) - M(1, 1) * M(2, 0);
  adj(2, 1) = M(0, 1) * M(2, 0) - M(0, 0) * M(2, 1);
  adj(2, 2) = M(0, 0) * M(1, 1) - M(0, 1) * M(1, 0);
  return M(0, 0) * adj(0, 0) + M(0, 1) * adj(1, 0) + M(0, 2) * adj(2, 0);
}

/// Largest accepted trace of He⁻¹, the inverse of the equilibrated information matrix (unit
/// diagonal), in FusionForm::information. He's eigenvalues are at most DoF, so its condition
/// number is at most DoF · 1000 (6000 for SE(3)): the explicit inverse then loses at most about
/// 6000 eps relative, within a factor 80 (√6000) of the square-root form's bound. Beyond it
/// fuseFactored hands the call to the square-root form. Realistic factors (the benchmark's:
/// σ 0.1–1 mm, 0.5–2°) give traces of 6.0–7.0.
template <class Scalar>
Scalar informationTraceLimit() noexcept {
  return Scalar(1000);
}

/// Sylvester's criterion below the full determinant: whether the leading principal minors of
/// orders 1 … n−1 of M are positive (the caller has det M > 0). A positive determinant alone
/// admits an even number of negative eigenvalues (1 + a(11ᵀ − I) with a = 2 has det 5 and
/// eigenvalues 5, −1, −1); with every leading minor positive, M is positive definite.
template <class Mat>
bool leadingMinorsPositive(const Mat& M) noexcept {
  using Scalar = typename Mat::Scalar;
  constexpr int n = Mat::RowsAtCompileTime;
  static_assert(n >= 1 && n <= 4, "leadingMinorsPositive: sizes 1-4");
  if (!(M(0, 0) > Scalar(0))) return false;
  if constexpr (n >= 3)
    if (!(M.template topLeftCorner<2, 2>().determinant() > Scalar(0))) return false;
  if constexpr (n >= 4)
    if (!(M.template topLeftCorner<3, 3>().determinant() > Scalar(0))) return false;
  return true;
}

/// The inverse of an equilibrated SPD 6×6 matrix He (unit diagonal) by 3×3 blocks (Schur
/// complement):
///     He = [[A, B], [Bᵀ, C]],  K = A⁻¹B,  S = C − BᵀK,
///     He⁻¹ = [[A⁻¹ + K S⁻¹ Kᵀ, −K S⁻¹], [−S⁻¹ Kᵀ, S⁻¹]].
/// Two divisions in the whole chain, where a Cholesky factorisation or a Householder reduction
/// waits on six square roots and six divisions one after another. He is SPD exactly when A and
/// S are; false unless both pass Sylvester's criterion (leading minors and determinant > 0).
template <class Scalar>
bool spdInverseBlocks(const Eigen::Matrix<Scalar, 6, 6>& He, Eigen::Matrix<Scalar, 6, 6>& E) noexcept {
  using M3 = Eigen::Matrix<Scalar, 3, 3>;
  const M3 A = He.template topLeftCorner<3, 3>();
  const M3 B = He.template topRightCorner<3, 3>();
  M3 adjA;
  const Scalar detA = adjugate3(A, adjA);
  if (!(detA > Scalar(0)) || !leadingMinorsPositive(A)) return false;
  const M3 Ai = adjA * (Scalar(1) / detA);
  const M3 K = Ai * B;
  const M3 S = He.template bottomRightCorner<3, 3>() - B.transpose() * K;
  M3 adjS;
  const Scalar detS = adjugate3(S, adjS);
  if (!(detS > Scalar(0)) || !leadingMinorsPositive(S)) return false;
  const M3 Si = adjS * (Scalar(1) / detS);
  const M3 KSi = K * Si;
  E.template topLeftCorner<3, 3>() = Ai + KSi * K.transpose();
  E.template topRightCorner<3, 3>() = -KSi;
  E.template bottomLeftCorner<3, 3>() = -KSi.transpose();
  E.template bottomRightCorner<3, 3>() = Si;
  return true;
}

/// H⁻¹ of an SPD information matrix H (DoF 1–4 or 6), after the diagonal equilibration
/// He = D H D, D = diag(H_ii)^−½, H⁻¹ = D He⁻¹ D: 6×6 by spdInverseBlocks, smaller sizes by
/// cofactors (Eigen's fixed-size inverse, which also returns the determinant). Returns false
/// (Hinv unwritten) unless H's diagonal is positive and finite, He passes Sylvester's criterion
/// (every leading principal minor positive: He is SPD) and n ≤ trace(He⁻¹) ≤
/// informationTraceLimit() (to 1 %: below n the inverse is lost to rounding). `trace`
/// (optional) receives trace(He⁻¹).
template <class Mat>
bool spdInverse(const Mat& H, Mat& Hinv, typename Mat::Scalar* trace = nullptr) noexcept {
  using Scalar = typename Mat::Scalar;
  constexpr int n = Mat::RowsAtCompileTime;
  Eigen::Matrix<Scalar, n, 1> d;
  for (int i = 0; i < n; ++i) {
    if (!(H(i, i) > Scalar(0)) || !std::isfinite(H(i, i))) return false;
    d(i) = Scalar(1) / std::sqrt(H(i, i));
  }
  const Mat He = d.asDiagonal() * H * d.asDiagonal();
  Mat E;
  if constexpr (n == 6) {
    if (!spdInverseBlocks(He, E)) return false;
  } else {
    static_assert(n <= 4, "spdInverse: sizes 1-4 and 6");
    Scalar det(0);
    bool invertible = false;
    He.computeInverseAndDetWithCheck(E, det, invertible, Scalar(0));
    if (!invertible || !(det > Scalar(0)) || !leadingMinorsPositive(He)) return false;
  }
  // trace(He⁻¹) ≥ n for an SPD He with a unit diagonal (its eigenvalues average 1, and the
  // mean of their inverses is at least the inverse of their mean): a smaller computed trace is
  // an inverse lost to rounding.
  const Scalar tr = E.trace();
  if (!(tr >= Scalar(0.99) * Scalar(n) && tr <= informationTraceLimit<Scalar>())) return false;  // also NaN
  Hinv = d.asDiagonal() * E * d.asDiagonal();
  if (trace) *trace = tr;
  return true;
}

/// Whether the (symmetrised) inverse that spdInverse returned with trace(He⁻¹) = tr is positive
/// definite beyond doubt, so that a Cholesky test of it would only repeat what is known. The
/// exact He⁻¹ has its eigenvalues ≥ 1/n (He is SPD with a unit diagonal, so its eigenvalues are
/// at most its trace n), and the computed one is off by about κ(He)·eps·‖He⁻¹‖ ≤ n·tr²·eps
/// times a modest constant. Certified when n²·tr²·eps ≤ 1e-6, which leaves that constant a
/// margin of 10⁶: in double always (tr ≤ informationTraceLimit()), in float never for n = 6
/// (tr ≥ n), where the Cholesky test stays.
template <int n, class Scalar>
bool spdInverseCertified(Scalar tr) noexcept {
  const Scalar bound = Scalar(n) * tr;
  return bound * bound * std::numeric_limits<Scalar>::epsilon() <= Scalar(1e-6);
}

/// νᵀ S⁻¹ ν with S = Σ_a + Σ_b, for an innovation ν and two covariances already known to be
/// finite (normalizedInnovationSquared checks them; the filter has). Status: ok, not_spd,
/// numerical_failure; `nis` is written only when ok.
template <class G>
Status innovationNis(const typename G::Tangent& nu, const typename G::Jacobian& Sigma_a,
                     const typename G::Jacobian& Sigma_b, typename G::Scalar& nis) noexcept {
  const typename G::Jacobian S = Sigma_a + Sigma_b;
  typename G::Jacobian L;
  const Status s = choleskyChecked(S, L);
  if (s != Status::ok) return s;
  typename G::Tangent w = nu;
  lowerSolveInPlace(L, w);
  const typename G::Scalar r = w.squaredNorm();
  if (!allFinite(nu) || !std::isfinite(r)) return Status::numerical_failure;
  nis = r;
  return Status::ok;
}

}  // namespace detail

/// Normalised innovation squared of an observation against a prior (both concentrated
/// Gaussians), linearised at the prior mean to first order:
///     ν = ln(X̄_obs X̄_prior⁻¹)^∨ ≈ ε_prior − ε_obs,   S = Σ_prior + Σ_obs,   NIS = νᵀ S⁻¹ ν.
/// (With X = exp(ε_p^)X̄_prior = exp(ε_o^)X̄_obs: X̄_obs X̄_prior⁻¹ = exp(−ε_o^) exp(ε_p^), and
/// BCH to first order in the ε gives ν ≈ ε_p − ε_o; the J(ν) corrections are second order.)
/// Under a consistent model NIS ~ χ²(DoF). `innovation` (optional) receives ν.
/// Status: ok; non_finite_input / not_orthonormal / not_spd when either Gaussian fails
/// validate(); not_spd / numerical_failure from S. `nis` and `innovation` are written only
/// when ok.
template <class G>
Status normalizedInnovationSquared(const ConcentratedGaussian<G>& observation,
                                   const ConcentratedGaussian<G>& prior,
                                   typename G::Scalar& nis,
                                   typename G::Tangent* innovation = nullptr) noexcept {
  Status s = observation.validate();
  if (s == Status::ok) s = prior.validate();
  if (s != Status::ok) return s;
  const typename G::Tangent nu = lminus(observation.mean, prior.mean);
  s = detail::innovationNis<G>(nu, observation.covariance, prior.covariance, nis);
  if (s != Status::ok) return s;
  if (innovation) *innovation = nu;
  return Status::ok;
}

namespace detail {

/// ξ_2 = ln(X̄_1 X̄_2⁻¹)^∨ at the fusion's initial operating point and J(ξ_2)⁻¹, when the caller
/// has them already (the filter's innovation: Policy::logAndInverse of X̄_1 X̄_2⁻¹).
template <class G>
struct InitialResidual {
  typename G::Tangent xi;
  typename G::Jacobian Jinv;
};

/// The iteration of Algorithm 3 (alg:se3_data_fusion) on factors that are already validated: `means` are
/// valid group elements, `L` the lower Cholesky factors of their covariances (Σ_i = L_i L_iᵀ,
/// as choleskyChecked returns them), 1 ≤ count ≤ kMaxFusionFactors, options valid. fuse()
/// validates and factorises, then calls this; the filter calls it directly with the factors it
/// already has, so that no input is checked or factorised twice. `second` (optional): the
/// second factor's InitialResidual, computed as this function would, so that its log is not
/// taken twice. Status as fuse().
template <class Policy, class G>
LIESERVO_FLATTEN_GCC Status fuseFactored(const G* means, const typename G::Jacobian* L, int count,
                    const FusionOptions<typename G::Scalar>& options, FusionResult<G>& result,
                    const InitialResidual<G>* second = nullptr) noexcept {
  using Scalar = typename G::Scalar;
  using Tangent = typename G::Tangent;
  using Jacobian = typename G::Jacobian;
  constexpr int D = G::DoF;

  // Per factor, once per call: X̄_i⁻¹ and the whitening W_i = L_i⁻¹ (lower triangular), so an
  // iteration multiplies instead of solving (A_i = W_i J_i⁻¹, b_i = W_i ξ_i).
  Jacobian W[kMaxFusionFactors];
  G inv_mean[kMaxFusionFactors];
  for (int i = 0; i < count; ++i) {
    W[i] = lowerTriangularInverse(L[i]);
    inv_mean[i] = means[i].inverse();
  }

  G X = means[0];  // operating point X̄ ← X̄_1
  Scalar max_sep(0);
  const bool information_form = options.form == FusionForm::information;
  SqrtInformation<G> info;
  Jacobian H = Jacobian::Zero();  // information form: H = Σ A_iᵀA_i, g = Σ A_iᵀb_i
  Tangent g = Tangent::Zero();
  Jacobian R = Jacobian::Identity();
  // The result is formed in place: the information form's H⁻¹ is Σ* after the last iteration.
  ConcentratedGaussian<G> fused;
  Jacobian& Hinv = fused.covariance;
  Scalar inverse_trace(0);  // trace of the equilibrated H⁻¹ (spdInverse)
  Tangent mu = Tangent::Zero();
  Scalar step(0), step_sigmas(0);
  int it = 0;
  bool converged = false;
  while (it < options.max_iterations) {
    // The step's length in standard deviations: for the converged rule at every update, for
    // the fixed count only at the last (FusionResult::step_sigmas).
    const bool measure = options.tolerance > Scalar(0) || it + 1 == options.max_iterations;
    if (information_form) {
      H.setZero();
      g.setZero();
    } else {
      info.reset();
    }
    for (int i = 0; i < count; ++i) {
      if (it == 0 && i == 0) {
        // The operating point starts at X̄_1: ξ_1 = ln(X̄_1 X̄_1⁻¹)^∨ = 0 and J(0)⁻¹ = 1, so
        // A_1 = L_1⁻¹ and b_1 = 0 (exactly, where the log of the rounded X̄_1 X̄_1⁻¹ is not).
        if (information_form)
          H.noalias() += W[0].transpose() * W[0];
        else
          info.add(W[0], Tangent::Zero());
        continue;
      }
      Jacobian Jinv;
      Tangent xi;  // ξ_i, J(ξ_i)⁻¹
      if (it == 0 && i == 1 && second != nullptr) {
        xi = second->xi;
        Jinv = second->Jinv;
      } else if (it == 1 && i == 0 && rotationAngle<G>(mu) < pi<Scalar>() - cutLocusMargin<Scalar>()) {
        // After the first update X̄ = exp(μ^) X̄_1, so ξ_1 = ln(exp(μ^))^∨ = μ exactly (ln
        // inverts exp inside the cut locus), where the log of the rounded X̄ X̄_1⁻¹ is not.
        xi = mu;
        Jinv = Policy::template inverse<G>(mu);
      } else {
        xi = Policy::logAndInverse(X * inv_mean[i], Jinv);
      }
      if (it == 0) {
        // At the initial operating point ξ_i = ln(X̄_1 X̄_i⁻¹): how far apart the means are.
        if (!allFinite(xi)) return Status::numerical_failure;
        if (i > 0) max_sep = std::max(max_sep, rotationAngle<G>(xi));
      }
      // A_i = L_i⁻¹ J_i⁻¹ (so A_iᵀA_i = J_i⁻ᵀ Σ_i⁻¹ J_i⁻¹), b_i = L_i⁻¹ ξ_i
      if (information_form) {
        const Jacobian A = W[i].lazyProduct(Jinv);
        H.noalias() += A.transpose() * A;
        g.noalias() += A.transpose() * (W[i] * xi);
      } else {
        info.add(W[i].lazyProduct(Jinv), W[i] * xi);
      }
    }
    if (it == 0 && max_sep > pi<Scalar>() - cutLocusMargin<Scalar>())
      return Status::invalid_argument;
    // μ = −Σ Σ_i J_i⁻ᵀ Σ_i⁻¹ ξ_i
    if (information_form) {
      // μ = −H⁻¹ g. An H too ill-conditioned for the explicit inverse: the whole call is
      // handed to the square-root form (so the result is the square-root form's).
      if (!spdInverse(H, Hinv, &inverse_trace)) {
        FusionOptions<Scalar> sqrt_options = options;
        sqrt_options.form = FusionForm::square_root;
        return fuseFactored<Policy>(means, L, count, sqrt_options, result, second);
      }
      mu.noalias() = -(Hinv * g);
      if (measure) step_sigmas = std::sqrt(std::max(Scalar(0), mu.dot(H * mu)));  // √(μᵀ H μ)
    } else {
      info.compress();
      R = info.R();
      for (int k = 0; k < D; ++k)
        if (!(std::abs(R(k, k)) > Scalar(0))) return Status::numerical_failure;
      // = −(RᵀR)⁻¹ Rᵀc = −R⁻¹ c
      mu = -info.c();
      upperSolveInPlace(R, mu);
      if (measure) step_sigmas = upperTimes(R, mu).norm();  // ‖R μ‖ = √(μᵀ RᵀR μ)
    }
    if (!allFinite(mu)) return Status::numerical_failure;
    X = G::exp(mu) * X;  // eq. 54 (eqn:se3_normalised_prod_update)
    ++it;
    step = mu.norm();
    if (options.tolerance > Scalar(0) && step_sigmas < options.tolerance) {
      converged = true;
      break;
    }
  }
  if (options.tolerance > Scalar(0) && !converged && options.require_convergence) return Status::not_converged;

  X.normalize();
  // Σ* = H⁻¹ = (RᵀR)⁻¹ = R⁻¹ R⁻ᵀ, from the last linearisation (as the paper's algorithm
  // returns it).
  fused.mean = X;
  Jacobian& Sigma = fused.covariance;  // information form: H⁻¹ already
  if (!information_form) {
    const Jacobian Rinv = upperTriangularInverse(R);
    Sigma = Rinv * Rinv.transpose();
  }
  if (!X.allFinite() || !allFinite(Sigma) || !std::isfinite(step) || !std::isfinite(step_sigmas))
    return Status::numerical_failure;
  // Σ* is SPD in exact arithmetic; rounding can break that when its eigenvalues span more than
  // ~1/eps in a rotated basis (only the square-root form reaches such spreads): symmetrise, and
  // repair with a rounding-level diagonal load. An explicit inverse that spdInverseCertified
  // vouches for is SPD already and is only symmetrised.
  if (information_form && spdInverseCertified<D>(inverse_trace))
    symmetrize(Sigma);
  else if (repairSpd(Sigma) != Status::ok)
    return Status::numerical_failure;

  // Status::ok promises a result that validates, by the same tests as every input: a repaired
  // Σ* can pass the checks above and still fail those (SO(3), first-order series Jacobian), and
  // the certificate rests on the computed trace, which rounding can make look well conditioned
  // when H is singular to working precision.
  if (fused.validate() != Status::ok) return Status::numerical_failure;
  result.fused = fused;
  result.iterations = it;
  result.step_norm = step;
  result.step_sigmas = step_sigmas;
  result.converged = converged;
  result.max_rotation_separation = max_sep;
  return Status::ok;
}

}  // namespace detail

/// N-ary fusion (Algorithm 3, alg:se3_data_fusion generalised to `count` factors, 1 ≤ count ≤
/// kMaxFusionFactors): the operating point starts at factors[0].mean.
/// Status: ok; invalid_argument (count out of range, or two means on the cut locus: relative
/// rotation within cutLocusMargin() of π); options.validate()'s Status; non_finite_input / not_orthonormal /
/// not_spd (a factor fails validate()); not_converged (tolerance > 0 not reached within
/// max_iterations, with require_convergence);
/// numerical_failure (a non-finite or non-SPD intermediate/result). `result` is written only
/// when the Status is ok. noexcept, allocation-free.
template <class Policy = DefaultJacobian, class G>
Status fuse(const ConcentratedGaussian<G>* factors, int count,
            const FusionOptions<typename G::Scalar>& options, FusionResult<G>& result) noexcept {
  if (factors == nullptr || count < 1 || count > kMaxFusionFactors) return Status::invalid_argument;
  if (const Status s = options.validate(); s != Status::ok) return s;
  // Validate each factor and factorise its covariance once (Σ_i = L_i L_iᵀ).
  typename G::Jacobian L[kMaxFusionFactors];
  G means[kMaxFusionFactors];
  for (int i = 0; i < count; ++i) {
    Status s = validateElement(factors[i].mean);
    if (s != Status::ok) return s;
    s = detail::choleskyChecked(factors[i].covariance, L[i]);
    if (s != Status::ok) return s;
    means[i] = factors[i].mean;
  }
  return detail::fuseFactored<Policy>(means, L, count, options, result);
}

/// Fusion of two factors (Algorithm 3, alg:se3_data_fusion); the operating point starts at `first.mean`
/// (in the filter: the observation, as in the paper). See the N-ary overload for the Status.
template <class Policy = DefaultJacobian, class G>
Status fuse(const ConcentratedGaussian<G>& first, const ConcentratedGaussian<G>& second,
            const FusionOptions<typename G::Scalar>& options, FusionResult<G>& result) noexcept {
  const ConcentratedGaussian<G> factors[2] = {first, second};
  return fuse<Policy>(factors, 2, options, result);
}

}  // namespace lieservo

#include <lieservo/detail/options_pop.hpp>

// lieservo/estimation/concentrated_gaussian.hpp — Gaussian random variables on a matrix Lie
// group G ("concentrated Gaussians"), Appendix B of the paper (sec:se3_probabilistic_transform).
//
//     X = exp(ε^) X̄,   ε ~ N(0, Σ)                                 (eq. 35, eqn:se3_random_variable_2)
//
// X̄ is the deterministic mean (`mean`), Σ the covariance of the LEFT perturbation ε
// (`covariance`, DoF×DoF, tangent ordering [ρ; φ], translation first). The induced density on
// G is p(X) = β(ε) exp(−½ εᵀ Σ⁻¹ ε), ε = ln(X X̄⁻¹)^∨, β(ε) = η/|det J(ε)| (eq. 36, eqn:se3_pdf).
//
// Functions returning Status are noexcept and allocation-free, and write their outputs only
// when the Status is ok. The value-returning operations (transform, inverse, compose) are
// unchecked fast paths for inputs the caller has already validated.
#pragma once
#include <lieservo/detail/options_push.hpp>

#include <type_traits>
#include <utility>

#include <Eigen/Core>

#include <lieservo/sampling/random.hpp>
#include <lieservo/status.hpp>
#include <lieservo/units.hpp>
#include <lieservo/estimation/detail/linalg.hpp>
#include <lieservo/estimation/jacobian_policy.hpp>

namespace lieservo {

namespace detail {
template <class G, class = void>
struct HasAdjointCongruence : std::false_type {};
template <class G>
struct HasAdjointCongruence<
    G, std::void_t<decltype(std::declval<const G&>().adjointCongruence(std::declval<const typename G::Jacobian&>()))>>
    : std::true_type {};

/// Ad(X) Σ Ad(X)ᵀ: by blocks where the group offers it (SE(3): G::adjointCongruence), else the
/// 6×6 products.
template <class G>
typename G::Jacobian adjointCongruence(const G& X, const typename G::Jacobian& Sigma) noexcept {
  if constexpr (HasAdjointCongruence<G>::value) {
    return X.adjointCongruence(Sigma);
  } else {
    const typename G::Jacobian Ad = X.Ad();
    return Ad * Sigma * Ad.transpose();
  }
}
}  // namespace detail

/// A concentrated Gaussian on G: X = exp(ε^) mean, ε ~ N(0, covariance).
template <class G>
struct ConcentratedGaussian {
  using Group = G;  ///< the group of the mean
  using Scalar = typename G::Scalar;  ///< float or double
  using Tangent = typename G::Tangent;  ///< a tangent vector (ε)
  using Jacobian = typename G::Jacobian;  ///< DoF × DoF (the covariance)
  static constexpr int DoF = G::DoF;  ///< tangent dimension

  G mean;               ///< deterministic mean X̄
  Jacobian covariance;  ///< covariance Σ of the left perturbation ε

  /// Identity mean, identity covariance.
  ConcentratedGaussian() noexcept : mean(), covariance(Jacobian::Identity()) {}
  ConcentratedGaussian(const G& m, const Jacobian& c) noexcept : mean(m), covariance(c) {}  ///< mean m, covariance c, as given (validate() checks them)

  /// ok when the mean is a valid group element (finite, orthonormal rotation, det +1) and the
  /// covariance is finite, symmetric (relative tolerance sqrt(eps)) and positive-definite.
  Status validate() const noexcept;
};

/// The same Gaussian in another scalar type (e.g. double → float): mean.cast, covariance.cast.
template <class NewScalar, class G>
auto castGaussian(const ConcentratedGaussian<G>& x) {
  using G2 = std::decay_t<decltype(x.mean.template cast<NewScalar>())>;
  return ConcentratedGaussian<G2>(x.mean.template cast<NewScalar>(),
                                  x.covariance.template cast<NewScalar>());
}

/// Checks a covariance matrix: ok, non_finite_input or not_spd (see ConcentratedGaussian::validate).
template <class Mat>
Status checkCovariance(const Mat& S) noexcept {
  return detail::checkSpd(S);
}

/// ConcentratedGaussian::validate() as a free function.
template <class G>
Status validate(const ConcentratedGaussian<G>& x) noexcept {
  const Status s = validateElement(x.mean);
  if (s != Status::ok) return s;
  return detail::checkSpd(x.covariance);
}

template <class G>
Status ConcentratedGaussian<G>::validate() const noexcept {
  return lieservo::validate(*this);
}

namespace detail {
/// The two products of eq. 41 (eqn:se3_rv_probabilistic_transform_2) written into `out`,
/// which must not alias `x`; neither normalised nor symmetrised: transformUnchecked
/// symmetrises, the filter's prediction normalises and factorises.
template <class G>
void transformProducts(const ConcentratedGaussian<G>& x, const G& T_bar, const typename G::Jacobian& Sigma_phi,
                       ConcentratedGaussian<G>& out) noexcept {
  out.mean = T_bar * x.mean;
  out.covariance = adjointCongruence(T_bar, x.covariance) + Sigma_phi;
}
}  // namespace detail

/// Probabilistic transformation X' = T X with T = exp(φ^) T̄, φ ~ N(0, Σφ) independent of X
/// (eq. 41, eqn:se3_rv_probabilistic_transform_2, first order in the covariances):
///     X̄' = T̄ X̄,    Σ' = Ad(T̄) Σ Ad(T̄)ᵀ + Σφ.
/// Unchecked (the caller guarantees valid inputs; transform() checks them); the result
/// covariance is symmetrised.
template <class G>
ConcentratedGaussian<G> transformUnchecked(const ConcentratedGaussian<G>& x, const G& T_bar,
                                           const typename G::Jacobian& Sigma_phi) noexcept {
  ConcentratedGaussian<G> out;
  detail::transformProducts(x, T_bar, Sigma_phi, out);
  detail::symmetrize(out.covariance);
  return out;
}

/// Checked version of transform (eq. 41, eqn:se3_rv_probabilistic_transform_2): x must validate, T̄
/// must be a valid group element, Σφ finite symmetric positive semi-definite (0 allowed);
/// the result must be finite and SPD (else numerical_failure; a rounding-level loss of
/// definiteness is repaired by detail::repairSpd). `out` may alias `x`.
template <class G>
Status transform(const ConcentratedGaussian<G>& x, const G& T_bar,
                 const typename G::Jacobian& Sigma_phi, ConcentratedGaussian<G>& out) noexcept {
  Status s = validate(x);
  if (s != Status::ok) return s;
  s = validateElement(T_bar);
  if (s != Status::ok) return s;
  s = detail::checkPsd(Sigma_phi);
  if (s != Status::ok) return s;
  ConcentratedGaussian<G> r = transformUnchecked(x, T_bar, Sigma_phi);
  r.mean.normalize();
  if (!r.mean.allFinite() || !r.covariance.allFinite()) return Status::numerical_failure;
  if (detail::repairSpd(r.covariance) != Status::ok) return Status::numerical_failure;
  out = r;
  return Status::ok;
}

/// Inverse of a concentrated Gaussian: X⁻¹ = X̄⁻¹ exp(−ε^) = exp((−Ad(X̄⁻¹) ε)^) X̄⁻¹, so
///     mean X̄⁻¹,   covariance Ad(X̄⁻¹) Σ Ad(X̄⁻¹)ᵀ   (exact: a linear map of ε). Unchecked.
template <class G>
ConcentratedGaussian<G> inverse(const ConcentratedGaussian<G>& x) noexcept {
  ConcentratedGaussian<G> out;
  out.mean = x.mean.inverse();
  out.covariance = detail::adjointCongruence(out.mean, x.covariance);
  detail::symmetrize(out.covariance);
  return out;
}

/// Compounding of two INDEPENDENT uncertain elements, X = A B:
///     A B = exp(ε_a^) Ā exp(ε_b^) B̄ = exp(ε_a^) exp((Ad(Ā) ε_b)^) Ā B̄
///         ≈ exp((ε_a + Ad(Ā) ε_b)^) Ā B̄            (first order, as eq. 41 (eqn:se3_rv_probabilistic_transform_2))
/// so mean Ā B̄ and covariance Σ_a + Ad(Ā) Σ_b Ad(Ā)ᵀ. Unchecked.
template <class G>
ConcentratedGaussian<G> compose(const ConcentratedGaussian<G>& a,
                                const ConcentratedGaussian<G>& b) noexcept {
  ConcentratedGaussian<G> out;
  out.mean = a.mean * b.mean;
  out.covariance = a.covariance + detail::adjointCongruence(a.mean, b.covariance);
  detail::symmetrize(out.covariance);
  return out;
}

/// From a Gaussian in exponential coordinates ξ ~ N(μ, Σξ) to a concentrated Gaussian
/// (eq. 14, eq:se3_inverse_transform, inverting eq. 38 (eqn:glob_tangent_space_pdf)):
///     X̄ = exp(μ^),   Σ = J(μ) Σξ J(μ)ᵀ,
/// J evaluated by the policy (DefaultJacobian, the paper's truncation, which the fusion and the
/// filter also use by default; ClosedFormJacobian for the exact J). μ must lie in the principal
/// branch of ln, rotation angle |φ| ≤ π: beyond it the same X̄ has a shorter μ, and J(μ) tends
/// to singular at 2π (condition numbers ~1e67), so the covariance would be meaningless. Status: non_finite_input, invalid_argument (|φ| > π),
/// not_spd (Σξ), numerical_failure (a non-finite result).
template <class Policy = DefaultJacobian, class G>
Status fromTangentCovariance(const typename G::Tangent& mu, const typename G::Jacobian& Sigma_xi,
                             ConcentratedGaussian<G>& out) noexcept {
  using Scalar = typename G::Scalar;
  if (!mu.allFinite() || !Sigma_xi.allFinite()) return Status::non_finite_input;
  if (detail::rotationAngle<G>(mu) > pi<Scalar>()) return Status::invalid_argument;
  Status s = detail::checkSpd(Sigma_xi);
  if (s != Status::ok) return s;
  ConcentratedGaussian<G> r;
  r.mean = G::exp(mu);
  const typename G::Jacobian J = Policy::template forward<G>(mu);
  r.covariance = J * Sigma_xi * J.transpose();
  if (!r.mean.allFinite() || !r.covariance.allFinite()) return Status::numerical_failure;
  if (detail::repairSpd(r.covariance) != Status::ok) return Status::numerical_failure;
  out = r;
  return Status::ok;
}

/// eq. 14 (eq:se3_inverse_transform) with a diagonal tangent covariance diag(σ²): the form of the
/// GDN output (μ, σ), σ per component (all > 0).
template <class Policy = DefaultJacobian, class G>
Status fromTangentGaussian(const typename G::Tangent& mu, const typename G::Tangent& sigma,
                           ConcentratedGaussian<G>& out) noexcept {
  if (!mu.allFinite() || !sigma.allFinite()) return Status::non_finite_input;
  if (!(sigma.array() > typename G::Scalar(0)).all()) return Status::not_spd;
  const typename G::Jacobian S = sigma.array().square().matrix().asDiagonal();
  return fromTangentCovariance<Policy>(mu, S, out);
}

/// The Gaussian in exponential coordinates of a concentrated Gaussian
/// (eq. 37, eqn:glob_tangent_space_approx, eq. 38 (eqn:glob_tangent_space_pdf)):
///     μ = ln(X̄)^∨,   Σξ = J(μ)⁻¹ Σ J(μ)⁻ᵀ.
/// Meaningful while the rotation angle of μ is below π (ln is then unique).
template <class Policy = DefaultJacobian, class G>
Status toTangentGaussian(const ConcentratedGaussian<G>& x, typename G::Tangent& mu,
                         typename G::Jacobian& Sigma_xi) noexcept {
  Status s = validate(x);
  if (s != Status::ok) return s;
  typename G::Jacobian Jinv;
  const typename G::Tangent m = Policy::logAndInverse(x.mean, Jinv);
  typename G::Jacobian S = Jinv * x.covariance * Jinv.transpose();
  detail::symmetrize(S);
  if (!m.allFinite() || !S.allFinite()) return Status::numerical_failure;
  mu = m;
  Sigma_xi = S;
  return Status::ok;
}

/// Squared Mahalanobis distance of X from x in the left perturbation: ε = ln(X X̄⁻¹)^∨,
/// d² = εᵀ Σ⁻¹ ε (the exponent of eq. 43 (eqn:se3_pdf_approx); NEES when X is the true state).
template <class G>
Status mahalanobisSquared(const ConcentratedGaussian<G>& x, const G& X,
                          typename G::Scalar& d2) noexcept {
  Status s = validateElement(x.mean);
  if (s == Status::ok) s = validateElement(X);
  if (s != Status::ok) return s;
  typename G::Jacobian L;
  s = detail::choleskyChecked(x.covariance, L);
  if (s != Status::ok) return s;
  typename G::Tangent w = lminus(X, x.mean);  // ε = X ⊖ X̄
  detail::lowerSolveInPlace(L, w);                     // L⁻¹ ε
  const typename G::Scalar r = w.squaredNorm();
  if (!std::isfinite(r)) return Status::numerical_failure;
  d2 = r;
  return Status::ok;
}

/// Draws X = exp(ε^) X̄ with ε ~ N(0, Σ) into `out`, using Σ's Cholesky factor. Refuses a
/// mean that is not a valid element or a Σ that is not SPD (its status; `out` and the generator
/// untouched). Not real-time; for simulations and tests. The draws come from
/// sampling::standardNormal, so a seed gives the same sample on every platform.
template <class G, class URBG>
Status sample(const ConcentratedGaussian<G>& x, URBG& rng, G& out) {
  using Scalar = typename G::Scalar;
  Status s = validateElement(x.mean);
  if (s != Status::ok) return s;
  typename G::Jacobian L;
  s = detail::choleskyChecked(x.covariance, L);
  if (s != Status::ok) return s;
  const typename G::Tangent z = sampling::standardNormalVector<G::DoF, Scalar>(rng);
  out = G::exp(L * z) * x.mean;
  return Status::ok;
}

}  // namespace lieservo

#include <lieservo/detail/options_pop.hpp>

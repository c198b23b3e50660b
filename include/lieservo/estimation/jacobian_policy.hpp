// lieservo/estimation/jacobian_policy.hpp — how the estimators evaluate the left Jacobian
// J(ξ) and its inverse J(ξ)⁻¹ of a group G.
//
// The paper (Lloyd & Lepora) truncates the series of both after second order
// (eq. 33, eqn:left_jacobian_def, eq. 34 (eqn:inv_jacobian_def); "we typically truncate the corresponding series
// after second-order terms"), and Algorithm 3 (alg:se3_data_fusion) uses
//     J(ξ)⁻¹ ≈ 1 − ½ ξ⋏ + (1/12)(ξ⋏)²,    ξ⋏ = ad(ξ).
// A policy is a stateless type with three static member templates:
//     template <class G> static typename G::Jacobian inverse(const typename G::Tangent& xi);
//     template <class G> static typename G::Jacobian forward(const typename G::Tangent& xi);
//     template <class G> static typename G::Tangent  logAndInverse(const G& X, typename G::Jacobian& Jinv);
// logAndInverse returns ξ = ln(X)^∨ and writes J(ξ)⁻¹ (sharing the trigonometric work where
// the policy can). All are noexcept and allocation-free (fixed-size Eigen only).
#pragma once
#include <lieservo/detail/options_push.hpp>

#include <Eigen/Core>

namespace lieservo {

/// The exact (closed-form) left Jacobian and its inverse, from the group core
/// (G::leftJacobian, G::leftJacobianInverse, G::logAndLeftJacobianInverse).
struct ClosedFormJacobian {
  static constexpr int order = -1;  ///< -1: closed form (no truncation)

  template <class G>
  /// J(ξ)⁻¹ in closed form.
  static typename G::Jacobian inverse(const typename G::Tangent& xi) noexcept {
    return G::leftJacobianInverse(xi);
  }
  template <class G>
  /// J(ξ) in closed form.
  static typename G::Jacobian forward(const typename G::Tangent& xi) noexcept {
    return G::leftJacobian(xi);
  }
  template <class G>
  /// ξ = ln(X)^∨, and J(ξ)⁻¹ into Jinv, sharing the trigonometric work.
  static typename G::Tangent logAndInverse(const G& X, typename G::Jacobian& Jinv) noexcept {
    return X.logAndLeftJacobianInverse(Jinv);
  }
};

/// The Bernoulli series of order N (eq. 34, eqn:inv_jacobian_def):
///     J(ξ)⁻¹ ≈ Σ_{n=0}^{N} (B_n/n!) (ξ⋏)^n,
/// and for the forward Jacobian the series of eq. 33 (eqn:left_jacobian_def) to the same order:
///     J(ξ) ≈ Σ_{n=0}^{N} (ξ⋏)^n/(n+1)!.
/// N = 0 gives the identity (a purely "Euclidean" tangent-space fusion), N = 2 is the paper's
/// choice (PaperJacobian). The series converge for rotation angles |θ| < 2π; their error grows
/// like θ^{N+1} (translation enters linearly through ξ⋏).
template <int N>
struct SeriesJacobian {
  static_assert(N >= 0, "series order must be >= 0");
  static constexpr int order = N;  ///< N

  template <class G>
  /// J(ξ)⁻¹ by the Bernoulli series of order N.
  static typename G::Jacobian inverse(const typename G::Tangent& xi) noexcept {
    return G::template leftJacobianInverseSeries<N>(xi);
  }
  template <class G>
  /// J(ξ) by its series of order N (Horner).
  static typename G::Jacobian forward(const typename G::Tangent& xi) noexcept {
    using Jacobian = typename G::Jacobian;
    using Scalar = typename G::Scalar;
    const Jacobian ad = G::ad(xi);
    // Horner: Σ_{n=0}^{N} ad^n/(n+1)!  =  c0 I + ad (c1 I + ad (c2 I + …)),  c_n = 1/(n+1)!
    Scalar c[N + 1];
    Scalar f = Scalar(1);
    for (int n = 0; n <= N; ++n) {
      f /= Scalar(n + 1);
      c[n] = f;
    }
    Jacobian r = c[N] * Jacobian::Identity();
    for (int n = N - 1; n >= 0; --n) r = c[n] * Jacobian::Identity() + ad * r;
    return r;
  }
  template <class G>
  /// ξ = ln(X)^∨ (closed form), and J(ξ)⁻¹ by the series into Jinv.
  static typename G::Tangent logAndInverse(const G& X, typename G::Jacobian& Jinv) noexcept {
    const typename G::Tangent xi = X.log();
    Jinv = inverse<G>(xi);
    return xi;
  }
};

/// The paper's choice: second-order series (Algorithm 3, alg:se3_data_fusion).
using PaperJacobian = SeriesJacobian<2>;

/// The one default of the observation path: fromTangentGaussian / fromTangentCovariance /
/// toTangentGaussian, fuse and DiscriminativeBayesFilter all linearise with it unless given
/// another policy, so an observation is converted (eq. 14, eq:se3_inverse_transform) with the
/// same Jacobian the fusion iterates with. It is the paper's series; pass ClosedFormJacobian
/// to all of them for the exact Jacobian (docs/estimation.md, "One default").
using DefaultJacobian = PaperJacobian;

}  // namespace lieservo

#include <lieservo/detail/options_pop.hpp>

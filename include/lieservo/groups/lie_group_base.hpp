// lieservo/groups/lie_group_base.hpp — what every group builds from its own exp, log, inverse
// and left Jacobians, written once: the right Jacobians, the first-order BCH formulas, the
// geodesic and the Bernoulli series of J⁻¹.
#pragma once
#include <lieservo/detail/options_push.hpp>

#include <lieservo/groups/detail/generic.hpp>

namespace lieservo {

/// The common part of SO2, SE2, SO3 and SE3 (the curiously recurring template pattern, as in
/// manif): group G derives from LieGroupBase<G, G::Tangent, G::Jacobian>. The tangent and
/// Jacobian types are passed in because G is still incomplete where its base is instantiated.
/// Everything here calls G's own static exp and left Jacobians, so it is inlined as if G had
/// written it; a group that has a cheaper form declares its own, which hides this one (SE3's
/// Bernoulli series).
template <class G, class TangentT, class JacobianT>
class LieGroupBase {
 public:
  /// Right Jacobian J_r(ξ) = J(−ξ) (left perturbation, docs/conventions.md).
  static JacobianT rightJacobian(const TangentT& xi) { return G::leftJacobian(-xi); }
  /// J_r(ξ)⁻¹ = J(−ξ)⁻¹.
  static JacobianT rightJacobianInverse(const TangentT& xi) { return G::leftJacobianInverse(-xi); }

  /// Truncated series Σ_{n=0}^{N} (B_n/n!) ad(ξ)ⁿ of J(ξ)⁻¹ (eq. 34, eqn:inv_jacobian_def);
  /// N = 2 is the paper's. Converges for rotation angles below 2π.
  template <int N>
  static JacobianT leftJacobianInverseSeries(const TangentT& xi) {
    return detail::inverseJacobianSeries<G, N>(xi);
  }

  /// ln(exp(ξ1^) exp(ξ2^))^∨ to first order in a small ξ1: J(ξ2)⁻¹ ξ1 + ξ2 (eq. 32,
  /// eqn:bch_approx). Exact on the abelian SO(2).
  static TangentT bchLeftSmall(const TangentT& xi1_small, const TangentT& xi2) {
    return G::leftJacobianInverse(xi2) * xi1_small + xi2;
  }
  /// ln(exp(ξ1^) exp(ξ2^))^∨ to first order in a small ξ2: ξ1 + J(−ξ1)⁻¹ ξ2.
  static TangentT bchRightSmall(const TangentT& xi1, const TangentT& xi2_small) {
    return xi1 + G::leftJacobianInverse(-xi1) * xi2_small;
  }

  /// The geodesic from *this (t = 0) to other (t = 1): *this · exp(t · ln(this⁻¹ · other)).
  G interpolate(const G& other, typename TangentT::Scalar t) const {
    const G& self = static_cast<const G&>(*this);
    return self * G::exp(t * (self.inverse() * other).log());
  }

 protected:
  LieGroupBase() = default;  // only as the base of a group
};

}  // namespace lieservo

#include <lieservo/detail/options_pop.hpp>

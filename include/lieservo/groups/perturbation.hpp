// lieservo/groups/perturbation.hpp — ⊕ and ⊖ on both sides, the Jacobians of the group
// operations, and the validity check of a group element. Written once for SO(2), SE(2), SO(3)
// and SE(3).
//
//   X ⊕ ε = exp(ε^) X             lplus   (left plus: ε is expressed in the fixed frame)
//   X ⊖ Y = ln(X Y⁻¹)^∨           lminus  (the ε with X = exp(ε^) Y)
//   X ⊕ᵣ ε = X exp(ε^)            rplus   (right plus: ε is expressed in the body frame)
//   X ⊖ᵣ Y = ln(Y⁻¹ X)^∨          rminus  (the ε with X = Y exp(ε^))
//
// The left ones are the perturbations of the paper's concentrated Gaussians (eq. 43,
// eqn:se3_pdf_approx): the error of an estimate X̄ of X is lminus(X, X̄). lminus(lplus(X, ε), X)
// = ε while the rotation angle of ε is below π (the principal branch of ln); the same for the
// right ones.
//
// Jacobians follow the library's convention, the left perturbation on every group-valued input
// and output (docs/conventions.md): for Z = f(X), J = ∂Z/∂X is the matrix with
// f(exp(δ^) X) = exp((J δ)^) f(X) + O(|δ|²); a tangent- or point-valued output is perturbed by
// addition. With J_l the left Jacobian (G::leftJacobian, eq. 33, eqn:left_jacobian_def) and
// J_r(ε) = J_l(−ε):
//   compose  Z = X Y          ∂Z/∂X = I,                 ∂Z/∂Y = Ad(X)
//   inverse  Z = X⁻¹          ∂Z/∂X = −Ad(X⁻¹)
//   act      q = X p          ∂q/∂X = [I | −q^] (SE(3); SO(3): −q^; 2-D: the same with
//                             [−q_y; q_x] for the rotation),   ∂q/∂p = R (X's rotation)
//   lplus    Z = exp(ε^) X    ∂Z/∂X = Ad(exp(ε^)),       ∂Z/∂ε = J_l(ε)
//   lminus   τ = ln(X Y⁻¹)^∨  ∂τ/∂X = J_l(τ)⁻¹,          ∂τ/∂Y = −J_r(τ)⁻¹
//   rplus    Z = X exp(ε^)    ∂Z/∂X = I,                 ∂Z/∂ε = Ad(Z) J_r(ε)
//   rminus   σ = ln(Y⁻¹ X)^∨  ∂σ/∂X = J_l(σ)⁻¹ Ad(Y⁻¹),  ∂σ/∂Y = −J_l(σ)⁻¹ Ad(Y⁻¹)
// (tests/groups/test_perturbation.cpp checks each against central differences.)
#pragma once
#include <lieservo/detail/options_push.hpp>

#include <type_traits>
#include <utility>

#include <lieservo/status.hpp>

#include <Eigen/Core>

namespace lieservo {

/// Left plus, X ⊕ ε = exp(ε^) X.
template <class G>
G lplus(const G& X, const typename G::Tangent& eps) {
  return G::exp(eps) * X;
}

/// Left minus, X ⊖ Y = ln(X Y⁻¹)^∨: the left perturbation that takes Y to X.
template <class G>
typename G::Tangent lminus(const G& X, const G& Y) {
  return (X * Y.inverse()).log();
}

/// Right plus, X ⊕ᵣ ε = X exp(ε^).
template <class G>
G rplus(const G& X, const typename G::Tangent& eps) {
  return X * G::exp(eps);
}

/// Right minus, X ⊖ᵣ Y = ln(Y⁻¹ X)^∨: the right perturbation that takes Y to X.
template <class G>
typename G::Tangent rminus(const G& X, const G& Y) {
  return (Y.inverse() * X).log();
}

// ---- Jacobians (the file comment gives each formula) -----------------------------------------

/// Z = X Y with ∂Z/∂X and ∂Z/∂Y.
template <class G>
G compose(const G& X, const G& Y, typename G::Jacobian& J_X, typename G::Jacobian& J_Y) {
  J_X.setIdentity();
  J_Y = X.Ad();
  return X * Y;
}

/// Z = X⁻¹ with ∂Z/∂X.
template <class G>
G inverse(const G& X, typename G::Jacobian& J_X) {
  const G Z = X.inverse();
  J_X = -Z.Ad();
  return Z;
}

/// q = X p (X acting on a point) with ∂q/∂X and ∂q/∂p.
template <class G>
typename G::Point act(const G& X, const typename G::Point& p,
                      Eigen::Matrix<typename G::Scalar, G::Point::RowsAtCompileTime, G::DoF>& J_X,
                      Eigen::Matrix<typename G::Scalar, G::Point::RowsAtCompileTime, G::Point::RowsAtCompileTime>& J_p) {
  constexpr int P = G::Point::RowsAtCompileTime;
  constexpr int rotation_dof = G::RotationDoF;  // the tangent's rotation part comes last
  const typename G::Point q = X * p;
  if constexpr (P == 2) {
    J_X.template rightCols<1>() << -q(1), q(0);  // d/dθ of R(θ) q at θ = 0
  } else {
    J_X.template rightCols<3>() << 0, q(2), -q(1), -q(2), 0, q(0), q(1), -q(0), 0;  // −q^
  }
  if constexpr (G::DoF > rotation_dof) J_X.template leftCols<P>().setIdentity();  // translation
  J_p = X.rotationMatrix();
  return q;
}

/// Z = exp(ε^) X with ∂Z/∂X and ∂Z/∂ε.
template <class G>
G lplus(const G& X, const typename G::Tangent& eps, typename G::Jacobian& J_X, typename G::Jacobian& J_eps) {
  const G E = G::exp(eps);
  J_X = E.Ad();  // exp(ε^) exp(δ^) X = exp((Ad(exp ε^) δ)^) exp(ε^) X
  J_eps = G::leftJacobian(eps);
  return E * X;
}

/// τ = ln(X Y⁻¹)^∨ with ∂τ/∂X and ∂τ/∂Y.
template <class G>
typename G::Tangent lminus(const G& X, const G& Y, typename G::Jacobian& J_X, typename G::Jacobian& J_Y) {
  const typename G::Tangent tau = lminus(X, Y);
  J_X = G::leftJacobianInverse(tau);
  J_Y = -G::leftJacobianInverse(-tau);
  return tau;
}

/// Z = X exp(ε^) with ∂Z/∂X and ∂Z/∂ε.
template <class G>
G rplus(const G& X, const typename G::Tangent& eps, typename G::Jacobian& J_X, typename G::Jacobian& J_eps) {
  const G Z = rplus(X, eps);
  J_X.setIdentity();
  J_eps = Z.Ad() * G::leftJacobian(-eps);
  return Z;
}

/// σ = ln(Y⁻¹ X)^∨ with ∂σ/∂X and ∂σ/∂Y.
template <class G>
typename G::Tangent rminus(const G& X, const G& Y, typename G::Jacobian& J_X, typename G::Jacobian& J_Y) {
  const G Y_inv = Y.inverse();  // once, for σ and Ad(Y⁻¹)
  const typename G::Tangent sigma = (Y_inv * X).log();
  J_X = G::leftJacobianInverse(sigma) * Y_inv.Ad();
  J_Y = -J_X;
  return sigma;
}

namespace detail {
/// Whether G checks its stored numbers itself (G::validate()), as SO(3) and SE(3) do.
template <class G, class = void>
struct HasValidate : std::false_type {};
template <class G>
struct HasValidate<G, std::void_t<decltype(std::declval<const G&>().validate())>> : std::true_type {};
}  // namespace detail

/// Is X a valid element? ok; non_finite_input (a NaN or inf); not_orthonormal (rotation block
/// not orthonormal with det +1 within G's default tolerance); invalid_argument (homogeneous
/// bottom row). The checks of the group's checked constructor G::fromMatrix.
template <class G>
Status validateElement(const G& X) noexcept {
  if constexpr (detail::HasValidate<G>::value) {
    return X.validate();  // the same checks on the stored numbers (SO(3), SE(3))
  } else {
    G tmp;
    return G::fromMatrix(X.matrix(), tmp);
  }
}

}  // namespace lieservo

#include <lieservo/detail/options_pop.hpp>

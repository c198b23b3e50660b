// lieservo/groups/perturbation.hpp — the left perturbation X = exp(ε^) X̄ as operators, and the
// validity check of a group element. Written once for SO(2), SE(2), SO(3) and SE(3).
//
//   X ⊕ ε = exp(ε^) X             lplus   (left plus: ε is expressed in the fixed frame)
//   X ⊖ Y = ln(X Y⁻¹)^∨           lminus  (the ε with X = exp(ε^) Y)
//
// These are the perturbations of the paper's concentrated Gaussians (eq. 43, eqn:se3_pdf_approx): the
// error of an estimate X̄ of X is lminus(X, X̄). lminus(lplus(X, ε), X) = ε while the rotation
// angle of ε is below π (the principal branch of ln).
#pragma once

#include <lieservo/status.hpp>

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

/// Is X a valid element? ok; non_finite_input (a NaN or inf); not_orthonormal (rotation block
/// not orthonormal with det +1 within G's default tolerance); invalid_argument (homogeneous
/// bottom row). The checks of the group's checked constructor G::fromMatrix.
template <class G>
Status validateElement(const G& X) noexcept {
  G tmp;
  return G::fromMatrix(X.matrix(), tmp);
}

}  // namespace lieservo

// lieservo_adapters/gdn_observation.hpp — a GDN prediction (μ, σ in library units,
// mm and rad) as the SE(3) observation Gaussian of the Bayes filter:
//     X̄ᵒᵇˢ = exp(μ^),   Σᵒᵇˢ = J(μ) diag(σ²) J(μ)ᵀ          (eq. 14, eq:se3_inverse_transform)
// via lieservo::fromTangentGaussian. Header-only: the adapters library itself does not
// need the estimation headers.
#pragma once

#include "lieservo/estimation/concentrated_gaussian.hpp"
#include "lieservo/groups/se3.hpp"
#include "lieservo/status.hpp"
#include "lieservo_adapters/onnx_pose_model.hpp"

namespace lieservo::adapters {

/// invalid_argument for a CNN prediction (no σ); otherwise fromTangentGaussian's Status
/// (non_finite_input, not_spd for σ ≤ 0, numerical_failure). `out` unchanged unless ok.
template <class Policy = DefaultJacobian>
Status toObservation(const Prediction& p, ConcentratedGaussian<SE3d>& out) noexcept {
  if (!p.sigma) return Status::invalid_argument;
  return fromTangentGaussian<Policy>(SE3d::Tangent(p.mu), SE3d::Tangent(*p.sigma), out);
}

}  // namespace lieservo::adapters

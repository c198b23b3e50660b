// lieservo_sim/observation_model.hpp — GDN-like pose-and-shear observations (μ, σ).
//
// The real GDN (examples/gdn, paper Section 3.1.5 (sec:gdn_model)) maps a tactile image to a Gaussian over
// ξ = log(X_sf)^∨ = [ρ; φ] (X_sf = X_fs⁻¹, translation first; here mm and RADIANS).  This model
// produces the same output from the true contact pose:
//
//     μ = ξ_true + σ ⊙ ε,   ε ~ N(0, I₆)          (per-component Gaussian errors)
//     σ_i = σ̄_i · h_i(contact),                   (heteroscedastic: the GDN's own σ)
//     h_i = a0_i + a_r,i · |s| / 5 mm + a_z,i · max(0, 1.5 mm − z) / 1 mm
//               + a_t,i · max(0, tilt − 25°) / 10°   (+ ×4 out of contact)
//
// σ grows with the shear magnitude |s| (aliasing under slip, paper Section 5.2 (sec:nn_pose_shear_estimate_exp)
// discussion), at shallow depth (weak images) and outside the training cap of tilts (25°).
// Calibration: σ̄_i is set so that the mean absolute error over the paper's training
// distribution (|s| = 5√u mm, z ~ U[0.5, 6] mm, tilt within 25°, Section 3.1.2 (sec:data_collection)) equals
// the calibration MAE_i:  E|σ ε| = σ·sqrt(2/π)  ⇒  σ̄_i = MAE_i · sqrt(π/2) / E[h_i],
// with E[|s|/5] = 2/3, E[max(0, 1.5 − z)] = 1/11 mm, E[tilt term] = 0.
// Source of MAE_i: a GDN model card's measured MAE (GdnCalibration::fromModelCard; the demo
// reads the deployed GDN's, examples/gdn/models/train_val/model_card.json, when it exists), else the
// paper's Table 1 (tab:nn_pose_shear_estimate_results), GDN column (0.426, 0.422, 0.123 mm;
// 0.45°, 0.64°, 1.16°; GdnCalibration::paperTable1, the default of TaskOptions and the tests).
#pragma once

#include <cstdint>
#include <string>

#include <lieservo/sampling/random.hpp>
#include <lieservo/status.hpp>

#include "common.hpp"
#include "contact_model.hpp"

namespace lieservo::sim {

struct GdnCalibration {
  Vec6 mae = Vec6::Zero();  ///< per component of ξ (mm, mm, mm, rad, rad, rad)
  std::string source;

  /// Paper Table 1, GDN column.
  static GdnCalibration paperTable1();
  /// From per-component MAEs (mm ×3, then DEGREES ×3), e.g. a model card.
  static GdnCalibration fromValues(const Vec6& mae_mm_deg, std::string source);
  /// From a GDN model card (examples/gdn/export_onnx.py): the MAE measured on images the
  /// network never saw, models.gdn.held_out.mae (a network trained on train + val: its held-out
  /// rows) or else models.gdn.validation.mae (trained on train only: the val session), keys
  /// rho1_mm … phi3_deg.  Returns false (out unchanged) if the file is missing or malformed or
  /// the six values are not finite and > 0.
  static bool fromModelCard(const std::string& path, GdnCalibration& out);
  void validate() const;  ///< throws SceneError
};

struct HeteroscedasticShape {
  // Shear components (ρ_x, ρ_y, φ_z) depend mostly on the shear; pose components (ρ_z, φ_x,
  // φ_y) mostly on depth.  Index order of ξ: 0..2 translation, 3..5 rotation.
  Vec6 a0 = (Vec6() << 0.5, 0.5, 0.8, 0.8, 0.8, 0.5).finished();
  Vec6 a_shear = (Vec6() << 0.75, 0.75, 0.3, 0.3, 0.3, 0.75).finished();
  Vec6 a_depth = (Vec6() << 0.5, 0.5, 1.0, 1.0, 1.0, 0.5).finished();
  Vec6 a_tilt = Vec6::Constant(0.5);
  double out_of_contact_factor = 4.0;
};

struct GdnObservation {
  Vec6 mu = Vec6::Zero();     ///< GDN mean of ξ = log(X_sf)^∨ (mm, rad)
  Vec6 sigma = Vec6::Ones();  ///< GDN standard deviations (mm, rad)
  Vec6 truth = Vec6::Zero();  ///< ξ_true, for diagnostics only
};

/// Where the tasks' observations come from: the calibrated Gaussian model below, or the GDN on
/// real TacTip images (real_observation.hpp, the `real` mode). observe never throws; an
/// observation that could not be made returns a Status other than ok.
class ObservationSource {
 public:
  virtual ~ObservationSource() = default;
  virtual Status observe(const ContactState& contact, GdnObservation& out) noexcept = 0;
  /// For reports: which mode ran.
  virtual std::string describe() const = 0;
};

class GdnObservationModel final : public ObservationSource {
 public:
  GdnObservationModel(const GdnCalibration& calibration = GdnCalibration::paperTable1(),
                      const HeteroscedasticShape& shape = {}, std::uint64_t seed = 1);

  /// Observation of the true contact (never throws).
  GdnObservation observe(const ContactState& contact);
  Status observe(const ContactState& contact, GdnObservation& out) noexcept override {
    out = observe(contact);
    return Status::ok;
  }
  std::string describe() const override { return "calibrated Gaussian model (" + calib_.source + ")"; }
  /// σ for a contact (no noise drawn).
  Vec6 sigmaFor(const ContactState& contact) const;
  /// The base σ̄ (mm, rad) after calibration.
  const Vec6& baseSigma() const { return sigma_bar_; }
  const GdnCalibration& calibration() const { return calib_; }
  void reseed(std::uint64_t seed) { rng_.seed(seed); }

 private:
  GdnCalibration calib_;
  HeteroscedasticShape shape_;
  Vec6 sigma_bar_;
  lieservo::sampling::Rng rng_;
};

}  // namespace lieservo::sim

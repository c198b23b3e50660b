// lieservo_sim/real_observation.hpp — the `real` observation mode: the project's GDN on real
// TacTip images, in the simulated loop.
//
// For a simulated contact X_fs, the labelled image whose contact pose is nearest is looked up
// in a k-d tree (nanoflann) over the labels (x, y, z, α, β, γ), each divided by its standard
// deviation over the images used. The images used are those of the shared TacTip data (train
// and val splits only) that the model card says the network did not train on
// (lieservo_dataset/trained_on.hpp): an error on a trained-on image is a fitting error, smaller
// than what a new contact shows. The
// ONNX GDN runs on that image through the OpenCV adapters (pre-processing, cv::dnn; its output
// is cached per image), and the observation carries the GDN's error on the image over to the
// simulated contact (ξ = log(X_sf)^∨, mm and rad):
//
//     μ = ξ_true + (μ_GDN(image) − ξ_image),    σ = σ_GDN(image)
//
// with σ as the adapter gives it (the model card's σ calibration applied). No noise is drawn:
// the errors are the network's own, heteroscedastic and correlated between nearby contacts as
// a real sensor's are. Contacts outside the data's range (deeper than 6 mm, tilted beyond
// 25°, out of contact) take the nearest image at the range's edge.
//
// Needs OpenCV and nanoflann (the lieservo_sim_real target); set-up errors throw SceneError
// naming the path, observe() never throws.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "observation_model.hpp"

namespace lieservo::sim {

struct RealObservationOptions {
  std::string data_dir;    ///< the TacTip data: <data_dir>/<split>/targets.csv, processed_images/
  std::string model_card;  ///< model_card.json naming the GDN's ONNX file
  std::vector<std::string> splits{"train", "val"};  ///< only the shared train and val sets
  /// Whether any split's targets.csv exists: the programs' `auto` mode then runs `real`.
  bool dataSetPresent() const;
};

class RealGdnObservations final : public ObservationSource {
 public:
  /// Reads the labels of the images the card's network did not train on, builds the tree and
  /// loads the GDN. Throws SceneError naming what is missing or malformed: the data set
  /// (RealObservationOptions::data_dir), a split's targets.csv, the model card, its held-out
  /// list or its ONNX file, or fewer than two unseen images.
  explicit RealGdnObservations(const RealObservationOptions& options);
  ~RealGdnObservations() override;
  RealGdnObservations(const RealGdnObservations&) = delete;
  RealGdnObservations& operator=(const RealGdnObservations&) = delete;

  /// The observation of a simulated contact. invalid_argument when the image cannot be read
  /// or the network fails on it, numerical_failure for a non-finite output (lastError() says
  /// which image and why).
  Status observe(const ContactState& contact, GdnObservation& out) noexcept override;
  std::string describe() const override;

  std::size_t size() const noexcept;  ///< labelled images
  /// The image whose label is nearest to the contact pose e = (x, y, z mm; α, β, γ rad).
  std::size_t nearest(const Vec6& euler) const noexcept;
  const Vec6& labelEuler(std::size_t i) const;  ///< (x, y, z, α, β, γ) of image i (mm, rad)
  const Vec6& labelXi(std::size_t i) const;     ///< ξ_image = log(X_fs⁻¹)^∨ (mm, rad)
  const std::string& imagePath(std::size_t i) const;
  /// The GDN on image i (μ, σ in mm and rad), computed once and cached.
  Status prediction(std::size_t i, Vec6& mu, Vec6& sigma) noexcept;
  std::size_t evaluatedImages() const noexcept;  ///< distinct images run through the GDN so far
  const std::string& lastError() const noexcept;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace lieservo::sim

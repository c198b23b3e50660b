// lieservo_adapters/onnx_pose_model.hpp — runs the trained pose-and-shear networks
// (GDN, paper Section 3.1.5 (sec:gdn_model); CNN regression, Section 3.1.4 (sec:cnn_model)) exported to ONNX, with
// OpenCV's cv::dnn, and converts their outputs to library units.
//
// Network outputs are in the units recorded in the model card (this project's models:
// mm and DEGREES; σ⁻¹ in 1/mm and 1/deg). Prediction::mu / sigma are converted to
// library units: translation mm (unchanged), rotation RADIANS. The SE(3) observation
// Gaussian (eq. 14, eq:se3_inverse_transform) is built in gdn_observation.hpp.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <opencv2/dnn.hpp>

#include <lieservo/status.hpp>

namespace lieservo::adapters {

enum class ModelKind { gdn, cnn };

/// What the adapter needs from a model card (models.<kind> entry of model_card.json).
struct ModelCard {
  ModelKind kind = ModelKind::gdn;
  std::string onnx_file;  ///< absolute or relative to the card's directory ("" if not given)
  /// SHA-256 of the ONNX file, 64 lowercase hex digits (models.<kind>.sha256, or sha256 in a
  /// flat card; "" = not given): the loader refuses a file that does not match. Every card the
  /// project ships carries it (examples/gdn/export_onnx.py writes it; tests/adapters check it).
  std::string sha256;
  int input_size = 128;   ///< input [N, 1, input_size, input_size]
  int outputs = 12;       ///< 12 for a GDN (μ, σ⁻¹), 6 for a CNN
  /// Per-component factor from network units to library units (mm -> 1, deg -> π/180, rad -> 1).
  std::array<double, 6> to_library{1, 1, 1, 1, 1, 1};
  std::array<std::string, 6> units{"mm", "mm", "mm", "deg", "deg", "deg"};
  /// σ calibration (GDN only): Prediction::sigma = sigma_scale ⊙ (the network's σ). All ones
  /// (the network as trained, the paper's use) unless the card has
  /// `sigma_calibration: {"scale": [6 positive numbers], "source": "..."}` — factors measured on
  /// images the network did not train on (examples/gdn/calibrate_sigma.py).
  std::array<double, 6> sigma_scale{1, 1, 1, 1, 1, 1};
  std::string sigma_calibration_source;  ///< where sigma_scale comes from ("" = none)
  bool hasSigmaCalibration() const noexcept {
    for (double k : sigma_scale)
      if (k != 1.0) return true;
    return false;
  }

  /// Reads model_card.json. Accepts the project's card (models.{gdn,cnn}.{file,input.shape,
  /// output.shape,output.units}) and a flat card ({"kind", "input_size", "output_units": [6 strings]}),
  /// either with an optional sigma_calibration entry (GDN only).
  /// Throws std::runtime_error naming the file and the missing/invalid field.
  static ModelCard fromJsonFile(const std::string& path, ModelKind kind);
};

/// SHA-256 of a file's bytes, 64 lowercase hex digits. Throws std::runtime_error naming the file
/// when it cannot be read.
std::string sha256OfFile(const std::string& path);

/// One network evaluation, in library units (mm, rad).
struct Prediction {
  Eigen::Matrix<double, 6, 1> mu = Eigen::Matrix<double, 6, 1>::Zero();        ///< ξ estimate [ρ; φ]
  /// Std dev σ (mm, rad) of a GDN's prediction; a CNN (regression head only) has none.
  std::optional<Eigen::Matrix<double, 6, 1>> sigma;
  std::array<double, 12> raw{};  ///< the network's outputs as returned (network units)
  bool hasUncertainty() const noexcept { return sigma.has_value(); }
  /// σ⁻¹ in library units (1/mm, 1/rad); nullopt for a CNN.
  std::optional<Eigen::Matrix<double, 6, 1>> precisionSqrt() const {
    if (!sigma) return std::nullopt;
    return Eigen::Matrix<double, 6, 1>(sigma->cwiseInverse());
  }
};

class OnnxPoseModel {
 public:
  /// Loads the ONNX file and checks it against the card (runs one dummy input to verify the
  /// output shape). Throws std::runtime_error for a missing/malformed model or card.
  OnnxPoseModel(const std::string& onnx_path, const ModelCard& card);
  /// Loads the model named by the card's models.<kind>.file, relative to the card's directory.
  static OnnxPoseModel fromCard(const std::string& card_path, ModelKind kind);

  const ModelCard& card() const noexcept { return card_; }
  bool hasUncertainty() const noexcept { return card_.outputs == 12; }

  /// One pre-processed image: CV_32FC1 (or CV_8UC1, scaled by 1/255) input_size x input_size.
  /// Status: ok; invalid_argument (empty image, wrong size or type); device_error (cv::dnn
  /// failed or returned an unexpected shape); numerical_failure (a non-finite output or a
  /// σ⁻¹ ≤ 0). `prediction` is written only when ok; lastError() gives the detail.
  Status predict(const cv::Mat& image, Prediction& prediction);
  /// A batch (all the same size/type); one forward pass. Status as predict(); an empty batch
  /// is invalid_argument. `predictions` is written only when ok.
  Status predictBatch(const std::vector<cv::Mat>& images, std::vector<Prediction>& predictions);
  /// What the latest failed call met; empty before any failure.
  const std::string& lastError() const noexcept { return last_error_; }

  /// Converts raw network outputs (card.outputs values, network units) to a Prediction
  /// (library units; σ multiplied by card.sigma_scale). numerical_failure for NaN/inf or
  /// σ⁻¹ <= 0 (the component is in `detail` when given); `prediction` written only when ok.
  static Status fromRaw(const ModelCard& card, const double* raw, Prediction& prediction,
                        std::string* detail = nullptr);

 private:
  Status fail(Status s, std::string detail);
  Status checkInput(const cv::Mat& image, std::size_t index, cv::Mat& input);

  ModelCard card_;
  std::string path_;
  cv::dnn::Net net_;
  std::string last_error_;
};

}  // namespace lieservo::adapters

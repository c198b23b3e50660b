// examples/collection/image_source.hpp — where collection gets its tactile images from.
//
// ImageSource is the seam for the real camera: an adapter (examples/adapters) grabs a
// 640×480 frame, pre-processes it (grayscale, crop, median blur, adaptive threshold — paper
// Section 3.1.3 (sec:pre_post_processing)) and returns the processed 8-bit image; paramsJson() describes that
// processing (written as processed_image_params.json). For CI, SyntheticTactileSource renders
// a binarised marker pattern that depends on the current sensor pose relative to the surface.
#pragma once

#include "image_io.hpp"
#include <lieservo_dataset/json_writer.hpp>

#include <robot/robot_interface.hpp>

#include <lieservo/groups/se3.hpp>
#include <lieservo/status.hpp>

#include <cmath>
#include <string>

namespace lieservo::collection {

// The JSON and data set readers are the shared ones of examples/dataset.
using namespace lieservo::dataset;

class ImageSource {
 public:
  virtual ~ImageSource() = default;
  /// Capture one pre-processed image (blocking). Not ok → the sample is not written.
  virtual Status capture(GrayImage& out) = 0;
  /// One-line JSON object describing the processing (processed_image_params.json).
  virtual std::string paramsJson() const = 0;
};

/// A stand-in tactile image: a hexagonal grid of white markers on black inside a circular
/// mask. The markers shift with the translational shear and the tilt, rotate with γ, and
/// grow with the depth — so every distinct pose gives a distinct image. Not a sensor model.
class SyntheticTactileSource final : public ImageSource {
 public:
  /// `arm` is read at each capture; X_wf is the surface feature frame in the work frame.
  SyntheticTactileSource(robot::RobotInterface& arm, const SE3<double>& X_wf, int width = 128,
                         int height = 128)
      : arm_(arm), X_fw_(X_wf.inverse()), width_(width), height_(height) {}

  Status capture(GrayImage& out) override {
    if (width_ <= 0 || height_ <= 0) return Status::invalid_argument;
    SE3<double> X_ws;
    const Status st = arm_.readPose(X_ws);
    if (st != Status::ok) return st;
    const auto e = (X_fw_ * X_ws).toEulerXYZ6();  // x, y, z (mm), α, β, γ (rad)
    const double depth = e(2) > 0 ? e(2) : 0.0;
    const double cg = std::cos(-e(5)), sg = std::sin(-e(5));
    // Normalised image coordinates in [-1, 1]; marker spacing 0.16, radius grows with depth.
    const double shift_u = 0.02 * e(0) + 0.4 * e(4) * (0.5 + depth / 6.0);
    const double shift_v = 0.02 * e(1) - 0.4 * e(3) * (0.5 + depth / 6.0);
    const double spacing = 0.16, radius = 0.035 + 0.006 * depth;
    const double s3 = std::sqrt(3.0);
    GrayImage img(width_, height_, 0);
    for (int r = 0; r < height_; ++r) {
      for (int c = 0; c < width_; ++c) {
        const double u = (2.0 * c + 1.0) / width_ - 1.0, v = (2.0 * r + 1.0) / height_ - 1.0;
        if (u * u + v * v > 0.9 * 0.9) continue;
        const double du = u - shift_u, dv = v - shift_v;
        const double pu = cg * du - sg * dv, pv = sg * du + cg * dv;
        // nearest point of the lattice a1 = (s, 0), a2 = (s/2, s√3/2)
        const double j = pv / (spacing * s3 / 2.0);
        const double i = pu / spacing - j / 2.0;
        double best = 1e9;
        for (int di = 0; di <= 1; ++di) {
          for (int dj = 0; dj <= 1; ++dj) {
            const double li = std::floor(i) + di, lj = std::floor(j) + dj;
            const double qu = spacing * (li + lj / 2.0), qv = spacing * s3 / 2.0 * lj;
            const double d2 = (pu - qu) * (pu - qu) + (pv - qv) * (pv - qv);
            if (d2 < best) best = d2;
          }
        }
        if (best < radius * radius) img.at(r, c) = 255;
      }
    }
    out = std::move(img);
    return Status::ok;
  }

  std::string paramsJson() const override {
    return JsonObjectWriter()
        .field("type", "synthetic")
        .field("pattern", "hexagonal markers, pose dependent (lieservo stand-in, not a sensor model)")
        .field("gray", true)
        .field("binarised", true)
        .field("size", std::vector<double>{static_cast<double>(width_), static_cast<double>(height_)})
        .str();
  }

 private:
  robot::RobotInterface& arm_;
  SE3<double> X_fw_;
  int width_, height_;
};

}  // namespace lieservo::collection

// Synthetic TacTip-like raw camera frames (640 x 480 BGR): bright round markers on a
// dark, slightly noisy background, arranged on a hexagonal grid inside the crop.
#pragma once

#include <cmath>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace synthetic {

struct SyntheticFrame {
  cv::Mat bgr;                             ///< 640 x 480, CV_8UC3
  std::vector<cv::Point> markers_in_crop;  ///< marker centres, crop coordinates
  std::vector<cv::Point> gaps_in_crop;     ///< points between markers, crop coordinates
};

/// `shift` moves the marker grid by that many pixels in x (makes frames differ).
inline SyntheticFrame makeRawFrame(int shift, unsigned seed = 1) {
  SyntheticFrame f;
  f.bgr = cv::Mat(480, 640, CV_8UC3, cv::Scalar(35, 40, 45));
  cv::Mat noise(480, 640, CV_8UC3);
  cv::RNG rng(seed);
  rng.fill(noise, cv::RNG::UNIFORM, 0, 12);
  f.bgr += noise;
  const cv::Point crop_origin(105, 20), centre(222, 220);
  const double pitch = 24.0;
  for (int row = -9; row <= 9; ++row) {
    for (int col = -9; col <= 9; ++col) {
      const double x = centre.x + shift + col * pitch + ((row & 1) != 0 ? pitch / 2 : 0.0);
      const double y = centre.y + row * pitch * std::sqrt(3.0) / 2.0;
      if (std::hypot(x - centre.x, y - centre.y) > 190.0) continue;
      const cv::Point c(static_cast<int>(std::lround(x)), static_cast<int>(std::lround(y)));
      cv::circle(f.bgr, c + crop_origin, 7, cv::Scalar(230, 235, 240), cv::FILLED, cv::LINE_AA);
      f.markers_in_crop.push_back(c);
      // Midway to the right-hand neighbour: background.
      const cv::Point g(static_cast<int>(std::lround(x + pitch / 2)), c.y);
      if (std::hypot(g.x - centre.x, g.y - centre.y) < 180.0) f.gaps_in_crop.push_back(g);
    }
  }
  // A bright blob in the crop's corner, outside the mask radius: must be masked out.
  cv::circle(f.bgr, crop_origin + cv::Point(8, 8), 6, cv::Scalar(255, 255, 255), cv::FILLED);
  return f;
}

}  // namespace synthetic

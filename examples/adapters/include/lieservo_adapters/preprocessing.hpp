// lieservo_adapters/preprocessing.hpp — TacTip image pre-processing
// (paper Section 3.1.3 (sec:pre_post_processing)).
//
// Raw camera frame (640 x 480, BGR or gray)
//   1. 8-bit grayscale                                   (paper step 1)
//   2. crop to bbox [x0, y0, x1, y1] = [105, 20, 550, 460] -> 445 x 440 (step 2;
//      the data set's processed_image_params.json gives the box actually used)
//   3. 5 x 5 median blur                                 (step 3)
//   4. adaptive threshold, Gaussian-weighted, block 61, C 5, THRESH_BINARY (step 4):
//      the markers come out white (255) on black, as in the data set's images
//   5. circular mask radius 230 about the crop centre (w/2, h/2); outside -> 0
//      (checked against the data set: its processed images are 0 beyond r = 230)
//   6. resize to 128 x 128 with INTER_AREA on the 8-bit image (step 5)
//   7. convert to float32 and divide by 255 -> [0, 1]    (step 6)
// The data set's processed_images/ already hold the output of steps 1-5; for those,
// only steps 6-7 apply (fromProcessed).
#pragma once

#include <string>

#include <opencv2/core.hpp>

#include <lieservo/status.hpp>

namespace lieservo::adapters {

struct PreprocessParams {
  cv::Size raw_size{640, 480};       ///< expected camera frame size (width, height)
  bool gray = true;                  ///< convert to grayscale (must be true: the network takes one channel)
  cv::Rect bbox{105, 20, 445, 440};  ///< crop, from [x0, y0, x1, y1] = [105, 20, 550, 460]
  int median_kernel = 5;             ///< median blur aperture (odd, >= 3); 0 disables
  bool threshold = true;             ///< apply the adaptive threshold
  int threshold_block = 61;          ///< adaptive threshold block size (odd, >= 3)
  double threshold_c = 5.0;          ///< adaptive threshold constant C
  int circle_mask_radius = 230;      ///< 0 disables the mask
  int output_size = 128;             ///< network input: output_size x output_size

  /// Size of the processed (cropped) image, i.e. the data set's processed_images size.
  cv::Size processedSize() const { return bbox.size(); }

  /// Throws std::runtime_error naming the offending field when a value is out of range.
  void validate() const;

  /// Reads a data set's processed_image_params.json (keys "gray", "bbox",
  /// "thresh" [block, C], "circle_mask_radius"; unknown keys are ignored).
  /// Throws std::runtime_error naming the file (and line/column for malformed JSON).
  static PreprocessParams fromJsonFile(const std::string& path);
};

/// The pre-processor. Per-image calls return a lieservo::Status (invalid_argument for an empty
/// image or a wrong size, depth or channel count; io_error for a file that cannot be read),
/// write their output only when it is ok, and leave the detail in lastError(). One object per
/// thread: the detail is the object's only state (copies are cheap).
class Preprocessor {
 public:
  Preprocessor() : Preprocessor(PreprocessParams{}) {}
  explicit Preprocessor(PreprocessParams params);  ///< validates; throws std::runtime_error

  const PreprocessParams& params() const noexcept { return p_; }

  /// Steps 1-5: raw frame (raw_size; 8-bit, 1/3/4 channels) -> 8-bit binary image of
  /// bbox size, like the data set's processed_images.
  Status binarise(const cv::Mat& raw, cv::Mat& binary) const;

  /// Steps 1-7: raw frame -> CV_32FC1 output_size x output_size in [0, 1].
  Status processRaw(const cv::Mat& raw, cv::Mat& input) const;

  /// Steps 6-7 for an already-processed image (bbox size; 8-bit, 1/3/4 channels).
  Status fromProcessed(const cv::Mat& processed, cv::Mat& input) const;

  /// Reads a processed image from disk (grayscale) and applies fromProcessed.
  Status loadProcessed(const std::string& path, cv::Mat& input) const;

  /// What the latest failed call met (sizes, types, the path); empty before any failure.
  const std::string& lastError() const noexcept { return last_error_; }

 private:
  Status fail(Status s, std::string detail) const;
  Status toGray8(const cv::Mat& img, const cv::Size& expected, const char* what, cv::Mat& gray) const;
  cv::Mat resizeAndScale(const cv::Mat& gray8) const;

  PreprocessParams p_;
  cv::Mat mask_;  ///< 8-bit circular mask of bbox size (empty when disabled)
  mutable std::string last_error_;
};

}  // namespace lieservo::adapters

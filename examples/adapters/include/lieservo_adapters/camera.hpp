// lieservo_adapters/camera.hpp — a TacTip camera (cv::VideoCapture) yielding
// pre-processed frames (paper Section 3.1.3 (sec:pre_post_processing)) with steady_clock time stamps.
//
// Sources: a device index (live camera), a video file, or an image sequence given as a
// printf pattern such as "dir/image_%d.png" (OpenCV's CAP_IMAGES backend).
// Frames are raw camera frames (640 x 480) by default; set
// CameraOptions::input = FrameInput::processed for sequences of already-processed
// images (such as the data set's processed_images/).
//
// Opening throws std::runtime_error (set-up). next() never throws and returns a
// lieservo::Status: device_error for a live camera that stops delivering frames or for a
// stale frame (bitwise the frame before: a frozen driver re-delivering its last buffer),
// end_of_stream for a file/sequence that ends, invalid_argument for a frame of the wrong
// size or type; lastError() gives the detail.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>

#include <opencv2/core.hpp>
#include <opencv2/videoio.hpp>

#include "lieservo_adapters/preprocessing.hpp"

namespace lieservo::adapters {

enum class FrameInput { raw, processed };

struct CameraOptions {
  FrameInput input = FrameInput::raw;
  bool set_resolution = true;       ///< devices only: request raw_size from the driver
  double exposure = 0.0;            ///< devices only: CAP_PROP_EXPOSURE when != 0 (data set used -7)
  int max_consecutive_failures = 3; ///< live sources: failed reads before device_error
  /// Path sources are live (a failed read = device_error) when the path is a device node
  /// ("/dev/video…") or a stream URL ("…://…"), or when this is set; otherwise a failed
  /// read is the end of the file/sequence (end_of_stream).
  bool force_live = false;
  /// A frame bitwise equal to the one read before it is stale and never delivered: a live
  /// TacTip image always changes by its sensor noise, and a frozen camera or driver
  /// re-delivers its last buffer. A live source counts it as a failed read and reads again
  /// (device_error after max_consecutive_failures in a row); a file or sequence returns
  /// device_error for it and goes on with the next frame at the next call. Meanwhile the loop
  /// sends no command, and the robot's watchdog stops the arm if no fresh frame follows
  /// (docs/hardware.md).
  bool refuse_stale = true;
};

struct CameraFrame {
  cv::Mat image;  ///< pre-processed network input: CV_32FC1, output_size², in [0, 1]
  cv::Mat raw;    ///< the frame as read (BGR or gray)
  std::chrono::steady_clock::time_point stamp;  ///< when the read returned
  std::uint64_t index = 0;                      ///< 0, 1, 2, ... frames delivered
};

class TactileCamera {
 public:
  /// Live camera by device index. Throws std::runtime_error when it cannot be opened.
  TactileCamera(int device, Preprocessor preprocessor, CameraOptions options = {});
  /// Video file or image-sequence pattern ("dir/image_%d.png"). Throws when it cannot be opened.
  TactileCamera(const std::string& path, Preprocessor preprocessor, CameraOptions options = {});

  TactileCamera(const TactileCamera&) = delete;
  TactileCamera& operator=(const TactileCamera&) = delete;

  /// Reads and pre-processes the next frame into `frame` (written only when ok).
  Status next(CameraFrame& frame);
  /// What the latest failed next() met; empty before any failure.
  const std::string& lastError() const noexcept { return last_error_; }

  bool isLive() const noexcept { return live_; }
  const std::string& source() const noexcept { return source_; }
  std::uint64_t framesDelivered() const noexcept { return delivered_; }
  void release();

 private:
  cv::VideoCapture cap_;
  Preprocessor pre_;
  CameraOptions opt_;
  std::string source_;
  bool live_ = false;
  bool lost_ = false;
  std::uint64_t delivered_ = 0;
  std::uint64_t read_ = 0;  ///< frames read, stale ones included
  cv::Mat previous_;        ///< the last frame read (refuse_stale)
  std::string last_error_;
};

}  // namespace lieservo::adapters

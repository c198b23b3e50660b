// lieservo_adapters/tactile_frame.hpp — one tactile frame as a rig's tactile thread sees it:
// a 640x480 camera frame, the Preprocessor and the card's GDN, and a timer for the whole loop
// (image -> preprocessing -> GDN -> observation Gaussian -> Bayes filter -> servo controller ->
// one cycle of the real-time pipeline: FrameLoop) on one thread. Used by lieservo_frame_bench
// (benchmarks/bench_frame.cpp) and the demo's report (examples/replay/demo_hook.cpp).
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include <opencv2/core.hpp>

#include <lieservo/lieservo.hpp>
#include "lieservo_adapters/onnx_pose_model.hpp"
#include "lieservo_adapters/preprocessing.hpp"

namespace lieservo::adapters {

struct TactileFrame {
  Preprocessor preprocessor;
  OnnxPoseModel gdn;
  cv::Mat raw;               ///< the camera frame (8-bit, the preprocessor's raw size)
  std::string image_source;  ///< what the frame shows, for reports

  /// The processed image at `processed_png` (a data set's processed_images/*.png) placed into
  /// its camera frame's crop box, or, when it cannot be read, a drawn pin pattern of the same
  /// size (the GDN's time does not depend on what it sees; image_source says which); the GDN
  /// of the model card at `card_path`. Throws std::runtime_error for a missing or bad card or
  /// model.
  static TactileFrame load(const std::string& processed_png, const std::string& card_path);
};

/// The rest of a frame after the network, as a rig's tactile thread runs it: the observation
/// Gaussian (eq. 14, eq:se3_inverse_transform), the Bayes filter (Algorithm 2,
/// alg:se3_bayes_filter), the servo controller (surface following, Table 7) and one 1 ms cycle
/// of the real-time pipeline with the new command. Used by timeFrames and by
/// benchmarks/bench_frame.cpp.
struct FrameLoop {
  using Loop = TactileLoop<TactileServoController<SE3d>>;  ///< the filter and the servo (control/tactile_loop.hpp)
  Loop loop{Loop::Options{{}, surfaceFollowingPreset<double>()}};
  realtime::CartesianVelocityPipeline pipeline;
  ConcentratedGaussian<SE3d> observation;
  SE3d::Tangent twist = SE3d::Tangent::Zero();  ///< the servo's command (sensor frame)
  std::array<double, 6> command{};              ///< the pipeline's output (base frame)
  std::uint64_t frames = 0;

  /// The robot's sensor pose at frame k: 0.5 mm and 0.1° per frame, as in a slow servo,
  /// wrapping every 50 frames.
  static SE3d robotPose(std::uint64_t k);
  /// One frame from the network's prediction, the robot at robotPose(frames), stamped at 20 Hz.
  /// The first failing stage's Status; a failure leaves the loop's state as each stage's
  /// contract says (unchanged for the failing stage). A gated observation is not a failure:
  /// the tactile loop's policy uses the prediction.
  Status step(const Prediction& prediction);
};

/// Medians over the timed frames, in microseconds.
struct FrameTiming {
  double preprocess_us = 0, gdn_us = 0;
  double estimation_control_us = 0;  ///< observation + filter step + controller step + one pipeline cycle
  double whole_us = 0;               ///< the whole frame
  int frames = 0;
};

/// Runs `frames` frames (after two warm-up ones) through every stage on this thread, with
/// OpenCV held to one thread meanwhile, and returns the median stage times. A stage that fails
/// throws std::runtime_error naming it.
FrameTiming timeFrames(TactileFrame& frame, int frames);

}  // namespace lieservo::adapters

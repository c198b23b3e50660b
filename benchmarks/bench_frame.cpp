// The whole tactile frame, stage by stage, on one thread (docs/performance.md, "The whole
// tactile frame"): what one camera frame costs from the image to the robot command.
//
//   raw 640x480 frame -> Preprocessor::processRaw (crop, median, adaptive threshold, mask,
//   128x128, [0, 1]) -> the deployed GDN (ONNX, OpenCV dnn) -> toObservation (eq. 14,
//   eq:se3_inverse_transform) -> DiscriminativeBayesFilter::step (Algorithm 2, alg:se3_bayes_filter)
//   -> TactileServoController::step (eq. 19, eqn:ff_fb_pid_control) -> one 1 ms cycle of
//   realtime::CartesianVelocityPipeline (on hardware its own 1 kHz thread runs it 50 times per
//   20 Hz frame).
//
// The image: val/processed_images/image_1.png of the shared TacTip data set, placed into its
// camera frame's crop box (the data set holds processed images only); without the data set a
// drawn pin pattern of the same size (lieservo_adapters/tactile_frame.hpp). The benchmark's
// context says which. benchmarks/frame_report.py runs it beside the same network's
// forward pass in PyTorch and prints each stage's share and the frame rate the loop sustains.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include <opencv2/core.hpp>

#include <lieservo/lieservo.hpp>
#include "lieservo_adapters/gdn_observation.hpp"
#include "lieservo_adapters/tactile_frame.hpp"
#include "bench_main.hpp"

namespace {

using namespace lieservo;
namespace ad = lieservo::adapters;

struct Frame {
  std::unique_ptr<ad::TactileFrame> tactile;
  cv::Mat input;  // the network input the camera frame gives
  ad::Prediction prediction;
  ConcentratedGaussian<SE3d> observation;
};

Frame& frame() {
  static Frame f;
  return f;
}

// -1 when the frame goes through; kSkipped without the TacTip data.
int setUp() {
  Frame& f = frame();
  const std::string image = std::string(LIESERVO_DATA_DIR) + "/val/processed_images/image_1.png";
  if (!std::filesystem::exists(image)) {
    std::printf("lieservo_frame_bench: SKIPPED: %s not found (the TacTip data set is absent)\n", image.c_str());
    return lieservo::cli::kSkipped;
  }
  f.tactile = std::make_unique<ad::TactileFrame>(ad::TactileFrame::load(
      image, std::string(LIESERVO_SOURCE_DIR) + "/examples/gdn/models/train_val/model_card.json"));
  if (f.tactile->preprocessor.processRaw(f.tactile->raw, f.input) != Status::ok ||
      f.tactile->gdn.predict(f.input, f.prediction) != Status::ok ||
      ad::toObservation(f.prediction, f.observation) != Status::ok) {
    std::fprintf(stderr, "bench_frame: the frame does not go through: %s %s\n",
                 f.tactile->preprocessor.lastError().c_str(), f.tactile->gdn.lastError().c_str());
    return lieservo::cli::kUsageOrSetup;
  }
  return -1;
}

void BM_FramePreprocess(benchmark::State& state) {
  Frame& f = frame();
  cv::Mat input;
  for (auto _ : state) {
    benchmark::DoNotOptimize(f.tactile->preprocessor.processRaw(f.tactile->raw, input));
    benchmark::ClobberMemory();
  }
}
BENCHMARK(BM_FramePreprocess)->Unit(benchmark::kMicrosecond);

void BM_FrameGdn(benchmark::State& state) {
  Frame& f = frame();
  ad::Prediction p;
  for (auto _ : state) benchmark::DoNotOptimize(f.tactile->gdn.predict(f.input, p));
}
BENCHMARK(BM_FrameGdn)->Unit(benchmark::kMicrosecond);

void BM_FrameObservation(benchmark::State& state) {
  Frame& f = frame();
  ConcentratedGaussian<SE3d> g;
  for (auto _ : state) {
    benchmark::DoNotOptimize(ad::toObservation(f.prediction, g));
    benchmark::DoNotOptimize(g);
  }
}
BENCHMARK(BM_FrameObservation)->Unit(benchmark::kMicrosecond);

// The robot moves as in FrameLoop::robotPose: 0.5 mm and 0.1° between frames.
void BM_FrameFilter(benchmark::State& state) {
  Frame& f = frame();
  DiscriminativeBayesFilter<SE3d> filter;
  (void)filter.step(SE3d(), f.observation);  // the first step initialises
  int k = 0;
  for (auto _ : state) benchmark::DoNotOptimize(filter.step(ad::FrameLoop::robotPose(std::uint64_t(++k)), f.observation));
}
BENCHMARK(BM_FrameFilter)->Unit(benchmark::kMicrosecond);

void BM_FrameController(benchmark::State& state) {
  Frame& f = frame();
  TactileServoController<SE3d> servo(surfaceFollowingPreset<double>());
  SE3d::Tangent u;
  for (auto _ : state) {
    benchmark::DoNotOptimize(servo.step(f.observation.mean, 0.05, u));
    benchmark::DoNotOptimize(u);
  }
}
BENCHMARK(BM_FrameController)->Unit(benchmark::kMicrosecond);

// One 1 ms cycle of the real-time pipeline with a fresh command, as an adapter runs it: the one
// parse of the robot's pose, watchdog, sensor twist to the base frame, jerk-limited smoothing.
void BM_FramePipeline(benchmark::State& state) {
  realtime::CartesianVelocityPipeline pipeline;
  realtime::TwistCommand cmd;
  cmd.twist_s = {1.0, 0.0, 0.0, 0.0, 0.0, 0.01};
  cmd.in_contact = true;
  const Eigen::Matrix4d T_OE = Eigen::Matrix4d::Identity();
  std::array<double, 6> out{};
  std::int64_t now = 0;
  std::uint64_t sequence = 0;
  for (auto _ : state) {
    now += 1000000;
    SE3d T;
    benchmark::DoNotOptimize(realtime::poseFromHomogeneous(T_OE, T));
    benchmark::DoNotOptimize(pipeline.step(T, cmd, realtime::ChannelStamp{++sequence, now}, now, out));
    benchmark::DoNotOptimize(out);
  }
}
BENCHMARK(BM_FramePipeline)->Unit(benchmark::kMicrosecond);

// Everything above in sequence, as the tactile thread runs it for one frame (with the
// pipeline's cycle that takes the frame's command).
void BM_FrameWhole(benchmark::State& state) {
  Frame& f = frame();
  ad::FrameLoop loop;
  cv::Mat input;
  ad::Prediction p;
  for (auto _ : state) {
    Status s = f.tactile->preprocessor.processRaw(f.tactile->raw, input);
    if (s == Status::ok) s = f.tactile->gdn.predict(input, p);
    if (s == Status::ok) s = loop.step(p);
    if (s != Status::ok) {
      state.SkipWithError("a stage failed");
      break;
    }
    benchmark::DoNotOptimize(loop.command);
  }
}
BENCHMARK(BM_FrameWhole)->Unit(benchmark::kMicrosecond);

}  // namespace

int main(int argc, char** argv) {
  cv::setNumThreads(1);  // one thread: the tactile thread's budget
  return lieservo::bench::runBenchmarks(argc, argv, "one tactile frame on one thread, stage by stage", [] {
    if (const int status = setUp(); status >= 0) return status;
    benchmark::AddCustomContext("frame_image", frame().tactile->image_source);
    benchmark::AddCustomContext("frame_model", "examples/gdn/models/train_val/model_card.json (the deployed GDN)");
    benchmark::AddCustomContext("frame_threads", "1 (cv::setNumThreads(1))");
    return -1;
  });
}

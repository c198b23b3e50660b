// examples/adapters/src/tactile_frame.cpp — see lieservo_adapters/tactile_frame.hpp.
#include "lieservo_adapters/tactile_frame.hpp"

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "lieservo_adapters/gdn_observation.hpp"

namespace lieservo::adapters {
namespace {

// A TacTip-like camera frame: bright pins on a dark ground, inside the crop box.
cv::Mat drawnFrame(const PreprocessParams& p) {
  cv::Mat raw(p.raw_size, CV_8UC1, cv::Scalar(40));
  const cv::Point c(p.bbox.x + p.bbox.width / 2, p.bbox.y + p.bbox.height / 2);
  for (int y = -220; y <= 220; y += 22)
    for (int x = -220; x <= 220; x += 22)
      if (x * x + y * y < 220 * 220) cv::circle(raw, c + cv::Point(x, y), 6, cv::Scalar(200), cv::FILLED);
  return raw;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

TactileFrame TactileFrame::load(const std::string& processed_png, const std::string& card_path) {
  TactileFrame f{Preprocessor(), OnnxPoseModel::fromCard(card_path, ModelKind::gdn), cv::Mat(), ""};
  const PreprocessParams& p = f.preprocessor.params();
  const cv::Mat processed = cv::imread(processed_png, cv::IMREAD_GRAYSCALE);
  if (!processed.empty() && processed.size() == p.processedSize()) {
    f.raw = cv::Mat(p.raw_size, CV_8UC1, cv::Scalar(0));
    processed.copyTo(f.raw(p.bbox));
    f.image_source = processed_png + " in its camera frame's crop box";
  } else {
    f.raw = drawnFrame(p);
    f.image_source = "a drawn pin pattern (" + processed_png + " cannot be read)";
  }
  return f;
}

SE3d FrameLoop::robotPose(std::uint64_t k) {
  SE3d::Tangent xi;
  xi << 0.5, 0.0, 0.0, 0.0, 0.0, 1.745e-3;
  return SE3d::exp(double(k % 50) * xi);
}

Status FrameLoop::step(const Prediction& prediction) {
  ++frames;
  Status s = toObservation(prediction, observation);
  if (s == Status::ok) s = loop.step(robotPose(frames), observation, 0.05, twist);
  if (s != Status::ok) return s;
  realtime::TwistCommand cmd;
  for (int j = 0; j < 6; ++j) cmd.twist_s[std::size_t(j)] = twist[j];
  cmd.in_contact = true;
  const std::int64_t now = std::int64_t(frames) * 50000000;  // 20 Hz
  return pipeline.step(SE3d(), cmd, realtime::ChannelStamp{frames, now}, now, command);
}

FrameTiming timeFrames(TactileFrame& frame, int frames) {
  using clock = std::chrono::steady_clock;
  auto us = [](clock::time_point a, clock::time_point b) { return std::chrono::duration<double, std::micro>(b - a).count(); };
  FrameLoop loop;
  cv::Mat input;
  Prediction prediction;
  std::vector<double> pre, gdn, rest, whole;
  const int threads = cv::getNumThreads();
  cv::setNumThreads(1);  // the tactile thread's budget: one core
  struct Restore {
    int n;
    ~Restore() { cv::setNumThreads(n); }
  } restore{threads};
  for (int k = 0; k < frames + 2; ++k) {
    const clock::time_point t0 = clock::now();
    if (frame.preprocessor.processRaw(frame.raw, input) != Status::ok)
      throw std::runtime_error("preprocessing failed: " + frame.preprocessor.lastError());
    const clock::time_point t1 = clock::now();
    if (frame.gdn.predict(input, prediction) != Status::ok) throw std::runtime_error("the GDN failed: " + frame.gdn.lastError());
    const clock::time_point t2 = clock::now();
    const Status s = loop.step(prediction);
    const clock::time_point t3 = clock::now();
    if (s != Status::ok) throw std::runtime_error(std::string("the estimation and control stages failed: ") + describe(s));
    if (k < 2) continue;  // warm-up
    pre.push_back(us(t0, t1));
    gdn.push_back(us(t1, t2));
    rest.push_back(us(t2, t3));
    whole.push_back(us(t0, t3));
  }
  FrameTiming t;
  t.frames = frames;
  t.preprocess_us = median(pre);
  t.gdn_us = median(gdn);
  t.estimation_control_us = median(rest);
  t.whole_us = median(whole);
  return t;
}

}  // namespace lieservo::adapters

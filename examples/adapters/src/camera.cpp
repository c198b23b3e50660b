#include "lieservo_adapters/camera.hpp"

#include <algorithm>
#include <stdexcept>

namespace lieservo::adapters {

TactileCamera::TactileCamera(int device, Preprocessor preprocessor, CameraOptions options)
    : pre_(std::move(preprocessor)), opt_(options), source_("camera device " + std::to_string(device)), live_(true) {
  if (opt_.input != FrameInput::raw) throw std::runtime_error(source_ + ": a live camera delivers raw frames");
  bool opened = false;
  try {
    opened = cap_.open(device);
  } catch (const cv::Exception& e) {
    throw std::runtime_error(source_ + ": cannot open: " + e.what());
  }
  if (!opened || !cap_.isOpened()) throw std::runtime_error(source_ + ": cannot open (no such camera or busy)");
  if (opt_.set_resolution) {
    cap_.set(cv::CAP_PROP_FRAME_WIDTH, pre_.params().raw_size.width);
    cap_.set(cv::CAP_PROP_FRAME_HEIGHT, pre_.params().raw_size.height);
  }
  if (opt_.exposure != 0.0) cap_.set(cv::CAP_PROP_EXPOSURE, opt_.exposure);
}

TactileCamera::TactileCamera(const std::string& path, Preprocessor preprocessor, CameraOptions options)
    : pre_(std::move(preprocessor)),
      opt_(options),
      source_(path),
      live_(options.force_live || path.rfind("/dev/video", 0) == 0 || path.find("://") != std::string::npos) {
  if (path.empty()) throw std::runtime_error("TactileCamera: empty source path");
  bool opened = false;
  try {
    // An image-sequence pattern goes to CAP_IMAGES; anything else to whichever backend takes it.
    const bool pattern = path.find('%') != std::string::npos;
    opened = pattern ? cap_.open(path, cv::CAP_IMAGES) : cap_.open(path);
  } catch (const cv::Exception& e) {
    throw std::runtime_error(path + ": cannot open video/image sequence: " + e.what());
  }
  if (!opened || !cap_.isOpened())
    throw std::runtime_error(path + ": cannot open video/image sequence (missing file, or no frame matches the pattern)");
}

void TactileCamera::release() {
  cap_.release();
  lost_ = true;
}

Status TactileCamera::next(CameraFrame& frame) {
  if (lost_ || !cap_.isOpened()) {
    last_error_ = source_ + ": not open";
    return live_ ? Status::device_error : Status::end_of_stream;
  }
  CameraFrame f;
  const int attempts = live_ ? std::max(1, opt_.max_consecutive_failures) : 1;
  bool got = false, stale = false;
  for (int i = 0; i < attempts && !got; ++i) {
    try {
      got = cap_.read(f.raw) && !f.raw.empty();
    } catch (const cv::Exception&) {
      got = false;
    }
    stale = false;
    if (!got) continue;
    ++read_;
    if (opt_.refuse_stale) {
      stale = !previous_.empty() && previous_.size == f.raw.size && previous_.type() == f.raw.type() &&
              cv::norm(previous_, f.raw, cv::NORM_INF) == 0.0;
      f.raw.copyTo(previous_);
      got = !stale;  // a stale read counts as a failed one: a live camera reads again
    }
  }
  f.stamp = std::chrono::steady_clock::now();
  if (stale) {
    last_error_ = source_ + ": stale frame: read " + std::to_string(read_) + " is bitwise the one before it" +
                  (attempts > 1 ? " (" + std::to_string(attempts) + " reads in a row)" : std::string()) +
                  ": a frozen camera re-delivers its last buffer";
    return Status::device_error;
  }
  if (!got) {
    lost_ = true;
    if (live_) {
      last_error_ = source_ + ": camera lost: " + std::to_string(attempts) +
                    " consecutive reads failed or returned an empty frame after " + std::to_string(delivered_) +
                    " frames";
      return Status::device_error;
    }
    last_error_ = source_ + ": end of stream after " + std::to_string(delivered_) + " frames";
    return Status::end_of_stream;
  }
  const Status s = opt_.input == FrameInput::raw ? pre_.processRaw(f.raw, f.image) : pre_.fromProcessed(f.raw, f.image);
  if (s != Status::ok) {
    last_error_ = source_ + " frame " + std::to_string(delivered_) + ": " + pre_.lastError();
    return s;
  }
  f.index = delivered_++;
  frame = std::move(f);
  return Status::ok;
}

}  // namespace lieservo::adapters

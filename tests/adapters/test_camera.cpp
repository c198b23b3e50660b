// TactileCamera on image sequences (real processed images, synthetic raw frames) and on
// sources that do not exist.
#include <catch2/catch.hpp>

#include <filesystem>
#include <string>

#include <opencv2/imgcodecs.hpp>

#include "lieservo_adapters/camera.hpp"
#include "file_test_util.hpp"
#include "synthetic_frames.hpp"

using namespace lieservo::adapters;
using lieservo::Status;

TEST_CASE("camera: image sequence of real processed images", "[adapters][camera][data]") {
  const std::string src = std::string(LIESERVO_DATA_DIR) + "/val/processed_images";
  if (!file_test::exists(src + "/image_1.png")) {
    WARN("TacTip data not found under " << LIESERVO_DATA_DIR << ": skipping");
    return;
  }
  const std::string dir = file_test::makeTempDir("cam");
  const int n = 5;
  for (int i = 1; i <= n; ++i)
    std::filesystem::copy_file(src + "/image_" + std::to_string(i) + ".png",
                               dir + "/image_" + std::to_string(i) + ".png");
  const Preprocessor pre;
  CameraOptions opt;
  opt.input = FrameInput::processed;
  TactileCamera cam(dir + "/image_%d.png", pre, opt);
  CHECK_FALSE(cam.isLive());
  auto last = std::chrono::steady_clock::time_point::min();
  for (int i = 1; i <= n; ++i) {
    CameraFrame f;
    REQUIRE(cam.next(f) == Status::ok);
    CHECK(f.index == static_cast<std::uint64_t>(i - 1));
    CHECK(f.stamp >= last);
    last = f.stamp;
    REQUIRE(f.image.size() == cv::Size(128, 128));
    // The same network input as reading the file directly.
    cv::Mat direct;
    REQUIRE(pre.loadProcessed(dir + "/image_" + std::to_string(i) + ".png", direct) == Status::ok);
    CHECK(cv::norm(f.image, direct, cv::NORM_INF) == 0.0);
  }
  CameraFrame end;
  end.index = 42;
  CHECK(cam.next(end) == Status::end_of_stream);
  CHECK(end.index == 42u);  // a failed call leaves the frame as it was
  CHECK(cam.lastError().find("after 5 frames") != std::string::npos);
  CHECK(cam.framesDelivered() == 5u);

  // The same processed images treated as raw camera frames: clear size error, not a crash.
  TactileCamera as_raw(dir + "/image_%d.png", pre);
  CameraFrame wrong;
  CHECK(as_raw.next(wrong) == Status::invalid_argument);
  CHECK(as_raw.lastError().find("640x480") != std::string::npos);
  file_test::removeTree(dir);
}

TEST_CASE("camera: image sequence of synthetic raw frames", "[adapters][camera]") {
  const std::string dir = file_test::makeTempDir("camraw");
  const Preprocessor pre;
  for (int i = 0; i < 3; ++i) cv::imwrite(dir + "/frame_" + std::to_string(i) + ".png", synthetic::makeRawFrame(3 * i).bgr);
  TactileCamera cam(dir + "/frame_%d.png", pre);
  for (int i = 0; i < 3; ++i) {
    CameraFrame f;
    REQUIRE(cam.next(f) == Status::ok);
    CHECK(f.raw.size() == cv::Size(640, 480));
    cv::Mat expected;
    REQUIRE(pre.processRaw(synthetic::makeRawFrame(3 * i).bgr, expected) == Status::ok);
    CHECK(cv::norm(f.image, expected, cv::NORM_INF) == 0.0);
  }
  CameraFrame f;
  CHECK(cam.next(f) == Status::end_of_stream);
  // Once ended it stays ended.
  CHECK(cam.next(f) == Status::end_of_stream);

  // The same source treated as a live camera: running out of frames is a lost camera.
  CameraOptions live;
  live.force_live = true;
  TactileCamera lost(dir + "/frame_%d.png", pre, live);
  CHECK(lost.isLive());
  for (int i = 0; i < 3; ++i) REQUIRE(lost.next(f) == Status::ok);
  CHECK(lost.next(f) == Status::device_error);
  CHECK(lost.lastError().find("camera lost") != std::string::npos);
  CHECK(lost.lastError().find("after 3 frames") != std::string::npos);
  CHECK(lost.next(f) == Status::device_error);
  file_test::removeTree(dir);
}

TEST_CASE("camera: missing sources throw at set-up with the path", "[adapters][camera]") {
  const Preprocessor pre;
  CHECK_THROWS_WITH(TactileCamera("/nonexistent/dir/image_%d.png", pre), Catch::Contains("/nonexistent/dir/image_%d.png"));
  CHECK_THROWS_WITH(TactileCamera("/nonexistent/video.mp4", pre), Catch::Contains("cannot open"));
  CHECK_THROWS_WITH(TactileCamera(std::string(), pre), Catch::Contains("empty source path"));
  const std::string dir = file_test::makeTempDir("camempty");
  CHECK_THROWS(TactileCamera(dir + "/image_%d.png", pre));  // pattern matches nothing
  file_test::removeTree(dir);
  CameraOptions processed;
  processed.input = FrameInput::processed;
  CHECK_THROWS_WITH(TactileCamera(0, pre, processed), Catch::Contains("raw frames"));
  // A device index with no camera behind it.
  CHECK_THROWS_WITH(TactileCamera(97, pre), Catch::Contains("camera device 97"));
}

TEST_CASE("camera: a stale frame (bitwise the one before) is refused, the next fresh one delivered",
          "[adapters][camera]") {
  // Frames 0, 1, 1 again (a frozen driver re-delivering its buffer), 2.
  const std::string dir = file_test::makeTempDir("camstale");
  const Preprocessor pre;
  const int shifts[] = {0, 3, 3, 6};
  for (int i = 0; i < 4; ++i) cv::imwrite(dir + "/frame_" + std::to_string(i) + ".png", synthetic::makeRawFrame(shifts[i]).bgr);
  TactileCamera cam(dir + "/frame_%d.png", pre);
  CameraFrame f;
  REQUIRE(cam.next(f) == Status::ok);
  REQUIRE(cam.next(f) == Status::ok);
  const CameraFrame before = f;
  CHECK(cam.next(f) == Status::device_error);
  CHECK(cam.lastError().find("stale frame") != std::string::npos);
  CHECK(cam.lastError().find("read 3") != std::string::npos);
  CHECK(f.index == before.index);  // the frame is left as it was
  CHECK(f.stamp == before.stamp);
  CHECK(cam.framesDelivered() == 2);
  REQUIRE(cam.next(f) == Status::ok);  // fresh again
  cv::Mat expected;
  REQUIRE(pre.processRaw(synthetic::makeRawFrame(6).bgr, expected) == Status::ok);
  CHECK(cv::norm(f.image, expected, cv::NORM_INF) == 0.0);
  CHECK(f.index == 2);
  CHECK(cam.next(f) == Status::end_of_stream);

  // With the check off, the repeated frame is delivered like any other.
  CameraOptions keep;
  keep.refuse_stale = false;
  TactileCamera all(dir + "/frame_%d.png", pre, keep);
  for (int i = 0; i < 4; ++i) REQUIRE(all.next(f) == Status::ok);
  CHECK(all.framesDelivered() == 4);
  file_test::removeTree(dir);
}

TEST_CASE("camera: a live source reads past a stale frame, and reports a frozen one", "[adapters][camera]") {
  const std::string dir = file_test::makeTempDir("camfrozen");
  const Preprocessor pre;
  // 0, 1, 1, 2, then 2 three times more: one repeat is read past, four in a row are a frozen camera.
  const int shifts[] = {0, 3, 3, 6, 6, 6, 6};
  for (int i = 0; i < 7; ++i) cv::imwrite(dir + "/frame_" + std::to_string(i) + ".png", synthetic::makeRawFrame(shifts[i]).bgr);
  CameraOptions live;
  live.force_live = true;  // max_consecutive_failures = 3
  TactileCamera cam(dir + "/frame_%d.png", pre, live);
  CameraFrame f;
  REQUIRE(cam.next(f) == Status::ok);
  REQUIRE(cam.next(f) == Status::ok);
  REQUIRE(cam.next(f) == Status::ok);  // the repeat of frame 1 is read past
  cv::Mat expected;
  REQUIRE(pre.processRaw(synthetic::makeRawFrame(6).bgr, expected) == Status::ok);
  CHECK(cv::norm(f.image, expected, cv::NORM_INF) == 0.0);
  CHECK(f.index == 2);
  const CameraFrame before = f;
  CHECK(cam.next(f) == Status::device_error);  // three reads in a row, each bitwise the one before
  CHECK(cam.lastError().find("stale frame") != std::string::npos);
  CHECK(cam.lastError().find("3 reads in a row") != std::string::npos);
  CHECK(f.index == before.index);
  CHECK(cam.framesDelivered() == 3);
  file_test::removeTree(dir);
}

// TacTip pre-processing (paper Section 3.1.3 (sec:pre_post_processing)) on synthetic raw frames and on
// the data set's processed images.
#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <string>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "lieservo_adapters/preprocessing.hpp"
#include "file_test_util.hpp"
#include "synthetic_frames.hpp"

using namespace lieservo::adapters;
using lieservo::Status;

TEST_CASE("preprocessing: synthetic raw frame -> binary crop and 128x128 network input", "[adapters][preprocessing]") {
  const Preprocessor pre;  // the data set's parameters are the defaults
  const synthetic::SyntheticFrame sf = synthetic::makeRawFrame(7);
  REQUIRE(sf.bgr.size() == cv::Size(640, 480));

  cv::Mat b;
  REQUIRE(pre.binarise(sf.bgr, b) == Status::ok);
  REQUIRE(b.size() == cv::Size(445, 440));
  REQUIRE(b.type() == CV_8UC1);
  // Binary.
  cv::Mat not_binary = (b != 0) & (b != 255);
  CHECK(cv::countNonZero(not_binary) == 0);
  // Markers white, gaps between them black (as in the data set's images).
  int white_markers = 0;
  for (const cv::Point& c : sf.markers_in_crop) white_markers += b.at<uchar>(c) == 255 ? 1 : 0;
  CHECK(white_markers == static_cast<int>(sf.markers_in_crop.size()));
  int black_gaps = 0;
  for (const cv::Point& g : sf.gaps_in_crop) black_gaps += b.at<uchar>(g) == 0 ? 1 : 0;
  CHECK(black_gaps >= static_cast<int>(0.95 * static_cast<double>(sf.gaps_in_crop.size())));
  // Circular mask: radius 230 about (222, 220); everything beyond is 0, even the bright
  // marker the synthetic frame puts in the corner of the crop.
  for (int y = 0; y < b.rows; ++y)
    for (int x = 0; x < b.cols; ++x)
      if (std::hypot(x - 222.0, y - 220.0) > 230.5) REQUIRE(b.at<uchar>(y, x) == 0);

  cv::Mat in;
  REQUIRE(pre.processRaw(sf.bgr, in) == Status::ok);
  REQUIRE(in.size() == cv::Size(128, 128));
  REQUIRE(in.type() == CV_32FC1);
  double lo = 0, hi = 0;
  cv::minMaxLoc(in, &lo, &hi);
  CHECK(lo >= 0.0);
  CHECK(hi <= 1.0);
  CHECK(hi > 0.9);
  // Equals resize(INTER_AREA) of the 8-bit binary image, then / 255.
  cv::Mat small, expected;
  cv::resize(b, small, cv::Size(128, 128), 0, 0, cv::INTER_AREA);
  small.convertTo(expected, CV_32F, 1.0 / 255.0);
  CHECK(cv::norm(in, expected, cv::NORM_INF) == 0.0);

  // Gray and BGRA inputs give the same result as BGR.
  cv::Mat gray, bgra, from_gray, from_bgra;
  cv::cvtColor(sf.bgr, gray, cv::COLOR_BGR2GRAY);
  cv::cvtColor(sf.bgr, bgra, cv::COLOR_BGR2BGRA);
  REQUIRE(pre.processRaw(gray, from_gray) == Status::ok);
  REQUIRE(pre.processRaw(bgra, from_bgra) == Status::ok);
  CHECK(cv::norm(from_gray, in, cv::NORM_INF) == 0.0);
  CHECK(cv::norm(from_bgra, in, cv::NORM_INF) == 0.0);
}

TEST_CASE("preprocessing: wrong sizes, types and empty images give clear errors", "[adapters][preprocessing]") {
  const Preprocessor pre;
  // The output is written only on success: a failed call leaves it as it was.
  const cv::Mat before = cv::Mat::ones(3, 3, CV_32F);
  cv::Mat out = before.clone();
  auto rejected = [&](Status s, Status expected, const std::string& words) {
    CHECK(s == expected);
    CHECK(cv::norm(out, before, cv::NORM_INF) == 0.0);
    CHECK(pre.lastError().find(words) != std::string::npos);
  };
  rejected(pre.processRaw(cv::Mat::zeros(440, 445, CV_8UC1), out), Status::invalid_argument, "expected 640x480");
  CHECK(pre.lastError().find("445x440") != std::string::npos);
  rejected(pre.fromProcessed(cv::Mat::zeros(480, 640, CV_8UC3), out), Status::invalid_argument, "expected 445x440");
  rejected(pre.processRaw(cv::Mat(), out), Status::invalid_argument, "empty image");
  rejected(pre.fromProcessed(cv::Mat::zeros(440, 445, CV_16UC1), out), Status::invalid_argument, "8-bit");
  rejected(pre.fromProcessed(cv::Mat::zeros(440, 445, CV_8UC2), out), Status::invalid_argument, "channels");
  rejected(pre.loadProcessed("/nonexistent/image_1.png", out), Status::io_error, "/nonexistent/image_1.png");

  const std::string dir = file_test::makeTempDir("prep");
  std::ofstream(dir + "/not_an_image.png") << "this is not a PNG";
  rejected(pre.loadProcessed(dir + "/not_an_image.png", out), Status::io_error, "not_an_image.png");
  file_test::removeTree(dir);

  PreprocessParams bad;
  bad.bbox = cv::Rect(300, 100, 445, 440);
  CHECK_THROWS_WITH(Preprocessor(bad), Catch::Contains("outside"));
}

TEST_CASE("preprocessing: the data set's processed images", "[adapters][preprocessing][data]") {
  const std::string val = std::string(LIESERVO_DATA_DIR) + "/val";
  if (!file_test::exists(val + "/processed_images/image_1.png")) {
    WARN("TacTip data not found under " << LIESERVO_DATA_DIR << ": skipping");
    return;
  }
  const Preprocessor pre(PreprocessParams::fromJsonFile(val + "/processed_image_params.json"));
  for (const char* name : {"image_1.png", "image_1000.png", "image_2000.png"}) {
    const std::string path = val + "/processed_images/" + name;
    const cv::Mat raw8 = cv::imread(path, cv::IMREAD_GRAYSCALE);
    REQUIRE(raw8.size() == cv::Size(445, 440));
    cv::Mat in;
    REQUIRE(pre.loadProcessed(path, in) == Status::ok);
    REQUIRE(in.size() == cv::Size(128, 128));
    REQUIRE(in.type() == CV_32FC1);
    double lo = 0, hi = 0;
    cv::minMaxLoc(in, &lo, &hi);
    CHECK(lo == 0.0);
    CHECK(hi == Approx(1.0));
    // Area resampling keeps the mean intensity (up to 8-bit rounding).
    CHECK(cv::mean(in)[0] == Approx(cv::mean(raw8)[0] / 255.0).margin(2e-3));
    // Outside the mask stays black: the corners.
    CHECK(in.at<float>(0, 0) == 0.0f);
    CHECK(in.at<float>(127, 127) == 0.0f);
    // Each value is an 8-bit level / 255.
    for (int y = 0; y < 128; y += 7)
      for (int x = 0; x < 128; x += 7) {
        const double v = 255.0 * in.at<float>(y, x);
        REQUIRE(std::fabs(v - std::round(v)) < 1e-3);
      }
    // The processed image is a fixed point of the mask step: re-masking changes nothing.
    cv::Mat mask = cv::Mat::zeros(raw8.size(), CV_8UC1), remasked = cv::Mat::zeros(raw8.size(), CV_8UC1);
    cv::circle(mask, cv::Point(222, 220), 230, cv::Scalar(255), cv::FILLED);
    raw8.copyTo(remasked, mask);
    CHECK(cv::countNonZero(remasked != raw8) == 0);
  }
}

// processed_image_params.json goes through the shared JSON reader (examples/dataset):
// malformed files name the file, line and column; wrongly typed values the file and the key.
TEST_CASE("preprocessing: params file errors name the path (and line:column, or the key)", "[adapters][preprocessing][json]") {
  CHECK_THROWS_WITH(PreprocessParams::fromJsonFile("/nonexistent/dir/params.json"),
                    Catch::Contains("/nonexistent/dir/params.json") && Catch::Contains("cannot open"));
  const std::string dir = file_test::makeTempDir("json");
  const std::string bad = dir + "/processed_image_params.json";
  std::ofstream(bad) << "{\"gray\": true, \"bbox\": [105, 20, 550 460]}";
  CHECK_THROWS_WITH(PreprocessParams::fromJsonFile(bad), Catch::Contains(bad + ":1:"));
  std::ofstream(bad) << "{\"gray\": true, \"bbox\": [105, 20, 550]}";
  CHECK_THROWS_WITH(PreprocessParams::fromJsonFile(bad),
                    Catch::Contains(bad + ": error: \"bbox\"") && Catch::Contains("should have 4 entries"));
  std::ofstream(bad) << "{\"gray\": true, \"bbox\": [105, 20.5, 550, 460]}";
  CHECK_THROWS_WITH(PreprocessParams::fromJsonFile(bad), Catch::Contains(bad + ": error: \"bbox[1]\"") && Catch::Contains("integer"));
  std::ofstream(bad) << "{\"gray\": \"yes\"}";
  CHECK_THROWS_WITH(PreprocessParams::fromJsonFile(bad), Catch::Contains(bad + ": error: \"gray\"") && Catch::Contains("true or false"));
  std::ofstream(bad) << "{\"bbox\": [105, 20, 700, 460]}";
  CHECK_THROWS_WITH(PreprocessParams::fromJsonFile(bad), Catch::Contains(bad) && Catch::Contains("outside"));
  std::ofstream(bad) << "{\"thresh\": [60, 5]}";
  CHECK_THROWS_WITH(PreprocessParams::fromJsonFile(bad), Catch::Contains("odd"));
  std::ofstream(bad) << "{\"gray\": true, \"thresh\": false, \"circle_mask_radius\": null, \"dims\": [64, 64], \"z\": [Infinity]}";
  const PreprocessParams ok = PreprocessParams::fromJsonFile(bad);
  CHECK(ok.gray);
  CHECK_FALSE(ok.threshold);
  CHECK(ok.circle_mask_radius == 0);
  CHECK(ok.output_size == 64);
  file_test::removeTree(dir);
}

TEST_CASE("preprocessing: the data set's processed_image_params.json", "[adapters][preprocessing][json][data]") {
  const std::string val = std::string(LIESERVO_DATA_DIR) + "/val";
  if (!file_test::exists(val + "/processed_image_params.json")) {
    WARN("TacTip data not found under " << LIESERVO_DATA_DIR << ": skipping");
    return;
  }
  const PreprocessParams p = PreprocessParams::fromJsonFile(val + "/processed_image_params.json");
  CHECK(p.gray);
  CHECK(p.bbox == cv::Rect(105, 20, 445, 440));
  CHECK(p.processedSize() == cv::Size(445, 440));
  CHECK(p.threshold);
  CHECK(p.threshold_block == 61);
  CHECK(p.threshold_c == 5.0);
  CHECK(p.circle_mask_radius == 230);
  CHECK(p.output_size == 128);
}

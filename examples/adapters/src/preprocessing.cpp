#include "lieservo_adapters/preprocessing.hpp"

#include <sstream>
#include <stdexcept>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <lieservo_dataset/json.hpp>

namespace lieservo::adapters {


namespace {
std::string sizeStr(const cv::Size& s) {
  std::ostringstream os;
  os << s.width << "x" << s.height;
  return os.str();
}
}  // namespace

void PreprocessParams::validate() const {
  auto bad = [](const std::string& m) { throw std::runtime_error("PreprocessParams: " + m); };
  if (raw_size.width <= 0 || raw_size.height <= 0) bad("raw_size must be positive");
  if (!gray) bad("gray must be true (the networks take one channel)");
  if (bbox.width <= 0 || bbox.height <= 0) bad("bbox must have x1 > x0 and y1 > y0");
  if (bbox.x < 0 || bbox.y < 0 || bbox.x + bbox.width > raw_size.width || bbox.y + bbox.height > raw_size.height)
    bad("bbox [" + std::to_string(bbox.x) + "," + std::to_string(bbox.y) + "," + std::to_string(bbox.x + bbox.width) +
        "," + std::to_string(bbox.y + bbox.height) + "] lies outside the " + sizeStr(raw_size) + " frame");
  if (median_kernel != 0 && (median_kernel < 3 || median_kernel % 2 == 0)) bad("median_kernel must be 0 or odd >= 3");
  if (threshold && (threshold_block < 3 || threshold_block % 2 == 0)) bad("threshold block must be odd >= 3");
  if (circle_mask_radius < 0) bad("circle_mask_radius must be >= 0");
  if (output_size <= 0) bad("output_size must be positive");
}

PreprocessParams PreprocessParams::fromJsonFile(const std::string& path) {
  // The shared reader (examples/dataset): Python's Infinity/NaN accepted; malformed input and
  // wrongly typed values throw DatasetError naming the path (and line:column, or the key).
  using lieservo::dataset::DatasetError;
  using lieservo::dataset::JsonValue;
  using lieservo::dataset::find;
  const lieservo::dataset::JsonDocument doc = lieservo::dataset::readJsonFile(path);
  PreprocessParams p;
  try {
    const JsonValue& r = doc.expect(doc.root.IsObject(), doc.root, "", "top level should be an object");
    if (const JsonValue* v = find(r, "gray")) p.gray = doc.asBool(*v, "gray");
    if (const JsonValue* v = find(r, "bbox"); v != nullptr && !v->IsNull()) {
      const auto a = doc.asArray(*v, "bbox");
      if (a.Size() != 4) doc.fail("bbox", "should have 4 entries [x0, y0, x1, y1]");
      const int x0 = doc.asInt(a[0], "bbox[0]"), y0 = doc.asInt(a[1], "bbox[1]");
      const int x1 = doc.asInt(a[2], "bbox[2]"), y1 = doc.asInt(a[3], "bbox[3]");
      p.bbox = cv::Rect(x0, y0, x1 - x0, y1 - y0);
    }
    if (const JsonValue* v = find(r, "thresh")) {
      if (v->IsNull() || v->IsFalse()) {
        p.threshold = false;
      } else {
        const auto a = doc.asArray(*v, "thresh");
        if (a.Size() != 2) doc.fail("thresh", "should be [block_size, C]");
        p.threshold = true;
        p.threshold_block = doc.asInt(a[0], "thresh[0]");
        p.threshold_c = doc.asNumber(a[1], "thresh[1]");
      }
    }
    if (const JsonValue* v = find(r, "circle_mask_radius")) {
      p.circle_mask_radius = v->IsNull() ? 0 : doc.asInt(*v, "circle_mask_radius");
    }
    if (const JsonValue* v = find(r, "dims"); v != nullptr && !v->IsNull()) {
      const auto a = doc.asArray(*v, "dims");
      if (a.Size() != 2 || doc.asInt(a[0], "dims[0]") != doc.asInt(a[1], "dims[1]"))
        doc.fail("dims", "should be a square [n, n]");
      p.output_size = doc.asInt(a[0], "dims[0]");
    }
    p.validate();
  } catch (const DatasetError&) {
    throw;  // already names the file and where in it
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(path + ": " + e.what());
  }
  return p;
}

Preprocessor::Preprocessor(PreprocessParams params) : p_(params) {
  p_.validate();
  if (p_.circle_mask_radius > 0) {
    mask_ = cv::Mat::zeros(p_.bbox.size(), CV_8UC1);
    // Centre (w/2, h/2) with integer division, filled disc of radius r: matches the data set.
    cv::circle(mask_, cv::Point(p_.bbox.width / 2, p_.bbox.height / 2), p_.circle_mask_radius, cv::Scalar(255),
               cv::FILLED, cv::LINE_8);
  }
}

Status Preprocessor::fail(Status s, std::string detail) const {
  last_error_ = std::move(detail);
  return s;
}

Status Preprocessor::toGray8(const cv::Mat& img, const cv::Size& expected, const char* what, cv::Mat& gray) const {
  if (img.empty()) return fail(Status::invalid_argument, std::string(what) + ": empty image");
  if (img.size() != expected)
    return fail(Status::invalid_argument,
                std::string(what) + ": expected " + sizeStr(expected) + " but got " + sizeStr(img.size()));
  if (img.depth() != CV_8U)
    return fail(Status::invalid_argument,
                std::string(what) + ": expected an 8-bit image, got depth " + std::to_string(img.depth()));
  switch (img.channels()) {
    case 1: gray = img; break;
    case 3: cv::cvtColor(img, gray, cv::COLOR_BGR2GRAY); break;
    case 4: cv::cvtColor(img, gray, cv::COLOR_BGRA2GRAY); break;
    default:
      return fail(Status::invalid_argument,
                  std::string(what) + ": expected 1, 3 or 4 channels, got " + std::to_string(img.channels()));
  }
  return Status::ok;
}

cv::Mat Preprocessor::resizeAndScale(const cv::Mat& gray8) const {
  cv::Mat small, out;
  cv::resize(gray8, small, cv::Size(p_.output_size, p_.output_size), 0, 0, cv::INTER_AREA);
  small.convertTo(out, CV_32F, 1.0 / 255.0);
  return out;
}

Status Preprocessor::binarise(const cv::Mat& raw, cv::Mat& binary) const {
  cv::Mat g;
  const Status s = toGray8(raw, p_.raw_size, "raw frame", g);
  if (s != Status::ok) return s;
  cv::Mat img = g(p_.bbox).clone();
  if (p_.median_kernel > 0) {
    cv::Mat blurred;
    cv::medianBlur(img, blurred, p_.median_kernel);
    img = blurred;
  }
  if (p_.threshold) {
    cv::Mat thresholded;
    cv::adaptiveThreshold(img, thresholded, 255, cv::ADAPTIVE_THRESH_GAUSSIAN_C, cv::THRESH_BINARY, p_.threshold_block,
                          p_.threshold_c);
    img = thresholded;
  }
  if (!mask_.empty()) {
    cv::Mat masked = cv::Mat::zeros(img.size(), CV_8UC1);
    img.copyTo(masked, mask_);
    img = masked;
  }
  binary = img;
  return Status::ok;
}

Status Preprocessor::processRaw(const cv::Mat& raw, cv::Mat& input) const {
  cv::Mat b;
  const Status s = binarise(raw, b);
  if (s != Status::ok) return s;
  input = resizeAndScale(b);
  return Status::ok;
}

Status Preprocessor::fromProcessed(const cv::Mat& processed, cv::Mat& input) const {
  cv::Mat g;
  const Status s = toGray8(processed, p_.processedSize(), "processed image", g);
  if (s != Status::ok) return s;
  input = resizeAndScale(g);
  return Status::ok;
}

Status Preprocessor::loadProcessed(const std::string& path, cv::Mat& input) const {
  cv::Mat img;
  try {
    img = cv::imread(path, cv::IMREAD_GRAYSCALE);
  } catch (const cv::Exception& e) {
    return fail(Status::io_error, path + ": " + e.what());
  }
  if (img.empty()) return fail(Status::io_error, path + ": cannot read image (missing or not an image)");
  const Status s = fromProcessed(img, input);
  if (s != Status::ok) last_error_ = path + ": " + last_error_;
  return s;
}

}  // namespace lieservo::adapters

#include "replay_network.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <stdexcept>
#include <utility>

#include <lieservo_cli/program.hpp>

#include <opencv2/core.hpp>
#include <opencv2/core/utility.hpp>

#include "lieservo_adapters/onnx_pose_model.hpp"
#include "lieservo_adapters/preprocessing.hpp"

namespace lieservo::replay {

namespace cli = lieservo::cli;
namespace ad = lieservo::adapters;
using Clock = std::chrono::steady_clock;

namespace {
// The magic line names the format's version; any version's file is the replay's own to replace.
constexpr const char* kCacheFamily = "lieservo-replay-cache";
constexpr const char* kCacheMagic = "lieservo-replay-cache v2 (sha256)";

}  // namespace

std::string cacheKey(const std::string& gdn_onnx, const std::string& cnn_onnx, const std::vector<Sample>& samples,
                     const std::string& image_dir) {
  const std::string cnn = cnn_onnx.empty() ? std::string("none") : adapters::sha256OfFile(cnn_onnx);
  return "gdn " + adapters::sha256OfFile(gdn_onnx) + " cnn " + cnn + " n " + std::to_string(samples.size()) +
         " first " + (samples.empty() ? std::string("-") : samples.front().image) + " last " +
         (samples.empty() ? std::string("-") : samples.back().image) + " images " + image_dir;
}

void requireOwnCache(const std::string& path) {
  std::string why;
  if (cli::mayOverwrite("--cache", path, kCacheFamily, why)) return;
  std::error_code ec;
  throw std::runtime_error(std::filesystem::exists(path, ec) ? why + " (it is not a lieservo_replay cache)" : why);
}

bool readCache(const std::string& path, const std::string& key, std::size_t n, bool with_cnn, RawOutputs& out) {
  std::ifstream in(path);
  if (!in) return false;
  std::string magic, k;
  if (!std::getline(in, magic) || magic != kCacheMagic) return false;
  if (!std::getline(in, k) || k != key) return false;
  RawOutputs r;
  r.gdn.resize(n);
  if (with_cnn) r.cnn.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < 12; ++j)
      if (!(in >> r.gdn[i][j])) return false;
    if (with_cnn)
      for (std::size_t j = 0; j < 6; ++j)
        if (!(in >> r.cnn[i][j])) return false;
  }
  out = std::move(r);
  return true;
}

void writeCache(const std::string& path, const std::string& key, const RawOutputs& r) {
  const std::string tmp = cli::temporaryBeside(path);
  std::ofstream out(tmp);
  if (!out) return;  // a cache is optional
  out << kCacheMagic << "\n" << key << "\n" << std::setprecision(9);
  for (std::size_t i = 0; i < r.gdn.size(); ++i) {
    for (std::size_t j = 0; j < 12; ++j) out << r.gdn[i][j] << ' ';
    if (!r.cnn.empty())
      for (std::size_t j = 0; j < 6; ++j) out << r.cnn[i][j] << ' ';
    out << '\n';
  }
  (void)cli::finishTemporary(out, tmp, path);  // optional: a failed write leaves the old cache, the next run recomputes
}

namespace {

std::vector<std::array<double, 12>> runNetwork(ad::OnnxPoseModel& model, const std::vector<cv::Mat>& images,
                                               int batch) {
  std::vector<std::array<double, 12>> out;
  out.reserve(images.size());
  for (std::size_t start = 0; start < images.size(); start += static_cast<std::size_t>(batch)) {
    const std::size_t end = std::min(images.size(), start + static_cast<std::size_t>(batch));
    std::vector<cv::Mat> b(images.begin() + static_cast<std::ptrdiff_t>(start),
                           images.begin() + static_cast<std::ptrdiff_t>(end));
    std::vector<ad::Prediction> r;
    if (model.predictBatch(b, r) != Status::ok)
      throw std::runtime_error("inference on images " + std::to_string(start) + ".." + std::to_string(end - 1) +
                               ": " + model.lastError());
    for (const auto& p : r) out.push_back(p.raw);
  }
  return out;
}

}  // namespace

RawOutputs networkOutputs(const ReplayOptions& opt, const Networks& nets, const std::vector<Sample>& samples,
                          ReplayResults& res, const Log& log) {
  const std::size_t n = samples.size();
  const std::string split_dir = opt.data_dir + "/" + opt.split;
  const std::string image_dir = split_dir + "/processed_images";
  RawOutputs raw;
  const auto t1 = Clock::now();
  if (!opt.cache_file.empty()) {
    requireOwnCache(opt.cache_file);
    const std::string key = cacheKey(nets.gdn.onnx_file, nets.with_cnn ? nets.cnn.onnx_file : "", samples, image_dir);
    if (readCache(opt.cache_file, key, n, nets.with_cnn, raw)) {
      res.inference_cached = true;
      log("network outputs read from cache " + opt.cache_file);
      return raw;
    }
  }
  const ad::Preprocessor pre(ad::PreprocessParams::fromJsonFile(split_dir + "/processed_image_params.json"));
  // Decoding the PNGs is most of the load: spread over OpenCV's threads, a Preprocessor per
  // range (its error text is its only state); the first failing image in order is reported.
  std::vector<cv::Mat> images(n);
  std::vector<std::string> errors(n);
  cv::parallel_for_(cv::Range(0, int(n)), [&](const cv::Range& r) {
    const ad::Preprocessor local = pre;
    for (int i = r.start; i < r.end; ++i)
      if (local.loadProcessed(image_dir + "/" + samples[std::size_t(i)].image, images[std::size_t(i)]) != Status::ok)
        errors[std::size_t(i)] = local.lastError();
  });
  for (const std::string& e : errors)
    if (!e.empty()) throw std::runtime_error(e);
  res.seconds_load = std::chrono::duration<double>(Clock::now() - t1).count();
  log("loaded " + std::to_string(n) + " images in " + std::to_string(res.seconds_load) + " s");
  ad::OnnxPoseModel gdn(nets.gdn.onnx_file, nets.gdn);
  raw.gdn = runNetwork(gdn, images, std::max(1, opt.batch));
  if (nets.with_cnn) {
    ad::OnnxPoseModel cnn(nets.cnn.onnx_file, nets.cnn);
    raw.cnn = runNetwork(cnn, images, std::max(1, opt.batch));
  }
  if (!opt.cache_file.empty())
    writeCache(opt.cache_file, cacheKey(nets.gdn.onnx_file, nets.with_cnn ? nets.cnn.onnx_file : "", samples, image_dir),
               raw);
  return raw;
}

}  // namespace lieservo::replay

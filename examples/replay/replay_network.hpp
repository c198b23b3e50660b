// examples/replay/replay_network.hpp — the networks' raw outputs on the replayed images: by
// inference (OpenCV dnn), or from the replay's cache (--cache FILE), keyed by the SHA-256 of
// the ONNX files and the image list, so that a re-run with the same models and images skips
// the inference.
#pragma once

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "lieservo_adapters/onnx_pose_model.hpp"
#include "replay.hpp"

namespace lieservo::replay {

/// Raw network outputs for every sample (GDN: 12, CNN: 6 or empty).
struct RawOutputs {
  std::vector<std::array<double, 12>> gdn;
  std::vector<std::array<double, 12>> cnn;
};

/// The networks' cards: the GDN's, and the CNN's when `with_cnn`.
struct Networks {
  adapters::ModelCard gdn, cnn;
  bool with_cnn = false;
};
/// The networks' raw outputs on every image of `samples`: from opt.cache_file when it holds
/// this key (requireOwnCache first), else by inference, then cached; the load time into `res`.
RawOutputs networkOutputs(const ReplayOptions& opt, const Networks& nets, const std::vector<Sample>& samples,
                          ReplayResults& res, const std::function<void(const std::string&)>& log);

/// The cache's key: the networks' SHA-256 (`cnn_onnx` "" without the CNN), the number of
/// samples, the first and last image and the image folder. Throws when an ONNX file cannot be read.
std::string cacheKey(const std::string& gdn_onnx, const std::string& cnn_onnx, const std::vector<Sample>& samples,
                     const std::string& image_dir);

/// A cache file may be overwritten only when it is one: absent, or starting with the cache's
/// magic line. Throws std::runtime_error naming the file otherwise, before anything is written.
void requireOwnCache(const std::string& path);

/// Reads the cache when it is there and has this key and n samples; false otherwise (`out` unchanged).
bool readCache(const std::string& path, const std::string& key, std::size_t n, bool with_cnn, RawOutputs& out);

/// Writes the cache under a temporary name and renames it over `path`, so that a killed run
/// leaves the old cache or the new one, never half of one. A cache is optional: a failure is silent.
void writeCache(const std::string& path, const std::string& key, const RawOutputs& r);

}  // namespace lieservo::replay

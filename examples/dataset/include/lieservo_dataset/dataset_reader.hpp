// lieservo_dataset/dataset_reader.hpp — reads a pose-and-shear data set split
// (targets.csv + parameter JSON files + processed_images/), the shared TacTip data's format
// and the format lieservo_collect writes. Header-only, no OpenCV; used by
// examples/collection and the collection and sampling tests.
//
// targets.csv columns (mm, degrees, extrinsic-xyz Euler angles):
//   sensor_image,pose_x,pose_y,pose_z,pose_Rx,pose_Ry,pose_Rz,shear_x,shear_y,shear_z,
//   shear_Rx,shear_Ry,shear_Rz
// pose_* is X_perp (only z, Rx, Ry non-zero), shear_* is X_par (only x, y, Rz non-zero);
// the surface contact pose is X_fs = X_par·X_perp = Euler6(shear_x, shear_y, pose_z,
// pose_Rx, pose_Ry, shear_Rz) (see examples/collection/contact_sampling.hpp).
//
// Errors throw DatasetError naming "<file>:<line>:<column>".
#pragma once

#include "lieservo_dataset/json.hpp"

#include <Eigen/Core>
#include <lieservo/groups/se3.hpp>

#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace lieservo::dataset {

inline constexpr std::array<const char*, 13> kTargetColumns = {
    "sensor_image", "pose_x",  "pose_y",  "pose_z",   "pose_Rx",  "pose_Ry", "pose_Rz",
    "shear_x",      "shear_y", "shear_z", "shear_Rx", "shear_Ry", "shear_Rz"};

/// The label ξ = log(X_fs⁻¹)^∨ (mm, rad) of a contact pose X_fs given as extrinsic-xyz Euler
/// (x, y, z, α, β, γ) in mm and degrees: what the GDN learns to predict (paper
/// Section 3.1.3 (sec:pre_post_processing), label steps 1-3).
inline Eigen::Matrix<double, 6, 1> labelFromEuler6Degrees(const Eigen::Matrix<double, 6, 1>& e) {
  return SE3<double>::fromEulerXYZ6Degrees(e).inverse().log();
}

struct TargetRow {
  std::string sensor_image;     ///< e.g. "image_7.png" (relative to processed_images/)
  std::array<double, 6> pose{};   ///< pose_x, pose_y, pose_z [mm], pose_Rx, pose_Ry, pose_Rz [deg]
  std::array<double, 6> shear{};  ///< shear_x, shear_y, shear_z [mm], shear_Rx, shear_Ry, shear_Rz [deg]
  int line = 0;                 ///< 1-based line in targets.csv

  /// The surface contact pose (x, y, z, α, β, γ) in mm and degrees:
  /// (shear_x, shear_y, pose_z, pose_Rx, pose_Ry, shear_Rz).
  Eigen::Matrix<double, 6, 1> euler6Degrees() const {
    Eigen::Matrix<double, 6, 1> e;
    e << shear[0], shear[1], pose[2], pose[3], pose[4], shear[5];
    return e;
  }
  /// This row's label ξ = log(X_fs⁻¹)^∨ (mm, rad); see labelFromEuler6Degrees.
  Eigen::Matrix<double, 6, 1> label() const { return labelFromEuler6Degrees(euler6Degrees()); }
  Eigen::Matrix<double, 6, 1> poseEuler6Degrees() const {
    return Eigen::Map<const Eigen::Matrix<double, 6, 1>>(pose.data());
  }
  Eigen::Matrix<double, 6, 1> shearEuler6Degrees() const {
    return Eigen::Map<const Eigen::Matrix<double, 6, 1>>(shear.data());
  }
  /// pose_x, pose_y, pose_Rz, shear_z, shear_Rx, shear_Ry are all exactly 0.
  bool componentsSeparated() const {
    return pose[0] == 0 && pose[1] == 0 && pose[5] == 0 && shear[2] == 0 && shear[3] == 0 &&
           shear[4] == 0;
  }
};

namespace detail {

inline std::string_view trimField(std::string_view f) {
  while (!f.empty() && (f.front() == ' ' || f.front() == '\t')) f.remove_prefix(1);
  while (!f.empty() && (f.back() == ' ' || f.back() == '\t' || f.back() == '\r')) f.remove_suffix(1);
  return f;
}

/// Splits one CSV line (no quoting: the format has none) into fields with 1-based start columns.
inline void splitCsvLine(std::string_view line, std::vector<std::string_view>& fields,
                         std::vector<int>& columns) {
  fields.clear();
  columns.clear();
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = line.find(',', start);
    const std::size_t end = comma == std::string_view::npos ? line.size() : comma;
    fields.push_back(line.substr(start, end - start));
    columns.push_back(static_cast<int>(start) + 1);
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
}

/// Python/pandas number text: decimal, exponent, inf/-inf/nan also accepted.
inline bool parseDouble(std::string_view f, double& out) {
  if (f.empty()) return false;
  std::string_view g = f;
  bool neg = false;
  if (g.front() == '+' || g.front() == '-') {
    neg = g.front() == '-';
    g.remove_prefix(1);
  }
  if (g == "inf" || g == "Infinity" || g == "INF") {
    out = neg ? -std::numeric_limits<double>::infinity() : std::numeric_limits<double>::infinity();
    return true;
  }
  if (g == "nan" || g == "NaN" || g == "NAN") {
    out = std::numeric_limits<double>::quiet_NaN();
    return true;
  }
  if (g.empty() || g.front() == '+' || g.front() == '-') return false;
  double x = 0;
  const auto r = std::from_chars(g.data(), g.data() + g.size(), x);
  if (r.ec != std::errc() || r.ptr != g.data() + g.size()) return false;
  out = neg ? -x : x;
  return true;
}

}  // namespace detail

struct TargetsReadOptions {
  std::size_t max_rows = std::numeric_limits<std::size_t>::max();  ///< stop after this many rows
  bool require_finite = true;   ///< reject inf/nan labels
};

/// Reads targets.csv. The header must list kTargetColumns in order (spaces and a trailing
/// '\r' tolerated). Blank lines are skipped. Throws DatasetError "<path>:<line>:<col>: ...".
inline std::vector<TargetRow> parseTargetsCsv(std::string_view text, const std::string& path,
                                              const TargetsReadOptions& opt = {}) {
  std::vector<TargetRow> rows;
  std::vector<std::string_view> fields;
  std::vector<int> cols;
  auto fail = [&](int line, int col, const std::string& what) -> void {
    throw DatasetError(path + ":" + std::to_string(line) + ":" + std::to_string(col) +
                       ": error: " + what);
  };
  std::size_t pos = 0;
  int line_no = 0;
  bool header_seen = false;
  while (pos < text.size() && rows.size() < opt.max_rows) {
    std::size_t nl = text.find('\n', pos);
    if (nl == std::string_view::npos) nl = text.size();
    std::string_view line = text.substr(pos, nl - pos);
    pos = nl + 1;
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line_no == 1 && line.substr(0, 3) == "\xEF\xBB\xBF") line.remove_prefix(3);
    if (detail::trimField(line).empty()) {
      if (!header_seen) fail(line_no, 1, "empty line where the header was expected");
      continue;
    }
    detail::splitCsvLine(line, fields, cols);
    if (!header_seen) {
      if (fields.size() != kTargetColumns.size()) {
        fail(line_no, 1, "header has " + std::to_string(fields.size()) + " columns, expected " +
                             std::to_string(kTargetColumns.size()) + " (sensor_image,pose_x,...,shear_Rz)");
      }
      for (std::size_t i = 0; i < fields.size(); ++i) {
        if (detail::trimField(fields[i]) != kTargetColumns[i]) {
          fail(line_no, cols[i], "header column " + std::to_string(i + 1) + " is '" +
                                     std::string(detail::trimField(fields[i])) + "', expected '" +
                                     kTargetColumns[i] + "'");
        }
      }
      header_seen = true;
      continue;
    }
    if (fields.size() != kTargetColumns.size()) {
      fail(line_no, 1, "row has " + std::to_string(fields.size()) + " fields, expected " +
                           std::to_string(kTargetColumns.size()));
    }
    TargetRow r;
    r.line = line_no;
    r.sensor_image = std::string(detail::trimField(fields[0]));
    if (r.sensor_image.empty()) fail(line_no, cols[0], "empty sensor_image");
    for (std::size_t i = 1; i < fields.size(); ++i) {
      const std::string_view f = detail::trimField(fields[i]);
      double x = 0;
      if (!detail::parseDouble(f, x)) {
        fail(line_no, cols[i], std::string("column '") + kTargetColumns[i] + "': expected a number, got '" +
                                   std::string(f) + "'");
      }
      if (opt.require_finite && !std::isfinite(x)) {
        fail(line_no, cols[i], std::string("column '") + kTargetColumns[i] + "': non-finite value '" +
                                   std::string(f) + "'");
      }
      (i <= 6 ? r.pose[i - 1] : r.shear[i - 7]) = x;
    }
    rows.push_back(std::move(r));
  }
  if (!header_seen) fail(1, 1, "missing header (empty file)");
  return rows;
}

inline std::vector<TargetRow> readTargetsCsv(const std::string& path, const TargetsReadOptions& opt = {}) {
  return parseTargetsCsv(readTextFile(path), path, opt);
}

/// Width and height from a PNG's IHDR chunk (no decoding). False when not a PNG.
inline bool readPngSize(const std::string& path, int& width, int& height) {
  std::ifstream f(path, std::ios::binary);
  unsigned char b[24];
  if (!f.read(reinterpret_cast<char*>(b), sizeof b)) return false;
  static const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  for (int i = 0; i < 8; ++i) {
    if (b[i] != sig[i]) return false;
  }
  if (b[12] != 'I' || b[13] != 'H' || b[14] != 'D' || b[15] != 'R') return false;
  auto be32 = [&](int o) {
    return static_cast<std::uint32_t>(b[o]) << 24 | static_cast<std::uint32_t>(b[o + 1]) << 16 |
           static_cast<std::uint32_t>(b[o + 2]) << 8 | static_cast<std::uint32_t>(b[o + 3]);
  };
  width = static_cast<int>(be32(16));
  height = static_cast<int>(be32(20));
  return true;
}

/// The sampling ranges of collect_params.json (the shared format): pose_llims/pose_ulims,
/// shear_llims/shear_ulims (6-vectors, mm and degrees), sample_disk, sort.
struct CollectParams {
  std::array<double, 6> pose_llims{}, pose_ulims{}, shear_llims{}, shear_ulims{};
  bool sample_disk = true;
  bool sort = false;
  std::optional<double> phi_max_deg;          ///< lieservo_collect also writes these
  std::optional<unsigned long long> seed;
  std::optional<std::size_t> n_samples;

  static CollectParams fromJson(const JsonDocument& d) {
    CollectParams p;
    auto six = [&](const char* key, std::array<double, 6>& out) {
      const auto v = d.numbers(key, 6);
      for (int i = 0; i < 6; ++i) out[static_cast<std::size_t>(i)] = v[static_cast<std::size_t>(i)];
    };
    six("pose_llims", p.pose_llims);
    six("pose_ulims", p.pose_ulims);
    six("shear_llims", p.shear_llims);
    six("shear_ulims", p.shear_ulims);
    if (d.has("sample_disk")) p.sample_disk = d.boolean("sample_disk");
    if (d.has("sort")) p.sort = d.boolean("sort");
    if (d.has("phi_max")) p.phi_max_deg = d.number("phi_max");
    if (d.has("seed")) {
      const double s = d.number("seed");
      if (!(s >= 0) || s != std::floor(s) || s > 9007199254740992.0) d.fail("seed", "must be a non-negative integer");
      p.seed = static_cast<unsigned long long>(s);
    }
    if (d.has("n_samples")) {
      const double n = d.number("n_samples");
      if (!(n >= 0) || n != std::floor(n) || n > 1e12) d.fail("n_samples", "must be a non-negative integer");
      p.n_samples = static_cast<std::size_t>(n);
    }
    return p;
  }
};

/// One split directory (train/, val/, or a lieservo_collect output directory).
struct DatasetSplit {
  std::string dir;
  std::vector<TargetRow> targets;
  std::optional<JsonDocument> collect_params, processed_image_params, env_params, meta;
  std::vector<std::string> warnings;   ///< repaired JSON quirks, with file:line:col

  std::string imagePath(const TargetRow& r) const { return dir + "/processed_images/" + r.sensor_image; }
};

struct DatasetReadOptions {
  TargetsReadOptions targets;
  /// Accept the shared data's quirks: Infinity/NaN literals and a stray closing bracket
  /// (warning). False: strict JSON (non-finite literals still accepted if allow_non_finite).
  bool tolerate_quirks = true;
  bool require_params = false;   ///< missing collect/processed_image/env params → error
};

inline bool fileExists(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return static_cast<bool>(f);
}

/// Reads dir/targets.csv and the JSON files present (collect_params, processed_image_params,
/// env_params, meta). Throws DatasetError naming the file (and line:column).
inline DatasetSplit readDatasetSplit(const std::string& dir, const DatasetReadOptions& opt = {}) {
  DatasetSplit s;
  s.dir = dir;
  s.targets = readTargetsCsv(dir + "/targets.csv", opt.targets);
  JsonParseOptions jo;
  jo.allow_non_finite = true;
  jo.repair_stray_closers = opt.tolerate_quirks;
  auto load = [&](const char* file, std::optional<JsonDocument>& out, bool required) {
    const std::string path = dir + "/" + file;
    if (!fileExists(path)) {
      if (required) throw DatasetError(path + ": error: missing parameter file");
      return;
    }
    out = readJsonFile(path, jo);
    for (const auto& w : out->warnings) s.warnings.push_back(w);
  };
  load("collect_params.json", s.collect_params, opt.require_params);
  load("processed_image_params.json", s.processed_image_params, opt.require_params);
  load("env_params.json", s.env_params, opt.require_params);
  load("meta.json", s.meta, false);
  return s;
}

}  // namespace lieservo::dataset

// examples/collection/collector.hpp — training-data collection (paper Algorithm 1 (alg:data_collection)),
// resumable after an interruption.
//
// For sample i = 1..N of a seeded plan (examples/collection/contact_sampling.hpp), with
// X_wf the surface feature frame {f} in the robot's work frame and h the start height:
//   1. moveTo X_wf·T(0, 0, −h)                          start point above the surface
//   2. moveTo X_wf·Euler6(0, 0, −h, α, β, 0)            rotate to the contact angle (α, β)
//   3. moveTo X_wf·Euler6(0, 0, z, α, β, 0) = X_wf·X_perp   move along the normal to depth z
//   4. moveTo X_wf·X_par·X_perp = X_wf·Euler6(x, y, z, α, β, γ)   shear by (x, y, γ)
//   5. capture the pre-processed image, write processed_images/image_i.png (atomically),
//      then append the targets.csv row (flushed)
//   6. moveTo X_wf·Euler6(x, y, −h, α, β, γ)            lift off along the normal
// Output directory (same format as the shared TacTip data): targets.csv, processed_images/,
// collect_params.json, processed_image_params.json, env_params.json, meta.json (valid JSON).
//
// Resumability: the plan is a pure function of (seed, N, ranges, sort). On start, an existing
// directory is checked: its parameter files must equal what this configuration writes; a torn
// last CSV line (crash mid-append) is cut off; every remaining row must be exactly the row
// this plan gives for its index and its image must exist. Collection continues at the next
// index. An image without a row (crash between rename and append) is rewritten. Hence rows are
// never lost (flushed + fsynced after their image) nor duplicated (index i is written once).
#pragma once

#include <lieservo_dataset/dataset_reader.hpp>
#include "image_io.hpp"
#include "image_source.hpp"
#include <lieservo_dataset/json.hpp>
#include <lieservo_dataset/json_writer.hpp>

#include <robot/robot_interface.hpp>

#include <lieservo/groups/se3.hpp>
#include "contact_sampling.hpp"
#include <lieservo/sampling/random.hpp>
#include <lieservo/status.hpp>

#include <charconv>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

#if defined(__unix__) || defined(__APPLE__)
#include <unistd.h>
#endif

namespace lieservo::collection {

// The JSON and data set readers are the shared ones of examples/dataset.
using namespace lieservo::dataset;

using SE3d = SE3<double>;
using ContactPose = sampling::SurfaceContactPose<double>;

struct CollectionConfig {
  std::string out_dir;
  std::size_t n_samples = 20;
  std::uint64_t seed = 1;
  sampling::ContactSamplingRanges<double> ranges{};   ///< mm, degrees (paper defaults)
  bool sort_by_depth = false;      ///< order the plan by depth z (the shared data's row order)
  double start_height_mm = 10;     ///< h: start point above the surface (meta.json work_start_pose z = −10)
  Eigen::Matrix<double, 6, 1> work_frame = Eigen::Matrix<double, 6, 1>::Zero();  ///< X_wf, mm + degrees (sxyz)
  Eigen::Matrix<double, 6, 1> tcp_pose = Eigen::Matrix<double, 6, 1>::Zero();    ///< for env_params.json only
  std::string robot_name = "kinematic_standin";
  std::string stim_name = "flat";
  std::size_t stop_after = std::numeric_limits<std::size_t>::max();  ///< new samples in this run
  bool progress = true;
  std::ostream* log = &std::cerr;
  const volatile std::sig_atomic_t* stop_requested = nullptr;  ///< e.g. set by SIGINT: finish the sample, stop
  /// Test hook: terminate the process (exit code 75) while writing sample `crash_at` (1-based):
  /// crash_point 0 = after its image, before its row; 1 = after half of its row.
  std::size_t crash_at = 0;
  int crash_point = 0;
};

struct CollectionResult {
  std::size_t rows_before = 0;   ///< complete rows found on start
  std::size_t written = 0;       ///< samples written in this run
  std::size_t rows_after = 0;
  bool complete = false;         ///< rows_after == n_samples
  std::vector<std::string> notes;  ///< repairs made on resume (torn row cut, orphan image)
};

/// The sampling plan: n poses from lieservo::sampling::Rng(seed). Throws on invalid ranges.
inline std::vector<ContactPose> collectionPlan(const CollectionConfig& c) {
  lieservo::sampling::Rng rng(c.seed);
  std::vector<ContactPose> plan;
  const Status st = sampling::sampleSurfaceContactPoses(rng, c.n_samples, c.ranges, plan, c.sort_by_depth);
  if (st != Status::ok) throw DatasetError(std::string("invalid sampling ranges: ") + describe(st));
  return plan;
}

inline std::string imageName(std::size_t index) { return "image_" + std::to_string(index) + ".png"; }

inline std::string targetsHeader() {
  std::string h;
  for (std::size_t i = 0; i < kTargetColumns.size(); ++i) h += (i ? "," : "") + std::string(kTargetColumns[i]);
  return h;
}

/// Shortest decimal that reads back to the same double (std::to_chars); −0 as 0.
inline std::string shortestDecimal(double x) {
  if (x == 0) return "0";
  char buf[32];
  return std::string(buf, std::to_chars(buf, buf + sizeof buf, x).ptr);
}

/// One targets.csv row (no newline): mm and degrees, shortest round-trip decimals.
/// pose_* = X_perp = (0, 0, z, α, β, 0), shear_* = X_par = (x, y, 0, 0, 0, γ).
inline std::string targetsRow(std::size_t index, const ContactPose& p) {
  const auto e = p.euler6Degrees();  // x, y, z, α, β, γ
  const double v[12] = {0, 0, e(2), e(3), e(4), 0, e(0), e(1), 0, 0, 0, e(5)};
  std::string row = imageName(index);
  for (double x : v) row += "," + shortestDecimal(x);
  return row;
}

inline std::string collectParamsJson(const CollectionConfig& c) {
  const auto& r = c.ranges;
  return JsonObjectWriter()
      .field("pose_llims", std::vector<double>{0, 0, r.z_min_mm, -r.phi_max_deg, -r.phi_max_deg, 0})
      .field("pose_ulims", std::vector<double>{0, 0, r.z_max_mm, r.phi_max_deg, r.phi_max_deg, 0})
      .field("shear_llims", std::vector<double>{-r.r_max_mm, -r.r_max_mm, 0, 0, 0, r.gamma_min_deg})
      .field("shear_ulims", std::vector<double>{r.r_max_mm, r.r_max_mm, 0, 0, 0, r.gamma_max_deg})
      .field("sample_disk", true)
      .field("sort", c.sort_by_depth)
      .field("phi_max", r.phi_max_deg)
      .field("seed", static_cast<unsigned long long>(c.seed))
      .field("n_samples", static_cast<unsigned long long>(c.n_samples))
      .field("generator", "std::mt19937_64")
      .field("sampler", "lieservo::sampling::sampleSurfaceContactPose (r', theta, z, phi', theta, gamma)")
      .str() + "\n";
}

inline std::vector<double> toStdVector(const Eigen::Matrix<double, 6, 1>& v) {
  return std::vector<double>(v.data(), v.data() + 6);
}

inline std::string envParamsJson(const CollectionConfig& c) {
  return JsonObjectWriter()
      .field("robot", c.robot_name)
      .field("stim_name", c.stim_name)
      .field("work_frame", toStdVector(c.work_frame))
      .field("tcp_pose", toStdVector(c.tcp_pose))
      .str() + "\n";
}

/// meta.json like the shared one, but valid JSON: the original's Infinity-valued
/// z_shear_rng / phi_shear_rng (unused) are left out.
inline std::string metaJson(const CollectionConfig& c) {
  const auto& r = c.ranges;
  return JsonObjectWriter()
      .field("z_rng", std::vector<double>{r.z_min_mm, r.z_max_mm})
      .field("phi_max", r.phi_max_deg)
      .field("d_r_max", r.r_max_mm)
      .field("d_gamma_max", r.gamma_max_deg)
      .field("n_samples", static_cast<unsigned long long>(c.n_samples))
      .field("robot_axes", "sxyz")
      .field("work_start_pose", std::vector<double>{0, 0, -c.start_height_mm, 0, 0, 0})
      .field("work_frame", toStdVector(c.work_frame))
      .field("robot_tcp", toStdVector(c.tcp_pose))
      .str() + "\n";
}

/// Steps 1–4 of Algorithm 1 (alg:data_collection): end at X_wf·X_par·X_perp.
inline Status moveToContactPose(robot::RobotInterface& arm, const SE3d& X_wf, const ContactPose& p, double h) {
  using V6 = Eigen::Matrix<double, 6, 1>;
  V6 e;
  e << 0, 0, -h, 0, 0, 0;
  Status st = arm.moveTo(X_wf * SE3d::fromEulerXYZ6(e));                         // 1. above the start point
  if (st != Status::ok) return st;
  e << 0, 0, -h, p.alpha, p.beta, 0;
  if ((st = arm.moveTo(X_wf * SE3d::fromEulerXYZ6(e))) != Status::ok) return st;  // 2. contact angle
  const SE3d X_perp = sampling::normalContactTransform(p.z, p.alpha, p.beta);
  if ((st = arm.moveTo(X_wf * X_perp)) != Status::ok) return st;                 // 3. normal contact, depth z
  const SE3d X_par = sampling::shearTransform(p.x, p.y, p.gamma);
  return arm.moveTo(X_wf * X_par * X_perp);                                       // 4. shear (x, y, γ)
}

/// Step 6: lift off along the normal to the start height, keeping the orientation.
inline Status liftOff(robot::RobotInterface& arm, const SE3d& X_wf, const ContactPose& p, double h) {
  Eigen::Matrix<double, 6, 1> e;
  e << p.x, p.y, -h, p.alpha, p.beta, p.gamma;
  return arm.moveTo(X_wf * SE3d::fromEulerXYZ6(e));
}

namespace detail {

inline std::string hms(double s) {
  if (!(s >= 0) || !std::isfinite(s)) return "--:--:--";
  const long t = static_cast<long>(s + 0.5);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%02ld:%02ld:%02ld", t / 3600, (t / 60) % 60, t % 60);
  return buf;
}

inline void appendAndSync(const std::string& path, const std::string& text, std::size_t crash_after_bytes) {
  std::FILE* f = std::fopen(path.c_str(), "ab");
  if (f == nullptr) throw DatasetError(path + ": error: cannot open for appending");
  const std::size_t n = crash_after_bytes < text.size() ? crash_after_bytes : text.size();
  bool ok = std::fwrite(text.data(), 1, n, f) == n && std::fflush(f) == 0;
#if defined(__unix__) || defined(__APPLE__)
  ok = ok && ::fsync(::fileno(f)) == 0;
#endif
  if (n < text.size()) std::_Exit(75);  // test hook: a torn row
  if (std::fclose(f) != 0 || !ok) throw DatasetError(path + ": error: append failed");
}

/// Existing parameter file must equal `text`; a missing one is written.
inline void ensureParamFile(const std::string& path, const std::string& text) {
  if (fileExists(path)) {
    const std::string have = readTextFile(path);
    if (have != text) {
      throw DatasetError(path + ": error: exists with different content — this directory was "
                                "collected with other parameters; resume with the same options or "
                                "use a new --out directory.\n  existing: " + have + "  this run: " + text);
    }
    return;
  }
  writeFileAtomic(path, text);
}

/// Resume: the rows already in `csv` must be this plan's first rows, each with its image; a
/// torn last line (an interrupted append) is cut. Counts them in res.rows_before and notes the
/// repairs in res.notes. Throws DatasetError naming the file and line otherwise.
inline void validateExisting(const CollectionConfig& c, const std::vector<ContactPose>& plan, const std::string& csv,
                             const std::string& img_dir, CollectionResult& res) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const std::string header = targetsHeader();
  if (!fileExists(csv)) {
    writeFileAtomic(csv, header + "\n");
  } else {
    std::string text = readTextFile(csv);
    if (!text.empty() && text.back() != '\n') {
      const std::size_t keep = text.rfind('\n') == std::string::npos ? 0 : text.rfind('\n') + 1;
      res.notes.push_back(csv + ": cut a torn last line (" + std::to_string(text.size() - keep) + " bytes) left by an interruption");
      if (keep == 0) {
        writeFileAtomic(csv, header + "\n");
        text = header + "\n";
      } else {
        fs::resize_file(csv, keep, ec);
        if (ec) throw DatasetError(csv + ": error: cannot truncate torn line: " + ec.message());
        text.resize(keep);
      }
    }
    std::size_t pos = 0;
    int line_no = 0;
    while (pos < text.size()) {
      const std::size_t nl = text.find('\n', pos);
      std::string line = text.substr(pos, nl - pos);
      pos = nl + 1;
      ++line_no;
      if (!line.empty() && line.back() == '\r') line.pop_back();
      if (line_no == 1) {
        if (line != header) throw DatasetError(csv + ":1:1: error: unexpected header '" + line + "'");
        continue;
      }
      const std::size_t index = res.rows_before + 1;
      if (index > plan.size()) {
        throw DatasetError(csv + ":" + std::to_string(line_no) + ":1: error: more rows than n_samples = " + std::to_string(plan.size()));
      }
      const std::string expected = targetsRow(index, plan[index - 1]);
      if (line != expected) {
        throw DatasetError(csv + ":" + std::to_string(line_no) + ":1: error: row is not sample " + std::to_string(index) +
                           " of this plan (seed " + std::to_string(c.seed) + ")\n  found:    " + line + "\n  expected: " + expected);
      }
      const std::string img = img_dir + "/" + imageName(index);
      int w = 0, h = 0;
      if (!readPngSize(img, w, h)) {
        throw DatasetError(csv + ":" + std::to_string(line_no) + ":1: error: row " + std::to_string(index) + " has no valid image " + img +
                           " (deleted after it was written?)");
      }
      ++res.rows_before;
    }
    if (res.rows_before < plan.size() && fileExists(img_dir + "/" + imageName(res.rows_before + 1))) {
      res.notes.push_back(imageName(res.rows_before + 1) + ": image without a row (interrupted before its row was appended); re-collecting it");
    }
  }
}

}  // namespace detail

/// Runs (or resumes) a collection. Throws DatasetError on any file problem or robot/camera
/// failure (the arm is stopped first).
inline CollectionResult runCollection(const CollectionConfig& c, robot::RobotInterface& arm, ImageSource& camera) {
  namespace fs = std::filesystem;
  CollectionResult res;
  if (c.out_dir.empty()) throw DatasetError("no output directory given");
  if (!(c.start_height_mm >= 0) || !std::isfinite(c.start_height_mm)) throw DatasetError("start height must be finite and >= 0");
  const std::vector<ContactPose> plan = collectionPlan(c);
  const SE3d X_wf = SE3d::fromEulerXYZ6Degrees(c.work_frame);
  const std::string dir = c.out_dir, img_dir = dir + "/processed_images", csv = dir + "/targets.csv";
  std::error_code ec;
  fs::create_directories(img_dir, ec);
  if (ec) throw DatasetError(img_dir + ": error: cannot create directory: " + ec.message());

  detail::ensureParamFile(dir + "/collect_params.json", collectParamsJson(c));
  detail::ensureParamFile(dir + "/processed_image_params.json", camera.paramsJson() + "\n");
  detail::ensureParamFile(dir + "/env_params.json", envParamsJson(c));
  detail::ensureParamFile(dir + "/meta.json", metaJson(c));

  detail::validateExisting(c, plan, csv, img_dir, res);
  for (const auto& entry : fs::directory_iterator(img_dir, ec)) {  // stale partial writes
    if (entry.path().extension() == ".tmp") fs::remove(entry.path(), ec);
  }
  if (c.log != nullptr) {
    for (const auto& n : res.notes) *c.log << "[lieservo_collect] note: " << n << "\n";
    if (res.rows_before > 0) *c.log << "[lieservo_collect] resuming at sample " << res.rows_before + 1 << " of " << plan.size() << "\n";
  }

  // ---- collect --------------------------------------------------------------------------
  const auto t0 = std::chrono::steady_clock::now();
  auto last_report = t0 - std::chrono::seconds(10);
  std::size_t index = res.rows_before;
  GrayImage image;
  while (index < plan.size() && res.written < c.stop_after) {
    if (c.stop_requested != nullptr && *c.stop_requested != 0) break;
    const std::size_t i = index + 1;
    const ContactPose& p = plan[index];
    Status st = moveToContactPose(arm, X_wf, p, c.start_height_mm);
    if (st == Status::ok) st = camera.capture(image);
    if (st != Status::ok) {
      arm.stop();
      throw DatasetError("sample " + std::to_string(i) + ": robot or camera failed: " + describe(st));
    }
    writePngAtomic(img_dir + "/" + imageName(i), image);
    if (c.crash_at == i && c.crash_point == 0) std::_Exit(75);  // test hook
    const std::string row = targetsRow(i, p) + "\n";
    detail::appendAndSync(csv, row, (c.crash_at == i && c.crash_point == 1) ? row.size() / 2 : row.size());
    ++res.written;
    index = i;
    if ((st = liftOff(arm, X_wf, p, c.start_height_mm)) != Status::ok) {
      arm.stop();
      throw DatasetError("sample " + std::to_string(i) + ": lift-off failed: " + describe(st));
    }
    const auto now = std::chrono::steady_clock::now();
    if (c.progress && c.log != nullptr &&
        (now - last_report >= std::chrono::seconds(1) || index == plan.size() || res.written == c.stop_after)) {
      last_report = now;
      const double el = std::chrono::duration<double>(now - t0).count();
      const double rate = el > 0 ? static_cast<double>(res.written) / el : 0.0;
      const double eta = rate > 0 ? static_cast<double>(plan.size() - index) / rate : -1.0;
      char buf[256];
      std::snprintf(buf, sizeof buf, "[lieservo_collect] %zu/%zu (%.1f%%) %s  elapsed %s  %.1f samples/s  ETA %s",
                    index, plan.size(), 100.0 * static_cast<double>(index) / static_cast<double>(plan.size()),
                    imageName(i).c_str(), detail::hms(el).c_str(), rate, detail::hms(eta).c_str());
      *c.log << buf << "\n" << std::flush;
    }
  }
  res.rows_after = index;
  res.complete = index == plan.size();
  return res;
}

}  // namespace lieservo::collection

#include "replay.hpp"

#include <lieservo_dataset/dataset_reader.hpp>
#include <lieservo_dataset/trained_on.hpp>
#include <lieservo/sampling/random.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <utility>

#include <opencv2/core.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>

#include "lieservo/estimation/bayes_filter.hpp"
#include "lieservo/estimation/concentrated_gaussian.hpp"
#include "lieservo/groups/se3.hpp"
#include "lieservo_adapters/gdn_observation.hpp"
#include "lieservo_adapters/onnx_pose_model.hpp"
#include "lieservo_adapters/preprocessing.hpp"
#include "plots.hpp"

namespace lieservo::replay {

namespace ad = lieservo::adapters;
using Clock = std::chrono::steady_clock;

namespace {

constexpr double kPi = lieservo::pi<double>();
constexpr double kRad2Deg = 180.0 / kPi;
constexpr double kDeg2Rad = kPi / 180.0;

double seconds(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }

Vec6 toReportUnits(const Vec6& xi) {
  Vec6 v = xi;
  for (std::size_t j = 3; j < 6; ++j) v[j] *= kRad2Deg;
  return v;
}

/// 1/σ in 1/mm, 1/deg from σ in mm, rad.
Vec6 precisionReportUnits(const Eigen::Matrix<double, 6, 1>& sigma) {
  Vec6 v{};
  for (int j = 0; j < 6; ++j) {
    const double s = j < 3 ? sigma(j) : sigma(j) * kRad2Deg;
    v[static_cast<std::size_t>(j)] = 1.0 / s;
  }
  return v;
}

std::uint64_t fnv1a(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return 0;
  std::uint64_t h = 1469598103934665603ull;
  char buf[1 << 16];
  while (in) {
    in.read(buf, sizeof buf);
    const std::streamsize got = in.gcount();
    for (std::streamsize i = 0; i < got; ++i) {
      h ^= static_cast<unsigned char>(buf[i]);
      h *= 1099511628211ull;
    }
  }
  return h;
}

std::string hex(std::uint64_t h) {
  std::ostringstream os;
  os << std::hex << std::setw(16) << std::setfill('0') << h;
  return os.str();
}

/// Raw network outputs for every sample (GDN: 12, CNN: 6 or empty).
struct RawOutputs {
  std::vector<std::array<double, 12>> gdn;
  std::vector<std::array<double, 12>> cnn;
};

std::string cacheKey(const std::string& gdn_hash, const std::string& cnn_hash, const std::vector<Sample>& samples,
                     const std::string& image_dir) {
  return "gdn " + gdn_hash + " cnn " + cnn_hash + " n " + std::to_string(samples.size()) + " first " +
         (samples.empty() ? std::string("-") : samples.front().image) + " last " +
         (samples.empty() ? std::string("-") : samples.back().image) + " images " + image_dir;
}

constexpr const char* kCacheMagic = "lieservo-replay-cache v1";

// A cache file may be overwritten only when it is one: absent, or starting with the magic line.
// Anything else (a typo naming a user's file, a folder) is refused before anything is written.
void requireOwnCache(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(path, ec)) return;
  std::string magic;
  std::ifstream in(path);
  if (fs::is_regular_file(path, ec) && in && std::getline(in, magic) && magic == kCacheMagic) return;
  throw std::runtime_error("--cache " + path + ": the file exists and is not a lieservo_replay cache (its first line is not '" +
                           kCacheMagic + "'); it is left untouched: name another file");
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

// Written to a temporary name beside the cache and renamed over it, so a killed run leaves the
// old cache or the new one, never half of one.
void writeCache(const std::string& path, const std::string& key, const RawOutputs& r) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp);
    if (!out) return;  // a cache is optional
    out << kCacheMagic << "\n" << key << "\n" << std::setprecision(9);
    for (std::size_t i = 0; i < r.gdn.size(); ++i) {
      for (std::size_t j = 0; j < 12; ++j) out << r.gdn[i][j] << ' ';
      if (!r.cnn.empty())
        for (std::size_t j = 0; j < 6; ++j) out << r.cnn[i][j] << ' ';
      out << '\n';
    }
    if (!out.flush()) {
      out.close();
      std::remove(tmp.c_str());
      return;
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) std::remove(tmp.c_str());
}

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

std::string splitRole(const std::string& card_path, const std::string& split) {
  const std::string name = "the `" + split + "` split";
  dataset::JsonDocument card;
  dataset::TrainedOn trained;
  try {
    card = dataset::readJsonFile(card_path);
    trained = dataset::trainedOn(card, card_path);
  } catch (const std::exception&) {
    return name + ": the model card cannot be read, so whether the network saw these images is unknown.";
  }
  using dataset::find;
  const dataset::JsonValue* data = find(card.root, "data");
  const dataset::JsonValue* listed = data != nullptr ? find(*data, split) : nullptr;
  std::string stopping;
  if (const dataset::JsonValue* models = find(card.root, "models"))
    if (const dataset::JsonValue* gdn = find(*models, "gdn"))
      if (const dataset::JsonValue* training = find(*gdn, "training"))
        if (const dataset::JsonValue* es = find(*training, "early_stopping"))
          if (es->IsString()) stopping = es->GetString();
  if (trained.sawAll(split))
    return name + " is what the network was trained on: these numbers do not measure generalisation.";
  if (trained.sawSplit(split))
    return name + ": the network was trained on " + std::to_string(trained.images.at(split)) + " of its images (the other " +
           std::to_string(trained.heldOutCount(split)) + " are listed in " + trained.held_out_file +
           "): these numbers mix trained-on and unseen images and do not measure generalisation.";
  if (listed == nullptr)
    return name + " is not listed in the model card's data: the network did not see it in training "
                  "(if the card is complete).";
  if (listed->IsString())
    return name + ": the model card says \"" + std::string(listed->GetString()) + "\".";
  if (!stopping.empty() && stopping.find(split) != std::string::npos)
    return name + " was used for model selection (the card's early stopping: \"" + stopping +
           "\"), so these numbers are slightly optimistic for a new session.";
  return name + " is listed in the model card's data (" + std::to_string(listed->IsNumber() ? static_cast<long>(listed->GetDouble()) : 0L) +
         " images) but not as used in training.";
}

Vec6 labelFromEulerDegrees(const Vec6& e) {
  SE3d::Vector6 v;
  for (int j = 0; j < 6; ++j) v(j) = e[static_cast<std::size_t>(j)];
  const SE3d::Tangent xi = dataset::labelFromEuler6Degrees(v);  // the data set's one definition
  Vec6 out{};
  for (int j = 0; j < 6; ++j) out[static_cast<std::size_t>(j)] = xi(j);
  return out;
}

std::vector<Sample> readTargets(const std::string& csv_path) {
  // The project's one targets.csv reader (examples/dataset); its errors name file:line:column.
  std::vector<Sample> out;
  for (const dataset::TargetRow& r : dataset::readTargetsCsv(csv_path)) {
    Sample s;
    s.image = r.sensor_image;
    const auto e = r.euler6Degrees();  // (shear_x, shear_y, pose_z, pose_Rx, pose_Ry, shear_Rz)
    for (std::size_t j = 0; j < 6; ++j) s.euler[j] = e[static_cast<Eigen::Index>(j)];
    s.xi = labelFromEulerDegrees(s.euler);
    out.push_back(std::move(s));
  }
  if (out.empty()) throw std::runtime_error(csv_path + ": no samples");
  return out;
}

Vec6 toReportUnits(const SE3d::Tangent& xi) {
  Vec6 v{};
  for (int j = 0; j < 6; ++j) v[static_cast<std::size_t>(j)] = j < 3 ? xi(j) : xi(j) * kRad2Deg;
  return v;
}

namespace {
/// σψ per tangent component: mm for ρ, degrees converted to radians for φ.
SE3d::Tangent psiSigma(double sig) {
  SE3d::Tangent sd;
  sd << sig, sig, sig, sig * kDeg2Rad, sig * kDeg2Rad, sig * kDeg2Rad;
  return sd;
}
}  // namespace

SE3d::Jacobian replayProcessNoise(double sig) { return psiSigma(sig).array().square().matrix().asDiagonal(); }

std::vector<SE3d> replayMotions(const std::vector<Sample>& samples, double sig, std::uint64_t seed) {
  const std::size_t n = samples.size();
  std::vector<SE3d> X(n), T(n);
  for (std::size_t i = 0; i < n; ++i) {
    SE3d::Tangent xi;
    for (int j = 0; j < 6; ++j) xi(j) = samples[i].xi[static_cast<std::size_t>(j)];
    X[i] = SE3d::exp(xi);
  }
  const SE3d::Tangent sd = psiSigma(sig);
  lieservo::sampling::Rng rng(seed);
  for (std::size_t k = 1; k < n; ++k) {
    SE3d::Tangent psi;
    for (int j = 0; j < 6; ++j) psi(j) = sd(j) * lieservo::sampling::standardNormal(rng);
    T[k] = SE3d::exp(psi) * X[k] * X[k - 1].inverse();
  }
  return T;
}

FilterRun replayFilter(const std::vector<Sample>& samples, const std::vector<ConcentratedGaussian<SE3d>>& obs,
                       double sig, std::uint64_t seed, const FusionOptions<double>& fusion, bool measure_fusion_error) {
  const std::size_t n = std::min(samples.size(), obs.size());
  FilterRun run;
  FilterRow& row = run.row;
  row.sigma_psi = sig;
  if (n == 0) return run;
  std::vector<Vec6> actual(n);  // the labels ξ_k (the true states X_k = exp(ξ_k^) = X_sf)
  for (std::size_t i = 0; i < n; ++i) actual[i] = toReportUnits(samples[i].xi);
  const std::vector<SE3d> T = replayMotions(samples, sig, seed);
  DiscriminativeBayesFilter<SE3d>::Options fo;
  fo.process_noise = replayProcessNoise(sig);  // Σφ = Σψ
  fo.fusion = fusion;
  DiscriminativeBayesFilter<SE3d> filter(fo);
  DiscriminativeBayesFilter<SE3d>::Options full = fo;  // the reference: the fusion run to convergence
  full.fusion.max_iterations = 50;
  full.fusion.tolerance = 1e-12;
  full.fusion.require_convergence = false;
  run.mu.resize(n);
  run.precision.resize(n);
  long iterations = 0, corrections = 0;
  for (std::size_t k = 0; k < n; ++k) {
    Status s = Status::ok;
    if (k == 0) {
      s = filter.step(SE3d(), obs[0]);  // the first step initialises
    } else {
      std::optional<DiscriminativeBayesFilter<SE3d>> reference;  // the same state, the reference fusion
      if (measure_fusion_error) {
        reference = filter;
        if (reference->configure(full) != Status::ok) throw std::logic_error("replayFilter: reference options rejected");
      }
      s = filter.predict(T[k]);
      if (s == Status::ok) s = filter.correct(obs[k]);
      if (s == Status::ok) {
        iterations += filter.diagnostics().iterations;
        ++corrections;
      }
      Status r = Status::ok;
      if (reference && s == Status::ok) {
        r = reference->predict(T[k]);
        if (r == Status::ok) r = reference->correct(obs[k]);
      }
      if (reference && s == Status::ok && r == Status::ok) {
        FusionError& worst = run.fusion_error;
        const SE3d::Tangent e = lminus(filter.filtered().mean, reference->filtered().mean);
        worst.mm = std::max(worst.mm, e.head<3>().norm());
        worst.rad = std::max(worst.rad, e.tail<3>().norm());
        const Eigen::LLT<SE3d::Jacobian> llt(reference->filtered().covariance);
        worst.sigma = std::max(worst.sigma, llt.matrixL().solve(e).norm());
      }
    }
    if (s != Status::ok) {
      ++row.failures;
      if (row.failures <= 3)
        run.notes.push_back("sigma_psi " + std::to_string(sig) + ": step " + std::to_string(k) + " (" +
                            samples[k].image + "): " + describe(s) + "; filter re-initialised");
      filter.reset();
      (void)filter.step(SE3d(), obs[k]);
    }
    const ConcentratedGaussian<SE3d>& f = filter.filtered();
    SE3d::Tangent mu;
    SE3d::Jacobian Sxi;
    if (toTangentGaussian(f, mu, Sxi) != Status::ok) {
      mu = f.mean.log();
      Sxi = f.covariance;
    }
    run.mu[k] = toReportUnits(mu);
    const Eigen::Matrix<double, 6, 1> sdev = Sxi.diagonal().cwiseMax(0.0).cwiseSqrt();
    run.precision[k] = precisionReportUnits(sdev);
    for (std::size_t j = 0; j < 6; ++j) {
      row.mae[j] += std::fabs(run.mu[k][j] - actual[k][j]);
      row.mean_sigma[j] += 1.0 / run.precision[k][j];
    }
  }
  for (std::size_t j = 0; j < 6; ++j) {
    row.mae[j] /= static_cast<double>(n);
    row.mean_sigma[j] /= static_cast<double>(n);
  }
  row.mean_iterations = corrections > 0 ? static_cast<double>(iterations) / static_cast<double>(corrections) : 0.0;
  return run;
}

void setDemoOutputs(ReplayOptions& opt, const std::string& out_dir) {
  opt.cache_file = out_dir.empty() ? std::string() : out_dir + "/replay_network_outputs.txt";
  opt.plot_dir = out_dir.empty() ? std::string() : out_dir + "/replay";
}

ReplayResults runReplay(const ReplayOptions& opt) {
  const auto t0 = Clock::now();
  const std::clock_t c0 = std::clock();
  ReplayResults res;
  auto log = [&](const std::string& m) {
    if (opt.verbose) std::cerr << "[replay] " << m << std::endl;
  };

  const std::string split_dir = opt.data_dir + "/" + opt.split;
  std::vector<Sample> samples = readTargets(split_dir + "/targets.csv");
  res.split_role = splitRole(opt.models_dir + "/model_card.json", opt.split);
  if (opt.unseen_only) {
    const std::string card = opt.models_dir + "/model_card.json";
    const dataset::TrainedOn trained = dataset::readTrainedOn(card);  // DatasetError names the file
    const std::size_t all = samples.size();
    samples.erase(std::remove_if(samples.begin(), samples.end(),
                                 [&](const Sample& s) { return trained.saw(opt.split, s.image); }),
                  samples.end());
    if (samples.empty())
      throw std::runtime_error("--unseen-only: the network of " + card + " trained on every image of " + split_dir);
    res.unseen_of = static_cast<int>(all);
    if (samples.size() < all)
      res.split_role = "these are the " + std::to_string(samples.size()) + " of the " + std::to_string(all) +
                       " images of the `" + opt.split + "` split that the network did not train on (the model card's "
                       "held-out rows), so they measure it on unseen images of a session it has seen.";
  }
  if (opt.quick > 0 && static_cast<std::size_t>(opt.quick) < samples.size())
    samples.resize(static_cast<std::size_t>(opt.quick));
  const std::size_t n = samples.size();
  res.n = static_cast<int>(n);

  const std::string card_path = opt.models_dir + "/model_card.json";
  ad::ModelCard gdn_card = ad::ModelCard::fromJsonFile(card_path, ad::ModelKind::gdn);
  if (gdn_card.onnx_file.empty()) gdn_card.onnx_file = opt.models_dir + "/gdn.onnx";
  std::string cnn_note;
  bool with_cnn = false;
  ad::ModelCard cnn_card;
  if (opt.run_cnn) {
    try {
      cnn_card = ad::ModelCard::fromJsonFile(card_path, ad::ModelKind::cnn);
      if (cnn_card.onnx_file.empty()) cnn_card.onnx_file = opt.models_dir + "/cnn.onnx";
      with_cnn = std::filesystem::exists(cnn_card.onnx_file);
      if (!with_cnn) cnn_note = "CNN skipped: " + cnn_card.onnx_file + " not found";
    } catch (const std::runtime_error& e) {
      cnn_note = std::string("CNN skipped: ") + e.what();
    }
    if (!cnn_note.empty()) {
      res.notes.push_back(cnn_note);
      log(cnn_note);
    }
  }
  if (!std::filesystem::exists(gdn_card.onnx_file))
    throw std::runtime_error(gdn_card.onnx_file + ": GDN model not found");

  // ---- network outputs (cached by model hashes) ------------------------------------
  const std::string image_dir = split_dir + "/processed_images";
  const std::string key =
      cacheKey(hex(fnv1a(gdn_card.onnx_file)), with_cnn ? hex(fnv1a(cnn_card.onnx_file)) : "none", samples, image_dir);
  RawOutputs raw;
  const auto t1 = Clock::now();
  if (!opt.cache_file.empty()) requireOwnCache(opt.cache_file);
  if (!opt.cache_file.empty() && readCache(opt.cache_file, key, n, with_cnn, raw)) {
    res.inference_cached = true;
    log("network outputs read from cache " + opt.cache_file);
  } else {
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
    const auto t_loaded = Clock::now();
    res.seconds_load = seconds(t1, t_loaded);
    log("loaded " + std::to_string(n) + " images in " + std::to_string(res.seconds_load) + " s");
    ad::OnnxPoseModel gdn(gdn_card.onnx_file, gdn_card);
    raw.gdn = runNetwork(gdn, images, std::max(1, opt.batch));
    if (with_cnn) {
      ad::OnnxPoseModel cnn(cnn_card.onnx_file, cnn_card);
      raw.cnn = runNetwork(cnn, images, std::max(1, opt.batch));
    }
    if (!opt.cache_file.empty()) writeCache(opt.cache_file, key, raw);
  }
  const auto t2 = Clock::now();
  res.seconds_inference = seconds(t1, t2) - res.seconds_load;
  log("inference " + std::to_string(res.seconds_inference) + " s" + (res.inference_cached ? " (cached)" : ""));

  // ---- Table 1 ------------------------------------------------------------------
  // The paper's tables use the network's own σ; a card's σ calibration gets its own Table 2
  // below, so both can be read side by side.
  ad::ModelCard network_card = gdn_card;
  network_card.sigma_scale = {1, 1, 1, 1, 1, 1};
  auto predictions = [&](const ad::ModelCard& card) {
    std::vector<ad::Prediction> pred(n);
    for (std::size_t i = 0; i < n; ++i) {
      std::string detail;
      if (ad::OnnxPoseModel::fromRaw(card, raw.gdn[i].data(), pred[i], &detail) != Status::ok)
        throw std::runtime_error(samples[i].image + ": GDN output: " + detail);
      if (!pred[i].sigma) throw std::runtime_error(card.onnx_file + ": the GDN card has no sigma outputs");
    }
    return pred;
  };
  const std::vector<ad::Prediction> gdn_pred = predictions(network_card);
  std::vector<ad::Prediction> cnn_pred;
  if (with_cnn) {
    cnn_pred.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      std::string detail;
      if (ad::OnnxPoseModel::fromRaw(cnn_card, raw.cnn[i].data(), cnn_pred[i], &detail) != Status::ok)
        throw std::runtime_error(samples[i].image + ": CNN output: " + detail);
    }
  }
  std::vector<Vec6> actual(n), gdn_mu(n), gdn_prec(n), cnn_mu;
  const Vec6 alpha{1, 1, 1, 100, 100, 100};
  double nll = 0.0, mse = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    actual[i] = toReportUnits(samples[i].xi);
    gdn_mu[i] = toReportUnits(SE3d::Tangent(gdn_pred[i].mu));
    const Eigen::Matrix<double, 6, 1>& sigma = *gdn_pred[i].sigma;  // present: checked when predicted
    gdn_prec[i] = precisionReportUnits(sigma);
    for (std::size_t j = 0; j < 6; ++j) {
      const int jj = static_cast<int>(j);
      res.gdn_mae[j] += std::fabs(gdn_mu[i][j] - actual[i][j]);
      res.gdn_mean_sigma[j] += 1.0 / gdn_prec[i][j];
      const double z = (samples[i].xi[j] - gdn_pred[i].mu(jj)) / sigma(jj);  // mm, rad
      nll += 0.5 * z * z + std::log(sigma(jj));
      if (with_cnn) {
        const double e = samples[i].xi[j] - cnn_pred[i].mu(jj);
        mse += alpha[j] * e * e;
      }
    }
  }
  for (std::size_t j = 0; j < 6; ++j) {
    res.gdn_mae[j] /= static_cast<double>(n);
    res.gdn_mean_sigma[j] /= static_cast<double>(n);
  }
  // Fraction of |error| <= scale_j · σ (the network's σ), per component.
  auto coverage = [&](const Vec6& scale) {
    Vec6 c{};
    for (std::size_t j = 0; j < 6; ++j) {
      for (std::size_t i = 0; i < n; ++i)
        if (std::fabs(gdn_mu[i][j] - actual[i][j]) * gdn_prec[i][j] <= scale[j]) c[j] += 1.0;
      c[j] /= static_cast<double>(n);
    }
    return c;
  };
  res.gdn_coverage = coverage(Vec6{1, 1, 1, 1, 1, 1});
  res.have_gdn = true;
  res.gdn_nll_rad = nll / static_cast<double>(n);
  res.gdn_nll_rad_with_c = res.gdn_nll_rad + 3.0 * std::log(2.0 * kPi);
  if (with_cnn) {
    res.have_cnn = true;
    res.cnn_mse_rad = mse / static_cast<double>(n);
    cnn_mu.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      cnn_mu[i] = toReportUnits(SE3d::Tangent(cnn_pred[i].mu));
      for (std::size_t j = 0; j < 6; ++j) res.cnn_mae[j] += std::fabs(cnn_mu[i][j] - actual[i][j]);
    }
    for (double& m : res.cnn_mae) m /= static_cast<double>(n);
  }

  // ---- Table 2: the SE(3) Bayes filter over the sequence ------------------------------
  const auto t3 = Clock::now();
  auto observations = [&](const std::vector<ad::Prediction>& pred) {
    std::vector<ConcentratedGaussian<SE3d>> obs(n);
    for (std::size_t i = 0; i < n; ++i) {
      const Status s = ad::toObservation(pred[i], obs[i]);  // eq. 14 (eq:se3_inverse_transform)
      if (s != Status::ok) throw std::runtime_error(samples[i].image + ": observation: " + describe(s));
    }
    return obs;
  };
  std::vector<FilterRun> traces;
  {
    const auto obs = observations(gdn_pred);
    res.samples = samples;
    res.observations = obs;
    for (double sig : opt.sigma_psi) {
      FilterRun run = replayFilter(samples, obs, sig, opt.seed);
      for (const auto& note : run.notes) res.notes.push_back(note);
      res.filter.push_back(run.row);
      traces.push_back(std::move(run));
      const FilterRun rule = replayFilter(samples, obs, sig, opt.seed, FusionOptions<double>::converged(), true);
      for (const auto& note : rule.notes) res.notes.push_back("converged rule: " + note);
      res.filter_converged.push_back(rule.row);
      res.converged_rule_error.push_back(rule.fusion_error);
    }
  }
  if (gdn_card.hasSigmaCalibration()) {  // the same experiment with the card's calibrated σ
    res.have_calibration = true;
    res.sigma_scale = gdn_card.sigma_scale;
    res.calibration_source = gdn_card.sigma_calibration_source;
    res.gdn_coverage_calibrated = coverage(res.sigma_scale);
    const auto obs = observations(predictions(gdn_card));
    for (double sig : opt.sigma_psi) {
      FilterRun run = replayFilter(samples, obs, sig, opt.seed);
      for (const auto& note : run.notes) res.notes.push_back("calibrated sigma: " + note);
      res.filter_calibrated.push_back(run.row);
    }
  }
  const auto t4 = Clock::now();
  res.seconds_filter = seconds(t3, t4);
  log("filter " + std::to_string(res.seconds_filter) + " s");

  // ---- plots ----------------------------------------------------------------------
  if (!opt.plot_dir.empty()) {
    std::filesystem::create_directories(opt.plot_dir);
    const std::string suffix = " (" + opt.split + ", n = " + std::to_string(n) + ")";
    auto plot = [&](const std::string& file, const std::string& title, const std::vector<Vec6>& pred,
                    const std::vector<Vec6>& prec) {
      const std::string path = opt.plot_dir + "/" + file;
      writeScatterPlot(path, title + suffix, actual, pred, prec);
      res.plots.push_back(path);
    };
    if (with_cnn) plot("table1_cnn.svg", "CNN regression: predicted vs actual", cnn_mu, {});
    plot("table1_gdn.svg", "GDN: predicted vs actual, coloured by predicted precision", gdn_mu, gdn_prec);
    for (std::size_t r = 0; r < res.filter.size(); ++r) {
      char name[64];
      std::snprintf(name, sizeof name, "table2_filter_sigma_%g.svg", res.filter[r].sigma_psi);
      char title[128];
      std::snprintf(title, sizeof title, "GDN + SE(3) Bayes filter, sigma_psi = %g: filtered vs actual",
                    res.filter[r].sigma_psi);
      plot(name, title, traces[r].mu, traces[r].precision);
    }
  }
  const auto t5 = Clock::now();
  res.seconds_plots = seconds(t4, t5);
  res.seconds_total = seconds(t0, t5);
  res.cpu_seconds_total = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
  return res;
}

// ---- reports ------------------------------------------------------------------------

namespace {

std::string f3(double v, int prec = 3) {
  char b[32];
  std::snprintf(b, sizeof b, "%.*f", prec, v);
  return b;
}

const char* kComp[6] = {"v_x / rho_x (mm)", "v_y / rho_y (mm)", "v_z / rho_z (mm)",
                        "w_x / phi_x (deg)", "w_y / phi_y (deg)", "w_z / phi_z (deg)"};

int precOf(std::size_t j) { return j < 3 ? 3 : 2; }

std::string sci(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.1e", v);
  return b;
}

/// The largest |MAE difference| between two rows: over the translations (mm) and over the
/// rotations (deg).
std::pair<double, double> maeDifference(const FilterRow& a, const FilterRow& b) {
  double mm = 0, deg = 0;
  for (std::size_t j = 0; j < 6; ++j) {
    double& worst = j < 3 ? mm : deg;
    worst = std::max(worst, std::fabs(a.mae[j] - b.mae[j]));
  }
  return {mm, deg};
}

const Vec6* paperFilterRow(double sigma) {
  for (std::size_t i = 0; i < PaperTables::sigma.size(); ++i)
    if (std::fabs(PaperTables::sigma[i] - sigma) <= 1e-12 * std::max(1.0, sigma)) return &PaperTables::filter_mae[i + 1];
  return nullptr;
}

}  // namespace

bool paperFilterRatio(double sigma_psi, std::size_t j, double& ratio) {
  const Vec6* p = j < 6 ? paperFilterRow(sigma_psi) : nullptr;
  if (p == nullptr) return false;
  ratio = (*p)[j] / PaperTables::filter_mae[0][j];
  return true;
}

namespace {

/// The "MAE ratio to σψ = ∞, ours [paper] (diff)" table; returns (ratios within ±15 %, ratios compared).
std::pair<int, int> ratioTable(std::ostream& md, const std::vector<FilterRow>& filter, const Vec6& mae_inf) {
  md << "| MAE ratio to σψ = ∞ |";
  for (const auto& r : filter) md << " σψ = " << r.sigma_psi << " ours [paper] (diff) |";
  md << "\n|---|";
  for (std::size_t r = 0; r < filter.size(); ++r) md << "---|";
  md << "\n";
  int within = 0, total = 0;
  for (std::size_t j = 0; j < 6; ++j) {
    md << "| " << kComp[j] << " |";
    for (const auto& r : filter) {
      const double ours = r.mae[j] / mae_inf[j];
      md << " " << f3(ours, 2);
      double paper = 0.0;
      if (paperFilterRatio(r.sigma_psi, j, paper)) {
        const double rel = ours / paper - 1.0;
        md << " [" << f3(paper, 2) << "] (" << (rel >= 0 ? "+" : "") << f3(100.0 * rel, 0) << " %)";
        ++total;
        if (std::fabs(rel) <= kTable2Tolerance) ++within;
      }
      md << " |";
    }
    md << "\n";
  }
  return {within, total};
}

}  // namespace

std::string ReplayResults::table() const {
  std::ostringstream os;
  os << "Table 1 (tab:nn_pose_shear_estimate_results), n = " << n << " images; ours vs paper (test set, 10-model mean)\n";
  os << "  component            CNN ours  CNN paper   GDN ours  GDN paper  GDN<=paper\n";
  for (std::size_t j = 0; j < 6; ++j) {
    char line[200];
    std::snprintf(line, sizeof line, "  %-19s %9s %10s %10s %10s  %s\n", kComp[j],
                  have_cnn ? f3(cnn_mae[j], precOf(j)).c_str() : "-", f3(PaperTables::cnn_mae[j], precOf(j)).c_str(),
                  f3(gdn_mae[j], precOf(j)).c_str(), f3(PaperTables::gdn_mae[j], precOf(j)).c_str(),
                  gdn_mae[j] <= PaperTables::gdn_mae[j] ? "yes" : "NO");
    os << line;
  }
  os << "  loss: CNN weighted MSE (mm, rad) " << (have_cnn ? f3(cnn_mse_rad) : std::string("-")) << " (paper "
     << PaperTables::cnn_mse << "); GDN mean NLL (mm, rad) " << f3(gdn_nll_rad, 2) << " without c, "
     << f3(gdn_nll_rad_with_c, 2) << " with c = 3 ln 2pi (paper " << PaperTables::gdn_nll << ")\n\n";
  os << "Table 2 (tab:bayes_filter_results): filtered MAE; ours [paper]; ratio to sigma_psi = inf: ours [paper]\n";
  os << "  component          inf";
  for (const auto& r : filter) os << "            sigma " << r.sigma_psi;
  os << "\n";
  for (std::size_t j = 0; j < 6; ++j) {
    os << "  " << std::left << std::setw(18) << kComp[j] << std::right << " " << f3(gdn_mae[j], precOf(j)) << " ["
       << f3(PaperTables::filter_mae[0][j], precOf(j)) << "]";
    for (const auto& r : filter) {
      const Vec6* p = paperFilterRow(r.sigma_psi);
      os << "  " << f3(r.mae[j], precOf(j));
      if (p != nullptr) os << " [" << f3((*p)[j], precOf(j)) << "]";
      os << " x" << f3(r.mae[j] / gdn_mae[j], 2);
      if (p != nullptr) os << " [x" << f3((*p)[j] / PaperTables::filter_mae[0][j], 2) << "]";
    }
    os << "\n";
  }
  if (have_calibration) {
    os << "  with the card's calibrated sigma (scale";
    for (double k : sigma_scale) os << " " << f3(k, 2);
    os << "): ratio to sigma_psi = inf\n";
    for (std::size_t j = 0; j < 6; ++j) {
      os << "  " << std::left << std::setw(18) << kComp[j] << std::right << "      ";
      for (const auto& r : filter_calibrated) os << "  " << f3(r.mae[j], precOf(j)) << " x" << f3(r.mae[j] / gdn_mae[j], 2);
      os << "\n";
    }
  }
  if (filter_converged.size() == filter.size() && !filter.empty()) {
    os << "  converged rule (an update under 0.001 sigma, at most 5): updates per correction; largest |MAE difference| "
          "from the 5 iterations (mm, deg); largest fusion error against the fusion run to convergence (mm, rad, sigma)\n";
    for (std::size_t i = 0; i < filter.size(); ++i) {
      const auto [mm, deg] = maeDifference(filter_converged[i], filter[i]);
      const FusionError& e = converged_rule_error[i];
      os << "    sigma " << filter[i].sigma_psi << ": " << f3(filter_converged[i].mean_iterations, 2) << " updates; "
         << sci(mm) << " mm, " << sci(deg) << " deg; " << sci(e.mm) << " mm, " << sci(e.rad) << " rad, " << sci(e.sigma)
         << " sigma\n";
    }
  }
  for (const auto& r : filter)
    if (r.failures > 0) os << "  sigma " << r.sigma_psi << ": " << r.failures << " filter steps failed\n";
  for (const auto& note : notes) os << "  note: " << note << "\n";
  os << "  time: load " << f3(seconds_load, 2) << " s, inference " << f3(seconds_inference, 2) << " s"
     << (inference_cached ? " (cached)" : "") << ", filter " << f3(seconds_filter, 2) << " s, plots "
     << f3(seconds_plots, 2) << " s, total " << f3(seconds_total, 2) << " s wall, " << f3(cpu_seconds_total, 1)
     << " s CPU\n";
  return os.str();
}

std::string displayPath(const std::string& path, const std::string& root, bool executable) {
  namespace fs = std::filesystem;
  std::string out = path;
  if (!root.empty() && fs::path(path).is_absolute()) {
    std::error_code ec;
    const fs::path p = fs::weakly_canonical(fs::absolute(path, ec), ec);
    const fs::path r = fs::weakly_canonical(fs::path(root), ec);
    if (!ec) {
      const fs::path rel = p.lexically_relative(r);
      if (!rel.empty()) out = rel.string();
    }
  }
  if (executable && !out.empty() && out.front() != '/' && out.front() != '.') out = "./" + out;
  return out;
}

std::string ReplayResults::markdown(const ReplayOptions& o, const std::string& command) const {
  std::ostringstream md;
  md << "# Results: the paper's Tables 1 and 2 on the real TacTip data\n\n";
  md << "Generated by `lieservo_replay` (examples/replay) — re-run the command below, from the repository root, "
        "to regenerate this file.\n\n";
  md << "```\n" << command << "\n```\n\n";
  md << "- Data: `" << displayPath(o.data_dir + "/" + o.split, o.display_root) << "` — " << n << " images";
  if (o.unseen_only) md << " (`--unseen-only`: of its " << unseen_of << ", those the network did not train on)";
  if (o.quick > 0) md << " (first " << o.quick << " only: `--quick`)";
  md << ", in file order (targets.csv, increasing contact depth), as one sequence.\n";
  md << "- Models: `" << displayPath(o.models_dir, o.display_root) << "` (gdn.onnx" << (have_cnn ? ", cnn.onnx" : "")
     << "; units from model_card.json), run from C++ with OpenCV cv::dnn after the paper's pre-processing "
        "(resize 128×128 INTER_AREA, /255).\n";
  md << "- Labels ξ = log(X_fs⁻¹)^∨ (translation first), X_fs from the Euler 6-vector "
        "(shear_x, shear_y, pose_z, pose_Rx, pose_Ry, shear_Rz), extrinsic xyz; MAE in mm and degrees "
        "(the paper's tables print mm/s and deg/s: the quantities are poses, not velocities).\n";
  md << "- Caveat: the paper reports means over 10 models on its held-out **test** set; this is one model, and "
     << split_role << "\n\n";

  md << "## Table 1 — single-image estimates (tab:nn_pose_shear_estimate_results)\n\n";
  md << "| Metric | CNN (ours) | CNN (paper) | GDN (ours) | GDN (paper) | GDN ≤ paper |\n|---|---|---|---|---|---|\n";
  md << "| loss | " << (have_cnn ? f3(cnn_mse_rad) + " (MSE)" : std::string("—")) << " | 1.43 ± 0.02 | "
     << f3(gdn_nll_rad, 2) << " (NLL, no c) / " << f3(gdn_nll_rad_with_c, 2) << " (with c) | -7.20 ± 0.25 | |\n";
  for (std::size_t j = 0; j < 6; ++j) {
    md << "| MAE " << kComp[j] << " | " << (have_cnn ? f3(cnn_mae[j], precOf(j)) : std::string("—")) << " | "
       << f3(PaperTables::cnn_mae[j], precOf(j)) << " | " << f3(gdn_mae[j], precOf(j)) << " | "
       << f3(PaperTables::gdn_mae[j], precOf(j)) << " | " << (gdn_mae[j] <= PaperTables::gdn_mae[j] ? "yes" : "**no**")
       << " |\n";
  }
  int met = 0;
  for (std::size_t j = 0; j < 6; ++j) met += gdn_mae[j] <= PaperTables::gdn_mae[j] ? 1 : 0;
  md << "\nTarget \"GDN MAE ≤ the paper's GDN row\": met for " << met << " of 6 components.\n";
  md << "\nLosses use the paper's units (mm, rad): CNN weighted MSE with α = (1,1,1,100,100,100); GDN mean NLL "
        "(eq. 5, eqn:gdn_mean_nll_loss_def) without and with the constant c = 3 ln 2π. Mean predicted GDN σ: ";
  for (std::size_t j = 0; j < 6; ++j) md << (j ? ", " : "") << f3(gdn_mean_sigma[j], precOf(j));
  md << " (mm, deg); fraction of |error| ≤ σ: ";
  for (std::size_t j = 0; j < 6; ++j) md << (j ? ", " : "") << f3(gdn_coverage[j], 2);
  md << " (0.68 for a calibrated Gaussian).\n\n";

  md << "## Table 2 — SE(3) Bayes filter over the sequence (Table 2, tab:bayes_filter_results)\n\n";
  md << "Tₖ = exp(ψₖ^) Xₖ Xₖ₋₁⁻¹ with Xₖ the label poses (eq. 23, eqn:se3_filter_exp_state_trans_model), "
        "ψₖ ~ N(0, σψ² 1) (eq. 24, eqn:se3_filter_exp_state_trans_cov), σψ in mm for ρ and in **degrees** for φ "
        "(converted to radians before the library), Σφ = Σψ; filter `lieservo::DiscriminativeBayesFilter<SE3d>` "
        "(Algorithm 2, alg:se3_bayes_filter, fusion Algorithm 3 (alg:se3_data_fusion), 5 iterations), observations from "
        "eq. 14 (eq:se3_inverse_transform); ψ seed " << o.seed << ". Cells: ours [paper]; second table: MAE relative to σψ = ∞.\n\n";
  md << "| MAE | σψ = ∞ |";
  for (const auto& r : filter) md << " σψ = " << r.sigma_psi << " |";
  md << "\n|---|---|";
  for (std::size_t r = 0; r < filter.size(); ++r) md << "---|";
  md << "\n";
  for (std::size_t j = 0; j < 6; ++j) {
    md << "| " << kComp[j] << " | " << f3(gdn_mae[j], precOf(j)) << " [" << f3(PaperTables::filter_mae[0][j], precOf(j))
       << "] |";
    for (const auto& r : filter) {
      const Vec6* p = paperFilterRow(r.sigma_psi);
      md << " " << f3(r.mae[j], precOf(j));
      if (p != nullptr) md << " [" << f3((*p)[j], precOf(j)) << "]";
      md << " |";
    }
    md << "\n";
  }
  md << "\n";
  const auto [within, total] = ratioTable(md, filter, gdn_mae);
  md << "\n" << within << " of " << total << " ratios within ±15 % of the paper's. The paper's ratios divide by "
        "Table 2's own σψ = ∞ column (its ω_x entry reads 0.50 there, 0.45 in Table 1).\n";
  auto sigmaTable = [&md](const std::vector<FilterRow>& rows) {
    md << "\nMean filtered σ (tangent, mm / deg):\n\n| σψ |";
    for (std::size_t j = 0; j < 6; ++j) md << " " << kComp[j] << " |";
    md << " fusion iterations | failed steps |\n|---|---|---|---|---|---|---|---|---|\n";
    for (const auto& r : rows) {
      md << "| " << r.sigma_psi << " |";
      for (std::size_t j = 0; j < 6; ++j) md << " " << f3(r.mean_sigma[j], precOf(j)) << " |";
      md << " " << f3(r.mean_iterations, 1) << " | " << r.failures << " |\n";
    }
  };
  sigmaTable(filter);
  if (filter_converged.size() == filter.size() && !filter.empty()) {
    md << "\nThe same runs with the converged rule (`FusionOptions::converged()`: stop after an update under 0.001 "
          "standard deviations, at most 5; docs/estimation.md, \"Stopping rule\") instead of the paper's 5 iterations:\n\n"
          "| σψ | updates per correction | largest \\|MAE difference\\| from 5 iterations, mm / deg | largest fusion error "
          "against the fusion run to convergence (same belief and observation), mm / rad / σ | failed steps |\n"
          "|---|---|---|---|---|\n";
    for (std::size_t i = 0; i < filter.size(); ++i) {
      const auto [mm, deg] = maeDifference(filter_converged[i], filter[i]);
      const FusionError& e = converged_rule_error[i];
      md << "| " << filter[i].sigma_psi << " | " << f3(filter_converged[i].mean_iterations, 2) << " | " << sci(mm)
         << " / " << sci(deg) << " | " << sci(e.mm) << " / " << sci(e.rad) << " / " << sci(e.sigma) << " | "
         << filter_converged[i].failures << " |\n";
    }
  }
  if (have_calibration) {
    md << "\n### Table 2 with the model card's σ calibration\n\n";
    md << "The same experiment with each GDN σ multiplied by the card's `sigma_calibration.scale` = (";
    for (std::size_t j = 0; j < 6; ++j) md << (j ? ", " : "") << f3(sigma_scale[j], 2);
    md << "); the means are unchanged, so the σψ = ∞ column is Table 1's. Source of the factors: "
       << (calibration_source.empty() ? std::string("not stated") : calibration_source) << ".\n\n";
    md << "| |";
    for (std::size_t j = 0; j < 6; ++j) md << " " << kComp[j] << " |";
    md << "\n|---|---|---|---|---|---|---|\n| fraction of \\|error\\| ≤ σ, network σ |";
    for (std::size_t j = 0; j < 6; ++j) md << " " << f3(gdn_coverage[j], 2) << " |";
    md << "\n| fraction of \\|error\\| ≤ σ, calibrated σ |";
    for (std::size_t j = 0; j < 6; ++j) md << " " << f3(gdn_coverage_calibrated[j], 2) << " |";
    md << "\n\n(0.68 for a calibrated Gaussian.)\n\n";
    const auto [cal_within, cal_total] = ratioTable(md, filter_calibrated, gdn_mae);
    md << "\n" << cal_within << " of " << cal_total << " ratios within ±15 % of the paper's with the calibrated σ (" << within
       << " with the network's).\n";
    sigmaTable(filter_calibrated);
  }
  md << "\nWhere the remaining gaps come from (shear error by contact depth, σ coverage by depth, the "
        "filter's effect per depth with `lieservo_filter_diagnosis`): examples/gdn/README.md, \"Diagnosis\".\n";
  if (!plots.empty()) {
    md << "\n## Plots\n\nPredicted vs actual per component, coloured by predicted precision (red high, blue low), "
          "like the paper's fig:nn_pose_shear_estimate_performance and fig:bayes_filter_performance "
          "(written by the command above; not committed):\n\n";
    for (const auto& p : plots) md << "- `" << displayPath(p, o.display_root) << "`\n";
  }
  if (!notes.empty()) {
    md << "\n## Notes\n\n";
    for (const auto& note : notes) md << "- " << note << "\n";
  }
  md << "\n## Timing\n\nload " << f3(seconds_load, 2) << " s, inference " << f3(seconds_inference, 2) << " s"
     << (inference_cached ? " (cached)" : "") << ", filter (" << filter.size() + filter_calibrated.size() + filter_converged.size() << " runs) " << f3(seconds_filter, 2)
     << " s, plots " << f3(seconds_plots, 2) << " s, total " << f3(seconds_total, 2) << " s wall, "
     << f3(cpu_seconds_total, 1) << " s CPU (all threads; the wall time depends on the machine's load). "
        "With `--cache FILE` the network outputs are kept (keyed by the ONNX files' hashes) and a re-run "
        "takes about a second.\n";
  return md.str();
}

}  // namespace lieservo::replay

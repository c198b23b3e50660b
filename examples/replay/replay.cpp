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
#include <functional>
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
#include "lieservo/units.hpp"
#include "lieservo_adapters/gdn_observation.hpp"
#include "lieservo_adapters/onnx_pose_model.hpp"
#include "lieservo_adapters/preprocessing.hpp"
#include "plots.hpp"
#include "replay_network.hpp"

namespace lieservo::replay {

namespace ad = lieservo::adapters;
using Clock = std::chrono::steady_clock;

namespace {

constexpr double kPi = lieservo::pi<double>();

double seconds(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }



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
  return dataset::labelFromEuler6Degrees(e);  // the data set's one definition
}

std::vector<Sample> readTargets(const std::string& csv_path) {
  // The project's one targets.csv reader (examples/dataset); its errors name file:line:column.
  std::vector<Sample> out;
  for (const dataset::TargetRow& r : dataset::readTargetsCsv(csv_path)) {
    Sample s;
    s.image = r.sensor_image;
    s.euler = r.euler6Degrees();  // (shear_x, shear_y, pose_z, pose_Rx, pose_Ry, shear_Rz)
    s.xi = labelFromEulerDegrees(s.euler);
    out.push_back(std::move(s));
  }
  if (out.empty()) throw std::runtime_error(csv_path + ": no samples");
  return out;
}

Vec6 toReportUnits(const Vec6& xi) { return poseRadToDeg(xi); }

Vec6 precisionReportUnits(const Eigen::Matrix<double, 6, 1>& sigma) {
  Vec6 v;
  for (int j = 0; j < 6; ++j) {
    const double s = j < 3 ? sigma(j) : rad2deg(sigma(j));
    v[static_cast<std::size_t>(j)] = 1.0 / s;
  }
  return v;
}

void setDemoOutputs(ReplayOptions& opt, const std::string& out_dir) {
  opt.cache_file = out_dir.empty() ? std::string() : out_dir + "/replay_network_outputs.txt";
  opt.plot_dir = out_dir.empty() ? std::string() : out_dir + "/replay";
}

namespace {

using Log = std::function<void(const std::string&)>;

// The split's samples in file order, narrowed by --unseen-only and --quick; the split's role
// into `res`.
std::vector<Sample> selectSamples(const ReplayOptions& opt, ReplayResults& res) {
  const std::string split_dir = opt.data_dir + "/" + opt.split;
  const std::string card = opt.models_dir + "/model_card.json";
  std::vector<Sample> samples = readTargets(split_dir + "/targets.csv");
  res.split_role = splitRole(card, opt.split);
  if (opt.unseen_only) {
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
  res.n = static_cast<int>(samples.size());
  return samples;
}

Networks readNetworks(const ReplayOptions& opt, ReplayResults& res, const Log& log) {
  const std::string card_path = opt.models_dir + "/model_card.json";
  Networks nets;
  nets.gdn = ad::ModelCard::fromJsonFile(card_path, ad::ModelKind::gdn);
  if (nets.gdn.onnx_file.empty()) nets.gdn.onnx_file = opt.models_dir + "/gdn.onnx";
  if (opt.run_cnn) {
    std::string note;
    try {
      nets.cnn = ad::ModelCard::fromJsonFile(card_path, ad::ModelKind::cnn);
      if (nets.cnn.onnx_file.empty()) nets.cnn.onnx_file = opt.models_dir + "/cnn.onnx";
      nets.with_cnn = std::filesystem::exists(nets.cnn.onnx_file);
      if (!nets.with_cnn) note = "CNN skipped: " + nets.cnn.onnx_file + " not found";
    } catch (const std::runtime_error& e) {
      note = std::string("CNN skipped: ") + e.what();
    }
    if (!note.empty()) {
      res.notes.push_back(note);
      log(note);
    }
  }
  if (!std::filesystem::exists(nets.gdn.onnx_file))
    throw std::runtime_error(nets.gdn.onnx_file + ": GDN model not found");
  return nets;
}

// The GDN's predictions under `card` (its σ scaled as the card says).
std::vector<ad::Prediction> gdnPredictions(const ad::ModelCard& card, const RawOutputs& raw,
                                           const std::vector<Sample>& samples) {
  std::vector<ad::Prediction> pred(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    std::string detail;
    if (ad::OnnxPoseModel::fromRaw(card, raw.gdn[i].data(), pred[i], &detail) != Status::ok)
      throw std::runtime_error(samples[i].image + ": GDN output: " + detail);
    if (!pred[i].sigma) throw std::runtime_error(card.onnx_file + ": the GDN card has no sigma outputs");
  }
  return pred;
}

// Table 1's estimates in report units (mm, deg): the labels, the GDN's means and precisions,
// the CNN's means (empty without it).
struct Estimates {
  std::vector<Vec6> actual, gdn_mu, gdn_prec, cnn_mu;
};

// Fraction of |error| <= scale_j · σ (the network's σ), per component.
Vec6 coverage(const Estimates& est, const Vec6& scale) {
  Vec6 c = Vec6::Zero();
  const std::size_t n = est.actual.size();
  for (std::size_t j = 0; j < 6; ++j) {
    for (std::size_t i = 0; i < n; ++i)
      if (std::fabs(est.gdn_mu[i][j] - est.actual[i][j]) * est.gdn_prec[i][j] <= scale[j]) c[j] += 1.0;
    c[j] /= static_cast<double>(n);
  }
  return c;
}

// Table 1 (tab:nn_pose_shear_estimate_results): the GDN's MAE, σ and NLL and the CNN's MAE and MSE.
Estimates table1(const std::vector<ad::Prediction>& gdn_pred, const Networks& nets, const RawOutputs& raw,
                 const std::vector<Sample>& samples, ReplayResults& res) {
  const std::size_t n = samples.size();
  Estimates est;
  est.actual.resize(n);
  est.gdn_mu.resize(n);
  est.gdn_prec.resize(n);
  const Vec6 alpha = (Vec6() << 1, 1, 1, 100, 100, 100).finished();
  double nll = 0.0, mse = 0.0;
  std::vector<ad::Prediction> cnn_pred(nets.with_cnn ? n : 0);
  for (std::size_t i = 0; i < cnn_pred.size(); ++i) {
    std::string detail;
    if (ad::OnnxPoseModel::fromRaw(nets.cnn, raw.cnn[i].data(), cnn_pred[i], &detail) != Status::ok)
      throw std::runtime_error(samples[i].image + ": CNN output: " + detail);
  }
  for (std::size_t i = 0; i < n; ++i) {
    est.actual[i] = toReportUnits(samples[i].xi);
    est.gdn_mu[i] = toReportUnits(SE3d::Tangent(gdn_pred[i].mu));
    const Eigen::Matrix<double, 6, 1>& sigma = *gdn_pred[i].sigma;  // present: checked when predicted
    est.gdn_prec[i] = precisionReportUnits(sigma);
    for (std::size_t j = 0; j < 6; ++j) {
      const int jj = static_cast<int>(j);
      res.gdn_mae[j] += std::fabs(est.gdn_mu[i][j] - est.actual[i][j]);
      res.gdn_mean_sigma[j] += 1.0 / est.gdn_prec[i][j];
      const double z = (samples[i].xi[j] - gdn_pred[i].mu(jj)) / sigma(jj);  // mm, rad
      nll += 0.5 * z * z + std::log(sigma(jj));
      if (nets.with_cnn) {
        const double e = samples[i].xi[j] - cnn_pred[i].mu(jj);
        mse += alpha[j] * e * e;
      }
    }
  }
  for (std::size_t j = 0; j < 6; ++j) {
    res.gdn_mae[j] /= static_cast<double>(n);
    res.gdn_mean_sigma[j] /= static_cast<double>(n);
  }
  res.gdn_coverage = coverage(est, Vec6::Ones());
  res.have_gdn = true;
  res.gdn_nll_rad = nll / static_cast<double>(n);
  res.gdn_nll_rad_with_c = res.gdn_nll_rad + 3.0 * std::log(2.0 * kPi);
  if (nets.with_cnn) {
    res.have_cnn = true;
    res.cnn_mse_rad = mse / static_cast<double>(n);
    est.cnn_mu.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      est.cnn_mu[i] = toReportUnits(SE3d::Tangent(cnn_pred[i].mu));
      for (std::size_t j = 0; j < 6; ++j) res.cnn_mae[j] += std::fabs(est.cnn_mu[i][j] - est.actual[i][j]);
    }
    for (double& m : res.cnn_mae) m /= static_cast<double>(n);
  }
  return est;
}

// The GDN's observations (eq. 14, eq:se3_inverse_transform) of every sample.
std::vector<ConcentratedGaussian<SE3d>> observationsOf(const std::vector<ad::Prediction>& pred,
                                                       const std::vector<Sample>& samples) {
  std::vector<ConcentratedGaussian<SE3d>> obs(pred.size());
  for (std::size_t i = 0; i < pred.size(); ++i) {
    const Status s = ad::toObservation(pred[i], obs[i]);
    if (s != Status::ok) throw std::runtime_error(samples[i].image + ": observation: " + describe(s));
  }
  return obs;
}

// Table 2 (tab:bayes_filter_results): the SE(3) Bayes filter over the sequence per σψ, with the
// paper's 5 iterations and with the converged rule; again with the card's σ calibration.
// Returns the paper-rule runs (their traces are plotted).
std::vector<FilterRun> table2(const ReplayOptions& opt, const Networks& nets, const RawOutputs& raw,
                              const std::vector<ad::Prediction>& gdn_pred, const Estimates& est,
                              const std::vector<Sample>& samples, ReplayResults& res) {
  std::vector<FilterRun> traces;
  res.samples = samples;
  res.observations = observationsOf(gdn_pred, samples);
  for (double sig : opt.sigma_psi) {
    FilterRun run = replayFilter(samples, res.observations, sig, opt.seed);
    for (const auto& note : run.notes) res.notes.push_back(note);
    res.filter.push_back(run.row);
    traces.push_back(std::move(run));
    const FilterRun rule =
        replayFilter(samples, res.observations, sig, opt.seed, FusionOptions<double>::converged(), true);
    for (const auto& note : rule.notes) res.notes.push_back("converged rule: " + note);
    res.filter_converged.push_back(rule.row);
    res.converged_rule_error.push_back(rule.fusion_error);
#ifdef LIESERVO_REPLAY_SMOOTHER
    res.smoother.push_back(replaySmoother(samples, res.observations, sig, opt.seed));
    if (!res.smoother.back().refused.empty()) res.notes.push_back("smoother: " + res.smoother.back().refused);
#endif
  }
  if (nets.gdn.hasSigmaCalibration()) {  // the same experiment with the card's calibrated σ
    res.have_calibration = true;
    res.sigma_scale = Eigen::Map<const Vec6>(nets.gdn.sigma_scale.data());
    res.calibration_source = nets.gdn.sigma_calibration_source;
    res.gdn_coverage_calibrated = coverage(est, res.sigma_scale);
    const auto obs = observationsOf(gdnPredictions(nets.gdn, raw, samples), samples);
    for (double sig : opt.sigma_psi) {
      FilterRun run = replayFilter(samples, obs, sig, opt.seed);
      for (const auto& note : run.notes) res.notes.push_back("calibrated sigma: " + note);
      res.filter_calibrated.push_back(run.row);
    }
  }
  return traces;
}

// The predicted-vs-actual scatter plots of Tables 1 and 2 in opt.plot_dir.
void writePlots(const ReplayOptions& opt, const Estimates& est, const std::vector<FilterRun>& traces,
                ReplayResults& res) {
  std::filesystem::create_directories(opt.plot_dir);
  const std::string suffix = " (" + opt.split + ", n = " + std::to_string(res.n) + ")";
  auto plot = [&](const std::string& file, const std::string& title, const std::vector<Vec6>& pred,
                  const std::vector<Vec6>& prec) {
    const std::string path = opt.plot_dir + "/" + file;
    writeScatterPlot(path, title + suffix, est.actual, pred, prec);
    res.plots.push_back(path);
  };
  if (!est.cnn_mu.empty()) plot("table1_cnn.svg", "CNN regression: predicted vs actual", est.cnn_mu, {});
  plot("table1_gdn.svg", "GDN: predicted vs actual, coloured by predicted precision", est.gdn_mu, est.gdn_prec);
  for (std::size_t r = 0; r < res.filter.size(); ++r) {
    char name[64];
    std::snprintf(name, sizeof name, "table2_filter_sigma_%g.svg", res.filter[r].sigma_psi);
    char title[128];
    std::snprintf(title, sizeof title, "GDN + SE(3) Bayes filter, sigma_psi = %g: filtered vs actual",
                  res.filter[r].sigma_psi);
    plot(name, title, traces[r].mu, traces[r].precision);
  }
}

}  // namespace

ReplayResults runReplay(const ReplayOptions& opt) {
  const auto t0 = Clock::now();
  const std::clock_t c0 = std::clock();
  ReplayResults res;
  const Log log = [&](const std::string& m) {
    if (opt.verbose) std::cerr << "[replay] " << m << std::endl;
  };
  const std::vector<Sample> samples = selectSamples(opt, res);
  const Networks nets = readNetworks(opt, res, log);
  const auto t1 = Clock::now();
  const RawOutputs raw = networkOutputs(opt, nets, samples, res, log);
  const auto t2 = Clock::now();
  res.seconds_inference = seconds(t1, t2) - res.seconds_load;
  log("inference " + std::to_string(res.seconds_inference) + " s" + (res.inference_cached ? " (cached)" : ""));
  // The paper's tables use the network's own σ; a card's σ calibration gets its own Table 2,
  // so both can be read side by side.
  ad::ModelCard network_card = nets.gdn;
  network_card.sigma_scale = {1, 1, 1, 1, 1, 1};
  const std::vector<ad::Prediction> gdn_pred = gdnPredictions(network_card, raw, samples);
  const Estimates est = table1(gdn_pred, nets, raw, samples, res);
  const auto t3 = Clock::now();
  const std::vector<FilterRun> traces = table2(opt, nets, raw, gdn_pred, est, samples, res);
  const auto t4 = Clock::now();
  res.seconds_filter = seconds(t3, t4);
  log("filter " + std::to_string(res.seconds_filter) + " s");
  if (!opt.plot_dir.empty()) writePlots(opt, est, traces, res);
  const auto t5 = Clock::now();
  res.seconds_plots = seconds(t4, t5);
  res.seconds_total = seconds(t0, t5);
  res.cpu_seconds_total = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
  return res;
}

}  // namespace lieservo::replay

// examples/replay/replay.hpp — reproduce the paper's Tables 1 and 2 on a split of the real
// TacTip data, val/ by default (paper Section 5.2 (sec:nn_pose_shear_estimate_exp), Section 5.3 (sec:se3_bayes_filter_exp)).
//
//   Table 1 (tab:nn_pose_shear_estimate_results): per-component MAE of the CNN-regression
//     and GDN estimates of ξ = log(X_fs⁻¹)^∨ (mm, deg), and their losses.
//   Table 2 (tab:bayes_filter_results): the GDN estimates, taken as a sequence in file
//     order, through lieservo::DiscriminativeBayesFilter<SE3d> (Algorithm 2, alg:se3_bayes_filter) with
//     the state dynamics Tₖ = exp(ψₖ^) Xₖ Xₖ₋₁⁻¹ (eq. 23, eqn:se3_filter_exp_state_trans_model),
//     ψₖ ~ N(0, σψ² 1) (eq. 24, eqn:se3_filter_exp_state_trans_cov) and Σφ = Σψ; σψ per component
//     in mm and DEGREES, converted to radians for the rotational components.
//
// Use: ReplayResults r = runReplay(options); r.markdown(options) → docs/results.md.
#pragma once

#include <array>
#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

#include <lieservo_dataset/paper_tables.hpp>

#include "lieservo/estimation/concentrated_gaussian.hpp"
#include "lieservo/estimation/fusion.hpp"
#include "lieservo/groups/se3.hpp"

namespace lieservo::replay {

struct ReplayOptions {
  std::string data_dir;          ///< contains <split>/ (targets.csv, processed_images/, processed_image_params.json)
  std::string split = "val";     ///< the data set's sub-folder to replay (val, train, test, ...)
  std::string models_dir;        ///< contains model_card.json, gdn.onnx, cnn.onnx
  int quick = 0;                 ///< > 0: only the first N images
  /// Only the split's images the card's network did not train on (its data.trained_on and
  /// held-out list, lieservo_dataset/trained_on.hpp): e.g. the deployed GDN's held-out rows.
  bool unseen_only = false;
  std::vector<double> sigma_psi{10.0, 1.0, 0.1, 0.01};  ///< Table 2 columns (mm and deg)
  std::uint64_t seed = 1;        ///< ψₖ noise
  bool run_cnn = true;           ///< also evaluate cnn.onnx when present
  std::string plot_dir;          ///< "" → no plots
  std::string cache_file;        ///< "" → no cache; else network outputs cached here (keyed by model hashes)
  int batch = 32;                ///< images per cv::dnn forward pass
  bool verbose = true;
  std::string display_root;      ///< reports show paths relative to this folder ("" = as given)
};

/// An absolute `path` relative to `root` when `root` is set ("../shared/..." for the data
/// beside the repository); a relative one as given. `executable`: prefixed with "./" when
/// relative.
std::string displayPath(const std::string& path, const std::string& root, bool executable = false);

/// A 6-vector: a label (x, y, z, α, β, γ) or a tangent ξ = [ρ; φ], as in the simulation and
/// the library (SE3<double>::Tangent).
using Vec6 = Eigen::Matrix<double, 6, 1>;

struct Sample {
  std::string image;  ///< file name in processed_images/
  Vec6 euler = Vec6::Zero();  ///< (x, y, z, α, β, γ), mm and deg
  Vec6 xi = Vec6::Zero();     ///< label ξ, mm and rad
};

/// How far a filter's corrections stop from the fusion run to convergence (an update under
/// 1e-12 σ, at most 50) from the same belief and observation: the largest over the corrections.
struct FusionError {
  double mm = 0.0;     ///< translation error ‖Δρ‖, mm
  double rad = 0.0;    ///< rotation error ‖Δφ‖, rad
  double sigma = 0.0;  ///< Mahalanobis length in the converged fusion's covariance
};

struct FilterRow {
  double sigma_psi = 0.0;        ///< mm and deg
  Vec6 mae = Vec6::Zero();         ///< mm, mm, mm, deg, deg, deg
  Vec6 mean_sigma = Vec6::Zero();  ///< mean filtered tangent σ (mm, deg)
  int failures = 0;              ///< filter steps that did not return ok (filter re-initialised)
  double mean_iterations = 0.0;  ///< fusion iterations per correction
};

/// Table 2's experiment through the fixed-interval smoother (lieservo_ceres/smoother.hpp) beside
/// the filter, at one σψ: both scored on their poses, ln(X̂ₖ)^∨ against the labels.
struct SmootherRow {
  double sigma_psi = 0.0;          ///< mm and deg
  Vec6 filter = Vec6::Zero();      ///< MAE of the filtered means X̄ₖ (mm, deg)
  Vec6 smoothed = Vec6::Zero();    ///< MAE of the smoothed poses (mm, deg)
  double seconds_autodiff = 0.0;   ///< ceres::Solve with Jets
  double seconds_closed_form = 0.0;///< ceres::Solve with lminus's closed-form Jacobians
  int iterations = 0;              ///< Levenberg–Marquardt iterations (Jets)
  std::string refused;             ///< the smoother's message when a solve was refused; "" when both converged
};

struct ReplayResults {
  int n = 0;                      ///< images replayed
  int unseen_of = 0;              ///< with unseen_only: the split's images before the selection
  bool have_gdn = false;
  bool have_cnn = false;
  Vec6 gdn_mae = Vec6::Zero();         ///< mm, deg
  Vec6 cnn_mae = Vec6::Zero();
  Vec6 gdn_mean_sigma = Vec6::Zero();  ///< mean predicted σ (mm, deg), the network's own
  Vec6 gdn_coverage = Vec6::Zero();    ///< fraction of |error| <= σ (network σ; 0.683 for a calibrated Gaussian)
  double gdn_nll_rad = 0.0;       ///< mean NLL without c, rotations in radians (paper units)
  double gdn_nll_rad_with_c = 0.0;///< ... plus c = 3 ln(2π)
  double cnn_mse_rad = 0.0;       ///< weighted MSE, α = (1,1,1,100,100,100), rotations in radians
  std::vector<Sample> samples;    ///< the replayed sequence (after quick / unseen_only)
  /// The GDN's observations of `samples` with the network's own σ (eq. 14): what Table 2 filters.
  std::vector<ConcentratedGaussian<SE3d>> observations;
  std::vector<FilterRow> filter;  ///< Table 2 (σψ = ∞ is gdn_mae), the network's σ as in the paper
  /// The same runs with the converged rule (FusionOptions::converged()) instead of the paper's
  /// 5 iterations: how many updates a correction takes on real observations.
  std::vector<FilterRow> filter_converged;
  /// Per σψ: the converged rule's fusion error against the fusion run to convergence on the
  /// same inputs (FilterRun::fusion_error).
  std::vector<FusionError> converged_rule_error;
  // When the model card has a σ calibration (ModelCard::sigma_scale), Table 2 again with it:
  bool have_calibration = false;
  Vec6 sigma_scale = Vec6::Ones();
  std::string calibration_source;
  Vec6 gdn_coverage_calibrated = Vec6::Zero();
  std::vector<FilterRow> filter_calibrated;
  /// Table 2 beside the smoother (builds with Ceres; empty otherwise).
  std::vector<SmootherRow> smoother;
  double seconds_load = 0.0, seconds_inference = 0.0, seconds_filter = 0.0, seconds_plots = 0.0,
         seconds_total = 0.0;
  double cpu_seconds_total = 0.0;  ///< process CPU time (all threads) spent in runReplay
  bool inference_cached = false;
  /// What this split is to the network, from the model card (e.g. "used for early stopping"):
  /// the report's caveat. Set by runReplay (splitRole).
  std::string split_role;
  std::vector<std::string> plots;  ///< files written
  std::vector<std::string> notes;  ///< warnings (missing CNN, filter failures, ...)

  /// A human-readable report with the paper's numbers beside ours.
  std::string table() const;
  /// The whole docs/results.md (`command` is printed as the command that produced it).
  std::string markdown(const ReplayOptions& options, const std::string& command) const;

 private:
  void markdownHeader(std::ostream& md, const ReplayOptions& o, const std::string& command) const;
  void markdownTable1(std::ostream& md) const;
  int markdownTable2(std::ostream& md, const ReplayOptions& o) const;  ///< ratios within ±15 %
  void markdownCalibrated(std::ostream& md, int within) const;
  void markdownSmoother(std::ostream& md) const;
  void markdownTail(std::ostream& md, const ReplayOptions& o) const;
};

/// The first line of docs/results.md as the replay writes it: --results-md overwrites only a
/// file that starts with it.
inline constexpr const char* kResultsHeading = "# Results: the paper's Tables 1 and 2 on the real TacTip data";

/// What `split` is to the network described by the model card at `card_path`, as a sentence
/// for the report: the split it was trained on (all of it, or all but the card's held-out rows:
/// data.trained_on, lieservo_dataset/trained_on.hpp), one used for model selection (the card's
/// training.early_stopping names it), one the card lists but the network did not use, or one
/// the card does not mention. Never says "validation" unless the split is called so.
std::string splitRole(const std::string& card_path, const std::string& split);

/// Throws std::runtime_error when the data or the GDN model is missing or malformed
/// (message names the path). The CNN is optional (skipped with a note when absent).
ReplayResults runReplay(const ReplayOptions& options);

/// Where the main job's replay writes, in its results folder `out_dir`: the network-output
/// cache (out_dir/replay_network_outputs.txt) and the plots (out_dir/replay); nothing when
/// out_dir is empty (lieservo_demo --no-files writes no file).
void setDemoOutputs(ReplayOptions& options, const std::string& out_dir);

/// Label ξ = log(X_fs⁻¹)^∨ (mm, rad) of a targets.csv row's Euler 6-vector
/// (x, y, z, α, β, γ) = (shear_x, shear_y, pose_z, pose_Rx, pose_Ry, shear_Rz), mm and deg.
Vec6 labelFromEulerDegrees(const Vec6& euler_mm_deg);

/// Reads <split_dir>/targets.csv (file order). Throws std::runtime_error naming the file/line.
std::vector<Sample> readTargets(const std::string& csv_path);

/// The filter's process noise of the Table 2 experiment: Σφ = Σψ = σψ² 1 (eq. 24,
/// eqn:se3_filter_exp_state_trans_cov), σψ in mm for ρ and in degrees for φ (radians returned).
SE3d::Jacobian replayProcessNoise(double sigma_psi);
/// The experiment's motions: T_k = exp(ψ_k^) X_k X_{k−1}⁻¹ (eq. 23, eqn:se3_filter_exp_state_trans_model)
/// with X_k = exp(ξ_k^) the samples' labels and ψ_k ~ N(0, Σψ) drawn from `seed` in order of k;
/// T_0 (no motion before the first image) is the identity.
std::vector<SE3d> replayMotions(const std::vector<Sample>& samples, double sigma_psi, std::uint64_t seed);

/// The Table 2 experiment on one sequence: states Xₖ = exp(ξₖ^) from the samples' labels,
/// observations `obs`, Tₖ = exp(ψₖ^) Xₖ Xₖ₋₁⁻¹ with ψₖ ~ N(0, diag(σψ² [mm², mm², mm², rad², rad², rad²]))
/// (σψ given in mm and deg), Σφ = Σψ. Returns the row (MAE vs the labels) and the filtered
/// estimates (mm, deg) and precisions (1/mm, 1/deg) per step. `fusion`: the correction's
/// iterations (default: the paper's fixed 5). `measure_fusion_error`: each correction is also
/// made from the same belief with the fusion run to convergence, and `fusion_error` says how far
/// the filtered estimates were from it.
struct FilterRun {
  FilterRow row;
  std::vector<Vec6> mu;
  std::vector<Vec6> precision;
  std::vector<SE3d> mean;  ///< the filtered means X̄ₖ themselves (the smoother's lesson compares poses)
  std::vector<std::string> notes;
  FusionError fusion_error;  ///< with measure_fusion_error; zero otherwise
};
FilterRun replayFilter(const std::vector<Sample>& samples, const std::vector<ConcentratedGaussian<SE3d>>& obs,
                       double sigma_psi, std::uint64_t seed, const FusionOptions<double>& fusion = {},
                       bool measure_fusion_error = false);

/// Mean absolute error of poses, ln(X̂ₖ)^∨ against the samples' labels, in mm and degrees.
Vec6 poseMae(const std::vector<SE3d>& X, const std::vector<Sample>& samples);

/// The smoother beside the filter on one sequence (replayFilter's run and replayMotions' motions,
/// Σφ = replayProcessNoise): defined in builds with Ceres (replay_smoother.cpp). The smoothed poses
/// come from the solve with Jets; with `time_closed_form` the closed-form Jacobians' solve is also
/// made, for its time (seconds_closed_form stays 0 without it).
SmootherRow replaySmoother(const std::vector<Sample>& samples, const std::vector<ConcentratedGaussian<SE3d>>& obs,
                           double sigma_psi, std::uint64_t seed, bool time_closed_form = true);

/// mm, rad -> mm, deg (components 4-6).
Vec6 toReportUnits(const Vec6& xi);
/// 1/σ in 1/mm, 1/deg from σ in mm, rad.
Vec6 precisionReportUnits(const Eigen::Matrix<double, 6, 1>& sigma);

/// The paper's Table 2 MAE ratio for component j (0..5): its σψ = sigma_psi row over its own
/// σψ = ∞ row. false when the paper has no such column.
bool paperFilterRatio(double sigma_psi, std::size_t j, double& ratio);
/// The Table 2 target: |ours / paper − 1| ≤ this, per ratio.
inline constexpr double kTable2Tolerance = 0.15;

// The paper's numbers (means over 10 models, test set), for the report.
using dataset::PaperTables;

}  // namespace lieservo::replay

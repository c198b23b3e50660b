// The replay's reports: the console tables (ReplayResults::table) and docs/results.md
// (ReplayResults::markdown), the paper's numbers beside ours.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <ostream>
#include <sstream>
#include <utility>

#include "replay.hpp"

namespace lieservo::replay {

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

const PaperTables::Row* paperFilterRow(double sigma) {
  for (std::size_t i = 0; i < PaperTables::sigma.size(); ++i)
    if (std::fabs(PaperTables::sigma[i] - sigma) <= 1e-12 * std::max(1.0, sigma)) return &PaperTables::filter_mae[i + 1];
  return nullptr;
}

}  // namespace

bool paperFilterRatio(double sigma_psi, std::size_t j, double& ratio) {
  const PaperTables::Row* p = j < 6 ? paperFilterRow(sigma_psi) : nullptr;
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
      const PaperTables::Row* p = paperFilterRow(r.sigma_psi);
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

namespace {

/// Mean filtered σ, fusion iterations and failed steps per σψ.
void sigmaTable(std::ostream& md, const std::vector<FilterRow>& rows) {
  md << "\nMean filtered σ (tangent, mm / deg):\n\n| σψ |";
  for (std::size_t j = 0; j < 6; ++j) md << " " << kComp[j] << " |";
  md << " fusion iterations | failed steps |\n|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : rows) {
    md << "| " << r.sigma_psi << " |";
    for (std::size_t j = 0; j < 6; ++j) md << " " << f3(r.mean_sigma[j], precOf(j)) << " |";
    md << " " << f3(r.mean_iterations, 1) << " | " << r.failures << " |\n";
  }
}

}  // namespace

// docs/results.md in parts: what was run on what, Table 1, Table 2, Table 2 with the card's σ
// calibration, then the plots, notes and times.
void ReplayResults::markdownHeader(std::ostream& md, const ReplayOptions& o, const std::string& command) const {
  md << kResultsHeading << "\n\n";
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

}

void ReplayResults::markdownTable1(std::ostream& md) const {
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

}

int ReplayResults::markdownTable2(std::ostream& md, const ReplayOptions& o) const {
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
      const PaperTables::Row* p = paperFilterRow(r.sigma_psi);
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
  sigmaTable(md, filter);
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
  return within;
}

void ReplayResults::markdownSmoother(std::ostream& md) const {
  if (smoother.empty()) return;
  md << "\n### Table 2 beside the fixed-interval smoother\n\n"
        "The same observations, motions and Σφ solved over the whole sequence at once: one nonlinear least-squares "
        "problem in Ceres (examples/adapters/ceres, `lieservo_ceres/smoother.hpp`; lesson 08). The filter uses frames "
        "0…k for pose k; the smoother uses every frame. Both are scored on their poses, ln(X̂ₖ)^∨ against the labels "
        "(the table above scores the filter's tangent-Gaussian mean). Solve times: one run of `ceres::Solve`, with Jets "
        "and with lminus's closed-form Jacobians (not a benchmark: `lieservo_replay_bench --benchmark_filter=Smoother` "
        "times both, docs/performance.md).\n\n"
        "| σψ | estimate |";
  for (std::size_t j = 0; j < 6; ++j) md << " " << kComp[j] << " |";
  md << " solve, Jets / closed form | LM iterations |\n|---|---|---|---|---|---|---|---|---|---|\n";
  for (const SmootherRow& r : smoother) {
    if (!r.refused.empty()) {
      md << "| " << r.sigma_psi << " | refused: " << r.refused << " | | | | | | | | |\n";
      continue;
    }
    md << "| " << r.sigma_psi << " | filter |";
    for (std::size_t j = 0; j < 6; ++j) md << " " << f3(r.filter[j], precOf(j)) << " |";
    md << " | |\n| | smoother |";
    for (std::size_t j = 0; j < 6; ++j) md << " " << f3(r.smoothed[j], precOf(j)) << " |";
    md << " " << f3(r.seconds_autodiff, 3) << " s / " << f3(r.seconds_closed_form, 3) << " s | " << r.iterations << " |\n";
  }
}

void ReplayResults::markdownCalibrated(std::ostream& md, int within) const {
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
  sigmaTable(md, filter_calibrated);
}

void ReplayResults::markdownTail(std::ostream& md, const ReplayOptions& o) const {
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
     << (inference_cached ? " (cached)" : "") << ", filter (" << filter.size() + filter_calibrated.size() + filter_converged.size() << " runs"
     << (smoother.empty() ? std::string() : ", " + std::to_string(2 * smoother.size()) + " smoother solves") << ") "
     << f3(seconds_filter, 2)
     << " s, plots " << f3(seconds_plots, 2) << " s, total " << f3(seconds_total, 2) << " s wall, "
     << f3(cpu_seconds_total, 1) << " s CPU (all threads; the wall time depends on the machine's load). "
        "With `--cache FILE` the network outputs are kept (keyed by the ONNX files' hashes) and a re-run "
        "takes about a second.\n";
}

std::string ReplayResults::markdown(const ReplayOptions& o, const std::string& command) const {
  std::ostringstream md;
  markdownHeader(md, o, command);
  markdownTable1(md);
  const int within = markdownTable2(md, o);
  if (have_calibration) markdownCalibrated(md, within);
  markdownSmoother(md);
  markdownTail(md, o);
  return md.str();
}

}  // namespace lieservo::replay

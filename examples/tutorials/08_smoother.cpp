// Tutorial 08 — the smoother beside the filter: how much does a causal filter leave on the table?
//
// The story. The paper's filter (Algorithm 2, alg:se3_bayes_filter) is causal: its estimate at
// frame k uses frames 0…k only, so that a robot can act on it at once. Its Table 2
// (tab:bayes_filter_results) shows what that gains over the raw network. Offline, with the whole
// sequence recorded, the same two models give a better estimate: the fixed-interval smoother,
// which uses every frame, past and future, for every pose. Here it is one nonlinear least-squares
// problem on SE(3), solved by Ceres (lieservo_ceres/smoother.hpp):
//   - each observation Z_k (the GDN's μ, σ as a concentrated Gaussian, eq. 14) is a residual
//     ln(X_k Z_k⁻¹)^∨ whitened by its covariance;
//   - each known sensor motion T_k is a residual ln(X_k (T_k X_{k−1})⁻¹)^∨ whitened by the
//     filter's process noise Σφ = Σψ (eq. 23, eqn:se3_filter_exp_state_trans_model, and
//     eq. 24, eqn:se3_filter_exp_state_trans_cov);
//   - the poses live on the SE3Manifold (left perturbation), and Jets differentiate lieservo's
//     own log, or the closed-form Jacobians of lminus do (the two timings are printed).
// examples/replay/replay_smoother.cpp makes the two solves and scores them (read it beside this
// file); the replay's report (docs/results.md) prints the same comparison.
// This program
//   1. draws three 1000-frame sequences from the filter's own model, in the Table 2 set-up (random
//      contacts, the motions T_k = exp(ψ_k^) X_k X_{k−1}⁻¹ with ψ_k ~ N(0, σψ² 1)), and counts the
//      (sequence, σψ, component) triples where the smoother's MAE is above the filter's. The
//      smoother is the better estimate in expectation, not on every sequence: at σψ = 10 both are
//      within 0.03 of the raw network, and on one of these sequences the smoother is above the
//      filter there (z, by under 1e-4 mm) and at σψ = 0.01 (β, 0.066° against 0.059°). The count
//      is printed as the check "at or below on every component", which these sequences do not
//      meet (docs/estimation.md, "The smoother"). With --sequences N (N > 3) it draws N and
//      prints, per σψ and component, on how many the smoother is above and the mean ratio of
//      the two MAEs: the Monte Carlo behind "better in expectation";
//   2. runs the same comparison on the real TacTip validation sequence that Table 2 uses (the
//      replay's GDN observations, examples/replay), when the data is there, and prints it in
//      Table 2's layout. On the real sequence the numbers are reported, whatever they are.
// Both estimates are scored the same way: the MAE of ln(X̂_k)^∨ against the label, mm and deg.
// Exit status 1 when a solve is refused or the real sequence cannot be read, 2 for bad usage.
//
// Build and run:  cmake --build <build> --target lieservo_tutorial_08_smoother &&
//                 <build>/examples/tutorials/lieservo_tutorial_08_smoother [--no-real] [--sequences N]
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <lieservo/estimation.hpp>
#include <lieservo/sampling/random.hpp>
#include <lieservo/units.hpp>

#include "replay.hpp"

// LIESERVO_DEFAULT_DATA_DIR and LIESERVO_DEFAULT_MODELS_DIR: set by examples/tutorials/CMakeLists.txt.

using namespace lieservo;
namespace replay = lieservo::replay;
using replay::Sample;
using replay::Vec6;
using Observations = std::vector<ConcentratedGaussian<SE3d>>;

namespace {

const std::vector<double> kSigmaPsi{10.0, 1.0, 0.1, 0.01};  // Table 2's columns, mm and deg
constexpr std::uint64_t kSeed = 1;                          // the replay's ψ_k seed

/// Table 2's layout: the raw GDN (σψ = ∞), then the filter and the smoother at each σψ.
void printTable(const Vec6& gdn, const std::vector<replay::SmootherRow>& rows) {
  std::printf("  %-8s %-9s %7s %7s %7s %7s %7s %7s   %s\n", "sigma_psi", "estimate", "x mm", "y mm", "z mm",
              "a deg", "b deg", "g deg", "smoother solve (autodiff | closed form, LM iterations)");
  auto line = [](const char* s, const char* what, const Vec6& v) {
    std::printf("  %-9s %-9s", s, what);
    for (int j = 0; j < 6; ++j) std::printf(" %7.3f", v[j]);
  };
  line("inf", "GDN", gdn);
  std::printf("\n");
  for (const replay::SmootherRow& r : rows) {
    if (!r.refused.empty()) {
      std::printf("  sigma_psi %g: the smoother refused: %s\n", r.sigma_psi, r.refused.c_str());
      continue;
    }
    char s[32];
    std::snprintf(s, sizeof s, "%g", r.sigma_psi);
    line(s, "filter", r.filter);
    std::printf("\n");
    line("", "smoother", r.smoothed);
    std::printf("   %.3f s | %.3f s, %d\n", r.seconds_autodiff, r.seconds_closed_form, r.iterations);
  }
}

/// Part 1's sequence: `n` random contacts like the data set's labels, observed through the
/// filter's own observation model Z_k = exp(ε_k^) X_k, ε_k ~ N(0, diag σ²), with σ from the paper's
/// Table 1 GDN MAE (σ = MAE √(π/2) for a Gaussian).
void drawSequence(std::uint64_t seed, std::size_t n, std::vector<Sample>& samples, Observations& obs) {
  sampling::Rng rng(seed);
  const replay::PaperTables paper;
  Vec6 sigma;  // mm, rad
  for (int j = 0; j < 6; ++j) sigma[j] = paper.gdn_mae[static_cast<std::size_t>(j)] * std::sqrt(pi<double>() / 2.0);
  sigma.tail<3>() *= deg2rad(1.0);
  const SE3d::Jacobian R = sigma.array().square().matrix().asDiagonal();
  for (std::size_t k = 0; k < n; ++k) {
    Sample s;
    s.euler << sampling::uniform(rng, -4.0, 4.0), sampling::uniform(rng, -4.0, 4.0), sampling::uniform(rng, 0.5, 4.5),
        sampling::uniform(rng, -5.0, 5.0), sampling::uniform(rng, -5.0, 5.0), sampling::uniform(rng, -5.0, 5.0);
    s.xi = replay::labelFromEulerDegrees(s.euler);
    Vec6 eps;
    for (int j = 0; j < 6; ++j) eps[j] = sigma[j] * sampling::standardNormal(rng);
    obs.push_back({SE3d::exp(eps) * SE3d::exp(s.xi), R});
    samples.push_back(s);
  }
}

/// Part 1: the model's own sequences (seeds 11, 12, …), each table printed for the first three.
/// With more than three, the count per (σψ, component) and the mean ratio of the two MAEs: the
/// Monte Carlo behind "better in expectation". Returns the number of refused solves.
int partSynthetic(int sequences) {
  std::printf("1. %d 1000-frame sequences drawn from the filter's own model (the Table 2 set-up)\n", sequences);
  const std::size_t levels = kSigmaPsi.size();
  std::vector<Vec6> above(levels, Vec6::Zero()), ratio(levels, Vec6::Zero());
  std::vector<int> solved_at(levels, 0);
  int worse = 0, refused = 0, solved = 0;
  for (int i = 0; i < sequences; ++i) {
    const std::uint64_t seed = 11u + static_cast<std::uint64_t>(i);
    std::vector<Sample> samples;
    Observations obs;
    drawSequence(seed, 1000, samples, obs);
    std::vector<SE3d> raw;
    for (const auto& z : obs) raw.push_back(z.mean);
    std::vector<replay::SmootherRow> rows;
    for (double s : kSigmaPsi) rows.push_back(replay::replaySmoother(samples, obs, s, kSeed));
    const bool shown = i < 3;
    if (shown) {
      std::printf(" seed %llu:\n", static_cast<unsigned long long>(seed));
      printTable(replay::poseMae(raw, samples), rows);
    }
    for (std::size_t l = 0; l < levels; ++l) {
      const replay::SmootherRow& r = rows[l];
      refused += !r.refused.empty();
      if (!r.refused.empty()) continue;
      ++solved;
      ++solved_at[l];
      for (int j = 0; j < 6; ++j) {
        ratio[l][j] += r.smoothed[j] / r.filter[j];
        if (r.smoothed[j] > r.filter[j]) {
          ++worse;
          above[l][j] += 1;
          if (shown)
            std::printf("  above: sigma_psi %g, component %d: smoother %.4f, filter %.4f\n", r.sigma_psi, j + 1,
                        r.smoothed[j], r.filter[j]);
        }
      }
    }
  }
  if (sequences > 3) {
    std::printf(" over the %d sequences: on how many the smoother's MAE is above the filter's | the mean of "
                "smoother MAE / filter MAE\n  %-9s %13s %13s %13s %13s %13s %13s\n",
                sequences, "sigma_psi", "x", "y", "z", "a", "b", "g");
    for (std::size_t l = 0; l < levels; ++l) {
      std::printf("  %-9g", kSigmaPsi[l]);
      for (int j = 0; j < 6; ++j) std::printf("   %3.0f | %5.3f", above[l][j], ratio[l][j] / std::max(1, solved_at[l]));
      std::printf("\n");
    }
  }
  std::printf(" the smoother's MAE is above the filter's on %d of %d (sequence, σψ, component) triples: "
              "the check \"at or below on every component\" is %s\n\n",
              worse, 6 * solved, worse == 0 ? "met" : "NOT met");
  return refused;
}

/// Part 2: the real validation sequence, as the replay reads it (file order, the network's σ).
int partReal() {
  replay::ReplayOptions o;
  o.data_dir = LIESERVO_DEFAULT_DATA_DIR;
  o.models_dir = LIESERVO_DEFAULT_MODELS_DIR;
  o.run_cnn = false;
  o.verbose = false;
  o.sigma_psi = kSigmaPsi;
  if (!std::filesystem::exists(o.data_dir + "/val/targets.csv")) {
    std::printf("2. The real sequence: skipped, no data at %s (../shared/data/tactip)\n", o.data_dir.c_str());
    return 0;
  }
  const replay::ReplayResults res = replay::runReplay(o);
  std::printf("2. The real TacTip validation sequence (%d frames, the GDN of %s), as Table 2:\n", res.n,
              o.models_dir.c_str());
  if (res.smoother.size() != kSigmaPsi.size()) {
    std::printf("   the replay made no smoother rows (a build without Ceres)\n");
    return 1;
  }
  int refused = 0;
  for (const replay::SmootherRow& r : res.smoother) refused += !r.refused.empty();
  std::vector<SE3d> raw;
  for (const auto& z : res.observations) raw.push_back(z.mean);
  printTable(replay::poseMae(raw, res.samples), res.smoother);
  return refused;
}

}  // namespace

int main(int argc, char** argv) {
  bool real = true;
  int sequences = 3;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--no-real") == 0) {
      real = false;
    } else if (std::strcmp(argv[i], "--sequences") == 0) {
      const char* v = i + 1 < argc ? argv[++i] : "";
      char* end = nullptr;
      const long n = std::strtol(v, &end, 10);
      if (*v == '\0' || *end != '\0' || n < 1 || n > 10000) {
        std::fprintf(stderr, "%s: --sequences needs a whole number from 1 to 10000, got '%s'\n", argv[0], v);
        return 2;
      }
      sequences = static_cast<int>(n);
    } else {
      std::fprintf(stderr, "usage: %s [--no-real] [--sequences N]; unknown option '%s'\n", argv[0], argv[i]);
      return 2;
    }
  }
  int failed = partSynthetic(sequences);
  if (real) {
    try {
      failed += partReal();
    } catch (const std::exception& e) {
      std::printf("2. The real sequence: %s\n", e.what());
      ++failed;
    }
  }
  std::printf("%s\n", failed == 0 ? "OK: every smoother solve converged" : "FAILED (see above)");
  return failed == 0 ? 0 : 1;
}

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
//   1. draws 400 1000-frame sequences from the filter's own model, in the Table 2 set-up (random
//      contacts, the motions T_k = exp(ψ_k^) X_k X_{k−1}⁻¹ with ψ_k ~ N(0, σψ² 1)), prints the
//      first three as Table 2, and then, per σψ and component, the MAE of each estimate over all
//      the frames and on how many sequences the smoother's MAE is above the filter's. The smoother
//      is the better estimate in expectation, not on every sequence: at σψ = 10 the motion adds
//      almost nothing to the observations (a gain of about 0.1 %), and the smoother is above the
//      filter on about a third of the sequences there. The check, which can fail, is on all the
//      frames: over the 400 sequences the smoother's MAE is at or below the filter's on every
//      (σψ, component) (exit 1 otherwise). Its sample size comes from a pilot on other seeds
//      (docs/estimation.md, "The smoother"); with --sequences N below 400 it is not made;
//   2. runs the same comparison on the real TacTip validation sequence that Table 2 uses (the
//      replay's GDN observations, examples/replay), when the data is there, and prints it in
//      Table 2's layout. On the real sequence the numbers are reported, whatever they are.
// Both estimates are scored the same way: the MAE of ln(X̂_k)^∨ against the label, mm and deg.
// Exit status 1 when a solve is refused, the check is not met or the real sequence cannot be read,
// 2 for bad usage.
//
// Build and run:  cmake --build <build> --target lieservo_tutorial_08_smoother &&
//                 <build>/examples/tutorials/lieservo_tutorial_08_smoother [--no-real] [--sequences N]
//                 [--first-seed S]
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
// Part 1's check: its sample size and seeds, fixed before it was first run (docs/estimation.md,
// "The smoother", gives the pilot on seeds 11-70 that set the size).
constexpr int kCheckSequences = 400;
constexpr long kCheckFirstSeed = 1001;

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

/// Part 1: the model's own sequences (seeds first_seed, first_seed + 1, …), each table printed for
/// the first three; then, per σψ and component, the MAE of each estimate over all the sequences'
/// frames and on how many sequences the smoother's MAE is above the filter's. The check, made when
/// there are at least kCheckSequences sequences: over them, the smoother's MAE is at or below the
/// filter's on every (σψ, component). Returns the number of refused solves, plus 1 when the check
/// is made and not met.
int partSynthetic(int sequences, std::uint64_t first_seed) {
  std::printf("1. %d 1000-frame sequences drawn from the filter's own model (the Table 2 set-up, seeds %llu-%llu)\n",
              sequences, static_cast<unsigned long long>(first_seed),
              static_cast<unsigned long long>(first_seed + static_cast<std::uint64_t>(sequences) - 1));
  const std::size_t levels = kSigmaPsi.size();
  std::vector<Vec6> above(levels, Vec6::Zero()), filter_sum(levels, Vec6::Zero()), smoother_sum(levels, Vec6::Zero());
  int refused = 0;
  for (int i = 0; i < sequences; ++i) {
    const std::uint64_t seed = first_seed + static_cast<std::uint64_t>(i);
    std::vector<Sample> samples;
    Observations obs;
    drawSequence(seed, 1000, samples, obs);
    const bool shown = i < 3;
    std::vector<replay::SmootherRow> rows;  // the closed-form solve's time only for the tables shown
    for (double s : kSigmaPsi) rows.push_back(replay::replaySmoother(samples, obs, s, kSeed, shown));
    if (shown) {
      std::vector<SE3d> raw;
      for (const auto& z : obs) raw.push_back(z.mean);
      std::printf(" seed %llu:\n", static_cast<unsigned long long>(seed));
      printTable(replay::poseMae(raw, samples), rows);
    }
    for (std::size_t l = 0; l < levels; ++l) {
      const replay::SmootherRow& r = rows[l];
      if (!r.refused.empty()) {
        std::printf("  seed %llu, sigma_psi %g: the smoother refused: %s\n", static_cast<unsigned long long>(seed),
                    r.sigma_psi, r.refused.c_str());
        ++refused;
        continue;
      }
      // Every sequence has 1000 frames: the MAE over all of them is the mean of the sequences' MAEs.
      filter_sum[l] += r.filter;
      smoother_sum[l] += r.smoothed;
      above[l] += (r.smoothed.array() > r.filter.array()).cast<double>().matrix();
    }
  }
  std::printf(" over all %d sequences: the MAE of each estimate, smoother / filter, and on how many sequences the "
              "smoother's MAE is above the filter's\n  %-9s %-9s %7s %7s %7s %7s %7s %7s\n",
              sequences, "sigma_psi", "", "x mm", "y mm", "z mm", "a deg", "b deg", "g deg");
  bool met = refused == 0;
  for (std::size_t l = 0; l < levels; ++l) {
    const Vec6 f = filter_sum[l] / sequences, m = smoother_sum[l] / sequences;
    met = met && (m.array() <= f.array()).all();
    std::printf("  %-9g %-9s", kSigmaPsi[l], "filter");
    for (int j = 0; j < 6; ++j) std::printf(" %7.4f", f[j]);
    std::printf("\n  %-9s %-9s", "", "smoother");
    for (int j = 0; j < 6; ++j) std::printf(" %7.4f", m[j]);
    std::printf("\n  %-9s %-9s", "", "ratio");
    for (int j = 0; j < 6; ++j) std::printf(" %7.4f", m[j] / f[j]);
    std::printf("\n  %-9s %-9s", "", "above on");
    for (int j = 0; j < 6; ++j) std::printf(" %7.0f", above[l][j]);
    std::printf("\n");
  }
  if (sequences < kCheckSequences) {
    std::printf(" the check needs %d sequences or more (--sequences): not made\n\n", kCheckSequences);
    return refused;
  }
  std::printf(" the check \"over the sequences, the smoother's MAE is at or below the filter's on every component\" "
              "is %s\n\n", met ? "met" : "NOT met");
  return refused + (met ? 0 : 1);
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
  int sequences = kCheckSequences;
  long first_seed = kCheckFirstSeed;
  for (int i = 1; i < argc; ++i) {
    const bool count = std::strcmp(argv[i], "--sequences") == 0, seed = std::strcmp(argv[i], "--first-seed") == 0;
    if (std::strcmp(argv[i], "--no-real") == 0) {
      real = false;
    } else if (count || seed) {
      const char* v = i + 1 < argc ? argv[++i] : "";
      char* end = nullptr;
      const long n = std::strtol(v, &end, 10);
      const long lo = count ? 1 : 0, hi = count ? 10000 : 1000000000;
      if (*v == '\0' || *end != '\0' || n < lo || n > hi) {
        std::fprintf(stderr, "%s: %s needs a whole number from %ld to %ld, got '%s'\n", argv[0], argv[i - 1], lo, hi,
                     v);
        return 2;
      }
      if (count)
        sequences = static_cast<int>(n);
      else
        first_seed = n;
    } else {
      std::fprintf(stderr, "usage: %s [--no-real] [--sequences N] [--first-seed S]; unknown option '%s'\n", argv[0],
                   argv[i]);
      return 2;
    }
  }
  int failed = partSynthetic(sequences, static_cast<std::uint64_t>(first_seed));
  if (real) {
    try {
      failed += partReal();
    } catch (const std::exception& e) {
      std::printf("2. The real sequence: %s\n", e.what());
      ++failed;
    }
  }
  std::printf("%s\n", failed == 0 ? "OK: every smoother solve converged, and the check was met or not made"
                                   : "FAILED (see above)");
  return failed == 0 ? 0 : 1;
}

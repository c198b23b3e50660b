// lieservo_filter_diagnosis — the Table 2 experiment of lieservo_replay on GDN outputs read from a
// text file, with a breakdown by contact depth: which contacts does the SE(3) Bayes filter help,
// and which does it hurt, for a given σ? (examples/gdn/README.md, "Diagnosis").
//
//   /usr/bin/python3 examples/gdn/diagnose.py --dump /tmp/val_card.txt --dump-sigma card
//   lieservo_filter_diagnosis /tmp/val_card.txt [--sigmas 10,1,0.1,0.01] [--synthetic SEED]
//                             [--converged] [--expect-improvement]
//
// Input: one row per image, in sequence order, 19 numbers: the contact depth z (mm), the label
// ξ (6), the GDN mean μ (6) and its σ (6), all in mm and radians (translation first). Lines
// starting with '#' are comments.
// --synthetic SEED replaces each μ by ξ + σ ⊙ n, n ~ N(0, 1): observations whose σ is exactly
// right, so any harm the filter does with them is the filter's, not the network's.
// The experiment is lieservo_replay's (replayFilter, seed 1): Tₖ = exp(ψₖ^) Xₖ Xₖ₋₁⁻¹ (eq. 23, eqn:se3_filter_exp_state_trans_model),
// ψₖ ~ N(0, σψ² 1) with σψ in mm and degrees (eq. 24, eqn:se3_filter_exp_state_trans_cov), Σφ = Σψ,
// the paper's 5 fusion iterations (or --converged: up to 50, tolerance 1e-12).
// Exit codes: 0 ok; 1 --expect-improvement and the smallest σψ did not lower every component's
// MAE; 2 bad usage or an unreadable or malformed rows file.
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <limits>
#include <stdexcept>
#include <sstream>
#include <string>
#include <vector>

#include <lieservo_cli/cli.hpp>

#include <lieservo/sampling/random.hpp>

#include "lieservo/estimation.hpp"
#include "lieservo/groups.hpp"
#include "replay.hpp"  // replayFilter, toReportUnits, paperFilterRatio

namespace {

using lieservo::ConcentratedGaussian;
using lieservo::SE3d;
using lieservo::Status;
using Tangent = SE3d::Tangent;

struct Row {
  double z = 0.0;
  Tangent xi, mu, sigma;
};

constexpr std::array<double, 4> kDepthEdges{0.5, 1.5, 3.0, 6.0};  // as diagnose.py
constexpr int kBins = static_cast<int>(kDepthEdges.size()) - 1;

int depthBin(double z) {
  for (int b = 1; b < kBins; ++b)
    if (z < kDepthEdges[static_cast<std::size_t>(b)]) return b - 1;
  return kBins - 1;
}

std::vector<Row> readRows(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw std::runtime_error(path + ": cannot open");
  std::vector<Row> rows;
  std::string line;
  int line_no = 0;
  while (std::getline(f, line)) {
    ++line_no;
    if (line.empty() || line[0] == '#') continue;
    std::istringstream is(line);
    Row r;
    is >> r.z;
    for (Tangent* v : {&r.xi, &r.mu, &r.sigma})
      for (int j = 0; j < 6; ++j) is >> (*v)(j);
    std::string extra;
    if (!is || (is >> extra))
      throw std::runtime_error(path + ":" + std::to_string(line_no) + ": expected 19 numbers");
    if (!std::isfinite(r.z) || !r.xi.allFinite() || !r.mu.allFinite() || !(r.sigma.array() > 0.0).all() ||
        !r.sigma.allFinite())
      throw std::runtime_error(path + ":" + std::to_string(line_no) + ": non-finite value or sigma <= 0");
    rows.push_back(r);
  }
  if (rows.size() < 2) throw std::runtime_error(path + ": fewer than 2 rows");
  return rows;
}

// MAE (mm, deg) per depth bin; index kBins: all rows.
using Vec6 = lieservo::replay::Vec6;
using BinMae = std::array<Vec6, kBins + 1>;

// MAE of the estimates est[k] (mm, deg) against the rows' labels, by depth.
BinMae binnedMae(const std::vector<Row>& rows, const std::vector<Vec6>& est) {
  BinMae mae;
  mae.fill(Vec6::Zero());
  std::array<int, kBins + 1> count{};
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const auto b = static_cast<std::size_t>(depthBin(rows[k].z));
    const Vec6 label = lieservo::replay::toReportUnits(rows[k].xi);
    for (std::size_t j = 0; j < 6; ++j) {
      const double e = std::fabs(est[k][j] - label[j]);
      mae[b][j] += e;
      mae[kBins][j] += e;
    }
    ++count[b];
    ++count[kBins];
  }
  for (std::size_t b = 0; b <= kBins; ++b)
    mae[b] = count[b] ? Vec6(mae[b] / double(count[b])) : Vec6::Constant(NAN);
  return mae;
}

BinMae unfilteredMae(const std::vector<Row>& rows) {
  std::vector<Vec6> est(rows.size());
  for (std::size_t k = 0; k < rows.size(); ++k) est[k] = lieservo::replay::toReportUnits(rows[k].mu);
  return binnedMae(rows, est);
}

// lieservo_replay's Table 2 experiment (replayFilter) on the rows, its MAE broken down by depth.
BinMae filterMae(const std::vector<Row>& rows, double sig, bool converged, int& failures) {
  std::vector<lieservo::replay::Sample> samples(rows.size());
  std::vector<ConcentratedGaussian<SE3d>> obs(rows.size());
  for (std::size_t k = 0; k < rows.size(); ++k) {
    samples[k].xi = rows[k].xi;
    if (lieservo::fromTangentGaussian(rows[k].mu, rows[k].sigma, obs[k]) != Status::ok)  // eq. 14 (eq:se3_inverse_transform)
      throw std::runtime_error("row " + std::to_string(k) + ": observation rejected");
  }
  lieservo::FusionOptions<double> fusion;  // the paper's fixed 5 iterations
  if (converged) {
    fusion.max_iterations = 50;
    fusion.tolerance = 1e-12;
  }
  const lieservo::replay::FilterRun run = lieservo::replay::replayFilter(samples, obs, sig, 1, fusion);
  failures = run.row.failures;
  return binnedMae(rows, run.mu);
}

}  // namespace

static int run(int argc, char** argv) {
  namespace cli = lieservo::cli;
  std::string path;
  std::vector<double> sigmas{10.0, 1.0, 0.1, 0.01};
  long synthetic_seed = -1;
  bool converged = false, expect_improvement = false;
  CLI::App app("lieservo_filter_diagnosis: the filter's MAE against the unfiltered GDN's on a dump of rows, binned by\n"
               "depth. FILE: 19 numbers per row (z mm; xi, mu, sigma in mm and rad), e.g. from\n"
               "examples/gdn/diagnose.py --dump FILE --dump-sigma {network,card,power}. Exit status: 0 ok,\n"
               "1 --expect-improvement not met, 2 bad usage or an unreadable file.",
               "lieservo_filter_diagnosis");
  app.add_option("FILE", path, "the rows")->required();
  app.add_option("--sigmas", sigmas, "process noise levels sigma_psi (mm and deg), comma-separated")
      ->delimiter(',')
      ->capture_default_str()
      ->check(cli::finiteIn(1e-6, 100));
  app.add_option("--synthetic", synthetic_seed, "replace mu by xi + sigma * N(0, 1) drawn with this seed")
      ->check(cli::integerIn<long>(0, std::numeric_limits<long>::max()));
  app.add_flag("--converged", converged, "fuse to convergence (tolerance 1e-12) instead of the paper's 5 iterations");
  app.add_flag("--expect-improvement", expect_improvement, "exit 1 unless the filter improves every component");
  if (const int status = cli::parse(app, argc, argv); status >= 0) return status;
  std::vector<Row> rows;
  try {
    rows = readRows(path);
  } catch (const std::exception& e) {
    std::cerr << "lieservo_filter_diagnosis: " << e.what() << "\n";
    return cli::kUsageOrSetup;
  }
  if (synthetic_seed >= 0) {
    lieservo::sampling::Rng g(static_cast<std::uint64_t>(synthetic_seed));
    for (Row& r : rows)
      for (int j = 0; j < 6; ++j) r.mu(j) = r.xi(j) + r.sigma(j) * lieservo::sampling::standardNormal(g);
  }

  const BinMae base = unfilteredMae(rows);
  const char* bin_name[kBins + 1] = {"z 0.5-1.5 mm", "z 1.5-3 mm", "z 3-6 mm", "all"};
  std::printf("%zu rows from %s%s; MAE ratio filtered / unfiltered (rho1 rho2 rho3 phi1 phi2 phi3)\n",
              rows.size(), path.c_str(), synthetic_seed >= 0 ? " (synthetic observations)" : "");
  std::printf("unfiltered MAE (mm, deg)\n");
  for (std::size_t b = 0; b <= kBins; ++b) {
    std::printf("  %-14s", bin_name[b]);
    for (double v : base[b]) std::printf(" %7.3f", v);
    std::printf("\n");
  }
  bool improved = true;
  int within = 0, cells = 0;
  for (std::size_t si = 0; si < sigmas.size(); ++si) {
    int failures = 0;
    const BinMae m = filterMae(rows, sigmas[si], converged, failures);
    std::printf("sigma_psi = %g (failed steps %d)\n", sigmas[si], failures);
    for (std::size_t b = 0; b <= kBins; ++b) {
      std::printf("  %-14s", bin_name[b]);
      for (std::size_t j = 0; j < 6; ++j) std::printf(" %7.3f", m[b][j] / base[b][j]);
      std::printf("\n");
    }
    // Beside the paper's Table 2 ratios, where it has this σψ.
    double paper = 0.0;
    if (lieservo::replay::paperFilterRatio(sigmas[si], 0, paper)) {
      std::printf("  %-14s", "vs paper (%)");
      for (std::size_t j = 0; j < 6; ++j) {
        lieservo::replay::paperFilterRatio(sigmas[si], j, paper);
        const double d = (m[kBins][j] / base[kBins][j]) / paper - 1.0;
        std::printf(" %+7.0f", 100.0 * d);
        within += std::fabs(d) <= lieservo::replay::kTable2Tolerance;
        ++cells;
      }
      std::printf("\n");
    }
    if (si + 1 == sigmas.size())
      for (std::size_t j = 0; j < 6; ++j) improved = improved && m[kBins][j] < base[kBins][j];
  }
  if (cells > 0) std::printf("%d of %d ratios within +-15 %% of the paper's\n", within, cells);
  if (expect_improvement && !improved) {
    std::fprintf(stderr, "--expect-improvement: the smallest sigma_psi did not lower every component's MAE\n");
    return cli::kCriteriaMissed;
  }
  return cli::kOk;
}

int main(int argc, char** argv) {
  return lieservo::cli::runProgram("lieservo_filter_diagnosis", [&] { return run(argc, argv); });
}

// The filter step on real observations (docs/performance.md, "The converged rule"): the paper's
// Table 2 experiment as the replay runs it (examples/replay) — the GDN's observations of the
// 2000 TacTip images of `val` in file order, motions T_k = exp(ψ_k^) X_k X_{k−1}⁻¹ (eq. 23,
// eqn:se3_filter_exp_state_trans_model) at each of the paper's σψ — one filter step per image
// (Algorithm 2, alg:se3_bayes_filter; the sensor poses X_k^sens are chained so that the step's
// T̄_k = (X_k^sens)⁻¹ X_{k−1}^sens is the experiment's T_k), with the paper's 5 fusion iterations
// and with the converged rule, beside one SE(3) exp in the same run. The counter `updates` is
// the fusion updates per correction. In builds with Ceres (lieservo::ceres), also the
// fixed-interval smoother over the whole sequence (lieservo_ceres/smoother.hpp, lesson 08), the
// same observations, motions and Σφ, with the derivatives from Jets and from the closed-form
// Jacobians: one iteration is one smooth() call (set-up and ceres::Solve, from the observations'
// means), and `lm_iterations` counts its Levenberg–Marquardt iterations.
//
//   lieservo_replay_bench [Google Benchmark flags]    (exit 77 without the data set or the GDN)
//
// The network's outputs are computed once at start-up (OpenCV dnn, a few seconds); the timed
// loop is the filter alone.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include <lieservo/lieservo.hpp>

#ifdef LIESERVO_BENCH_SMOOTHER
#include <lieservo_ceres/smoother.hpp>
#endif

#include "bench_common.hpp"
#include "replay.hpp"
#include "bench_main.hpp"

namespace {

using namespace lieservo;
namespace rp = lieservo::replay;

constexpr double kSigmaPsi[4] = {10.0, 1.0, 0.1, 0.01};  // the paper's Table 2 columns (mm and deg)

struct Sequence {
  std::vector<ConcentratedGaussian<SE3d>> observations;
  std::vector<SE3d> motions[4];  // T_k per σψ (eq. 23)
  std::vector<SE3d> sensor[4];   // X_k^sens per σψ
};

Sequence& sequence() {
  static Sequence s;
  return s;
}

void setUp() {
  rp::ReplayOptions o;
  o.data_dir = LIESERVO_DATA_DIR;
  o.models_dir = std::string(LIESERVO_SOURCE_DIR) + "/examples/gdn/models";
  o.run_cnn = false;
  o.verbose = false;
  o.sigma_psi.clear();  // the observations only: the filter runs are the benchmark's
  const rp::ReplayResults r = rp::runReplay(o);
  Sequence& s = sequence();
  s.observations = r.observations;
  for (int i = 0; i < 4; ++i) {
    const std::vector<SE3d>& T = s.motions[i] = rp::replayMotions(r.samples, kSigmaPsi[i], o.seed);
    s.sensor[i].assign(T.size(), SE3d());
    for (std::size_t k = 1; k < T.size(); ++k) s.sensor[i][k] = s.sensor[i][k - 1] * T[k].inverse();
  }
}

template <bool Converged>
void BM_ReplayFilterStep(benchmark::State& state) {
  const Sequence& s = sequence();
  const int level = static_cast<int>(state.range(0));
  const std::vector<SE3d>& sensor = s.sensor[level];
  const std::size_t n = s.observations.size();
  DiscriminativeBayesFilter<SE3d>::Options o;
  o.process_noise = rp::replayProcessNoise(kSigmaPsi[level]);
  o.fusion = Converged ? FusionOptions<double>::converged() : FusionOptions<double>::paper();
  DiscriminativeBayesFilter<SE3d> filter(o);
  (void)filter.step(sensor[0], s.observations[0]);  // the first image initialises
  std::size_t k = 1;
  long updates = 0, corrections = 0;
  for (auto _ : state) {
    const Status st = filter.step(sensor[k], s.observations[k]);
    benchmark::DoNotOptimize(st);
    if (st == Status::ok) {
      updates += filter.diagnostics().iterations;
      ++corrections;
    }
    if (++k == n) {  // the sequence again from its first image
      filter.reset();
      (void)filter.step(sensor[0], s.observations[0]);
      k = 1;
    }
  }
  state.counters["updates"] = corrections > 0 ? double(updates) / double(corrections) : 0.0;
  char label[32];
  std::snprintf(label, sizeof label, "sigma_psi %g", kSigmaPsi[level]);
  state.SetLabel(label);
}
BENCHMARK_TEMPLATE(BM_ReplayFilterStep, false)->DenseRange(0, 3);
BENCHMARK_TEMPLATE(BM_ReplayFilterStep, true)->DenseRange(0, 3);

#ifdef LIESERVO_BENCH_SMOOTHER
// The whole sequence at once (docs/estimation.md, "The smoother"): min over the trajectory of the
// whitened observation residuals (eq. 14) and motion residuals (eqs. 23–24), through lieservo's log.
template <lieservo::ceres_adapter::SmootherOptions::Jacobians Kind>
void BM_ReplaySmoother(benchmark::State& state) {
  namespace sm = lieservo::ceres_adapter;
  const Sequence& s = sequence();
  const int level = static_cast<int>(state.range(0));
  const SE3d::Jacobian Q = rp::replayProcessNoise(kSigmaPsi[level]);
  sm::SmootherOptions o;
  o.jacobians = Kind;
  std::vector<SE3d> poses;
  long lm_iterations = 0, solves = 0;
  for (auto _ : state) {
    const sm::SmootherReport r = sm::smooth(s.observations, s.motions[level], Q, poses, o);
    if (r.status != Status::ok) {
      state.SkipWithError(r.message.c_str());
      return;
    }
    lm_iterations += r.iterations;
    ++solves;
    benchmark::DoNotOptimize(poses.data());
  }
  state.counters["lm_iterations"] = solves > 0 ? double(lm_iterations) / double(solves) : 0.0;
  char label[32];
  std::snprintf(label, sizeof label, "sigma_psi %g", kSigmaPsi[level]);
  state.SetLabel(label);
}
BENCHMARK_TEMPLATE(BM_ReplaySmoother, lieservo::ceres_adapter::SmootherOptions::Jacobians::autodiff)
    ->DenseRange(0, 3)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_ReplaySmoother, lieservo::ceres_adapter::SmootherOptions::Jacobians::closed_form)
    ->DenseRange(0, 3)
    ->Unit(benchmark::kMillisecond);
#endif

// The unit of the filter's cost, timed as lieservo_bench times it.
void BM_exp_SE3(benchmark::State& state) {
  const auto& in = lieservo_bench::GroupInputs<SE3d>::get();
  std::size_t i = 0;
  for (auto _ : state) {
    auto r = SE3d::exp(in.xi[i]);
    benchmark::DoNotOptimize(r);
    i = (i + 1) & (lieservo_bench::kRing - 1);
  }
}
BENCHMARK(BM_exp_SE3);

}  // namespace

int main(int argc, char** argv) {
  return lieservo::bench::runBenchmarks(argc, argv, "the filter step on the real-data replay's sequence, the paper's 5 iterations and the converged rule; with Ceres, the fixed-interval smoother over it, with Jets and with the closed-form Jacobians", [] {
    try {
      setUp();
    } catch (const std::exception& e) {
      std::printf("lieservo_replay_bench: SKIPPED: %s\n", e.what());
      return int(lieservo::cli::kSkipped);
    }
    if (sequence().observations.size() < 2) {
      std::printf("lieservo_replay_bench: SKIPPED: fewer than two images\n");
      return int(lieservo::cli::kSkipped);
    }
    benchmark::AddCustomContext("replay_sequence", "val, " + std::to_string(sequence().observations.size()) +
                                                       " images, the GDN of examples/gdn/models (network sigma)");
    return -1;
  });
}

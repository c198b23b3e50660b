// benchmarks/bench_estimation.cpp — estimation and control: two-factor fusion
// (Algorithm 3, alg:se3_data_fusion) with 1–10 iterations under each Jacobian policy, one full filter step
// (Algorithm 2, alg:se3_bayes_filter: predict + correct, 5 fusion iterations; information (the
// default) and square-root form; with 1–5 iterations; and with the converged rule), one controller step
// (TactileServoController, PushingController) and the whole estimate-and-control cycle
// (fromTangentGaussian + filter step + servo step), SE(3), float and double.
#include <benchmark/benchmark.h>

#include <lieservo/control.hpp>

#include "bench_common.hpp"

namespace {

using lieservo_bench::FilterInputs;
using lieservo_bench::FilterSequence;
using lieservo_bench::kRing;

// ---- fusion: argument = number of fixed iterations (tolerance 0: real-time mode) ------------
template <class Policy, class G, lieservo::FusionForm Form = lieservo::FusionForm::information>
void BM_fuse(benchmark::State& state) {
  const auto& in = FilterInputs<G>::get();
  lieservo::FusionOptions<typename G::Scalar> opt;
  opt.max_iterations = static_cast<int>(state.range(0));
  opt.form = Form;
  lieservo::FusionResult<G> r;
  std::size_t i = 0;
  for (auto _ : state) {
    const auto s = lieservo::fuse<Policy>(in.obs[i], in.obs[(i + 1) & (kRing - 1)], opt, r);
    benchmark::DoNotOptimize(s);
    benchmark::DoNotOptimize(r);
    i = (i + 1) & (kRing - 1);
  }
}

#define LIESERVO_FUSE_BENCHMARKS(G)                                                        \
  BENCHMARK_TEMPLATE(BM_fuse, lieservo::SeriesJacobian<1>, G)->DenseRange(1, 10);          \
  BENCHMARK_TEMPLATE(BM_fuse, lieservo::SeriesJacobian<2>, G)->DenseRange(1, 10);          \
  BENCHMARK_TEMPLATE(BM_fuse, lieservo::SeriesJacobian<3>, G)->DenseRange(1, 10);          \
  BENCHMARK_TEMPLATE(BM_fuse, lieservo::SeriesJacobian<4>, G)->DenseRange(1, 10);          \
  BENCHMARK_TEMPLATE(BM_fuse, lieservo::ClosedFormJacobian, G)->DenseRange(1, 10)

LIESERVO_FUSE_BENCHMARKS(lieservo::SE3<double>);
LIESERVO_FUSE_BENCHMARKS(lieservo::SE3<float>);
// The square-root form (FusionForm::square_root), paper policy.
BENCHMARK_TEMPLATE(BM_fuse, lieservo::SeriesJacobian<2>, lieservo::SE3<double>, lieservo::FusionForm::square_root)
    ->DenseRange(1, 10);

// ---- one filter step: predict + correct (5 iterations, the paper's settings) ---------------
template <class G, class Policy, template <class> class Inputs = FilterInputs>
void runFilterSteps(benchmark::State& state,
                    const typename lieservo::DiscriminativeBayesFilter<G, Policy>::Options& options) {
  const auto& in = Inputs<G>::get();
  lieservo::DiscriminativeBayesFilter<G, Policy> filter(options);
  filter.reset();
  (void)filter.step(in.sensor[0], in.obs[0]);  // initialisation
  std::size_t i = 1;
  for (auto _ : state) {
    const auto s = filter.step(in.sensor[i], in.obs[i]);
    benchmark::DoNotOptimize(s);
    i = (i + 1) & (kRing - 1);
    if (i == 0) {  // keep the run stationary: restart the trajectory
      state.PauseTiming();
      filter.reset();
      (void)filter.step(in.sensor[0], in.obs[0]);  // initialisation
      i = 1;
      state.ResumeTiming();
    }
  }
}

template <class G, class Policy, lieservo::FusionForm Form = lieservo::FusionForm::information>
void BM_FilterStep(benchmark::State& state) {
  typename lieservo::DiscriminativeBayesFilter<G, Policy>::Options options;
  options.fusion.form = Form;
  runFilterSteps<G, Policy>(state, options);
}
BENCHMARK_TEMPLATE(BM_FilterStep, lieservo::SE3<double>, lieservo::PaperJacobian);
BENCHMARK_TEMPLATE(BM_FilterStep, lieservo::SE3<double>, lieservo::ClosedFormJacobian);
BENCHMARK_TEMPLATE(BM_FilterStep, lieservo::SE3<double>, lieservo::PaperJacobian, lieservo::FusionForm::square_root);
BENCHMARK_TEMPLATE(BM_FilterStep, lieservo::SE3<float>, lieservo::PaperJacobian);
BENCHMARK_TEMPLATE(BM_FilterStep, lieservo::SE3<float>, lieservo::ClosedFormJacobian);

// The same step with 1–5 fusion iterations (argument; the paper runs 5): what fewer iterations
// buy, for a loop that cannot afford the paper's.
template <class G, class Policy>
void BM_FilterIterations(benchmark::State& state) {
  typename lieservo::DiscriminativeBayesFilter<G, Policy>::Options options;
  options.fusion.max_iterations = static_cast<int>(state.range(0));
  runFilterSteps<G, Policy>(state, options);
}
BENCHMARK_TEMPLATE(BM_FilterIterations, lieservo::SE3<double>, lieservo::PaperJacobian)->DenseRange(1, 5);
BENCHMARK_TEMPLATE(BM_FilterIterations, lieservo::SE3<double>, lieservo::ClosedFormJacobian)->DenseRange(1, 5);

// The same step with the converged rule (FusionOptions::converged(): stop once an update is
// under 0.001 standard deviations, at most 5); the counter is the mean number of iterations.
// On FilterSequence (observations as the filter's model expects them, bench_common.hpp), and
// on FilterInputs, whose observations jump by up to 15° against a σ of 0.5–2°.
template <class G, class Policy, template <class> class Inputs = FilterSequence>
void BM_FilterStepConverged(benchmark::State& state) {
  typename lieservo::DiscriminativeBayesFilter<G, Policy>::Options options;
  options.fusion = lieservo::FusionOptions<typename G::Scalar>::converged();
  runFilterSteps<G, Policy, Inputs>(state, options);
  // The iterations of the same inputs, counted outside the timed loop.
  const auto& in = Inputs<G>::get();
  lieservo::DiscriminativeBayesFilter<G, Policy> filter(options);
  (void)filter.step(in.sensor[0], in.obs[0]);
  double sum = 0;
  for (std::size_t i = 1; i < kRing; ++i) {
    (void)filter.step(in.sensor[i], in.obs[i]);
    sum += filter.diagnostics().iterations;
  }
  state.counters["iterations"] = sum / double(kRing - 1);
}
BENCHMARK_TEMPLATE(BM_FilterStepConverged, lieservo::SE3<double>, lieservo::PaperJacobian);
BENCHMARK_TEMPLATE(BM_FilterStepConverged, lieservo::SE3<double>, lieservo::ClosedFormJacobian);
BENCHMARK_TEMPLATE(BM_FilterStepConverged, lieservo::SE3<float>, lieservo::PaperJacobian);
BENCHMARK_TEMPLATE(BM_FilterStepConverged, lieservo::SE3<double>, lieservo::PaperJacobian, FilterInputs);

// ---- one controller step ----------------------------------------------------------------------
template <class Scalar>
void BM_ServoStep(benchmark::State& state) {
  using G = lieservo::SE3<Scalar>;
  const auto& in = FilterInputs<G>::get();
  lieservo::TactileServoController<G> servo(lieservo::objectTrackingPreset<Scalar>());
  typename G::Tangent u;
  const Scalar dt = Scalar(0.05);
  std::size_t i = 0;
  for (auto _ : state) {
    const auto s = servo.step(in.obs[i].mean, dt, u);
    benchmark::DoNotOptimize(s);
    benchmark::DoNotOptimize(u);
    i = (i + 1) & (kRing - 1);
  }
}
BENCHMARK_TEMPLATE(BM_ServoStep, double);
BENCHMARK_TEMPLATE(BM_ServoStep, float);

template <class Scalar>
void BM_PushingStep(benchmark::State& state) {
  using G = lieservo::SE3<Scalar>;
  const auto& in = FilterInputs<G>::get();
  auto opt = lieservo::pushingPreset<Scalar>();
  typename G::Vector3 target(Scalar(0), Scalar(0), Scalar(375));  // the paper's target: far away
  opt.target = G(typename G::SO3Type(), target);
  lieservo::PushingController<lieservo::SE3<Scalar>> push(opt);
  typename G::Tangent u;
  const Scalar dt = Scalar(0.05);
  std::size_t i = 0;
  for (auto _ : state) {
    const auto s = push.step(in.obs[i].mean, in.sensor[i], dt, u);
    benchmark::DoNotOptimize(s);
    benchmark::DoNotOptimize(u);
    i = (i + 1) & (kRing - 1);
  }
  if (push.terminated()) state.SkipWithError("pushing controller terminated: benchmark invalid");
}
BENCHMARK_TEMPLATE(BM_PushingStep, double);
BENCHMARK_TEMPLATE(BM_PushingStep, float);

// ---- the whole estimate-and-control cycle -------------------------------------------------------
// GDN output (μ, σ) → fromTangentGaussian → TactileLoop::step (the filter step, then the servo
// step on the filtered pose, as the robot programs run them).
template <class Scalar, class Policy>
void BM_Cycle(benchmark::State& state) {
  using G = lieservo::SE3<Scalar>;
  using Loop = lieservo::TactileLoop<lieservo::TactileServoController<G>, lieservo::DiscriminativeBayesFilter<G, Policy>>;
  const auto& in = FilterInputs<G>::get();
  typename Loop::Options options;
  options.controller = lieservo::objectTrackingPreset<Scalar>();
  Loop loop(options);
  typename G::Tangent u;
  const Scalar dt = Scalar(0.05);
  (void)loop.step(in.sensor[0], in.obs[0], dt, u);  // initialisation
  std::size_t i = 1;
  for (auto _ : state) {
    lieservo::ConcentratedGaussian<G> obs;
    auto s = lieservo::fromTangentGaussian(in.mu[i], in.sigma[i], obs);
    if (s == lieservo::Status::ok) s = loop.step(in.sensor[i], obs, dt, u);
    benchmark::DoNotOptimize(s);
    benchmark::DoNotOptimize(u);
    i = (i + 1) & (kRing - 1);
    if (i == 0) {
      state.PauseTiming();
      loop.reset();
      (void)loop.step(in.sensor[0], in.obs[0], dt, u);  // initialisation
      i = 1;
      state.ResumeTiming();
    }
  }
}
BENCHMARK_TEMPLATE(BM_Cycle, double, lieservo::PaperJacobian);
BENCHMARK_TEMPLATE(BM_Cycle, double, lieservo::ClosedFormJacobian);
BENCHMARK_TEMPLATE(BM_Cycle, float, lieservo::PaperJacobian);

}  // namespace

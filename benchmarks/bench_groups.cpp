// benchmarks/bench_groups.cpp — the group core: exp, log, Ad, ad, left Jacobian and its
// inverse (closed form and Bernoulli series of order 1–4), the combined exp-and-Jacobian /
// log-and-inverse-Jacobian kernels, compose, inverse and act, for SO(3) and SE(3), float and
// double. Names read BM_<op><SO3<double>> etc.; the label column gives nothing extra.
#include <benchmark/benchmark.h>

#include "bench_common.hpp"

namespace {

using lieservo_bench::GroupInputs;
using lieservo_bench::kRing;

#define LIESERVO_RING_LOOP(expr)                 \
  const auto& in = GroupInputs<G>::get();        \
  std::size_t i = 0;                             \
  for (auto _ : state) {                         \
    auto r = expr;                               \
    benchmark::DoNotOptimize(r);                 \
    i = (i + 1) & (kRing - 1);                   \
  }

template <class G>
void BM_exp(benchmark::State& state) { LIESERVO_RING_LOOP(G::exp(in.xi[i])) }
template <class G>
void BM_log(benchmark::State& state) { LIESERVO_RING_LOOP(in.X[i].log()) }
template <class G>
void BM_Ad(benchmark::State& state) { LIESERVO_RING_LOOP(in.X[i].Ad()) }
template <class G>
void BM_ad(benchmark::State& state) { LIESERVO_RING_LOOP(G::ad(in.xi[i])) }
template <class G>
void BM_leftJacobian(benchmark::State& state) { LIESERVO_RING_LOOP(G::leftJacobian(in.xi[i])) }
template <class G>
void BM_leftJacobianInverse(benchmark::State& state) { LIESERVO_RING_LOOP(G::leftJacobianInverse(in.xi[i])) }
template <class G, int N>
void BM_leftJacobianSeries(benchmark::State& state) {
  LIESERVO_RING_LOOP(lieservo::SeriesJacobian<N>::template forward<G>(in.xi[i]))
}
template <class G, int N>
void BM_leftJacobianInverseSeries(benchmark::State& state) {
  LIESERVO_RING_LOOP(G::template leftJacobianInverseSeries<N>(in.xi[i]))
}
template <class G>
void BM_expAndLeftJacobian(benchmark::State& state) {
  typename G::Jacobian J;
  LIESERVO_RING_LOOP(G::expAndLeftJacobian(in.xi[i], J));
  benchmark::DoNotOptimize(J);
}
template <class G>
void BM_logAndLeftJacobianInverse(benchmark::State& state) {
  typename G::Jacobian J;
  LIESERVO_RING_LOOP(in.X[i].logAndLeftJacobianInverse(J));
  benchmark::DoNotOptimize(J);
}
template <class G>
void BM_compose(benchmark::State& state) { LIESERVO_RING_LOOP(in.X[i] * in.Y[i]) }
template <class G>
void BM_inverse(benchmark::State& state) { LIESERVO_RING_LOOP(in.X[i].inverse()) }
template <class G>
void BM_act(benchmark::State& state) { LIESERVO_RING_LOOP(typename G::Point(in.X[i] * in.p[i])) }

#define LIESERVO_GROUP_BENCHMARKS(G)                        \
  BENCHMARK_TEMPLATE(BM_exp, G);                            \
  BENCHMARK_TEMPLATE(BM_log, G);                            \
  BENCHMARK_TEMPLATE(BM_Ad, G);                             \
  BENCHMARK_TEMPLATE(BM_ad, G);                             \
  BENCHMARK_TEMPLATE(BM_leftJacobian, G);                   \
  BENCHMARK_TEMPLATE(BM_leftJacobianInverse, G);            \
  BENCHMARK_TEMPLATE(BM_leftJacobianSeries, G, 1);          \
  BENCHMARK_TEMPLATE(BM_leftJacobianSeries, G, 2);          \
  BENCHMARK_TEMPLATE(BM_leftJacobianSeries, G, 3);          \
  BENCHMARK_TEMPLATE(BM_leftJacobianSeries, G, 4);          \
  BENCHMARK_TEMPLATE(BM_leftJacobianInverseSeries, G, 1);   \
  BENCHMARK_TEMPLATE(BM_leftJacobianInverseSeries, G, 2);   \
  BENCHMARK_TEMPLATE(BM_leftJacobianInverseSeries, G, 3);   \
  BENCHMARK_TEMPLATE(BM_leftJacobianInverseSeries, G, 4);   \
  BENCHMARK_TEMPLATE(BM_expAndLeftJacobian, G);             \
  BENCHMARK_TEMPLATE(BM_logAndLeftJacobianInverse, G);      \
  BENCHMARK_TEMPLATE(BM_compose, G);                        \
  BENCHMARK_TEMPLATE(BM_inverse, G);                        \
  BENCHMARK_TEMPLATE(BM_act, G)

using lieservo::SE3;
using lieservo::SO3;
LIESERVO_GROUP_BENCHMARKS(SO3<float>);
LIESERVO_GROUP_BENCHMARKS(SO3<double>);
LIESERVO_GROUP_BENCHMARKS(SE3<float>);
LIESERVO_GROUP_BENCHMARKS(SE3<double>);

}  // namespace

// benchmarks/bench_sophus.cpp — OPTIONAL side-by-side comparison with Sophus (built only with
// -DLIESERVO_SOPHUS_DIR=/path/to/Sophus; Sophus is not part of this repository).
//
// 1. Accuracy (printed first): the SO(3) left-Jacobian coefficients B = (1 − cosθ)/θ²,
//    C = (θ − sinθ)/θ³ and the inverse-Jacobian coefficient D = (1 − (θ/2)cot(θ/2))/θ², read
//    back exactly from each library's 3×3 matrices (φ = (a, a, 0): J(2,1) = B a, J(0,1) = C a²,
//    J⁻¹(0,1) = D a²), against an independent long-double Taylor series, for θ ∈ [1e-9, 1e-3].
// 2. Speed: SE(3) double exp, log, Ad, left Jacobian and its inverse, compose, inverse, act —
//    ours and Sophus's on the same inputs, in the same run (names BM_<op>/lieservo|sophus).
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>

#include <sophus/se3.hpp>

#include "bench_common.hpp"

namespace {

using lieservo_bench::kRing;
using G = lieservo::SE3<double>;

// ---- accuracy -------------------------------------------------------------------------------
long double refB(long double x) {  // Σ (−1)^k x^k/(2k+2)!
  long double s = 0, t = 0.5L;
  for (int k = 0; k < 12; ++k) {
    s += t;
    t *= -x / ((2 * k + 3) * (2 * k + 4));
  }
  return s;
}
long double refC(long double x) {  // Σ (−1)^k x^k/(2k+3)!
  long double s = 0, t = 1.0L / 6;
  for (int k = 0; k < 12; ++k) {
    s += t;
    t *= -x / ((2 * k + 4) * (2 * k + 5));
  }
  return s;
}
long double refD(long double x) {  // 1/12 + x/720 + x²/30240 + x³/1209600 (x ≤ 1e-6: plenty)
  return 1.0L / 12 + x / 720 + x * x / 30240 + x * x * x / 1209600;
}

void accuracyReport() {
  double worst[2][3] = {{0, 0, 0}, {0, 0, 0}};  // [lib][B, C, D]
  for (int i = 0; i <= 120; ++i) {
    const double theta = std::pow(10.0, -9.0 + 6.0 * i / 120.0);
    const double a = theta / std::sqrt(2.0);
    const long double x = 2.0L * (long double)a * (long double)a;
    const long double rb = refB(x), rc = refC(x), rd = refD(x);
    const Eigen::Vector3d phi(a, a, 0);
    const Eigen::Matrix3d J0 = lieservo::SO3<double>::leftJacobian(phi);
    const Eigen::Matrix3d Ji0 = lieservo::SO3<double>::leftJacobianInverse(phi);
    const Eigen::Matrix3d J1 = Sophus::SO3<double>::leftJacobian(phi);
    const Eigen::Matrix3d Ji1 = Sophus::SO3<double>::leftJacobianInverse(phi);
    const Eigen::Matrix3d* Js[2] = {&J0, &J1};
    const Eigen::Matrix3d* Jis[2] = {&Ji0, &Ji1};
    for (int l = 0; l < 2; ++l) {
      const long double B = (long double)(*Js[l])(2, 1) / a;
      const long double C = (long double)(*Js[l])(0, 1) / ((long double)a * a);
      const long double D = (long double)(*Jis[l])(0, 1) / ((long double)a * a);
      worst[l][0] = std::max(worst[l][0], double(std::fabs(B - rb) / rb));
      worst[l][1] = std::max(worst[l][1], double(std::fabs(C - rc) / rc));
      worst[l][2] = std::max(worst[l][2], double(std::fabs(D - rd) / rd));
    }
  }
  std::printf("SO(3) Jacobian coefficients, max relative error for theta in [1e-9, 1e-3] (121 points, double):\n");
  std::printf("  coefficient                      lieservo     Sophus\n");
  std::printf("  B = (1-cos t)/t^2      (J)       %.2e     %.2e\n", worst[0][0], worst[1][0]);
  std::printf("  C = (t-sin t)/t^3      (J)       %.2e     %.2e\n", worst[0][1], worst[1][1]);
  std::printf("  D = (1-(t/2)cot(t/2))/t^2 (J^-1) %.2e     %.2e\n\n", worst[0][2], worst[1][2]);
}

// ---- speed ----------------------------------------------------------------------------------
struct Inputs {
  G::Tangent xi[kRing];
  G X[kRing], Y[kRing];
  Sophus::SE3d sX[kRing], sY[kRing];
  Eigen::Vector3d p[kRing];
  Inputs() {
    const auto& in = lieservo_bench::GroupInputs<G>::get();
    for (std::size_t i = 0; i < kRing; ++i) {
      xi[i] = in.xi[i];
      X[i] = in.X[i];
      Y[i] = in.Y[i];
      p[i] = in.p[i];
      sX[i] = Sophus::SE3d(Sophus::SO3d(X[i].rotationMatrix()), X[i].translation());
      sY[i] = Sophus::SE3d(Sophus::SO3d(Y[i].rotationMatrix()), Y[i].translation());
    }
  }
  static const Inputs& get() {
    static const Inputs in;
    return in;
  }
};

#define LIESERVO_SIDE_BY_SIDE(name, ours, theirs)                \
  void BM_##name##_lieservo(benchmark::State& state) {            \
    const auto& in = Inputs::get();                               \
    std::size_t i = 0;                                            \
    for (auto _ : state) {                                        \
      auto r = ours;                                              \
      benchmark::DoNotOptimize(r);                                \
      i = (i + 1) & (kRing - 1);                                  \
    }                                                             \
  }                                                               \
  void BM_##name##_sophus(benchmark::State& state) {              \
    const auto& in = Inputs::get();                               \
    std::size_t i = 0;                                            \
    for (auto _ : state) {                                        \
      auto r = theirs;                                            \
      benchmark::DoNotOptimize(r);                                \
      i = (i + 1) & (kRing - 1);                                  \
    }                                                             \
  }                                                               \
  BENCHMARK(BM_##name##_lieservo);                                \
  BENCHMARK(BM_##name##_sophus)

LIESERVO_SIDE_BY_SIDE(SE3d_exp, G::exp(in.xi[i]), Sophus::SE3d::exp(in.xi[i]));
LIESERVO_SIDE_BY_SIDE(SE3d_log, in.X[i].log(), in.sX[i].log());
LIESERVO_SIDE_BY_SIDE(SE3d_leftJacobian, G::leftJacobian(in.xi[i]), Sophus::SE3d::leftJacobian(in.xi[i]));
LIESERVO_SIDE_BY_SIDE(SE3d_leftJacobianInverse, G::leftJacobianInverse(in.xi[i]),
                      Sophus::SE3d::leftJacobianInverse(in.xi[i]));
LIESERVO_SIDE_BY_SIDE(SE3d_Ad, in.X[i].Ad(), in.sX[i].Adj());
LIESERVO_SIDE_BY_SIDE(SE3d_compose, in.X[i] * in.Y[i], in.sX[i] * in.sY[i]);
LIESERVO_SIDE_BY_SIDE(SE3d_inverse, in.X[i].inverse(), in.sX[i].inverse());
LIESERVO_SIDE_BY_SIDE(SE3d_act, Eigen::Vector3d(in.X[i] * in.p[i]), Eigen::Vector3d(in.sX[i] * in.p[i]));
LIESERVO_SIDE_BY_SIDE(SO3d_exp, lieservo::SO3<double>::exp(in.xi[i].tail<3>()),
                      Sophus::SO3d::exp(in.xi[i].tail<3>()));
LIESERVO_SIDE_BY_SIDE(SO3d_log, in.X[i].so3().log(), in.sX[i].so3().log());

}  // namespace

int main(int argc, char** argv) {
  accuracyReport();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

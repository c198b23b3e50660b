// benchmarks/bench_peers.cpp — OPTIONAL side-by-side comparison with Sophus and manif, built
// only when at least one of them is given (-DLIESERVO_SOPHUS_DIR=<Sophus checkout>,
// -DLIESERVO_MANIF_DIR=<manif checkout>); neither is part of this repository.
//
// 1. Accuracy (printed first): the SO(3) left-Jacobian coefficients B = (1 − cosθ)/θ²,
//    C = (θ − sinθ)/θ³ and the inverse-Jacobian coefficient D = (1 − (θ/2)cot(θ/2))/θ², read
//    back exactly from each library's 3×3 matrices (φ = (a, a, 0): J(2,1) = B a, J(0,1) = C a²,
//    J⁻¹(0,1) = D a²), against an independent long-double Taylor series, for θ ∈ [1e-9, 1e-3];
//    and the angle of the SO(3) log in float for θ ∈ [1e-4, 1e-2], in ulps.
// 2. Speed, every library on the same inputs in the same run (names <op>/<library>):
//    SE(3) exp, log, Ad, left Jacobian and its inverse, compose, inverse, act; SO(3) exp and
//    log; double and float. The tangents have angles up to 1 rad; SO(3) exp is also timed on
//    angles between a quarter and a half turn (exp_large), and SO(3) exp and log on three angle
//    sets (exp_<set>, log_<set>): uniform over [0, π) (full), small (θ = 10^u, u uniform in
//    [−8, −2]) and near a half turn (θ = π − 10^u).
//    The peers store a unit quaternion and lieservo a rotation matrix, so SO(3) is timed
//    twice for the peers: in their own representation (exp returns a quaternion, log starts
//    from one) and as a matrix (exp followed by the conversion to a matrix, log preceded by the
//    conversion from one), which is what lieservo's calls do.
#include <benchmark/benchmark.h>

#include <cfloat>
#include <cmath>
#include <cstdio>
#include <string>

#include "bench_common.hpp"

#ifdef LIESERVO_HAVE_SOPHUS
#include <sophus/se3.hpp>
#endif
#ifdef LIESERVO_HAVE_MANIF
#include <manif/SE3.h>
#include <manif/SO3.h>
#include "bench_main.hpp"
#endif

namespace {

using lieservo_bench::kRing;

// The SO(3) angle sets: uniform over [0, π), small, and near π (see the file comment).
enum AngleSet { kFull, kSmall, kNearPi, kSets };
const char* const kSetName[kSets] = {"full", "small", "near_pi"};
double angleOf(AngleSet set, lieservo::sampling::Rng& rng) {
  const double pi = lieservo::pi<double>();
  if (set == kFull) return lieservo_bench::uniform(rng, 0.0, 1.0) * pi;
  const double tiny = std::pow(10.0, lieservo_bench::uniform(rng, -8.0, -2.0));
  return set == kSmall ? tiny : pi - tiny;
}

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

// The worst relative error of B, C, D over the angle grid for one library's J and J⁻¹.
template <class JacobianFn, class InverseFn>
void coefficientErrors(const char* library, JacobianFn J_of, InverseFn Jinv_of) {
  double worst[3] = {0, 0, 0};
  for (int i = 0; i <= 120; ++i) {
    const double theta = std::pow(10.0, -9.0 + 6.0 * i / 120.0);
    const double a = theta / std::sqrt(2.0);
    const long double x = 2.0L * (long double)a * (long double)a;
    const Eigen::Vector3d phi(a, a, 0);
    const Eigen::Matrix3d J = J_of(phi), Ji = Jinv_of(phi);
    const long double B = (long double)J(2, 1) / a;
    const long double C = (long double)J(0, 1) / ((long double)a * a);
    const long double D = (long double)Ji(0, 1) / ((long double)a * a);
    worst[0] = std::max(worst[0], double(std::fabs(B - refB(x)) / refB(x)));
    worst[1] = std::max(worst[1], double(std::fabs(C - refC(x)) / refC(x)));
    worst[2] = std::max(worst[2], double(std::fabs(D - refD(x)) / refD(x)));
  }
  std::printf("  %-10s  B %.2e   C %.2e   D %.2e\n", library, worst[0], worst[1], worst[2]);
}

// The worst error of the SO(3) log's angle in float for θ ∈ [1e-4, 1e-2] (201 log-spaced points
// about (0.6, 0.8, 0)), in float ulps of the angle; each library's reference is the angle of its
// own float input (lieservo: the matrix, in long double; the peers: the quaternion).
template <class Angle>
void smallLogError(const char* library, Angle angle_and_reference) {
  double worst = 0;
  for (int i = 0; i <= 200; ++i) {
    const double theta = std::pow(10.0, -4.0 + 2.0 * i / 200.0);
    long double reference = 0;
    const long double angle = angle_and_reference(theta, reference);
    worst = std::max(worst, double(std::fabs(angle - reference) / reference) / double(FLT_EPSILON));
  }
  std::printf("  %-10s  %.1f ulp\n", library, worst);
}

void accuracyReport() {
  std::printf("SO(3) Jacobian coefficients, max relative error for theta in [1e-9, 1e-3] (121 points, double):\n");
  std::printf("  B = (1-cos t)/t^2 (J), C = (t-sin t)/t^3 (J), D = (1-(t/2)cot(t/2))/t^2 (J^-1)\n");
  using S3 = lieservo::SO3<double>;
  coefficientErrors("lieservo", [](const Eigen::Vector3d& p) { return S3::leftJacobian(p); },
                    [](const Eigen::Vector3d& p) { return S3::leftJacobianInverse(p); });
#ifdef LIESERVO_HAVE_SOPHUS
  coefficientErrors("Sophus", [](const Eigen::Vector3d& p) { return Sophus::SO3d::leftJacobian(p); },
                    [](const Eigen::Vector3d& p) { return Sophus::SO3d::leftJacobianInverse(p); });
#endif
#ifdef LIESERVO_HAVE_MANIF
  coefficientErrors("manif", [](const Eigen::Vector3d& p) { return manif::SO3Tangentd(p).ljac(); },
                    [](const Eigen::Vector3d& p) { return manif::SO3Tangentd(p).ljacinv(); });
#endif
  std::printf("\n");
  std::printf("SO(3) log in float, theta in [1e-4, 1e-2] (201 points): worst error of the angle\n");
  const Eigen::Vector3f axis(0.6f, 0.8f, 0.f);
  smallLogError("lieservo", [&](double t, long double& ref) {
    const Eigen::Matrix3f C = Eigen::AngleAxisf(float(t), axis).toRotationMatrix();
    ref = lieservo::SO3<long double>::fromMatrixUnchecked(C.cast<long double>()).log().norm();
    return (long double)lieservo::SO3f::fromMatrixUnchecked(C).log().norm();
  });
  const auto quaternionAngle = [](const Eigen::Quaternionf& q) {
    const long double n = std::sqrt((long double)q.x() * q.x() + (long double)q.y() * q.y() + (long double)q.z() * q.z());
    return 2 * std::atan2(n, (long double)q.w());
  };
  (void)quaternionAngle;  // unused without a peer
#ifdef LIESERVO_HAVE_SOPHUS
  smallLogError("Sophus", [&](double t, long double& ref) {
    const Eigen::Quaternionf q = Eigen::Quaternionf(Eigen::AngleAxisf(float(t), axis)).normalized();
    ref = quaternionAngle(q);
    return (long double)Sophus::SO3f(q).log().norm();
  });
#endif
#ifdef LIESERVO_HAVE_MANIF
  smallLogError("manif", [&](double t, long double& ref) {
    const Eigen::Quaternionf q = Eigen::Quaternionf(Eigen::AngleAxisf(float(t), axis)).normalized();
    ref = quaternionAngle(q);
    return (long double)manif::SO3f(q).log().coeffs().norm();
  });
#endif
}

// ---- speed ----------------------------------------------------------------------------------
// The same seeded elements (bench_common.hpp) in each library's own type.
template <class S>
struct Inputs {
  using G = lieservo::SE3<S>;
  using Quat = Eigen::Quaternion<S>;
  typename G::Tangent xi[kRing];
  G X[kRing], Y[kRing];
  Eigen::Matrix<S, 3, 3> R[kRing];  // X's rotation matrix (the peers' "log from a matrix")
  Eigen::Matrix<S, 3, 1> p[kRing];
  Eigen::Matrix<S, 3, 1> phi_large[kRing];  // rotation vectors with θ ∈ (π/2, π)
  Eigen::Matrix<S, 3, 1> phi_set[kSets][kRing];  // rotation vectors of each angle set
  lieservo::SO3<S> C_set[kSets][kRing];           // their rotations (log's inputs)
#ifdef LIESERVO_HAVE_SOPHUS
  Sophus::SE3<S> sX[kRing], sY[kRing];
  Sophus::SO3<S> sC_set[kSets][kRing];
#endif
#ifdef LIESERVO_HAVE_MANIF
  manif::SE3<S> mX[kRing], mY[kRing];
  manif::SO3<S> mC_set[kSets][kRing];
#endif
  Inputs() {
    const auto& in = lieservo_bench::GroupInputs<G>::get();
    lieservo::sampling::Rng rng(99);
    for (int set = 0; set < kSets; ++set) {
      for (std::size_t i = 0; i < kRing; ++i) {
        const double angle = angleOf(AngleSet(set), rng);
        const Eigen::Vector3d axis = lieservo_bench::randomTangent<lieservo::SO3d>(rng, 0.0, 1.0).normalized();
        phi_set[set][i] = (axis * angle).cast<S>();
        C_set[set][i] = lieservo::SO3<S>::fromMatrixUnchecked(lieservo::SO3d::exp(axis * angle).matrix().cast<S>());
#ifdef LIESERVO_HAVE_SOPHUS
        sC_set[set][i] = Sophus::SO3<S>(Quat(C_set[set][i].matrix()).normalized());
#endif
#ifdef LIESERVO_HAVE_MANIF
        mC_set[set][i] = manif::SO3<S>(Quat(C_set[set][i].matrix()).normalized());
#endif
      }
    }
    for (std::size_t i = 0; i < kRing; ++i) {
      const double angle = lieservo_bench::uniform(rng, 0.5, 1.0) * lieservo::pi<double>();
      phi_large[i] = lieservo_bench::randomTangent<lieservo::SO3<S>>(rng, 0.0, 1.0).normalized() * S(angle);
      xi[i] = in.xi[i];
      X[i] = in.X[i];
      Y[i] = in.Y[i];
      R[i] = X[i].rotationMatrix();
      p[i] = in.p[i];
#ifdef LIESERVO_HAVE_SOPHUS
      sX[i] = Sophus::SE3<S>(Sophus::SO3<S>(X[i].rotationMatrix()), X[i].translation());
      sY[i] = Sophus::SE3<S>(Sophus::SO3<S>(Y[i].rotationMatrix()), Y[i].translation());
#endif
#ifdef LIESERVO_HAVE_MANIF
      mX[i] = manif::SE3<S>(X[i].translation(), Quat(X[i].rotationMatrix()).normalized());
      mY[i] = manif::SE3<S>(Y[i].translation(), Quat(Y[i].rotationMatrix()).normalized());
#endif
    }
  }
  static const Inputs& get() {
    static const Inputs in;
    return in;
  }
};

// Times op(inputs, i) cycling through the ring.
template <class S, class Op>
void registerOp(const std::string& name, Op op) {
  benchmark::RegisterBenchmark(name.c_str(), [op](benchmark::State& state) {
    const auto& in = Inputs<S>::get();
    std::size_t i = 0;
    for (auto _ : state) {
      auto r = op(in, i);
      benchmark::DoNotOptimize(r);
      i = (i + 1) & (kRing - 1);
    }
  });
}

template <class S>
void registerAll(const std::string& sfx) {  // sfx: "d" or "f", as the libraries name types
  using G = lieservo::SE3<S>;
  using SO3 = lieservo::SO3<S>;
  using In = Inputs<S>;
  using V3 = Eigen::Matrix<S, 3, 1>;
  const std::string se3 = "SE3" + sfx + "_", so3 = "SO3" + sfx + "_";

  registerOp<S>(se3 + "exp/lieservo", [](const In& in, std::size_t i) { return G::exp(in.xi[i]); });
  registerOp<S>(se3 + "log/lieservo", [](const In& in, std::size_t i) { return in.X[i].log(); });
  registerOp<S>(se3 + "leftJacobian/lieservo", [](const In& in, std::size_t i) { return G::leftJacobian(in.xi[i]); });
  registerOp<S>(se3 + "leftJacobianInverse/lieservo",
                [](const In& in, std::size_t i) { return G::leftJacobianInverse(in.xi[i]); });
  registerOp<S>(se3 + "Ad/lieservo", [](const In& in, std::size_t i) { return in.X[i].Ad(); });
  registerOp<S>(se3 + "compose/lieservo", [](const In& in, std::size_t i) { return in.X[i] * in.Y[i]; });
  registerOp<S>(se3 + "inverse/lieservo", [](const In& in, std::size_t i) { return in.X[i].inverse(); });
  registerOp<S>(se3 + "act/lieservo", [](const In& in, std::size_t i) { return V3(in.X[i] * in.p[i]); });
  registerOp<S>(so3 + "exp/lieservo", [](const In& in, std::size_t i) { return SO3::exp(in.xi[i].template tail<3>()); });
  registerOp<S>(so3 + "log/lieservo", [](const In& in, std::size_t i) { return in.X[i].so3().log(); });
  registerOp<S>(so3 + "exp_large/lieservo", [](const In& in, std::size_t i) { return SO3::exp(in.phi_large[i]); });
  for (int set = 0; set < kSets; ++set) {
    const std::string tag = std::string("_") + kSetName[set] + "/";
    registerOp<S>(so3 + "exp" + tag + "lieservo", [set](const In& in, std::size_t i) { return SO3::exp(in.phi_set[set][i]); });
    registerOp<S>(so3 + "log" + tag + "lieservo", [set](const In& in, std::size_t i) { return in.C_set[set][i].log(); });
#ifdef LIESERVO_HAVE_SOPHUS
    registerOp<S>(so3 + "exp" + tag + "sophus",
                  [set](const In& in, std::size_t i) { return Sophus::SO3<S>::exp(in.phi_set[set][i]); });
    registerOp<S>(so3 + "log" + tag + "sophus", [set](const In& in, std::size_t i) { return in.sC_set[set][i].log(); });
#endif
#ifdef LIESERVO_HAVE_MANIF
    registerOp<S>(so3 + "exp" + tag + "manif",
                  [set](const In& in, std::size_t i) { return manif::SO3Tangent<S>(in.phi_set[set][i]).exp(); });
    registerOp<S>(so3 + "log" + tag + "manif", [set](const In& in, std::size_t i) { return in.mC_set[set][i].log(); });
#endif
  }

#ifdef LIESERVO_HAVE_SOPHUS
  using SE = Sophus::SE3<S>;
  using SO = Sophus::SO3<S>;
  registerOp<S>(se3 + "exp/sophus", [](const In& in, std::size_t i) { return SE::exp(in.xi[i]); });
  registerOp<S>(se3 + "log/sophus", [](const In& in, std::size_t i) { return in.sX[i].log(); });
  registerOp<S>(se3 + "leftJacobian/sophus", [](const In& in, std::size_t i) { return SE::leftJacobian(in.xi[i]); });
  registerOp<S>(se3 + "leftJacobianInverse/sophus",
                [](const In& in, std::size_t i) { return SE::leftJacobianInverse(in.xi[i]); });
  registerOp<S>(se3 + "Ad/sophus", [](const In& in, std::size_t i) { return in.sX[i].Adj(); });
  registerOp<S>(se3 + "compose/sophus", [](const In& in, std::size_t i) { return in.sX[i] * in.sY[i]; });
  registerOp<S>(se3 + "inverse/sophus", [](const In& in, std::size_t i) { return in.sX[i].inverse(); });
  registerOp<S>(se3 + "act/sophus", [](const In& in, std::size_t i) { return V3(in.sX[i] * in.p[i]); });
  registerOp<S>(so3 + "exp/sophus", [](const In& in, std::size_t i) { return SO::exp(in.xi[i].template tail<3>()); });
  registerOp<S>(so3 + "log/sophus", [](const In& in, std::size_t i) { return in.sX[i].so3().log(); });
  registerOp<S>(so3 + "exp_large/sophus", [](const In& in, std::size_t i) { return SO::exp(in.phi_large[i]); });
  registerOp<S>(so3 + "exp_matrix/sophus",
                [](const In& in, std::size_t i) { return SO::exp(in.xi[i].template tail<3>()).matrix(); });
  registerOp<S>(so3 + "log_matrix/sophus", [](const In& in, std::size_t i) { return SO(in.R[i]).log(); });
#endif
#ifdef LIESERVO_HAVE_MANIF
  using MT = manif::SE3Tangent<S>;
  using MRT = manif::SO3Tangent<S>;
  using MR = manif::SO3<S>;
  registerOp<S>(se3 + "exp/manif", [](const In& in, std::size_t i) { return MT(in.xi[i]).exp(); });
  registerOp<S>(se3 + "log/manif", [](const In& in, std::size_t i) { return in.mX[i].log(); });
  registerOp<S>(se3 + "leftJacobian/manif", [](const In& in, std::size_t i) { return MT(in.xi[i]).ljac(); });
  registerOp<S>(se3 + "leftJacobianInverse/manif", [](const In& in, std::size_t i) { return MT(in.xi[i]).ljacinv(); });
  registerOp<S>(se3 + "Ad/manif", [](const In& in, std::size_t i) { return in.mX[i].adj(); });
  registerOp<S>(se3 + "compose/manif", [](const In& in, std::size_t i) { return in.mX[i] * in.mY[i]; });
  registerOp<S>(se3 + "inverse/manif", [](const In& in, std::size_t i) { return in.mX[i].inverse(); });
  registerOp<S>(se3 + "act/manif", [](const In& in, std::size_t i) { return V3(in.mX[i].act(in.p[i])); });
  registerOp<S>(so3 + "exp/manif", [](const In& in, std::size_t i) { return MRT(in.xi[i].template tail<3>()).exp(); });
  registerOp<S>(so3 + "log/manif", [](const In& in, std::size_t i) { return in.mX[i].asSO3().log(); });
  registerOp<S>(so3 + "exp_large/manif", [](const In& in, std::size_t i) { return MRT(in.phi_large[i]).exp(); });
  registerOp<S>(so3 + "exp_matrix/manif",
                [](const In& in, std::size_t i) { return MRT(in.xi[i].template tail<3>()).exp().rotation(); });
  registerOp<S>(so3 + "log_matrix/manif",
                [](const In& in, std::size_t i) { return MR(Eigen::Quaternion<S>(in.R[i])).log(); });
#endif
}

}  // namespace

int main(int argc, char** argv) {
  // Registered before runBenchmarks, which checks --benchmark_filter against what is registered
  // before it runs the set-up (the accuracy report).
  registerAll<double>("d");
  registerAll<float>("f");
  return lieservo::bench::runBenchmarks(argc, argv, "SO(3) and SE(3) beside Sophus and manif, after an accuracy report", [] {
    accuracyReport();
    return -1;
  });
}

// No heap allocation per control step.  This executable replaces the global operator
// new/delete (all forms) with counting versions; counting is switched on only around the
// controller steps (Catch2's own allocations happen outside the window).
#include <catch2/catch.hpp>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>

#include <lieservo/control.hpp>
#include <lieservo/groups/se2.hpp>
#include <lieservo/groups/so2.hpp>
#include <lieservo/groups/so3.hpp>
#include <lieservo/units.hpp>

namespace {
std::atomic<bool> g_counting{false};
std::atomic<long> g_allocations{0};

void* countedAlloc(std::size_t n) {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* countedAlignedAlloc(std::size_t n, std::align_val_t al) {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1, std::memory_order_relaxed);
  const std::size_t a = static_cast<std::size_t>(al);
  void* p = nullptr;
  if (posix_memalign(&p, a < sizeof(void*) ? sizeof(void*) : a, n ? n : 1) != 0) throw std::bad_alloc();
  return p;
}

/// Counts allocations made while it is alive.
struct AllocationWindow {
  AllocationWindow() {
    g_allocations = 0;
    g_counting = true;
  }
  ~AllocationWindow() { g_counting = false; }
  long count() const { return g_allocations.load(); }
};
}  // namespace

void* operator new(std::size_t n) { return countedAlloc(n); }
void* operator new[](std::size_t n) { return countedAlloc(n); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  try {
    return countedAlloc(n);
  } catch (...) {
    return nullptr;
  }
}
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept {
  try {
    return countedAlloc(n);
  } catch (...) {
    return nullptr;
  }
}
void* operator new(std::size_t n, std::align_val_t a) { return countedAlignedAlloc(n, a); }
void* operator new[](std::size_t n, std::align_val_t a) { return countedAlignedAlloc(n, a); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }

using namespace lieservo;
using G = SE3<double>;
using V6 = G::Tangent;

TEST_CASE("no allocation: the counter works", "[control][alloc]") {
  long n = 0;
  {
    AllocationWindow w;
    void* volatile p = ::operator new(16);  // an explicit call: not elided
    ::operator delete(p);
    n = w.count();
  }
  CHECK(n == 1);
}

TEST_CASE("no allocation per step: PIDs and servo controllers on every group", "[control][alloc]") {
  const int steps = 5000;
  MimoPid<double, 6> mimo(paperMimoPid<double>(paper::kStabiliser));
  SisoPid<double> siso(paperAlignmentPid<double>(true));
  TactileServoController<G> servo(surfaceFollowingPreset<double>());
  TactileServoController<SE2<double>> servo2;
  TactileServoController<SO3<double>> servo3;
  TactileServoController<SO2<double>> servo1;
  int failures = 0;
  long allocations = 0;
  {
    AllocationWindow w;
    for (int k = 0; k < steps; ++k) {
      const double t = 0.001 * k;
      V6 e = V6::Zero();
      for (int i = 0; i < 6; ++i) e[i] = std::sin(t + i);
      V6 u = V6::Zero();
      failures += mimo.update(e, V6::Zero(), 0.001, u) != Status::ok;
      double uy = 0;
      failures += siso.update(e[0], 0.0, 0.001, uy) != Status::ok;
      failures += servo.step(G::exp(0.1 * e), 0.001, u) != Status::ok;
      SE2<double>::Tangent u2 = SE2<double>::Tangent::Zero();
      failures += servo2.step(SE2<double>::exp(e.head<3>()), 0.001, u2) != Status::ok;
      SO3<double>::Tangent u3 = SO3<double>::Tangent::Zero();
      failures += servo3.step(SO3<double>::exp(0.5 * e.tail<3>()), 0.001, u3) != Status::ok;
      SO2<double>::Tangent u1 = SO2<double>::Tangent::Zero();
      failures += servo1.step(SO2<double>::exp(e.head<1>()), 0.001, u1) != Status::ok;
      // failing steps must not allocate either
      failures += servo.step(G::exp(e), -1.0, u) == Status::ok;
    }
    allocations = w.count();
  }
  CHECK(failures == 0);
  CHECK(allocations == 0);
}

TEST_CASE("no allocation per step: pushing and dual-arm pushing with filters", "[control][alloc]") {
  const int steps = 3000;
  auto po = pushingPreset<double>(PushingConfiguration::single_arm);
  po.target = G(SO3<double>(), Eigen::Vector3d(0, 200, 600));
  PushingController<double> push(po);
  auto dopts = dualArmPushingPreset<double>(true);
  dopts.leader.target = G(SO3<double>(), Eigen::Vector3d(0, 100, 1e4));
  DualArmPushing<double> dual(dopts, DiscriminativeBayesFilter<G>(), DiscriminativeBayesFilter<G>());
  const G X_ofF(SO3<double>::fromEulerXYZ(pi<double>(), 0, 0), Eigen::Vector3d(0, 0, 60));
  G X_wsL = dopts.leader.servo.reference, X_wsF = X_ofF * dopts.follower.reference, X_wo;
  G::Jacobian cov = G::Jacobian::Identity() * 0.01;
  int failures = 0;
  long allocations = 0;
  {
    AllocationWindow w;
    for (int k = 0; k < steps; ++k) {
      V6 n = V6::Zero();
      for (int i = 0; i < 6; ++i) n[i] = 0.01 * std::sin(0.7 * k + i);
      V6 u = V6::Zero();
      // pushing: alternate far (alignment active) and near (cut-off) geometries
      const G X_ws = G(SO3<double>(), Eigen::Vector3d(0, 0, (k % 2) ? 0.0 : 550.0));
      failures += push.step(G::exp(n) * po.servo.reference.inverse(), X_ws, 0.02, u) != Status::ok;
      DualArmPushing<double>::ArmInput inL{X_wsL, {G::exp(n) * X_wsL.inverse() * X_wo, cov}};
      DualArmPushing<double>::ArmInput inF{X_wsF, {G::exp(-n) * X_wsF.inverse() * X_wo * X_ofF, cov}};
      DualArmPushing<double>::ArmOutput outL, outF;
      failures += dual.step(inL, inF, 0.02, outL, outF) != Status::ok;
      X_wsL = X_wsL * G::exp(0.02 * outL.velocity);
      X_wsF = X_wsF * G::exp(0.02 * outF.velocity);
      X_wo = X_wo * G::exp(0.02 * (V6() << 0, 0, 10, 0, 0, 0).finished());
    }
    // termination path
    auto near = po;
    near.target = G(SO3<double>(), Eigen::Vector3d(0, 1, 5));
    failures += push.configure(near) != Status::ok;
    failures += push.setTarget(near.target) != Status::ok;
    V6 u = V6::Zero();
    failures += push.step(po.servo.reference.inverse(), G::identity(), 0.02, u) != Status::ok;
    failures += !push.terminated();
    allocations = w.count();
  }
  CHECK(failures == 0);
  CHECK(allocations == 0);
}

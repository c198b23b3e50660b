// Zero heap allocations per real-time step. This executable replaces the global operator
// new/delete (C++17 [replacement.functions]) to count allocations while `g_counting` is set.
// Under AddressSanitizer/ThreadSanitizer, which own the allocator and its new/delete, the
// replacement is compiled out and the counting tests only WARN (the release build counts).
#include <catch2/catch.hpp>

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define LIESERVO_COUNT_ALLOCATIONS 0
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define LIESERVO_COUNT_ALLOCATIONS 0
#endif
#endif
#ifndef LIESERVO_COUNT_ALLOCATIONS
#define LIESERVO_COUNT_ALLOCATIONS 1
#endif

#include <lieservo/realtime.hpp>

#include <atomic>
#include <cstdlib>
#include <memory>
#include <new>

namespace {
std::atomic<bool> g_counting{false};
std::atomic<long> g_allocations{0};

[[maybe_unused]] void* countedAlloc(std::size_t n) {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(n == 0 ? 1 : n)) return p;
  throw std::bad_alloc();
}
[[maybe_unused]] void* countedAlignedAlloc(std::size_t n, std::align_val_t al) {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1, std::memory_order_relaxed);
  const std::size_t a = static_cast<std::size_t>(al);
  const std::size_t size = ((n == 0 ? 1 : n) + a - 1) / a * a;
  if (void* p = std::aligned_alloc(a, size)) return p;
  throw std::bad_alloc();
}

// Counts allocations in the scope.
struct Counting {
  Counting() {
    g_allocations.store(0);
    g_counting.store(true);
  }
  ~Counting() { g_counting.store(false); }
  long count() const { return g_allocations.load(); }
};
}  // namespace

#if LIESERVO_COUNT_ALLOCATIONS
void* operator new(std::size_t n) { return countedAlloc(n); }
void* operator new[](std::size_t n) { return countedAlloc(n); }
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
void* operator new(std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
  try {
    return countedAlignedAlloc(n, a);
  } catch (...) {
    return nullptr;
  }
}
void* operator new[](std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
  try {
    return countedAlignedAlloc(n, a);
  } catch (...) {
    return nullptr;
  }
}
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
#endif

using namespace lieservo::realtime;
using lieservo::Status;

TEST_CASE("alloc: the counter sees allocations (self-check)", "[realtime][alloc]") {
  if (!LIESERVO_COUNT_ALLOCATIONS) {
    WARN("allocation counting is disabled under sanitizers; run the release build");
    return;
  }
  long n = 0;
  {
    Counting c;
    auto* p = new int(3);
    n = c.count();
    delete p;
  }
  CHECK(n == 1);
}

TEST_CASE("alloc: smoother, watchdog, latest-value hand-over, frames and pipeline steps allocate nothing", "[realtime][alloc]") {
  // Everything constructed before counting starts.
  VelocitySmoother<double> smoother;
  CommandWatchdog watchdog;
  REQUIRE(watchdog.configure(WatchdogOptions{}) == Status::ok);
  auto channel = std::make_unique<LatestValueChannel<TwistCommand>>();
  CartesianVelocityPipeline pipe;
  PipelineOptions po;
  po.mount.p_es = Vector3(0, 0, 0.12);
  REQUIRE(pipe.configure(po) == Status::ok);
  std::array<double, 16> O_T_EE = toColumnMajor(Matrix4::Identity());
  std::array<double, 6> out{};
  Eigen::Matrix<double, 6, 1> target;
  target << 0.3, -0.2, 0.1, 1.0, -0.5, 0.2;
  Vector6 base;
  TwistCommand cmd;
  cmd.twist_s = {5, 0, 2, 0.1, 0, 0};
  cmd.in_contact = true;
  ChannelStamp stamp;

  long n = -1;
  {
    Counting c;
    for (int k = 0; k < 3000; ++k) {
      const double sgn = (k / 500) % 2 ? -1.0 : 1.0;
      (void)smoother.step(sgn * target, 1e-3);
      (void)smoother.step(target, 0.0);  // error path too
      (void)watchdog.update(static_cast<std::uint64_t>(k / 30 + 1), 0.01, true);
      channel->write(cmd);
      TwistCommand got;
      (void)channel->read(got, stamp);
      (void)sensorTwistToBaseChecked(O_T_EE, po.mount, target, 1e-3, base);
      (void)pipe.step(O_T_EE, *channel, steadyNowNs(), out);
      if (k == 2500) pipe.requestStop();
      (void)pipe.stepStopping(out);
      (void)smoother.stoppingTimeBound(1e-3);
    }
    n = c.count();
  }
  if (!LIESERVO_COUNT_ALLOCATIONS) {
    WARN("allocation counting is disabled under sanitizers; run the release build");
    return;
  }
  CHECK(n == 0);
}

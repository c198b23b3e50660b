// Latest-value channel under real concurrency (also built and run under ThreadSanitizer):
// no tearing, monotone sequence, the newest value delivered; and the whole pipeline fed
// by a tactile thread while a 1 kHz thread commands a fake robot.
#include <catch2/catch.hpp>

#include <lieservo/realtime/latest_value_channel.hpp>
#include <lieservo/realtime/velocity_pipeline.hpp>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <thread>

using namespace lieservo::realtime;

namespace {

struct Wide {
  std::uint64_t f[16];  // 128 bytes: spans two cache lines, so a torn copy would show
  double d;
};

}  // namespace

TEST_CASE("channel: nothing to read before the first write, then the newest value", "[realtime][channel]") {
  LatestValueChannel<Wide> ch;
  Wide w{};
  ChannelStamp st;
  CHECK_FALSE(ch.read(w));
  CHECK_FALSE(ch.read(w, st));
  for (std::uint64_t i = 1; i <= 5; ++i) {
    Wide x{};
    for (auto& f : x.f) f = i;
    ch.write(x, static_cast<std::int64_t>(100 * i));
  }
  REQUIRE(ch.read(w, st));
  CHECK(w.f[0] == 5);
  CHECK(w.f[15] == 5);
  CHECK(st.sequence == 5);
  CHECK(st.time_ns == 500);
  // Reading again gives the same value and stamp.
  ChannelStamp st2;
  REQUIRE(ch.read(w, st2));
  CHECK(st2.sequence == 5);
  CHECK(ch.writtenCount() == 5);
  // Default timestamps come from steady_clock.
  const std::int64_t before = steadyNowNs();
  ch.write(Wide{});
  REQUIRE(ch.read(w, st));
  CHECK(st.sequence == 6);
  CHECK(st.time_ns >= before);
  CHECK(st.time_ns <= steadyNowNs());
}

TEST_CASE("channel: concurrent writes never tear and the sequence is monotone", "[realtime][channel][threads]") {
  LatestValueChannel<Wide> ch;
  constexpr std::uint64_t kWrites = 200000;
  std::atomic<bool> writer_done{false}, reader_started{false};
  std::thread writer([&] {
    while (!reader_started.load(std::memory_order_acquire)) std::this_thread::yield();
    for (std::uint64_t i = 1; i <= kWrites; ++i) {
      if (i % 256 == 0) std::this_thread::yield();  // let the reader in on a busy 2-core box
      Wide x;
      for (auto& f : x.f) f = i;
      x.d = static_cast<double>(i);
      ch.write(x, static_cast<std::int64_t>(i));
    }
    writer_done.store(true, std::memory_order_release);
  });

  std::uint64_t last = 0, reads = 0, distinct = 0, torn = 0, backwards = 0, bad_stamp = 0;
  Wide w;
  ChannelStamp st;
  auto check_one = [&] {
    if (!ch.read(w, st)) return;
    ++reads;
    for (auto f : w.f)
      if (f != w.f[0]) ++torn;
    if (w.d != static_cast<double>(w.f[0])) ++torn;
    if (st.sequence != w.f[0] || st.time_ns != static_cast<std::int64_t>(w.f[0])) ++bad_stamp;
    if (w.f[0] < last) ++backwards;
    if (w.f[0] != last) ++distinct;
    last = w.f[0];
  };
  reader_started.store(true, std::memory_order_release);
  while (!writer_done.load(std::memory_order_acquire)) check_one();
  writer.join();
  check_one();  // after the writer finished: must be the very last value
  CHECK(torn == 0);
  CHECK(backwards == 0);
  CHECK(bad_stamp == 0);
  CHECK(last == kWrites);
  CHECK(distinct >= 2);
  INFO("reads " << reads << " distinct " << distinct);
  CHECK(reads > 0);
}

TEST_CASE("channel: a tactile thread feeding the 1 kHz pipeline, then stalling", "[realtime][channel][threads][pipeline]") {
  // Tactile thread: ~100 Hz commands for 0.3 s, then silence. Robot thread: ~1 kHz steps on a
  // fake arm. Checks the data flow end to end and the watchdog stop on a stalled writer.
  LatestValueChannel<TwistCommand> ch;
  CartesianVelocityPipeline pipe;
  PipelineOptions o;
  o.watchdog.command_timeout_s = 0.15;  // generous: shared CI machines, sanitizers
  o.watchdog.rearm_fresh_commands = 2;
  REQUIRE(pipe.configure(o) == lieservo::Status::ok);

  std::atomic<bool> tactile_done{false};
  std::thread tactile([&] {
    const auto t0 = std::chrono::steady_clock::now();
    while (std::chrono::steady_clock::now() - t0 < std::chrono::milliseconds(300)) {
      TwistCommand c;
      c.twist_s = {0, 10, 0, 0, 0, 0};  // 10 mm/s along the sensor y
      c.in_contact = true;
      ch.write(c);
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    tactile_done.store(true, std::memory_order_release);
  });

  lieservo::SE3<double> T_OE;
  std::array<double, 6> out{};
  double max_vy = 0;
  bool moved = false;
  const auto start = std::chrono::steady_clock::now();
  while (std::chrono::steady_clock::now() - start < std::chrono::seconds(3)) {
    REQUIRE(pipe.step(T_OE, ch, steadyNowNs(), out) == lieservo::Status::ok);
    T_OE = lieservo::SE3<double>(T_OE.so3(), T_OE.translation() + Vector3(0, 1e-3 * out[1], 0));
    max_vy = std::max(max_vy, out[1]);
    if (out[1] > 0) moved = true;
    if (tactile_done.load(std::memory_order_acquire) && pipe.stopped()) break;
    std::this_thread::sleep_for(std::chrono::microseconds(1000));
  }
  tactile.join();
  CHECK(moved);
  CHECK(max_vy <= 0.01 + 1e-12);
  CHECK(pipe.stopped());
  CHECK(pipe.watchdog().state() == WatchdogState::tripped_timeout);
  CHECK(T_OE.translation().y() > 0);
}

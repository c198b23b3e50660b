// lieservo/realtime/latest_value_channel.hpp — lock-free latest-value channel.
//
// Carries the newest command from the tactile (camera-rate) thread to the 1 kHz robot
// thread: the writer never waits, the reader never waits, and the reader always gets the
// most recent complete value (older unread values are overwritten, never queued).
//
// Implementation: a triple buffer. Three slots; at any time the writer owns one ("back"),
// the reader owns one ("front"), and the third ("middle") is the hand-over slot, named by
// an atomic index that also carries a "fresh" bit. The writer fills its back slot, then
// swaps it with the middle (exchange, acq_rel) marking it fresh; the reader, when the
// fresh bit is set, swaps its front slot with the middle (exchange, acq_rel). Each slot is
// accessed by exactly one thread between hand-overs, and every hand-over is an atomic
// release/acquire pair, so there is no data race (clean under ThreadSanitizer) and a value
// can never be torn.
//
// Each value carries a Stamp: a sequence number (1, 2, … in write order; 0 = never
// written) and the writer's timestamp in nanoseconds of std::chrono::steady_clock (or a
// caller-given clock), so the reader can tell a new value from a repeated one and its age.
//
// Threading: ONE writer thread and ONE reader thread at a time (SPSC). Several writers
// must serialise their writes themselves (e.g. a mutex on the non-real-time side).
// write() and read() are wait-free, noexcept and allocation-free.
#pragma once
#include <lieservo/detail/options_push.hpp>

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <type_traits>

namespace lieservo::realtime {

/// Sequence number and timestamp of a value in a LatestValueChannel.
struct ChannelStamp {
  std::uint64_t sequence = 0;  ///< 1, 2, … in write order; 0 = nothing written yet
  std::int64_t time_ns = 0;    ///< writer's timestamp (steady_clock ns unless given)
};

/// Nanoseconds since the epoch of std::chrono::steady_clock (monotonic; noexcept).
inline std::int64_t steadyNowNs() noexcept {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

template <typename T>
/// Lock-free single-writer single-reader channel of the newest value of T (a triple buffer;
/// the header comment gives the design): write() and read() are wait-free.
class LatestValueChannel {
  static_assert(std::is_trivially_copyable<T>::value,
                "LatestValueChannel<T> needs a trivially copyable T (copied by value, no allocation)");

 public:
  LatestValueChannel() noexcept = default;
  LatestValueChannel(const LatestValueChannel&) = delete;
  LatestValueChannel& operator=(const LatestValueChannel&) = delete;

  /// Publish `value` stamped with steady_clock now. Writer thread only.
  void write(const T& value) noexcept { write(value, steadyNowNs()); }

  /// Publish `value` with the caller's timestamp (ns). Writer thread only.
  void write(const T& value, std::int64_t time_ns) noexcept {
    Slot& slot = slots_[back_];
    slot.value = value;
    slot.stamp.sequence = ++written_;
    slot.stamp.time_ns = time_ns;
    back_ = middle_.exchange(back_ | kFresh, std::memory_order_acq_rel) & kIndexMask;
  }

  /// Copy the newest value to `out`; false (out untouched) if nothing was ever written.
  /// Reader thread only. Reading the same value twice returns the same stamp.
  bool read(T& out) noexcept {
    ChannelStamp ignored;
    return read(out, ignored);
  }

  /// As read(out), also giving the value's stamp.
  bool read(T& out, ChannelStamp& stamp) noexcept {
    if (middle_.load(std::memory_order_relaxed) & kFresh)
      front_ = middle_.exchange(front_, std::memory_order_acq_rel) & kIndexMask;
    const Slot& slot = slots_[front_];
    if (slot.stamp.sequence == 0) return false;
    out = slot.value;
    stamp = slot.stamp;
    return true;
  }

  /// Number of values written so far. Writer thread only.
  std::uint64_t writtenCount() const noexcept { return written_; }

 private:
  static constexpr unsigned kIndexMask = 3u;
  static constexpr unsigned kFresh = 4u;

  struct alignas(64) Slot {
    T value{};
    ChannelStamp stamp{};
  };

  std::array<Slot, 3> slots_{};
  alignas(64) unsigned back_ = 0;             // writer-owned
  std::uint64_t written_ = 0;                 // writer-owned
  alignas(64) std::atomic<unsigned> middle_{1u};  // shared hand-over index (+ fresh bit)
  alignas(64) unsigned front_ = 2;            // reader-owned
};

}  // namespace lieservo::realtime

#include <lieservo/detail/options_pop.hpp>

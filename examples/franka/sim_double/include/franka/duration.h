// franka/duration.h (lieservo's libfranka test double) — the part of libfranka's
// franka::Duration that the Franka adapter uses, with libfranka's declarations.
#pragma once

#include <chrono>
#include <cstdint>

namespace franka {

/// A time span in whole milliseconds (libfranka's control period is 1 ms).
class Duration {
 public:
  Duration() noexcept = default;
  explicit Duration(uint64_t milliseconds) noexcept : duration_(milliseconds) {}
  Duration(std::chrono::duration<uint64_t, std::milli> duration) noexcept : duration_(duration) {}
  Duration(const Duration&) = default;
  Duration& operator=(const Duration&) = default;

  operator std::chrono::duration<uint64_t, std::milli>() const noexcept { return duration_; }
  double toSec() const noexcept { return double(duration_.count()) / 1000.0; }
  uint64_t toMSec() const noexcept { return duration_.count(); }

  Duration operator+(const Duration& rhs) const noexcept { return Duration(duration_ + rhs.duration_); }
  Duration& operator+=(const Duration& rhs) noexcept {
    duration_ += rhs.duration_;
    return *this;
  }
  bool operator==(const Duration& rhs) const noexcept { return duration_ == rhs.duration_; }
  bool operator!=(const Duration& rhs) const noexcept { return duration_ != rhs.duration_; }

 private:
  std::chrono::duration<uint64_t, std::milli> duration_{0};
};

}  // namespace franka

// franka/exception.h (lieservo's libfranka test double) — libfranka's exception types, with
// its declarations (ControlException carries no log here).
#pragma once

#include <stdexcept>
#include <string>

namespace franka {

struct Exception : public std::runtime_error {
  using std::runtime_error::runtime_error;
};
struct NetworkException : public Exception {
  using Exception::Exception;
};
/// A control command the robot refused, or a reflex (limit violation, collision).
struct ControlException : public Exception {
  explicit ControlException(const std::string& what) noexcept : Exception(what) {}
};
struct CommandException : public Exception {
  using Exception::Exception;
};
struct RealtimeException : public Exception {
  using Exception::Exception;
};
struct InvalidOperationException : public Exception {
  using Exception::Exception;
};

}  // namespace franka

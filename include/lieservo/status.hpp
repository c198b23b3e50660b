// lieservo/status.hpp — the error codes of lieservo, core and adapters alike.
//
// Functions on the real-time path (filter and controller steps, checked
// constructors) never throw and never allocate: they return a Status and leave
// their outputs/state untouched unless the Status is Status::ok. The adapters at
// the edges (camera, network, robot; examples/) report per-frame and per-cycle
// errors the same way, with the last three codes for what only they meet, and a
// human-readable detail from their lastError().
#pragma once
#include <lieservo/detail/options_push.hpp>

namespace lieservo {

/// What every checked call returns: ok, or the reason it failed (each function says what it
/// leaves unchanged; describe() gives a phrase). [[nodiscard]]: a call whose Status is dropped
/// does not compile without a warning; discard one on purpose with a (void) cast and a reason.
enum class [[nodiscard]] Status : int {
  ok = 0,                ///< success
  non_finite_input,      ///< a NaN or infinity in an input
  not_orthonormal,       ///< a rotation block is not orthonormal (or det != +1)
  not_spd,               ///< a covariance/information matrix is not symmetric positive-definite
  invalid_time_step,     ///< dt <= 0 or non-finite
  not_initialised,       ///< e.g. a filter step before the first observation
  invalid_argument,      ///< a parameter outside its documented range
  outlier_rejected,      ///< an observation failed the chi-square gate (state predicted only)
  not_converged,         ///< an iteration hit its limit before its tolerance
  numerical_failure,     ///< a factorisation or result became non-finite
  io_error,              ///< a file could not be read (adapters)
  end_of_stream,         ///< a recorded source (video, image sequence) has no more frames (adapters)
  device_error,          ///< a device or the library driving it failed: camera lost, robot reflex, cv::dnn error (adapters)
};

/// A short, human-readable description; never allocates.
constexpr const char* describe(Status s) noexcept {
  switch (s) {
    case Status::ok: return "ok";
    case Status::non_finite_input: return "input contains a non-finite value (NaN or inf)";
    case Status::not_orthonormal: return "rotation is not orthonormal with determinant +1";
    case Status::not_spd: return "matrix is not symmetric positive-definite";
    case Status::invalid_time_step: return "time step must be finite and > 0";
    case Status::not_initialised: return "not initialised: no first observation yet";
    case Status::invalid_argument: return "argument outside its documented range";
    case Status::outlier_rejected: return "observation rejected by the chi-square gate";
    case Status::not_converged: return "iteration limit reached before tolerance";
    case Status::numerical_failure: return "numerical failure (factorisation or non-finite result)";
    case Status::io_error: return "a file could not be read";
    case Status::end_of_stream: return "end of stream: no more frames";
    case Status::device_error: return "device error (camera, robot or inference library)";
  }
  return "unknown status";
}

/// True when s is Status::ok.
constexpr bool succeeded(Status s) noexcept { return s == Status::ok; }

}  // namespace lieservo

#include <lieservo/detail/options_pop.hpp>

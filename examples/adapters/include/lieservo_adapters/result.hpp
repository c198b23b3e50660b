// lieservo_adapters/result.hpp — the error type of the per-frame adapter paths.
//
// Set-up code (loading parameter files, models, opening a camera) throws
// std::runtime_error with a message naming the file and the problem. The
// per-frame paths (pre-processing one image, reading one camera frame, running
// the network on one image) never throw for bad input: they return a
// Result<T> that holds either the value or an AdapterError.
#pragma once

#include <string>
#include <utility>
#include <variant>

namespace lieservo::adapters {

enum class ErrorCode : int {
  empty_image,       ///< an empty cv::Mat (or one that could not be decoded)
  wrong_size,        ///< image dimensions differ from the expected ones
  wrong_type,        ///< unsupported depth or channel count
  io_error,          ///< a file could not be read
  camera_lost,       ///< a live camera stopped delivering frames
  end_of_stream,     ///< a video file / image sequence has no more frames
  inference_failed,  ///< cv::dnn raised an error or returned an unexpected shape
  non_finite_output, ///< the network returned NaN/inf or a non-positive precision
  invalid_argument,  ///< e.g. an empty batch
};

const char* describe(ErrorCode code) noexcept;

struct AdapterError {
  ErrorCode code;
  std::string message;  ///< human-readable detail (sizes, paths, ...)
};

/// Either a value or an AdapterError (a small std::expected stand-in for C++17).
template <class T>
class Result {
 public:
  Result(T value) : v_(std::move(value)) {}                  // NOLINT(implicit)
  Result(AdapterError error) : v_(std::move(error)) {}       // NOLINT(implicit)

  bool ok() const noexcept { return v_.index() == 0; }
  explicit operator bool() const noexcept { return ok(); }

  /// The value; calling it on an error is a programming error (throws std::bad_variant_access).
  T& value() & { return std::get<0>(v_); }
  const T& value() const& { return std::get<0>(v_); }
  T&& value() && { return std::get<0>(std::move(v_)); }
  T* operator->() { return &std::get<0>(v_); }
  const T* operator->() const { return &std::get<0>(v_); }
  T& operator*() & { return std::get<0>(v_); }
  const T& operator*() const& { return std::get<0>(v_); }

  const AdapterError& error() const { return std::get<1>(v_); }

 private:
  std::variant<T, AdapterError> v_;
};

inline AdapterError makeError(ErrorCode code, std::string message) {
  return AdapterError{code, std::move(message)};
}

}  // namespace lieservo::adapters

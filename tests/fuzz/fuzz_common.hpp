// Shared helpers of the libFuzzer targets: turning arbitrary bytes into scalars, tangent
// vectors, group elements and covariances — including non-finite and extreme values — and a
// hard failure (abort) when a property is violated.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>

#include <lieservo/estimation.hpp>
#include <lieservo/groups.hpp>

namespace lieservo::fuzz {

[[noreturn]] inline void fail(const char* what, int line) {
  std::fprintf(stderr, "PROPERTY VIOLATED (line %d): %s\n", line, what);
  std::abort();
}
#define LIESERVO_FUZZ_REQUIRE(cond) \
  do {                              \
    if (!(cond)) ::lieservo::fuzz::fail(#cond, __LINE__); \
  } while (0)

/// Consumes bytes; once exhausted, returns zeros.
class Bytes {
 public:
  Bytes(const std::uint8_t* d, std::size_t n) : d_(d), n_(n) {}
  bool empty() const { return n_ == 0; }
  std::uint8_t u8() {
    if (n_ == 0) return 0;
    --n_;
    return *d_++;
  }
  std::int16_t i16() {
    std::uint16_t v = std::uint16_t(u8()) | std::uint16_t(std::uint16_t(u8()) << 8);
    std::int16_t r;
    std::memcpy(&r, &v, sizeof r);
    return r;
  }
  double rawDouble() {
    std::uint64_t bits = 0;
    for (int i = 0; i < 8; ++i) bits |= std::uint64_t(u8()) << (8 * i);
    double r;
    std::memcpy(&r, &bits, sizeof r);
    return r;
  }
  /// A double: mostly moderate values (so that valid inputs are common), sometimes raw bit
  /// patterns (NaN, inf, subnormals, anything), huge/tiny magnitudes or special values.
  double value() {
    const std::uint8_t m = u8();
    switch (m & 7) {
      case 0:
        return rawDouble();
      case 6: {
        const int e = int(std::int8_t(u8()));  // 2^[-128, 127]
        return std::ldexp(double(i16()) / 32768.0, e * 8 > 1000 ? 1000 : (e * 8 < -1000 ? -1000 : e * 8));
      }
      case 7: {
        const double specials[] = {0.0,
                                   -0.0,
                                   1e-300,
                                   1e300,
                                   std::numeric_limits<double>::infinity(),
                                   -std::numeric_limits<double>::infinity(),
                                   std::numeric_limits<double>::quiet_NaN(),
                                   std::numeric_limits<double>::denorm_min(),
                                   std::numeric_limits<double>::max(),
                                   lieservo::pi<double>(),
                                   -lieservo::pi<double>(),
                                   1e-12,
                                   1e12};
        return specials[u8() % (sizeof specials / sizeof specials[0])];
      }
      default:
        return double(i16()) / 256.0;  // [-128, 128), 1/256 steps
    }
  }
  /// A positive-ish standard deviation: mostly exp of a moderate value, sometimes anything.
  double sigma() {
    const std::uint8_t m = u8();
    if ((m & 3) == 0) return value();
    return std::exp(double(std::int8_t(u8())) / 8.0);  // e^[-16, 16]
  }
  /// Conversion to Scalar without undefined behaviour (out-of-range double → ±inf for float).
  template <class Scalar>
  static Scalar to(double v) {
    if (std::isfinite(v) && std::abs(v) > double(std::numeric_limits<Scalar>::max()))
      return v > 0 ? std::numeric_limits<Scalar>::infinity() : -std::numeric_limits<Scalar>::infinity();
    return static_cast<Scalar>(v);
  }
  template <class Vec>
  Vec vector() {
    Vec v;
    for (Eigen::Index i = 0; i < v.size(); ++i) v.data()[i] = to<typename Vec::Scalar>(value());
    return v;
  }
  template <class Vec>
  Vec sigmas() {
    Vec v;
    for (Eigen::Index i = 0; i < v.size(); ++i) v.data()[i] = to<typename Vec::Scalar>(sigma());
    return v;
  }

 private:
  const std::uint8_t* d_;
  std::size_t n_;
};

/// A group element: usually exp of a tangent vector (valid when finite), sometimes a raw
/// matrix (almost always invalid), sometimes a projected raw matrix.
template <class G>
G groupElement(Bytes& b) {
  const std::uint8_t m = b.u8();
  if ((m & 7) == 0) return G::fromMatrixUnchecked(b.vector<typename G::Matrix>());
  if ((m & 7) == 1) {
    G out;
    if (G::fromMatrixProjected(b.vector<typename G::Matrix>(), out) == Status::ok) return out;
    return G();
  }
  return G::exp(b.vector<typename G::Tangent>());
}

/// A covariance: raw matrix, diagonal, L·Lᵀ, or the GDN form J(μ) diag(σ²) J(μ)ᵀ.
template <class G>
typename G::Jacobian covariance(Bytes& b) {
  using J = typename G::Jacobian;
  using S = typename G::Scalar;
  const std::uint8_t m = b.u8() & 3;
  if (m == 0) return b.vector<J>();
  if (m == 1) return b.sigmas<typename G::Tangent>().array().square().matrix().asDiagonal();
  if (m == 2) {
    J L = b.vector<J>();
    L = L.template triangularView<Eigen::Lower>();
    for (int i = 0; i < G::DoF; ++i) L(i, i) = Bytes::to<S>(b.sigma());
    return L * L.transpose();
  }
  ConcentratedGaussian<G> x;
  const typename G::Tangent mu = b.vector<typename G::Tangent>();
  const typename G::Tangent s = b.sigmas<typename G::Tangent>();
  if (fromTangentGaussian(mu, s, x) == Status::ok) return x.covariance;
  return J::Identity();
}

template <class G>
ConcentratedGaussian<G> gaussian(Bytes& b) {
  ConcentratedGaussian<G> x;
  x.mean = groupElement<G>(b);
  x.covariance = covariance<G>(b);
  return x;
}

template <class G>
bool allFinite(const ConcentratedGaussian<G>& x) {
  return x.mean.allFinite() && x.covariance.allFinite();
}

/// Bitwise equality of two Gaussians (for "output untouched" checks).
template <class G>
bool bitwiseEqual(const ConcentratedGaussian<G>& a, const ConcentratedGaussian<G>& b) {
  const typename G::Matrix ma = a.mean.matrix(), mb = b.mean.matrix();
  return std::memcmp(ma.data(), mb.data(), sizeof(typename G::Scalar) * std::size_t(ma.size())) == 0 &&
         std::memcmp(a.covariance.data(), b.covariance.data(),
                     sizeof(typename G::Scalar) * std::size_t(a.covariance.size())) == 0;
}

}  // namespace lieservo::fuzz

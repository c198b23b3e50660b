// Seeded random draws (include/lieservo/sampling/random.hpp): uniform draws from the generator's
// raw bits, normal draws by Box–Muller, and the vector helpers.
//
// Statistical tests use a fixed seed and significance level α = 0.001, and n = 32000 as the
// contact-sampling tests (KS: power ≥ 0.9 against any CDF off by ≥ 0.0145 somewhere). Each shows
// that it rejects a plausible wrong sampler (negative control).
#include <catch2/catch.hpp>

#include <lieservo/sampling/random.hpp>
#include <lieservo/units.hpp>

#include "goodness_of_fit.hpp"

#include <cmath>
#include <random>
#include <vector>

using namespace lieservo::sampling;
using lieservo::test::ksPValue;
using lieservo::test::ksStatisticUniform;

namespace {
constexpr double kAlpha = 1e-3;
constexpr std::size_t kN = 32000;

double normalCdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }
}  // namespace

TEST_CASE("uniformCanonical: values in 0..1, portable bits, seeded, any 2^k-1 generator", "[sampling]") {
  Rng a(42), b(42);
  std::mt19937 c32(42);
  double mean = 0, mean32 = 0;
  for (int i = 0; i < 10000; ++i) {
    const double u = uniformCanonical<double>(a);
    REQUIRE(u >= 0.0);
    REQUIRE(u < 1.0);
    REQUIRE(u == uniformCanonical<double>(b));  // same seed, same sequence
    mean += u / 10000;
    const double v = uniformCanonical<double>(c32);  // two 32-bit draws per value
    REQUIRE(v >= 0.0);
    REQUIRE(v < 1.0);
    mean32 += v / 10000;
    const float f = uniformCanonical<float>(c32);
    REQUIRE(f >= 0.0f);
    REQUIRE(f < 1.0f);
  }
  CHECK(mean == Approx(0.5).margin(0.02));
  CHECK(mean32 == Approx(0.5).margin(0.02));
  // 53 high bits of one 64-bit draw: reproducible across platforms.
  lieservo::sampling::Rng g(7), h(7);
  CHECK(uniformCanonical<double>(g) == static_cast<double>(h() >> 11) * std::ldexp(1.0, -53));
}

TEST_CASE("standardNormal: Box–Muller of two uniform draws, N(0, 1) by KS, seeded", "[sampling]") {
  // The transform itself, from the same two draws.
  Rng a(11), b(11);
  const double u1 = uniformCanonical<double>(b), u2 = uniformCanonical<double>(b);
  CHECK(standardNormal(a) == std::sqrt(-2.0 * std::log(1.0 - u1)) * std::cos(2.0 * lieservo::pi<double>() * u2));
  CHECK(a() == b());  // both consumed exactly two raw draws

  Rng rng(20261124), again(20261124);
  std::vector<double> u(kN), wide(kN);
  double m1 = 0, m2 = 0, m4 = 0;
  for (std::size_t i = 0; i < kN; ++i) {
    const double z = standardNormal(rng);
    REQUIRE(std::isfinite(z));
    REQUIRE(z == standardNormal(again));
    u[i] = normalCdf(z);
    wide[i] = normalCdf(1.1 * z);  // negative control: σ = 1.1
    m1 += z / kN;
    m2 += z * z / kN;
    m4 += z * z * z * z / kN;
  }
  CHECK(ksPValue(ksStatisticUniform(u), kN) > kAlpha);
  CHECK(ksPValue(ksStatisticUniform(wide), kN) < kAlpha);
  // Moments within 5 standard errors: sd(mean) = 1/√n, sd(m2) = √(2/n), sd(m4) = √(96/n).
  const double n = static_cast<double>(kN);
  CHECK(std::abs(m1) < 5 / std::sqrt(n));
  CHECK(std::abs(m2 - 1) < 5 * std::sqrt(2 / n));
  CHECK(std::abs(m4 - 3) < 5 * std::sqrt(96 / n));
}

TEST_CASE("standardNormal in float, and the vector helpers", "[sampling]") {
  Rng rng(5), ref(5);
  const float f = standardNormal<float>(rng);
  CHECK(f == static_cast<float>(standardNormal<double>(ref)));

  // uniformVector: each entry one uniform(a, b) draw, in order.
  const Eigen::Matrix<double, 4, 1> v = uniformVector<4>(rng, -2.0, 3.0);
  for (int i = 0; i < 4; ++i) {
    CHECK(v[i] == uniform(ref, -2.0, 3.0));
    CHECK(v[i] >= -2.0);
    CHECK(v[i] < 3.0);
  }
  // normalVector: σ_i times one standard normal draw each, in order; a fixed-size σ keeps its
  // type and a dynamic one its length.
  const Eigen::Vector3d sigma(0.5, 2.0, 0.0);
  const Eigen::Vector3d z = normalVector(rng, sigma);
  const Eigen::Vector3d zr = standardNormalVector<3>(ref);
  CHECK(z[0] == 0.5 * zr[0]);
  CHECK(z[1] == 2.0 * zr[1]);
  CHECK(z[2] == 0.0);
  const Eigen::VectorXd sd = Eigen::VectorXd::Constant(7, 3.0);
  CHECK(normalVector(rng, sd).size() == 7);

  // Per-component standard deviations over 32000 draws of a 2-vector with σ = (0.5, 2).
  double s0 = 0, s1 = 0, c01 = 0;
  for (std::size_t i = 0; i < kN; ++i) {
    const Eigen::Vector2d w = normalVector(rng, Eigen::Vector2d(0.5, 2.0));
    s0 += w[0] * w[0] / kN;
    s1 += w[1] * w[1] / kN;
    c01 += w[0] * w[1] / kN;
  }
  const double se = 5 * std::sqrt(2.0 / kN);  // 5 standard errors of a variance ratio
  CHECK(std::abs(s0 / 0.25 - 1) < se);
  CHECK(std::abs(s1 / 4.0 - 1) < se);
  CHECK(std::abs(c01 / 1.0) < 5 / std::sqrt(static_cast<double>(kN)));  // independent
}

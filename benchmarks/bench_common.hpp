// benchmarks/bench_common.hpp — seeded, realistic inputs shared by the benchmark executables.
//
// Inputs are generated once, outside the timed loops, and cycled through (a power-of-two ring)
// so that the compiler cannot constant-fold a call and the branch predictor sees a realistic
// mix of angles. Magnitudes follow the paper's data set: translations of a few mm, rotations
// up to ~25°, GDN-like standard deviations of 0.1–1 mm and 0.5–2°.
#pragma once

#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <vector>

#include <lieservo/estimation.hpp>
#include <lieservo/lieservo.hpp>
#include <lieservo/sampling/random.hpp>

namespace lieservo_bench {

using lieservo::sampling::standardNormal;
using lieservo::sampling::uniform;

inline constexpr std::size_t kRing = 256;  // power of two
inline constexpr double kPi = lieservo::pi<double>();
inline constexpr double kDeg = kPi / 180.0;

/// A random tangent vector of G: translation components uniform in ±t_max, rotation vector
/// with a uniformly random direction and angle uniform in [0, rot_max].
template <class G, class Rng>
typename G::Tangent randomTangent(Rng& rng, double t_max, double rot_max) {
  using Scalar = typename G::Scalar;
  typename G::Tangent xi;
  constexpr int R = G::Dim * (G::Dim - 1) / 2;  // rotational DoF (the tail of ξ)
  for (int i = 0; i < G::DoF - R; ++i) xi(i) = Scalar(t_max * uniform(rng, -1.0, 1.0));
  double axis[3] = {standardNormal(rng), standardNormal(rng), standardNormal(rng)};
  const double an = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
  const double angle = rot_max * uniform(rng, 0.0, 1.0);
  for (int i = 0; i < R; ++i) xi(G::DoF - R + i) = Scalar(R == 1 ? angle : angle * axis[i] / an);
  return xi;
}

/// GDN-like standard deviations: σ_t ∈ [0.1, 1] mm, σ_r ∈ [0.5°, 2°] (in rad).
template <class G, class Rng>
typename G::Tangent randomSigma(Rng& rng) {
  using Scalar = typename G::Scalar;
  constexpr int R = G::Dim * (G::Dim - 1) / 2;
  typename G::Tangent s;
  for (int i = 0; i < G::DoF; ++i) s(i) = Scalar(i < G::DoF - R ? uniform(rng, 0.1, 1.0) : uniform(rng, 0.5 * kDeg, 2.0 * kDeg));
  return s;
}

/// Ring of inputs of one group type.
template <class G>
struct GroupInputs {
  std::vector<typename G::Tangent> xi;   // tangents, |φ| ≤ 1 rad, |ρ_i| ≤ 5
  std::vector<G> X, Y;                   // group elements
  std::vector<typename G::Point> p;      // points
  GroupInputs() {
    lieservo::sampling::Rng rng(20240601);
    for (std::size_t i = 0; i < kRing; ++i) {
      xi.push_back(randomTangent<G>(rng, 5.0, 1.0));
      X.push_back(G::exp(randomTangent<G>(rng, 5.0, 25 * kDeg)));
      Y.push_back(G::exp(randomTangent<G>(rng, 5.0, 25 * kDeg)));
      typename G::Point q;
      for (int k = 0; k < q.size(); ++k) q(k) = typename G::Scalar(uniform(rng, -5.0, 5.0));
      p.push_back(q);
    }
  }
  static const GroupInputs& get() {
    static const GroupInputs in;
    return in;
  }
};

/// A ring of (sensor pose, observation) pairs of a tactile-servo run: the sensor moves a
/// little each step (≤ 0.5 mm, ≤ 1°) and observes a feature pose within the data set's range
/// (≤ 5 mm, ≤ 25°) with GDN-like uncertainty (observation built by fromTangentGaussian).
template <class G>
struct FilterInputs {
  using Tangent = typename G::Tangent;
  std::vector<G> sensor;
  std::vector<Tangent> mu, sigma;
  std::vector<lieservo::ConcentratedGaussian<G>> obs;
  FilterInputs() {
    lieservo::sampling::Rng rng(7);
    G pose = G::identity();
    const Tangent feature = randomTangent<G>(rng, 3.0, 10 * kDeg);
    for (std::size_t i = 0; i < kRing; ++i) {
      pose = G::exp(randomTangent<G>(rng, 0.5, 1.0 * kDeg)) * pose;
      sensor.push_back(pose);
      const Tangent m = feature + randomTangent<G>(rng, 2.0, 15 * kDeg);
      const Tangent s = randomSigma<G>(rng);
      mu.push_back(m);
      sigma.push_back(s);
      lieservo::ConcentratedGaussian<G> o;
      if (lieservo::fromTangentGaussian(m, s, o) != lieservo::Status::ok)
        throw std::runtime_error("benchmark inputs: an observation Gaussian was refused");
      obs.push_back(o);
    }
  }
  static const FilterInputs& get() {
    static const FilterInputs in;
    return in;
  }
};

/// A ring of (sensor pose, observation) pairs that a consistent filter model produces: the
/// sensor moves as in FilterInputs, the feature stays put in the world (so its pose in the
/// sensor frame follows the sensor's motion, as the filter's prediction assumes), and each
/// observation is the true pose perturbed by noise drawn from its own GDN-like σ. The
/// observations of FilterInputs jump by up to 15° between steps against a σ of 0.5–2°: a mix
/// of angles for the fixed-count step, far outside what the filter's model expects.
template <class G>
struct FilterSequence {
  using Tangent = typename G::Tangent;
  std::vector<G> sensor;
  std::vector<lieservo::ConcentratedGaussian<G>> obs;
  FilterSequence() {
    lieservo::sampling::Rng rng(11);
    G pose = G::identity();
    const G feature = G::exp(randomTangent<G>(rng, 3.0, 10 * kDeg));  // in the world
    for (std::size_t i = 0; i < kRing; ++i) {
      pose = G::exp(randomTangent<G>(rng, 0.5, 1.0 * kDeg)) * pose;
      sensor.push_back(pose);
      const Tangent s = randomSigma<G>(rng);
      Tangent m = (pose.inverse() * feature).log();
      for (int k = 0; k < G::DoF; ++k) m(k) += s(k) * typename G::Scalar(standardNormal(rng));
      lieservo::ConcentratedGaussian<G> o;
      if (lieservo::fromTangentGaussian(m, s, o) != lieservo::Status::ok)
        throw std::runtime_error("benchmark inputs: an observation Gaussian was refused");
      obs.push_back(o);
    }
  }
  static const FilterSequence& get() {
    static const FilterSequence in;
    return in;
  }
};

}  // namespace lieservo_bench

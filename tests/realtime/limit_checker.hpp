// tests/realtime/limit_checker.hpp — finite-difference limit checks as a 1 kHz robot sees them.
#pragma once

#include <lieservo/realtime/velocity_smoother.hpp>

#include <Eigen/Core>
#include <algorithm>

namespace rt_test {

using Twist = Eigen::Matrix<double, 6, 1>;

/// Feeds commanded velocities; tracks the worst ratio (value / limit) of the velocity,
/// acceleration and jerk NORMS of each part and of every single axis (libfranka-style).
struct LimitChecker {
  lieservo::realtime::SmootherLimits<double> limits;
  double dt = 1e-3;
  Twist v_prev = Twist::Zero(), a_prev = Twist::Zero();
  double worst_norm = 0;  // max over parts and orders of ||x|| / limit
  double worst_axis = 0;  // max over axes and orders of |x_i| / limit

  void push(const Twist& v) {
    const Twist a = (v - v_prev) / dt;
    const Twist j = (a - a_prev) / dt;
    for (int part = 0; part < 2; ++part) {
      const auto& l = part == 0 ? limits.translation : limits.rotation;
      const double lim[3] = {l.velocity, l.acceleration, l.jerk};
      const Twist* x[3] = {&v, &a, &j};
      for (int o = 0; o < 3; ++o) {
        const auto seg = x[o]->segment<3>(3 * part);
        worst_norm = std::max(worst_norm, seg.norm() / lim[o]);
        worst_axis = std::max(worst_axis, seg.cwiseAbs().maxCoeff() / lim[o]);
      }
    }
    v_prev = v;
    a_prev = a;
  }
};

/// The target after the smoother's velocity clamp (norm of each part <= its limit).
inline Twist clampedTarget(const Twist& t, const lieservo::realtime::SmootherLimits<double>& l) {
  Twist w = t;
  const double nl = w.head<3>().norm(), na = w.tail<3>().norm();
  if (nl > l.translation.velocity) w.head<3>() *= l.translation.velocity / nl;
  if (na > l.rotation.velocity) w.tail<3>() *= l.rotation.velocity / na;
  return w;
}

}  // namespace rt_test

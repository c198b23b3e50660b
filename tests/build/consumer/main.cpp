// A downstream project's view of lieservo. The body of run() is the README's usage
// example, kept here so that it is compiled and run by CTest (build.consumer_*).
#include <lieservo/lieservo.hpp>

#include <cstdio>

namespace {

int run() {
  // --- README usage example (keep in sync with README.md) ---------------------------
  using namespace lieservo;
  using SE3d = SE3<double>;

  // The tactile loop: the paper's filter (Σφ = 0.5² mm², deg²→rad²; 5 fusion iterations) and
  // Table 7's servo (radians inside), stepped together under one policy (docs/control.md).
  TactileLoop<TactileServoController<SE3d>> loop({{}, surfaceFollowingPreset<double>()});

  SE3d X_ws;                                    // sensor pose from the robot (mm, rad)
  SE3d::Tangent mu, sigma, twist;               // GDN output per component (mm, rad)
  mu << 0.5, -0.3, -3.2, 0.02, -0.01, 0.03;
  sigma << 0.4, 0.4, 0.12, 0.009, 0.010, 0.021;
  const double dt = 0.05;                       // 20 Hz tactile loop

  for (int k = 0; k < 100; ++k) {
    ConcentratedGaussian<SE3d> obs;
    Status s = fromTangentGaussian(mu, sigma, obs);                    // eq. 14 (eq:se3_inverse_transform)
    if (s == Status::ok)
      s = loop.step(X_ws, obs, dt, twist);  // Algorithm 2, then the servo: the sensor-frame twist
    if (s != Status::ok) { std::fprintf(stderr, "lieservo: %s\n", describe(s)); return 1; }  // nothing changed
  }
  // --- end of the README example -------------------------------------------------------
  std::printf("lieservo consumer: twist = [%.3f %.3f %.3f %.4f %.4f %.4f]\n", twist[0], twist[1],
              twist[2], twist[3], twist[4], twist[5]);
  return twist.allFinite() ? 0 : 1;
}

}  // namespace

int main() { return run(); }

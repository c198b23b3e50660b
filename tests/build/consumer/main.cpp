// Uses the public API the way a downstream project would; exits non-zero on failure.
#include <lieservo/lieservo.hpp>

#include <cstdio>

int main() {
  using SE3 = lieservo::SE3<double>;
  SE3::Tangent xi;
  xi << 1.0, -2.0, 0.5, 0.1, -0.2, 0.3;
  const SE3 X = SE3::exp(xi);
  const double err = (X.log() - xi).norm();
  std::printf("lieservo consumer: |log(exp(xi)) - xi| = %.3g\n", err);
  return err < 1e-12 ? 0 : 1;
}

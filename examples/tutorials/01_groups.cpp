// Tutorial 01 — Lie groups: exp and log, the adjoint, left Jacobians, BCH, float vs double.
//
// A sensor pose is a rigid motion X ∈ SE(3): a rotation C and a translation r, the 4 × 4
// matrix of the paper's eq. 26. Small changes live in the tangent space as 6-vectors
// ξ = [ρ; φ] (translation first, mm and radians; ξ^ is eq. 28, φ^ eq. 29), and
//   X = exp(ξ^)        maps a tangent vector to the group (paper Appendix A),
//   ξ = ln(X)^∨        maps back (its inverse, for rotation angles below π).
// The sections below follow the appendix: the adjoint (eq. 30), the left Jacobian and its
// inverse (eqs. 33 and 34), and the BCH approximation (eq. 32).
// Everything below is checked numerically; the program exits with status 1 if a check fails.
//
// Build and run:  cmake --build <build> --target lieservo_tutorial_01_groups &&
//                 <build>/examples/tutorials/lieservo_tutorial_01_groups
#include <cmath>
#include <cstdio>

#include <lieservo/lieservo.hpp>
#include <lieservo/sampling/random.hpp>

using namespace lieservo;
using SE3d = SE3<double>;
using Tangent = SE3d::Tangent;

namespace {

int failures = 0;
void check(bool ok, const char* what, double value) {
  std::printf("  %-58s %10.3g  %s\n", what, value, ok ? "ok" : "FAILED");
  failures += !ok;
}

// A random tangent: normal draws with standard deviation rho (translation) and phi (rotation).
Tangent randomTangent(sampling::Rng& rng, double rho, double phi) {
  Tangent sigma;
  sigma << rho, rho, rho, phi, phi, phi;
  return sampling::normalVector(rng, sigma);
}

}  // namespace

int main() {
  sampling::Rng rng(1);  // seeded: the same numbers on every run and platform

  std::printf("1. exp and log are inverse (rotation angle below pi)\n");
  const Tangent xi = randomTangent(rng, 10.0, 0.5);  // 10 mm, 0.5 rad
  const SE3d X = SE3d::exp(xi);
  check((X.log() - xi).norm() < 1e-12, "|ln(exp(xi)) - xi|", (X.log() - xi).norm());

  std::printf("2. the adjoint (eq. 30) moves a tangent vector between frames: X exp(d) X^-1 = exp(Ad(X) d)\n");
  const Tangent d = randomTangent(rng, 1.0, 0.1);
  const SE3d lhs = X * SE3d::exp(d) * X.inverse();
  const SE3d rhs = SE3d::exp(X.Ad() * d);
  check(lminus(lhs, rhs).norm() < 1e-12, "|ln(lhs rhs^-1)|", lminus(lhs, rhs).norm());

  std::printf("3. the left Jacobian (eq. 33): exp(xi + e) = exp(J(xi) e) exp(xi) to first order in e\n");
  // Central differences of e ↦ ln(exp(xi + e) exp(xi)^-1) give J column by column.
  SE3d::Jacobian J_num;
  const double h = 1e-6;
  for (int i = 0; i < 6; ++i) {
    const Tangent e = Tangent::Unit(i) * h;
    J_num.col(i) = (lminus(SE3d::exp(xi + e), X) - lminus(SE3d::exp(xi - e), X)) / (2 * h);
  }
  const SE3d::Jacobian J = SE3d::leftJacobian(xi);
  check((J - J_num).norm() < 1e-7, "|J - J_numerical|", (J - J_num).norm());
  const SE3d::Jacobian I = J * SE3d::leftJacobianInverse(xi);
  check((I - SE3d::Jacobian::Identity()).norm() < 1e-12, "|J J^-1 - I|", (I - SE3d::Jacobian::Identity()).norm());

  std::printf("4. BCH (eq. 32): a small left step d on exp(xi) adds J^-1(xi) d (eq. 34) in the tangent space\n");
  const Tangent small = 1e-4 * randomTangent(rng, 1.0, 1.0);
  const Tangent exact = (SE3d::exp(small) * X).log();
  const Tangent first_order = xi + SE3d::leftJacobianInverse(xi) * small;
  check((exact - first_order).norm() < 1e-7, "|ln(exp(d) exp(xi)) - (xi + J^-1 d)|", (exact - first_order).norm());

  std::printf("5. hard cases: tiny angles and angles near pi\n");
  for (const double angle : {1e-12, 1e-6, pi<double>() - 1e-6}) {
    Tangent t;
    t << 5.0, -3.0, 1.0, angle * 0.6, 0.0, angle * 0.8;  // axis (0.6, 0, 0.8)
    const Tangent back = SE3d::exp(t).log();
    char what[80];
    std::snprintf(what, sizeof what, "angle %.2g: relative |ln(exp(xi)) - xi|", angle);
    check((back - t).norm() / t.norm() < 1e-9, what, (back - t).norm() / t.norm());
  }
  std::printf("   (near pi the rotation axis is found from C + C^T; exactly at pi, +phi and -phi\n"
              "    are the same rotation and log returns one of them)\n");

  std::printf("6. float vs double: the same round trip in single precision\n");
  const SE3<float>::Tangent xf = xi.cast<float>();
  const float err_f = (SE3<float>::exp(xf).log() - xf).norm() / xf.norm();
  check(err_f < 1e-5f, "float: relative round-trip error (eps 1.2e-7)", double(err_f));

  std::printf("%s\n", failures == 0 ? "all checks passed" : "SOME CHECKS FAILED");
  return failures == 0 ? 0 : 1;
}
